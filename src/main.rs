//! The `demsweep` command: plan, check (and run) parameter sweeps of 2D DEM deposition.
//!
//! Everything it prints goes through `demsweep::output::terminal` (escaped; a write to a closed pipe
//! or a full disk never ends the process midway): hence these macros instead of `println!`. SIGPIPE
//! stays ignored, as the Rust runtime sets it, so that a reader that goes away never stops a sweep.

/// `print!` through the text edge, to standard output.
macro_rules! out {
    ($($arg:tt)*) => { demsweep::output::terminal::out(format_args!($($arg)*)) };
}

/// `println!` through the text edge, to standard output.
macro_rules! outln {
    () => { demsweep::output::terminal::out(format_args!("\n")) };
    ($($arg:tt)*) => { demsweep::output::terminal::out(format_args!("{}\n", format_args!($($arg)*))) };
}

/// `eprintln!` through the text edge, to standard error.
macro_rules! errln {
    ($($arg:tt)*) => { demsweep::output::terminal::err(format_args!("{}\n", format_args!($($arg)*))) };
}

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}
