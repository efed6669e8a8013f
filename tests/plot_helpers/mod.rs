//! Shared by the plot tests: tiny real runs, an output folder, and reading back PNG and SVG files.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use demsweep::physics::config::SceneConfig;
use demsweep::physics::record::RunRecord;
use demsweep::physics::run_scene;
use demsweep::physics::simulation::Control;

/// A tiny deposition: 40 disks of radius 1 cm dropped into a 0.2 m x 0.3 m box for at most 0.7 s,
/// frames at 0, 0.1 and 0.2 s, with a loose settle criterion so that a stable run settles.
pub fn tiny_scene(restitution: f64, time_step: f64) -> SceneConfig {
    let mut scene = SceneConfig::default();
    scene.particles.count = 40;
    scene.domain.width = 0.2;
    scene.domain.height = 0.3;
    scene.material.restitution = Some(restitution);
    scene.integrator.time_step = Some(time_step);
    scene.run.duration = 0.7;
    scene.run.frame_times = vec![0.0, 0.1, 0.2];
    scene.settle.ubf_threshold = 0.05;
    scene.settle.hold_time = 0.02;
    scene
}

/// Runs `scene` to its end.
pub fn run(scene: &SceneConfig) -> RunRecord {
    run_scene(scene, None, &mut |_| Control::Continue).expect("tiny scene runs")
}

/// A fresh, empty folder for the files of test `name`.
pub fn out_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("plot_tests").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Width and height (pixels) of a PNG file, from its header.
pub fn png_size(path: &Path) -> (u32, u32) {
    let decoder = png::Decoder::new(std::fs::File::open(path).unwrap());
    let info = decoder.read_info().unwrap();
    (info.info().width, info.info().height)
}

/// The attributes of every `<tag .../>` element of an SVG file, in document order.
pub fn svg_elements(path: &Path, tag: &str) -> Vec<HashMap<String, String>> {
    let svg = std::fs::read_to_string(path).unwrap();
    let opening = format!("<{tag} ");
    svg.split(opening.as_str())
        .skip(1)
        .map(|rest| {
            let body = &rest[..rest.find('>').unwrap()];
            body.split('"')
                .collect::<Vec<_>>()
                .chunks(2)
                .filter(|pair| pair.len() == 2)
                .map(|pair| (pair[0].trim().trim_end_matches('=').to_string(), pair[1].to_string()))
                .collect()
        })
        .collect()
}

/// A numeric attribute of an SVG element.
pub fn number(element: &HashMap<String, String>, key: &str) -> f64 {
    element[key].parse().unwrap()
}
