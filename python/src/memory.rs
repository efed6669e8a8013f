//! The in-memory results of the module's `run` and `run_batch`: a result sink that keeps the
//! summary table the runner hands it at the end.

use std::convert::Infallible;
use std::sync::{Arc, Mutex};

use demsweep::output::{ResultSink, RunResult, SummaryTable, Tables};

/// The summary of one scene's runs, shared between the sink the runner drives and the caller.
#[derive(Clone, Default)]
pub struct InMemory(Arc<Mutex<Option<SummaryTable>>>);

impl InMemory {
    /// The summary the runner handed the sink; `None` before it finished.
    pub fn summary(&self) -> Option<SummaryTable> {
        self.0.lock().expect("the runner does not panic holding the summary").take()
    }
}

impl ResultSink for InMemory {
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
