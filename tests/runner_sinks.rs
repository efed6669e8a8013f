//! Sinks the caller chooses: a sink handed to the runner after the results file's receives every run
//! the sweep makes and, at the end, the same tables as the file; a sweep into sinks alone writes no
//! file; a sink's own error stops the sweep and comes back as it is.

mod runner_common;

use demsweep::output::{
    DynSink, MemorySink, ResultSink, RunResult, SummaryRow, SummaryTable, Tables, dyn_sink, reader,
};
use demsweep::runner::{self, RunOptions, RunReport, RunnerError, Start};
use demsweep::study::Plan;

/// A sink keeping in memory what it receives; the test lends it to the runner and reads it after.
#[derive(Default)]
struct Collect {
    rows: Vec<SummaryRow>,
    commits: usize,
    tables: Option<Tables>,
}

impl ResultSink for Collect {
    type Error = std::convert::Infallible;

    fn accept(&mut self, run: &RunResult) -> Result<(), Self::Error> {
        self.rows.push(run.row.clone());
        Ok(())
    }

    fn commit(&mut self) -> Result<(), Self::Error> {
        self.commits += 1;
        Ok(())
    }

    fn finish(&mut self, tables: &Tables) -> Result<(), Self::Error> {
        self.tables = Some(tables.clone());
        Ok(())
    }
}

impl Collect {
    /// The ids of the runs received, sorted.
    fn ids(&self) -> Vec<&str> {
        let mut ids: Vec<&str> = self.rows.iter().map(|r| r.id.as_str()).collect();
        ids.sort_unstable();
        ids
    }
}

/// Tables compared as text: NaN (a missing value) equals NaN.
fn text(table: &SummaryTable) -> String {
    format!("{table:?}")
}

/// Runs `plan` into its results file and then into `sink`.
fn run_into_file(plan: &Plan, options: &RunOptions, sink: DynSink<'_>) -> Result<RunReport, RunnerError> {
    let (start, writer) = runner::open_results(plan, options)?;
    let sinks = runner::results_sinks(writer).into_iter().chain([sink]).collect();
    runner::run_plan_into(plan, options, start, sinks)
}

#[test]
fn a_chosen_sink_receives_every_run_and_the_tables_of_the_file() {
    let dir = runner_common::scratch("sinks_collect");
    let plan = runner_common::sweep("sinks", 5);
    let mut sink = Collect::default();
    let report = run_into_file(&plan, &runner_common::options(&dir, 2), dyn_sink(&mut sink)).unwrap();
    assert_eq!(sink.ids(), ["r000", "r001", "r002", "r003", "r004"], "every run, once");
    assert!(sink.commits >= 1, "committed at least at the end");
    let tables = sink.tables.expect("finished");
    let file = reader::open(&report.results).unwrap();
    let stored = reader::summary(&file, &report.results).unwrap();
    assert_eq!(text(&tables.summary), text(&stored), "the summary of the file");
    assert_eq!(text(&SummaryTable::from_rows(&sink.rows)), text(&stored), "the rows of the file");
    assert_eq!(text(&tables.points), text(&report.points));

    // Resuming a complete file makes no run: the sink receives none, and the tables of them all.
    let resume = RunOptions { resume: true, ..runner_common::options(&dir, 2) };
    let mut again = Collect::default();
    run_into_file(&plan, &resume, dyn_sink(&mut again)).unwrap();
    assert!(again.rows.is_empty(), "no run made again");
    assert_eq!(text(&again.tables.expect("finished").summary), text(&stored));
}

#[test]
fn on_resume_a_sink_receives_the_runs_made_now_and_the_tables_of_every_run() {
    let dir = runner_common::scratch("sinks_resume");
    runner::run_plan(&runner_common::sweep("grown", 3), &runner_common::options(&dir, 2)).unwrap();
    let grown = runner_common::sweep("grown", 5);
    let resume = RunOptions { resume: true, ..runner_common::options(&dir, 2) };
    let mut sink = Collect::default();
    let report = run_into_file(&grown, &resume, dyn_sink(&mut sink)).unwrap();
    assert_eq!((report.already_done, report.ran), (3, 2));
    assert_eq!(sink.ids(), ["r003", "r004"], "only the runs made this time");
    let tables = sink.tables.expect("finished");
    assert_eq!(tables.summary.len(), 5, "the tables of every run, the stored ones included");
    let stored = reader::summary(&reader::open(&report.results).unwrap(), &report.results).unwrap();
    assert_eq!(text(&tables.summary), text(&stored));
}

#[test]
fn a_study_runs_into_memory_alone_and_writes_no_file() {
    let dir = runner_common::scratch("sinks_memory");
    let plan = runner_common::sweep("memory", 4);
    let options = runner_common::options(&dir.join("out"), 2);
    let mut memory = MemorySink::default();
    let report =
        runner::run_plan_into(&plan, &options, Start::fresh(&plan, &options), vec![dyn_sink(&mut memory)]).unwrap();
    assert_eq!((report.selected, report.ran, report.failed()), (4, 4, 0));
    assert!(!dir.join("out").exists(), "no results file, CSV table or folder written");
    let in_memory = memory.into_summary().expect("finished");
    let filed = runner::run_plan(&plan, &runner_common::options(&dir.join("file"), 1)).unwrap();
    assert_eq!(text(&in_memory.without_timing()), text(&filed.summary.without_timing()), "the runs of a file");
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
}

#[test]
fn a_failing_sink_stops_the_sweep_with_its_own_error() {
    let dir = runner_common::scratch("sinks_refuse");
    let plan = runner_common::sweep("refuse", 3);
    match run_into_file(&plan, &runner_common::options(&dir, 1), dyn_sink(Refuse)) {
        Err(RunnerError::Sink(error)) => {
            assert_eq!(error.to_string(), "the test sink is full");
            assert!(std::error::Error::source(&error).is_some_and(|e| e.is::<Full>()), "the sink's error kept");
        }
        other => panic!("{other:?}"),
    }
}
