//! The commands' workflows as library calls, one implementation for every front end (the `demsweep`
//! command prints what they return, the Python module returns it): a study file checked and run as
//! `demsweep run` does it, a tune file checked and tuned as `demsweep tune` does it, each ending with
//! the results' report page.

use std::fmt;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::output::guard::{self, Existing, GuardError};
use crate::output::{DynSink, OutputError, dyn_sink};
use crate::plot::PlotError;
use crate::report::{self, ReportContext, ReportSink};
use crate::runner::{self, RunOptions, RunReport, RunnerError};
use crate::study::{self, Plan, StudyErrors};
use crate::tune::report::{WriteError, Written};
use crate::tune::{self, TuneError, TuneOptions, TuneReport, TuneSpec};

/// Why a study file cannot be run.
#[derive(Clone, Debug, PartialEq)]
pub enum LoadError {
    /// The file is a tune file, which `demsweep tune` runs.
    TuneFile(PathBuf),
    /// The study's problems, each naming file, line, key and reason.
    Invalid(StudyErrors),
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LoadError::TuneFile(path) => write!(
                f,
                "{0} is a tune file ([levers], [keep], [search]), not a study: run it with `demsweep tune {0}`",
                path.display()
            ),
            LoadError::Invalid(errors) => write!(f, "{errors}"),
        }
    }
}

/// A study file's plan (its warnings in `plan.warnings`), and a warning when its results would not
/// fit in `out` (default `results/<name>/`).
pub fn load_study(path: &Path, out: Option<&Path>) -> Result<(Plan, Option<String>), LoadError> {
    if tune::is_tune_file(path) {
        return Err(LoadError::TuneFile(path.to_path_buf()));
    }
    let plan = study::load(path).map_err(LoadError::Invalid)?;
    let out = out.map_or_else(|| Path::new("results").join(&plan.name), Path::to_path_buf);
    let space = study::resources::output_space_warning(&plan, &out);
    Ok((plan, space))
}

/// The report page written after a sweep or tune: where it went, the run groups left out of it and
/// the charts that could not be drawn, or why there is none.
pub type Page = report::Written;

/// What `demsweep run` did: the sweep and its report page.
#[derive(Clone, Debug)]
pub struct StudyRun {
    /// The sweep: results file, summary, points, counts, warnings.
    pub report: RunReport,
    /// The report page next to the results.
    pub page: Page,
}

/// Runs a plan as `demsweep run` does: the runs into the results file and its CSV tables
/// ([`runner::results_sinks`]), the report page ([`ReportSink`], from the tables the sweep computed)
/// and then `sinks`, the caller's (which see only the runs made now on `--resume`, and at the end the
/// tables of every run).
pub fn run_study(plan: &Plan, options: &RunOptions, sinks: Vec<DynSink<'_>>) -> Result<StudyRun, RunnerError> {
    let (start, writer) = runner::open_results(plan, options)?;
    let existing = Existing::Ours { force: options.force };
    let mut page = ReportSink::new(start.results(), existing, ReportContext::default());
    let listed = runner::results_sinks(writer).into_iter().chain([dyn_sink(&mut page)]).chain(sinks).collect();
    let report = runner::run_plan_into(plan, options, start, listed)?;
    let page = page.written().expect("a sweep that ends well has finished its sinks");
    Ok(StudyRun { report, page })
}

/// A tune file's spec and its warnings (clipped lever ranges, the reference scene's predicted
/// validity warnings), each naming the file.
pub fn load_tune(path: &Path) -> Result<(TuneSpec, Vec<String>), StudyErrors> {
    let spec = tune::load(path)?;
    let clipped = spec.warnings.iter().map(|w| format!("{}: {w}", path.display()));
    let warnings = clipped.chain(tune::reference_warnings(&spec)).collect();
    Ok((spec, warnings))
}

/// What `demsweep tune` did.
#[derive(Clone, Debug)]
pub struct TuneRun {
    /// The search and its results file.
    pub report: TuneReport,
    /// The recommendation, one paragraph.
    pub recommendation: String,
    /// The files written next to the results (candidates, best study, recommendation, charts).
    pub written: Written,
    /// The tune's section of the report page (`<name>_tune.json`), or why it was not written.
    pub section: Result<PathBuf, SectionError>,
    /// The report page.
    pub page: Page,
}

/// Why a tune's section of the report page was not written.
#[derive(Clone, Debug)]
pub enum SectionError {
    /// Its chart could not be drawn.
    Chart(PlotError),
    /// Its file could not be written.
    Write(OutputError),
}

impl fmt::Display for SectionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SectionError::Chart(e) => write!(f, "{e}"),
            SectionError::Write(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for SectionError {}

/// Why a tune did not finish.
#[derive(Debug)]
pub enum TuneRunError {
    /// The search stopped (interrupted, a runner or results-file failure, no reference).
    Tune(TuneError),
    /// Its files could not be written next to the results.
    Write(WriteError),
}

impl fmt::Display for TuneRunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TuneRunError::Tune(e) => write!(f, "{e}"),
            TuneRunError::Write(e) => write!(f, "{e}"),
        }
    }
}

/// Tunes as `demsweep tune` does: the search into the results file, the recommendation and its files,
/// the tune's report section and the report page.
pub fn tune_file(spec: &mut TuneSpec, options: &TuneOptions) -> Result<TuneRun, TuneRunError> {
    let started = Instant::now();
    let existing = Existing::Ours { force: options.force };
    check_tune_files(spec, options).map_err(|e| TuneRunError::Write(WriteError::File(e)))?;
    let outcome = tune::tune(spec, options).map_err(TuneRunError::Tune)?;
    let text = tune::report::paragraph(spec, &outcome.result, options.out_dir.as_deref());
    let dir = outcome.results.parent().unwrap_or(Path::new(".")).to_path_buf();
    let written = tune::report::write_all(spec, &outcome.result, &dir, &text, existing).map_err(TuneRunError::Write)?;
    let section =
        tune::report::report_section(spec, &outcome.result, &text).map_err(SectionError::Chart).and_then(|s| {
            report::write_tune_section(&outcome.results, &spec.name, &s, existing).map_err(SectionError::Write)
        });
    let jobs =
        if options.jobs == 0 { std::thread::available_parallelism().map_or(1, |n| n.get()) } else { options.jobs };
    let context = ReportContext { jobs: Some(jobs), elapsed: Some(started.elapsed().as_secs_f64()) };
    let page = report::write_report(&outcome.results, (None, existing), &context);
    Ok(TuneRun { report: outcome, recommendation: text, written, section, page })
}

/// Checks, before a tune runs, that the files it writes beside its results (its tables and their
/// sidecars, its text files, its report section) may be replaced: only files demsweep wrote unless
/// `--force`, no link or folder.
fn check_tune_files(spec: &TuneSpec, options: &TuneOptions) -> Result<(), GuardError> {
    let results = tune::results_path(spec, options.out_dir.as_deref());
    let dir = results.parent().unwrap_or(Path::new("."));
    let [candidates, skipped, text @ ..] = tune::report::files(spec, dir);
    let tables = [&candidates, &skipped].map(|csv| [csv.clone(), crate::output::csv::metadata_path(csv)]);
    let section = report::tune_section_path(&results, &spec.name);
    let existing = Existing::Ours { force: options.force };
    let check = |path: &PathBuf| guard::check_replaceable(path, &[&results], existing);
    let checked = tables.iter().flatten().chain(&text).chain([&section]).try_for_each(check);
    checked.map_err(|e| if options.resume { e.resuming() } else { e })
}
