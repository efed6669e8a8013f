//! An independent libhdf5-based reader (h5py) finds exactly what the simulations produced: every
//! group, dataset and attribute of the results file (`/points` included) is compared with a JSON
//! description built here from the plan and from re-running each (deterministic) simulation.

mod python_env;
mod runner_common;

use demsweep::output::SummaryTable;
use demsweep::output::table::ColumnData;
use demsweep::physics::RunRecord;
use demsweep::physics::quantity::{self, HISTORY_SERIES, PILE_METRICS};
use demsweep::physics::record::DISK_FIELDS;
use demsweep::physics::run_scene;
use demsweep::physics::simulation::Control;
use demsweep::physics::warning::ValidityWarning;
use demsweep::study::{ParamValue, Plan, PlannedRun, RunIdentity};
use serde_json::{Map, Value, json};

fn param_json(v: &ParamValue) -> Value {
    match v {
        ParamValue::Float(x) => json!(x),
        ParamValue::Int(i) => json!(i),
        ParamValue::Bool(b) => json!(b),
        ParamValue::Text(s) => json!(s),
    }
}

/// The expected attributes of a run group and its tables `values`, `parameters` and `warnings`
/// (the last absent when the run has none), by dataset name.
fn run_group(
    run: &PlannedRun,
    record: Option<&RunRecord>,
    error: &str,
    (wall_time, cpu_time): (f64, f64),
) -> (Map<String, Value>, Vec<(&'static str, Value)>) {
    let mut a = Map::new();
    let nan = f64::NAN;
    a.insert("index".into(), json!(run.index));
    a.insert("id".into(), json!(run.id));
    a.insert("status".into(), json!(record.map_or("error", |r| r.status.as_str())));
    a.insert("message".into(), json!(record.map_or(error.to_string(), |r| r.message.clone().unwrap_or_default())));
    // The run's identity (what its results depend on) names its group and is an attribute, beside
    // the program and results format that made it.
    a.insert("identity".into(), json!(RunIdentity::of(run).to_string()));
    a.insert("demsweep_version".into(), json!(env!("CARGO_PKG_VERSION")));
    a.insert("results_format".into(), json!(3));
    a.insert("scene.json".into(), json!(serde_json::to_string(&run.scene).unwrap()));
    // The per-run values, typed, one field each (NaN as null), in the quantity table's order.
    let mut values = Map::new();
    values.insert("settle_time".into(), json!(record.and_then(|r| r.settle_time)));
    values.insert("steps".into(), json!(record.map_or(0, |r| r.steps)));
    values.insert("particle_steps".into(), json!(record.map_or(0, |r| r.steps * r.final_state.x.len() as u64)));
    values.insert("simulated_time".into(), json!(record.map_or(0.0, |r| r.simulated_time)));
    values.insert("wall_time".into(), json!(wall_time));
    values.insert("cpu_time".into(), json!(cpu_time));
    let last = |f: fn(&RunRecord) -> &Vec<f64>| record.map_or(nan, |r| *f(r).last().unwrap());
    let finals = [
        ("final_kinetic", last(|r| &r.history.kinetic_translational) + last(|r| &r.history.kinetic_rotational)),
        ("final_potential", last(|r| &r.history.potential)),
        ("final_elastic", last(|r| &r.history.elastic)),
        ("final_dissipated", last(|r| &r.history.dissipated)),
        ("final_numerical_damping_dissipated", last(|r| &r.history.numerical_damping_dissipated)),
        ("time_step", record.map_or(nan, |r| r.time_step)),
        ("final_mechanical", last(|r| &r.history.mechanical)),
        ("final_ubf", last(|r| &r.history.unbalanced_force_ratio)),
        ("energy_balance_error", record.map_or(nan, |r| r.energy_balance_error)),
        ("largest_overlap_ratio", record.map_or(nan, |r| r.largest_overlap_ratio)),
        ("physics_start_time", record.map_or(nan, |r| r.stage_ends.last().map_or(0.0, |e| e.time.unwrap_or(nan)))),
        ("poured_disks", record.and_then(|r| r.pour).map_or(nan, |p| p.inserted as f64)),
        ("refused_disks", record.and_then(|r| r.pour).map_or(nan, |p| p.refused as f64)),
        ("pile_height", record.map_or(nan, |r| pile_height(&r.final_state))),
        ("packing_fraction", record.map_or(nan, |r| packing_fraction(&r.final_state, run.scene.domain.width))),
    ];
    for (name, value) in finals {
        values.insert(name.into(), json!(value));
    }
    // The other pile metrics, as the record has them.
    for metric in PILE_METRICS.iter().filter(|m| !["pile_height", "packing_fraction"].contains(&m.name)) {
        values.insert(metric.name.to_string(), json!(record.map_or(nan, |r| r.pile[metric.name])));
    }
    let declared: Vec<quantity::Declaration> =
        quantity::OUTCOME.iter().copied().chain(quantity::final_value_declarations()).collect();
    assert_eq!(declared.len(), values.len(), "every per-run value is expected");
    let fields = declared.iter().map(|q| (q.name, json!([values[q.name]]))).collect();
    let units: Vec<&str> = declared.iter().map(|q| q.unit).collect();
    let mut tables = vec![("values", table(fields, json!({"units": units})))];
    let parameters = run.parameters.iter().map(|(k, v)| (k.as_str(), json!([param_json(v)]))).collect();
    let units: Vec<&str> = run.parameters.iter().map(|(k, _)| key_unit(k)).collect();
    tables.push(("parameters", table(parameters, json!({"units": units}))));
    let warnings = record.map_or(vec![], |r| r.warnings.clone());
    if !warnings.is_empty() {
        let column = |f: fn(&ValidityWarning) -> Option<f64>| json!(warnings.iter().map(f).collect::<Vec<_>>());
        let kinds: Vec<Value> = warnings.iter().map(|w| serde_json::to_value(w.kind).unwrap()).collect();
        let fields = vec![
            ("kind", json!(kinds)),
            ("value", column(|w| Some(w.value))),
            ("limit", column(|w| Some(w.limit))),
            ("time", column(|w| w.time)),
            ("impact_speed", column(|w| w.impact_speed)),
            ("safe_time_step", column(|w| w.safe_time_step)),
        ];
        tables.push(("warnings", table(fields, json!({}))));
    }
    (a, tables)
}

/// The highest disk top (m).
fn pile_height(s: &demsweep::physics::record::Snapshot) -> f64 {
    s.y.iter().zip(&s.r).map(|(y, r)| y + r).fold(0.0, f64::max)
}

/// Disk area over width times pile height.
fn packing_fraction(s: &demsweep::physics::record::Snapshot, width: f64) -> f64 {
    s.r.iter().map(|r| std::f64::consts::PI * r * r).sum::<f64>() / (width * pile_height(s))
}

/// A compound table: fields as `[name, values]` pairs, in order.
fn table(fields: Vec<(&str, Value)>, attrs: Value) -> Value {
    let fields: Vec<Value> = fields.into_iter().map(|(k, v)| json!([k, v])).collect();
    json!({"attrs": attrs, "fields": fields})
}

/// The frames as arrays over time: `time` (T) and one (T, N) array per disk field, with its unit.
fn frames(base: &str, frames: &[demsweep::physics::record::Snapshot], datasets: &mut Map<String, Value>) {
    let times: Vec<f64> = frames.iter().map(|s| s.time).collect();
    datasets.insert(format!("{base}/frames/time"), json!({"attrs": {"unit": "s"}, "values": times}));
    for (field, unit) in DISK_FIELDS.iter().map(|f| (f.name, f.unit)) {
        let values: Vec<Vec<f64>> = frames
            .iter()
            .map(|s| snapshot(s)["fields"].as_array().unwrap().iter().find(|p| p[0] == field).unwrap()[1].clone())
            .map(|v| serde_json::from_value(v).unwrap())
            .collect();
        datasets.insert(format!("{base}/frames/{field}"), json!({"attrs": {"unit": unit}, "values": values}));
    }
    // Every frame's contacts in one table, frame after frame, with the frame of each first.
    let mut all: Vec<(String, Vec<Value>)> = vec![("frame".into(), Vec::new())];
    for (k, s) in frames.iter().enumerate() {
        all[0].1.extend(std::iter::repeat_n(json!(k), s.contacts.len()));
        for (i, pair) in contacts(s)["fields"].as_array().unwrap().iter().enumerate() {
            if all.len() <= i + 1 {
                all.push((pair[0].as_str().unwrap().to_string(), Vec::new()));
            }
            all[i + 1].1.extend(pair[1].as_array().unwrap().iter().cloned());
        }
    }
    let fields = all.iter().map(|(n, v)| (n.as_str(), Value::Array(v.clone()))).collect();
    let units: Vec<&str> = std::iter::once("").chain(CONTACT_UNITS).collect();
    datasets.insert(format!("{base}/frames/contacts"), table(fields, json!({"units": units})));
}

fn snapshot(s: &demsweep::physics::record::Snapshot) -> Value {
    let f = vec![
        ("x", json!(s.x)),
        ("y", json!(s.y)),
        ("vx", json!(s.vx)),
        ("vy", json!(s.vy)),
        ("omega", json!(s.omega)),
        ("angle", json!(s.angle)),
        ("r", json!(s.r)),
        ("contact_force", json!(s.contact_force)),
    ];
    let units = ["m", "m", "m/s", "m/s", "rad/s", "rad", "m", "N"];
    table(f, json!({"time": s.time, "units": units}))
}

fn contacts(s: &demsweep::physics::record::Snapshot) -> Value {
    let c = &s.contacts;
    let f = vec![
        ("first", json!(c.first)),
        ("second", json!(c.second)),
        ("normal_x", json!(c.normal_x)),
        ("normal_y", json!(c.normal_y)),
        ("normal_force", json!(c.normal_force)),
        ("tangential_force", json!(c.tangential_force)),
        ("overlap", json!(c.overlap)),
        ("point_x", json!(c.point_x)),
        ("point_y", json!(c.point_y)),
        ("sliding", json!(c.sliding)),
        ("tangential_spring", json!(c.tangential_spring)),
        ("law_state", json!(c.law_state)),
    ];
    table(f, json!({"time": s.time, "units": CONTACT_UNITS}))
}

/// The units of a contact table's fields: forces in N, lengths in m, the rest none.
const CONTACT_UNITS: [&str; 12] = ["", "", "", "", "N", "N", "m", "m", "m", "", "m", "m"];

/// Floats with infinities kept (`{"$float": "inf"}`; JSON has none, and NaN is `null`): the UBF is
/// infinite while contacts carry no force.
fn floats(values: &[f64]) -> Value {
    let value = |&v: &f64| if v.is_infinite() { json!({"$float": v.to_string()}) } else { json!(v) };
    Value::Array(values.iter().map(value).collect())
}

fn history(r: &RunRecord) -> Value {
    let h = &r.history;
    let f = vec![
        ("t", json!(h.time)),
        ("kinetic_translational", json!(h.kinetic_translational)),
        ("kinetic_rotational", json!(h.kinetic_rotational)),
        ("potential", json!(h.potential)),
        ("elastic", json!(h.elastic)),
        ("dissipated", json!(h.dissipated)),
        ("numerical_damping_dissipated", json!(h.numerical_damping_dissipated)),
        ("total", json!(h.total)),
        ("mechanical", json!(h.mechanical)),
        ("unbalanced_force_ratio", floats(&h.unbalanced_force_ratio)),
        ("contacts", json!(h.contacts)),
        ("max_overlap_ratio", json!(h.max_overlap_ratio)),
    ];
    let units: Vec<&str> = HISTORY_SERIES.iter().map(|s| s.quantity.unit).collect();
    assert_eq!(units[..2], ["s", "J"], "time in seconds, energies in joules");
    table(f, json!({"units": units}))
}

/// The stress profile of the run's final state, with the columns and units docs/results.md names.
fn stress_profile(r: &RunRecord, scene: &demsweep::physics::config::SceneConfig) -> Value {
    let p = demsweep::physics::stress::StressProfile::of_state(
        &r.final_state,
        scene.domain.width,
        scene.particles.thickness,
    );
    let stress = |f: fn(&demsweep::physics::stress::Stress) -> f64| json!(p.stress.iter().map(f).collect::<Vec<_>>());
    let f = vec![
        ("bottom", json!(p.bottom)),
        ("top", json!(p.top)),
        ("stress_xx", stress(|s| s.xx)),
        ("stress_yy", stress(|s| s.yy)),
        ("stress_xy", stress(|s| s.xy)),
        ("stress_pressure", stress(|s| 0.5 * (s.xx + s.yy))),
        ("stress_deviatoric", stress(|s| s.deviatoric())),
        ("wall_normal_stress", json!(p.wall_normal)),
        ("wall_shear_stress", json!(p.wall_shear)),
    ];
    assert!(!p.is_empty(), "a settled pile has a profile to check");
    table(f, json!({"units": ["m", "m", "Pa", "Pa", "Pa", "Pa", "Pa", "Pa", "Pa"]}))
}

/// The SI unit of a scene key, from the key table (`demsweep keys`).
fn key_unit(path: &str) -> &'static str {
    demsweep::physics::keys::scene_keys().into_iter().find(|k| k.path == path).map_or("", |k| k.unit)
}

