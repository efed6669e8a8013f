//! Charts of one run: pixel sizes, disks at their recorded positions, NaN-tolerant histories.

#[allow(dead_code)]
mod plot_helpers;

use demsweep::physics::RunStatus;
use demsweep::physics::record::History;
use demsweep::plot::run::{self, ColourBy, ColourScale};
use demsweep::plot::{ChartOptions, Format};
use plot_helpers::{number, out_dir, png_size, run as run_tiny, svg_elements, tiny_scene};

/// The lowest and highest colours of plotters' viridis table, as SVG writes them.
const VIRIDIS_LOW: &str = "#440154";
const VIRIDIS_HIGH: &str = "#FEE825";

/// The UBF chart's marks of a scene without stages.
fn marks(threshold: f64, settle_time: Option<f64>) -> run::UbfMarks<'static> {
    run::UbfMarks { threshold, settle_time, stage_ends: &[] }
}

fn options(width: u32, height: u32, format: Format) -> ChartOptions {
    ChartOptions { width, height, format, subject: Some("test run".into()), ..Default::default() }
}

#[test]
fn png_charts_have_the_requested_pixel_size() {
    let scene = tiny_scene(0.5, 1e-5);
    let record = run_tiny(&scene);
    let dir = out_dir("png_sizes");
    let frame = &record.frames[1];
    let scale = ColourScale::fitted(ColourBy::Speed, [frame]);
    for (width, height) in [(1000, 700), (640, 480), (1600, 1200)] {
        let opts = options(width, height, Format::Png);
        let energy = dir.join(format!("energy_{width}.png"));
        let ubf = dir.join(format!("ubf_{width}.png"));
        let pile = dir.join(format!("pile_{width}.png"));
        run::energy_chart(&record.history, &[], &opts, &energy).unwrap();
        run::ubf_chart(&record.history, marks(scene.settle.ubf_threshold, record.settle_time), &opts, &ubf).unwrap();
        run::snapshot(frame, (scene.domain.width, scene.domain.height), &scale, &opts, &pile).unwrap();
        for path in [energy, ubf, pile] {
            assert_eq!(png_size(&path), (width, height), "{}", path.display());
        }
    }
    assert_eq!(ChartOptions::default().width, 1000);
    assert_eq!(ChartOptions::default().height, 700);
}

#[test]
fn svg_snapshot_has_one_circle_per_disk_at_its_recorded_position() {
    let scene = tiny_scene(0.5, 1e-5);
    let record = run_tiny(&scene);
    let frame = &record.frames[1];
    assert_eq!(frame.time, 0.1);
    let dir = out_dir("svg_snapshot");
    let path = dir.join("pile.svg");
    let scale = ColourScale::fitted(ColourBy::Speed, [frame]);
    let box_size = (scene.domain.width, scene.domain.height);
    let placed = run::snapshot(frame, box_size, &scale, &options(1000, 700, Format::Svg), &path).unwrap();

    // To scale: a metre spans the same number of pixels along x and y.
    let (per_x, per_y) = placed.pixels_per_metre;
    assert!((per_x - per_y).abs() <= 0.01 * per_x, "x {per_x} vs y {per_y} pixels per metre");

    let circles = svg_elements(&path, "circle");
    assert_eq!(circles.len(), frame.x.len(), "one circle per disk");
    for (i, circle) in circles.iter().enumerate() {
        let (px, py) = placed.to_pixel(frame.x[i], frame.y[i]);
        assert!((number(circle, "cx") - px).abs() <= 1.0, "disk {i}: cx {} vs {px}", circle["cx"]);
        assert!((number(circle, "cy") - py).abs() <= 1.0, "disk {i}: cy {} vs {py}", circle["cy"]);
        assert!((number(circle, "r") - frame.r[i] * per_x).abs() <= 1.0, "disk {i}: r {}", circle["r"]);
    }

    // The box walls (the only black 3-pixel-wide path) run through the frame's corners.
    let black_3px =
        |p: &std::collections::HashMap<String, String>| p["stroke-width"] == "3" && p["stroke"] == "#000000";
    let walls: Vec<_> = svg_elements(&path, "polyline").into_iter().filter(black_3px).collect();
    assert_eq!(walls.len(), 1);
    let corners: Vec<(f64, f64)> = walls[0]["points"]
        .split_whitespace()
        .map(|p| p.split_once(',').map(|(x, y)| (x.parse().unwrap(), y.parse().unwrap())).unwrap())
        .collect();
    let (w, h) = box_size;
    let expected = [(0.0, h), (0.0, 0.0), (w, 0.0), (w, h)].map(|(x, y)| placed.to_pixel(x, y));
    assert_eq!(corners.len(), 4);
    for (got, want) in corners.iter().zip(expected) {
        assert!((got.0 - want.0).abs() <= 1.0 && (got.1 - want.1).abs() <= 1.0, "wall corner {got:?} vs {want:?}");
    }
}

