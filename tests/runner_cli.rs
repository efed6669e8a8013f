//! `demsweep run` as a user runs it: killed with SIGKILL or stopped with Ctrl-C, SIGTERM or SIGHUP mid-sweep, then
//! continued with `--resume`, it ends with the summary of an uninterrupted run; `summary`, `history`
//! and `merge` on its files.

mod runner_common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

use demsweep::output::summary;
use runner_common::demsweep;

const RUNS: usize = 80;

fn study(dir: &Path) -> PathBuf {
    let path = dir.join("cli_sweep.toml");
    std::fs::write(&path, runner_common::cli_study("cli_sweep")).unwrap();
    path
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Starts a sweep that commits often, on one worker.
fn spawn_run(study: &Path, out: &Path) -> Child {
    Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(["run", study.to_str().unwrap(), "--out", out.to_str().unwrap(), "--jobs", "1"])
        .args(["--commit-interval", "0.05", "--progress", "quiet"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap()
}

/// The summary of an uninterrupted run of the study.
fn reference(study: &Path, test: &str) -> demsweep::output::SummaryTable {
    let out = runner_common::scratch(test);
    let run = demsweep(&["run", study.to_str().unwrap(), "--out", out.to_str().unwrap(), "--progress", "quiet"]);
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    summary::read(&out.join("cli_sweep.h5")).unwrap().without_timing()
}

/// Resumes the sweep and checks it completes to the reference summary.
fn resume_and_compare(study: &Path, out: &Path, kept: usize, reference: &demsweep::output::SummaryTable) {
    let resumed = demsweep(&["run", study.to_str().unwrap(), "--out", out.to_str().unwrap(), "--resume"]);
    assert_eq!(resumed.status.code(), Some(0), "{}", stderr(&resumed));
    let report = String::from_utf8_lossy(&resumed.stdout);
    let expected = format!("{} run now, {kept} already done", RUNS - kept);
    assert!(report.contains(&expected), "{report}");
    let table = summary::read(&out.join("cli_sweep.h5")).unwrap();
    assert_eq!(&table.without_timing(), reference);
}

/// A sweep started in its own folder and stopped by `stop` once it has committed a run; returns the
/// study file, the output folder, the exit code and how many runs the file kept.
fn stopped_midway(test: &str, stop: impl FnOnce(&mut Child)) -> (PathBuf, PathBuf, Option<i32>, usize) {
    let dir = runner_common::scratch(test);
    let study = study(&dir);
    let out = dir.join("out");
    let mut child = spawn_run(&study, &out);
    runner_common::wait_for_first_commit(&out.join("cli_sweep.h5"), &mut child);
    stop(&mut child);
    let code = child.wait().unwrap().code();
    let kept = summary::read(&out.join("cli_sweep.h5")).expect("the stopped sweep's file is valid").len();
    assert!((1..RUNS).contains(&kept), "kept {kept} of {RUNS}");
    (study, out, code, kept)
}

#[test]
fn killed_with_sigkill_then_resumed_equals_an_uninterrupted_run() {
    let (study, out, code, kept) = stopped_midway("cli_kill", |child| child.kill().unwrap());
    assert_eq!(code, None, "killed by a signal");

    let again = demsweep(&["run", study.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(again.status.code(), Some(1));
    assert!(stderr(&again).contains("--resume"), "{}", stderr(&again));

    resume_and_compare(&study, &out, kept, &reference(&study, "cli_kill_reference"));
}

#[test]
fn ctrl_c_stops_cleanly_with_exit_130_and_resumes() {
    let (study, out, code, kept) = stopped_midway("cli_ctrl_c", |child| {
        let sent = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
        assert!(sent.success());
    });
    assert_eq!(code, Some(130));
    let file = hdf5_pure::File::open(out.join("cli_sweep.h5")).unwrap();
    assert!(file.group("summary").is_ok(), "a clean stop writes /summary");
    let csv = std::fs::read_to_string(out.join("cli_sweep_summary.csv")).unwrap();
    assert_eq!(csv.lines().count(), kept + 1, "names and a line per finished run");

    resume_and_compare(&study, &out, kept, &reference(&study, "cli_ctrl_c_reference"));
}

#[test]
fn sigterm_and_sighup_stop_cleanly_like_ctrl_c() {
    for signal in ["TERM", "HUP"] {
        let (_, out, code, kept) = stopped_midway(&format!("cli_sig{signal}"), |child| {
            let sent = Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status().unwrap();
            assert!(sent.success());
        });
        assert_eq!(code, Some(130), "SIG{signal}");
        let file = hdf5_pure::File::open(out.join("cli_sweep.h5")).unwrap();
        assert!(file.group("summary").is_ok(), "SIG{signal}: a clean stop writes /summary");
        let csv = std::fs::read_to_string(out.join("cli_sweep_summary.csv")).unwrap();
        assert_eq!(csv.lines().count(), kept + 1, "SIG{signal}: every finished run is in the CSV");
    }
}

/// A complete study sweeping `material.<axis>` over two values, run in `dir`; its results file.
fn one_axis_results(dir: &Path, axis: &str) -> PathBuf {
    let study = dir.join(format!("{axis}.toml"));
    let text = format!(
        "name = \"{axis}\"\n[scene]\nparticles.count = 12\ndomain.width = 0.12\ndomain.height = 0.2\n\
         run.duration = 0.05\n[sweep]\n\"material.{axis}\" = [0.3, 0.6]\n[output]\nframes = false\n"
    );
    std::fs::write(&study, text).unwrap();
    let out = dir.join(axis);
    let run = demsweep(&["run", study.to_str().unwrap(), "--out", out.to_str().unwrap(), "--progress", "quiet"]);
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    out.join(format!("{axis}.h5"))
}

#[test]
fn merging_complete_studies_of_different_axes_succeeds_whatever_their_charts() {
    let dir = runner_common::scratch("cli_merge_axes");
    let (first, second) = (one_axis_results(&dir, "restitution"), one_axis_results(&dir, "friction"));
    let merged = dir.join("merged");
    let args = [merged.to_str().unwrap(), first.to_str().unwrap(), second.to_str().unwrap()];
    let out = demsweep(&["merge", args[0], args[1], args[2], "--name", "both"]);
    assert_eq!(out.status.code(), Some(0), "a chart decides nothing: {}", stderr(&out));
    assert!(stderr(&out).contains("warning: chart not drawn on the report page: "), "{}", stderr(&out));
    assert_eq!(summary::read(&merged.join("both.h5")).unwrap().len(), 4);
    assert!(merged.join("both_report.html").is_file());
}

#[test]
fn summary_history_and_merge_commands() {
    let dir = runner_common::scratch("cli_commands");
    let study = study(&dir);
    let s = study.to_str().unwrap();
    let shards = dir.join("shards");
    for k in ["1/2", "2/2"] {
        let run = demsweep(&["run", s, "--out", shards.to_str().unwrap(), "--shard", k, "--progress", "lines"]);
        assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
        let lines = String::from_utf8_lossy(&run.stdout).lines().filter(|l| l.contains(" not_settled ")).count();
        assert_eq!(lines, RUNS / 2, "one line per finished run");
        let page = shards.join(format!("cli_sweep.shard-{}-of-2_report.html", &k[..1]));
        assert!(String::from_utf8_lossy(&run.stdout).contains(&format!("report: {}", page.display())));
    }
    assert!(!shards.join("cli_sweep_report.html").exists(), "each shard has its own page, none shared");
    let merged = dir.join("merged");
    let merge = demsweep(&["merge", merged.to_str().unwrap(), shards.to_str().unwrap()]);
    assert_eq!(merge.status.code(), Some(0), "{}", stderr(&merge));
    let results = merged.join("cli_sweep.h5");

    let printed = demsweep(&["summary", results.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&printed.stdout);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), RUNS + 1);
    assert!(lines[0].starts_with("run_id  index  material.restitution  placement.seed  status"), "{}", lines[0]);
    assert!(lines[1].starts_with("r0000 "), "{}", lines[1]);
    // By default the chosen metrics only (with units); --all every column; --metric picks them.
    assert!(lines[0].contains("settle_time (s)") && !lines[0].contains("final_kinetic"), "{}", lines[0]);
    assert!(lines.iter().all(|l| l.chars().count() < 250), "default lines stay readable: {}", lines[0]);
    let all = demsweep(&["summary", results.to_str().unwrap(), "--all"]);
    let all = String::from_utf8_lossy(&all.stdout);
    assert!(all.lines().next().unwrap().contains("final_kinetic"), "{all}");
    let picked = demsweep(&["summary", results.to_str().unwrap(), "--metric", "steps"]);
    let picked = String::from_utf8_lossy(&picked.stdout);
    assert!(picked.lines().next().unwrap().trim_end().ends_with("steps  warnings"), "{picked}");
    let unknown = demsweep(&["summary", results.to_str().unwrap(), "--metric", "nonsense"]);
    assert_eq!(unknown.status.code(), Some(2));
    assert!(stderr(&unknown).contains("no metric `nonsense`"), "{}", stderr(&unknown));

    let csv = dir.join("exported.csv");
    let export = demsweep(&["summary", results.to_str().unwrap(), "--csv", csv.to_str().unwrap()]);
    assert_eq!(export.status.code(), Some(0));
    assert_eq!(std::fs::read(&csv).unwrap(), std::fs::read(merged.join("cli_sweep_summary.csv")).unwrap());

    let history = demsweep(&["history", results.to_str().unwrap(), "r0005"]);
    let text = String::from_utf8_lossy(&history.stdout);
    assert!(
        text.starts_with("t,kinetic_translational,kinetic_rotational,potential,"),
        "the names as in /history: {text}"
    );
    assert!(text.lines().nth(1).unwrap().starts_with("0.0,"), "then the values, from t = 0: {text}");
    assert_eq!(text.lines().count(), 1 + 101, "0.2 s sampled every 2 ms, both ends included");

    let missing = demsweep(&["history", results.to_str().unwrap(), "r9999"]);
    assert_eq!(missing.status.code(), Some(1));
    assert!(stderr(&missing).contains("no run `r9999`"), "{}", stderr(&missing));

    let r = results.to_str().unwrap();
    let by_point = demsweep(&["summary", r, "--by-point"]);
    let text = String::from_utf8_lossy(&by_point.stdout);
    assert_eq!(text.lines().count(), 1 + 4, "one line per restitution value:\n{text}");
    assert!(text.lines().nth(1).unwrap().starts_with("0.2  "), "{text}");
    assert!(text.lines().next().unwrap().contains("  settle_time (s) ±95%  "), "labelled as everywhere: {text}");
    let points_csv = dir.join("points.csv");
    let export = demsweep(&["summary", r, "--by-point", "--csv", points_csv.to_str().unwrap()]);
    assert_eq!(export.status.code(), Some(0));
    assert_eq!(std::fs::read(&points_csv).unwrap(), std::fs::read(merged.join("cli_sweep_points.csv")).unwrap());

    let compare = demsweep(&["compare", r, "--reference", "restitution=0.4", "--keep", "pile_height=0.05"]);
    let text = String::from_utf8_lossy(&compare.stdout);
    assert_eq!(compare.status.code(), Some(0), "{}", stderr(&compare));
    let decided = text.lines().filter(|l| l.contains("  pile_height  "));
    let decisions: Vec<&str> = decided.filter_map(|l| l.split_whitespace().nth(8)).collect();
    assert_eq!(decisions.len(), 3, "the three other points, one metric:\n{text}");
    assert!(decisions.iter().all(|d| ["equivalent", "different", "undecided"].contains(d)), "{text}");
    for (reference, keep, expected) in [
        ("restitution=0.3", "pile_height=0.05", "no point has restitution=0.3"),
        (
            "restitution=0.4",
            "bogus=0.1",
            "`bogus`: not a per-run quantity or numeric summary column; the metrics of this file are: settle_time,",
        ),
        ("placement.seed=1", "pile_height=0.05", "placement.seed is not a point coordinate"),
    ] {
        let refused = demsweep(&["compare", r, "--reference", reference, "--keep", keep]);
        assert_eq!(refused.status.code(), Some(2), "{reference} {keep}");
        assert!(stderr(&refused).starts_with(&format!("error: {r}: {expected}")), "{}", stderr(&refused));
    }
}

#[test]
fn a_sweep_says_how_many_warnings_each_run_has_and_which_kinds() {
    let out_dir = runner_common::scratch("cli_warnings");
    let study = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/paper_table1.toml");
    let out = demsweep(&["run", study, "--out", out_dir.to_str().unwrap(), "--progress", "lines"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let line = stdout.lines().next().unwrap();
    assert!(line.starts_with("r0000  not_settled  settle -  wall ") && line.ends_with(" s  4 warnings"), "{stdout}");
    let stderr = stderr(&out);
    let digest: Vec<&str> = stderr.lines().skip_while(|l| !l.starts_with("warnings: ")).collect();
    assert_eq!(digest.first(), Some(&"warnings: 4 kind(s) in 1 of 1 runs run now:"), "{stderr}");
    for expected in [
        "  1 run (r0000): an impact at 3.37 m/s would overlap 0.8144 radii",
        "  1 run (r0000): the settled pile's weight would press the bottom disks 8.528 radii into the floor",
        "  1 run (r0000): largest overlap 3.044 radii at t = ",
        "  1 run (r0000): energy balance (mechanical + dissipated = initial) is off by ",
    ] {
        assert!(digest.iter().any(|l| l.starts_with(expected)), "{expected}\n{stderr}");
    }
    assert!(digest.last().unwrap().starts_with("each run's warnings: `demsweep summary "), "{stderr}");
}
