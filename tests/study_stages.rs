//! Deposition protocols in study and tune files: a stage's keys swept and tuned by name, bad
//! protocols refused with the file, line and key.

use runner_common::{demsweep, text};
use std::path::{Path, PathBuf};

mod runner_common;
mod tune_common;

const STUDY: &str = r#"name = "protocol"
[scene.domain]
width = 0.15
height = 0.25
[scene.particles]
count = 60
radius = 0.004
radius_max = 0.006
[scene.material]
restitution = 0.4
[scene.integrator]
time_step = 2e-5
[scene.run]
duration = 1.5

[[scene.stages]]
name = "fill"
until.time = 0.2
damping.local = 0.5

[sweep]
"stages.fill.damping.local" = [0.2, 0.6]
"stages.fill.until.time" = [0.1, 0.25]
"#;

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// The summary CSV's rows as maps from column to text.
fn summary(path: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines.map(|l| header.iter().map(|h| h.to_string()).zip(l.split(',').map(String::from)).collect()).collect()
}

#[test]
fn a_sweep_over_a_stages_keys_runs_each_protocol_and_reports_when_its_physics_began() {
    let dir = runner_common::scratch("stages_swept");
    let study = write(&dir, "protocol.toml", STUDY);
    let out = dir.join("out");
    let run = demsweep(&["run", study.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    let rows = summary(&out.join("protocol_summary.csv"));
    assert_eq!(rows.len(), 4);
    for row in &rows {
        let until: f64 = row["stages.fill.until.time"].parse().unwrap();
        let began: f64 = row["physics_start_time"].parse().unwrap();
        assert!((began - until).abs() < 1e-9, "physics began at {began} s, the fill lasted {until} s");
        let settled: f64 = row["settle_time"].parse().unwrap();
        assert!(settled >= began, "settled at {settled} s, before the physics began at {began} s");
        assert_eq!(row["status"], "settled");
    }
    for row in &rows {
        assert_eq!(row["stage_end_time.fill"], row["physics_start_time"], "one stage: its end is the physics' start");
    }
    // The summary made again from the results file has the same stage columns.
    let again = dir.join("again.csv");
    let made = demsweep(&["summary", out.join("protocol.h5").to_str().unwrap(), "--csv", again.to_str().unwrap()]);
    assert_eq!(made.status.code(), Some(0), "{}", text(&made.stderr));
    let from_file = summary(&again);
    let column = |rows: &[std::collections::HashMap<String, String>]| -> Vec<String> {
        rows.iter().map(|r| r["stage_end_time.fill"].clone()).collect()
    };
    assert_eq!(column(&from_file), column(&rows));
    let sidecar = std::fs::read_to_string(out.join("protocol_summary.csv-metadata.json")).unwrap();
    assert!(sidecar.contains("\"titles\": \"stage_end_time.fill\""), "{sidecar}");
    let damping: Vec<&str> = rows.iter().map(|r| r["stages.fill.damping.local"].as_str()).collect();
    assert_eq!(damping, ["0.2", "0.2", "0.6", "0.6"]);
}

#[test]
fn bad_protocols_are_refused_with_file_line_and_key() {
    let dir = runner_common::scratch("stages_refused");
    let no_until_sweep = ("\"stages.fill.until.time\" = [0.1, 0.25]\n", "");
    let cases: [(&[(&str, &str)], &str); 6] = [
        (
            &[("damping.local = 0.5", "material.youngs_modulus = 1e7")],
            "scene.stages: unknown field `youngs_modulus`, expected one of `beta`, `restitution`, `friction`",
        ),
        (
            &[("damping.local = 0.5", "damping.local = 0.5\nmaterial.friction = -0.2")],
            "scene.stages.fill.material.friction (run r0000 and 3 more runs): must be a finite number >= 0, got -0.2",
        ),
        (
            &[("until.time = 0.2\n", ""), no_until_sweep],
            "scene.stages.fill.until (run r0000 and 1 more run): a stage needs a condition that ends it",
        ),
        (
            &[("until.time = 0.2", "until.time = -0.2"), no_until_sweep],
            "scene.stages.fill.until.time (run r0000 and 1 more run): must be a finite number > 0, got -0.2",
        ),
        (
            &[("\"stages.fill.damping.local\"", "\"stages.fil.damping.local\"")],
            "sweep.\"stages.fil.damping.local\": cannot sweep this key: scene.stages has no table named \"fil\" (its names: \"fill\")",
        ),
        (
            &[(
                "damping.local = 0.5\n",
                "damping.local = 0.5\n[[scene.stages]]\nname = \"fill\"\nuntil.all_in_contact = true\n",
            )],
            "scene.stages.fill.name (run r0000 and 3 more runs): two stages are named \"fill\"",
        ),
    ];
    for (edits, expected) in cases {
        let edited = edits.iter().fold(STUDY.to_string(), |text, (from, to)| text.replacen(from, to, 1));
        let file = write(&dir, "bad.toml", &edited);
        let check = demsweep(&["check", file.to_str().unwrap()]);
        let stderr = text(&check.stderr);
        assert_eq!(check.status.code(), Some(2), "{edits:?}: {stderr}");
        let line =
            stderr.lines().find(|l| l.contains(expected)).unwrap_or_else(|| panic!("{expected}\nnot in\n{stderr}"));
        let location = line.strip_prefix(&format!("{}:", file.display())).expect("the file first");
        let at: Vec<&str> = location.splitn(3, ':').collect();
        assert!(at[0].parse::<usize>().is_ok_and(|l| l >= 16), "a line of the stages or the sweep: {line}");
        assert_eq!(stderr.lines().filter(|l| l.contains("invalid type")).count(), 0, "no follow-on errors: {stderr}");
    }
}

#[test]
fn a_tune_over_a_stages_keys_changes_only_its_levers_and_names_the_stage() {
    let dir = runner_common::scratch("stages_tuned");
    let tune = tune_common::TUNE
        .replace("[levers]\n", "[[scene.stages]]\nname = \"fill\"\nuntil.time = 0.05\ndamping.local = 0.3\n\n[levers]\n")
        .replace(
            "\"integrator.time_step\" = { log = [5e-6, 2.5e-5] }",
            "\"stages.fill.damping.local\" = { linear = [0.0, 0.7] }\n\"stages.fill.until.time\" = { linear = [0.02, 0.2] }",
        )
        // Its settings cost about a reference deposition each: room for a second verification round.
        .replace("budget = 40\n", "budget = 40\nmax_spend = 40\n");
    let file = write(&dir, "tiny_tune.toml", &tune);
    let out = dir.join("out");
    let run = demsweep(&["tune", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--jobs", "2"]);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    let candidates = std::fs::read_to_string(out.join("tiny_tune_candidates.csv")).unwrap();
    let header = candidates.lines().next().unwrap();
    assert!(
        header.starts_with("candidate,origin,material.restitution,stages.fill.damping.local,stages.fill.until.time,n,"),
        "{header}"
    );
    let change = std::fs::read_to_string(out.join("tiny_tune_scene_change.toml")).unwrap();
    let keys: Vec<&str> = change
        .lines()
        .filter(|l| !l.starts_with('#') && l.contains(" = "))
        .map(|l| l.split(" = ").next().unwrap())
        .collect();
    assert_eq!(keys, ["material.restitution"], "{change}");
    assert!(change.contains("# and in the stage named \"fill\""), "{change}");
    for key in ["#   damping.local = ", "#   until.time = "] {
        assert!(change.contains(key), "{key} in\n{change}");
    }
    // The runnable study of the answer is a valid study with the stage as tuned.
    let best = out.join("tiny_tune_best.toml");
    let check = demsweep(&["check", best.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(0), "{}", text(&check.stderr));
    let best: toml::Table = toml::from_str(&std::fs::read_to_string(&best).unwrap()).unwrap();
    let stage = &best["scene"]["stages"][0];
    assert_eq!(stage["name"].as_str(), Some("fill"));
    let tuned = stage["damping"]["local"].as_float().unwrap();
    assert!((0.0..=0.7).contains(&tuned), "{tuned}");
}

#[test]
fn the_planned_cost_is_an_upper_bound_at_the_smallest_step_of_the_stages() {
    let dir = runner_common::scratch("stages_cost");
    let plain = demsweep::study::load(&write(&dir, "plain.toml", STUDY)).unwrap();
    let finer = STUDY.replacen("until.time = 0.2\n", "until.time = 0.2\nintegrator.time_step = 1e-5\n", 1);
    let finer = demsweep::study::load(&write(&dir, "finer.toml", &finer)).unwrap();
    for (a, b) in plain.runs.iter().zip(&finer.runs) {
        assert_eq!(a.time_step, b.time_step, "the physics' own step");
        assert_eq!(b.estimated_cost, 2.0 * a.estimated_cost, "the whole duration at half the step");
    }
}

#[test]
fn a_swept_stage_name_sets_its_stages_keys_whatever_the_order_of_the_axes() {
    let dir = runner_common::scratch("stages_renamed");
    let name = "\"stages.fill.name\" = [\"a\", \"z\"]\n";
    let damping = "\"stages.fill.damping.local\" = [0.1, 0.2]\n";
    for sweep in [format!("{name}{damping}"), format!("{damping}{name}")] {
        let edited = STUDY.replacen(
            "\"stages.fill.damping.local\" = [0.2, 0.6]\n\"stages.fill.until.time\" = [0.1, 0.25]\n",
            &sweep,
            1,
        );
        let file = write(&dir, "renamed.toml", &edited);
        let check = demsweep(&["check", file.to_str().unwrap()]);
        assert_eq!(check.status.code(), Some(0), "{sweep}: {}", text(&check.stderr));
        let plan = demsweep::study::load(&file).unwrap();
        let mut stages: Vec<(String, Option<f64>)> =
            plan.runs.iter().map(|r| (r.scene.stages[0].name.clone(), r.scene.stages[0].damping.local)).collect();
        stages.sort_by(|a, b| a.partial_cmp(b).unwrap());
        let expected = [("a", 0.1), ("a", 0.2), ("z", 0.1), ("z", 0.2)].map(|(n, d)| (n.to_string(), Some(d)));
        assert_eq!(stages, expected, "{sweep}");
    }
}

#[test]
fn a_tune_over_a_stages_name_and_another_of_its_keys_evaluates_its_candidates() {
    let dir = runner_common::scratch("stages_tuned_renamed");
    let tune = tune_common::TUNE
        .replace(
            "[levers]\n",
            "[[scene.stages]]\nname = \"fill\"\nuntil.time = 0.05\ndamping.local = 0.3\n\n[levers]\n",
        )
        .replace(
            "\"integrator.time_step\" = { log = [5e-6, 2.5e-5] }",
            "\"stages.fill.name\" = [\"fill\", \"pour\"]\n\"stages.fill.damping.local\" = { linear = [0.0, 0.7] }",
        );
    let file = write(&dir, "renamed_tune.toml", &tune);
    let check = demsweep(&["check", file.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(0), "{}", text(&check.stderr));
    let out = dir.join("out");
    let run = demsweep(&["tune", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--jobs", "2"]);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    let candidates = std::fs::read_to_string(out.join("tiny_tune_candidates.csv")).unwrap();
    // Settings other than the reference's were run, each with a stage name of the lever's.
    let rows: Vec<Vec<&str>> = candidates.lines().skip(1).map(|l| l.split(',').collect()).collect();
    let run: Vec<&Vec<&str>> =
        rows.iter().filter(|r| r[1] != "reference" && r[5].parse::<u32>().is_ok_and(|n| n > 0)).collect();
    assert!(!run.is_empty(), "no setting was run:\n{candidates}");
    assert!(run.iter().all(|r| ["fill", "pour"].contains(&r[3])), "{candidates}");
    assert!(run.iter().any(|r| r[3] == "pour"), "the renamed stage's settings were run too:\n{candidates}");
}
