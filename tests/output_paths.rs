//! Output paths never destroy results: every command refuses, naming the path and the reason, an
//! output that is, holds or replaces one of its inputs, a results file, a folder demsweep did not
//! make, `/`, `.` or `..`, or a symbolic link, and a table over a file written beside the results file
//! it reads without `--force`; and the files there survive byte for byte.

mod runner_common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Output;

/// A 4-run study of 12 disks (a second or so).
const STUDY: &str = include_str!("data/paths.toml");

use runner_common::demsweep_in as demsweep;

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// `<scratch>/work/paths.toml` run into `<scratch>/work/results/`: (work folder, results folder).
fn results(test: &str) -> (PathBuf, PathBuf) {
    let work = runner_common::scratch(test).join("work");
    std::fs::create_dir_all(&work).unwrap();
    std::fs::write(work.join("paths.toml"), STUDY).unwrap();
    let out = demsweep(&work, &["run", "paths.toml", "--out", "results", "--progress", "quiet"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    (work.clone(), work.join("results"))
}

/// Every file under `dir` (recursively, links not followed) with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut files = BTreeMap::new();
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        let kind = entry.file_type().unwrap();
        if kind.is_dir() {
            files.extend(snapshot(&path));
        } else if kind.is_file() {
            files.insert(path.clone(), std::fs::read(&path).unwrap());
        }
    }
    files
}

/// Runs `args` in `cwd`, expecting a refusal (exit 1) whose text names `path` and contains `reason`,
/// and that every file under `guarded` is unchanged.
fn refused(cwd: &Path, guarded: &Path, args: &[&str], path: &str, reason: &str) {
    let before = snapshot(guarded);
    assert!(before.keys().any(|p| p.extension().is_some_and(|e| e == "h5")), "a results file to guard");
    let out = demsweep(cwd, args);
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {text}");
    assert!(text.contains(path) && text.contains(reason), "{args:?}: expected `{path}` and `{reason}` in: {text}");
    assert_eq!(snapshot(guarded), before, "{args:?} changed files");
}

#[test]
fn export_into_the_results_folder_with_force_is_refused() {
    let (work, results) = results("paths_dot");
    refused(&results, &work, &["export", "paths.h5", "--format", "csv", "--out", ".", "--force"], ".", "refused");
    refused(&results, &work, &["export", "paths.h5", "--format", "csv", "--out", "./", "--force"], ".", "refused");
}

#[test]
fn export_into_the_parent_folder_is_refused() {
    let (work, results) = results("paths_dotdot");
    refused(&results, &work, &["export", "paths.h5", "--format", "csv", "--out", "..", "--force"], "..", "refused");
}

#[test]
fn export_over_the_results_folder_with_force_is_refused() {
    let (work, _) = results("paths_folder");
    let args = ["export", "results/paths.h5", "--format", "csv", "--out", "results", "--force"];
    refused(&work, &work, &args, "results", "holds the input");
}

#[test]
fn export_over_the_root_folder_is_refused() {
    let (work, _) = results("paths_root");
    refused(&work, &work, &["export", "results/paths.h5", "--format", "csv", "--out", "/", "--force"], "/", "refused");
}

#[test]
fn export_force_replaces_only_a_folder_it_made() {
    let (work, _) = results("paths_marker");
    let mine = work.join("mine");
    std::fs::create_dir_all(&mine).unwrap();
    std::fs::write(mine.join("notes.txt"), "my notes").unwrap();
    let args = ["export", "results/paths.h5", "--format", "csv", "--out", "mine", "--force"];
    refused(&work, &work, &args, "mine", "not written by demsweep export");
    let export = ["export", "results/paths.h5", "--format", "csv", "--out", "piles"];
    assert_eq!(demsweep(&work, &export).status.code(), Some(0));
    assert!(work.join("piles/.demsweep-export").is_file());
    let again = demsweep(&work, &[&export[..], &["--force"]].concat());
    assert_eq!(again.status.code(), Some(0), "{}", stderr(&again));
}

#[test]
fn an_existing_partial_folder_it_did_not_make_is_kept() {
    let (work, _) = results("paths_partial");
    std::fs::create_dir_all(work.join("piles.partial")).unwrap();
    std::fs::write(work.join("piles.partial/data.txt"), "someone's").unwrap();
    let args = ["export", "results/paths.h5", "--format", "csv", "--out", "piles"];
    refused(&work, &work, &args, "piles.partial", "not written by demsweep export");
}

