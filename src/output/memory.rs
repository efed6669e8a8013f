//! Results kept in memory: a result sink that keeps the summary table the runner hands it at the end,
//! for callers that want a sweep's table without a results file (the Python module's `run` and
//! `run_batch`). The caller lends it to the runner (`&mut MemorySink`) and reads it afterwards.

use std::convert::Infallible;

use super::sink::{ResultSink, Tables};
use super::table::SummaryTable;

/// The summary of one group of runs.
#[derive(Clone, Debug, Default)]
pub struct MemorySink(Option<SummaryTable>);

impl MemorySink {
    /// The summary the runner handed the sink; `None` before it finished.
    pub fn into_summary(self) -> Option<SummaryTable> {
        self.0
    }
}

impl ResultSink for MemorySink {
    type Error = Infallible;

    fn finish(&mut self, tables: &Tables) -> Result<(), Infallible> {
        self.0 = Some(tables.summary.clone());
        Ok(())
    }
}
