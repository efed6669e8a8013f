//! Results format 3 as a user meets it: a flipped byte inside stored data is an error naming the
//! run and the dataset (from `export`, `history` and h5py), never a value; each run records the
//! demsweep version that made it, and `run --resume` and `merge` refuse runs of another version,
//! naming the run and both versions, unless told to accept them; `merge --name` names the file.

mod python_env;
mod runner_common;

use std::path::{Path, PathBuf};
use std::process::Output;

use demsweep::output::{reader, stored};
use hdf5_pure::AttrValue;
use runner_common::demsweep;

const VERSION: &str = env!("CARGO_PKG_VERSION");

/// Six disks falling for 10 ms (6 history samples: stored uncompressed, so their bytes are found
/// as they are), one run per friction value, with a contact-time limit strict enough to warn.
fn study(frictions: &str) -> String {
    format!(
        "name = \"layout\"\n[scene]\nparticles.count = 6\ndomain.width = 0.08\ndomain.height = 0.1\n\
         run.duration = 0.01\nrun.sample_interval = 0.002\nplacement.seed = 7\nlimits.contact_time_fraction = 0.01\nintegrator.time_step = 1e-4\n\
         [sweep]\n\"material.friction\" = [{frictions}]\n"
    )
}

fn text(out: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr))
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs the study `text` (saved as `<dir>/<name>.toml`) into `<dir>/<name>/`; its results file.
fn run(dir: &Path, name: &str, study_text: &str) -> PathBuf {
    let study = dir.join(format!("{name}.toml"));
    std::fs::write(&study, study_text).unwrap();
    let out = dir.join(name);
    let ran = demsweep(&["run", path(&study), "--out", path(&out), "--progress", "quiet"]);
    assert!(ran.status.success(), "{}", text(&ran));
    out.join("layout.h5")
}

/// A copy of `results` with every occurrence of `value`'s bytes changed in one bit.
fn flipped(results: &Path, value: f64, name: &str) -> PathBuf {
    let mut bytes = std::fs::read(results).unwrap();
    let pattern = value.to_le_bytes();
    let at: Vec<usize> = (0..bytes.len() - 8).filter(|&i| bytes[i..i + 8] == pattern).collect();
    assert!(!at.is_empty(), "{value} is stored as it is");
    for i in at {
        bytes[i + 3] ^= 0x10;
    }
    let copy = results.with_file_name(name);
    std::fs::write(&copy, bytes).unwrap();
    copy
}

#[test]
fn a_flipped_byte_inside_a_stored_final_state_or_history_is_an_error_naming_the_run_and_dataset() {
    let dir = runner_common::scratch("layout_checksums");
    let results = run(&dir, "a", &study("0.2, 0.4"));
    let file = reader::open(&results).unwrap();
    let rows = reader::rows(&file, &results).unwrap();
    let run = stored::read_run(&file, &results, &rows[1]).unwrap();
    let group = reader::find_run(&file, &results, "r0001").unwrap();
    drop(file);
    let final_state = flipped(&results, run.final_state.unwrap().x[2], "final.h5");
    let history = flipped(&results, run.history.unwrap().potential[1], "history.h5");

    let export = |file: &Path, out: &str| {
        demsweep(&["export", path(file), "--run", "r0001", "--format", "csv", "--out", path(&dir.join(out))])
    };
    let refused = export(&final_state, "exported_final");
    assert!(!refused.status.success(), "{}", text(&refused));
    let message = text(&refused);
    assert!(
        message.contains(&format!("run r0001: /{group}/final cannot be read")) && message.contains("fletcher32"),
        "{message}"
    );
    for args in [
        vec!["history", path(&history), "r0001"],
        vec!["plot", path(&history), "--out", path(&dir.join("plots"))],
        vec!["report", path(&history), "--out", path(&dir.join("page.html"))],
    ] {
        let refused = demsweep(&args);
        let message = text(&refused);
        assert!(!refused.status.success(), "{args:?}: {message}");
        assert!(message.contains(&format!("run r0001: /{group}/history cannot be read")), "{args:?}: {message}");
    }
    let refused = export(&history, "exported_history");
    assert!(!refused.status.success() && text(&refused).contains("/history cannot be read"), "{}", text(&refused));
    // The summary (its own checksummed columns) still reads: the damage is in one run's data only.
    assert!(demsweep(&["summary", path(&final_state)]).status.success());

    // libhdf5 checks the same checksums: h5py raises rather than return the damaged values.
    let script = dir.join("read.py");
    std::fs::write(
        &script,
        "import sys, h5py\nf = h5py.File(sys.argv[1], 'r')\nfor name in sys.argv[2:]:\n    try:\n        \
         f[name][()]\n        print(name, 'read')\n    except OSError:\n        print(name, 'refused')\n",
    )
    .unwrap();
    for (file, dataset) in [(&final_state, "final"), (&history, "history")] {
        let other = rows[0].group_name();
        let read = python_env::python(path(&script))
            .args([path(file), &format!("{group}/{dataset}"), &format!("{group}/values")])
            .output()
            .unwrap();
        let said = text(&read);
        assert!(said.contains(&format!("{group}/{dataset} refused")), "{said}");
        assert!(said.contains(&format!("{group}/values read")), "{said} ({other})");
    }
}

