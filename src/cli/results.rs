//! The result commands: `run`, `summary`, `history` and `merge`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use clap::{Args, ValueEnum};
use demsweep::output::SummaryTable;
use demsweep::output::guard::Existing;
use demsweep::output::table::{ColumnData, short_float};
use demsweep::output::{self, ShardSpec};
use demsweep::physics::quantity::{self, SETTLE_TIME};
use demsweep::plot::{self, ChartOptions};
use demsweep::report::ReportContext;
use demsweep::runner::{
    self, CommitPolicy, EXIT_PARTIAL, NotePolicy, ProgressMode, RunCounts, RunOptions, RunReport, SweepOutcome,
    interrupt,
};
use demsweep::stats::compare::{self, Tolerance};
use demsweep::stats::points::{self, Points};

use super::exit::FAILED;
/// Exit status for bad input: an unknown point or metric.
const BAD_INPUT: u8 = super::exit::INVALID_STUDY;
/// Exit status of `summary`, `report` and `plot` on a results file with damaged run groups (what
/// could be read is shown; `run --resume` runs the damaged runs again).
pub(super) const DAMAGED: u8 = 3;

/// Warns about the damaged run groups of `results`; the exit status that says so (success if none).
pub(super) fn damage_status(results: &Path, damaged: &[output::reader::DamagedGroup]) -> ExitCode {
    if damaged.is_empty() {
        return ExitCode::SUCCESS;
    }
    errln!("warning: {}: {}", results.display(), output::reader::damage_text(damaged));
    ExitCode::from(DAMAGED)
}

/// Kinds of warnings printed in full at the end of a sweep.
const WARNING_KINDS_SHOWN: usize = 5;

#[derive(Args)]
pub struct RunArgs {
    /// The study file (TOML).
    study: PathBuf,
    /// Worker threads, one simulation each (default: all cores); while fewer runs are left to start
    /// than threads, a run started then is given them all (from 8 000 disks on; the same results).
    #[arg(long, short = 'j')]
    jobs: Option<usize>,
    /// Output directory (default: results/<study name>/).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Continue existing results, of this study or an edited one: stored runs are matched to the
    /// study's runs by identity (settings, input files, physics version), and only the runs the file
    /// lacks, that failed with an error or that lack an asked-for output run.
    #[arg(long, conflicts_with = "force")]
    resume: bool,
    /// With --resume: delete the stored runs the (edited) study no longer plans (else they stay in
    /// the file, out of the summary, points and report).
    #[arg(long, requires = "resume")]
    drop_unplanned: bool,
    /// With --resume: reuse stored runs made by another demsweep version of the same physics
    /// version (else such a resume is refused, naming the run and both versions).
    #[arg(long, requires = "resume")]
    accept_version: bool,
    /// Replace existing results.
    #[arg(long)]
    force: bool,
    /// Run only shard K of N (1-based, e.g. 2/8); writes <name>.shard-K-of-N.h5.
    #[arg(long, value_name = "K/N")]
    shard: Option<ShardSpec>,
    /// Progress display.
    #[arg(long, value_enum, default_value_t = Progress::Auto)]
    progress: Progress,
    /// Commit finished runs to the file at least this often (seconds; also after every 500 runs):
    /// `kill -9` loses at most the runs of this interval and one commit.
    #[arg(long, value_name = "SECONDS", default_value = "2", value_parser = seconds)]
    commit_interval: Duration,
    /// Treat the study's warnings as errors: run nothing (exit status 2), for scripts and CI.
    #[arg(long)]
    strict: bool,
    /// Save the state of each run in progress this often (wall time: `90s`, `10m`, `2h`) and when
    /// stopped, in OUT/<name>.checkpoints/; --resume continues a run from its checkpoint, to the
    /// same bits. `off`: none.
    #[arg(long, value_name = "INTERVAL", default_value = "10m", value_parser = interval)]
    checkpoint_every: Interval,
}

/// A checkpoint interval, `None` for none.
#[derive(Clone, Copy, Debug)]
struct Interval(Option<Duration>);

