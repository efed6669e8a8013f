//! What the commands write, as a careless or unlucky user meets it: shards of an edited study are not
//! merged into one result, a trailing slash does not lead through a link, a user's own files at an
//! output path are kept, a full disk leaves no file cut short under its final name, a refused
//! `--resume` changes nothing, and a shard cut short is named and merged as missing.

mod runner_common;

use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// An 8-run study named `s` (30 disks, 0.2 s each), with `run.duration` as given.
fn study(dir: &Path, duration: &str) -> PathBuf {
    let text = runner_common::cli_study("s")
        .replace("replicates = 20", "replicates = 2")
        .replace("run.duration = 0.2", &format!("run.duration = {duration}"));
    let path = dir.join("s.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn demsweep(args: &[&str]) -> Output {
    demsweep_with(args, |_| {})
}

/// `demsweep` with `args`, its command adjusted by `adjust` first (environment, limits).
fn demsweep_with(args: &[&str], adjust: impl FnOnce(&mut Command)) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_demsweep"));
    command.args(args);
    adjust(&mut command);
    let out = command.output().unwrap();
    assert_ne!(out.status.code(), Some(101), "no panic: {}", stderr(&out));
    out
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `run STUDY --out OUT` with `extra`, quiet.
fn run(study: &Path, out: &Path, extra: &[&str]) -> Output {
    demsweep(&[&["run", path(study), "--out", path(out), "--progress", "quiet"], extra].concat())
}

#[test]
fn shards_of_an_edited_study_are_refused_naming_both_files_and_the_change() {
    let dir = runner_common::scratch("safety_edited_shards");
    let shards = dir.join("shards");
    let mut study_file = study(&dir, "0.2");
    for k in ["1/3", "2/3"] {
        assert!(run(&study_file, &shards, &["--shard", k]).status.success());
    }
    study_file = study(&dir, "0.15");
    assert!(run(&study_file, &shards, &["--shard", "3/3", "--resume"]).status.success());
    let merged = demsweep(&["merge", path(&dir.join("m")), path(&shards), "--force"]);
    let message = stderr(&merged);
    assert_eq!(merged.status.code(), Some(1), "{message}");
    assert!(message.contains("s.shard-1-of-3.h5") && message.contains("s.shard-3-of-3.h5"), "{message}");
    assert!(message.contains("`run.duration = 0.2` and `run.duration = 0.15`"), "{message}");
    assert!(!dir.join("m").join("s.h5").exists(), "nothing merged");
}

#[test]
fn a_trailing_slash_does_not_lead_through_a_link() {
    let dir = runner_common::scratch("safety_slash");
    let results = dir.join("out").join("s.h5");
    assert!(run(&study(&dir, "0.2"), &dir.join("out"), &[]).status.success());
    let target = dir.join("target");
    assert!(demsweep(&["export", path(&results), "--format", "csv", "--out", path(&target)]).status.success());
    std::fs::write(target.join("notes.txt"), "mine").unwrap();
    let files = std::fs::read_dir(&target).unwrap().count();
    let link = dir.join("elink");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    for out in [format!("{}/", path(&link)), format!("{}/.", path(&link)), format!("{}//", path(&link))] {
        let refused = demsweep(&["export", path(&results), "--format", "csv", "--out", &out, "--force"]);
        assert_eq!(refused.status.code(), Some(1), "{out}");
        assert!(stderr(&refused).contains("is a symbolic link"), "{out}: {}", stderr(&refused));
        let report = demsweep(&["report", path(&results), "--out", &out]);
        assert!(stderr(&report).contains("is a symbolic link"), "{out}: {}", stderr(&report));
    }
    assert_eq!(std::fs::read_dir(&target).unwrap().count(), files, "the folder behind the link is whole");
    assert_eq!(std::fs::read_to_string(target.join("notes.txt")).unwrap(), "mine");
}

#[test]
fn files_demsweep_did_not_make_are_kept_unless_forced() {
    let dir = runner_common::scratch("safety_not_ours");
    let study_file = study(&dir, "0.2");
    let out = dir.join("d");
    std::fs::create_dir_all(&out).unwrap();
    let mine = ["s_summary.csv", "s_points.csv", "s_report.html"].map(|name| out.join(name));
    for file in &mine {
        std::fs::write(file, "my own notes\n").unwrap();
    }
    let refused = run(&study_file, &out, &[]);
    assert_eq!(refused.status.code(), Some(1), "{}", stderr(&refused));
    assert!(stderr(&refused).contains("s_summary.csv: refused: exists and was not written by demsweep"));
    assert!(!out.join("s.h5").exists(), "refused before any run");
    for file in &mine {
        assert_eq!(std::fs::read_to_string(file).unwrap(), "my own notes\n", "{}", file.display());
    }
    assert!(run(&study_file, &out, &["--force"]).status.success(), "--force replaces them");
    assert!(run(&study_file, &out, &["--resume"]).status.success(), "its own files are replaced");
    let results = out.join("s.h5");

    let before = std::fs::read(&study_file).unwrap();
    let report = demsweep(&["report", path(&results), "--out", path(&study_file)]);
    assert_eq!(report.status.code(), Some(1));
    assert!(stderr(&report).contains("was not written by demsweep"), "{}", stderr(&report));
    assert_eq!(std::fs::read(&study_file).unwrap(), before, "the study file is kept");
    let page = dir.join("page.html");
    for _ in 0..2 {
        assert!(demsweep(&["report", path(&results), "--out", path(&page)]).status.success(), "its own page");
    }

    let charts = dir.join("charts");
    std::fs::create_dir_all(&charts).unwrap();
    std::fs::write(charts.join("settle_time.png"), "my own chart").unwrap();
    let plot = |extra: &[&str]| demsweep(&[&["plot", path(&results), "--out", path(&charts)], extra].concat());
    assert_eq!(plot(&[]).status.code(), Some(1));
    assert_eq!(std::fs::read_to_string(charts.join("settle_time.png")).unwrap(), "my own chart");
    assert!(plot(&["--force"]).status.success());
    assert!(plot(&["--format", "both"]).status.success(), "its own charts are replaced");

    // `/` and home folders take no charts (HOME stands in for both here: nothing is written to `/`).
    let home = dir.join("home");
    std::fs::create_dir_all(&home).unwrap();
    let plotted = demsweep_with(&["plot", path(&results), "--out", path(&home), "--format", "svg"], |c| {
        c.env("HOME", &home);
    });
    assert_eq!(plotted.status.code(), Some(1));
    assert!(stderr(&plotted).contains("refused: is a home folder"), "{}", stderr(&plotted));
    assert_eq!(std::fs::read_dir(&home).unwrap().count(), 0);
}

/// Limits the files the command writes to `bytes` (a disk that fills up), as `ulimit -f` does.
fn file_size_limit(command: &mut Command, bytes: u64) {
    // SAFETY: only async-signal-safe calls between fork and exec.
    unsafe {
        command.pre_exec(move || {
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            let limit = libc::rlimit { rlim_cur: bytes, rlim_max: bytes };
            match libc::setrlimit(libc::RLIMIT_FSIZE, &limit) {
                0 => Ok(()),
                _ => Err(std::io::Error::last_os_error()),
            }
        });
    }
}

#[test]
fn a_full_disk_leaves_no_file_cut_short_and_fails_the_command() {
    let dir = runner_common::scratch("safety_full");
    let study_file = study(&dir, "0.2");
    let out = dir.join("out");
    assert!(run(&study_file, &out, &[]).status.success());
    let results = out.join("s.h5");
    let page = out.join("s_report.html");
    let (results_size, page_size) =
        (std::fs::metadata(&results).unwrap().len(), std::fs::metadata(&page).unwrap().len());
    assert!(results_size * 2 < page_size, "the page ({page_size} B) is larger than the results ({results_size} B)");
    let limit = (results_size + page_size) / 2;

    let full = dir.join("full");
    let ran = demsweep_with(&["run", path(&study_file), "--out", path(&full), "--progress", "quiet"], |c| {
        file_size_limit(c, limit)
    });
    assert_eq!(ran.status.code(), Some(1), "{}", stderr(&ran));
    assert!(stderr(&ran).contains("s_report.html: cannot write"), "{}", stderr(&ran));
    assert!(full.join("s.h5").exists() && full.join("s_summary.csv").exists(), "the results are kept");
    let left: Vec<_> = std::fs::read_dir(&full).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert!(!left.iter().any(|n| n.to_string_lossy().contains("report")), "no page cut short: {left:?}");

    let copy = dir.join("copy.html");
    let report = demsweep_with(&["report", path(&results), "--out", path(&copy)], |c| file_size_limit(c, limit / 4));
    assert_eq!(report.status.code(), Some(1));
    assert!(stderr(&report).contains("copy.html: cannot write"), "{}", stderr(&report));
    assert!(!copy.exists());
    std::fs::write(&copy, std::fs::read(&page).unwrap()).unwrap();
    let again = demsweep_with(&["report", path(&results), "--out", path(&copy)], |c| file_size_limit(c, limit / 4));
    assert_eq!(again.status.code(), Some(1));
    assert_eq!(std::fs::metadata(&copy).unwrap().len(), page_size, "the earlier page stays whole");
}

#[test]
fn a_refused_resume_of_an_edited_study_leaves_the_file_as_it_was() {
    let dir = runner_common::scratch("safety_refused_resume");
    let out = dir.join("out");
    assert!(run(&study(&dir, "0.2"), &out, &[]).status.success());
    let results = out.join("s.h5");
    runner_common::made_by(&results, "0.0.9");
    let before = std::fs::read(&results).unwrap();
    let grown = std::fs::read_to_string(dir.join("s.toml")).unwrap().replace("replicates = 2", "replicates = 3");
    std::fs::write(dir.join("s.toml"), grown).unwrap();
    let refused = run(&dir.join("s.toml"), &out, &["--resume"]);
    assert_eq!(refused.status.code(), Some(1));
    assert!(stderr(&refused).contains("was made by demsweep 0.0.9"), "{}", stderr(&refused));
    assert!(std::fs::read(&results).unwrap() == before, "header and runs unchanged");
}

#[test]
fn a_shard_cut_short_is_merged_as_missing_and_its_rerun_says_how() {
    let dir = runner_common::scratch("safety_cut_shard");
    let study_file = study(&dir, "0.2");
    let shards = dir.join("shards");
    for k in ["1/3", "2/3", "3/3"] {
        assert!(run(&study_file, &shards, &["--shard", k]).status.success());
    }
    let cut = shards.join("s.shard-2-of-3.h5");
    let bytes = std::fs::read(&cut).unwrap();
    std::fs::write(&cut, &bytes[..bytes.len() / 3]).unwrap();
    let merged = demsweep(&["merge", path(&dir.join("m")), path(&shards)]);
    let message = stderr(&merged);
    assert_eq!(merged.status.code(), Some(1), "{message}");
    assert!(String::from_utf8_lossy(&merged.stdout).starts_with("merged 5 of 8 runs from 2 of 3 shards"));
    assert!(message.contains(&format!("shard 2/3 ({}): cannot be read (", cut.display())), "{message}");
    let resumed = run(&study_file, &shards, &["--shard", "2/3", "--resume"]);
    assert_eq!(resumed.status.code(), Some(1));
    assert!(stderr(&resumed).contains("cut short or is damaged; run it again from the start with --force"));
    assert!(run(&study_file, &shards, &["--shard", "2/3", "--force"]).status.success());
    assert!(demsweep(&["merge", path(&dir.join("m")), path(&shards), "--force"]).status.success());
}

/// A user's CSV with CRLF line ends, which a spreadsheet writes.
const USER_CSV: &str = "sample,comment\r\nA1,looks fine\r\n";

#[test]
fn a_users_crlf_csv_is_kept() {
    let dir = runner_common::scratch("safety_crlf_csv");
    let study_file = study(&dir, "0.2");
    let out = dir.join("d");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("s_summary.csv"), USER_CSV).unwrap();
    let refused = run(&study_file, &out, &[]);
    assert_eq!(refused.status.code(), Some(1), "{}", stderr(&refused));
    assert!(stderr(&refused).contains("s_summary.csv: refused: exists and was not written by demsweep"));
    assert!(!out.join("s.h5").exists(), "refused before any run");
    std::fs::remove_file(out.join("s_summary.csv")).unwrap();
    assert!(run(&study_file, &out, &[]).status.success());
    let results = out.join("s.h5");
    let mine = dir.join("mine.csv");
    for args in [
        vec!["summary", path(&results), "--csv", path(&mine)],
        vec!["compare", path(&results), "--reference", "r0000", "--csv", path(&mine)],
    ] {
        std::fs::write(&mine, USER_CSV).unwrap();
        let refused = demsweep(&args);
        assert_eq!(refused.status.code(), Some(1), "{args:?}: {}", stderr(&refused));
        assert!(stderr(&refused).contains("was not written by demsweep"), "{}", stderr(&refused));
        assert_eq!(std::fs::read_to_string(&mine).unwrap(), USER_CSV, "{args:?}");
        assert!(!dir.join("mine.csv-metadata.json").exists(), "{args:?}");
        assert!(demsweep(&[&args[..], &["--force"]].concat()).status.success(), "{args:?} --force");
        assert!(demsweep(&args).status.success(), "{args:?}: its own CSV is replaced");
        std::fs::remove_file(dir.join("mine.csv-metadata.json")).unwrap();
    }
}

