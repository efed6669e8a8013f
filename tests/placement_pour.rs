//! Pouring at a rate: the exact count inserted without overlap, seeded; bad keys refused.

use demsweep::physics::config::{PlacementKind, SceneConfig};
use demsweep::physics::{Control, RunStatus, run_scene};

/// A small pour: 40 disks at 200 per second into a 0.2 m box, 1 s long.
fn pour_scene(seed: u64) -> SceneConfig {
    let mut scene = SceneConfig::default();
    scene.particles.count = 40;
    scene.domain.width = 0.2;
    scene.domain.height = 0.3;
    scene.placement.kind = PlacementKind::Pour;
    scene.placement.seed = seed;
    scene.placement.pour.rate = Some(200.0);
    scene.placement.pour.velocity = [0.0, -0.5];
    scene.placement.pour.velocity_spread = 0.1;
    scene.run.duration = 1.0;
    scene
}

fn worst_overlap(x: &[f64], y: &[f64], r: &[f64]) -> f64 {
    let mut worst = 0.0f64;
    for i in 0..x.len() {
        for j in i + 1..x.len() {
            let d = (x[i] - x[j]).hypot(y[i] - y[j]);
            worst = worst.max(1.0 - d / (r[i] + r[j]));
        }
    }
    worst
}

#[test]
fn a_pour_inserts_the_exact_count_without_overlap_seeded() {
    let scene = pour_scene(7);
    let mut frames_seen = Vec::new();
    let record = run_scene(&scene, None, &mut |p| {
        frames_seen.push(p.time);
        Control::Continue
    })
    .unwrap();
    let pour = record.pour.expect("a pour's counts");
    assert_eq!((pour.inserted, pour.refused), (40, 0));
    assert_eq!(record.final_state.x.len(), 40);
    // The last disk is due at 39/200 s: the pile settles after it, not at t = 0.
    let settle = record.settle_time.expect("settles");
    assert!(settle >= 39.0 / 200.0, "settled at {settle} s");
    assert_eq!(record.status, RunStatus::Settled);
    // Fewer particle steps than steps times disks: the disks were not all there from the start.
    assert!(record.particle_steps() < record.steps * 40, "{}", record.particle_steps());
    let f = &record.final_state;
    assert!(worst_overlap(&f.x, &f.y, &f.r) < 0.05, "a settled pile");
    let again = run_scene(&scene, None, &mut |_| Control::Continue).unwrap();
    assert_eq!(again.final_state.x, record.final_state.x, "same seed, same pile");
    let other = run_scene(&pour_scene(8), None, &mut |_| Control::Continue).unwrap();
    assert_ne!(other.final_state.x, record.final_state.x, "another seed, another pile");
}

#[test]
fn inserted_disks_overlap_nothing_when_they_enter() {
    // Without gravity and at rest, the disks stay where the inlet put them: none overlaps another.
    let mut scene = pour_scene(3);
    (scene.gravity, scene.placement.pour.velocity, scene.placement.pour.velocity_spread) =
        ([0.0, 0.0], [0.0, 0.0], 0.0);
    scene.placement.pour.y_min = Some(0.1);
    scene.placement.pour.rate = Some(4000.0);
    (scene.run.duration, scene.run.stop_at_settle) = (0.02, false);
    let record = run_scene(&scene, None, &mut |_| Control::Continue).unwrap();
    assert_eq!(record.pour.unwrap().inserted, 40);
    let f = &record.final_state;
    assert_eq!(worst_overlap(&f.x, &f.y, &f.r), 0.0);
    assert!(f.y.iter().zip(&f.r).all(|(y, r)| *y - r >= 0.1), "inside the inlet");
}

#[test]
fn a_full_inlet_refuses_disks_and_counts_them() {
    let mut scene = pour_scene(1);
    scene.placement.pour.rate = Some(1e6);
    scene.placement.max_attempts = 20;
    scene.run.duration = 0.05;
    let record = run_scene(&scene, None, &mut |_| Control::Continue).unwrap();
    let pour = record.pour.unwrap();
    assert!(pour.refused > 0, "{pour:?}");
    assert_eq!(pour.inserted + pour.refused, 40);
    assert_eq!(record.final_state.x.len() as u64, pour.inserted);
}

#[test]
fn bad_pour_keys_are_refused_by_key() {
    let issues = |scene: SceneConfig| -> Vec<String> {
        scene.validate().err().unwrap_or_default().into_iter().map(|issue| issue.key).collect()
    };
    let mut none = pour_scene(1);
    none.placement.pour.rate = None;
    assert_eq!(issues(none), ["placement.pour.rate"]);
    let mut both = pour_scene(1);
    both.placement.pour.mass_rate = Some(1.0);
    assert_eq!(issues(both), ["placement.pour.mass_rate"]);
    let mut negative = pour_scene(1);
    negative.placement.pour.rate = Some(-1.0);
    assert_eq!(issues(negative), ["placement.pour.rate"]);
    let mut outside = pour_scene(1);
    outside.placement.pour.x_max = Some(0.5);
    assert_eq!(issues(outside), ["placement.pour.x_max"]);
    let mut narrow = pour_scene(1);
    (narrow.placement.pour.x_min, narrow.placement.pour.x_max) = (Some(0.1), Some(0.105));
    assert_eq!(issues(narrow), ["placement.pour"]);
    let mut spread = pour_scene(1);
    spread.placement.pour.velocity_spread = -0.1;
    assert_eq!(issues(spread), ["placement.pour.velocity_spread"]);
    let mut not_a_pour = SceneConfig::default();
    not_a_pour.placement.pour.rate = Some(10.0);
    assert_eq!(issues(not_a_pour), ["placement.pour"]);
}
