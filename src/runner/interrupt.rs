//! Ctrl-C: the first press asks the sweep to stop cleanly (running simulations are interrupted,
//! finished runs stay committed); a second press ends the process at once.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Exit code of a sweep stopped by Ctrl-C (128 + SIGINT).
pub const EXIT_INTERRUPTED: i32 = 130;

/// Installs the Ctrl-C handler that sets `stop`; call once per process.
pub fn install_ctrl_c(stop: Arc<AtomicBool>) -> Result<(), String> {
    ctrlc::set_handler(move || {
        if stop.swap(true, Ordering::SeqCst) {
            std::process::exit(EXIT_INTERRUPTED);
        }
        eprintln!("\ninterrupt: stopping running simulations and saving finished runs (Ctrl-C again to quit now)");
    })
    .map_err(|e| format!("cannot install the Ctrl-C handler: {e}"))
}
