//! Running a plan: runs in parallel on a dedicated rayon pool (one simulation per task), finished
//! runs through a bounded channel to one writer thread that hands them to the sinks the caller lists
//! (the results file's: [`results_sinks`]), progress, resume, shards and Ctrl-C.
//!
//! Results do not depend on `jobs`: every simulation is deterministic on any number of threads (one
//! per run, unless fewer runs are left than threads: see `run_all`), and the summary is sorted by
//! run index whatever order runs finish in.

use std::collections::HashSet;
use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;

mod batch;
pub mod checkpoints;
mod environment;
mod execute;
pub mod interrupt;
pub mod merge;
mod notes;
mod outcome;
mod progress;
mod results_file;
mod reuse;
pub mod shard;
mod start;
mod warnings;
mod writer_thread;

pub use batch::{Batch, run_batches};
pub use environment::{PARALLEL_MIN_DISKS_VARIABLE, VECTOR_WIDTH_VARIABLE, parallel_min_disks, use_vector_width};
pub use merge::{MergeOptions, MergeReport, ShardProblem, merge};
pub use notes::{NotePolicy, RunNote, WorkerCap};
pub use outcome::{EXIT_PARTIAL, RunCounts, SweepOutcome};
pub use progress::ProgressMode;
pub use results_file::{open_results, results_path, results_sinks};
pub use start::Start;
pub use warnings::WarningDigest;
pub use writer_thread::CommitPolicy;

use crate::output::{self, DynSink, OutputError, RunResult, ShardSpec, SinkError, SummaryTable};
use crate::physics::Threads;
use crate::study::{Plan, PlannedRun};
use checkpoints::{Checkpointing, RunCheckpoint};
use progress::ProgressView;

/// How to run a plan.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Worker threads; 0 = the available cores.
    pub jobs: usize,
    /// Output directory; default `results/<study name>/`.
    pub out_dir: Option<PathBuf>,
    /// Continue an existing results file: run only the runs it lacks or that failed with an error.
    pub resume: bool,
    /// Overwrite an existing results file.
    pub force: bool,
    /// With `resume`: delete the stored runs the study no longer plans (else they stay in the file,
    /// out of the summary).
    pub drop_unplanned: bool,
    /// With `resume`: reuse stored runs made by another demsweep version (else refused, naming them).
    pub accept_version: bool,
    /// Run only this shard of the plan.
    pub shard: Option<ShardSpec>,
    /// How progress is shown.
    pub progress: ProgressMode,
    /// When finished runs are committed to the file.
    pub commit: CommitPolicy,
    /// Set (e.g. by Ctrl-C) to stop: running simulations are interrupted and not recorded.
    pub stop: Arc<AtomicBool>,
    /// Which notes are printed before the runs start.
    pub notes: NotePolicy,
    /// Save each run's state this often (wall time) and when the sweep is stopped, beside the
    /// results (`OUT/<name>.checkpoints/`); `None`: no checkpoints.
    pub checkpoint_every: Option<std::time::Duration>,
}

/// What a sweep did.
#[derive(Clone, Debug)]
pub struct RunReport {
    /// The HDF5 results file (where it goes, for a sweep whose sinks do not write it).
    pub results: PathBuf,
    /// The CSV summary next to it.
    pub summary_csv: PathBuf,
    /// The per-point CSV next to it.
    pub points_csv: PathBuf,
    /// Runs this invocation is responsible for (the whole plan, or the shard).
    pub selected: usize,
    /// Of those, runs already in the file before this invocation (`--resume`).
    pub already_done: usize,
    /// Runs finished and recorded by this invocation.
    pub ran: usize,
    /// Whether the sweep was stopped before every run finished.
    pub interrupted: bool,
    /// The summary of every run in the file.
    pub summary: SummaryTable,
    /// The statistics of every grid point in the file (see [`crate::stats::points`]).
    pub points: SummaryTable,
    /// Wall time of this invocation.
    pub wall_time: std::time::Duration,
    /// Time the writer thread spent staging, committing and finishing the results file.
    pub writer_time: std::time::Duration,
    /// The warnings of the runs finished by this invocation, by kind.
    pub warnings: WarningDigest,
    /// What this invocation found in the results file and did about it, printed as `note:` lines
    /// before the runs start (see [`RunNote::print_all`]): stored runs that run again and why
    /// (changed input files, physics version), stored runs the study no longer plans, fewer
    /// workers than asked.
    pub notes: Vec<RunNote>,
}

impl RunReport {
    /// Recorded runs whose status is `error`.
    pub fn failed(&self) -> usize {
        self.counts().errored
    }

    /// Selected runs not in the file (interrupted, or lost to an error).
    pub fn missing(&self) -> usize {
        self.counts().missing()
    }

    /// How many runs were selected and how the recorded ones ended.
    pub fn counts(&self) -> RunCounts {
        RunCounts::of_summary(self.selected, &self.summary)
    }

    /// How the sweep ended (see [`SweepOutcome`]).
    pub fn outcome(&self) -> SweepOutcome {
        SweepOutcome::of(&self.counts(), self.interrupted)
    }

