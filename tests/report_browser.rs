//! The HTML report as a person sees it: `demsweep run` writes it, and headless Chromium (Debian's
//! `chromium`, driven by Playwright; `scripts/test.sh` installs both) opens it. It loads with no console
//! error and no network request, its table has one row per grid point, a click on a header sorts
//! the rows, every chart has a size, and a run's section is reachable from its row. The point table's
//! columns sit under header groups with their units; a run with frames gets a player whose frames
//! are drawn where the results file has the disks.

use std::path::{Path, PathBuf};
mod python_env;

use std::process::Command;

use demsweep::physics::quantity;
use serde_json::Value;

/// 3 restitution values x 3 seeds of 25 disks.
const STUDY: &str = r#"name = "report_study"
description = "restitution with replicates, for the report test"
[scene]
particles.count = 25
domain.width = 0.16
domain.height = 0.2
run.duration = 1.5
[sweep]
"material.restitution" = [0.2, 0.5, 0.8]
replicates = 3
[output]
frames = false
[report]
reference = { "material.restitution" = 0.5 }
"#;

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// What the browser saw (see tests/report/check_report.py); with `results`, the players checked against it.
fn open_in_browser(report: &Path, results: Option<&Path>) -> Value {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/report/check_report.py");
    let mut command = python_env::python(script);
    command.arg(report);
    if let Some(results) = results {
        command.arg("--results").arg(results);
    }
    let out = command.output().expect("run the tests' Python");
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
    // Computing time: the runs' summed wall time, their CPU time beside it.
    let computing = html.split("computing time</dt><dd>").nth(1).and_then(|rest| rest.split("</dd>").next());
    assert!(
        computing.is_some_and(|c| c.contains(" s wall time summed over all runs; ") && c.ends_with(" s CPU time")),
        "{computing:?}"
    );

    // `demsweep report` reads the reference from the study text stored in the results file.
    let again = dir.join("again.html");
    let results = dir.join("report_study.h5");
    let out = Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(["report", results.to_str().unwrap(), "--out", again.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        std::fs::read_to_string(&again).unwrap().contains("id=\"reference-verdict\""),
        "report shows the reference"
    );

    let seen = open_in_browser(&report, None);
    println!("{seen}");
    assert_eq!(seen["console_errors"], Value::Array(Vec::new()), "{seen}");
    assert_eq!(seen["requests"], Value::Array(Vec::new()), "no network request: {seen}");
    assert_eq!((&seen["rows"], &seen["rows_in_page"]), (&Value::from(3), &Value::from(3)), "one row per grid point");
    the_answer_comes_first(&seen, &dir.join("report_study.h5"));
    assert_eq!(seen["sorted_column"], "material.restitution");
    assert_eq!((seen["sorted_ascending"].as_bool(), seen["sorted_descending"].as_bool()), (Some(true), Some(true)));
    let pile_charts = quantity::charted().count() - 1; // settle time against restitution is the settle-time chart
    let per_run = 4; // energies, unbalanced force ratio, stress profile, final pile
    assert_eq!(seen["charts"], 1 + pile_charts + 9 * per_run, "settle time, pile metrics and the runs' charts: {seen}");
    assert_eq!(seen["charts_without_size"], 0);
    assert_eq!(seen["bottom_reached"], true);
    assert_eq!(seen["run_links"], 3, "each point links to a run section");
    assert_eq!(seen["run_links_reached"], 3);
    header_groups_hold_their_columns(&seen);
    the_column_picker_fits_the_page(&seen);
}

/// At 1280 px the point table shows a compact set of header groups without sideways scroll; ticking
/// another group shows its columns (header and cells), unticking hides them again.
fn the_column_picker_fits_the_page(seen: &Value) {
    assert_eq!(seen["points_table_scrolls_sideways"], false, "{seen}");
    let strings = |key: &str| -> Vec<String> {
        seen[key]
            .as_array()
            .unwrap_or_else(|| panic!("{key}: {seen}"))
            .iter()
            .map(|c| c.as_str().unwrap().to_string())
            .collect()
    };
    let shown = strings("visible_columns");
    for column in ["material.restitution", &quantity::label("settle_time"), &quantity::label("pile_height")] {
        assert!(shown.iter().any(|c| c == column), "{column} shown at first: {shown:?}");
    }
    let all = strings("columns");
    assert!(shown.len() < all.len(), "some groups hidden at first: {shown:?}");
    let toggled = seen["toggled_group"].as_str().unwrap();
    let under: Vec<&str> = {
        let columns: Vec<&str> = all.iter().map(String::as_str).collect();
        let mut next = 0;
        let mut under = Vec::new();
        for group in seen["header_groups"].as_array().unwrap() {
            let span = group[1].as_u64().unwrap() as usize;
            if group[0] == toggled {
                under = columns[next..next + span].to_vec();
            }
            next += span;
        }
        under
    };
    assert!(!under.is_empty() && under.iter().all(|c| !shown.iter().any(|s| s == c)), "{toggled} hidden at first");
    let with = strings("visible_columns_toggled");
    assert_eq!(with.len(), shown.len() + under.len(), "{toggled} adds its columns: {with:?}");
    assert!(under.iter().all(|c| with.iter().any(|s| s == c)), "{toggled}'s columns shown: {with:?}");
    assert_eq!(seen["cells_per_row_toggled"], with.len(), "a row has a cell per shown column: {seen}");
    assert_eq!(strings("visible_columns_untoggled"), shown, "unticked, the group hides again");
}

/// The page opens on its answer, visible without scrolling: the grid points by mean settle time, the
/// fastest first, as the file's own per-point statistics order them.
fn the_answer_comes_first(seen: &Value, results: &Path) {
    assert_eq!(seen["first_section"], "verdict", "{seen}");
    assert_eq!(seen["verdict_in_first_screen"], true, "{seen}");
    assert_eq!(seen["stray_markup"], Value::Array(Vec::new()), "no markup shows as text: {seen}");
    let file = demsweep::output::reader::open(results).unwrap();
    let summary = demsweep::output::reader::summary(&file, results).unwrap();
    let points = demsweep::stats::points::Points::new(&summary);
    the_answer_is_the_fastest_equivalent_point(seen, &points);
    let mut means: Vec<(f64, String)> = (0..points.len())
        .map(|p| (points.describe(p, "settle_time").mean, points.label(p)))
        .filter(|(mean, _)| mean.is_finite())
        .collect();
    means.sort_by(|a, b| a.0.total_cmp(&b.0));
    let shown: Vec<&str> = seen["verdict_points"].as_array().unwrap().iter().map(|r| r[0].as_str().unwrap()).collect();
    let expected: Vec<&str> = means.iter().map(|(_, label)| label.as_str()).collect();
    assert_eq!(shown, expected, "the settled points, fastest first: {seen}");
    assert!(!shown.is_empty(), "the test's points settle: {seen}");
    the_reference_verdict_is_in_the_answer(seen, &points);
}

/// The first paragraph answers the study's question as `demsweep compare` decides it: the fastest
/// point (by cost ratio) faster than the reference that makes an equivalent pile, or none of them
/// and the nearest miss.
fn the_answer_is_the_fastest_equivalent_point(seen: &Value, points: &demsweep::stats::points::Points) {
    assert_eq!(seen["answer_id"], "answer", "{seen}");
    let text = seen["answer"].as_str().unwrap_or_default();
    let comparison = demsweep::stats::compare::compare(points, "material.restitution=0.5", &[]).unwrap();
    let faster: Vec<_> = comparison.points.iter().filter(|p| p.cost.ratio < 1.0).collect();
    let best = faster.iter().filter(|p| p.acceptable()).min_by(|a, b| a.cost.ratio.total_cmp(&b.cost.ratio));
    let expected = match (best, faster.len()) {
        (Some(p), _) => format!("{} is the fastest grid point that makes the same pile", points.label(p.point)),
        (None, 0) => "No grid point is faster than the reference".to_string(),
        (None, n) => format!("None of the {n} faster grid points makes the same pile"),
    };
    assert!(text.starts_with(&expected), "expected `{expected}…`: {seen}");
    assert!(text.contains("(material.restitution=0.5)"), "names the reference: {text}");
}

/// The study's reference point is compared in the answer's section, each other point judged as
/// `demsweep compare` judges it at its default tolerances.
fn the_reference_verdict_is_in_the_answer(seen: &Value, points: &demsweep::stats::points::Points) {
    assert_eq!(seen["reference_section"], "verdict", "{seen}");
    let text = seen["reference_verdict"].as_str().unwrap_or_default();
    assert!(text.starts_with("Reference: material.restitution=0.5."), "{seen}");
    let comparison = demsweep::stats::compare::compare(points, "material.restitution=0.5", &[]).unwrap();
    let judged = |p: &demsweep::stats::compare::PointComparison| {
        let different = p.tests.iter().any(|t| t.decision == demsweep::stats::Decision::Different);
        match (p.acceptable(), different) {
            (true, _) => "equivalent",
            (false, true) => "different",
            (false, false) => "undecided",
        }
    };
    let mut expected: Vec<(String, &str)> =
        comparison.points.iter().map(|p| (points.label(p.point), judged(p))).collect();
    let mut shown: Vec<(String, &str)> = seen["reference_rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| (r[0].as_str().unwrap().to_string(), r[1].as_str().unwrap()))
        .collect();
    expected.sort();
    shown.sort();
    assert_eq!(shown, expected, "every other point with compare's decision: {seen}");
    let equivalent = expected.iter().filter(|(_, j)| *j == "equivalent").count();
    assert!(text.contains(&format!("{equivalent} of 2 other grid points make an equivalent pile")), "{seen}");
}

/// The point table's header groups span every column, in the quantity table's order, each column
/// with its unit from the quantity table.
fn header_groups_hold_their_columns(seen: &Value) {
    let columns: Vec<&str> = seen["columns"].as_array().unwrap().iter().map(|c| c.as_str().unwrap()).collect();
    let mut under: Vec<(&str, Vec<&str>)> = Vec::new();
    let mut next = 0;
    for group in seen["header_groups"].as_array().unwrap() {
        let span = group[1].as_u64().unwrap() as usize;
        under.push((group[0].as_str().unwrap(), columns[next..next + span].to_vec()));
        next += span;
    }
    assert_eq!(next, columns.len(), "the groups span every column: {seen}");
    let names: Vec<&str> = under.iter().map(|(g, _)| *g).collect();
    let expected = ["grid point", "runs", "settle time & cost", "time step & final state", "pile geometry"];
    assert_eq!(names[..5], expected, "{names:?}");
    assert_eq!(names[5..], ["contacts & forces", "warnings & run ids"], "{names:?}");
    let group_of = |column: &str| under.iter().find(|(_, c)| c.contains(&column)).map(|(g, _)| *g);
    let header = |name: &str| quantity::label(name);
    assert_eq!(group_of("material.restitution"), Some("grid point"));
    assert_eq!(group_of(&header("settle_time")), Some("settle time & cost"));
    assert_eq!(group_of(&header("pile_height")), Some("pile geometry"));
    assert_eq!(group_of(&header("packing_fraction_interior")), Some("pile geometry"));
    assert_eq!(group_of(&header("mechanical_coordination_number")), Some("contacts & forces"));
    assert_eq!(group_of(&header("floor_mean_contact_force")), Some("contacts & forces"));
    for (name, unit) in [("settle_time", "s"), ("pile_height", "m"), ("floor_mean_contact_force", "N")] {
        assert_eq!(quantity::find(name).unwrap().unit, unit);
        assert!(columns.contains(&format!("{name} ({unit})").as_str()), "{name} with its unit: {columns:?}");
    }
}

#[test]
fn each_run_with_frames_has_a_player_that_draws_the_stored_frames() {
    let dir = scratch("report_player");
    let study = dir.join("report_study.toml");
    let with_frames = STUDY
        .replace("run.duration = 1.5", "run.duration = 0.3\nrun.frame_interval = 0.05")
        .replace("frames = false", "frames = true")
        .replace("replicates = 3", "replicates = 1")
        .replace("[report]\nreference = { \"material.restitution\" = 0.5 }\n", "");
    std::fs::write(&study, with_frames).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(["run", study.to_str().unwrap(), "--out", dir.to_str().unwrap(), "--progress", "quiet"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let seen = open_in_browser(&dir.join("report_study_report.html"), Some(&dir.join("report_study.h5")));
    println!("{seen}");
    assert_eq!(seen["console_errors"], Value::Array(Vec::new()), "{seen}");
    assert_eq!(seen["requests"], Value::Array(Vec::new()), "no network request: {seen}");
    assert_eq!(seen["player_count"], 3, "a player per run");
    // Without a reference point, the answer is the fastest point, its pile not compared.
    let answer = seen["answer"].as_str().unwrap_or_default();
    assert!(answer.contains("pile was not compared: the study names no reference point"), "{seen}");
    for player in seen["players"].as_array().unwrap() {
        // Frames at 0, 0.05, …, 0.3 s (the last is the final state's step).
        assert_eq!(player["frames"], 7, "{player}");
        assert_eq!(player["disks"], 25, "{player}");
        assert_eq!(
            (&player["first_frame"], &player["after_step"], &player["after_back"]),
            (&0.into(), &1.into(), &0.into())
        );
        let labels = player["labels"].as_array().unwrap();
        assert_eq!(labels[0], "frame 1 of 7, t = 0 s");
        assert_eq!(labels[1], "frame 2 of 7, t = 0.05 s");
        assert_eq!(labels[2], labels[0]);
        assert!(player["after_play"].as_u64().unwrap() >= 1, "playing advances: {player}");
        for (error, painted) in
            player["max_error_px"].as_array().unwrap().iter().zip(player["painted_centres"].as_array().unwrap())
        {
            let error = error.as_f64().expect("as many disks drawn as stored");
            assert!(error < 0.1, "drawn within 0.1 px of the stored disks: {player}");
            assert_eq!(painted.as_f64(), Some(1.0), "the canvas is painted at every disk's centre: {player}");
        }
    }
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
