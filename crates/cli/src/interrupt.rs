//! Ctrl-C and SIGTERM: the first one asks the run loop to write a checkpoint and stop
//! cleanly; a second one exits at once.

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Installs the handler (once per process; later calls are ignored).
pub fn install() {
    let _ = ctrlc::set_handler(|| {
        if REQUESTED.swap(true, Ordering::SeqCst) {
            eprintln!("grains: second interrupt, exiting without a checkpoint");
            std::process::exit(130);
        }
        eprintln!(
            "grains: interrupt received, writing a checkpoint and stopping (again to exit at once)"
        );
    });
}

/// Whether a stop was requested.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}