#[test]
fn ownership_rests_on_a_binding_not_on_a_resemblance() {
    let dir = runner_common::scratch("safety_binding");
    let study_file = study(&dir, "0.2");
    let out = dir.join("d");
    assert!(run(&study_file, &out, &[]).status.success());
    let results = out.join("s.h5");
    let summary_csv = |args: &[&str]| demsweep(&[&["summary", path(&results)], args].concat());
    let refused = |output: Output, path: &Path| {
        assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
        assert!(stderr(&output).contains(&format!("{}: refused", path.display())), "{}", stderr(&output));
    };

    // A user's CSV saved over demsweep's, its sidecar still there: the sidecar no longer describes it.
    let mine = dir.join("mine.csv");
    assert!(summary_csv(&["--csv", path(&mine)]).status.success());
    std::fs::write(&mine, USER_CSV).unwrap();
    refused(summary_csv(&["--csv", path(&mine)]), &mine);
    assert_eq!(std::fs::read_to_string(&mine).unwrap(), USER_CSV);
    std::fs::write(out.join("s_summary.csv"), USER_CSV).unwrap();
    refused(run(&study_file, &out, &["--resume"]), &out.join("s_summary.csv"));
    assert_eq!(std::fs::read_to_string(out.join("s_summary.csv")).unwrap(), USER_CSV);

    // A user's own file at a sidecar path.
    let other = dir.join("other.csv");
    let sidecar = dir.join("other.csv-metadata.json");
    std::fs::write(&sidecar, "{\"my\": \"notes\"}\n").unwrap();
    refused(summary_csv(&["--csv", path(&other)]), &sidecar);
    assert_eq!(std::fs::read_to_string(&sidecar).unwrap(), "{\"my\": \"notes\"}\n");
    assert!(!other.exists(), "the table is not written without its sidecar");

    // A user's page that quotes the generator tag in its body.
    let notes = dir.join("notes.html");
    let page = format!(
        "<!DOCTYPE html><html><head><title>notes</title></head><body><p>demsweep marks its pages with <code>{}</code></p></body></html>\n",
        demsweep::output::guard::HTML_MARK
    );
    std::fs::write(&notes, &page).unwrap();
    refused(demsweep(&["report", path(&results), "--out", path(&notes)]), &notes);
    assert_eq!(std::fs::read_to_string(&notes).unwrap(), page);
}
