//! The CSV tables beside a results file as a sink: the summary and points tables, each with its
//! metadata sidecar, written at the end from the tables the runner hands its sinks.

use std::path::{Path, PathBuf};

use super::sink::{ResultSink, Tables};
use super::{OutputError, write_csv_files};

/// Writes `<stem>_summary.csv` and `<stem>_points.csv` next to a results file when the sweep
/// finishes. Listed after the results file's sink, whose last commit then holds every row of them.
pub struct CsvTables {
    results: PathBuf,
}

impl CsvTables {
    /// The CSV tables beside the results file `results`.
    pub fn new(results: &Path) -> Self {
        Self { results: results.to_path_buf() }
    }
}

impl ResultSink for CsvTables {
    type Error = OutputError;

    fn finish(&mut self, tables: &Tables) -> Result<(), OutputError> {
        write_csv_files(&self.results, tables).map(drop)
    }
}
