//! Study files a careless or hostile user might write: settle thresholds at the ends of the f64
//! range (charts with degenerate log axes), named pipes and other files' secrets as placement files,
//! and control characters that would drive the terminal. Each ends in a result or a clear error,
//! within a bounded time, with nothing leaked.

mod runner_common;

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Far more than any of these commands takes; past it the command hangs.
const HANG: Duration = Duration::from_secs(120);

/// Ten disks in a small box, with `extra` appended (a few milliseconds of computing per run).
fn study(name: &str, extra: &str) -> String {
    format!(
        "name = \"{name}\"\n[scene.domain]\nwidth = 0.05\nheight = 0.05\n[scene.particles]\ncount = 10\n\
         radius = 0.004\n[scene.run]\nduration = 0.05\n{extra}"
    )
}

/// Runs `demsweep args` in `dir` (with `env` set) and waits at most [`HANG`]; a command still
/// running then is killed and the test fails.
fn demsweep(dir: &Path, args: &[&str], env: (&str, &str)) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(args)
        .current_dir(dir)
        .env(env.0, env.1)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > HANG {
            child.kill().unwrap();
            child.wait().unwrap();
            panic!("`demsweep {}` hangs", args.join(" "));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    assert_ne!(out.status.code(), Some(101), "{args:?} panicked: {}", text(&out.stderr));
    out
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

const NO_ENV: (&str, &str) = ("DEMSWEEP_TEST", "1");

#[test]
fn settle_thresholds_at_the_ends_of_the_range_are_charted() {
    let dir = runner_common::scratch("hostile_ubf_threshold");
    for (name, threshold) in [("huge", "1e308"), ("subnormal", "5e-324")] {
        let file = format!("{name}.toml");
        std::fs::write(dir.join(&file), study(name, &format!("[scene.settle]\nubf_threshold = {threshold}\n")))
            .unwrap();
        let run = demsweep(&dir, &["run", &file, "--out", name, "--progress", "quiet"], NO_ENV);
        assert_eq!(run.status.code(), Some(0), "{name}: {}", text(&run.stderr));
        let results = format!("{name}/{name}.h5");
        let page = format!("{name}/again.html");
        let report = demsweep(&dir, &["report", &results, "--out", &page], NO_ENV);
        assert_eq!(report.status.code(), Some(0), "{name}: {}", text(&report.stderr));
        assert!(std::fs::read_to_string(dir.join(&page)).unwrap().contains("<svg"), "{name}: charts in the page");
        let plot = demsweep(&dir, &["plot", &results, "--out", &format!("{name}/charts")], NO_ENV);
        assert_eq!(plot.status.code(), Some(0), "{name}: {}", text(&plot.stderr));
        assert!(dir.join(format!("{name}/charts/r0000_ubf.png")).is_file(), "{name}: the UBF chart");
    }
}

#[test]
fn a_named_pipe_as_a_placement_or_contact_file_is_refused() {
    let dir = runner_common::scratch("hostile_fifo");
    let fifo = dir.join("disks.csv");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    std::fs::write(dir.join("disks_ok.csv"), "x,y\n0.01,0.01\n0.03,0.01\n").unwrap();
    for (name, placement) in [
        ("file", "kind = \"file\"\nfile = \"disks.csv\"\n"),
        ("contacts", "kind = \"file\"\nfile = \"disks_ok.csv\"\ncontacts = \"disks.csv\"\n"),
    ] {
        let file = format!("{name}.toml");
        std::fs::write(dir.join(&file), study(name, &format!("[scene.placement]\n{placement}"))).unwrap();
        let check = demsweep(&dir, &["check", &file], NO_ENV);
        let stderr = text(&check.stderr);
        assert_eq!(check.status.code(), Some(2), "{name}: {stderr}");
        assert!(stderr.contains("disks.csv: cannot read: not a regular file (a named pipe)"), "{name}: {stderr}");
        assert!(stderr.contains(&format!("scene.placement.{name}")), "{name}: {stderr}");
    }
}

#[test]
fn errors_quote_no_file_outside_the_study_folder() {
    let dir = runner_common::scratch("hostile_leak");
    let elsewhere = runner_common::scratch("hostile_leak_elsewhere").join("secret.txt");
    std::fs::write(&elsewhere, "SECRET-TOKEN:hunter2\n").unwrap();
    std::os::unix::fs::symlink(&elsewhere, dir.join("link.csv")).unwrap();
    std::fs::write(dir.join("mine.csv"), "x,radius\n0.01,0.01\n").unwrap();
    let secret_env = ("DEMSWEEP_SECRET", "ENV-SECRET-VALUE");
    let cases = [
        ("absolute", elsewhere.to_str().unwrap(), "line 1, column 1: unknown column name"),
        ("linked", "link.csv", "line 1, column 1: unknown column name"),
        ("environ", "/proc/self/environ", "line 1, column 1: unknown column name"),
        ("own", "mine.csv", "line 1, column 2: unknown column \"radius\""),
    ];
    for (name, placement, said) in cases {
        let file = format!("{name}.toml");
        let text_of = study(name, &format!("[scene.placement]\nkind = \"file\"\nfile = \"{placement}\"\n"));
        std::fs::write(dir.join(&file), text_of).unwrap();
        let check = demsweep(&dir, &["check", &file], secret_env);
        let stderr = text(&check.stderr);
        assert_eq!(check.status.code(), Some(2), "{name}: {stderr}");
        assert!(stderr.contains(said), "{name}: {stderr}");
        assert!(!stderr.contains("SECRET") && !stderr.contains("hunter2"), "{name} leaks: {stderr}");
    }
}

#[test]
fn control_characters_from_inputs_reach_the_terminal_escaped() {
    let dir = runner_common::scratch("hostile_control");
    std::fs::write(dir.join("disks.csv"), "x,y,\u{1b}[2J\n0.01,0.01,1\n").unwrap();
    let key = "[scene.material]\n\"\\u001b]0;retitled\\u0007\\u0000\" = 1\n";
    std::fs::write(dir.join("key.toml"), study("key", key)).unwrap();
    let placement = "[scene.placement]\nkind = \"file\"\nfile = \"disks.csv\"\n";
    std::fs::write(dir.join("cell.toml"), study("cell", placement)).unwrap();
    for (file, escaped) in [("key.toml", "\\u{1b}]0;retitled\\u{7}\\u{0}"), ("cell.toml", "\"\\u{1b}[2J\"")] {
        let check = demsweep(&dir, &["check", file], NO_ENV);
        let stderr = text(&check.stderr);
        assert_eq!(check.status.code(), Some(2), "{file}: {stderr}");
        assert!(stderr.contains(escaped), "{file}: {stderr}");
        let raw = check.stderr.iter().chain(&check.stdout).any(|b| b.is_ascii_control() && !b"\n\t".contains(b));
        assert!(!raw, "{file}: raw control bytes reach the terminal: {stderr:?}");
    }
}
