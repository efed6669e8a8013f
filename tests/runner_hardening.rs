//! A shared cluster's faults: two processes on one results folder, absurd `--jobs`, a killed merge.

mod runner_common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use demsweep::output::summary;

const RUNS: usize = 80;

/// The 80-run study of the CLI tests, named `shared`.
fn study_text() -> String {
    runner_common::cli_study("shared")
}

fn write_study(dir: &Path, text: &str) -> PathBuf {
    let path = dir.join("shared.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn command(args: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_demsweep"));
    command.args(args).stdout(Stdio::piped()).stderr(Stdio::piped());
    command
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// `demsweep run STUDY --out OUT --jobs 1` plus `extra`, started.
fn spawn_run(study: &Path, out: &Path, extra: &[&str]) -> Child {
    let (s, o) = (study.to_str().unwrap(), out.to_str().unwrap());
    command(&["run", s, "--out", o, "--jobs", "1", "--commit-interval", "0.05", "--progress", "quiet"])
        .args(extra)
        .spawn()
        .unwrap()
}

#[test]
fn force_and_resume_are_refused_while_another_process_writes() {
    let dir = runner_common::scratch("hard_force");
    let study = write_study(&dir, &study_text());
    let other =
        write_study(&runner_common::scratch("hard_force_other"), &study_text().replace("steps = 4", "steps = 2"));
    let out = dir.join("out");
    let results = out.join("shared.h5");
    let mut first = spawn_run(&study, &out, &[]);
    runner_common::wait_for_first_commit(&results, &mut first);
    for (study, flag) in [(&other, "--force"), (&study, "--resume"), (&study, "--force")] {
        let second = spawn_run(study, &out, &[flag]).wait_with_output().unwrap();
        assert_eq!(second.status.code(), Some(1), "{flag}: {}", stderr(&second));
        let expected = format!("is being written by another process (pid {} on ", first.id());
        assert!(stderr(&second).contains(&expected), "{flag}: {}", stderr(&second));
        assert!(stderr(&second).contains("then use --resume"), "{}", stderr(&second));
        assert!(!stderr(&second).contains("HDF5_USE_FILE_LOCKING"), "no library text: {}", stderr(&second));
    }
    let first = first.wait_with_output().unwrap();
    assert_eq!(first.status.code(), Some(0), "{}", stderr(&first));
    assert_eq!(summary::read(&results).unwrap().len(), RUNS, "the first study's file, whole");
    let csv = std::fs::read_to_string(out.join("shared_summary.csv")).unwrap();
    assert_eq!(csv.lines().count(), RUNS + 1, "the CSV is the same study's (names, runs)");
}

#[test]
fn of_two_fresh_starts_at_once_exactly_one_writes() {
    let dir = runner_common::scratch("hard_fresh");
    let study = write_study(&dir, &study_text().replace("replicates = 20", "replicates = 2"));
    for trial in 0..4 {
        let out = dir.join(format!("out{trial}"));
        let children = [spawn_run(&study, &out, &[]), spawn_run(&study, &out, &[])];
        let outputs: Vec<Output> = children.into_iter().map(|c| c.wait_with_output().unwrap()).collect();
        let mut codes: Vec<Option<i32>> = outputs.iter().map(|o| o.status.code()).collect();
        codes.sort();
        assert_eq!(codes, [Some(0), Some(1)], "trial {trial}: {:?}", outputs.iter().map(stderr).collect::<Vec<_>>());
        let refused = outputs.iter().find(|o| o.status.code() == Some(1)).unwrap();
        let message = stderr(refused);
        assert!(
            message.contains("is being written by another process") || message.contains("results already exist"),
            "{message}"
        );
        assert_eq!(summary::read(&out.join("shared.h5")).unwrap().len(), 8, "trial {trial}");
    }
}

#[test]
fn jobs_are_capped_by_the_runs_to_do() {
    let dir = runner_common::scratch("hard_jobs");
    let study = write_study(&dir, &study_text().replace("replicates = 20", "").replace("steps = 4", "steps = 2"));
    let (s, out) = (study.to_str().unwrap(), dir.join("out"));
    let run = command(&["run", s, "--out", out.to_str().unwrap(), "--jobs", "100000"]).output().unwrap();
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    assert!(stderr(&run).contains("note: --jobs 100000 capped to 2 worker threads (2 runs to do)"), "{}", stderr(&run));
}

