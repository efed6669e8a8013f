//! `demsweep plot`: PNG and SVG charts of a results file (see `demsweep::plot::results`).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, ValueEnum};
use demsweep::plot::results::{DEFAULT_RUN_LIMIT, Event, PlotRequest, plot_results};
use demsweep::plot::run::ColourBy;
use demsweep::plot::{ChartOptions, Format};

#[derive(Args)]
pub struct PlotArgs {
    /// A results file (.h5) written by `demsweep run` or `demsweep merge`, or a folder holding one.
    #[arg(value_parser = super::results::results_file)]
    results: PathBuf,
    /// Draw the per-run charts of this run (repeatable), e.g. --run r0007.
    #[arg(long = "run", value_name = "ID")]
    runs: Vec<String>,
    /// Draw the per-run charts of every run (by default at most 20 runs, spread over the study).
    #[arg(long, conflicts_with = "runs")]
    all_runs: bool,
    /// Image folder (default: plots/ next to the results file).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Replace any file at a chart's path (by default only a chart demsweep drew is replaced).
    #[arg(long)]
    force: bool,
    /// Image format.
    #[arg(long, value_enum, default_value_t = FormatArg::Png)]
    format: FormatArg,
    /// What the disks of pile snapshots are coloured by (speed on one scale for all of a run's
    /// snapshots; contact force on a scale per snapshot).
    #[arg(long, value_enum, default_value_t = ColourArg::Speed)]
    colour_by: ColourArg,
    /// Image width (pixels, at least 400).
    #[arg(long, default_value_t = ChartOptions::default().width,
          value_parser = clap::value_parser!(u32).range(i64::from(ChartOptions::MIN_SIZE.0)..))]
    width: u32,
    /// Image height (pixels, at least 300).
    #[arg(long, default_value_t = ChartOptions::default().height,
          value_parser = clap::value_parser!(u32).range(i64::from(ChartOptions::MIN_SIZE.1)..))]
    height: u32,
}

/// Image formats to write.
#[derive(Clone, Copy, ValueEnum)]
enum FormatArg {
    /// PNG images.
    Png,
    /// SVG images.
    Svg,
    /// Both, side by side.
    Both,
}

/// Snapshot colouring.
#[derive(Clone, Copy, ValueEnum)]
enum ColourArg {
    /// Speed |v| (m/s).
    Speed,
    /// Sum of contact force magnitudes on each disk (N).
    Force,
}

impl PlotArgs {
    fn request(&self) -> PlotRequest {
        PlotRequest {
            results: self.results.clone(),
            out_dir: self.out.clone(),
            run_ids: self.runs.clone(),
            all_runs: self.all_runs,
            formats: match self.format {
                FormatArg::Png => vec![Format::Png],
                FormatArg::Svg => vec![Format::Svg],
                FormatArg::Both => vec![Format::Png, Format::Svg],
            },
            colour_by: match self.colour_by {
                ColourArg::Speed => ColourBy::Speed,
                ColourArg::Force => ColourBy::ContactForce,
            },
            size: (self.width, self.height),
            force: self.force,
        }
    }
}

/// `demsweep plot`: prints each file written; exit 1 when a chart could not be drawn, 3 when run
/// groups are damaged (left out).
pub fn plot(args: &PlotArgs) -> ExitCode {
    let request = args.request();
    let outcome = plot_results(&request, &mut |event| match event {
        Event::Wrote(path) => outln!("wrote {}", path.display()),
        Event::Note(text) => outln!("note: {text}"),
        Event::Failed(error) => errln!("error: {error}"),
    });
    let report = match outcome {
        Ok(report) => report,
        Err(error) => {
            errln!("error: {error}");
            return ExitCode::FAILURE;
        }
    };
    if report.runs_charted < report.runs_total && args.runs.is_empty() {
        outln!(
            "per-run charts for {} of {} runs (at most {DEFAULT_RUN_LIMIT}, spread over the study): \
             choose runs with --run ID, or draw all with --all-runs",
            report.runs_charted,
            report.runs_total
        );
    }
    outln!("{} files in {}", report.written, request.image_dir().display());
    if report.failed > 0 {
        errln!("{} chart(s) or run(s) failed: see the errors above", report.failed);
        return ExitCode::FAILURE;
    }
    super::results::damage_status(&request.results, &report.damaged)
}
