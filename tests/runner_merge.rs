//! Shards run separately and merged give what one machine gives; bad shard sets are refused.

mod runner_common;

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

use demsweep::output::{ShardSpec, history, summary};
use demsweep::runner::{merge, results_path, run_plan};
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

/// The CSV text without its wall_time and cpu_time columns.
fn csv_without_timing(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let timing: Vec<usize> =
        ["wall_time", "cpu_time"].iter().map(|name| header.iter().position(|c| c == name).unwrap()).collect();
    text.lines()
        .map(|l| l.split(',').enumerate().filter(|(i, _)| !timing.contains(i)).map(|(_, f)| f).collect())
        .collect()
}

#[test]
fn merged_shards_equal_a_single_machine_run() {
    let plan = runner_common::sweep("merge", 7);
    let shards_dir = runner_common::scratch("merge_shards");
    let shard_files: Vec<PathBuf> = (1..=3).map(|k| run_shard(&plan, &shards_dir, k, 3)).collect();
    assert!(shard_files[1].ends_with("merge.shard-2-of-3.h5"));
    let sizes: Vec<usize> = shard_files.iter().map(|f| summary::read(f).unwrap().len()).collect();
    assert_eq!(sizes.iter().sum::<usize>(), 7);

    let merged = merge(&runner_common::scratch("merge_out"), std::slice::from_ref(&shards_dir), &Default::default())
        .expect("merge");
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
    let frames = |results: &std::path::Path| {
        let file = demsweep::output::reader::open(results).unwrap();
        let rows = demsweep::output::reader::rows(&file, results).unwrap();
        let row = rows.iter().find(|r| r.id == "r004").unwrap();
        let frames = demsweep::output::stored::read_run(&file, results, row).unwrap().frames;
        frames.iter().map(|f| (f.time, f.x.clone(), f.contacts.normal_force.clone())).collect::<Vec<_>>()
    };
    assert_eq!(frames(&merged.results).len(), 2);
    assert_eq!(frames(&merged.results), frames(&single.results), "frames were copied");
}

fn merge_error(inputs: &[PathBuf]) -> String {
    match merge(&runner_common::scratch("merge_refused_out"), inputs, &Default::default()) {
        Err(e) => e.to_string(),
        Ok(report) => panic!("merge should have been refused, made {report:?}"),
    }
}

#[test]
fn merge_refuses_other_studies_and_overlaps() {
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
    let e = merge_error(&[one, two, copy.clone()]);
    assert!(e.contains("overlaps") && e.contains("copy.shard-1-of-2.h5"), "{e}");
}

#[test]
fn merge_merges_what_there_is_and_names_the_shards_to_run_again() {
    let mut plan = runner_common::sweep("merge_partial", 6);
    let failing = demsweep::runner::shard::select(&plan, ShardSpec { index: 1, count: 3 })[0];
    plan.runs[failing].scene.integrator.time_step = Some(-1.0); // fails when the run starts (no study check in between)
    let dir = runner_common::scratch("merge_partial");
    let mut options = runner_common::options(&dir, 1);
    options.shard = Some(ShardSpec { index: 1, count: 3 });
    let one = run_plan(&plan, &options).unwrap();
    assert_eq!(one.exit_code(), demsweep::runner::EXIT_PARTIAL, "shard 1 holds the failing run");
    let failed_id = &plan.runs[failing].id;
    assert!(one.summary.len() == 2 && summary::read(&one.results).is_ok());
    // Shard 2 stopped before any run finished; shard 3 never ran.
    let mut stopped = runner_common::options(&dir, 1);
    stopped.shard = Some(ShardSpec { index: 2, count: 3 });
    stopped.stop.store(true, Ordering::SeqCst);
    run_plan(&plan, &stopped).unwrap();

    let out = runner_common::scratch("merge_partial_out");
    let report = merge(&out, std::slice::from_ref(&dir), &Default::default()).expect("a partial merge");
    assert_eq!((report.runs, report.shards, report.planned_runs, report.shard_count), (2, 2, 6, 3));
    assert_eq!(report.shards_to_rerun(), [1, 2, 3]);
    let reasons: Vec<&str> = report.problems.iter().map(|p| p.reason.as_str()).collect();
    assert!(
        reasons[0].starts_with("shard 1/3 (")
            && reasons[0].contains(&format!("run {failed_id} failed with an error: ")),
        "{reasons:?}"
    );
    assert!(reasons[1].starts_with("shard 2/3 (") && reasons[1].contains("2 of 2 runs missing"), "{reasons:?}");
    assert_eq!(reasons[2], "shard 3/3: no file given");
    assert_eq!(summary::read(&report.results).unwrap().len(), 2, "what there is was merged");

    let cli = std::process::Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args([
            "merge",
            out.to_str().unwrap(),
            dir.to_str().unwrap(),
            "--force",
            "--array-script",
            "/x/slurm/array.sbatch",
        ])
        .output()
        .unwrap();
    assert_eq!(cli.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&cli.stdout).starts_with("merged 2 of 6 runs from 2 of 3 shards\n"));
    let stderr = String::from_utf8_lossy(&cli.stderr);
    assert!(stderr.starts_with("error: the merge is incomplete:\n  shard 1/3 ("), "{stderr}");
    assert!(
        stderr.ends_with(
            "run them again, then merge again:\n  ARRAY=$(sbatch --parsable --array=1,2,3 /x/slurm/array.sbatch)\n  \
             sbatch --dependency=afterany:$ARRAY /x/slurm/merge.sbatch\n"
        ),
        "{stderr}"
    );
}

#[test]
fn shard_file_names_are_zero_padded_and_an_unpadded_one_is_continued() {
    let plan = runner_common::sweep("padded", 12);
    let dir = runner_common::scratch("padded_shards");
    let mut options = runner_common::options(&dir, 1);
    options.shard = Some(ShardSpec { index: 3, count: 12 });
    assert!(results_path(&plan, &options).ends_with("padded.shard-03-of-12.h5"), "lists in shard order");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("padded.shard-3-of-12.h5"), b"").unwrap();
    assert!(results_path(&plan, &options).ends_with("padded.shard-3-of-12.h5"), "a file named before padding");
    options.shard = Some(ShardSpec { index: 3, count: 4 });
    assert!(results_path(&plan, &options).ends_with("padded.shard-3-of-4.h5"));
}

#[test]
fn merged_tables_have_their_sidecars_and_leave_no_temporary_files() {
    let plan = runner_common::sweep("merge_sidecars", 4);
    let shards_dir = runner_common::scratch("merge_sidecars_shards");
    (1..=2).for_each(|k| drop(run_shard(&plan, &shards_dir, k, 2)));
    let out = runner_common::scratch("merge_sidecars_out");
    let merged = merge(&out, std::slice::from_ref(&shards_dir), &Default::default()).expect("merge");
    for table in [&merged.summary_csv, &merged.points_csv] {
        let sidecar = table.with_file_name(format!("{}-metadata.json", table.file_name().unwrap().to_string_lossy()));
        let meta: serde_json::Value = serde_json::from_slice(&std::fs::read(&sidecar).unwrap()).unwrap();
        assert_eq!(meta["url"].as_str(), table.file_name().unwrap().to_str(), "{}", sidecar.display());
        assert!(demsweep::output::guard::made_by_demsweep(table), "{}", table.display());
    }
    let names: Vec<String> =
        std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert!(names.iter().all(|name| !name.contains("merging")), "{names:?}");
}