    /// Process exit code of [`Self::outcome`]: 0 complete, 4 partial, 1 failed, 130 interrupted.
    pub fn exit_code(&self) -> i32 {
        self.outcome().exit_code()
    }
}

/// Why a sweep could not run or complete.
#[derive(Debug, Clone, PartialEq)]
pub enum RunnerError {
    /// A results-file problem (refused overwrite, other study, unwritable path, full disk …).
    Output(OutputError),
    /// An environment variable the runner reads holds a value it cannot use.
    Environment {
        /// The variable.
        variable: &'static str,
        /// Its value.
        value: String,
        /// What it should hold.
        expected: String,
    },
    /// A sink other than a results file failed (see [`crate::output::SinkError::Other`]).
    Sink(SinkError),
    /// The worker threads could not be started.
    WorkerPool {
        /// How many were asked for.
        threads: usize,
        /// Why the system refused them.
        reason: String,
    },
    /// The writer thread panicked.
    WriterPanicked,
}

impl fmt::Display for RunnerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunnerError::Output(e) => write!(f, "{e}"),
            RunnerError::Environment { variable, value, expected } => {
                write!(f, "environment variable {variable}: expected {expected}, got {value:?}")
            }
            RunnerError::Sink(e) => write!(f, "{e}"),
            RunnerError::WorkerPool { threads, reason } => write!(f, "cannot start {threads} worker threads: {reason}"),
            RunnerError::WriterPanicked => write!(f, "the writer thread panicked"),
        }
    }
}

impl std::error::Error for RunnerError {}

impl From<OutputError> for RunnerError {
    fn from(e: OutputError) -> Self {
        RunnerError::Output(e)
    }
}

impl From<SinkError> for RunnerError {
    fn from(e: SinkError) -> Self {
        match e {
            SinkError::Output(e) => RunnerError::Output(e),
            other => RunnerError::Sink(other),
        }
    }
}

/// Runs a plan (or one shard of it) into `OUT/<name>.h5` (or `OUT/<name>.shard-K-of-N.h5`) and its CSV
/// tables ([`results_sinks`]); see [`RunOptions`].
pub fn run_plan(plan: &Plan, options: &RunOptions) -> Result<RunReport, RunnerError> {
    let (start, writer) = open_results(plan, options)?;
    run_plan_into(plan, options, start, results_sinks(writer))
}

/// Makes the runs of `start` (from [`open_results`], or [`Start::fresh`]) and hands each to the
/// `sinks` in their order; at the end each gets the tables of every selected run, the stored ones
/// included (on `--resume` a sink sees only the runs made now, but the tables of them all).
pub fn run_plan_into(
    plan: &Plan,
    options: &RunOptions,
    start: Start,
    sinks: Vec<DynSink<'_>>,
) -> Result<RunReport, RunnerError> {
    let Start {
        results: path,
        lock: _lock,
        started,
        selected,
        identities,
        stored,
        todo,
        aliases,
        mut notes,
        checkpointing,
    } = start;
    let done: HashSet<usize> = stored.iter().map(|r| r.index).collect();
    let mut todo: Vec<Todo> = todo.iter().map(|&i| (&plan.runs[i], identities[i].as_str(), 0)).collect();
    todo.sort_by(|(a, ..), (b, ..)| b.estimated_cost.total_cmp(&a.estimated_cost).then(a.index.cmp(&b.index)));
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let (jobs, capped) = worker_count(options.jobs, todo.len(), cores);
    notes.extend(capped);
    RunNote::print_all(notes.iter().filter(|n| options.notes.prints(n)), &path, options.progress);
    let view = ProgressView::new(options.progress, selected.len(), done.len(), jobs);
    let group = writer_thread::Sinks { committed: stored, aliases, ..writer_thread::Sinks::new(sinks) };
    let threads = pool_threads(options.jobs, cores);
    let how = (options.commit, checkpointing.as_ref());
    let swept = sweep(&todo, vec![group], (jobs, threads), &view, how, &options.stop)?;
    let Swept { ran, warnings, mut tables, writer_time } = swept;
    let tables = tables.pop().expect("one group");
    let (summary_csv, points_csv) = (output::csv_path(&path), output::points_csv_path(&path));
    Ok(RunReport {
        results: path,
        summary_csv,
        points_csv,
        selected: selected.len(),
        already_done: done.len(),
        ran,
        interrupted: options.stop.load(Ordering::SeqCst) && tables.summary.len() < selected.len(),
        summary: tables.summary,
        points: tables.points,
        wall_time: started.elapsed(),
        writer_time,
        warnings,
        notes,
    })
}

/// Worker threads for `todo` runs on `cores` cores when `requested` were asked for (0 = one per
/// core): never more than the runs to do nor the cores, at least one; with a note when capped.
fn worker_count(requested: usize, todo: usize, cores: usize) -> (usize, Option<RunNote>) {
    let jobs = pool_threads(requested, cores).min(todo).max(1);
    let note = (requested > jobs).then(|| {
        let by = if jobs == todo { WorkerCap::Runs(todo) } else { WorkerCap::Cores(cores) };
        RunNote::WorkersCapped { asked: requested, used: jobs, by }
    });
    (jobs, note)
}

