//! Ctrl-C, SIGTERM and SIGHUP (a Slurm time limit, a closed terminal): the first signal asks the
//! sweep to stop cleanly (running simulations are interrupted, finished runs are committed); a second
//! one ends the process at once.

use std::fmt;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Exit code of a sweep stopped by Ctrl-C, SIGTERM or SIGHUP (128 + SIGINT, whichever signal it was).
pub const EXIT_INTERRUPTED: i32 = 130;

/// The handler of Ctrl-C, SIGTERM and SIGHUP could not be installed (one is already, or the system
/// refused): the library's reason.
#[derive(Debug)]
pub struct HandlerError(pub ctrlc::Error);

impl fmt::Display for HandlerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "cannot install the Ctrl-C/SIGTERM/SIGHUP handler: {}", self.0)
    }
}

impl std::error::Error for HandlerError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.0)
    }
}

/// Installs the handler of Ctrl-C, SIGTERM and SIGHUP that sets `stop`; call once per process.
pub fn install_ctrl_c(stop: Arc<AtomicBool>) -> Result<(), HandlerError> {
    ctrlc::set_handler(move || {
        if stop.swap(true, Ordering::SeqCst) {
            std::process::exit(EXIT_INTERRUPTED);
        }
        crate::output::terminal::err(format_args!(
            "\ninterrupt (Ctrl-C, SIGTERM or SIGHUP): stopping running simulations and saving finished runs \
             (signal again to quit now)\n"
        ));
    })
    .map_err(HandlerError)
}