/// An interval: a positive number with a unit `s`, `m` or `h`, or `off`.
fn interval(text: &str) -> Result<Interval, String> {
    if text == "off" {
        return Ok(Interval(None));
    }
    let unit = text.chars().last().and_then(|c| ["s", "m", "h"].iter().position(|u| u.starts_with(c)));
    let scale = [1.0, 60.0, 3600.0];
    let (number, unit) = match unit {
        Some(k) => (&text[..text.len() - 1], scale[k]),
        None => return Err(format!("`{text}` needs a unit: s, m or h (e.g. 10m), or off")),
    };
    let value: f64 = number.trim().parse().map_err(|_| format!("`{text}` is not a number with a unit (e.g. 10m)"))?;
    let duration = Duration::try_from_secs_f64(value * unit).ok().filter(|d| !d.is_zero());
    duration.map(|d| Interval(Some(d))).ok_or(format!("must be > 0 (or off), got {text}"))
}

/// A positive number of seconds.
fn seconds(text: &str) -> Result<Duration, String> {
    let value: f64 = text.parse().map_err(|_| format!("`{text}` is not a number of seconds"))?;
    Duration::try_from_secs_f64(value).ok().filter(|d| !d.is_zero()).ok_or(format!("must be > 0 seconds, got {text}"))
}

/// How progress is shown (see [`ProgressMode`]).
#[derive(Clone, Copy, ValueEnum)]
enum Progress {
    /// Bars on a terminal, else one line per finished run.
    Auto,
    /// Overall bar and one line per worker.
    Bars,
    /// One line per finished run.
    Lines,
    /// Nothing but warnings, notes about stored runs (what runs again and why) and the final report.
    Quiet,
}

/// A results file argument: the file, or the one results file in a folder.
pub fn results_file(arg: &str) -> Result<PathBuf, String> {
    demsweep::output::reader::locate(std::path::Path::new(arg)).map_err(|e| e.to_string())
}

#[derive(Args)]
pub struct SummaryArgs {
    /// A results file (.h5) written by `demsweep run` or `demsweep merge`, or a folder holding one.
    #[arg(value_parser = results_file)]
    results: PathBuf,
    /// Write the table to this CSV file instead of printing it.
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    /// One row per grid point (the runs that differ only by placement seed): n, status counts and
    /// mean, std, 95 % half-width, min, max of every numeric column.
    #[arg(long)]
    by_point: bool,
    /// Print these metrics (repeatable; default: settle time, the pile metrics compared by default,
    /// cost and wall time), after the run's (or point's) identity, swept values and status. The
    /// CSV always has every column.
    #[arg(long, value_name = "NAME")]
    metric: Vec<String>,
    /// Print every column (one row per run can then be several hundred characters wide).
    #[arg(long, conflicts_with = "metric")]
    all: bool,
    /// Replace any file at --csv (by default only a CSV table demsweep wrote).
    #[arg(long, requires = "csv")]
    force: bool,
}

#[derive(Args)]
pub struct CompareArgs {
    /// A results file (.h5) written by `demsweep run` or `demsweep merge`, or a folder holding one.
    #[arg(value_parser = results_file)]
    results: PathBuf,
    /// The reference point: its swept values (KEY=VALUE,KEY=VALUE; a key may be shortened to its last
    /// part) or the id of one of its runs.
    #[arg(long, value_name = "POINT")]
    reference: String,
    /// A metric to keep within a relative tolerance of the reference mean (repeatable), e.g.
    /// packing_fraction_interior=0.01. Default: packing_fraction_interior=0.01,
    /// coordination_number=0.03, floor_load_ratio=0.02, fabric_anisotropy=0.25 (those present;
    /// packing_fraction=0.01, pile_height=0.01 for files without pile metrics).
    #[arg(long, value_name = "METRIC=TOL")]
    keep: Vec<Tolerance>,
    /// Write the comparison (one row per point and metric) to this CSV file as well.
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    /// Draw a chart per kept metric and a cost-versus-deviation chart (PNG).
    #[arg(long)]
    plot: bool,
    /// Image folder for --plot (default: plots/ next to the results file).
    #[arg(long, value_name = "DIR", requires = "plot")]
    out: Option<PathBuf>,
    /// Replace any file at --csv or a chart's path (by default only files demsweep wrote).
    #[arg(long)]
    force: bool,
}