/// Threads of the worker pool when `requested` were asked for (0 = one per core): those of the
/// workers, and while fewer runs are left to start than it has threads, all of them for each run
/// started then (see `run_all`).
fn pool_threads(requested: usize, cores: usize) -> usize {
    (if requested == 0 { cores } else { requested }).min(cores).max(1)
}

/// A run to make: the run, its identity and the position of its group of sinks.
type Todo<'a> = (&'a PlannedRun, &'a str, usize);

/// What [`sweep`] did.
struct Swept {
    /// Runs recorded.
    ran: usize,
    /// The warnings of those runs, by kind.
    warnings: WarningDigest,
    /// Each group's tables.
    tables: Vec<output::Tables>,
    /// Time the writer thread spent staging, committing and finishing.
    writer_time: std::time::Duration,
}

/// Runs `todo` in this order on `jobs` workers in a pool of `threads` threads (see `run_all`), each
/// result through the writer thread to the sinks of its group in `groups`.
fn sweep(
    todo: &[Todo],
    groups: Vec<writer_thread::Sinks<'_>>,
    (jobs, threads): (usize, usize),
    view: &ProgressView,
    (commit, checkpointing): (CommitPolicy, Option<&Checkpointing>),
    stop: &Arc<AtomicBool>,
) -> Result<Swept, RunnerError> {
    let (sender, receiver) = mpsc::sync_channel(jobs * writer_thread::BACKLOG_PER_WORKER);
    std::thread::scope(|scope| {
        let writing = writer_thread::spawn(scope, groups, receiver, commit, stop.clone());
        let deliver = |position: usize, result| sender.send((todo[position].2, result)).is_ok();
        let ran = run_all(todo, (jobs, threads), (stop, checkpointing), view, &deliver);
        drop(sender); // the writer thread finishes once the channel closes
        let warnings = view.finish();
        let (tables, writer_time) = writing.join().map_err(|_| RunnerError::WriterPanicked)??;
        Ok(Swept { ran: ran?, warnings, tables, writer_time })
    })
}

/// Runs `todo` in this order on `jobs` workers in a pool of `threads` threads, handing each result
/// and its position in `todo` to `deliver` (which says whether it was taken); returns how many were
/// taken. One run per worker thread is the rule; a run started while fewer runs are left to start
/// than the pool has threads is given them all: the simulation shares the work of its steps out in
/// as many parts, which the pool's idle threads take up (results do not depend on it).
fn run_all(
    todo: &[Todo],
    (jobs, threads): (usize, usize),
    (stop, checkpointing): (&AtomicBool, Option<&Checkpointing>),
    view: &ProgressView,
    deliver: &(dyn Fn(usize, RunResult) -> bool + Sync),
) -> Result<usize, RunnerError> {
    let threads = threads.max(jobs);
    let min_disks = parallel_min_disks()?;
    use_vector_width()?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("demsweep-worker-{i}"))
        .build()
        .map_err(|e| RunnerError::WorkerPool { threads, reason: e.to_string() })?;
    let next = AtomicUsize::new(0);
    let finished = AtomicUsize::new(0);
    pool.scope(|scope| {
        for worker in 0..jobs {
            let (next, finished) = (&next, &finished);
            scope.spawn(move |_| {
                while !stop.load(Ordering::SeqCst) {
                    let position = next.fetch_add(1, Ordering::SeqCst);
                    let Some(&(run, identity, _)) = todo.get(position) else { break };
                    let count = if todo.len() - position < threads { threads } else { 1 };
                    let given = Threads { count, min_disks };
                    let checkpoint = checkpointing.map(|c| RunCheckpoint::new(c, &run.id, identity));
                    let result =
                        execute::run_one(run, stop, given, &mut |p| view.sample(worker, &run.id, p), checkpoint);
                    if let Some(mut result) = result {
                        result.row.identity = identity.to_string();
                        view.finished(worker, &result.row);
                        if deliver(position, result) {
                            finished.fetch_add(1, Ordering::SeqCst);
                        }
                    }
                }
            });
        }
    });
    Ok(finished.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn workers_are_capped_by_runs_to_do_and_cores() {
        assert_eq!(worker_count(0, 100, 8), (8, None));
        assert_eq!(worker_count(0, 3, 8), (3, None), "no note when the default is capped");
        assert_eq!(worker_count(4, 100, 8), (4, None));
        assert_eq!(worker_count(1, 0, 8), (1, None), "at least one");
        let words = |(jobs, note): (usize, Option<RunNote>)| (jobs, note.map(|n| n.to_string()));
        let capped = words(worker_count(100_000, 2, 16));
        assert_eq!(capped, (2, Some("--jobs 100000 capped to 2 worker threads (2 runs to do)".into())));
        let capped = words(worker_count(64, 1000, 16));
        assert_eq!(capped, (16, Some("--jobs 64 capped to 16 worker threads (16 cores)".into())));
    }
}
