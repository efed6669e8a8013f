//! The error of every results-file operation: the file concerned and what went wrong, as a typed
//! reason whose text [`OutputReason`]'s `Display` makes.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use super::guard::{GuardError, Refusal};
use super::header::ShardSpec;
use super::layout_error::LayoutError;
use crate::study::name::NameError;

/// A results-file problem, naming the file.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputError {
    /// The file or directory concerned.
    pub path: PathBuf,
    /// What went wrong (boxed: errors stay small in the `Result`s of the paths that succeed).
    pub reason: Box<OutputReason>,
}

/// What went wrong with a results file (or its folder, lock, companions).
#[derive(Debug, Clone, PartialEq)]
pub enum OutputReason {
    /// An I/O operation failed.
    Io {
        /// What was being done, shown before the error; `None` for a plain I/O error.
        doing: Option<&'static str>,
        /// The kind of the error.
        kind: io::ErrorKind,
        /// The error's text.
        text: String,
    },
    /// The HDF5 library reports a problem.
    Hdf5(String),
    /// Another process has the file open for writing.
    OpenElsewhere,
    /// Another demsweep process writes the results: who (the lock file's text; empty if unknown).
    Locked { holder: String },
    /// The lock file keeps being removed by other processes.
    LockContended,
    /// The results exist and the caller asked neither to continue nor to overwrite them.
    Exists {
        /// Whether `--resume` could continue them (a sweep) or only `--force` replace them (a merge).
        resumable: bool,
    },
    /// The path is not ours to write or replace.
    Refused(Refusal),
    /// The file holds results of another study, written before runs had identities.
    OtherStudy { name: String, fingerprint: String, expected: String },
    /// The file was written for another shard (or the whole study).
    OtherShard { file: Option<ShardSpec>, this: Option<ShardSpec> },
    /// The file cannot be continued: cut short or damaged.
    CannotContinue(Box<OutputReason>),
    /// No file at the path.
    NoSuchFile,
    /// A folder holding no results file.
    NoResultsFile,
    /// A folder holding several results files: their names.
    SeveralResultsFiles(Vec<String>),
    /// A file that is not HDF5, named by an extension of another format.
    NotHdf5 { extension: String, error: String },
    /// An HDF5 file whose header is not demsweep's.
    NotResults(LayoutError),
    /// No run of this id.
    NoRun(String),
    /// No run group for a run the summary lists.
    NoGroup(String),
    /// A run without histories.
    NoHistories(String),
    /// The run has no stress profile (failed run, histories off, or a file written before profiles).
    NoStressProfile(String),
    /// Run groups that cannot be read.
    Damaged(Vec<DamagedGroup>),
    /// A dataset of a run that cannot be read.
    BadData { run: String, dataset: String, reason: LayoutError },
    /// A run group to copy that cannot be read.
    BadCopy { group: String, reason: LayoutError },
    /// Stored runs made by another demsweep version: the first's id and version, and how many.
    OtherVersions { run: String, version: String, count: usize },
    /// A merge with no shard files: whether a folder (else the command line) was searched.
    NoShards { in_folder: bool },
    /// A merged file's name (`--name`) that cannot name a study.
    BadName(NameError),
    /// Shards of different studies or splits: what differs and the two files.
    DifferentStudies { why: String, first: String, other: String },
    /// Runs of different demsweep versions in a merge.
    DifferentVersions { run: String, version: String, first_run: String, first_file: PathBuf, first_version: String },
    /// A run without identity in a merge of different studies.
    NoIdentity { run: String },
    /// Runs of different physics versions in a merge.
    DifferentPhysics { version: u32, other: PathBuf, other_version: u32 },
    /// Two shards holding the same run.
    Overlap { other: PathBuf, run: String, index: usize },
    /// A reason given in words by a layer above (a report's, a command's).
    Other(String),
}

impl OutputError {
    /// An error about `path`.
    pub fn at(path: &Path, reason: OutputReason) -> Self {
        Self { path: path.to_path_buf(), reason: Box::new(reason) }
    }

    /// An error about `path` whose reason a layer above gives in words.
    pub fn new(path: &Path, message: impl Into<String>) -> Self {
        Self::at(path, OutputReason::Other(message.into()))
    }

    /// `path` refused by the guard of output paths (`error`'s path may be a file beside it).
    pub fn refused(path: &Path, error: GuardError) -> Self {
        Self::at(path, OutputReason::Refused(error.refusal))
    }

    /// An I/O error on `path`.
    pub fn io(path: &Path, error: io::Error) -> Self {
        Self::at(path, OutputReason::io(None, &error))
    }

