//! The `demsweep` command: plan, check (and run) parameter sweeps of 2D DEM deposition.

mod cli;

fn main() -> std::process::ExitCode {
    quit_quietly_on_a_closed_pipe();
    cli::main()
}

/// Restores the default action of SIGPIPE, which the Rust runtime ignores (so that every print to a
/// closed pipe, `demsweep summary F | head`, would panic): the process ends quietly when its reader
/// goes, like other command-line tools. A sweep so ended is a `kill -9`: its committed runs stay
/// and `--resume` runs the rest.
#[allow(unsafe_code)]
fn quit_quietly_on_a_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: called first in main, before any thread starts; SIG_DFL is a valid disposition.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
