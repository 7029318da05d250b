//! Ctrl-C and SIGTERM: the first one asks the run loop to stop cleanly (with a
//! checkpoint where the engine has one); a second one exits at once.

use std::sync::atomic::{AtomicBool, Ordering};

/// Set by the first signal; the run loop reads it.
pub static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Installs the handler (once per process; later calls are ignored).
pub fn install() {
    let _ = ctrlc::set_handler(|| {
        if REQUESTED.swap(true, Ordering::SeqCst) {
            eprintln!("grains: second interrupt, exiting without a checkpoint");
            std::process::exit(130);
        }
        eprintln!("grains: interrupt received, stopping (again to exit at once)");
    });
}
