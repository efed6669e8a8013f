//! The command's exit statuses other than 0 that several subcommands share (`demsweep run --help`
//! and docs/results.md list them all), and `--strict`'s refusal.

use std::path::Path;
use std::process::ExitCode;

/// A command that failed: a bad results file, a refused output, an I/O error.
pub const FAILED: u8 = 1;

/// An invalid study or tune file, or bad input (an unknown point or metric): nothing was run.
pub const INVALID_STUDY: u8 = 2;

/// With --strict, `warnings` (printed above) are errors: says so; the exit status of an invalid study.
pub fn refuse_warnings(path: &Path, warnings: usize, strict: bool) -> Result<(), ExitCode> {
    if !strict || warnings == 0 {
        return Ok(());
    }
    let n = if warnings == 1 { "1 warning".to_string() } else { format!("{warnings} warnings") };
    errln!("error: {}: {n} above, errors under --strict; nothing was run", path.display());
    Err(ExitCode::from(INVALID_STUDY))
}
