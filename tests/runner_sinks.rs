//! Sinks the caller chooses: a sink handed to the runner beside the results file receives every run
//! the sweep makes and, at the end, the same tables as the file; a sink's own error stops the sweep
//! and comes back as it is.

mod runner_common;

use std::sync::{Arc, Mutex};

use demsweep::output::{ResultSink, RunResult, SummaryRow, SummaryTable, Tables, dyn_sink, reader};
use demsweep::runner::{RunOptions, RunnerError, run_plan_with};

/// What the test sink received.
#[derive(Default)]
struct Received {
    rows: Vec<SummaryRow>,
    commits: usize,
    tables: Option<Tables>,
}

/// A sink keeping in memory what it receives, shared with the test.
#[derive(Clone, Default)]
struct Collect(Arc<Mutex<Received>>);

impl ResultSink for Collect {
    type Error = std::convert::Infallible;

    fn accept(&mut self, run: &RunResult) -> Result<(), Self::Error> {
        self.0.lock().unwrap().rows.push(run.row.clone());
        Ok(())
    }

    fn commit(&mut self) -> Result<(), Self::Error> {
        self.0.lock().unwrap().commits += 1;
        Ok(())
    }

    fn finish(self: Box<Self>, tables: &Tables) -> Result<(), Self::Error> {
        self.0.lock().unwrap().tables = Some(tables.clone());
        Ok(())
    }
}

/// Tables compared as text: NaN (a missing value) equals NaN.
fn text(table: &SummaryTable) -> String {
    format!("{table:?}")
}

#[test]
fn a_chosen_sink_receives_every_run_and_the_tables_of_the_file() {
    let dir = runner_common::scratch("sinks_collect");
    let plan = runner_common::sweep("sinks", 5);
    let sink = Collect::default();
    let report = run_plan_with(&plan, &runner_common::options(&dir, 2), vec![dyn_sink(sink.clone())]).unwrap();
    let received = std::mem::take(&mut *sink.0.lock().unwrap());
    let mut ids: Vec<&str> = received.rows.iter().map(|r| r.id.as_str()).collect();
    ids.sort_unstable();
    assert_eq!(ids, ["r000", "r001", "r002", "r003", "r004"], "every run, once");
    assert!(received.commits >= 1, "committed at least at the end");
    let tables = received.tables.expect("finished");
    let file = reader::open(&report.results).unwrap();
    let stored = reader::summary(&file, &report.results).unwrap();
    assert_eq!(text(&tables.summary), text(&stored), "the summary of the file");
    assert_eq!(text(&SummaryTable::from_rows(&received.rows)), text(&stored), "the rows of the file");
    assert_eq!(text(&tables.points), text(&report.points));

    // Resuming a complete file makes no run: the sink receives none, and the tables of them all.
    let resume = RunOptions { resume: true, ..runner_common::options(&dir, 2) };
    let again = Collect::default();
    run_plan_with(&plan, &resume, vec![dyn_sink(again.clone())]).unwrap();
    let received = std::mem::take(&mut *again.0.lock().unwrap());
    assert!(received.rows.is_empty(), "no run made again");
    assert_eq!(text(&received.tables.expect("finished").summary), text(&stored));
}

/// The error of the failing sink.
#[derive(Debug)]
struct Full;

impl std::fmt::Display for Full {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "the test sink is full")
    }
}

impl std::error::Error for Full {}

impl From<Full> for demsweep::output::SinkError {
    fn from(error: Full) -> Self {
        Self::other(error)
    }
}

/// A sink that refuses every run.
struct Refuse;

impl ResultSink for Refuse {
    type Error = Full;

    fn accept(&mut self, _: &RunResult) -> Result<(), Full> {
        Err(Full)
    }

    fn commit(&mut self) -> Result<(), Full> {
        Ok(())
    }

    fn finish(self: Box<Self>, _: &Tables) -> Result<(), Full> {
        Ok(())
    }
}

#[test]
fn a_failing_sink_stops_the_sweep_with_its_own_error() {
    let dir = runner_common::scratch("sinks_refuse");
    let plan = runner_common::sweep("refuse", 3);
    match run_plan_with(&plan, &runner_common::options(&dir, 1), vec![dyn_sink(Refuse)]) {
        Err(RunnerError::Sink(error)) => {
            assert_eq!(error.to_string(), "the test sink is full");
            assert!(std::error::Error::source(&error).is_some_and(|e| e.is::<Full>()), "the sink's error kept");
        }
        other => panic!("{other:?}"),
    }
}
