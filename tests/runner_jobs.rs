//! Results do not depend on the number of worker threads.

mod runner_common;

use demsweep::output::{history, summary};
use demsweep::runner::run_plan;

#[test]
fn one_and_two_jobs_give_identical_summaries_and_histories() {
    let plan = runner_common::sweep("jobs", 6);
    let one = run_plan(&plan, &runner_common::options(&runner_common::scratch("jobs_1"), 1)).expect("jobs 1");
    let two = run_plan(&plan, &runner_common::options(&runner_common::scratch("jobs_2"), 2)).expect("jobs 2");
    assert_eq!(one.exit_code(), 0);
    assert_eq!(one.ran, 6);
    assert_eq!(one.summary.len(), 6);
    assert_eq!(one.summary.without_timing(), two.summary.without_timing());
    for report in [&one, &two] {
        assert!(report.writer_time > std::time::Duration::ZERO, "the writer's time is measured");
        assert!(report.writer_time < report.wall_time, "{:?} of {:?}", report.writer_time, report.wall_time);
    }
    assert_eq!(summary::read(&one.results).unwrap(), one.summary, "the file's /summary is what the run reported");
    for id in ["r000", "r003", "r005"] {
        let (mut a, mut b) = (Vec::new(), Vec::new());
        history::to_csv(&one.results, id, &mut a).unwrap();
        history::to_csv(&two.results, id, &mut b).unwrap();
        let text = String::from_utf8(a.clone()).unwrap();
        assert!(text.lines().count() > 10, "{id} has a history: {text}");
        assert_eq!(a, b, "history of {id}");
    }
}
