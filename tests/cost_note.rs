//! `check` and `run` say how long a long sweep will take (the figure `plan` gives) before it starts.

mod study_support;

use std::process::Command;

use study_support::StudyDir;

/// One run of 2 000 disks for 1 000 s at 0.1 µs steps: 2e13 particle-steps, days on any machine.
const LONG: &str = "name = \"long\"\n[scene]\nparticles.count = 2000\ndomain.width = 1.0\ndomain.height = 1.0\n\
                    placement.kind = \"lattice\"\nintegrator.time_step = 1e-7\nrun.duration = 1000.0\n";

#[test]
fn check_prints_the_estimate_of_a_sweep_longer_than_an_hour() {
    let dir = StudyDir::new("cost_note");
    let study = dir.write("long.toml", LONG);
    let out = Command::new(env!("CARGO_BIN_EXE_demsweep")).arg("check").arg(&study).output().unwrap();
    let text = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{text}");
    assert!(text.contains("note: ") && text.contains(" h on ") && text.contains("2.0000e13 particle-steps"), "{text}");
    let short = dir.write("short.toml", &LONG.replace("run.duration = 1000.0", "run.duration = 0.001"));
    let out = Command::new(env!("CARGO_BIN_EXE_demsweep")).arg("check").arg(&short).output().unwrap();
    assert!(!String::from_utf8_lossy(&out.stderr).contains("particle-steps"), "no note for a short sweep");
}
