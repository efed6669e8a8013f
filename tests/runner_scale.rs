//! Costs that must not grow faster than the number of runs, checked by counted quantities (never
//! wall time): a commit onto a file of 4N runs reads no more than onto one of N; reading a finished
//! file reads no run group's attribute set; and `demsweep … | head` ends quietly.

mod runner_common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use demsweep::output::{ResultsWriter, RunResult, SummaryRow, SummaryTable, reader};
use demsweep::physics::SceneConfig;
use demsweep::study::OutputOptions;

/// `runs` runs of one disk for 20 steps (well under a millisecond each), with no validity warning.
fn tiny_study(dir: &Path, runs: usize) -> PathBuf {
    let path = dir.join("scale.toml");
    let text = format!(
        "name = \"scale\"\n[scene]\nparticles.count = 1\nrun.duration = 1e-3\nintegrator.time_step = 5e-5\n\
         [sweep]\n\"material.friction\" = {{ linear = [0.0, 1.0], steps = {runs} }}\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

fn demsweep() -> Command {
    Command::new(env!("CARGO_BIN_EXE_demsweep"))
}

/// A results file of `runs` tiny runs, written by `demsweep run`.
fn results(test: &str, runs: usize) -> PathBuf {
    let dir = runner_common::scratch(test);
    let study = tiny_study(&dir, runs);
    let out = demsweep()
        .args(["run", study.to_str().unwrap(), "--out", dir.to_str().unwrap(), "--progress", "quiet"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    dir.join("scale.h5")
}

/// Read system calls made by this thread so far (Linux `/proc/thread-self/io`, `syscr`).
fn reads_so_far() -> u64 {
    let io = std::fs::read_to_string("/proc/thread-self/io").unwrap();
    let line = io.lines().find_map(|l| l.strip_prefix("syscr: ")).unwrap();
    line.trim().parse().unwrap()
}

/// Read system calls of the second of two one-run commits onto the file (the first one of a session
/// proves the file free of object references, once).
fn reads_of_a_commit(results: &Path) -> u64 {
    let (mut writer, _) = ResultsWriter::open(results, OutputOptions::default()).unwrap();
    let mut commit_one = |index: usize| {
        let row = SummaryRow::failed(index, &format!("extra{index}"), &[], "added by the test");
        writer.stage(&RunResult { row, scene: SceneConfig::default(), record: None }).unwrap();
        let before = reads_so_far();
        writer.commit().unwrap();
        reads_so_far() - before
    };
    commit_one(1_000_000);
    commit_one(1_000_001)
}

#[cfg(target_os = "linux")]
#[test]
fn a_commit_reads_as_much_on_a_file_four_times_larger() {
    let small = reads_of_a_commit(&results("scale_commit_small", 250));
    let large = reads_of_a_commit(&results("scale_commit_large", 1000));
    // hdf5-pure walked every object of the file on each commit (a count of hard links, a search
    // for object references): 4x the reads on 4x the runs.
    assert!(large <= small + small / 4, "a commit read {small} times on 250 runs, {large} times on 1000");
}

#[test]
fn a_finished_file_is_read_from_its_summary_and_a_killed_one_from_its_run_groups() {
    let path = results("scale_reads", 300);
    let file = reader::open(&path).unwrap();
    let before = reader::attribute_sets_read();
    let runs = reader::committed_runs(&file, &path).unwrap();
    assert_eq!((runs.rows.len(), runs.damaged.len()), (300, 0));
    assert_eq!(reader::attribute_sets_read(), before, "no run group's attributes for a finished file");
    let from_summary = runs.rows;

    // Without /summary (a writer killed before the end), every row comes from its run group: once.
    std::fs::remove_file(path.with_file_name("scale_summary.csv")).unwrap();
    let file = hdf5_pure::File::open_rw(&path).unwrap();
    file.root().delete("summary").unwrap();
    file.commit().unwrap();
    drop(file);
    let file = reader::open(&path).unwrap();
    let before = reader::attribute_sets_read();
    let runs = reader::committed_runs(&file, &path).unwrap();
    assert_eq!(reader::attribute_sets_read() - before, 300, "one attribute set per run");
    let same = SummaryTable::from_rows(&runs.rows) == SummaryTable::from_rows(&from_summary);
    assert!(same, "the rows read from the run groups differ from those of /summary");
}

/// Runs `args`, reads one line of its output and closes the pipe; returns its stderr.
fn read_one_line_of(args: &[&str]) -> String {
    let mut child = demsweep().args(args).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut first).unwrap();
    assert!(!first.is_empty(), "{args:?} printed nothing");
    let out = child.wait_with_output().unwrap();
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn output_piped_into_head_ends_quietly() {
    let dir = runner_common::scratch("scale_pipe");
    let study = tiny_study(&dir, 3000);
    let (s, o) = (study.to_str().unwrap(), dir.to_str().unwrap());
    let run = read_one_line_of(&["run", s, "--out", o, "--progress", "lines", "--jobs", "1"]);
    assert!(!run.contains("panicked"), "run: {run}");
    let resumed = demsweep().args(["run", s, "--out", o, "--resume", "--progress", "quiet"]).output().unwrap();
    assert!(resumed.status.success(), "the file of a sweep ended by its reader resumes");
    let results = dir.join("scale.h5");
    let summary = read_one_line_of(&["summary", results.to_str().unwrap()]);
    assert!(!summary.contains("panicked"), "summary: {summary}");
    // One run sampled 10 000 times: a history longer than a pipe holds.
    let long = dir.join("long.toml");
    let text = std::fs::read_to_string(&study)
        .unwrap()
        .replace("run.duration = 1e-3", "run.duration = 1.0\nrun.sample_interval = 1e-4");
    let text = text.replace("name = \"scale\"", "name = \"long\"");
    std::fs::write(
        &long,
        text.replace("\"material.friction\" = { linear = [0.0, 1.0], steps = 3000 }", "replicates = 1"),
    )
    .unwrap();
    let made = demsweep().args(["run", long.to_str().unwrap(), "--out", o, "--progress", "quiet"]).output().unwrap();
    assert!(made.status.success(), "{}", String::from_utf8_lossy(&made.stderr));
    let long = dir.join("long.h5");
    let id = demsweep::output::summary::read(&long).unwrap().column("run_id").unwrap().data.text(0);
    let history = read_one_line_of(&["history", long.to_str().unwrap(), &id]);
    assert!(!history.contains("panicked"), "history: {history}");
}

#[test]
fn resuming_a_finished_file_rewrites_nothing() {
    // Rewriting /summary deletes the old one, and hdf5-pure walks the whole file to free it.
    let path = results("scale_resume", 50);
    let before = std::fs::read(&path).unwrap();
    let study = path.with_file_name("scale.toml");
    let out = demsweep()
        .args(["run", study.to_str().unwrap(), "--out", path.parent().unwrap().to_str().unwrap(), "--resume"])
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&out.stdout).contains("0 run now, 50 already done"), "{out:?}");
    assert!(std::fs::read(&path).unwrap() == before, "the file changed");
}

/// The attributes a run group had before batch groups: one per value.
fn legacy_attrs(row: &SummaryRow) -> Vec<(String, hdf5_pure::AttrValue)> {
    use hdf5_pure::AttrValue::{F64, I64, String as Text, StringArray};
    let mut attrs = vec![
        ("index".to_string(), I64(row.index as i64)),
        ("id".into(), Text(row.id.clone())),
        ("status".into(), Text(row.status.as_str().into())),
        ("message".into(), Text(row.message.clone())),
        ("warning_count".into(), I64(0)),
        ("settle_time".into(), F64(row.settle_time.unwrap_or(f64::NAN))),
        ("steps".into(), I64(row.steps as i64)),
        ("particle_steps".into(), I64(row.particle_steps as i64)),
        ("simulated_time".into(), F64(row.simulated_time)),
        ("wall_time".into(), F64(row.wall_time)),
        ("parameters".into(), StringArray(row.parameters.iter().map(|(k, _)| k.clone()).collect())),
    ];
    for (key, value) in &row.parameters {
        let demsweep::study::ParamValue::Float(x) = value else { panic!("{key} is not a float") };
        attrs.push((key.clone(), F64(*x)));
    }
    let finals = demsweep::physics::quantity::final_value_declarations().zip(row.final_values);
    attrs.extend(finals.map(|(q, v)| (q.name.to_string(), F64(v))));
    attrs
}

#[test]
fn a_file_of_the_older_layout_reads_and_resumes() {
    // Rewrite a results file of 20 runs in the layout before batch groups (runs in /runs/b0000, one
    // attribute per value, no datasets), leaving out run 7 and /summary (as a killed writer would).
    let path = results("scale_legacy", 20);
    let file = reader::open(&path).unwrap();
    let (header, rows) = (reader::header(&file, &path).unwrap(), reader::rows(&file, &path).unwrap());
    drop(file);
    let mut builder = hdf5_pure::FileBuilder::new();
    for (name, value) in header.to_attrs() {
        builder.set_attr(name, value);
    }
    builder.write(&path).unwrap();
    let file = hdf5_pure::File::open_rw(&path).unwrap();
    file.root().create_group("runs").unwrap();
    file.root().create_group("runs/b0000").unwrap();
    for row in rows.iter().filter(|r| r.index != 7) {
        file.root()
            .create_group_with(&format!("runs/b0000/{}", row.id), |g| {
                for (name, value) in legacy_attrs(row) {
                    g.set_attr(&name, value);
                }
            })
            .unwrap();
    }
    file.commit().unwrap();
    drop(file);

    let file = reader::open(&path).unwrap();
    let read = reader::rows(&file, &path).unwrap();
    drop(file);
    // The older layout has no run identities and no CPU time.
    let without_7: Vec<SummaryRow> = rows
        .iter()
        .filter(|r| r.index != 7)
        .map(|r| SummaryRow { identity: String::new(), cpu_time: f64::NAN, ..r.clone() })
        .collect();
    assert!(SummaryTable::from_rows(&read) == SummaryTable::from_rows(&without_7), "the older layout reads");
    let study = path.with_file_name("scale.toml");
    let out = demsweep()
        .args(["run", study.to_str().unwrap(), "--out", path.parent().unwrap().to_str().unwrap(), "--resume"])
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&out.stdout).contains("1 run now, 19 already done"), "{out:?}");
    let resumed = demsweep::output::summary::read(&path).unwrap();
    // The runs of the older layout keep no identity; the run that ran now has one.
    let expected: Vec<SummaryRow> = rows
        .iter()
        .map(|r| if r.index == 7 { r.clone() } else { SummaryRow { identity: String::new(), ..r.clone() } })
        .collect();
    assert!(resumed.without_timing() == SummaryTable::from_rows(&expected).without_timing(), "the run left out ran");
}
