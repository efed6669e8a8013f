//! Charts of a study: heatmap cells, settle-time lines, diverged and not-settled runs marked.

#[allow(dead_code)]
mod plot_helpers;

use demsweep::physics::RunStatus;
use demsweep::plot::study::{self, CellState};
use demsweep::plot::{ChartOptions, Format, StudyPoint};
use plot_helpers::{number, out_dir, png_size, run, svg_elements, tiny_scene};

const RESTITUTION: &str = "material.restitution";
const TIME_STEP: &str = "integrator.time_step";
/// Colours the charts use for diverged runs (crosses, cell fill) and not-settled runs (hollow circles).
const DIVERGED_STROKE: &str = "#C81414";
const DIVERGED_FILL: &str = "#FAC8C8";
const NOT_SETTLED_STROKE: &str = "#8C8C8C";

fn svg() -> ChartOptions {
    ChartOptions { format: Format::Svg, subject: Some("test study".into()), ..Default::default() }
}

/// A real 3 x 3 study: restitution x time step, the largest step diverging.
fn grid_study() -> Vec<StudyPoint> {
    let mut points = Vec::new();
    for restitution in [0.3, 0.6, 0.9] {
        for time_step in [1e-5, 5e-5, 1e-3] {
            let record = run(&tiny_scene(restitution, time_step));
            let parameters = vec![(RESTITUTION.to_string(), restitution), (TIME_STEP.to_string(), time_step)];
            points.push(StudyPoint { parameters, status: record.status, settle_time: record.settle_time });
        }
    }
    points
}

fn point(restitution: f64, time_step: f64, status: RunStatus, settle_time: Option<f64>) -> StudyPoint {
    let parameters = vec![(RESTITUTION.to_string(), restitution), (TIME_STEP.to_string(), time_step)];
    StudyPoint { parameters, status, settle_time }
}

#[test]
fn heatmap_has_one_cell_per_grid_point() {
    let points = grid_study();
    assert!(points.iter().filter(|p| p.parameter(TIME_STEP) == Some(1e-3)).all(|p| p.status == RunStatus::Diverged));
    let path = out_dir("heatmap").join("heatmap.svg");
    let cells = study::settle_time_heatmap(&points, RESTITUTION, TIME_STEP, &svg(), &path).unwrap();
    assert_eq!(cells.len(), 9);

    let rects = svg_elements(&path, "rect");
    let geometry =
        |r: &std::collections::HashMap<String, String>| ["x", "y", "width", "height"].map(|k| number(r, k) as i32);
    let [(x0, y0), (x1, y1)] = cells[0].pixels;
    let cell_sized = |r: &[i32; 4]| (r[2] - (x1 - x0)).abs() <= 1 && (r[3] - (y1 - y0)).abs() <= 1;
    assert_eq!(rects.iter().map(geometry).filter(cell_sized).count(), 9, "one cell-sized rectangle per grid point");
    for cell in &cells {
        let [(x0, y0), (x1, y1)] = cell.pixels;
        let drawn: Vec<_> = rects.iter().filter(|r| geometry(r) == [x0, y0, x1 - x0, y1 - y0]).collect();
        assert_eq!(drawn.len(), 1, "cell at ({}, {})", cell.x, cell.y);
        let run =
            points.iter().find(|p| p.parameter(RESTITUTION) == Some(cell.x) && p.parameter(TIME_STEP) == Some(cell.y));
        let run = run.unwrap();
        assert_eq!(cell.runs, 1);
        match cell.state {
            CellState::Diverged => {
                assert_eq!(run.status, RunStatus::Diverged);
                assert_eq!(drawn[0]["fill"], DIVERGED_FILL);
            }
            CellState::Settled(t) => assert_eq!(Some(t), run.settle_time),
            CellState::NotSettled => assert_ne!(run.status, RunStatus::Settled),
        }
    }
    // Larger x to the right, larger y further up.
    let at = |x: f64, y: f64| cells.iter().find(|c| c.x == x && c.y == y).unwrap().pixels[0];
    assert!(at(0.9, 1e-5).0 > at(0.3, 1e-5).0);
    assert!(at(0.3, 1e-3).1 < at(0.3, 5e-5).1 && at(0.3, 5e-5).1 < at(0.3, 1e-5).1);
}