#[test]
fn force_chains_are_lines_between_centres_as_wide_as_the_normal_force() {
    let scene = tiny_scene(0.3, 1e-5);
    let record = run_tiny(&scene);
    let pile = &record.final_state;
    let dir = out_dir("force_chains");
    let path = dir.join("pile.svg");
    let scale = ColourScale::fitted(ColourBy::Speed, [pile]);
    let box_size = (scene.domain.width, scene.domain.height);
    let placed = run::snapshot(pile, box_size, &scale, &options(1000, 700, Format::Svg), &path).unwrap();
    let red = format!("#{:02X}{:02X}{:02X}", run::CHAIN_COLOUR.0, run::CHAIN_COLOUR.1, run::CHAIN_COLOUR.2);
    let chains: Vec<_> = svg_elements(&path, "polyline").into_iter().filter(|p| p["stroke"] == red).collect();
    let c = &pile.contacts;
    assert!(c.len() > 20 && !chains.is_empty(), "{} contacts, {} chain lines", c.len(), chains.len());
    let largest = c.normal_force.iter().copied().fold(0.0, f64::max);
    let mut widths = Vec::new();
    for chain in &chains {
        let ends: Vec<(f64, f64)> = chain["points"]
            .split_whitespace()
            .map(|p| p.split_once(',').map(|(x, y)| (x.parse().unwrap(), y.parse().unwrap())).unwrap())
            .collect();
        let near = |at: (f64, f64), (x, y): (f64, f64)| {
            let (px, py) = placed.to_pixel(x, y);
            (px - at.0).abs() <= 1.0 && (py - at.1).abs() <= 1.0
        };
        let k = (0..c.len())
            .find(|&k| {
                let i = c.first[k] as usize;
                let far = usize::try_from(c.second[k]).map_or((c.point_x[k], c.point_y[k]), |j| (pile.x[j], pile.y[j]));
                near(ends[0], (pile.x[i], pile.y[i])) && near(ends[1], far)
            })
            .expect("a chain line joins the two bodies of a contact");
        widths.push((c.normal_force[k], number(chain, "stroke-width")));
    }
    let widest = widths.iter().map(|w| w.1).fold(0.0, f64::max);
    for (force, width) in &widths {
        // width = round(W F / F_max), the widest round(W): within a pixel of widest · F / F_max.
        assert!((width - widest * force / largest).abs() <= 1.0, "{force} N: {width} px of {widest}");
    }
}

/// The frames of an (A)PNG file as RGB pixels, and its animation's frame count (`None`: a still).
fn png_frames(path: &std::path::Path) -> (Option<u32>, Vec<Vec<u8>>) {
    let mut reader = png::Decoder::new(std::fs::File::open(path).unwrap()).read_info().unwrap();
    let animated = reader.info().animation_control().map(|a| a.num_frames);
    let mut frames = Vec::new();
    let mut pixels = vec![0; reader.output_buffer_size()];
    while reader.next_frame(&mut pixels).is_ok() {
        frames.push(pixels.clone());
    }
    (animated, frames)
}

#[test]
fn the_deposition_animation_plays_each_snapshot_as_drawn_alone() {
    let scene = tiny_scene(0.5, 1e-5);
    let record = run_tiny(&scene);
    let dir = out_dir("animation");
    let box_size = (scene.domain.width, scene.domain.height);
    let mut snapshots: Vec<_> = record.frames.iter().collect();
    snapshots.push(&record.final_state);
    let scale = ColourScale::fitted(ColourBy::Speed, snapshots.iter().copied());
    let scaled: Vec<_> = snapshots.iter().map(|s| (*s, scale)).collect();
    let opts = options(640, 480, Format::Png);
    let path = dir.join("deposition.png");
    run::animation(&scaled, box_size, &opts, &path).unwrap();
    let (animated, frames) = png_frames(&path);
    assert_eq!(animated, Some(snapshots.len() as u32));
    assert_eq!(frames.len(), snapshots.len());
    for (k, snapshot) in snapshots.iter().enumerate() {
        let still = dir.join(format!("still_{k}.png"));
        run::snapshot(snapshot, box_size, &scale, &opts, &still).unwrap();
        let (not_animated, still_frames) = png_frames(&still);
        assert_eq!(not_animated, None);
        assert!(frames[k] == still_frames[0], "frame {k} differs from its still picture");
    }
}