#[derive(Args)]
pub struct HistoryArgs {
    /// A results file (.h5), or a folder holding one.
    #[arg(value_parser = results_file)]
    results: PathBuf,
    /// The run id (first column of `demsweep summary`), e.g. r0007.
    run_id: String,
    /// Print the run's stress profile instead: one line per height band of the settled pile (band
    /// edges in m, its Love–Weber stress and the side walls' normal and shear stress in Pa).
    #[arg(long)]
    stress_profile: bool,
    /// Write the CSV to this file instead, with its metadata sidecar (<FILE>-metadata.json: each
    /// column's unit and datatype).
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    /// Replace any file at --csv (by default only a CSV file demsweep wrote).
    #[arg(long, requires = "csv")]
    force: bool,
}

#[derive(Args)]
pub struct ReportArgs {
    /// A results file (.h5), or a folder holding one.
    #[arg(value_parser = results_file)]
    results: PathBuf,
    /// Where to write the page (default: <results file name without .h5>_report.html next to it).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Replace any file at the page's path (by default only a report page demsweep wrote).
    #[arg(long)]
    force: bool,
}

#[derive(Args)]
pub struct MergeArgs {
    /// Output directory: receives <study name>.h5 and <study name>_summary.csv.
    out: PathBuf,
    /// Shard files (<name>.shard-K-of-N.h5) or directories holding them.
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
    /// Replace an existing merged file.
    #[arg(long)]
    force: bool,
    /// Merge runs made by different demsweep versions (of one physics version); else refused,
    /// naming a run of each.
    #[arg(long)]
    accept_version: bool,
    /// The merged study's name: writes <NAME>.h5 (default: the first file's study name).
    #[arg(long)]
    name: Option<String>,
    /// The Slurm array script that ran the shards (`demsweep slurm` passes it): shards to run again
    /// are then given as `sbatch --array=K,...` of it.
    #[arg(long, value_name = "PATH")]
    array_script: Option<PathBuf>,
}

impl RunArgs {
    /// The study file.
    pub fn study(&self) -> &std::path::Path {
        &self.study
    }

    /// The worker threads asked for, when given.
    pub fn jobs(&self) -> Option<usize> {
        self.jobs.filter(|&j| j > 0)
    }

    /// The output directory, when given.
    pub fn out(&self) -> Option<&std::path::Path> {
        self.out.as_deref()
    }

    /// Whether warnings are errors.
    pub fn strict(&self) -> bool {
        self.strict
    }
}

/// `demsweep run`: exit 0 when every run finished, 1 on failed or missing runs, 130 after Ctrl-C.
pub fn run(args: &RunArgs, plan: &demsweep::study::Plan) -> ExitCode {
    let stop = Arc::new(AtomicBool::new(false));
    if let Err(e) = interrupt::install_ctrl_c(stop.clone()) {
        errln!("warning: {e}");
    }
    let options = RunOptions {
        jobs: args.jobs.unwrap_or(0),
        out_dir: args.out.clone(),
        resume: args.resume,
        force: args.force,
        drop_unplanned: args.drop_unplanned,
        accept_version: args.accept_version,
        shard: args.shard,
        progress: match args.progress {
            Progress::Auto => ProgressMode::Auto,
            Progress::Bars => ProgressMode::Bars,
            Progress::Lines => ProgressMode::Lines,
            Progress::Quiet => ProgressMode::Quiet,
        },
        commit: CommitPolicy { interval: args.commit_interval, ..CommitPolicy::default() },
        stop,
        notes: NotePolicy::All,
        checkpoint_every: args.checkpoint_every.0,
    };
    match demsweep::workflow::run_study(plan, &options, Vec::new()) {
        Ok(run) => {
            print_report(&run.report);
            let paged = page_written(&run.report.results, run.page);
            print_missing(&run.report, args);
            if !paged {
                return ExitCode::from(FAILED);
            }
            sweep_status(&run.report.counts(), run.report.interrupted)
        }
        Err(e) => {
            errln!("error: {e}");
            ExitCode::from(FAILED)
        }
    }
}

