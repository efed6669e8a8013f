//! Existing results are never overwritten by accident; bad output paths fail before any run.

mod runner_common;

use demsweep::output::OutputReason;
use demsweep::runner::{RunnerError, run_plan};

fn refusal(result: Result<demsweep::runner::RunReport, RunnerError>) -> demsweep::output::OutputError {
    match result {
        Err(RunnerError::Output(e)) => e,
        other => panic!("expected an output error, got {other:?}"),
    }
}

#[test]
fn existing_results_need_resume_or_force() {
    let plan = runner_common::sweep("existing", 2);
    let dir = runner_common::scratch("existing");
    let first = run_plan(&plan, &runner_common::options(&dir, 2)).unwrap();
    let before = std::fs::read(&first.results).unwrap();

    let e = refusal(run_plan(&plan, &runner_common::options(&dir, 2)));
    assert_eq!(e.path, first.results);
    assert_eq!(*e.reason, OutputReason::Exists { resumable: true });
    assert!(e.to_string().contains("--resume") && e.to_string().contains("--force"), "{e}");
    assert_eq!(std::fs::read(&first.results).unwrap(), before, "the refused run left the file alone");

    let mut resume = runner_common::options(&dir, 2);
    resume.resume = true;
    let resumed = run_plan(&plan, &resume).unwrap();
    assert_eq!((resumed.already_done, resumed.ran, resumed.exit_code()), (2, 0, 0));

    let mut force = runner_common::options(&dir, 2);
    force.force = true;
    let forced = run_plan(&plan, &force).unwrap();
    assert_eq!((forced.already_done, forced.ran), (0, 2));
    assert_eq!(forced.summary.without_timing(), first.summary.without_timing());
}

#[test]
fn an_unwritable_output_path_fails_before_running() {
    let dir = runner_common::scratch("unwritable");
    let blocker = dir.join("a_file");
    std::fs::write(&blocker, "not a directory").unwrap();
    let out = blocker.join("results");
    let e = refusal(run_plan(&runner_common::sweep("unwritable", 1), &runner_common::options(&out, 1)));
    assert_eq!(e.path, out);
    match &*e.reason {
        OutputReason::Io { doing: Some(doing), .. } => assert_eq!(*doing, "cannot create the output directory"),
        other => panic!("{other:?}"),
    }
    assert!(e.to_string().contains("cannot create the output directory"), "{e}");
}
