//! The command's exit statuses other than 0 that several subcommands share (`demsweep run --help`
//! and docs/results.md list them all).

/// A command that failed: a bad results file, a refused output, an I/O error.
pub const FAILED: u8 = 1;

/// An invalid study or tune file, or bad input (an unknown point or metric): nothing was run.
pub const INVALID_STUDY: u8 = 2;