#[test]
fn a_killed_merge_leaves_nothing_under_the_final_name() {
    let dir = runner_common::scratch("hard_merge");
    let study = write_study(&dir, &study_text());
    let shards = dir.join("shards");
    for k in ["1/2", "2/2"] {
        let run = command(&["run", study.to_str().unwrap(), "--out", shards.to_str().unwrap(), "--shard", k])
            .output()
            .unwrap();
        assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    }
    let merged = dir.join("merged");
    let results = merged.join("shared.h5");
    let mut merge = command(&["merge", merged.to_str().unwrap(), shards.to_str().unwrap()]).spawn().unwrap();
    let started = Instant::now();
    while !merged.join("shared.merging.h5").exists() && !results.exists() && merge.try_wait().unwrap().is_none() {
        assert!(started.elapsed() < Duration::from_secs(60), "the merge wrote nothing within a minute");
        std::thread::sleep(Duration::from_micros(200));
    }
    merge.kill().unwrap();
    let killed = merge.wait().unwrap().code().is_none();
    assert!(killed, "the merge ended before it could be killed: make the shards larger");
    assert!(!results.exists(), "a partial merge under the final name");
    let again = command(&["merge", merged.to_str().unwrap(), shards.to_str().unwrap()]).output().unwrap();
    assert_eq!(again.status.code(), Some(0), "{}", stderr(&again));
    assert_eq!(summary::read(&results).unwrap().len(), RUNS);
}

/// 10 000 runs of one disk for 10 steps (well under a millisecond each): the writer is the bottleneck.
const TINY_RUNS: &str = r#"name = "shared"
[scene]
particles.count = 1
run.duration = 1e-3
integrator.time_step = 1e-4
[sweep]
"material.friction" = { linear = [0.0, 1.0], steps = 10000 }
"#;

#[test]
fn kill_9_loses_at_most_the_commit_interval_even_when_runs_are_tiny() {
    use std::io::BufRead;
    let dir = runner_common::scratch("hard_tiny_kill");
    let study = write_study(&dir, TINY_RUNS);
    let out = dir.join("out");
    let (s, o) = (study.to_str().unwrap(), out.to_str().unwrap());
    let mut child = command(&["run", s, "--out", o, "--jobs", "1", "--commit-interval", "0.1", "--progress", "lines"])
        .spawn()
        .unwrap();
    // One line per finished run, printed before the run goes to the writer.
    let mut lines = std::io::BufReader::new(child.stdout.take().unwrap()).lines();
    let finished = 1000;
    for k in 0..finished {
        assert!(lines.next().is_some_and(|l| l.is_ok()), "the sweep ended after {k} runs");
    }
    std::thread::sleep(Duration::from_secs(4));
    assert!(child.try_wait().unwrap().is_none(), "the sweep ended before the kill: make it longer");
    child.kill().unwrap();
    child.wait().unwrap();
    let committed = summary::read(&out.join("shared.h5")).expect("a killed sweep's file is valid").len();
    assert!(committed >= finished, "{committed} of the {finished} runs finished 4 s before kill -9 were committed");
}

/// A short run and one of 300 disks sampled only at its start and end: 1000 s simulated, hours of
/// computing between its two samples (run side by side: the longer starts first).
const FAR_APART_SAMPLES: &str = r#"name = "shared"
[scene]
particles.count = 300
particles.radius = 0.005
domain.width = 0.2
domain.height = 0.3
run.sample_interval = 1000.0
run.stop_at_settle = false
[sweep]
"run.duration" = [0.01, 1000.0]
[output]
frames = false
"#;

#[test]
fn sigterm_ends_a_run_between_far_apart_samples_within_a_second() {
    let dir = runner_common::scratch("hard_sigterm_between_samples");
    let study = write_study(&dir, FAR_APART_SAMPLES);
    let out = dir.join("out");
    let (s, o) = (study.to_str().unwrap(), out.to_str().unwrap());
    let mut child = command(&["run", s, "--out", o, "--jobs", "2", "--commit-interval", "0.05", "--progress", "quiet"])
        .spawn()
        .unwrap();
    runner_common::wait_for_first_commit(&out.join("shared.h5"), &mut child);
    std::thread::sleep(Duration::from_millis(300)); // well into the long run's first sample interval
    let sent = Instant::now();
    assert!(Command::new("kill").args(["-TERM", &child.id().to_string()]).status().unwrap().success());
    while child.try_wait().unwrap().is_none() && sent.elapsed() < Duration::from_secs(10) {
        std::thread::sleep(Duration::from_millis(5));
    }
    let took = sent.elapsed();
    let _ = child.kill();
    let ended = child.wait_with_output().unwrap();
    assert!(took < Duration::from_secs(1), "the sweep ended {took:?} after SIGTERM");
    assert_eq!(ended.status.code(), Some(130), "{}", stderr(&ended));
    assert!(stderr(&ended).contains("--resume"), "{}", stderr(&ended));
    let kept = summary::read(&out.join("shared.h5")).unwrap();
    assert_eq!(kept.len(), 1, "the finished run is kept, the interrupted one is not");
}

