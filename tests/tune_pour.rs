//! The deposition rate as a tune lever: a tune file moving `placement.pour.rate` is checked, planned
//! and run like any other lever (levers are scene keys).

mod runner_common;

use runner_common::demsweep;
use std::path::Path;
use std::process::Output;

/// 20 disks poured at 200 disks per second into a small box; the rate moves over 100 to 1000.
const TUNE: &str = r#"name = "tune_pour"
[scene]
domain.width = 0.06
domain.height = 0.12
particles.count = 20
particles.radius = 0.004
placement.kind = "pour"
placement.seed = 5
placement.pour.rate = 200.0
placement.pour.y_min = 0.1
material.youngs_modulus = 1e9
run.duration = 1.0
settle.ubf_threshold = 5e-2
settle.hold_time = 0.02

[levers]
"placement.pour.rate" = { log = [100.0, 1000.0] }

[keep]
pile_height = 0.2

[search]
seeds = 2
max_seeds = 2
reference_seeds = 2
verify_seeds = 2
budget = 16
seed = 1

[output]
histories = false
frames = false
"#;

fn text(output: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr))
}

/// The cells of `columns` in each row of a CSV file (columns ahead of any quoted comma).
fn cells(path: &Path, columns: &[&str]) -> Vec<Vec<String>> {
    let csv = std::fs::read_to_string(path).unwrap();
    let mut lines = csv.lines();
    let names: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at: Vec<usize> = columns.iter().map(|c| names.iter().position(|n| n == c).expect(c)).collect();
    lines
        .map(|line| line.split(',').collect::<Vec<_>>())
        .map(|row| at.iter().map(|&k| row[k].to_string()).collect())
        .collect()
}

#[test]
fn the_pour_rate_is_a_lever_tune_checks_plans_and_moves() {
    let dir = runner_common::scratch("tune_pour");
    let file = dir.join("tune_pour.toml");
    std::fs::write(&file, TUNE).unwrap();
    let file = file.to_str().unwrap();
    let check = demsweep(&["check", file]);
    assert_eq!(check.status.code(), Some(0), "{}", text(&check));
    assert!(text(&check).contains("ok: tune file, 1 levers"), "{}", text(&check));
    let plan = demsweep(&["plan", file]);
    assert_eq!(plan.status.code(), Some(0), "{}", text(&plan));
    assert!(text(&plan).contains("placement.pour.rate: log 100 .. 1000"), "{}", text(&plan));

    let out = dir.join("out");
    let tune = demsweep(&["tune", file, "--out", out.to_str().unwrap(), "--jobs", "2"]);
    assert_eq!(tune.status.code(), Some(0), "{}", text(&tune));
    // Every run poured at its candidate's rate: the reference's, and others inside the lever's range.
    let runs = cells(&out.join("tune_pour_summary.csv"), &["placement.pour.rate", "tune.role"]);
    assert!(runs.len() >= 6, "{runs:?}");
    let rate = |row: &Vec<String>| row[0].parse::<f64>().unwrap();
    assert!(runs.iter().filter(|r| r[1] == "reference").all(|r| rate(r) == 200.0), "{runs:?}");
    let moved: Vec<f64> = runs.iter().filter(|r| r[1] != "reference").map(rate).collect();
    assert!(moved.iter().all(|r| (100.0..=1000.0).contains(r)) && moved.iter().any(|&r| r != 200.0), "{runs:?}");
    // Pouring faster ends sooner: the fastest candidate costs less than the reference.
    let candidates = cells(&out.join("tune_pour_candidates.csv"), &["origin", "placement.pour.rate", "cost_ratio"]);
    let fastest = candidates.iter().max_by(|a, b| a[1].parse::<f64>().unwrap().total_cmp(&b[1].parse().unwrap()));
    let fastest = fastest.unwrap();
    assert!(fastest[1].parse::<f64>().unwrap() > 200.0, "{candidates:?}");
    assert!(fastest[2].parse::<f64>().unwrap() < 1.0, "{candidates:?}");
}
