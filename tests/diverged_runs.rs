//! Sweeps whose runs diverge (speeds around 1e177, or a disk started at 1e200 m/s) go through every
//! command that reads them: `run` (which writes the report), `report`, `plot`, shards and `merge`,
//! `--resume`, `export` and `compare` end with an exit status, never a panic (101) or a signal.

mod runner_common;

use std::path::Path;
use std::process::{Command, Output, Stdio};

/// Stiffness x time step: the stiff, coarse corner diverges (checked below), the soft, fine one does not.
const STIFFNESS_TIME_STEP: &str = r#"name = "blowup"
[scene]
particles.count = 40
domain.width = 0.16
domain.height = 0.25
run.duration = 0.1
run.sample_interval = 0.02
[sweep]
"material.youngs_modulus" = [1e8, 1e10, 1e12, 1e14]
"integrator.time_step" = [1e-5, 1e-4, 1e-3]
"#;

/// Ten disks in a row, the first at 1e200 m/s.
const FAST_PLACEMENT: &str = r#"name = "blowup"
[scene]
particles.count = 10
particles.radius = 0.005
domain.width = 0.16
domain.height = 0.25
run.duration = 0.02
run.sample_interval = 2e-3
placement.kind = "file"
placement.file = "fast.csv"
[sweep]
"material.restitution" = [0.3, 0.6]
"#;

fn demsweep(cwd: &Path, args: &[&str]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(args)
        .current_dir(cwd)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .output()
        .unwrap();
    let code = out.status.code();
    assert!(code.is_some_and(|c| c != 101), "{args:?}: {:?}\n{}", out.status, String::from_utf8_lossy(&out.stderr));
    out
}

/// Runs the study in `dir` whole and in two shards, then every reading command; returns the
/// statuses of the runs.
fn every_command(dir: &Path) -> Vec<String> {
    let quiet = ["--progress", "quiet"];
    demsweep(dir, &[&["run", "blowup.toml", "--out", "whole"][..], &quiet].concat());
    for shard in ["1/2", "2/2"] {
        demsweep(dir, &[&["run", "blowup.toml", "--out", "shards", "--shard", shard][..], &quiet].concat());
    }
    demsweep(dir, &["merge", "merged", "shards"]);
    demsweep(dir, &[&["run", "blowup.toml", "--out", "whole", "--resume"][..], &quiet].concat());
    demsweep(dir, &["report", "whole/blowup.h5", "--out", "page.html"]);
    demsweep(dir, &["plot", "whole/blowup.h5", "--all-runs", "--out", "plots"]);
    demsweep(dir, &["plot", "merged/blowup.h5", "--colour-by", "force", "--format", "both", "--out", "plots2"]);
    demsweep(dir, &["export", "whole/blowup.h5", "--format", "vtk", "--out", "vtk"]);
    demsweep(dir, &["compare", "whole/blowup.h5", "--reference", "r0000", "--plot", "--out", "compare"]);
    assert!(dir.join("page.html").is_file() && dir.join("plots").is_dir());
    let summary = demsweep::output::summary::read(&dir.join("whole/blowup.h5")).unwrap();
    let rows = demsweep::output::reader::rows(
        &demsweep::output::reader::open(&dir.join("whole/blowup.h5")).unwrap(),
        &dir.join("whole/blowup.h5"),
    )
    .unwrap();
    assert_eq!(rows.len(), summary.len());
    rows.iter().map(|r| r.status.to_string()).collect()
}

#[test]
fn a_stiffness_time_step_sweep_with_diverged_runs_goes_through_every_command() {
    let dir = runner_common::scratch("diverged_sweep");
    std::fs::write(dir.join("blowup.toml"), STIFFNESS_TIME_STEP).unwrap();
    let statuses = every_command(&dir);
    let diverged = statuses.iter().filter(|s| *s == "diverged").count();
    assert!(diverged >= 3 && diverged < statuses.len(), "some runs diverge, some do not: {statuses:?}");
}

#[test]
fn a_disk_started_at_1e200_metres_per_second_goes_through_every_command() {
    let dir = runner_common::scratch("diverged_placement");
    std::fs::write(dir.join("blowup.toml"), FAST_PLACEMENT).unwrap();
    let rows: Vec<String> = (0..10)
        .map(|i| format!("{},0.05,0.005,{},0", 0.01 + 0.015 * i as f64, if i == 0 { 1e200 } else { 0.0 }))
        .collect();
    std::fs::write(dir.join("fast.csv"), format!("x,y,r,vx,vy\n{}\n", rows.join("\n"))).unwrap();
    let statuses = every_command(&dir);
    assert_eq!(statuses, ["diverged", "diverged"]);
}
