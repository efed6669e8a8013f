//! The result commands: `run`, `summary`, `history` and `merge`.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use clap::{Args, ValueEnum};
use demsweep::output::table::ColumnData;
use demsweep::output::{self, ShardSpec};
use demsweep::runner::{self, CommitPolicy, ProgressMode, RunOptions, RunReport, interrupt};

/// Exit status of a command that failed (bad results file, refused output, I/O error).
const FAILED: u8 = 1;

/// Kinds of warnings printed in full at the end of a sweep.
const WARNING_KINDS_SHOWN: usize = 5;

#[derive(Args)]
pub struct RunArgs {
    /// The study file (TOML).
    study: PathBuf,
    /// Worker threads, one simulation each (default: all cores).
    #[arg(long, short = 'j')]
    jobs: Option<usize>,
    /// Output directory (default: results/<study name>/).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Continue existing results: run only the runs the file lacks or that failed with an error.
    #[arg(long, conflicts_with = "force")]
    resume: bool,
    /// Replace existing results.
    #[arg(long)]
    force: bool,
    /// Run only shard K of N (1-based, e.g. 2/8); writes <name>.shard-K-of-N.h5.
    #[arg(long, value_name = "K/N")]
    shard: Option<ShardSpec>,
    /// Progress display.
    #[arg(long, value_enum, default_value_t = Progress::Auto)]
    progress: Progress,
    /// Commit finished runs to the file at least this often (seconds; also after every 100 runs, and
    /// never so often that committing takes over 3 % of the time).
    #[arg(long, value_name = "SECONDS", default_value = "2", value_parser = seconds)]
    commit_interval: Duration,
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
    /// Nothing but the final report.
    Quiet,
}

#[derive(Args)]
pub struct SummaryArgs {
    /// A results file (.h5) written by `demsweep run` or `demsweep merge`.
    results: PathBuf,
    /// Write the summary to this CSV file instead of printing it.
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
}

#[derive(Args)]
pub struct HistoryArgs {
    /// A results file (.h5).
    results: PathBuf,
    /// The run id (first column of `demsweep summary`), e.g. r0007.
    run_id: String,
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

    /// The output directory, when given.
    pub fn out(&self) -> Option<&std::path::Path> {
        self.out.as_deref()
    }
}

/// `demsweep run`: exit 0 when every run finished, 1 on failed or missing runs, 130 after Ctrl-C.
pub fn run(args: &RunArgs, plan: &demsweep::study::Plan) -> ExitCode {
    let stop = Arc::new(AtomicBool::new(false));
    if let Err(e) = interrupt::install_ctrl_c(stop.clone()) {
        eprintln!("warning: {e}");
    }
    let options = RunOptions {
        jobs: args.jobs.unwrap_or(0),
        out_dir: args.out.clone(),
        resume: args.resume,
        force: args.force,
        shard: args.shard,
        progress: match args.progress {
            Progress::Auto => ProgressMode::Auto,
            Progress::Bars => ProgressMode::Bars,
            Progress::Lines => ProgressMode::Lines,
            Progress::Quiet => ProgressMode::Quiet,
        },
        commit: CommitPolicy { interval: args.commit_interval, ..CommitPolicy::default() },
        stop,
    };
    match runner::run_plan(plan, &options) {
        Ok(report) => {
            print_report(&report, args);
            ExitCode::from(report.exit_code() as u8)
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(FAILED)
        }
    }
}