fn print_report(report: &RunReport) {
    let counts = match report.summary.column("status").map(|c| &c.data) {
        Some(ColumnData::Text(statuses)) => status_counts(statuses),
        _ => String::new(),
    };
    outln!(
        "{} of {} runs recorded{counts}; {} run now, {} already done",
        report.summary.len(),
        report.selected,
        report.ran,
        report.already_done
    );
    let (wall, writer) = (report.wall_time.as_secs_f64(), report.writer_time.as_secs_f64());
    outln!(
        "wall time {wall:.2} s; writing results took {writer:.3} s ({:.1} % of it, in its own thread)",
        100.0 * writer / wall.max(f64::MIN_POSITIVE)
    );
    outln!(
        "results: {}\nsummary: {}\npoints: {}",
        report.results.display(),
        report.summary_csv.display(),
        report.points_csv.display()
    );
    print_warnings(report);
}

/// What to do about runs not recorded or failed.
fn print_missing(report: &RunReport, args: &RunArgs) {
    if report.missing() > 0 {
        let shard = args.shard.map_or(String::new(), |s| format!(" --shard {s}"));
        let out = args.out.as_ref().map_or(String::new(), |d| format!(" --out {}", d.display()));
        errln!(
            "{} runs not recorded{}: continue with `demsweep run {}{out}{shard} --resume`",
            report.missing(),
            if report.interrupted { " (interrupted)" } else { "" },
            args.study.display()
        );
    }
    if report.failed() > 0 {
        errln!(
            "{} runs failed with an error: see the status and message columns; `--resume` runs them again",
            report.failed()
        );
    }
}

/// Says how many runs failed, if any; the exit status of the sweep's [`SweepOutcome`].
fn sweep_status(counts: &RunCounts, interrupted: bool) -> ExitCode {
    let outcome = SweepOutcome::of(counts, interrupted);
    match outcome {
        SweepOutcome::Failed => errln!("error: {counts}: no run gave a result (exit status 1)"),
        SweepOutcome::Partial => errln!("warning: {counts} (exit status {EXIT_PARTIAL})"),
        SweepOutcome::Complete | SweepOutcome::Interrupted => {}
    }
    ExitCode::from(outcome.exit_code() as u8)
}

/// The warnings of the runs just run, one line per kind (the first few), then where to find the rest.
fn print_warnings(report: &RunReport) {
    let digest = &report.warnings;
    if digest.groups.is_empty() {
        return;
    }
    errln!("warnings: {} kind(s) in {} of {} runs run now:", digest.groups.len(), digest.runs, report.ran);
    for group in digest.groups.iter().take(WARNING_KINDS_SHOWN) {
        let runs = match group.runs {
            1 => format!("1 run ({})", group.first_run),
            n => format!("{n} runs (first {})", group.first_run),
        };
        errln!("  {runs}: {}", group.example);
    }
    if digest.groups.len() > WARNING_KINDS_SHOWN {
        errln!("  ... and {} more kind(s)", digest.groups.len() - WARNING_KINDS_SHOWN);
    }
    errln!(
        "each run's warnings: `demsweep summary {}` (warnings column), each one's kind, value, limit and time in each run group's `warnings` table",
        report.results.display()
    );
}

/// `demsweep summary`: the summary (or points) table, aligned on stdout or as a CSV file; exit 2 for
/// an unknown --metric.
pub fn summary(args: &SummaryArgs) -> ExitCode {
    let read =
        output::reader::open(&args.results).and_then(|file| output::reader::checked_summary(&file, &args.results));
    let (table, damaged) = match read {
        Ok(read) => read,
        Err(e) => return report_error(Err(e)),
    };
    let table = match (args.by_point, damaged.is_empty()) {
        (false, _) => table,
        (true, false) => Points::new(&table).table(),
        (true, true) => match points::read(&args.results) {
            Ok(table) => table,
            Err(e) => return report_error(Err(e)),
        },
    };
    let status = damage_status(&args.results, &damaged);
    if let Some(path) = &args.csv {
        let written = output::check_not_companion(&args.results, path, args.force)
            .and_then(|()| output::summary::write_csv(path, &table, Existing::Ours { force: args.force }));
        return if written.is_ok() { status } else { report_error(written) };
    }
    let known = if args.by_point { points::table_metrics(&table) } else { run_metrics(&table) };
    let metrics = if args.metric.is_empty() { default_metrics(&known) } else { args.metric.clone() };
    let metrics: Vec<&str> = metrics.iter().map(String::as_str).collect();
    let view = match (args.all, args.by_point) {
        (true, _) => Ok(table),
        (false, true) => points::view(&table, &metrics).map_err(|e| e.to_string()),
        (false, false) => run_view(&table, &known, &metrics),
    };
    let shown = match view {
        Ok(view) => view,
        Err(reason) => return bad_input(&output::OutputError::new(&args.results, reason)),
    };
    print(&shown);
    status
}

