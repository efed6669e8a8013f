//! The `demsweep` command: plan, check (and run) parameter sweeps of 2D DEM deposition.

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}
