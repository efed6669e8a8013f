//! Results files that lie: a `/summary` column shorter than the others, contacts joining disks the
//! state does not have, a run id that is no file name. Every command ends with a clear error, or a
//! result with a warning (exit 3), never a panic (101) or a signal, and writes nothing outside its
//! output.

mod runner_common;

use std::path::{Path, PathBuf};
use std::process::Output;

use demsweep::output::{ResultSink, ResultsWriter, RunResult, reader, stored};
use demsweep::physics::run_scene;
use demsweep::runner;
use demsweep::study::OutputOptions;
use demsweep::{Control, physics::contact_network::ContactNetwork};

/// A 4-run results file in `<scratch>/out/lies.h5`, written by the runner.
fn results(test: &str) -> (PathBuf, demsweep::study::Plan) {
    let dir = runner_common::scratch(test);
    let plan = runner_common::sweep("lies", 4);
    let report = runner::run_plan(&plan, &runner_common::options(&dir.join("out"), 1)).unwrap();
    (report.results, plan)
}

/// Adds a run to `results` as `lie` makes it from the first run (its row and a fresh record of its
/// scene), then writes `/summary` and `/points` as `tables` makes them from every row.
fn add_run(
    results: &Path,
    lie: impl FnOnce(&mut RunResult),
    tables: impl FnOnce(&[demsweep::output::SummaryRow]) -> demsweep::output::Tables,
) {
    let file = reader::open(results).unwrap();
    let mut rows = reader::rows(&file, results).unwrap();
    let scene = stored::read_run(&file, results, &rows[0]).unwrap().scene;
    drop(file);
    let record = run_scene(&scene, None, &mut |_| Control::Continue).unwrap();
    let mut row = rows[0].clone();
    // A run of its own, under an identity of its own (not that of the run it was copied from).
    (row.id, row.index, row.identity) = ("r900".into(), 900, "crafted-r900".into());
    let mut run = RunResult { row, scene, record: Some(record) };
    lie(&mut run);
    let options = OutputOptions { histories: true, final_states: true, frames: true };
    let (mut writer, _) = ResultsWriter::open(results, options).unwrap();
    writer.stage(&run).unwrap();
    writer.commit().unwrap();
    rows.push(run.row.clone());
    let tables = tables(&rows);
    writer.finish(&tables).unwrap();
    demsweep::output::write_csv_files(results, &tables).unwrap();
    keep_a_copy(results);
}

/// Copies the crafted file to `<target tmp>/crafted/<test folder>.h5`, where
/// `scripts/safety_counts.sh` finds it.
fn keep_a_copy(results: &Path) {
    let test = results.parent().and_then(Path::parent).and_then(Path::file_name).unwrap();
    let kept = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("crafted");
    std::fs::create_dir_all(&kept).unwrap();
    std::fs::copy(results, kept.join(test).with_extension("h5")).unwrap();
}

fn demsweep(cwd: &Path, args: &[&str]) -> Output {
    let out = runner_common::demsweep_in(cwd, args);
    let text = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        assert!(text.contains("lies.h5") || text.contains("error"), "{args:?}: a clear error, not: {text}");
    }
    out
}