#[test]
fn disks_are_coloured_on_the_scale() {
    let scene = tiny_scene(0.5, 1e-5);
    let record = run_tiny(&scene);
    let dir = out_dir("colours");
    let box_size = (scene.domain.width, scene.domain.height);
    let svg = options(1000, 700, Format::Svg);

    let frame = &record.frames[1];
    let speeds = ColourBy::Speed.values(frame);
    let fastest = (0..speeds.len()).max_by(|a, b| speeds[*a].total_cmp(&speeds[*b])).unwrap();
    let path = dir.join("speed.svg");
    run::snapshot(frame, box_size, &ColourScale::fitted(ColourBy::Speed, [frame]), &svg, &path).unwrap();
    let circles = svg_elements(&path, "circle");
    assert_eq!(circles[fastest]["fill"], VIRIDIS_HIGH);
    let distinct: std::collections::HashSet<&str> = circles.iter().map(|c| c["fill"].as_str()).collect();
    assert!(distinct.len() > 5, "speeds spread over the scale: {distinct:?}");

    // At t = 0 no disk touches another: every contact force is zero, the bottom of the scale.
    let start = &record.frames[0];
    let path = dir.join("force.svg");
    run::snapshot(start, box_size, &ColourScale::fitted(ColourBy::ContactForce, [start]), &svg, &path).unwrap();
    assert!(svg_elements(&path, "circle").iter().all(|c| c["fill"] == VIRIDIS_LOW));
}

/// Polylines drawn in the first series colour (the UBF line and its legend sample).
fn ubf_polylines(path: &std::path::Path) -> Vec<usize> {
    svg_elements(path, "polyline")
        .iter()
        .filter(|p| p["stroke"] == "#1F77B4")
        .map(|p| p["points"].split_whitespace().count())
        .collect()
}

#[test]
fn ubf_chart_leaves_out_samples_without_contacts_and_zeros() {
    let time: Vec<f64> = (0..10).map(|i| f64::from(i) * 0.01).collect();
    let nan = f64::NAN;
    let ratio = vec![nan, nan, 0.5, 0.2, 0.0, 0.1, 0.05, nan, 0.02, 0.01];
    let history = History { time, unbalanced_force_ratio: ratio, ..Default::default() };
    let dir = out_dir("ubf_gaps");
    let path = dir.join("ubf.svg");
    run::ubf_chart(&history, marks(0.03, Some(0.08)), &options(1000, 700, Format::Svg), &path).unwrap();
    // Three stretches of two samples each, then the two-point legend sample.
    assert_eq!(ubf_polylines(&path), vec![2, 2, 2, 2]);

    let no_contacts = History { unbalanced_force_ratio: vec![nan; 10], ..history };
    let path = dir.join("ubf_no_contacts.svg");
    run::ubf_chart(&no_contacts, marks(0.03, None), &options(1000, 700, Format::Svg), &path).unwrap();
    assert!(ubf_polylines(&path).is_empty());
}

#[test]
fn ubf_chart_marks_where_a_protocols_stages_end() {
    let time: Vec<f64> = (0..10).map(|i| f64::from(i) * 0.01).collect();
    let ratio = vec![0.9, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.004, 0.003];
    let history = History { time, unbalanced_force_ratio: ratio, ..Default::default() };
    let dir = out_dir("ubf_stages");
    let with = |stage_ends: &[(String, f64)], name: &str| {
        let path = dir.join(name);
        let marks = run::UbfMarks { stage_ends, ..marks(0.01, Some(0.06)) };
        run::ubf_chart(&history, marks, &options(1000, 700, Format::Svg), &path).unwrap();
        std::fs::read_to_string(path).unwrap()
    };
    let staged = with(&[("fill".into(), 0.02), ("calm".into(), 0.035)], "staged.svg");
    assert!(staged.contains("stage fill ends at 0.02 s") && staged.contains("stage calm ends at 0.035 s"), "{staged}");
    let cut_short = with(&[("fill".into(), 0.02), ("calm".into(), f64::NAN)], "cut_short.svg");
    assert!(cut_short.contains("stage fill ends") && !cut_short.contains("stage calm"));
    assert!(!with(&[], "plain.svg").contains("ends at"));
}

