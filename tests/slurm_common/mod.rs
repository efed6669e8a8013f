//! Shared helpers of the Slurm tests: a tiny study, the `demsweep` command and summary comparison.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use demsweep::output::{SummaryTable, summary};

/// 8 runs of 12 disks for 0.04 s (a few milliseconds each).
pub const STUDY: &str = r#"name = "slurm_tiny"
[scene]
particles.count = 12
domain.width = 0.12
domain.height = 0.2
run.duration = 0.04
run.sample_interval = 2e-3
[sweep]
"material.restitution" = { linear = [0.2, 0.8], steps = 4 }
replicates = 2
"#;
/// Runs in [`STUDY`].
pub const RUNS: usize = 8;
/// The study name in [`STUDY`].
pub const NAME: &str = "slurm_tiny";

/// An empty scratch directory for one test.
pub fn scratch(test: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("slurm_tests").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch directory");
    dir
}

/// Writes [`STUDY`] into `dir`.
pub fn write_study(dir: &Path) -> PathBuf {
    let path = dir.join("slurm_tiny.toml");
    std::fs::write(&path, STUDY).unwrap();
    path
}

/// `demsweep ARGS` with extra environment variables.
pub fn demsweep(args: &[&str], env: &[(&str, &Path)]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_demsweep"));
    command.args(args).envs(env.iter().map(|(k, v)| (k, v.as_os_str())));
    command.output().unwrap()
}

/// Panics with the command's output unless it succeeded; returns its stdout.
pub fn succeeded(what: &str, out: &Output) -> String {
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{what} failed ({}):\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// The summary of a one-machine run of the study into `dir`, timing columns aside.
pub fn local_summary(study: &Path, dir: &Path) -> SummaryTable {
    let out = demsweep(&["run", study.to_str().unwrap(), "--out", dir.to_str().unwrap(), "--progress", "quiet"], &[]);
    succeeded("local run", &out);
    merged_summary(dir)
}

/// The summary of `dir/<study name>.h5`, timing columns aside.
pub fn merged_summary(dir: &Path) -> SummaryTable {
    let table = summary::read(&dir.join(format!("{NAME}.h5"))).expect("read results").without_timing();
    assert_eq!(table.len(), RUNS);
    table
}