/// The expected datasets of the group `/<group>` (`summary`, `points`): one per column, typed by its values.
fn column_datasets(group: &str, table: &SummaryTable, datasets: &mut Map<String, Value>) -> Value {
    for c in &table.columns {
        let values = match &c.data {
            ColumnData::Float(v) => json!(v),
            ColumnData::Int(v) => json!(v),
            ColumnData::Bool(v) => json!(v),
            ColumnData::Text(v) => json!(v),
        };
        let attrs = match quantity::column_quantity(&c.name) {
            Some(q) => json!({"unit": q.unit, "description": q.description}),
            None if c.name.contains('.') => json!({"unit": key_unit(&c.name)}), // a swept key
            None => json!({}),
        };
        datasets.insert(format!("/{group}/{}", c.name), json!({"attrs": attrs, "values": values}));
    }
    json!({"columns": table.columns.iter().map(|c| &c.name).collect::<Vec<_>>()})
}

fn expected(plan: &Plan, summary: &SummaryTable) -> Value {
    let times = |name: &str| match &summary.column(name).unwrap().data {
        ColumnData::Float(v) => v.clone(),
        other => panic!("{name} column {other:?}"),
    };
    let (wall, cpu) = (times("wall_time"), times("cpu_time"));
    let mut groups = Map::new();
    let mut datasets = Map::new();
    groups.insert(
        "/".into(),
        json!({
            "study_name": plan.name, "study_text": plan.study_text, "fingerprint": plan.fingerprint,
            "demsweep_version": env!("CARGO_PKG_VERSION"), "planned_runs": plan.runs.len(),
            "created": {"$regex": r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ"},
        }),
    );
    // Run groups, named by the run's identity, sit in the batch group of the commit that wrote them
    // (`/runs_00000`, …): the check reads every batch's name as `/runs_*`.
    groups.insert("/runs_*".into(), json!({}));
    let mut stored_contacts = 0;
    for run in &plan.runs {
        let base = format!("/runs_*/{}", RunIdentity::of(run));
        let outcome = run_scene(&run.scene, None, &mut |_| Control::Continue);
        let record = outcome.as_ref().ok();
        let error = outcome.as_ref().err().map(ToString::to_string).unwrap_or_default();
        let (attrs, tables) = run_group(run, record, &error, (wall[run.index], cpu[run.index]));
        groups.insert(base.clone(), Value::Object(attrs));
        for (name, table) in tables {
            datasets.insert(format!("{base}/{name}"), table);
        }
        let Some(record) = record else { continue };
        // The worker thread's CPU time: some, and no more than its wall time (10 % and 20 ms slack for
        // the clocks' granularity), as the run's thread did nothing else meanwhile.
        let (wall, cpu) = (wall[run.index], cpu[run.index]);
        assert!(cpu > 0.0 && cpu <= wall * 1.1 + 0.02, "run {}: cpu_time {cpu} s, wall_time {wall} s", run.id);
        datasets.insert(format!("{base}/history"), history(record));
        datasets.insert(format!("{base}/stress_profile"), stress_profile(record, &run.scene));
        datasets.insert(format!("{base}/final"), snapshot(&record.final_state));
        stored_contacts += record.final_state.contacts.len();
        datasets.insert(format!("{base}/final_contacts"), contacts(&record.final_state));
        groups.insert(format!("{base}/frames"), json!({}));
        frames(&base, &record.frames, &mut datasets);
    }
    assert!(stored_contacts > 0, "the final states have contacts to check");
    let mut summary_attrs = column_datasets("summary", summary, &mut datasets);
    summary_attrs["columns"].as_array_mut().unwrap().extend([json!("group"), json!("demsweep_version")]);
    // Beside the columns: each run's group (its path) and the version that made it.
    let identities = summary.column("identity").unwrap();
    let paths: Vec<Value> =
        (0..summary.len()).map(|i| json!({"$regex": format!(r"runs_\d{{5}}/{}", identities.data.text(i))})).collect();
    datasets.insert("/summary/group".into(), json!({"attrs": {}, "values": paths}));
    let versions = vec![env!("CARGO_PKG_VERSION"); summary.len()];
    datasets.insert("/summary/demsweep_version".into(), json!({"attrs": {}, "values": versions}));
    // How the sweep ran: 2 worker threads (runner_common::options), for some seconds.
    summary_attrs["jobs"] = json!(2);
    summary_attrs["wall_time"] = json!({"$range": [0.0, 600.0]});
    // How many run groups the file held when /summary was written.
    summary_attrs["stored_runs"] = json!(plan.runs.len());
    groups.insert("/summary".into(), summary_attrs);
    // The crowded copy of run 0 (it failed) shares run 0's point; the others are points of their own.
    let points = demsweep::stats::points::Points::new(summary).table();
    let column = |name: &str| points.column(name).unwrap().data.clone();
    assert_eq!(column("n"), ColumnData::Int(vec![2, 1, 1]));
    assert_eq!(column("error"), ColumnData::Int(vec![1, 0, 0]));
    let steps = |i: usize| summary.column("steps").unwrap().data.number(i).unwrap();
    assert_eq!(column("steps_mean"), ColumnData::Float(vec![steps(0), steps(1), steps(2)]), "the failed run left out");
    groups.insert("/points".into(), column_datasets("points", &points, &mut datasets));
    json!({"groups": groups, "datasets": datasets})
}

/// A sweep `name` of three runs over time steps (each with a boolean and a quoted text parameter),
/// one more that fails (400 disks do not fit), run into a fresh folder.
fn run_interop(name: &str) -> (Plan, demsweep::runner::RunReport, std::path::PathBuf) {
    let mut plan = runner_common::sweep(name, 3);
    for run in &mut plan.runs {
        run.scene.run.duration = 0.3; // long enough for the disks to land: contacts to store
        run.parameters.push(("contact.allow_tension".into(), ParamValue::Bool(false)));
        run.parameters.push(("label".into(), ParamValue::Text(format!("case \"{}\", μ", run.index))));
    }
    let mut crowded = plan.runs[0].clone();
    crowded.scene.particles.count = 400;
    crowded.index = 3;
    crowded.id = "r003".into();
    plan.runs.push(crowded);
    let dir = runner_common::scratch(name);
    let report = demsweep::runner::run_plan(&plan, &runner_common::options(&dir, 2)).unwrap();
    assert_eq!(report.failed(), 1);
    (plan, report, dir)
}

#[test]
fn pandas_reads_every_csv_with_no_options_numbers_as_numbers() {
    let (_, report, _) = run_interop("plain_csv");
    let points = demsweep::output::points_csv_path(&report.results);
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/interop/check_plain_csv.py");
    let out = python_env::python(script).arg(&report.summary_csv).arg(&points).output().expect("run the tests' Python");
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "pandas check failed (scripts/test.sh installs pandas):\n{text}");
    assert!(text.contains("2 files") && text.contains("0 problems"), "{text}");
}

