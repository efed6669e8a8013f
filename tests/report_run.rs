//! The page a run writes is built from the tables the sweep computed; `demsweep report` builds the
//! page of the same results file from its runs: the two are the same page but for when each was
//! written.

mod runner_common;

use demsweep::output::guard::Existing;
use demsweep::report::{self, ReportContext};
use demsweep::runner::RunOptions;
use demsweep::study::Plan;
use demsweep::workflow;

/// The page without the time it was written (the one fact that differs between two writings).
fn untimed(page: &str) -> String {
    let fact = "<dt>report written</dt><dd>";
    let start = page.find(fact).expect("the time the page was written") + fact.len();
    let end = start + page[start..].find("</dd>").expect("its end");
    format!("{}{}", &page[..start], &page[end..])
}

/// Runs `plan` as `demsweep run` does into `options`' folder; the page it wrote and the page
/// `demsweep report` makes of its results file.
fn pages(plan: &Plan, options: &RunOptions) -> (String, String) {
    let run = workflow::run_study(plan, options, Vec::new()).unwrap();
    let (written, damaged, not_drawn) = run.page.expect("the run's page");
    assert!(damaged.is_empty() && not_drawn.is_empty(), "{damaged:?} {not_drawn:?}");
    assert_eq!(written, report::report_path(&run.report.results));
    let again = run.report.results.with_file_name("again.html");
    report::write_report(&run.report.results, (Some(&again), Existing::Any), &ReportContext::default()).unwrap();
    (std::fs::read_to_string(&written).unwrap(), std::fs::read_to_string(&again).unwrap())
}

#[test]
fn the_page_a_run_writes_is_the_report_of_its_results_file() {
    let dir = runner_common::scratch("report_run");
    let (page, reported) = pages(&runner_common::sweep("paged", 8), &runner_common::options(&dir, 2));
    assert!(page.contains("id=\"points-data\"") && page.contains("id=\"answer\""), "a page with its answer and points");
    assert_eq!(untimed(&page), untimed(&reported));
}

#[test]
fn a_resumed_file_holding_runs_the_study_no_longer_plans_has_the_page_of_all_its_runs() {
    let dir = runner_common::scratch("report_unplanned");
    workflow::run_study(&runner_common::sweep("shrunk", 5), &runner_common::options(&dir, 2), Vec::new()).unwrap();
    let resume = RunOptions { resume: true, ..runner_common::options(&dir, 2) };
    let (page, reported) = pages(&runner_common::sweep("shrunk", 3), &resume);
    assert!(page.contains("r004"), "the stored run the study no longer plans is on the page");
    assert_eq!(untimed(&page), untimed(&reported));
}