/// The numeric columns of a per-run summary table after its status (the metrics a view may show).
fn run_metrics(summary: &SummaryTable) -> Vec<&str> {
    let after_status = summary.columns.iter().skip_while(|c| c.name != "status").skip(1);
    after_status.filter(|c| !matches!(c.data, ColumnData::Text(_))).map(|c| c.name.as_str()).collect()
}

/// The per-run table cut to its identity, swept values and status, then `metrics` (each one of
/// `known`), then the warning count.
fn run_view(summary: &SummaryTable, known: &[&str], metrics: &[&str]) -> Result<SummaryTable, String> {
    if let Some(unknown) = metrics.iter().find(|m| !known.contains(m)) {
        let list = || format!("the metrics are: {}", known.join(", "));
        let hint = demsweep::study::did_you_mean(unknown, known.iter().copied()).unwrap_or_else(list);
        return Err(format!("no metric `{unknown}` in the summary table; {hint}"));
    }
    let column = |name: &str| summary.columns.iter().find(|c| c.name == name).cloned();
    let status = summary.columns.iter().position(|c| c.name == "status").map_or(0, |k| k + 1);
    let mut columns = summary.columns[..status].to_vec();
    columns.extend(metrics.iter().chain(&["warnings"]).filter_map(|m| column(m)));
    Ok(SummaryTable { columns })
}

/// The metrics `summary --by-point` prints by default: settle time, the default compare metrics
/// present, cost and wall time.
fn default_metrics(known: &[&str]) -> Vec<String> {
    let pile = quantity::kept_by_default().map(|(m, _)| m).filter(|m| known.contains(m)).collect::<Vec<_>>();
    let pile = if pile.is_empty() { compare::FALLBACK_KEEP.iter().map(|(m, _)| *m).collect() } else { pile };
    let cost = ["particle_steps", "steps"].into_iter().find(|c| known.contains(c));
    std::iter::once(SETTLE_TIME.name)
        .chain(pile)
        .chain(cost)
        .chain(["wall_time"])
        .filter(|m| known.contains(m))
        .map(str::to_string)
        .collect()
}

/// Prints a table aligned on stdout.
fn print(table: &SummaryTable) {
    let mut text = Vec::new();
    let _ = output::summary::print_aligned(&mut text, table); // writing to memory cannot fail
    out!("{}", String::from_utf8_lossy(&text));
}

/// `demsweep compare`: every point against the reference; exit 2 for an unknown point or metric.
pub fn compare(args: &CompareArgs) -> ExitCode {
    let read =
        output::reader::open(&args.results).and_then(|file| output::reader::checked_summary(&file, &args.results));
    let (summary, damaged) = match read {
        Ok(read) => read,
        Err(e) => return report_error(Err(e)),
    };
    let status = damage_status(&args.results, &damaged);
    let points = Points::new(&summary);
    let comparison = match compare::compare(&points, &args.reference, &args.keep) {
        Ok(comparison) => comparison,
        Err(reason) => return bad_input(&output::OutputError::new(&args.results, reason.to_string())),
    };
    let reference = comparison.reference;
    outln!("reference: {} (n = {})", points.label(reference), points.rows(reference).len());
    let kept: Vec<String> = comparison
        .kept
        .iter()
        .map(|k| format!("{} within {} (±{})", k.tolerance.metric, k.tolerance.relative, short_float(k.margin)))
        .collect();
    outln!("kept (relative tolerance of the reference mean): {}", kept.join(", "));
    for note in &comparison.notes {
        outln!("note: {note}");
    }
    let (decisions, costs) = comparison.printed(&points);
    let acceptable = comparison.points.iter().filter(|p| p.acceptable()).count();
    print(&decisions);
    outln!();
    print(&costs);
    outln!(
        "{acceptable} of {} points acceptable (every kept metric equivalent: its 90 % interval inside ± margin)",
        comparison.points.len()
    );
    let mut outcome = Ok(());
    if let Some(path) = &args.csv {
        outcome = outcome
            .and_then(|()| output::check_not_companion(&args.results, path, args.force))
            .and_then(|()| {
                output::summary::write_csv(path, &comparison.table(&points), Existing::Ours { force: args.force })
            })
            .map(|()| outln!("comparison: {}", path.display()));
    }
    if args.plot {
        let dir = args.out.clone().unwrap_or_else(|| args.results.parent().unwrap_or(Path::new("")).join("plots"));
        let options = ChartOptions { existing: Existing::Ours { force: args.force }, ..ChartOptions::default() };
        match plot::compare::draw_all(&points, &comparison, &dir, &options) {
            Ok(written) => written.iter().for_each(|p| outln!("wrote {}", p.display())),
            Err(e) => {
                errln!("error: {e}");
                return ExitCode::from(FAILED);
            }
        }
    }
    if outcome.is_ok() { status } else { report_error(outcome) }
}