fn versions(results: &Path) -> Vec<String> {
    let file = hdf5_pure::File::open(results).unwrap();
    file.dataset("summary/demsweep_version").unwrap().read_string().unwrap()
}

#[test]
fn resume_refuses_runs_of_another_demsweep_version_naming_them_unless_accepted() {
    let dir = runner_common::scratch("layout_versions");
    let results = run(&dir, "a", &study("0.2, 0.4, 0.6"));
    assert_eq!(versions(&results), [VERSION; 3], "each run records the version that made it");
    runner_common::made_by(&results, "0.0.9");
    let before = std::fs::read(&results).unwrap();
    let (study, out) = (dir.join("a.toml"), dir.join("a"));
    let resume = |extra: &[&str]| {
        let args = ["run", path(&study), "--out", path(&out), "--resume"];
        demsweep(&[&args[..], extra].concat())
    };
    let refused = resume(&[]);
    let message = text(&refused);
    assert!(!refused.status.success(), "{message}");
    assert!(
        message.contains(&format!(
            "run r0000 (and 2 more of the runs this study reuses) was made by demsweep 0.0.9, this is {VERSION}"
        )) && message.contains("--accept-version"),
        "{message}"
    );
    assert!(std::fs::read(&results).unwrap() == before, "a refused resume changes nothing");
    let accepted = resume(&["--accept-version", "--progress", "lines"]);
    assert!(accepted.status.success(), "{}", text(&accepted));
    assert!(
        text(&accepted).contains("reusing 3 stored run(s) made by another demsweep version"),
        "{}",
        text(&accepted)
    );
    assert_eq!(versions(&results), ["0.0.9"; 3], "reused, each keeping the version that made it");
}

#[test]
fn merge_refuses_runs_of_different_demsweep_versions_unless_accepted_and_takes_a_name() {
    let dir = runner_common::scratch("layout_merge");
    let a = run(&dir, "a", &study("0.2, 0.4"));
    let b = run(&dir, "b", &format!("# another study\n{}", study("0.4, 0.6")));
    runner_common::made_by(&b, "0.0.9");
    let out = dir.join("merged");
    let merge = |extra: &[&str]| demsweep(&[&["merge", path(&out), path(&a), path(&b)][..], extra].concat());
    let refused = merge(&[]);
    let message = text(&refused);
    assert!(!refused.status.success(), "{message}");
    assert!(
        message
            .contains(&format!("run r0000 was made by demsweep 0.0.9, but run r0000 of {} by {VERSION}", a.display()))
            && message.contains("--accept-version"),
        "{message}"
    );
    let bad = merge(&["--accept-version", "--name", "../elsewhere"]);
    assert!(!bad.status.success() && text(&bad).contains("--name `../elsewhere`"), "{}", text(&bad));
    let merged = merge(&["--accept-version", "--name", "both studies"]);
    assert!(merged.status.success(), "{}", text(&merged));
    let both = out.join("both studies.h5");
    assert_eq!(versions(&both), [VERSION, VERSION, "0.0.9"], "the run both hold is a's; 0.6 is b's");
    let file = reader::open(&both).unwrap();
    assert_eq!(reader::header(&file, &both).unwrap().study_name, "both studies");
}