#[test]
fn heatmap_cell_of_replicates_shows_their_mean_or_their_worst_end() {
    let points = vec![
        point(0.3, 1e-5, RunStatus::Settled, Some(0.2)),
        point(0.3, 1e-5, RunStatus::Settled, Some(0.4)),
        point(0.9, 1e-5, RunStatus::Settled, Some(0.3)),
        point(0.9, 1e-5, RunStatus::Diverged, None),
        point(0.3, 1e-4, RunStatus::Settled, Some(0.3)),
        point(0.3, 1e-4, RunStatus::NotSettled, None),
        point(0.9, 1e-4, RunStatus::Interrupted, None),
    ];
    let path = out_dir("heatmap_replicates").join("heatmap.png");
    let cells = study::settle_time_heatmap(&points, RESTITUTION, TIME_STEP, &ChartOptions::default(), &path).unwrap();
    let state = |x: f64, y: f64| cells.iter().find(|c| c.x == x && c.y == y).map(|c| (c.state, c.runs));
    assert!(matches!(state(0.3, 1e-5), Some((CellState::Settled(t), 2)) if (t - 0.3).abs() < 1e-12));
    // 95 % half-width of 0.2 and 0.4: t(0.975, 1) · s / √2 with s = 0.1 √2.
    let half_width = |x: f64, y: f64| cells.iter().find(|c| c.x == x && c.y == y).and_then(|c| c.half_width_95);
    assert!((half_width(0.3, 1e-5).unwrap() - 12.7062 * 0.1).abs() < 1e-4);
    assert_eq!((half_width(0.9, 1e-5), half_width(0.3, 1e-4)), (None, None), "no interval without a settle time");
    assert_eq!(state(0.9, 1e-5), Some((CellState::Diverged, 2)));
    assert_eq!(state(0.3, 1e-4), Some((CellState::NotSettled, 2)));
    assert_eq!(state(0.9, 1e-4), Some((CellState::NotSettled, 1)));
    assert_eq!(png_size(&path), (1000, 700));
}

#[test]
fn settle_time_lines_mark_every_run_without_a_settle_time() {
    let points = grid_study();
    let path = out_dir("lines").join("lines.svg");
    study::settle_time_lines(&points, RESTITUTION, Some(TIME_STEP), &svg(), &path).unwrap();

    // A cross is two strokes; one more cross is the legend's sample.
    let diverged = points.iter().filter(|p| p.status == RunStatus::Diverged).count();
    let cross_strokes = svg_elements(&path, "line").iter().filter(|l| l["stroke"] == DIVERGED_STROKE).count();
    assert_eq!(cross_strokes, 2 * (diverged + 1));
    let unsettled = points.iter().filter(|p| p.status != RunStatus::Settled && p.status != RunStatus::Diverged).count();
    let hollow = svg_elements(&path, "circle").iter().filter(|c| c["stroke"] == NOT_SETTLED_STROKE).count();
    assert_eq!(hollow, if unsettled > 0 { unsettled + 1 } else { 0 });

    // Per time step: a dot per settled run (radius 3) and a line vertex per restitution where some
    // run settled (a ring of radius 4), in the series' colour.
    let circles = svg_elements(&path, "circle");
    for (colour, time_step) in [("#1F77B4", 1e-5), ("#FF7F0E", 5e-5), ("#2CA02C", 1e-3)] {
        let settled: Vec<f64> = points
            .iter()
            .filter(|p| p.parameter(TIME_STEP) == Some(time_step) && p.status == RunStatus::Settled)
            .map(|p| p.parameter(RESTITUTION).unwrap())
            .collect();
        let mut vertices = settled.clone();
        vertices.dedup();
        let count = |key: &str, radius: &str| circles.iter().filter(|c| c[key] == colour && c["r"] == radius).count();
        assert_eq!(count("fill", "3"), settled.len(), "time step {time_step}");
        assert_eq!(count("stroke", "4"), vertices.len(), "time step {time_step}");
    }
}

