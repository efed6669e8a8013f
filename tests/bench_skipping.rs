//! The skipping benchmark on a small version of the damping-sweep scene: what it measures.

mod bench_common;

use bench_common::*;
use demsweep::bench::skipping::{SkippingOptions, damping_sweep_scene, skipping};

#[test]
fn skipping_measures_settle_stop_sampling_and_friction_on_the_same_scene() {
    let dir = fresh_dir("skipping");
    let mut scene = damping_sweep_scene();
    scene.particles.count = 20;
    scene.domain.width = 0.06;
    scene.domain.height = 0.1;
    scene.run.duration = 1.0;
    let options = SkippingOptions {
        source: "a small damping-sweep scene".into(),
        scenes: vec![scene],
        window: 0.02,
        sample_every: vec![1, 100],
        out_dir: dir.clone(),
    };
    let rows = skipping(&options).unwrap();
    let measures: Vec<&str> = rows.iter().map(|r| r.measure).collect();
    assert_eq!(measures, ["stop_at_settle", "stop_at_settle", "sampling", "sampling", "friction", "friction"]);
    let (full, stopped) = (&rows[0], &rows[1]);
    assert!((full.simulated_time - 1.0).abs() < 1e-5, "ran {} s", full.simulated_time);
    // The settle time of a deposition is chaotic (round-off moves it by several per cent); the pile
    // settles around half-way, well before the end.
    assert!(stopped.simulated_time < 0.75 * full.simulated_time, "stopped at {}", stopped.simulated_time);
    assert!(stopped.steps < full.steps);
    // Every row of a comparison covers the same steps; only the work per step differs.
    assert!(rows[2..].iter().all(|r| r.steps == rows[2].steps));
    assert!(rows.iter().all(|r| r.run_time > 0.0 && r.runs == 1));
    assert_eq!(rows[0].saved, 0.0);
    let csv = csv_lines(&dir.join("skipping.csv"));
    assert_eq!(csv.len(), 7, "names and 6 rows");
    assert_eq!(units(&dir.join("skipping.csv")).join(","), ",,,s,,s,ns,", "the sidecar's units of {}", csv[0]);
    assert!(std::fs::read_to_string(dir.join("skipping.md")).unwrap().contains("stop once settled"));
    std::fs::remove_dir_all(dir).unwrap();
}