    /// An I/O error on `path` while `doing` something.
    pub fn io_doing(path: &Path, doing: &'static str, error: io::Error) -> Self {
        Self::at(path, OutputReason::io(Some(doing), &error))
    }
}

impl OutputReason {
    fn io(doing: Option<&'static str>, error: &io::Error) -> Self {
        OutputReason::Io { doing, kind: error.kind(), text: error.to_string() }
    }
}

impl fmt::Display for OutputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.reason)
    }
}

impl fmt::Display for OutputReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use OutputReason::*;
        match self {
            Io { doing: None, text, .. } => write!(f, "{text}"),
            Io { doing: Some(doing), text, .. } => write!(f, "{doing}: {text}"),
            Hdf5(text) | Other(text) => write!(f, "{text}"),
            OpenElsewhere => {
                write!(f, "is open for writing in another process: wait for it to finish or stop it, then try again")
            }
            Locked { holder } => locked(f, holder),
            LockContended => write!(f, "cannot lock: the lock file keeps being removed by other processes"),
            Exists { resumable } => exists(f, *resumable),
            Refused(refusal) => write!(f, "{refusal}"),
            OtherStudy { name, fingerprint, expected } => other_study(f, name, fingerprint, expected),
            OtherShard { file, this } => {
                let show = |s: &Option<ShardSpec>| s.map_or("the whole study".to_string(), |s| format!("shard {s}"));
                write!(f, "was written for {} but this run is for {}", show(file), show(this))
            }
            CannotContinue(reason) => cannot_continue(f, reason),
            NoSuchFile => write!(f, "no such results file"),
            NoResultsFile => write!(f, "no results file (*.h5) in this folder"),
            SeveralResultsFiles(names) => {
                write!(f, "holds {} results files ({}): name one of them", names.len(), names.join(", "))
            }
            NotHdf5 { extension, error } => not_hdf5(f, extension, error),
            NotResults(reason) => write!(f, "not a demsweep results file: {reason}"),
            NoRun(run) => write!(f, "no run `{run}` in this file (see `demsweep summary` for the run ids)"),
            NoGroup(run) => write!(f, "no group for run `{run}` in this file"),
            NoHistories(run) => {
                write!(f, "run `{run}` has no histories (failed run, or the study's output.histories is off)")
            }
            NoStressProfile(run) => no_stress_profile(f, run),
            Damaged(damaged) => write!(f, "{}", damage_text(damaged)),
            BadData { run, dataset, reason } => write!(f, "run {run}: /{dataset} cannot be read: {reason}"),
            BadCopy { group, reason } => write!(f, "/{group}: {reason}"),
            OtherVersions { run, version, count } => other_versions(f, run, version, *count),
            NoShards { in_folder: true } => write!(f, "no shard files (*.shard-K-of-N.h5) in this directory"),
            NoShards { in_folder: false } => write!(f, "no shard files given"),
            BadName(error) => write!(f, "--name `{}`: {error}", error.name.escape_debug()),
            DifferentStudies { why, first, other } => different_studies(f, why, first, other),
            DifferentVersions { run, version, first_run, first_file, first_version } => {
                different_versions(f, run, version, first_run, first_file, first_version)
            }
            NoIdentity { run } => no_identity(f, run),
            DifferentPhysics { version, other, other_version } => different_physics(f, *version, other, *other_version),
            Overlap { other, run, index } => {
                write!(f, "overlaps {}: both hold run {run} (plan index {index})", other.display())
            }
        }
    }
}

/// [`OutputReason::Locked`]: who writes the results, and what to do.
fn locked(f: &mut fmt::Formatter<'_>, holder: &str) -> fmt::Result {
    let who = if holder.is_empty() { "another process".into() } else { format!("another process ({holder})") };
    write!(
        f,
        "is being written by {who}: wait for it to finish or stop it (Ctrl-C), then use --resume; \
         or write elsewhere with another --out"
    )
}

/// [`OutputReason::Exists`]: the results exist, and how to continue or replace them.
fn exists(f: &mut fmt::Formatter<'_>, resumable: bool) -> fmt::Result {
    if !resumable {
        return write!(f, "already exists: use --force to overwrite it");
    }
    write!(
        f,
        "results already exist: use --resume to continue them (only missing runs are run) or --force to \
         overwrite them"
    )
}

/// [`OutputReason::OtherStudy`]: results of another study, which cannot be matched.
fn other_study(f: &mut fmt::Formatter<'_>, name: &str, fingerprint: &str, expected: &str) -> fmt::Result {
    write!(
        f,
        "holds results of a different study (`{name}`, fingerprint {fingerprint}; this study's fingerprint \
         is {expected}) written before runs had identities, so its runs cannot be matched to this study's: \
         use another --out directory, or --force to overwrite"
    )
}

