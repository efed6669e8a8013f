//! Shared helpers of the runner tests: tiny plans built in code and scratch directories.
#![allow(dead_code)]

use std::path::PathBuf;

use demsweep::physics::SceneConfig;
use demsweep::runner::{ProgressMode, RunOptions};
use demsweep::study::{OutputOptions, ParamValue, Plan, PlannedRun};

/// A tiny deposition: `count` disks falling for `duration` seconds in a narrow box.
pub fn tiny_scene(count: usize, duration: f64) -> SceneConfig {
    let mut scene = SceneConfig::default();
    scene.particles.count = count;
    scene.domain.width = 0.12;
    scene.domain.height = 0.2;
    scene.run.duration = duration;
    scene.run.sample_interval = 2e-3;
    scene
}

/// A plan of the given runs (parameters, scene); ids `r000`, `r001`, …
pub fn plan(name: &str, runs: Vec<(Vec<(String, ParamValue)>, SceneConfig)>) -> Plan {
    let runs = runs
        .into_iter()
        .enumerate()
        .map(|(index, (parameters, scene))| PlannedRun::new(format!("r{index:03}"), index, parameters, scene, None))
        .collect();
    Plan {
        study_path: PathBuf::from(format!("{name}.toml")),
        study_text: format!("# test study {name}\n"),
        name: name.to_string(),
        fingerprint: format!("test-fingerprint-{name}"),
        output: OutputOptions { histories: true, final_states: true, frames: true },
        runs,
        warnings: Vec::new(),
    }
}

/// `n` tiny runs sweeping restitution and seed (and frames at two times).
pub fn sweep(name: &str, n: usize) -> Plan {
    let runs = (0..n)
        .map(|i| {
            let mut scene = tiny_scene(12 + i % 3 * 4, 0.04);
            let restitution = 0.3 + 0.1 * (i % 4) as f64;
            scene.material.restitution = Some(restitution);
            scene.placement.seed = 100 + i as u64;
            scene.run.frame_times = vec![0.0, 0.02];
            let params = vec![
                ("material.restitution".to_string(), ParamValue::Float(restitution)),
                ("placement.seed".to_string(), ParamValue::Int(100 + i as i64)),
            ];
            (params, scene)
        })
        .collect();
    plan(name, runs)
}

/// An empty scratch directory for one test.
pub fn scratch(test: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("runner_tests").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch directory");
    dir
}

/// Quiet options writing into `dir` with `jobs` workers.
pub fn options(dir: &std::path::Path, jobs: usize) -> RunOptions {
    RunOptions { jobs, out_dir: Some(dir.to_path_buf()), progress: ProgressMode::Quiet, ..RunOptions::default() }
}

/// A CLI test study named `name`: 80 runs of 30 disks (about 20 ms each on one worker), long
/// enough to be stopped midway or overlapped by another process.
pub fn cli_study(name: &str) -> String {
    format!(
        r#"name = "{name}"
[scene]
particles.count = 30
domain.width = 0.16
domain.height = 0.25
run.duration = 0.2
run.sample_interval = 2e-3
[sweep]
"material.restitution" = {{ linear = [0.2, 0.8], steps = 4 }}
replicates = 20
[output]
frames = false
"#
    )
}

/// Waits (at most a minute) until `results` holds a committed run while `child` runs.
pub fn wait_for_first_commit(results: &std::path::Path, child: &mut std::process::Child) {
    let started = std::time::Instant::now();
    while !demsweep::output::summary::read(results).is_ok_and(|t| !t.is_empty()) {
        assert!(child.try_wait().unwrap().is_none(), "the sweep ended before its first commit was seen");
        assert!(started.elapsed() < std::time::Duration::from_secs(60), "no commit within a minute");
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
}

/// Runs the `demsweep` binary with `args` in the test's working folder; returns its output.
pub fn demsweep(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_demsweep")).args(args).output().unwrap()
}

/// Bytes of a command's output as text (invalid UTF-8 replaced).
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Runs the `demsweep` binary in `cwd` with `args` and asserts it ended with an exit status other
/// than a panic's (101), not by a signal; returns its output.
pub fn demsweep_in(cwd: &std::path::Path, args: &[&str]) -> std::process::Output {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(args)
        .current_dir(cwd)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .output()
        .expect("demsweep starts");
    let panicked_or_killed = out.status.code().is_none_or(|c| c == 101);
    assert!(!panicked_or_killed, "{args:?}: {:?}\n{}", out.status, String::from_utf8_lossy(&out.stderr));
    out
}

/// Says that demsweep `version` made every run of `results` (as an older or newer program would
/// have), and drops `/summary`, so that the runs are read from their groups (as after a kill).
pub fn made_by(results: &std::path::Path, version: &str) {
    let file = hdf5_pure::File::open_rw(results).unwrap();
    let runs = demsweep::output::reader::committed_runs(&file, results).unwrap();
    for group in runs.groups.values() {
        let version = hdf5_pure::AttrValue::String(version.into());
        file.group(group).unwrap().set_attr("demsweep_version", version).unwrap();
    }
    file.root().delete("summary").unwrap();
    file.commit().unwrap();
    file.close().unwrap();
}