#[test]
fn h5py_reads_exactly_what_was_written() {
    let (plan, report, dir) = run_interop("interop");
    let json_path = dir.join("expected.json");
    std::fs::write(&json_path, serde_json::to_string(&expected(&plan, &report.summary)).unwrap()).unwrap();
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/interop/check_h5.py");
    let out = python_env::python(script).arg(&report.results).arg(&json_path).output().expect("run the tests' Python");
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "h5py check failed (scripts/test.sh installs h5py and numpy):\n{text}");
    assert!(text.contains("0 problems"), "{text}");
}

/// The ```python blocks of a docs chapter.
fn python_blocks(chapter: &str) -> Vec<String> {
    let text = std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(chapter)).unwrap();
    text.split("```python\n").skip(1).map(|block| block.split("```").next().unwrap().to_string()).collect()
}

#[test]
fn the_docs_python_snippets_run_against_a_fresh_results_file() {
    snippets_run_on("snippets", true);
}

#[test]
fn the_docs_python_snippets_run_on_a_study_without_frames_as_the_bundled_one() {
    snippets_run_on("snippets_no_frames", false);
}

/// Runs docs/results.md's Python snippets on a fresh results file of a small study (recording frames or
/// not) and checks what they read.
fn snippets_run_on(name: &str, frames: bool) {
    let dir = runner_common::scratch(name);
    let study = dir.join("snippets.toml");
    let text = format!(
        "name = \"snippets\"\n[scene]\nparticles.count = 4\ndomain.width = 0.06\ndomain.height = 0.08\n\
         run.duration = 0.01\nrun.sample_interval = 0.002\nrun.frame_interval = 0.005\n[sweep]\n\
         \"material.friction\" = [0.2, 0.6]\nreplicates = 4\n[output]\nframes = {frames}\n"
    );
    std::fs::write(&study, text).unwrap();
    let plan = demsweep::study::load(&study).unwrap();
    let report = demsweep::runner::run_plan(&plan, &runner_common::options(&dir, 2)).unwrap();
    let blocks = python_blocks("docs/results.md");
    assert!(!blocks.is_empty(), "docs/results.md has Python snippets");
    let status = report.summary.column("status").unwrap();
    let first = status.data.text(0);
    let count = (0..report.summary.len()).filter(|&i| status.data.text(i) == first).count();
    let identity = report.summary.column("identity").unwrap().data.text(7);
    let settle = report.summary.column("settle_time").unwrap().data.number(7).unwrap();
    let settle = if settle.is_nan() { "nan".to_string() } else { format!("{settle:?}") };
    let stored = demsweep::output::stored::read_run(
        &demsweep::output::reader::open(&report.results).unwrap(),
        &report.results,
        &report.summary.rows().unwrap()[7].0,
    )
    .unwrap();
    let times: Vec<f64> = stored.frames.iter().map(|f| f.time).collect();
    assert_eq!(times.len(), if frames { 3 } else { 0 }, "frames at 0, 5 and 10 ms, when recorded");
    let mut csv = Vec::new();
    demsweep::output::history::to_csv(&report.results, "r0007", &mut csv).unwrap();
    let samples = String::from_utf8(csv).unwrap().lines().count() - 1; // the names line
    for (k, block) in blocks.iter().enumerate() {
        let script = dir.join(format!("snippet_{k:02}.py"));
        // The snippet as written, on this file, then what it must have read.
        let mut checks = format!(
            "\nassert all(isinstance(s, str) for s in summary.status) and (summary.status == {first:?}).sum() == {count}\n\
             assert len(summary) == {} and list(summary.columns[:2]) == ['run_id', 'index']\n",
            report.summary.len()
        );
        if block.contains("group = ") {
            checks += &format!("assert group == {identity:?}\n");
        }
        if block.contains("run = f[") {
            checks += &format!(
                "assert run.name.endswith('/' + {identity:?})\n\
                 assert unit == 's' and repr(float(settle_time)) == {settle:?} and units['steps'] == ''\n"
            );
            if frames {
                checks += &format!("assert x.shape == (3, 4) and list(t) == {times:?}\n");
            }
        }
        if block.contains("history") {
            checks += &format!("assert len(history) == {samples}\n");
        }
        checks += "print('ok')\n";
        // The results file and the CSV files beside it (`<stem>.h5`, `<stem>_summary.csv`).
        let stem = report.results.with_extension("");
        let code = block.replace("results/damping_sweep/damping_sweep", stem.to_str().unwrap());
        std::fs::write(&script, code + &checks).unwrap();
        let out = python_env::python(script.to_str().unwrap()).output().expect("run the tests' Python");
        let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        assert!(
            out.status.success() && text.trim_end().ends_with("ok"),
            "docs/results.md snippet {k}:\n{block}\n{text}"
        );
    }
}