fn print_report(report: &RunReport, args: &RunArgs) {
    let mut counts: Vec<(String, usize)> = Vec::new();
    if let Some(ColumnData::Text(statuses)) = report.summary.column("status").map(|c| &c.data) {
        for status in statuses {
            match counts.iter_mut().find(|(s, _)| s == status) {
                Some((_, n)) => *n += 1,
                None => counts.push((status.clone(), 1)),
            }
        }
    }
    let counts: Vec<String> = counts.iter().map(|(s, n)| format!("{n} {s}")).collect();
    println!(
        "{} of {} runs recorded ({}); {} run now, {} already done",
        report.summary.len(),
        report.selected,
        counts.join(", "),
        report.ran,
        report.already_done
    );
    let (wall, writer) = (report.wall_time.as_secs_f64(), report.writer_time.as_secs_f64());
    println!(
        "wall time {wall:.2} s; writing results took {writer:.3} s ({:.1} % of it, in its own thread)",
        100.0 * writer / wall.max(f64::MIN_POSITIVE)
    );
    println!("results: {}\nsummary: {}", report.results.display(), report.summary_csv.display());
    print_warnings(report);
    if report.missing() > 0 {
        let shard = args.shard.map_or(String::new(), |s| format!(" --shard {s}"));
        let out = args.out.as_ref().map_or(String::new(), |d| format!(" --out {}", d.display()));
        eprintln!(
            "{} runs not recorded{}: continue with `demsweep run {}{out}{shard} --resume`",
            report.missing(),
            if report.interrupted { " (interrupted)" } else { "" },
            args.study.display()
        );
    }
    if report.failed() > 0 {
        eprintln!(
            "{} runs failed with an error: see the status and message columns; `--resume` runs them again",
            report.failed()
        );
    }
}

/// The warnings of the runs just run, one line per kind (the first few), then where to find the rest.
fn print_warnings(report: &RunReport) {
    let digest = &report.warnings;
    if digest.groups.is_empty() {
        return;
    }
    eprintln!("warnings: {} kind(s) in {} of {} runs run now:", digest.groups.len(), digest.runs, report.ran);
    for group in digest.groups.iter().take(WARNING_KINDS_SHOWN) {
        let runs = match group.runs {
            1 => format!("1 run ({})", group.first_run),
            n => format!("{n} runs (first {})", group.first_run),
        };
        eprintln!("  {runs}: {}", group.example);
    }
    if digest.groups.len() > WARNING_KINDS_SHOWN {
        eprintln!("  ... and {} more kind(s)", digest.groups.len() - WARNING_KINDS_SHOWN);
    }
    eprintln!(
        "each run's warnings: `demsweep summary {}` (warnings column), the texts in each run group's `warnings` attribute",
        report.results.display()
    );
}

/// `demsweep summary`: the summary table, aligned on stdout or as a CSV file.
pub fn summary(args: &SummaryArgs) -> ExitCode {
    let outcome = output::summary::read(&args.results).and_then(|table| match &args.csv {
        Some(path) => output::summary::write_csv(path, &table),
        None => output::summary::print_aligned(&mut std::io::stdout().lock(), &table)
            .map_err(|e| output::OutputError::io(std::path::Path::new("<stdout>"), e)),
    });
    report_error(outcome)
}

/// `demsweep history`: one run's histories as CSV on stdout (a closed pipe, as with `| head`, is no error).
pub fn history(args: &HistoryArgs) -> ExitCode {
    let mut csv = Vec::new();
    let outcome = output::history::to_csv(&args.results, &args.run_id, &mut csv);
    if outcome.is_ok() {
        let _ = std::io::stdout().lock().write_all(&csv);
    }
    report_error(outcome)
}

/// `demsweep merge`: shard files into one results file; exit 1 when shards or runs are missing or
/// failed (what there is is merged, and the commands that complete it are printed).
pub fn merge(args: &MergeArgs) -> ExitCode {
    let report = match output::merge(&args.out, &args.inputs, args.force) {
        Ok(report) => report,
        Err(e) => return report_error(Err(e)),
    };
    println!(
        "merged {} of {} runs from {} of {} shards\nresults: {}\nsummary: {}",
        report.runs,
        report.planned_runs,
        report.shards,
        report.shard_count,
        report.results.display(),
        report.summary_csv.display()
    );
    if report.problems.is_empty() {
        return ExitCode::SUCCESS;
    }
    eprintln!("error: the merge is incomplete:");
    for problem in &report.problems {
        eprintln!("  {}", problem.reason);
    }
    eprintln!("{}", rerun_commands(args, &report));
    ExitCode::from(FAILED)
}

/// The commands that run the shards of `report`'s problems again (each resumes its file: the runs it
/// lacks and those that failed run again) and merge after them.
fn rerun_commands(args: &MergeArgs, report: &output::MergeReport) -> String {
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
            eprintln!("error: {e}");
            ExitCode::from(FAILED)
        }
    }
}