#[test]
fn summary_csv_over_the_results_file_is_refused() {
    let (work, results) = results("paths_summary");
    refused(&results, &work, &["summary", "paths.h5", "--csv", "paths.h5"], "paths.h5", "is a results file");
}

#[test]
fn a_table_over_a_file_written_beside_the_results_file_is_refused_without_force() {
    let (work, results) = results("paths_companion");
    let beside = "written beside the results file";
    let by_point = ["summary", "paths.h5", "--by-point", "--csv", "paths_summary.csv"];
    refused(&results, &work, &by_point, "paths_summary.csv", beside);
    let args = ["compare", "paths.h5", "--reference", "r0000", "--csv", "paths_points.csv"];
    refused(&results, &work, &args, "paths_points.csv", beside);
    let args = ["history", "paths.h5", "r0000", "--csv", "paths_summary.csv-metadata.json"];
    refused(&results, &work, &args, "paths_summary.csv-metadata.json", beside);
    let forced = demsweep(&results, &[&by_point[..], &["--force"]].concat());
    assert_eq!(forced.status.code(), Some(0), "{}", stderr(&forced));
    let table = std::fs::read_to_string(results.join("paths_summary.csv")).unwrap();
    assert!(table.lines().next().is_some_and(|names| names.contains("settle_time_mean")), "{table}");
}

#[test]
fn report_over_the_results_file_is_refused() {
    let (work, results) = results("paths_report");
    refused(&results, &work, &["report", "paths.h5", "--out", "paths.h5"], "paths.h5", "refused");
}

#[test]
fn compare_csv_over_the_results_file_is_refused() {
    let (work, results) = results("paths_compare");
    let args = ["compare", "paths.h5", "--reference", "r0000", "--csv", "paths.h5"];
    refused(&results, &work, &args, "paths.h5", "is a results file");
}

#[test]
fn a_symlinked_lock_file_is_not_followed() {
    let (work, results) = results("paths_lock");
    std::fs::write(work.join("precious.txt"), "precious").unwrap();
    assert!(!results.join("paths.h5.lock").exists(), "a finished run leaves no lock file");
    std::os::unix::fs::symlink(work.join("precious.txt"), results.join("paths.h5.lock")).unwrap();
    let args = ["run", "paths.toml", "--out", "results", "--force", "--progress", "quiet"];
    refused(&work, &work, &args, "paths.h5.lock", "symbolic link");
}

#[test]
fn a_symlinked_summary_csv_is_not_followed() {
    let (work, results) = results("paths_csv_link");
    std::fs::write(work.join("precious.txt"), "precious").unwrap();
    std::fs::remove_file(results.join("paths_summary.csv")).unwrap();
    std::os::unix::fs::symlink(work.join("precious.txt"), results.join("paths_summary.csv")).unwrap();
    let args = ["run", "paths.toml", "--out", "results", "--force", "--progress", "quiet"];
    refused(&work, &work, &args, "paths_summary.csv", "symbolic link");
}

#[test]
fn run_force_replaces_only_a_results_file() {
    let (work, results) = results("paths_run_force");
    std::fs::remove_file(results.join("paths.h5")).unwrap();
    std::fs::write(results.join("paths.h5"), "not a results file").unwrap();
    let args = ["run", "paths.toml", "--out", "results", "--force", "--progress", "quiet"];
    let before = snapshot(&work);
    let out = demsweep(&work, &args);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("paths.h5") && stderr(&out).contains("not one"), "{}", stderr(&out));
    assert_eq!(snapshot(&work), before);
}

#[test]
fn a_folder_or_link_at_a_sidecar_path_is_refused_before_running() {
    let (work, results) = results("paths_sidecar");
    std::fs::write(work.join("precious.txt"), "precious").unwrap();
    let sidecar = results.join("paths_summary.csv-metadata.json");
    std::fs::remove_file(&sidecar).unwrap();
    std::fs::create_dir(&sidecar).unwrap();
    let args = ["run", "paths.toml", "--out", "results", "--force", "--progress", "quiet"];
    refused(&work, &work, &args, "paths_summary.csv-metadata.json", "is not a file");
    std::fs::remove_dir(&sidecar).unwrap();
    std::os::unix::fs::symlink(work.join("precious.txt"), &sidecar).unwrap();
    refused(&work, &work, &args, "paths_summary.csv-metadata.json", "symbolic link");
    let csv = ["summary", "results/paths.h5", "--csv", "results/paths_summary.csv", "--force"];
    refused(&work, &work, &csv, "paths_summary.csv-metadata.json", "symbolic link");
}
