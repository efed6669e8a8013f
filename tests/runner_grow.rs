//! Sweeps that grow: a study edited after it ran continues in the same results file (stored runs
//! matched by identity, only new ones run), and equals a fresh run of the edited study; a changed
//! input file reruns what depends on it; files of different studies merge run by run.

mod runner_common;

use std::path::{Path, PathBuf};

use demsweep::output::{history, summary};
use demsweep::runner::{RunNote, RunReport, merge, run_plan};
use demsweep::study::IdentityChange;

/// A study of tiny runs: friction values, `replicates` seeds, an optional extra axis and text.
fn study(frictions: &str, replicates: usize, extra: &str) -> String {
    format!(
        r#"name = "grow"
[scene]
particles.count = 6
domain.width = 0.08
domain.height = 0.1
run.duration = 0.01
run.sample_interval = 0.002
run.frame_times = [0.0, 0.005]
placement.seed = 7

[sweep]
"material.friction" = [{frictions}]
replicates = {replicates}
{extra}
"#
    )
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn run(study: &Path, out: &Path, resume: bool) -> RunReport {
    let plan = demsweep::study::load(study).unwrap_or_else(|e| panic!("{e}"));
    let mut options = runner_common::options(out, 2);
    options.resume = resume;
    let report = run_plan(&plan, &options).unwrap();
    assert_eq!(report.exit_code(), 0);
    report
}

fn history_text(path: &Path, id: &str) -> String {
    let mut out = Vec::new();
    history::to_csv(path, id, &mut out).unwrap();
    String::from_utf8(out).unwrap()
}

/// The grown file equals a fresh run of the edited study: summary (wall times aside), points,
/// and every run's history, found by its id.
fn assert_same_results(grown: &RunReport, fresh: &RunReport) {
    let grown_summary = summary::read(&grown.results).unwrap();
    assert_eq!(grown_summary.without_timing(), fresh.summary.without_timing());
    assert_eq!(grown.points.without_timing(), fresh.points.without_timing());
    let ids = grown_summary.column("run_id").unwrap();
    for i in 0..grown_summary.len() {
        let id = ids.data.text(i);
        assert_eq!(history_text(&grown.results, &id), history_text(&fresh.results, &id), "{id}");
    }
}

#[test]
fn an_edited_study_continues_in_its_file_and_equals_a_fresh_run() {
    let dir = runner_common::scratch("grow_edits");
    let out = dir.join("out");
    let first = run(&write(&dir, "a.toml", &study("0.2, 0.6", 2, "")), &out, false);
    assert_eq!((first.ran, first.summary.len()), (4, 4));

    // A third friction value in the middle, a third replicate, a comment: 9 runs, 5 new.
    let edited = format!("# the morning after\n{}", study("0.2, 0.4, 0.6", 3, ""));
    let grown = run(&write(&dir, "b.toml", &edited), &out, true);
    assert_eq!((grown.already_done, grown.ran, grown.summary.len()), (4, 5, 9));
    let fresh = run(&write(&dir, "b.toml", &edited), &dir.join("fresh_b"), false);
    assert_same_results(&grown, &fresh);

    // A new axis with one value equal to the base scene's: every stored run is still planned.
    let axis = study("0.2, 0.4, 0.6", 3, "\"material.rolling_friction\" = [0.0, 0.1]");
    let with_axis = run(&write(&dir, "c.toml", &axis), &out, true);
    assert_eq!((with_axis.already_done, with_axis.ran, with_axis.summary.len()), (9, 9, 18));
    let fresh = run(&write(&dir, "c.toml", &axis), &dir.join("fresh_c"), false);
    assert_same_results(&with_axis, &fresh);

    // Values removed: their runs stay in the file, out of the summary, until dropped.
    let shrunk = study("0.4", 1, "");
    let small = run(&write(&dir, "d.toml", &shrunk), &out, true);
    assert_eq!((small.already_done, small.ran, small.summary.len()), (1, 0, 1));
    assert_eq!(summary::read(&small.results).unwrap().len(), 1, "/summary holds the planned runs");
    let groups = |path: &Path| {
        let file = hdf5_pure::File::open(path).unwrap();
        demsweep::output::reader::committed_runs(&file, path).unwrap().rows.len()
    };
    assert_eq!(groups(&small.results), 18, "runs no longer planned stay in the file");
    let fresh = run(&write(&dir, "d.toml", &shrunk), &dir.join("fresh_d"), false);
    assert_same_results(&small, &fresh);
    let mut drop = runner_common::options(&out, 1);
    (drop.resume, drop.drop_unplanned) = (true, true);
    run_plan(&demsweep::study::load(&dir.join("d.toml")).unwrap(), &drop).unwrap();
    assert_eq!(groups(&small.results), 1, "--drop-unplanned deletes them");
}

#[test]
fn an_output_only_change_reruns_only_runs_lacking_the_output() {
    let dir = runner_common::scratch("grow_outputs");
    let out = dir.join("out");
    let without = format!("{}\n[output]\nframes = false\n", study("0.2, 0.6", 1, ""));
    run(&write(&dir, "a.toml", &without), &out, false);
    let same = run(&write(&dir, "a.toml", &without), &out, true);
    assert_eq!(same.ran, 0, "nothing new asked");
    let with_frames = run(&write(&dir, "b.toml", &study("0.2, 0.6", 1, "")), &out, true);
    assert_eq!((with_frames.already_done, with_frames.ran), (0, 2), "both runs lacked frames");
    let fewer = format!("{}\n[output]\nhistories = false\n", study("0.2, 0.6", 1, ""));
    assert_eq!(run(&write(&dir, "c.toml", &fewer), &out, true).ran, 0, "asking less reruns nothing");
}

#[test]
fn a_changed_input_file_reruns_the_runs_that_read_it() {
    let dir = runner_common::scratch("grow_inputs");
    let out = dir.join("out");
    let placement = |y: f64| format!("x,y,r\n0.02,{y},0.005\n0.05,0.03,0.005\n");
    write(&dir, "pile.csv", &placement(0.03));
    let text = format!(
        "{}\n",
        study("0.2, 0.6", 1, "")
            .replace("placement.seed = 7", "placement.kind = \"file\"\nplacement.file = \"pile.csv\"")
    );
    let text = text.replace("particles.count = 6\n", "particles.count = 2\n");
    let study_path = write(&dir, "s.toml", &text);
    run(&study_path, &out, false);
    assert_eq!(run(&study_path, &out, true).ran, 0, "same inputs: nothing to run");
    write(&dir, "pile.csv", &placement(0.06));
    let changed = run(&study_path, &out, true);
    assert_eq!((changed.already_done, changed.ran), (0, 2), "both runs read the edited file");
    let rerun = RunNote::IdentityChanged { runs: 2, changed: vec![IdentityChange::InputFiles] };
    let kept = RunNote::Unplanned { ids: vec!["r0000".into(), "r0001".into()], deleted: false };
    assert_eq!(changed.notes, [rerun, kept], "the resume says why both run again, and what it keeps");
    let fresh = run(&study_path, &dir.join("fresh"), false);
    assert_same_results(&changed, &fresh);
    // The command says so whatever the progress display: a quiet resume reruns nothing unsaid.
    write(&dir, "pile.csv", &placement(0.07));
    let (s, o) = (study_path.to_str().unwrap(), out.to_str().unwrap());
    let quiet = std::process::Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(["run", s, "--out", o, "--resume", "--progress", "quiet", "--jobs", "1"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&quiet.stderr);
    assert_eq!(quiet.status.code(), Some(0), "{stderr}");
    let expected = format!("note: {}: 2 run(s) of this study match stored runs", changed.results.display());
    assert!(stderr.contains(&expected) && stderr.contains("(input files"), "{stderr}");
}

#[test]
fn files_of_different_studies_merge_run_by_run() {
    let dir = runner_common::scratch("grow_merge");
    let a = run(&write(&dir, "a.toml", &study("0.2, 0.4", 1, "")), &dir.join("a"), false);
    let b = run(&write(&dir, "b.toml", &format!("# another\n{}", study("0.4, 0.6", 1, ""))), &dir.join("b"), false);
    let merged =
        merge(&dir.join("merged"), &[a.results.clone(), b.results.clone()], &Default::default()).expect("merge");
    assert_eq!(merged.runs, 3, "the run both studies hold is kept once");
    let table = summary::read(&merged.results).unwrap();
    let identities = table.column("identity").unwrap();
    let ids = table.column("run_id").unwrap();
    assert_eq!((0..3).map(|i| ids.data.text(i)).collect::<Vec<_>>(), ["r0000", "r0001", "r0002"]);
    let fresh = run(&write(&dir, "c.toml", &study("0.2, 0.4, 0.6", 1, "")), &dir.join("c"), false);
    let fresh_identities = fresh.summary.column("identity").unwrap();
    for i in 0..3 {
        assert_eq!(identities.data.text(i), fresh_identities.data.text(i));
        let id = ids.data.text(i);
        assert_eq!(history_text(&merged.results, &id), history_text(&fresh.results, &id), "{id}");
    }
}

#[test]
fn summary_report_plot_and_export_accept_a_folder_holding_one_results_file() {
    let dir = runner_common::scratch("grow_folder");
    let out = dir.join("out");
    run(&write(&dir, "a.toml", &study("0.2", 1, "")), &out, false);
    let demsweep =
        |args: &[&str]| std::process::Command::new(env!("CARGO_BIN_EXE_demsweep")).args(args).output().unwrap();
    let o = out.to_str().unwrap();
    let exported = dir.join("exported");
    let plots = dir.join("plots");
    for args in [
        vec!["summary", o],
        vec!["report", o],
        vec!["plot", o, "--format", "svg", "--out", plots.to_str().unwrap()],
        vec!["export", o, "--format", "csv", "--out", exported.to_str().unwrap()],
    ] {
        let done = demsweep(&args);
        assert!(done.status.success(), "{args:?}: {}", String::from_utf8_lossy(&done.stderr));
    }
    assert!(dir.join("out/grow_report.html").is_file() && plots.join("r0000_frame_00001.svg").is_file());
    std::fs::copy(out.join("grow.h5"), out.join("other.h5")).unwrap();
    let refused = demsweep(&["summary", o]);
    let text = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success() && text.contains("2 results files (grow.h5, other.h5)"), "{text}");
}