#[test]
fn settle_time_lines_join_the_mean_of_replicates() {
    // 0.2 and 0.4 at x = 0.3 average to 0.3, the settle time at x = 0.9: the line is level.
    let points = vec![
        point(0.3, 1e-5, RunStatus::Settled, Some(0.2)),
        point(0.3, 1e-5, RunStatus::Settled, Some(0.4)),
        point(0.9, 1e-5, RunStatus::Settled, Some(0.3)),
    ];
    let path = out_dir("lines_mean").join("lines.svg");
    study::settle_time_lines(&points, RESTITUTION, None, &svg(), &path).unwrap();
    let line = svg_elements(&path, "polyline")
        .into_iter()
        .find(|l| l["stroke"] == "#1F77B4" && l["stroke-width"] == "2" && l["points"].split_whitespace().count() == 2)
        .expect("the mean line");
    let rows: Vec<&str> = line["points"].split_whitespace().map(|p| p.split_once(',').unwrap().1).collect();
    assert_eq!(rows[0], rows[1], "level line: {}", line["points"]);
    // An error bar (a vertical stroke and two caps) at x = 0.3, with two runs, none at x = 0.9.
    let ends = |l: &std::collections::HashMap<String, String>| -> Vec<(f64, f64)> {
        let xy = |p: &str| p.split_once(',').map(|(x, y)| (x.parse().unwrap(), y.parse().unwrap())).unwrap();
        l["points"].split_whitespace().map(xy).collect()
    };
    let strokes: Vec<Vec<(f64, f64)>> =
        svg_elements(&path, "polyline").iter().filter(|l| l["stroke"] == "#1F77B4").map(ends).collect();
    let vertical: Vec<&Vec<(f64, f64)>> = strokes.iter().filter(|e| e.len() == 2 && e[0].0 == e[1].0).collect();
    assert_eq!(vertical.len(), 1, "{strokes:?}");
    let caps = strokes.iter().filter(|e| e.len() == 2 && e[0].1 == e[1].1 && e[0].0 != e[1].0).count();
    assert_eq!(caps, 2 + 2, "two caps, the level mean line and its legend sample");
    let mean_row: f64 = rows[0].parse().unwrap();
    let (top, bottom) = (vertical[0][0].1.min(vertical[0][1].1), vertical[0][0].1.max(vertical[0][1].1));
    assert!(top < mean_row && mean_row < bottom, "the bar spans the mean ({top} < {mean_row} < {bottom})");
}

#[test]
fn study_of_only_diverged_runs_plots() {
    let points: Vec<StudyPoint> = [0.3, 0.6, 0.9].iter().map(|&e| point(e, 1e-3, RunStatus::Diverged, None)).collect();
    let dir = out_dir("all_diverged");
    let png = ChartOptions::default();
    study::settle_time_lines(&points, RESTITUTION, Some(TIME_STEP), &png, &dir.join("lines.png")).unwrap();
    let cells = study::settle_time_heatmap(&points, RESTITUTION, TIME_STEP, &png, &dir.join("heatmap.png")).unwrap();
    assert_eq!(cells.len(), 3);
    assert!(cells.iter().all(|c| c.state == CellState::Diverged));
    assert_eq!(png_size(&dir.join("lines.png")), (1000, 700));
    assert_eq!(png_size(&dir.join("heatmap.png")), (1000, 700));
}

#[test]
fn plotting_against_an_unswept_parameter_names_it() {
    let points = vec![point(0.3, 1e-5, RunStatus::Settled, Some(0.2))];
    let path = out_dir("unswept").join("lines.png");
    let err =
        study::settle_time_lines(&points, "material.friction", None, &ChartOptions::default(), &path).unwrap_err();
    assert!(err.to_string().contains("'material.friction'"), "{err}");
    let err = study::settle_time_heatmap(&points, RESTITUTION, "seed", &ChartOptions::default(), &path).unwrap_err();
    assert!(err.to_string().contains("'seed'"), "{err}");
}

/// 2 restitutions x 2 frictions x 3 placement seeds of 120 disks of radius 5 mm, run until settled:
/// a grid whose points have intervals and piles deep enough for an interior.
const REPLICATED_STUDY: &str = r#"name = "replicated"
[scene]
particles.count = 120
particles.radius = 0.005
domain.width = 0.16
domain.height = 0.2
run.duration = 1.5
run.stop_at_settle = true
settle.ubf_threshold = 0.05
settle.hold_time = 0.02
[sweep]
"material.restitution" = [0.2, 0.8]
"material.friction" = [0.2, 0.6]
replicates = 3
"#;

/// Series colours of the charts, in order of the series values.
const SERIES_COLOURS: [&str; 2] = ["#1F77B4", "#FF7F0E"];

/// The ends of an SVG polyline.
fn polyline_ends(line: &std::collections::HashMap<String, String>) -> Vec<(f64, f64)> {
    let xy = |p: &str| p.split_once(',').map(|(x, y)| (x.parse().unwrap(), y.parse().unwrap())).unwrap();
    line["points"].split_whitespace().map(xy).collect()
}

