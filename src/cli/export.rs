//! `demsweep export`: stored piles as files for ParaView, LAMMPS or a restart (see `demsweep::export`).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Args;
use clap::builder::PossibleValuesParser;
use demsweep::export::{ExportRequest, FORMATS, export, format};

#[derive(Args)]
pub struct ExportArgs {
    /// A results file (.h5) written by `demsweep run` or `demsweep merge`, or a folder holding one.
    #[arg(value_parser = super::results::results_file)]
    results: PathBuf,
    /// File format (see below).
    #[arg(long, value_parser = PossibleValuesParser::new(FORMATS.iter().map(|f| f.name)), long_help = format_help())]
    format: String,
    /// Export this run (repeatable), e.g. --run r0007; default: every run that finished.
    #[arg(long = "run", value_name = "ID")]
    runs: Vec<String>,
    /// Also export each run's recorded frames (the study's output.frames).
    #[arg(long)]
    frames: bool,
    /// Output folder (created; it must not exist, unless --force).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Replace an existing output folder.
    #[arg(long)]
    force: bool,
}

/// The `--format` help: one line per format of the table.
fn format_help() -> String {
    let lines: Vec<String> = FORMATS.iter().map(|f| format!("  {}: {}", f.name, f.description)).collect();
    format!("File format, one of:\n{}", lines.join("\n"))
}

/// Runs the export and prints what it wrote.
pub fn run(args: &ExportArgs) -> ExitCode {
    let request = ExportRequest {
        results: args.results.clone(),
        format: format(&args.format).expect("clap checked the name against the table"),
        runs: args.runs.clone(),
        frames: args.frames,
        out: args.out.clone(),
        force: args.force,
    };
    let started = Instant::now();
    match export(&request) {
        Ok(summary) => {
            outln!(
                "exported {} runs: {} files, {:.1} MB in {} ({:.2} s)",
                summary.runs,
                summary.files,
                summary.bytes as f64 / 1e6,
                args.out.display(),
                started.elapsed().as_secs_f64()
            );
            super::results::damage_status(&args.results, &summary.damaged)
        }
        Err(e) => {
            errln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