/// Overwrites 64 bytes around the value of the `id` attribute of the run group of `id` in `results`
/// (the run id written just after the attribute's name, not the link to the group in its batch),
/// damaging that run group only.
fn damage_run_group(results: &Path, id: &str) {
    let mut bytes = std::fs::read(results).unwrap();
    let after_id_name = |at: usize| bytes[at.saturating_sub(48)..at].windows(3).any(|w| w == b"id\0");
    let at = (0..bytes.len() - id.len())
        .find(|&at| bytes[at..at + id.len()] == *id.as_bytes() && after_id_name(at))
        .expect("the run id attribute is in the file");
    bytes[at - 32..at + 32].fill(0xff);
    std::fs::write(results, bytes).unwrap();
}

#[test]
fn a_damaged_run_group_is_named_skipped_and_run_again_on_resume() {
    let dir = runner_common::scratch("hard_damaged");
    let study = write_study(&dir, &study_text().replace("replicates = 20", "replicates = 2"));
    let out = dir.join("out");
    let (s, o) = (study.to_str().unwrap(), out.to_str().unwrap());
    let first = command(&["run", s, "--out", o]).output().unwrap();
    assert_eq!(first.status.code(), Some(0), "{}", stderr(&first));
    let results = out.join("shared.h5");
    let intact = summary::read(&results).unwrap().without_timing();
    // Run groups are named by the run's identity (/summary's `identity` column is the index).
    let identity = intact.column("identity").unwrap().data.text(5);
    damage_run_group(&results, "r0005");
    let r = results.to_str().unwrap();
    let (vtk, compare_csv) = (dir.join("vtk"), dir.join("compare.csv"));
    let (vtk, compare_csv) = (vtk.to_str().unwrap(), compare_csv.to_str().unwrap());
    for args in [
        vec!["summary", r],
        vec!["report", r],
        vec!["plot", r, "--format", "svg"],
        vec!["export", r, "--format", "vtk", "--run", "r0001", "--out", vtk],
        vec!["compare", r, "--reference", "r0000", "--csv", compare_csv],
    ] {
        let seen = command(&args).output().unwrap();
        assert_eq!(seen.status.code(), Some(3), "{args:?}: {}", stderr(&seen));
        let expected = format!("damaged: 1 run group(s) cannot be read: /runs_00000/{identity} (");
        assert!(stderr(&seen).contains(&expected), "{args:?}: {}", stderr(&seen));
    }
    assert!(Path::new(vtk).join("r0001_final_disks.vtp").is_file() && Path::new(compare_csv).is_file());
    let export = command(&["export", r, "--format", "vtk", "--run", "r0005", "--out", "unused"]).output().unwrap();
    assert_eq!(export.status.code(), Some(1), "{}", stderr(&export));
    let expected = format!("run group /runs_00000/{identity} cannot be read");
    assert!(stderr(&export).contains(&expected), "{}", stderr(&export));
    let listed = String::from_utf8(command(&["summary", r]).output().unwrap().stdout).unwrap();
    assert_eq!(listed.lines().count(), 1 + 7, "the seven readable runs:\n{listed}");
    assert!(!listed.contains("r0005"), "{listed}");
    // Quiet progress still warns about what is damaged and runs again.
    let resumed = command(&["run", s, "--out", o, "--resume", "--progress", "quiet"]).output().unwrap();
    assert_eq!(resumed.status.code(), Some(0), "{}", stderr(&resumed));
    assert!(String::from_utf8_lossy(&resumed.stdout).contains("1 run now, 7 already done"), "{resumed:?}");
    assert!(stderr(&resumed).contains(&format!("/runs_00000/{identity}")), "the resume names what it runs again");
    assert_eq!(summary::read(&results).unwrap().without_timing(), intact);
    let clean = command(&["summary", r]).output().unwrap();
    assert_eq!(clean.status.code(), Some(0), "{}", stderr(&clean));
}