/// Reports bad input (an unknown point or metric) with exit status 2.
fn bad_input(error: &output::OutputError) -> ExitCode {
    errln!("error: {error}");
    ExitCode::from(BAD_INPUT)
}

/// `demsweep history`: one run's histories (or its stress profile) as CSV on stdout, or in a file.
pub fn history(args: &HistoryArgs) -> ExitCode {
    use output::history::{self, RunTable};
    let table = if args.stress_profile { RunTable::StressProfile } else { RunTable::History };
    if let Some(path) = &args.csv {
        let existing = Existing::Ours { force: args.force };
        let written = output::check_not_companion(&args.results, path, args.force)
            .and_then(|()| history::write_csv_file(&args.results, &args.run_id, table, (path, existing)));
        return report_error(written);
    }
    let mut csv = Vec::new();
    let outcome = match table {
        RunTable::StressProfile => history::stress_profile_to_csv(&args.results, &args.run_id, &mut csv),
        RunTable::History => history::to_csv(&args.results, &args.run_id, &mut csv),
    };
    if outcome.is_ok() {
        out!("{}", String::from_utf8_lossy(&csv));
    }
    report_error(outcome)
}

/// `demsweep report`: the HTML report of a results file.
pub fn report(args: &ReportArgs) -> ExitCode {
    let out = (args.out.as_deref(), Existing::Ours { force: args.force });
    match demsweep::report::write_report(&args.results, out, &ReportContext::default()) {
        Ok((path, damaged, not_drawn)) => {
            outln!("report: {}", path.display());
            charts_not_drawn(&not_drawn);
            damage_status(&args.results, &damaged)
        }
        Err(e) => report_error(Err(e)),
    }
}

/// Warns of each study chart the report page left out: the page is written, the command's job done.
fn charts_not_drawn(not_drawn: &[demsweep::plot::PlotError]) {
    for chart in not_drawn {
        errln!("warning: chart not drawn on the report page: {chart}");
    }
}

/// Says where the report page of `results` went (and which run groups and charts it left out), or
/// why there is none (the results are safe, but the command did not write all it was asked to):
/// false then.
pub fn page_written(results: &Path, page: demsweep::workflow::Page) -> bool {
    match page {
        Ok((path, damaged, not_drawn)) => {
            outln!("report: {}", path.display());
            charts_not_drawn(&not_drawn);
            damage_status(results, &damaged);
            true
        }
        Err(e) => {
            errln!("error: report page (the results are complete): {e}");
            false
        }
    }
}

