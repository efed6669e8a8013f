//! The `demsweep` command: plan, check (and run) parameter sweeps of 2D DEM deposition.
//!
//! Everything it prints goes through `demsweep::output::terminal` (see `cli`'s macros). SIGPIPE
//! stays ignored, as the Rust runtime sets it, so that a reader that goes away never stops a sweep.

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}
