//! `demsweep plot` on a real results file written by `demsweep run`: a tiny 3 x 2 study whose larger
//! time step diverges.

#[allow(dead_code)]
mod plot_helpers;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use demsweep::output::stored::{self, StoredRun};
use demsweep::output::{SummaryRow, reader};
use demsweep::physics::RunStatus;
use demsweep::physics::quantity;
use plot_helpers::{number, out_dir, png_size, svg_elements};

/// 40 disks of radius 1 cm in a 0.2 m x 0.3 m box, restitution 0.3, 0.6, 0.9 x time step 1e-5 s
/// (settles) and 1e-3 s (diverges); frames at 0, 0.1 and 0.2 s.
const STUDY: &str = r#"
name = "tiny"

[scene.domain]
width = 0.2
height = 0.3

[scene.particles]
count = 40
radius = 0.01

[scene.integrator]
time_step = 1e-5

[scene.run]
duration = 0.7
frame_times = [0.0, 0.1, 0.2]

[scene.settle]
ubf_threshold = 0.05
hold_time = 0.02

[sweep]
"material.restitution" = [0.3, 0.6, 0.9]
"integrator.time_step" = [1e-5, 1e-3]
"#;

/// Fill colour of a diverged heatmap cell.
const DIVERGED_FILL: &str = "#FAC8C8";

fn demsweep(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_demsweep")).args(args).output().expect("demsweep runs")
}

fn text(output: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr))
}

/// Runs the tiny study in a fresh folder `name`; returns the results file.
fn run_study(name: &str) -> PathBuf {
    let dir = out_dir(name);
    let study = dir.join("tiny.toml");
    std::fs::write(&study, STUDY).unwrap();
    let out = dir.join("results");
    let run = demsweep(&["run", study.to_str().unwrap(), "--out", out.to_str().unwrap(), "--progress", "quiet"]);
    // Some runs diverge by design: a partial sweep's exit status.
    assert_eq!(run.status.code(), Some(demsweep::runner::EXIT_PARTIAL), "{}", text(&run));
    out.join("tiny.h5")
}

/// The stored runs of a results file with their summary rows.
fn stored_runs(results: &Path) -> Vec<(SummaryRow, StoredRun)> {
    let file = reader::open(results).unwrap();
    let rows = reader::rows(&file, results).unwrap();
    rows.into_iter().map(|row| (row.clone(), stored::read_run(&file, results, &row).unwrap())).collect()
}

fn file_names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

#[test]
fn plots_every_run_and_the_study_at_the_requested_size_diverged_runs_included() {
    let results = run_study("cli_png");
    let runs = stored_runs(&results);
    let diverged = runs.iter().filter(|(row, _)| row.status == RunStatus::Diverged).count();
    assert_eq!(diverged, 3, "the 1e-3 s time step diverges");
    assert!(runs.iter().any(|(row, _)| row.status == RunStatus::Settled));

    let plot = demsweep(&["plot", results.to_str().unwrap(), "--width", "800", "--height", "600"]);
    assert!(plot.status.success(), "{}", text(&plot));
    let plots = results.parent().unwrap().join("plots");
    let names = file_names(&plots);
    let mut expected = vec!["settle_time.png".to_string(), "settle_time_heatmap.png".to_string()];
    // Each charted metric against each axis but settle time against the first (the chart above).
    for axis in ["material.restitution", "integrator.time_step"] {
        let metrics = quantity::charted().filter(|m| *m != "settle_time" || axis != "material.restitution");
        expected.extend(metrics.map(|metric| format!("{metric}_vs_{axis}.png")));
    }
    for (row, run) in &runs {
        let frames = run.frames.len();
        assert!(frames >= 1, "{}: frame at t = 0 recorded", row.id);
        expected.extend([format!("{}_energy.png", row.id), format!("{}_ubf.png", row.id)]);
        // The stress profile of every run whose pile has bands (a settled run's always has).
        let bands = run.stress_profile.as_ref().map_or(0, |p| p.bottom.len());
        assert!(bands > 0 || row.status != RunStatus::Settled, "{}: a settled pile has a stress profile", row.id);
        if bands > 0 {
            expected.push(format!("{}_stress_profile.png", row.id));
        }
        expected.extend((0..frames).map(|k| format!("{}_frame_{k:05}.png", row.id)));
        let final_time = run.final_state.as_ref().unwrap().time;
        let with_final = run.frames.last().is_none_or(|frame| (frame.time - final_time).abs() > 1e-9);
        if with_final {
            expected.push(format!("{}_final.png", row.id));
        }
        if frames + usize::from(with_final) > 1 {
            expected.push(format!("{}_deposition.png", row.id)); // the animation of those pictures
        }
    }
    expected.sort();
    assert_eq!(names, expected);
    for name in &names {
        assert_eq!(png_size(&plots.join(name)), (800, 600), "{name}");
    }
    let stdout = String::from_utf8_lossy(&plot.stdout);
    assert_eq!(stdout.lines().filter(|l| l.starts_with("wrote ")).count(), names.len());
    assert!(stdout.contains(&format!("{} files in {}", names.len(), plots.display())), "{stdout}");
}

