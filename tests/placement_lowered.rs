//! The lowered start (`placement.lowered_by`): the disks of a random placement made above the
//! lowering, moved down and falling at the speed of the height skipped, are the state that higher
//! pour reaches when its lowest disk meets the floor: the same impacts, without the free fall.

use demsweep::physics::config::SceneConfig;
use demsweep::physics::particles::InitialDisk;
use demsweep::physics::placement;
use demsweep::physics::simulation::Control;

/// 200 disks lowered by the fall of 0.2 s under the default gravity (9.81 m/s²).
fn lowered() -> SceneConfig {
    let mut s = SceneConfig::default();
    s.particles.count = 200;
    s.particles.radius_max = Some(0.012);
    s.placement.lowered_by = 0.5 * 9.81 * 0.2 * 0.2;
    s
}

#[test]
fn lowered_disks_fall_at_the_speed_of_the_height_they_skip_without_overlap() {
    let s = lowered();
    let disks = placement::generate(&s).unwrap();
    let top = s.domain.height - s.placement.lowered_by;
    let speed = 9.81 * 0.2;
    for (i, d) in disks.iter().enumerate() {
        assert!(d.y >= d.r && d.y + d.r <= top && d.x >= d.r && d.x + d.r <= s.domain.width, "disk {i} {d:?}");
        assert!(d.vx == 0.0 && (d.vy + speed).abs() < 1e-12, "disk {i} {d:?}");
        for (j, e) in disks.iter().enumerate().skip(i + 1) {
            assert!((d.x - e.x).hypot(d.y - e.y) >= d.r + e.r, "disks {i} and {j} overlap");
        }
    }
}

#[test]
fn a_lowered_start_is_the_higher_pour_after_its_free_fall() {
    let s = lowered();
    let start = placement::generate(&s).unwrap();
    let mut pour = s.clone();
    pour.placement.lowered_by = 0.0;
    (pour.run.duration, pour.run.stop_at_settle) = (0.2, false);
    let h = s.placement.lowered_by;
    let at_rest: Vec<InitialDisk> = start.iter().map(|d| InitialDisk { y: d.y + h, vy: 0.0, ..*d }).collect();
    let record = demsweep::physics::run_scene(&pour, Some(at_rest), &mut |_| Control::Continue).unwrap();
    let end = &record.final_state;
    for (i, d) in start.iter().enumerate() {
        let (dx, dy, dv) = (end.x[i] - d.x, end.y[i] - d.y, end.vy[i] - d.vy);
        assert!(dx.abs() < 1e-12 && dy.abs() < 1e-9 && dv.abs() < 1e-9, "disk {i}: off by ({dx}, {dy}), {dv} m/s");
    }
}

/// The validity prediction of a lowered start sees the impacts of the higher pour it stands for: a
/// disk falling at v from height d lands at √(v² + 2 g d), not v + √(2 g d).
#[test]
fn a_lowered_start_is_predicted_to_land_as_fast_as_the_higher_pour() {
    let s = lowered();
    let mut pour = s.clone();
    pour.placement.lowered_by = 0.0;
    let speed = |scene: &SceneConfig| {
        let disks = placement::generate(scene).unwrap();
        demsweep::physics::predict_stability(scene, &disks).impact_speed
    };
    let (lowered, poured) = (speed(&s), speed(&pour));
    assert!((lowered / poured - 1.0).abs() < 0.02, "lowered start {lowered} m/s, the pour {poured} m/s");
}
