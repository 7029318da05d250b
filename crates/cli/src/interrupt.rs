//! Ctrl-C and SIGTERM: the first one asks the run loop to stop cleanly (with a
//! checkpoint where the engine has one); a second one exits at once. Under mpirun the
//! loop stops every rank together when any rank got the signal.

use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};

/// Set by the first signal; the run loop reads it.
pub static REQUESTED: AtomicBool = AtomicBool::new(false);

/// The exit code of a run that is over (negative while it runs).
static SETTLED: AtomicI32 = AtomicI32::new(-1);

/// The run is over and has said so, with exit code `code`: a signal from now on (mpirun
/// stopping the job while MPI is being finalised) exits at once with that code.
pub fn settle(code: u8) {
    SETTLED.store(i32::from(code), Ordering::SeqCst);
}

/// Installs the handler (once per process; later calls are ignored) and returns the
/// flag it sets. With `speak` false (a rank other than 0), the first signal is taken
/// silently: rank 0 says how the run ended.
pub fn install(speak: bool) -> &'static AtomicBool {
    let _ = ctrlc::set_handler(move || {
        let settled = SETTLED.load(Ordering::SeqCst);
        if settled >= 0 {
            std::process::exit(settled);
        }
        if REQUESTED.swap(true, Ordering::SeqCst) {
            eprintln!("grains: second interrupt, exiting without a checkpoint");
            std::process::exit(130);
        }
        if speak {
            eprintln!("grains: interrupt received, stopping (again to exit at once)");
        }
    });
    &REQUESTED
}