#[test]
fn svg_snapshot_has_one_circle_per_disk_at_its_recorded_position_to_scale() {
    let results = run_study("cli_svg");
    let svg_dir = results.parent().unwrap().join("svg");
    let plot = demsweep(&["plot", results.to_str().unwrap(), "--format", "svg", "--out", svg_dir.to_str().unwrap()]);
    assert!(plot.status.success(), "{}", text(&plot));
    let (row, run) = stored_runs(&results).into_iter().find(|(row, _)| row.status == RunStatus::Settled).unwrap();
    let snapshots = run.frames.iter().enumerate().map(|(k, s)| (format!("frame_{k:05}"), s));
    for (name, snapshot) in snapshots.chain([("final".to_string(), run.final_state.as_ref().unwrap())]) {
        let circles = svg_elements(&svg_dir.join(format!("{}_{name}.svg", row.id)), "circle");
        assert_eq!(circles.len(), 40, "{name}: one circle per disk");
        // The pixel scale from the two disks farthest apart along x, then every disk checked with it.
        let (left, right) = extremes(&snapshot.x);
        let per_metre =
            (number(&circles[right], "cx") - number(&circles[left], "cx")) / (snapshot.x[right] - snapshot.x[left]);
        let origin_x = number(&circles[left], "cx") - snapshot.x[left] * per_metre;
        let origin_y = number(&circles[left], "cy") + snapshot.y[left] * per_metre;
        for (i, circle) in circles.iter().enumerate() {
            let (px, py) = (origin_x + snapshot.x[i] * per_metre, origin_y - snapshot.y[i] * per_metre);
            assert!((number(circle, "cx") - px).abs() <= 1.5, "{name} disk {i}: cx {} vs {px}", circle["cx"]);
            assert!((number(circle, "cy") - py).abs() <= 1.5, "{name} disk {i}: cy {} vs {py}", circle["cy"]);
            assert!(
                (number(circle, "r") - snapshot.r[i] * per_metre).abs() <= 1.0,
                "{name} disk {i}: r {}",
                circle["r"]
            );
        }
    }
}

/// Indices of the smallest and the largest value.
fn extremes(values: &[f64]) -> (usize, usize) {
    let order = |a: &&f64, b: &&f64| a.total_cmp(b);
    let index_of = |v: &f64| values.iter().position(|x| x == v).unwrap();
    (index_of(values.iter().min_by(order).unwrap()), index_of(values.iter().max_by(order).unwrap()))
}

#[test]
fn heatmap_has_one_cell_per_grid_point_with_the_diverged_ones_marked() {
    let results = run_study("cli_heatmap");
    let out = results.parent().unwrap().join("one_run");
    let plot = demsweep(&[
        "plot",
        results.to_str().unwrap(),
        "--format",
        "svg",
        "--run",
        "r0001",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(plot.status.success(), "{}", text(&plot));
    assert!(
        String::from_utf8_lossy(&plot.stdout)
            .contains("heatmap: 6 cells over material.restitution x integrator.time_step")
    );
    let rects = svg_elements(&out.join("settle_time_heatmap.svg"), "rect");
    let size = |r: &HashMap<String, String>| (number(r, "width"), number(r, "height"));
    // Cells are far larger than the colour bar's strips and the legend swatches, smaller than the image.
    let cells: Vec<_> = rects.iter().filter(|r| size(r).0 > 60.0 && size(r).1 > 60.0 && size(r).0 < 1000.0).collect();
    assert_eq!(cells.len(), 6, "3 restitutions x 2 time steps");
    assert_eq!(cells.iter().filter(|r| r["fill"] == DIVERGED_FILL).count(), 3);
    // Only the named run gets per-run charts.
    let per_run: Vec<String> = file_names(&out).into_iter().filter(|n| n.starts_with('r')).collect();
    assert!(per_run.iter().all(|n| n.starts_with("r0001_")) && per_run.len() >= 4, "{per_run:?}");
}

#[test]
fn an_unknown_run_or_a_missing_file_is_an_error_naming_it() {
    let results = run_study("cli_errors");
    let plot = demsweep(&["plot", results.to_str().unwrap(), "--run", "r0099"]);
    assert!(!plot.status.success());
    assert!(text(&plot).contains("no run `r0099`"), "{}", text(&plot));
    assert!(!results.parent().unwrap().join("plots").exists(), "nothing drawn");
    let plot = demsweep(&["plot", "/no/such/study.h5"]);
    assert!(!plot.status.success());
    assert!(text(&plot).contains("/no/such/study.h5: no such results file"), "{}", text(&plot));
    // A CSV table (such as the summary beside a results file) given in its place is named as one.
    let csv = results.with_file_name("cli_errors_summary.csv");
    std::fs::write(&csv, "run_id,settle_time (s)\nr0000,0.5\n").unwrap();
    let summary = demsweep(&["summary", csv.to_str().unwrap()]);
    assert!(!summary.status.success());
    assert!(
        text(&summary).contains("demsweep reads the HDF5 file (.h5) a run wrote; a .csv file"),
        "{}",
        text(&summary)
    );
}