/// [`OutputReason::CannotContinue`]: why, and how to start again.
fn cannot_continue(f: &mut fmt::Formatter<'_>, reason: &OutputReason) -> fmt::Result {
    write!(
        f,
        "cannot be continued: {reason}: the file was cut short or is damaged; run it again from the start \
         with --force in place of --resume (this replaces the file: move it away first to keep it)"
    )
}

/// [`OutputReason::NotHdf5`]: the file a command reads, and what the named file is.
fn not_hdf5(f: &mut fmt::Formatter<'_>, extension: &str, error: &str) -> fmt::Result {
    write!(
        f,
        "not a results file ({error}): demsweep reads the HDF5 file (.h5) a run wrote; a .{extension} file \
         (such as the _summary.csv or _points.csv beside it) is one of its tables"
    )
}

/// [`OutputReason::NoStressProfile`]: why a run may have none.
fn no_stress_profile(f: &mut fmt::Formatter<'_>, run: &str) -> fmt::Result {
    write!(
        f,
        "run `{run}` has no stress profile (failed run, the study's output.histories is off, or a file \
         written before stress profiles)"
    )
}

/// [`OutputReason::OtherVersions`]: the first run made by another version, and the choices.
fn other_versions(f: &mut fmt::Formatter<'_>, run: &str, version: &str, count: usize) -> fmt::Result {
    let more = match count {
        1 => String::new(),
        n => format!(" (and {} more of the runs this study reuses)", n - 1),
    };
    write!(
        f,
        "run {run}{more} was made by demsweep {version}, this is {} (both physics version {}): \
         `--resume --accept-version` reuses the stored runs (each keeps the version that made it, in \
         /summary/demsweep_version), `--force` runs every run again",
        super::row::DEMSWEEP_VERSION,
        crate::physics::PHYSICS_VERSION
    )
}

/// [`OutputReason::DifferentStudies`]: what differs, and the two files.
fn different_studies(f: &mut fmt::Formatter<'_>, why: &str, first: &str, other: &str) -> fmt::Result {
    write!(
        f,
        "cannot merge shards of different studies or splits ({why}): run them again from the same study \
         file and inputs:\n  {first}\n  {other}"
    )
}

/// [`OutputReason::DifferentVersions`]: the two runs and their versions, and the choices.
fn different_versions(
    f: &mut fmt::Formatter<'_>,
    run: &str,
    version: &str,
    first_run: &str,
    first_file: &Path,
    first_version: &str,
) -> fmt::Result {
    write!(
        f,
        "run {run} was made by demsweep {version}, but run {first_run} of {} by {first_version}: \
         `merge --accept-version` merges them (each run keeps the version that made it, in \
         /summary/demsweep_version), or run one of them again with this demsweep",
        first_file.display()
    )
}

/// [`OutputReason::NoIdentity`]: what a run without identity can merge with.
fn no_identity(f: &mut fmt::Formatter<'_>, run: &str) -> fmt::Result {
    write!(
        f,
        "run {run} has no run identity (a file written before them): it can only merge with shards of its \
         own study"
    )
}

/// [`OutputReason::DifferentPhysics`]: the two physics versions.
fn different_physics(f: &mut fmt::Formatter<'_>, version: u32, other: &Path, other_version: u32) -> fmt::Result {
    write!(
        f,
        "holds runs of physics version {version} but {} of version {other_version}: rerun one of them with \
         this demsweep",
        other.display()
    )
}

impl std::error::Error for OutputError {}

/// An HDF5 error on `path`.
pub(crate) fn hdf5_error(path: &Path, error: hdf5_pure::Error) -> OutputError {
    match error {
        hdf5_pure::Error::FileLocked(_) => OutputError::at(path, OutputReason::OpenElsewhere),
        other => OutputError::at(path, OutputReason::Hdf5(other.to_string())),
    }
}

/// A run group that cannot be read (overwritten bytes, a failed disk): its path and the reason.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DamagedGroup {
    /// The group, e.g. `/runs_00000/r0012` (a whole batch, `/runs_00003`, when its index is damaged).
    pub group: String,
    /// What could not be read.
    pub reason: LayoutError,
}

/// What is wrong with a file whose `damaged` run groups cannot be read, and what to do.
pub fn damage_text(damaged: &[DamagedGroup]) -> String {
    let named: Vec<String> = damaged.iter().take(10).map(|d| format!("{} ({})", d.group, d.reason)).collect();
    let more = if damaged.len() > 10 { format!(" and {} more", damaged.len() - 10) } else { String::new() };
    format!(
        "damaged: {} run group(s) cannot be read: {}{more}; `demsweep run STUDY --resume` on this file runs them again",
        damaged.len(),
        named.join(", ")
    )
}