#[test]
fn energy_chart_marks_where_a_protocols_stages_end() {
    let time: Vec<f64> = (0..10).map(|i| f64::from(i) * 0.01).collect();
    let falling: Vec<f64> = (0..10).map(|i| 1.0 - f64::from(i) * 0.1).collect();
    let history = History {
        kinetic_translational: falling.clone(),
        kinetic_rotational: vec![0.0; 10],
        potential: falling.clone(),
        elastic: vec![0.01; 10],
        total: falling.iter().map(|v| 2.0 * v).collect(),
        time,
        ..Default::default()
    };
    let dir = out_dir("energy_stages");
    let with = |stage_ends: &[(String, f64)], name: &str| {
        let path = dir.join(name);
        run::energy_chart(&history, stage_ends, &options(1000, 700, Format::Svg), &path).unwrap();
        std::fs::read_to_string(path).unwrap()
    };
    let staged = with(&[("fill".into(), 0.02), ("slip".into(), 0.035)], "staged.svg");
    assert!(staged.contains("stage fill ends at 0.02 s") && staged.contains("stage slip ends at 0.035 s"), "{staged}");
    let cut_short = with(&[("fill".into(), 0.02), ("slip".into(), f64::NAN)], "cut_short.svg");
    assert!(cut_short.contains("stage fill ends") && !cut_short.contains("stage slip"));
    // The ended stage's mark: dashes at one time, down both panels (the linear one takes the upper
    // 60 % of the height), besides its legend sample.
    let plain = with(&[], "plain.svg");
    assert!(!plain.contains("ends at"));
    let points = |line: &str| -> Vec<(f64, f64)> {
        let list = line.split("points=\"").nth(1).unwrap().split('"').next().unwrap();
        list.split_whitespace()
            .map(|p| p.split_once(',').unwrap())
            .map(|(x, y)| (x.parse().unwrap(), y.parse().unwrap()))
            .collect()
    };
    let added: Vec<Vec<(f64, f64)>> =
        cut_short.lines().filter(|l| l.starts_with("<polyline") && !plain.contains(*l)).map(points).collect();
    let dashes: Vec<&(f64, f64)> = added.iter().filter(|p| p.iter().all(|q| q.0 == p[0].0)).flatten().collect();
    assert!(dashes.iter().all(|p| p.0 == dashes[0].0), "one time: {dashes:?}");
    let split = 0.6 * 700.0;
    assert!(dashes.iter().any(|p| p.1 < split) && dashes.iter().any(|p| p.1 > split), "both panels: {dashes:?}");
}

#[test]
fn diverged_run_plots_without_panicking() {
    let scene = tiny_scene(0.5, 1e-3);
    let mut record = run_tiny(&scene);
    assert_eq!(record.status, RunStatus::Diverged);
    // Worse than the run itself: non-finite samples and a disk thrown to infinity.
    record.history.potential.push(f64::INFINITY);
    record.history.kinetic_translational.push(f64::NAN);
    record.history.time.push(f64::NAN);
    record.final_state.x[0] = f64::NAN;
    let dir = out_dir("diverged");
    let opts = options(800, 600, Format::Png);
    let box_size = (scene.domain.width, scene.domain.height);
    let scale = ColourScale::fitted(ColourBy::ContactForce, [&record.final_state]);
    run::energy_chart(&record.history, &[], &opts, &dir.join("energy.png")).unwrap();
    run::ubf_chart(&record.history, marks(scene.settle.ubf_threshold, None), &opts, &dir.join("ubf.png")).unwrap();
    run::snapshot(&record.final_state, box_size, &scale, &opts, &dir.join("pile.png")).unwrap();
    for name in ["energy.png", "ubf.png", "pile.png"] {
        assert_eq!(png_size(&dir.join(name)), (800, 600));
    }
    let svg = dir.join("pile.svg");
    run::snapshot(&record.final_state, box_size, &scale, &options(800, 600, Format::Svg), &svg).unwrap();
    assert_eq!(svg_elements(&svg, "circle").len(), record.final_state.x.len() - 1, "the NaN disk is left out");

    let empty = History::default();
    run::energy_chart(&empty, &[], &opts, &dir.join("empty_energy.png")).unwrap();
    run::ubf_chart(&empty, marks(0.01, None), &opts, &dir.join("empty_ubf.png")).unwrap();
}

#[test]
fn too_small_an_image_is_an_error_naming_the_file() {
    let dir = out_dir("too_small");
    let path = dir.join("energy.png");
    let err = run::energy_chart(&History::default(), &[], &options(100, 80, Format::Png), &path).unwrap_err();
    let message = err.to_string();
    assert!(message.contains("energy.png") && message.contains("100x80"), "{message}");
    assert!(!path.exists());
}
