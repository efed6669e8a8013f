//! Running a plan: runs in parallel on a dedicated rayon pool (one simulation per task), finished
//! runs through a bounded channel to one writer thread, progress, resume, shards and Ctrl-C.
//!
//! Results do not depend on `jobs`: every simulation is deterministic on any number of threads (one
//! per run, unless fewer runs are left than threads: see `run_all`), and the summary is sorted by
//! run index whatever order runs finish in.

use std::collections::HashSet;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;

mod batch;
pub mod checkpoints;
mod execute;
pub mod interrupt;
pub mod merge;
mod notes;
mod outcome;
mod progress;
mod reuse;
pub mod shard;
mod warnings;
mod writer_thread;

pub use batch::{Batch, run_batches};
pub use merge::{MergeOptions, MergeReport, ShardProblem, merge};
pub use notes::{NotePolicy, RunNote, WorkerCap};
pub use outcome::{EXIT_PARTIAL, RunCounts, SweepOutcome};
pub use progress::ProgressMode;
pub use warnings::WarningDigest;
pub use writer_thread::CommitPolicy;

use crate::output::header::utc_now;
use crate::output::lock::ResultsLock;
use crate::output::table::ColumnData;
use crate::output::{
    self, DynSink, FileHeader, OutputError, OutputReason, ResultsWriter, RunResult, ShardInfo, ShardSpec, SinkError,
    SummaryTable,
};
use crate::physics::Threads;
use crate::physics::parallel::PARALLEL_MIN_DISKS;
use crate::physics::vector::{self, Width};
use crate::study::{Plan, PlannedRun, RunIdentity};
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
    /// The HDF5 results file.
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
/// summary and points; see [`RunOptions`].
pub fn run_plan(plan: &Plan, options: &RunOptions) -> Result<RunReport, RunnerError> {
    run_plan_with(plan, options, Vec::new())
}

