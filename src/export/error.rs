//! Why an export failed, as a value: the variant says what, its fields name the file, run and
//! option; the text is made where a person reads it ([`std::fmt::Display`]).

use std::fmt;
use std::path::PathBuf;

use crate::output::OutputError;
use crate::output::guard::GuardError;

/// Why an export failed.
#[derive(Debug)]
pub enum ExportError {
    /// The output folder is refused (exists without `--force`, not demsweep's, an input's folder…).
    Guard(GuardError),
    /// The results file, or a run in it, cannot be read.
    Output(OutputError),
    /// A run asked for with `--run` lies in a damaged group.
    DamagedRun {
        /// The results file.
        results: PathBuf,
        /// The damaged group.
        group: String,
        /// What could not be read.
        reason: String,
    },
    /// No run has this id (`--run`).
    UnknownRun {
        /// The results file.
        results: PathBuf,
        /// The id asked for.
        id: String,
    },
    /// The run has no stored final state.
    NoFinalState {
        /// The results file.
        results: PathBuf,
        /// The run's id.
        id: String,
        /// The run's status (`settled`, `failed`, …).
        status: String,
    },
    /// `--frames` was asked for and the run has no stored frames.
    NoFrames {
        /// The results file.
        results: PathBuf,
        /// The run's id.
        id: String,
    },
    /// A format's writer failed on a run.
    Write {
        /// The folder written into.
        folder: PathBuf,
        /// The run's id.
        id: String,
        /// Which file, and why.
        source: WriteError,
    },
    /// The written folder cannot be listed.
    Io {
        /// The folder.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
}

impl fmt::Display for ExportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ExportError::Guard(e) => write!(f, "{e}"),
            ExportError::Output(e) => write!(f, "{e}"),
            ExportError::DamagedRun { results, group, reason } => {
                write!(f, "{}: run group {group} cannot be read ({reason})", results.display())
            }
            ExportError::UnknownRun { results, id } => write!(
                f,
                "{}: no run `{id}` (--run): see `demsweep summary {}` for the run ids",
                results.display(),
                results.display()
            ),
            ExportError::NoFinalState { results, id, status } => write!(
                f,
                "{}: run {id} has no stored final state (status {status}; its study had output.final_states = \
                 false, or it failed): leave it out of --run, or run it again with output.final_states = true",
                results.display()
            ),
            ExportError::NoFrames { results, id } => write!(
                f,
                "{}: run {id} has no stored frames (--frames): run it again with output.frames = true and \
                 run.frame_times or run.frame_interval set, or leave out --frames",
                results.display()
            ),
            ExportError::Write { folder, id, source } => write!(f, "{}: run {id}: {source}", folder.display()),
            ExportError::Io { path, source } => write!(f, "{}: cannot list: {source}", path.display()),
        }
    }
}

impl std::error::Error for ExportError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ExportError::Guard(e) => Some(e),
            ExportError::Output(e) => Some(e),
            ExportError::Io { source, .. } => Some(source),
            ExportError::Write { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// Why a format's writer could not write one of its files.
#[derive(Debug)]
pub enum WriteError {
    /// The file cannot be created: the output guard refuses the path, or the folder does not take it.
    Create(GuardError),
    /// Writing into the created file (`path`) failed: disk full, quota, I/O error.
    Write { path: PathBuf, source: std::io::Error },
}

impl fmt::Display for WriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WriteError::Create(e) => write!(f, "{e}"),
            WriteError::Write { path, source } => write!(f, "{}: cannot write: {source}", path.display()),
        }
    }
}

impl std::error::Error for WriteError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            WriteError::Create(e) => Some(e),
            WriteError::Write { source, .. } => Some(source),
        }
    }
}

impl From<GuardError> for ExportError {
    fn from(e: GuardError) -> Self {
        ExportError::Guard(e)
    }
}

impl From<OutputError> for ExportError {
    fn from(e: OutputError) -> Self {
        ExportError::Output(e)
    }
}
