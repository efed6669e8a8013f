//! The HTML report as a person sees it: `demsweep run` writes it, and headless Chromium (Debian's
//! `chromium`, driven by Playwright; `scripts/test.sh` installs both) opens it. It loads with no console
//! error and no network request, its table has one row per grid point, a click on a header sorts
//! the rows, every chart has a size, and a run's section is reachable from its row.

use std::path::{Path, PathBuf};
mod python_env;

use std::process::Command;

use serde_json::Value;

/// 3 restitution values x 3 seeds of 25 disks.
const STUDY: &str = r#"name = "report_study"
description = "restitution with replicates, for the report test"
[scene]
particles.count = 25
domain.width = 0.16
domain.height = 0.2
run.duration = 0.3
[sweep]
"material.restitution" = [0.2, 0.5, 0.8]
replicates = 3
[output]
frames = false
"#;

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// What the browser saw (see tests/report/check_report.py).
fn open_in_browser(report: &Path) -> Value {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/report/check_report.py");
    let out = python_env::python(script).arg(report).output().expect("run the tests' Python");
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "browser check failed (scripts/test.sh installs chromium and playwright):\n{text}");
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{e}: {text}"))
}

#[test]
fn the_report_opens_sorts_and_links_in_a_real_browser() {
    let dir = scratch("report_browser");
    let study = dir.join("report_study.toml");
    std::fs::write(&study, STUDY).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(["run", study.to_str().unwrap(), "--out", dir.to_str().unwrap(), "--progress", "quiet"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    let report = dir.join("report_study_report.html");
    assert!(stdout.contains(&format!("report: {}", report.display())), "{stdout}");
    let html = std::fs::read_to_string(&report).unwrap();
    // Only SVG namespace names look like addresses; nothing is fetched from anywhere.
    let names =
        html.replace("xmlns=\"http://www.w3.org/2000/svg\"", "").replace("\"http://www.w3.org/1999/xlink\"", "");
    assert!(!names.contains("http://") && !names.contains("https://"), "no address in the page");

    let seen = open_in_browser(&report);
    println!("{seen}");
    assert_eq!(seen["console_errors"], Value::Array(Vec::new()), "{seen}");
    assert_eq!(seen["requests"], Value::Array(Vec::new()), "no network request: {seen}");
    assert_eq!((&seen["rows"], &seen["rows_in_page"]), (&Value::from(3), &Value::from(3)), "one row per grid point");
    assert_eq!(seen["sorted_column"], "material.restitution");
    assert_eq!((seen["sorted_ascending"].as_bool(), seen["sorted_descending"].as_bool()), (Some(true), Some(true)));
    assert_eq!(seen["charts"], 1 + 9 * 3, "the settle-time chart and 3 charts per run: {seen}");
    assert_eq!(seen["charts_without_size"], 0);
    assert_eq!(seen["bottom_reached"], true);
    assert_eq!(seen["run_links"], 3, "each point links to a run section");
    assert_eq!(seen["run_links_reached"], 3);
}

#[test]
fn the_report_command_rewrites_a_report_anywhere() {
    let dir = scratch("report_command");
    let study = dir.join("report_study.toml");
    std::fs::write(&study, STUDY.replace("replicates = 3", "replicates = 1")).unwrap();
    let run = Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(["run", study.to_str().unwrap(), "--out", dir.to_str().unwrap(), "--progress", "quiet"])
        .output()
        .unwrap();
    assert!(run.status.success());
    let page = dir.join("elsewhere.html");
    let out = Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(["report", dir.join("report_study.h5").to_str().unwrap(), "--out", page.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(html.contains("restitution with replicates, for the report test"), "the study's description");
    assert!(html.contains("<dt>cores</dt>") && html.contains("<dt>wall time</dt>"), "how the sweep ran, from the file");
    assert_eq!(html.matches("<section id=\"run-").count(), 3, "a section per run of a small study");
    let missing = Command::new(env!("CARGO_BIN_EXE_demsweep")).args(["report", "/nonexistent.h5"]).output().unwrap();
    assert!(!missing.status.success());
    assert!(String::from_utf8_lossy(&missing.stderr).contains("/nonexistent.h5"), "the error names the file");
}