/// [`run_plan`], handing the runs also to `sinks`, after the results file: each gets the runs this
/// invocation makes and, at the end, the tables of every run in the file.
pub fn run_plan_with(plan: &Plan, options: &RunOptions, sinks: Vec<DynSink>) -> Result<RunReport, RunnerError> {
    let started = std::time::Instant::now();
    let selected = match options.shard {
        Some(spec) => shard::select(plan, spec),
        None => (0..plan.runs.len()).collect(),
    };
    let path = results_path(plan, options);
    let (_lock, mut writer, header) = open_results(plan, options, &path, &selected)?;
    let identities: Vec<String> = RunIdentity::all(&plan.runs).iter().map(ToString::to_string).collect();
    let stored = writer.take_existing();
    let reuse = reuse::Reuse::new(plan, &identities, (&selected, options.accept_version), stored, &mut writer)?;
    if let Some(header) = header {
        writer.set_header(&header)?;
    }
    if options.drop_unplanned {
        writer.forget(&reuse.unplanned.iter().map(|r| r.group_name().to_string()).collect::<Vec<_>>())?;
    }
    let mut notes = reuse.notes(options.drop_unplanned);
    let (existing, aliases) = (reuse.rows, reuse.aliases);
    let done: HashSet<usize> = existing.iter().map(|r| r.index).collect();
    let mut todo: Vec<Todo> = reuse.todo.iter().map(|&i| (&plan.runs[i], identities[i].as_str(), 0)).collect();
    todo.sort_by(|(a, ..), (b, ..)| b.estimated_cost.total_cmp(&a.estimated_cost).then(a.index.cmp(&b.index)));
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let (jobs, capped) = worker_count(options.jobs, todo.len(), cores);
    notes.extend(capped);
    RunNote::print_all(notes.iter().filter(|n| options.notes.prints(n)), &path, options.progress);
    writer.note_sweep(jobs, started);
    let view = ProgressView::new(options.progress, selected.len(), done.len(), jobs);
    let checkpointing =
        options.checkpoint_every.map(|every| Checkpointing { results: path.clone(), every, resume: options.resume });
    let remove_stored = checkpointing.as_ref().map(|_| output::dyn_sink(checkpoints::RemoveStored::new(&path)));
    let sinks = std::iter::once(output::dyn_sink(writer)).chain(remove_stored).chain(sinks).collect();
    let group = writer_thread::Sinks { committed: existing, aliases, ..writer_thread::Sinks::new(sinks) };
    let threads = pool_threads(options.jobs, cores);
    let how = (options.commit, checkpointing.as_ref());
    let swept = sweep(&todo, vec![group], (jobs, threads), &view, how, &options.stop)?;
    let Swept { ran, warnings, mut tables, writer_time } = swept;
    let tables = tables.pop().expect("one group");
    if let Some(ColumnData::Text(ids)) = tables.summary.column("run_id").map(|c| &c.data) {
        checkpoints::remove_finished(&path, ids.iter().cloned());
    }
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

/// The environment variable that sets from how many disks a run uses the threads it is given
/// (default [`PARALLEL_MIN_DISKS`]): for tests and measurements of small scenes.
pub const PARALLEL_MIN_DISKS_VARIABLE: &str = "DEMSWEEP_PARALLEL_MIN_DISKS";

/// The value of [`PARALLEL_MIN_DISKS_VARIABLE`], or the default.
pub fn parallel_min_disks() -> Result<usize, RunnerError> {
    std::env::var(PARALLEL_MIN_DISKS_VARIABLE).map_or(Ok(PARALLEL_MIN_DISKS), |text| min_disks_in(&text))
}

/// The disk count `text` (a value of [`PARALLEL_MIN_DISKS_VARIABLE`]) holds.
fn min_disks_in(text: &str) -> Result<usize, RunnerError> {
    text.trim().parse().map_err(|_| RunnerError::Environment {
        variable: PARALLEL_MIN_DISKS_VARIABLE,
        value: text.into(),
        expected: "a whole number of disks".into(),
    })
}

/// The environment variable that names the vector instructions the engine's hot loops run in
/// (`baseline`, `avx2`, `avx512`; default: the widest this CPU runs well, see
/// `physics::vector::width`): for measurements. Results are the same bits in every width.
pub const VECTOR_WIDTH_VARIABLE: &str = "DEMSWEEP_VECTOR";

/// Sets the width named by [`VECTOR_WIDTH_VARIABLE`], if it is set.
pub fn use_vector_width() -> Result<(), RunnerError> {
    if let Ok(text) = std::env::var(VECTOR_WIDTH_VARIABLE) {
        vector::use_width(width_in(&text)?);
    }
    Ok(())
}

/// The width `text` (a value of [`VECTOR_WIDTH_VARIABLE`]) names.
fn width_in(text: &str) -> Result<Width, RunnerError> {
    Width::parse(text.trim()).ok_or_else(|| {
        let names: Vec<_> = Width::ALL.iter().map(|w| w.name()).collect();
        RunnerError::Environment {
            variable: VECTOR_WIDTH_VARIABLE,
            value: text.into(),
            expected: format!("one of {}", names.join(", ")),
        }
    })
}

/// `OUT/<name>.h5`, or `OUT/<name>.shard-K-of-N.h5` for a shard, K zero-padded to the digits of N
/// (`shard-03-of-12`) so that the shards list in order; a shard file written before the padding
/// (`shard-3-of-12`) is continued under its own name.
pub fn results_path(plan: &Plan, options: &RunOptions) -> PathBuf {
    let dir = options.out_dir.clone().unwrap_or_else(|| Path::new("results").join(&plan.name));
    let Some(s) = options.shard else { return dir.join(format!("{}.h5", plan.name)) };
    let width = s.count.to_string().len();
    let padded = dir.join(format!("{}.shard-{:0width$}-of-{}.h5", plan.name, s.index, s.count));
    let unpadded = dir.join(format!("{}.shard-{}-of-{}.h5", plan.name, s.index, s.count));
    if !padded.exists() && unpadded.exists() { unpadded } else { padded }
}

/// Takes the results file's lock, then creates the file, or opens it to resume after checking it
/// holds this study (and shard); with the header a resumed file of an edited study takes once its
/// stored runs are accepted. The lock is held until the returned guard is dropped.
fn open_results(
    plan: &Plan,
    options: &RunOptions,
    path: &Path,
    selected: &[usize],
) -> Result<(ResultsLock, ResultsWriter, Option<FileHeader>), RunnerError> {
    let dir = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(|e| OutputError::io_doing(dir, "cannot create the output directory", e))?;
    check_writable(dir)?;
    // The CSV files and report page are written last: checked before anything runs or is replaced.
    output::check_companions(path, options.force, options.resume)?;
    let lock = ResultsLock::acquire(path)?;
    let exists = path.exists();
    if exists && options.resume {
        let (mut writer, header) =
            ResultsWriter::open(path, plan.output.clone()).map_err(|e| cannot_resume(path, e))?;
        check_same_study(path, &header, plan, options.shard, writer.has_identities())?;
        // The header is the study's once its stored runs are accepted (see `run_plan`).
        let header = (header.fingerprint != plan.fingerprint).then(|| FileHeader {
            study_text: plan.study_text.clone(),
            fingerprint: plan.fingerprint.clone(),
            planned_runs: plan.runs.len(),
            shard: options.shard.map(|spec| ShardInfo { spec, runs: selected.to_vec() }),
            ..header
        });
        // Damaged first: deleting a failed run rebuilds its batch, which needs every header in it.
        let damaged = writer.forget_damaged()?;
        writer.forget_failed()?;
        // A warning about stored results, not progress: shown whatever the progress display.
        if !damaged.is_empty() {
            crate::output::terminal::err(format_args!(
                "warning: {}: {}; they run now\n",
                path.display(),
                output::reader::damage_text(&damaged)
            ));
        }
        return Ok((lock, writer, header));
    }
    if exists && !options.force {
        return Err(OutputError::at(path, OutputReason::Exists { resumable: true }).into());
    }
    if exists {
        output::guard::check_results_replaceable(path, &[&plan.study_path])
            .map_err(|e| OutputError::refused(path, e))?;
        std::fs::remove_file(path).map_err(|e| OutputError::io(path, e))?;
    }
    let header = FileHeader {
        study_name: plan.name.clone(),
        study_text: plan.study_text.clone(),
        fingerprint: plan.fingerprint.clone(),
        demsweep_version: env!("CARGO_PKG_VERSION").to_string(),
        created: utc_now(),
        planned_runs: plan.runs.len(),
        shard: options.shard.map(|spec| ShardInfo { spec, runs: selected.to_vec() }),
    };
    Ok((lock, ResultsWriter::create(path, &header, plan.output.clone())?, None))
}

/// A results file that cannot be opened to resume: when it is one (cut short by a full disk or a
/// copy that stopped, or damaged), the error says how to go on.
fn cannot_resume(path: &Path, error: OutputError) -> OutputError {
    match output::guard::is_hdf5(path) {
        true => OutputError::at(path, OutputReason::CannotContinue(error.reason)),
        false => error,
    }
}

/// Fails early, naming the directory, when files cannot be created in it.
fn check_writable(dir: &Path) -> Result<(), OutputError> {
    let probe = dir.join(format!(".demsweep-write-test-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(|e| OutputError::io_doing(dir, "the output directory is not writable", e))?;
    std::fs::remove_file(&probe).map_err(|e| OutputError::io(&probe, e))
}

fn check_same_study(
    path: &Path,
    header: &FileHeader,
    plan: &Plan,
    shard: Option<ShardSpec>,
    identities: bool,
) -> Result<(), OutputError> {
    if header.fingerprint != plan.fingerprint && !identities {
        let (name, fingerprint) = (header.study_name.clone(), header.fingerprint.clone());
        let other = OutputReason::OtherStudy { name, fingerprint, expected: plan.fingerprint.clone() };
        return Err(OutputError::at(path, other));
    }
    let file_shard = header.shard.as_ref().map(|s| s.spec);
    if file_shard != shard {
        return Err(OutputError::at(path, OutputReason::OtherShard { file: file_shard, this: shard }));
    }
    Ok(())
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
    groups: Vec<writer_thread::Sinks>,
    (jobs, threads): (usize, usize),
    view: &ProgressView,
    (commit, checkpointing): (CommitPolicy, Option<&Checkpointing>),
    stop: &Arc<AtomicBool>,
) -> Result<Swept, RunnerError> {
    let (sender, receiver) = mpsc::sync_channel(jobs * writer_thread::BACKLOG_PER_WORKER);
    let writing = writer_thread::spawn(groups, receiver, commit, stop.clone());
    let deliver = |position: usize, result| sender.send((todo[position].2, result)).is_ok();
    let ran = run_all(todo, (jobs, threads), (stop, checkpointing), view, &deliver);
    drop(sender); // the writer thread finishes once the channel closes
    let warnings = view.finish();
    let (tables, writer_time) = writing.join().map_err(|_| RunnerError::WriterPanicked)??;
    Ok(Swept { ran: ran?, warnings, tables, writer_time })
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
    fn environment_values_are_read_or_refused_as_typed_errors() {
        assert_eq!(min_disks_in(" 500 "), Ok(500));
        assert_eq!(width_in("avx2"), Ok(Width::Avx2));
        let refused = RunnerError::Environment {
            variable: VECTOR_WIDTH_VARIABLE,
            value: "avx1024".into(),
            expected: "one of baseline, avx2, avx512".into(),
        };
        assert_eq!(width_in("avx1024"), Err(refused));
        match min_disks_in("many") {
            Err(RunnerError::Environment { variable, value, .. }) => {
                assert_eq!((variable, value.as_str()), (PARALLEL_MIN_DISKS_VARIABLE, "many"))
            }
            other => panic!("{other:?}"),
        }
    }

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