#[test]
fn pile_metric_charts_put_each_point_and_its_interval_where_the_points_table_says() {
    let dir = out_dir("pile_metrics");
    let study = dir.join("replicated.toml");
    std::fs::write(&study, REPLICATED_STUDY).unwrap();
    let demsweep =
        |args: &[&str]| std::process::Command::new(env!("CARGO_BIN_EXE_demsweep")).args(args).output().unwrap();
    let run = demsweep(&["run", study.to_str().unwrap(), "--out", dir.to_str().unwrap(), "--progress", "quiet"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let results = dir.join("replicated.h5");
    let plots = dir.join("svg");
    let plot = demsweep(&["plot", results.to_str().unwrap(), "--format", "svg", "--out", plots.to_str().unwrap()]);
    assert!(plot.status.success(), "{}", String::from_utf8_lossy(&plot.stderr));
    let table = demsweep::stats::points::read(&results).unwrap();
    let column = |name: &str| {
        let data = &table.column(name).unwrap_or_else(|| panic!("/points has {name}")).data;
        (0..table.len()).map(|row| data.number(row).unwrap_or(f64::NAN)).collect::<Vec<f64>>()
    };
    const FRICTION: &str = "material.friction";
    let mut checked = 0;
    for (axis, colour_axis) in [(RESTITUTION, FRICTION), (FRICTION, RESTITUTION)] {
        for metric in demsweep::physics::quantity::charted() {
            let path = plots.join(format!("{metric}_vs_{axis}.svg"));
            if metric == "settle_time" && axis == RESTITUTION {
                assert!(!path.exists(), "settle time against the first axis is the settle-time chart");
                continue;
            }
            let (x, series) = (column(axis), column(colour_axis));
            let (mean, half) = (column(&format!("{metric}_mean")), column(&format!("{metric}_ci95")));
            let circles = svg_elements(&path, "circle");
            let lines = svg_elements(&path, "polyline");
            // Markers: rings of radius 4 in the series colour, left to right; each with its error bar.
            let mut drawn = Vec::new(); // (pixel row of mean, low end, high end) against (mean, low, high)
            let mut steps = Vec::new(); // pixel distance between the two x values, per series
            for (colour, value) in SERIES_COLOURS.iter().zip([0.2, if colour_axis == FRICTION { 0.6 } else { 0.8 }]) {
                let mut expected: Vec<usize> =
                    (0..table.len()).filter(|&p| series[p] == value && mean[p].is_finite()).collect();
                assert_eq!(expected.len(), 2, "{metric}: finite means at both {axis} values of {colour}");
                expected.sort_by(|&a, &b| x[a].total_cmp(&x[b]));
                let mut markers: Vec<(f64, f64)> = circles
                    .iter()
                    .filter(|c| c.get("stroke").map(String::as_str) == Some(colour) && c["r"] == "4")
                    .map(|c| (number(c, "cx"), number(c, "cy")))
                    .collect();
                markers.sort_by(|a, b| a.0.total_cmp(&b.0));
                assert_eq!(markers.len(), expected.len(), "{metric} vs {axis}: a marker per point of {colour}");
                steps.push(markers[1].0 - markers[0].0);
                for (&(cx, cy), &p) in markers.iter().zip(&expected) {
                    let bar = lines
                        .iter()
                        .filter(|l| l["stroke"] == *colour)
                        .map(polyline_ends)
                        .find(|e| e.len() == 2 && e[0].0 == e[1].0 && (e[0].0 - cx).abs() <= 1.0)
                        .unwrap_or_else(|| panic!("{metric} vs {axis}: an interval at column {cx}"));
                    let (top, bottom) = (bar[0].1.min(bar[1].1), bar[0].1.max(bar[1].1));
                    drawn.push(([cy, bottom, top], [mean[p], mean[p] - half[p], mean[p] + half[p]]));
                }
            }
            assert!(steps[1] > 0.0 && (steps[0] - steps[1]).abs() <= 1.5, "one x scale for all series: {steps:?}");
            // One linear map from value to pixel row takes every mean and interval end where it was drawn.
            let pairs: Vec<(f64, f64)> =
                drawn.iter().flat_map(|(px, v)| v.iter().copied().zip(px.iter().copied())).collect();
            let (low, high) = (
                pairs.iter().copied().min_by(|a, b| a.0.total_cmp(&b.0)).unwrap(),
                pairs.iter().copied().max_by(|a, b| a.0.total_cmp(&b.0)).unwrap(),
            );
            let slope = (high.1 - low.1) / (high.0 - low.0);
            assert!(slope < 0.0, "{metric} vs {axis}: larger values higher up");
            for (value, row) in pairs {
                let expected = low.1 + (value - low.0) * slope;
                assert!(
                    (row - expected).abs() <= 1.5,
                    "{metric} vs {axis}: {value} drawn at row {row}, not {expected}"
                );
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 2 * demsweep::physics::quantity::charted().count() - 1);
}
