//! Stopping a sweep keeps finished runs; `--resume` runs only the missing ones and ends with the
//! summary an uninterrupted sweep gives.

mod runner_common;

use std::sync::atomic::Ordering;
use std::time::Duration;

use demsweep::output::{csv_path, points_csv_path, summary};
use demsweep::runner::{CommitPolicy, run_plan};

/// Runs long enough (tens of milliseconds each) for the sweep to be stopped midway.
fn longer_sweep(name: &str) -> demsweep::study::Plan {
    let mut plan = runner_common::sweep(name, RUNS);
    for run in &mut plan.runs {
        run.scene.run.duration = 0.2;
        run.scene.particles.count = 30;
    }
    plan
}

const RUNS: usize = 12;

#[test]
fn a_stopped_sweep_resumes_to_the_uninterrupted_result() {
    let plan = longer_sweep("resume");
    let dir = runner_common::scratch("resume");
    let mut first = runner_common::options(&dir, 1);
    first.commit = CommitPolicy { max_runs: 1, interval: Duration::ZERO };
    let results = dir.join("resume.h5");
    // Stop the sweep (as Ctrl-C does) as soon as the file holds two committed runs.
    let stop = first.stop.clone();
    let watcher = std::thread::spawn(move || {
        while !stop.load(Ordering::SeqCst) {
            if summary::read(&results).is_ok_and(|t| t.len() >= 2) {
                stop.store(true, Ordering::SeqCst);
            }
            std::thread::sleep(Duration::from_millis(1));
        }
    });
    let stopped = run_plan(&plan, &first).expect("interrupted sweep");
    first.stop.store(true, Ordering::SeqCst);
    watcher.join().unwrap();
    assert!(stopped.interrupted);
    assert_eq!(stopped.exit_code(), 130);
    let kept = stopped.summary.len();
    assert!((2..RUNS).contains(&kept), "kept {kept} runs");
    assert_eq!(summary::read(&stopped.results).unwrap(), stopped.summary, "the stopped file is complete and valid");

    let mut again = runner_common::options(&dir, 2);
    again.resume = true;
    let resumed = run_plan(&plan, &again).expect("resumed sweep");
    assert_eq!(resumed.already_done, kept);
    assert_eq!(resumed.ran, RUNS - kept);
    assert_eq!(resumed.exit_code(), 0);

    let reference = run_plan(&plan, &runner_common::options(&runner_common::scratch("resume_reference"), 2)).unwrap();
    assert_eq!(resumed.summary.without_timing(), reference.summary.without_timing());
}

#[test]
fn a_sweep_stopped_before_it_starts_records_nothing_and_stays_valid() {
    let plan = runner_common::sweep("stopped_early", 3);
    let dir = runner_common::scratch("stopped_early");
    let options = runner_common::options(&dir, 2);
    options.stop.store(true, Ordering::SeqCst);
    let report = run_plan(&plan, &options).unwrap();
    assert_eq!((report.ran, report.summary.len(), report.exit_code()), (0, 0, 130));
    assert_eq!(summary::read(&report.results).unwrap().len(), 0);
    let csv = std::fs::read_to_string(&report.summary_csv).unwrap();
    assert_eq!(csv.lines().count(), 1, "the names line only: {csv}");
}

#[test]
fn resume_runs_again_the_runs_that_failed_with_an_error() {
    let mut plan = runner_common::sweep("resume_failed", 4);
    let good_scene = plan.runs[2].scene.clone();
    plan.runs[2].scene.integrator.time_step = Some(-1.0); // fails when the run starts (no study check in between)
    let dir = runner_common::scratch("resume_failed");
    let first = run_plan(&plan, &runner_common::options(&dir, 2)).unwrap();
    assert_eq!((first.failed(), first.exit_code()), (1, demsweep::runner::EXIT_PARTIAL));

    plan.runs[2].scene = good_scene;
    let mut again = runner_common::options(&dir, 2);
    again.resume = true;
    let resumed = run_plan(&plan, &again).unwrap();
    assert_eq!((resumed.already_done, resumed.ran, resumed.failed(), resumed.exit_code()), (3, 1, 0, 0));
    let reference = run_plan(&plan, &runner_common::options(&runner_common::scratch("resume_failed_ref"), 2)).unwrap();
    assert_eq!(summary::read(&resumed.results).unwrap().without_timing(), reference.summary.without_timing());
}

/// The CSV metadata sidecar of `table`.
fn metadata_path(table: &std::path::Path) -> std::path::PathBuf {
    table.with_file_name(format!("{}-metadata.json", table.file_name().unwrap().to_string_lossy()))
}

#[test]
fn a_resume_takes_its_own_tables_left_without_their_sidecars() {
    let plan = runner_common::sweep("own_tables", 4);
    let dir = runner_common::scratch("own_tables");
    let done = run_plan(&plan, &runner_common::options(&dir, 2)).unwrap();
    let tables = [csv_path(&done.results), points_csv_path(&done.results)];
    // A command killed between a table and its sidecar, a full disk, a sidecar deleted.
    tables.iter().for_each(|table| std::fs::remove_file(metadata_path(table)).unwrap());
    let mut again = runner_common::options(&dir, 2);
    again.resume = true;
    let resumed = run_plan(&plan, &again).expect("its own tables are recognised");
    assert_eq!((resumed.already_done, resumed.ran), (4, 0));
    assert!(tables.iter().all(|table| metadata_path(table).is_file()), "the sidecars are written again");

    // A user's table there is kept, and the refusal advises no flag that would run the stored runs again.
    let mine = "sample,comment\r\nA1,looks fine\r\n";
    std::fs::remove_file(metadata_path(&tables[0])).unwrap();
    std::fs::write(&tables[0], mine).unwrap();
    let refused = run_plan(&plan, &again).unwrap_err().to_string();
    assert!(refused.contains("own_tables_summary.csv: refused"), "{refused}");
    assert!(refused.contains("move it elsewhere, then resume again") && !refused.contains("--force"), "{refused}");
    assert_eq!(std::fs::read_to_string(&tables[0]).unwrap(), mine);
}