/// `demsweep merge`: shard files into one results file; exit 1 when shards or runs are missing or
/// failed (what there is is merged, and the commands that complete it are printed).
pub fn merge(args: &MergeArgs) -> ExitCode {
    let options =
        runner::MergeOptions { force: args.force, accept_version: args.accept_version, name: args.name.clone() };
    let report = match runner::merge(&args.out, &args.inputs, &options) {
        Ok(report) => report,
        Err(e) => return report_error(Err(e)),
    };
    let merged = match report.shard_count {
        0 => format!("merged {} runs from {} results files", report.runs, report.shards),
        count => {
            format!("merged {} of {} runs from {} of {count} shards", report.runs, report.planned_runs, report.shards)
        }
    };
    outln!(
        "{merged}\nresults: {}\nsummary: {}\npoints: {}",
        report.results.display(),
        report.summary_csv.display(),
        report.points_csv.display()
    );
    let page = (None, Existing::Ours { force: args.force });
    let paged =
        page_written(&report.results, demsweep::report::write_report(&report.results, page, &Default::default()));
    if report.problems.is_empty() {
        if !paged {
            return ExitCode::from(FAILED);
        }
        return match output::summary::read(&report.results) {
            Ok(merged) => sweep_status(&RunCounts::of_summary(report.planned_runs, &merged), false),
            Err(e) => report_error(Err(e)),
        };
    }
    errln!("error: the merge is incomplete:");
    for problem in &report.problems {
        errln!("  {}", problem.reason);
    }
    errln!("{}", rerun_commands(args, &report));
    ExitCode::from(FAILED)
}

/// The commands that run the shards of `report`'s problems again (each resumes its file: the runs it
/// lacks and those that failed run again) and merge after them.
fn rerun_commands(args: &MergeArgs, report: &runner::MergeReport) -> String {
    let shards = report.shards_to_rerun();
    let out = args.out.display();
    let first = &args.inputs[0];
    let shard_dir = if first.is_dir() { first.as_path() } else { first.parent().unwrap_or(Path::new(".")) };
    match &args.array_script {
        Some(array) => {
            let list: Vec<String> = shards.iter().map(usize::to_string).collect();
            format!(
                "run them again, then merge again:\n  ARRAY=$(sbatch --parsable --array={} {})\n  \
                 sbatch --dependency=afterany:$ARRAY {}",
                list.join(","),
                array.display(),
                array.with_file_name("merge.sbatch").display()
            )
        }
        None => {
            let runs: Vec<String> = shards
                .iter()
                .map(|k| {
                    format!(
                        "  demsweep run STUDY --shard {k}/{} --out {} --resume",
                        report.shard_count,
                        shard_dir.display()
                    )
                })
                .collect();
            format!(
                "run them again (STUDY: the study file), then merge again:\n{}\n  demsweep merge {out} {} --force",
                runs.join("\n"),
                shard_dir.display()
            )
        }
    }
}

fn report_error(outcome: Result<(), output::OutputError>) -> ExitCode {
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            errln!("error: {e}");
            ExitCode::from(FAILED)
        }
    }
}

/// How many runs ended in each status, in order of first appearance: ` (2 settled, 1 diverged)`;
/// empty when no run was recorded.
fn status_counts(statuses: &[String]) -> String {
    let mut counts: Vec<(&str, usize)> = Vec::new();
    for status in statuses {
        match counts.iter_mut().find(|(s, _)| s == status) {
            Some((_, n)) => *n += 1,
            None => counts.push((status, 1)),
        }
    }
    let counts: Vec<String> = counts.iter().map(|(s, n)| format!("{n} {s}")).collect();
    if counts.is_empty() { String::new() } else { format!(" ({})", counts.join(", ")) }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    use super::*;

    /// `summary --help` names every column `summary` prints by default, old files' fallbacks too.
    #[test]
    fn summary_help_lists_the_default_columns() {
        let help =
            super::super::Cli::command().find_subcommand("summary").unwrap().get_long_about().unwrap().to_string();
        let pile = quantity::kept_by_default().chain(compare::FALLBACK_KEEP).map(|(m, _)| m);
        let all: Vec<&str> =
            [SETTLE_TIME.name, "particle_steps", "steps", "wall_time"].into_iter().chain(pile).collect();
        let newer = |m: &&str| *m == "particle_steps" || quantity::kept_by_default().any(|(k, _)| k == *m);
        let old: Vec<&str> = all.iter().copied().filter(|m| !newer(m)).collect();
        for metric in default_metrics(&all).iter().chain(&default_metrics(&old)).map(String::as_str).chain(["warnings"])
        {
            assert!(help.contains(metric), "`summary --help` does not name {metric}: {help}");
        }
    }

    #[test]
    fn no_recorded_run_gives_no_empty_parentheses() {
        assert_eq!(status_counts(&[]), "");
        let statuses = ["settled", "diverged", "settled"].map(String::from);
        assert_eq!(status_counts(&statuses), " (2 settled, 1 diverged)");
    }
}
