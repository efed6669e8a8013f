//! The error of every results-file operation: the file concerned and what went wrong.

use std::fmt;
use std::path::{Path, PathBuf};

/// A results-file problem, naming the file.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputError {
    /// The file or directory concerned.
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

impl OutputError {
    /// An error about `path`.
    pub fn new(path: &Path, message: impl Into<String>) -> Self {
        Self { path: path.to_path_buf(), message: message.into() }
    }

    /// An I/O error on `path`.
    pub fn io(path: &Path, error: std::io::Error) -> Self {
        Self::new(path, error.to_string())
    }
}

impl fmt::Display for OutputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for OutputError {}

/// An HDF5 error on `path`.
pub(crate) fn hdf5_error(path: &Path, error: hdf5_pure::Error) -> OutputError {
    match error {
        hdf5_pure::Error::FileLocked(_) => OutputError::new(
            path,
            "is open for writing in another process: wait for it to finish or stop it, then try again",
        ),
        other => OutputError::new(path, other.to_string()),
    }
}
