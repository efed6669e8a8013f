//! Results kept in memory: a result sink that keeps the summary table the runner hands it at the end,
//! for callers that want a sweep's table without a results file (the Python module's `run` and
//! `run_batch`).

use std::convert::Infallible;
use std::sync::{Arc, Mutex};

use super::sink::{ResultSink, RunResult, Tables};
use super::table::SummaryTable;

/// The summary of one group of runs, shared between the sink the runner drives and the caller (a
/// clone is the same summary).
#[derive(Clone, Default)]
pub struct MemorySink(Arc<Mutex<Option<SummaryTable>>>);

impl MemorySink {
    /// The summary the runner handed the sink; `None` before it finished (or once taken).
    pub fn summary(&self) -> Option<SummaryTable> {
        self.0.lock().expect("the runner does not panic holding the summary").take()
    }
}

impl ResultSink for MemorySink {
    type Error = Infallible;

    fn accept(&mut self, _: &RunResult) -> Result<(), Infallible> {
        Ok(())
    }

    fn commit(&mut self) -> Result<(), Infallible> {
        Ok(())
    }

    fn finish(self: Box<Self>, tables: &Tables) -> Result<(), Infallible> {
        *self.0.lock().expect("the caller does not panic holding the summary") = Some(tables.summary.clone());
        Ok(())
    }
}
