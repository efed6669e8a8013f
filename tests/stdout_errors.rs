//! Every command (as `demsweep --help` lists them, so that a new one is covered) with its standard
//! output on a full disk (`/dev/full`) and on a pipe whose reader has gone (`| head` ended): no
//! panic, no signal; a full disk fails the command with an error naming standard output, a closed
//! pipe changes nothing but the output; and a sweep records every run either way.

mod runner_common;
mod tune_common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// A two-run study of ten disks (a few milliseconds of computing).
const STUDY: &str = r#"name = "tiny"
[scene]
particles.count = 10
particles.radius = 0.004
domain.width = 0.05
domain.height = 0.05
run.duration = 0.05
[sweep]
"material.restitution" = [0.3, 0.6]
"#;

/// Where standard output goes.
#[derive(Clone, Copy, Debug)]
enum Sink {
    Captured,
    FullDisk,
    ClosedPipe,
}

fn demsweep(dir: &Path, args: &[String], sink: Sink) -> Output {
    let stdout = match sink {
        Sink::Captured => Stdio::piped(),
        Sink::FullDisk => std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap().into(),
        Sink::ClosedPipe => {
            let (reader, writer) = std::io::pipe().unwrap();
            drop(reader);
            writer.into()
        }
    };
    let mut command = Command::new(env!("CARGO_BIN_EXE_demsweep"));
    command.args(args).current_dir(dir).stdout(stdout).stderr(Stdio::piped());
    command.output().unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The commands `demsweep --help` lists.
fn commands(dir: &Path) -> Vec<String> {
    let help = text(&demsweep(dir, &["--help".into()], Sink::Captured).stdout);
    let listed = help.split("Commands:\n").nth(1).expect("a command list").split("\n\n").next().unwrap();
    listed.lines().filter_map(|line| line.split_whitespace().next()).map(str::to_string).collect()
}

/// Arguments that make `command` succeed and print, writing under `fresh` (a new folder per call).
fn arguments(command: &str, fresh: &Path) -> Option<Vec<String>> {
    let fresh = fresh.to_str().unwrap();
    let words: &[&str] = match command {
        "plan" | "check" => &["tiny.toml"],
        "run" => &["tiny.toml", "--progress", "lines", "--jobs", "1", "--out", fresh],
        "summary" => &["results/tiny.h5"],
        "compare" => &["results/tiny.h5", "--reference", "r0000"],
        "history" => &["results/tiny.h5", "r0000"],
        "merge" => &[fresh, "results/tiny.h5"],
        "export" => &["results/tiny.h5", "--format", "csv", "--out", fresh],
        "plot" => &["results/tiny.h5", "--run", "r0000", "--out", fresh],
        "report" => &["results/tiny.h5", "--out", &format!("{fresh}.html")],
        "keys" | "help" => &[],
        "bench" => &["stress", "--out", fresh],
        "slurm" => &["tiny.toml", "--shards", "2", "--print", "--demsweep", "/usr/bin/true", "--out", fresh],
        "tune" => &["tiny_tune.toml", "--jobs", "2", "--out", fresh],
        _ => return None,
    };
    let mut args = vec![command.to_string()];
    args.extend(words.iter().map(|w| w.to_string()));
    Some(args)
}

/// Asserts how `args` ended on `sink`; for `run`, that every run was recorded under `fresh`.
fn check(dir: &Path, args: &[String], sink: Sink, fresh: &Path) {
    let out = demsweep(dir, args, sink);
    let stderr = text(&out.stderr);
    let said = format!("{args:?} with stdout on {sink:?}: {:?}\n{stderr}", out.status);
    assert!(!stderr.contains("panicked"), "{said}");
    match sink {
        Sink::FullDisk => {
            assert_eq!(out.status.code(), Some(1), "{said}");
            assert!(stderr.contains("error: cannot write to standard output: No space left on device"), "{said}");
        }
        Sink::ClosedPipe | Sink::Captured => {
            assert_eq!(out.status.code(), Some(0), "{said}");
            assert!(!stderr.contains("standard output"), "{said}");
        }
    }
    if args[0] == "run" && args.len() > 2 {
        let runs = demsweep::output::summary::read(&fresh.join("tiny.h5")).map(|t| t.len());
        assert_eq!(runs, Ok(2), "{said}: progress output cost runs");
    }
}

#[test]
fn every_command_survives_a_full_disk_and_a_closed_pipe_on_stdout() {
    let dir = runner_common::scratch("stdout_errors");
    std::fs::write(dir.join("tiny.toml"), STUDY).unwrap();
    std::fs::write(dir.join("tiny_tune.toml"), tune_common::TUNE).unwrap();
    let setup: Vec<String> = ["run", "tiny.toml", "--out", "results", "--progress", "quiet"].map(String::from).into();
    assert_eq!(demsweep(&dir, &setup, Sink::Captured).status.code(), Some(0));
    let listed = commands(&dir);
    assert!(listed.len() >= 14 && listed.contains(&"run".to_string()), "{listed:?}");
    let mut count = 0;
    let mut fresh = || -> PathBuf {
        count += 1;
        dir.join(format!("out{count}"))
    };
    for command in &listed {
        for sink in [Sink::FullDisk, Sink::ClosedPipe] {
            let out = fresh();
            let args = arguments(command, &out)
                .unwrap_or_else(|| panic!("`{command}` is new: give it arguments in `arguments` above"));
            check(&dir, &args, sink, &out);
            let help = if command == "help" { "run" } else { "--help" };
            check(&dir, &[command.clone(), help.into()], sink, &out);
        }
    }
    for sink in [Sink::FullDisk, Sink::ClosedPipe] {
        check(&dir, &["--version".into()], sink, &dir);
    }
}
