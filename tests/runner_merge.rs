//! Shards run separately and merged give what one machine gives; bad shard sets are refused.

mod runner_common;

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

use demsweep::output::{ShardSpec, history, merge, summary};
use demsweep::runner::run_plan;
use demsweep::study::Plan;

fn run_shard(plan: &Plan, dir: &Path, k: usize, n: usize) -> PathBuf {
    let mut options = runner_common::options(dir, 1);
    options.shard = Some(ShardSpec { index: k, count: n });
    let report = run_plan(plan, &options).expect("shard run");
    assert_eq!(report.exit_code(), 0);
    report.results
}

fn history_text(path: &Path, id: &str) -> String {
    let mut out = Vec::new();
    history::to_csv(path, id, &mut out).unwrap();
    String::from_utf8(out).unwrap()
}

/// The CSV text without its wall_time column.
fn csv_without_timing(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let wall = header.iter().position(|c| *c == "wall_time").unwrap();
    text.lines().map(|l| l.split(',').enumerate().filter(|(i, _)| *i != wall).map(|(_, f)| f).collect()).collect()
}

#[test]
fn merged_shards_equal_a_single_machine_run() {
    let plan = runner_common::sweep("merge", 7);
    let shards_dir = runner_common::scratch("merge_shards");
    let shard_files: Vec<PathBuf> = (1..=3).map(|k| run_shard(&plan, &shards_dir, k, 3)).collect();
    assert!(shard_files[1].ends_with("merge.shard-2-of-3.h5"));
    let sizes: Vec<usize> = shard_files.iter().map(|f| summary::read(f).unwrap().len()).collect();
    assert_eq!(sizes.iter().sum::<usize>(), 7);

    let merged = merge(&runner_common::scratch("merge_out"), std::slice::from_ref(&shards_dir), false).expect("merge");
    assert_eq!((merged.runs, merged.shards), (7, 3));
    let single = run_plan(&plan, &runner_common::options(&runner_common::scratch("merge_single"), 2)).unwrap();

    assert_eq!(summary::read(&merged.results).unwrap().without_timing(), single.summary.without_timing());
    assert_eq!(csv_without_timing(&merged.summary_csv), csv_without_timing(&single.summary_csv));
    for run in &plan.runs {
        assert_eq!(history_text(&merged.results, &run.id), history_text(&single.results, &run.id), "{}", run.id);
    }
    let file = hdf5_pure::File::open(&merged.results).unwrap();
    let attrs = file.root().attrs().unwrap();
    assert!(!attrs.contains_key("shard"), "a merged file is not a shard");
    assert_eq!(attrs["fingerprint"].as_str(), Some(plan.fingerprint.as_str()));
    assert_eq!(file.group("runs/b0000/r004/frames").unwrap().datasets().unwrap().len(), 2, "frames were copied");
}

fn merge_error(inputs: &[PathBuf]) -> String {
    match merge(&runner_common::scratch("merge_refused_out"), inputs, false) {
        Err(e) => e.to_string(),
        Ok(report) => panic!("merge should have been refused, made {report:?}"),
    }
}

#[test]
fn merge_refuses_other_studies_overlaps_and_missing_runs() {
    let plan = runner_common::sweep("merge_checks", 5);
    let dir = runner_common::scratch("merge_checks");
    let one = run_shard(&plan, &dir, 1, 2);
    let two = run_shard(&plan, &dir, 2, 2);

    let mut other = plan.clone();
    other.fingerprint = "fingerprint-of-another-study".into();
    let other_dir = runner_common::scratch("merge_checks_other");
    let foreign = run_shard(&other, &other_dir, 2, 2);
    let e = merge_error(&[one.clone(), foreign.clone()]);
    assert!(e.contains("different studies") && e.contains("fingerprint-of-another-study"), "{e}");
    assert!(e.contains(&one.display().to_string()) && e.contains(&foreign.display().to_string()), "{e}");

    let copy = dir.join("copy.shard-1-of-2.h5");
    std::fs::copy(&one, &copy).unwrap();
    let e = merge_error(&[one.clone(), two.clone(), copy.clone()]);
    assert!(e.contains("overlaps") && e.contains("copy.shard-1-of-2.h5"), "{e}");

    let e = merge_error(std::slice::from_ref(&one));
    assert!(e.contains("shard 2/2: no file given") && e.contains("--shard K/N --resume"), "{e}");

    // A shard whose sweep was stopped before any run finished.
    let stopped_dir = runner_common::scratch("merge_checks_stopped");
    let mut options = runner_common::options(&stopped_dir, 1);
    options.shard = Some(ShardSpec { index: 2, count: 2 });
    options.stop.store(true, Ordering::SeqCst);
    let empty = run_plan(&plan, &options).unwrap().results;
    let e = merge_error(&[one, empty]);
    assert!(e.contains("shard 2/2") && e.contains("runs missing"), "{e}");
}
