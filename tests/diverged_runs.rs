//! Sweeps whose runs diverge (speeds around 1e177, or a disk started at 1e200 m/s) go through every
//! command that reads them: `run` (which writes the report), `report`, `plot`, shards and `merge`,
//! `--resume`, `export` and `compare` end with an exit status, never a panic (101) or a signal; `run`
//! and `merge` exit 4 when some runs diverged and 1 when every one did, saying how many.

mod runner_common;

use std::path::Path;
use std::process::Output;

/// Stiffness x time step: the stiff, coarse corner diverges (checked below), the soft, fine one does not.
const STIFFNESS_TIME_STEP: &str = include_str!("data/diverged/stiffness_time_step.toml");

/// Ten disks in a row (`fast.csv`), the first at 1e200 m/s.
const FAST_DISK: &str = include_str!("data/diverged/fast_disk.toml");

use runner_common::demsweep_in as demsweep;

/// Runs the study in `dir` whole and in two shards, then every reading command; returns the
/// statuses of the runs, and what the whole run and the merge said.
fn every_command(dir: &Path) -> (Vec<String>, [Output; 2]) {
    let quiet = ["--progress", "quiet"];
    let run = demsweep(dir, &[&["run", "blowup.toml", "--out", "whole"][..], &quiet].concat());
    for shard in ["1/2", "2/2"] {
        demsweep(dir, &[&["run", "blowup.toml", "--out", "shards", "--shard", shard][..], &quiet].concat());
    }
    let merge = demsweep(dir, &["merge", "merged", "shards"]);
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
    (rows.iter().map(|r| r.status.to_string()).collect(), [run, merge])
}

/// Asserts that `run` and `merge` exited with `code`, saying `said` on stderr.
fn assert_said(outputs: &[Output; 2], code: i32, said: &str) {
    for out in outputs {
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{stderr}");
        assert!(stderr.contains(said), "{said:?} not in {stderr}");
    }
}

#[test]
fn a_stiffness_time_step_sweep_with_diverged_runs_goes_through_every_command() {
    let dir = runner_common::scratch("diverged_sweep");
    std::fs::write(dir.join("blowup.toml"), STIFFNESS_TIME_STEP).unwrap();
    let (statuses, outputs) = every_command(&dir);
    let diverged = statuses.iter().filter(|s| *s == "diverged").count();
    assert!(diverged >= 3 && diverged < statuses.len(), "some runs diverge, some do not: {statuses:?}");
    let said = format!("warning: {diverged} of 12 runs failed ({diverged} diverged) (exit status 4)");
    assert_said(&outputs, 4, &said);
}

#[test]
fn a_disk_started_at_1e200_metres_per_second_goes_through_every_command() {
    let dir = runner_common::scratch("diverged_placement");
    std::fs::write(dir.join("blowup.toml"), FAST_DISK).unwrap();
    std::fs::write(dir.join("fast.csv"), include_str!("data/diverged/fast.csv")).unwrap();
    let (statuses, outputs) = every_command(&dir);
    assert_eq!(statuses, ["diverged", "diverged"]);
    assert_said(&outputs, 1, "error: 2 of 2 runs failed (2 diverged): no run gave a result");
}