/// Rewrites the run groups of `results` as results format 2 wrote them: the row as JSON text in an
/// attribute `row` (no `values`, `parameters`, `warnings` tables, no `results_format` or
/// `demsweep_version` attributes), and no `/summary`.
fn as_format_2(results: &Path) {
    let file = reader::open(results).unwrap();
    let runs = reader::committed_runs(&file, results).unwrap();
    drop(file);
    let file = hdf5_pure::File::open_rw(results).unwrap();
    for row in &runs.rows {
        let group = file.group(&runs.groups[row.group_name()]).unwrap();
        for table in ["values", "parameters", "warnings"] {
            if group.datasets().unwrap().iter().any(|d| d == table) {
                group.delete(table).unwrap();
            }
        }
        group.remove_attr("results_format").unwrap();
        group.remove_attr("demsweep_version").unwrap();
        let number = |x: f64| if x.is_nan() { serde_json::Value::Null } else { serde_json::json!(x) };
        let mut json = serde_json::Map::new();
        let parameters: Vec<serde_json::Value> = row
            .parameters
            .iter()
            .map(|(k, v)| match v {
                demsweep::study::ParamValue::Float(x) => serde_json::json!([k, x]),
                other => panic!("{other:?}"),
            })
            .collect();
        json.insert("parameters".into(), parameters.into());
        json.insert("warnings".into(), serde_json::to_value(&row.warnings).unwrap());
        json.insert("settle_time".into(), number(row.settle_time.unwrap_or(f64::NAN)));
        json.insert("steps".into(), row.steps.into());
        json.insert("particle_steps".into(), row.particle_steps.into());
        json.insert("simulated_time".into(), number(row.simulated_time));
        json.insert("wall_time".into(), number(row.wall_time));
        json.insert("cpu_time".into(), number(row.cpu_time));
        for (q, x) in demsweep::physics::quantity::final_value_declarations().zip(row.final_values) {
            json.insert(q.name.into(), number(x));
        }
        group.set_attr("row", AttrValue::String(serde_json::Value::Object(json).to_string())).unwrap();
    }
    file.root().delete("summary").unwrap();
    file.commit().unwrap();
    file.close().unwrap();
}

#[test]
fn a_file_of_results_format_2_reads_grows_in_format_3_and_merges() {
    let dir = runner_common::scratch("layout_format2");
    let results = run(&dir, "a", &study("0.2, 0.4"));
    let file = reader::open(&results).unwrap();
    let rows = reader::rows(&file, &results).unwrap();
    let history = |file: &Path, id: &str| {
        let out = demsweep(&["history", path(file), id]);
        assert!(out.status.success(), "{}", text(&out));
        String::from_utf8(out.stdout).unwrap()
    };
    let histories = [history(&results, "r0000"), history(&results, "r0001")];
    drop(file);
    as_format_2(&results);
    let file = reader::open(&results).unwrap();
    let read = reader::rows(&file, &results).unwrap();
    let warnings: usize = read.iter().map(|r| r.warnings.len()).sum();
    assert!(warnings > 0, "the runs have warnings to read back");
    let unrecorded: Vec<_> =
        rows.iter().map(|r| demsweep::output::SummaryRow { made_by: String::new(), ..r.clone() }).collect();
    let table = demsweep::output::SummaryTable::from_rows;
    assert!(table(&read) == table(&unrecorded), "format 2 reads back as written (NaN equal to NaN)");
    let warnings = |rows: &[demsweep::output::SummaryRow]| rows.iter().map(|r| r.warnings.clone()).collect::<Vec<_>>();
    assert_eq!(warnings(&read), warnings(&unrecorded));
    drop(file);

    // An edited study grows the file: the new run in format 3 beside the two of format 2.
    std::fs::write(dir.join("a.toml"), study("0.2, 0.3, 0.4")).unwrap();
    let grown = demsweep(&["run", path(&dir.join("a.toml")), "--out", path(&dir.join("a")), "--resume"]);
    assert!(grown.status.success() && text(&grown).contains("1 run now, 2 already done"), "{}", text(&grown));
    assert_eq!([history(&results, "r0000"), history(&results, "r0002")], histories, "the old runs read as before");
    assert_eq!(versions(&results), ["", VERSION, ""], "format 2 recorded no version");
    let file = hdf5_pure::File::open(&results).unwrap();
    let groups = file.dataset("summary/group").unwrap().read_string().unwrap();
    let format = |g: &str| file.group(g).unwrap().attrs().unwrap().get("results_format").and_then(AttrValue::as_i64);
    assert_eq!(groups.iter().map(|g| format(g)).collect::<Vec<_>>(), [None, Some(3), None]);
    drop(file);

    // And merges with a file of format 3 (a fresh run of another study).
    let b = run(&dir, "b", &format!("# another study\n{}", study("0.4, 0.6")));
    let merged = demsweep(&["merge", path(&dir.join("merged")), path(&results), path(&b)]);
    assert!(merged.status.success(), "{}", text(&merged));
    let both = dir.join("merged").join("layout.h5");
    assert_eq!(history(&both, "r0000"), histories[0]);
    assert_eq!(versions(&both), ["", VERSION, "", VERSION]);
}