/// Every reading command on `results` (run from its folder's parent); the names of what is left in
/// that parent after them (everything else went into the command's own output).
fn every_command(results: &Path) -> Vec<String> {
    let out = results.parent().unwrap();
    let work = out.parent().unwrap();
    for args in [
        &["summary", "out/lies.h5"][..],
        &["summary", "out/lies.h5", "--by-point"],
        &["report", "out/lies.h5"],
        &["plot", "out/lies.h5", "--all-runs", "--out", "plots"],
        &["export", "out/lies.h5", "--format", "vtk", "--out", "vtk"],
        &["export", "out/lies.h5", "--format", "csv", "--out", "csv"],
        &["compare", "out/lies.h5", "--reference", "r000"],
        &["history", "out/lies.h5", "r900"],
    ] {
        demsweep(work, args);
    }
    let mut names: Vec<String> =
        std::fs::read_dir(work).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

/// The runner's resume of `plan` into `results`' folder: an error or a report, never a panic.
fn resume(results: &Path, plan: &demsweep::study::Plan) -> Result<runner::RunReport, String> {
    let options = runner::RunOptions { resume: true, ..runner_common::options(results.parent().unwrap(), 1) };
    runner::run_plan(plan, &options).map_err(|e| e.to_string())
}

#[test]
fn a_summary_column_shorter_than_the_others_is_set_aside_and_the_file_repaired() {
    let (results, plan) = results("lie_short_column");
    add_run(
        &results,
        |_| {},
        |rows| {
            let mut tables = demsweep::stats::points::tables(rows);
            let column = tables.summary.columns.iter_mut().find(|c| c.name == "wall_time").unwrap();
            column.data = demsweep::output::table::ColumnData::Float(vec![0.1; rows.len() - 2]);
            tables
        },
    );
    assert_eq!(every_command(&results), ["csv", "out", "plots", "vtk"]);
    let summary = demsweep::output::summary::read(&results).unwrap();
    assert_eq!(summary.len(), 5, "rebuilt from the run groups");
    let report = resume(&results, &plan).unwrap();
    let rows = report.summary.len();
    assert_eq!(rows, plan.runs.len(), "the plan's runs (the crafted one is no run of the plan)");
    let file = reader::open(&results).unwrap();
    let stored = reader::stored_table(&file, &results, "summary").unwrap().expect("a /summary again");
    assert!(stored.columns.iter().all(|c| c.data.len() == rows), "--resume rewrote /summary whole");
}

#[test]
fn contacts_joining_disks_the_state_lacks_are_an_error_naming_the_run() {
    let (results, plan) = results("lie_contacts");
    add_run(
        &results,
        |run| {
            let state = &mut run.record.as_mut().unwrap().final_state;
            let mut contacts = ContactNetwork { first: vec![0, 10_000], second: vec![1, -2], ..Default::default() };
            for column in [&mut contacts.normal_x, &mut contacts.normal_y, &mut contacts.normal_force] {
                *column = vec![1.0, 1.0];
            }
            for column in [&mut contacts.tangential_force, &mut contacts.overlap, &mut contacts.point_x] {
                *column = vec![0.0, 0.0];
            }
            for column in [&mut contacts.point_y, &mut contacts.tangential_spring, &mut contacts.law_state] {
                *column = vec![0.0, 0.0];
            }
            contacts.sliding = vec![false, false];
            state.contacts = contacts;
        },
        demsweep::stats::points::tables,
    );
    every_command(&results);
    let work = results.parent().unwrap().parent().unwrap();
    let export = demsweep(work, &["export", "out/lies.h5", "--format", "vtk", "--run", "r900", "--out", "one"]);
    let text = String::from_utf8_lossy(&export.stderr);
    assert_eq!(export.status.code(), Some(1), "{text}");
    assert!(text.contains("r900") && text.contains("contact 1 joins body 10000"), "{text}");
    assert!(resume(&results, &plan).is_ok());
}

#[test]
fn a_run_id_that_is_no_file_name_is_refused_and_nothing_is_written_outside() {
    let (results, plan) = results("lie_id");
    add_run(&results, |run| run.row.id = "..".into(), demsweep::stats::points::tables);
    let names = every_command(&results);
    assert_eq!(names, ["csv", "out", "plots", "vtk"], "nothing written beside the output folders");
    let work = results.parent().unwrap().parent().unwrap();
    let summary = demsweep(work, &["summary", "out/lies.h5"]);
    let text = String::from_utf8_lossy(&summary.stderr);
    assert_eq!(summary.status.code(), Some(3), "{text}");
    assert!(text.contains("cannot name a file"), "{text}");
    assert!(resume(&results, &plan).is_ok());
}
