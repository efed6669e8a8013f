//! Result files: one HDF5 file per study (or shard) and a CSV summary next to it.
//!
//! Data flows one way: runner → [`ResultSink`]s; the results file ([`ResultsWriter`])
//! is one: run groups committed in batches, then `/summary`, `/points` and [`write_csv_files`] from
//! the tables the runner computes. This layer reads and writes; it computes no statistics. The
//! layout is in [`layout`] and docs/results.md.

use std::fmt;
use std::path::{Path, PathBuf};

pub(crate) mod compound;
pub(crate) mod copy;
pub(crate) mod csv;
pub mod guard;
pub mod header;
pub mod history;
pub mod layout;
pub mod lock;
pub mod reader;
pub mod row;
pub mod run_attrs;
mod sink;
pub mod stored;
pub mod summary;
pub mod table;
pub mod terminal;
mod writer;

pub use compound::Field;
pub use header::{FileHeader, ShardInfo, ShardSpec};
pub use row::SummaryRow;
pub use sink::{ResultSink, RunResult, Tables};
pub use table::SummaryTable;
pub use writer::ResultsWriter;

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

/// The summary CSV path next to a results file: `<stem>_summary.csv`.
pub fn csv_path(results: &Path) -> PathBuf {
    sibling(results, "summary")
}

/// The per-point CSV path next to a results file: `<stem>_points.csv`.
pub fn points_csv_path(results: &Path) -> PathBuf {
    sibling(results, "points")
}

/// The report page path next to a results file: `<stem>_report.html` (`<study name>_report.html`
/// for a study's results, `<study name>.shard-K-of-N_report.html` for a shard's, so that shards never
/// share a page).
pub fn report_path(results: &Path) -> PathBuf {
    let stem = results.file_stem().unwrap_or_default().to_string_lossy();
    results.with_file_name(format!("{stem}_report.html"))
}

/// `<stem>_<what>.csv` next to a results file.
fn sibling(results: &Path, what: &str) -> PathBuf {
    let stem = results.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    results.with_file_name(format!("{stem}_{what}.csv"))
}

/// Writes the summary and points CSV files next to a results file (each whole or not at all, see
/// [`guard::write_with`]); returns their paths. Whoever writes the results file checks them first
/// ([`check_companions`]).
pub fn write_csv_files(results: &Path, tables: &Tables) -> Result<(PathBuf, PathBuf), OutputError> {
    let (summary, points) = (csv_path(results), points_csv_path(results));
    summary::write_csv(&summary, &tables.summary, guard::Existing::Any)?;
    summary::write_csv(&points, &tables.points, guard::Existing::Any)?;
    Ok((summary, points))
}

/// Checks, before a results file is written, that the files written beside it (its CSV files and
/// report page) may be: no link, and only files demsweep wrote unless `force`.
pub fn check_companions(results: &Path, force: bool) -> Result<(), OutputError> {
    for path in [csv_path(results), points_csv_path(results), report_path(results)] {
        guard::check_replaceable(&path, &[results], guard::Existing::Ours { force })
            .map_err(|e| OutputError::new(&path, e.refusal_text()))?;
    }
    Ok(())
}
