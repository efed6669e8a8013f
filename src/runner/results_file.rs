//! The results file of a sweep: where it goes, opened (created, or continued with `--resume`) under
//! its lock, its stored runs sorted into those reused and those to make, and the sinks that write it.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::checkpoints::{Checkpointing, RemoveStored};
use super::reuse::Reuse;
use super::start::{self, Start};
use super::{RunOptions, RunnerError, worker_count};
use crate::output::header::utc_now;
use crate::output::lock::ResultsLock;
use crate::output::{
    self, CsvTables, DynSink, FileHeader, OutputError, OutputReason, ResultsWriter, ShardInfo, ShardSpec, dyn_sink,
};
use crate::study::Plan;

/// Opens the results file of a sweep of `plan` with `options` (see [`RunOptions`]): the file,
/// created or continued, and the sweep's [`Start`] (its lock, the stored runs it reuses, the runs to
/// make, the notes about them); stored runs it no longer needs are deleted from the file.
pub fn open_results(plan: &Plan, options: &RunOptions) -> Result<(Start, ResultsWriter), RunnerError> {
    let started = Instant::now();
    let selected = start::selected(plan, options);
    let path = results_path(plan, options);
    let (lock, mut writer, header) = open_file(plan, options, &path, &selected)?;
    let identities = start::identities(plan);
    let stored = writer.take_existing();
    let reuse = Reuse::new(plan, &identities, (&selected, options.accept_version), stored, &mut writer)?;
    if let Some(header) = header {
        writer.set_header(&header)?;
    }
    if options.drop_unplanned {
        writer.forget(&reuse.unplanned.iter().map(|r| r.group_name().to_string()).collect::<Vec<_>>())?;
    }
    let notes = reuse.notes(options.drop_unplanned);
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    writer.note_sweep(worker_count(options.jobs, reuse.todo.len(), cores).0, started);
    let checkpointing =
        options.checkpoint_every.map(|every| Checkpointing { results: path.clone(), every, resume: options.resume });
    let start = Start {
        results: path,
        lock: Some(lock),
        started,
        selected,
        identities,
        stored: reuse.rows,
        todo: reuse.todo,
        aliases: reuse.aliases,
        notes,
        checkpointing,
    };
    Ok((start, writer))
}

/// The sinks that write a results file, in the order that keeps it safe: the file (run groups at
/// each commit, `/summary` and `/points` at the end), then its CSV tables (written only once the
/// file's last commit holds their rows), then the removal of the stored runs' checkpoints (each
/// after the commit that stored its run).
pub fn results_sinks(writer: ResultsWriter) -> Vec<DynSink<'static>> {
    let path = writer.path().to_path_buf();
    vec![dyn_sink(writer), dyn_sink(CsvTables::new(&path)), dyn_sink(RemoveStored::new(&path))]
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
fn open_file(
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
        // The header is the study's once its stored runs are accepted (see `open_results`).
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
