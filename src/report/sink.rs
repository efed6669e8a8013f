//! The report page as a sink: written when a sweep finishes, from the tables its runner computed.

use std::convert::Infallible;
use std::path::{Path, PathBuf};

use super::{ReportContext, Written, write_report_of};
use crate::output::guard::Existing;
use crate::output::{ResultSink, Tables};

/// Writes the report page of a results file (to [`super::report_path`]) when the sweep finishes,
/// with the summary and per-point statistics the runner hands its sinks; the results file's sink
/// comes before it in the list, so that the page reads the file it closed. The caller lends it to
/// the runner and reads [`Self::written`] afterwards: a page that cannot be written leaves the
/// results whole, so it does not stop the sweep.
pub struct ReportSink {
    results: PathBuf,
    existing: Existing,
    context: ReportContext,
    written: Option<Written>,
}

impl ReportSink {
    /// The page of the results file `results`, replacing a page there as `existing` allows.
    pub fn new(results: &Path, existing: Existing, context: ReportContext) -> Self {
        Self { results: results.to_path_buf(), existing, context, written: None }
    }

    /// The page written, or why not; `None` when the sweep did not finish.
    pub fn written(self) -> Option<Written> {
        self.written
    }
}

impl ResultSink for ReportSink {
    type Error = Infallible;

    fn finish(&mut self, tables: &Tables) -> Result<(), Infallible> {
        self.written = Some(write_report_of(&self.results, tables, (None, self.existing), &self.context));
        Ok(())
    }
}
