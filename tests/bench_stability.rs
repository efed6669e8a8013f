//! Predicted-unstable scenes are warned, and a tiny stability map has no blow-up without a warning.

mod bench_common;

use bench_common::*;
use demsweep::bench::placed_disks;
use demsweep::bench::stability_map::{StabilityMapOptions, stability_map};
use demsweep::physics::SceneConfig;
use demsweep::physics::config::IntegratorKind;
use demsweep::physics::predict_stability as assess;
use demsweep::physics::warning::WarningKind;

fn small_scene() -> SceneConfig {
    let mut s = SceneConfig::default();
    s.particles.count = 20;
    s.domain.width = 0.12;
    s
}

#[test]
fn time_step_above_the_contact_time_and_strong_damping_are_warned() {
    let mut s = small_scene();
    let disks = placed_disks(&s).unwrap();
    let report = assess(&s, &disks);
    let time_step_kinds = [WarningKind::ContactTimeFraction, WarningKind::DampingRate, WarningKind::TimeStepCapped];
    assert!(report.warnings.iter().all(|w| !time_step_kinds.contains(&w.kind)), "{:?}", report.warnings);
    s.integrator.time_step = Some(report.contact_time);
    let coarse = assess(&s, &disks);
    let fraction = coarse.warnings.iter().find(|w| w.kind == WarningKind::ContactTimeFraction).expect("a warning");
    assert!((fraction.value - 1.0).abs() < 1e-9 && fraction.limit == s.limits.contact_time_fraction, "{fraction:?}");
    assert!(fraction.to_string().contains("of the contact time"), "{fraction}");
    s.integrator.time_step = Some(1e-5);
    s.material.beta = Some(50.0);
    let damped = assess(&s, &disks);
    assert!(damped.dt_times_damping_rate > 0.5);
    let rate = damped.warnings.iter().find(|w| w.kind == WarningKind::DampingRate).expect("a damping-rate warning");
    assert_eq!((rate.value, rate.safe_time_step), (damped.dt_times_damping_rate, Some(damped.safe_time_step)));
    s.integrator.time_step = Some(damped.safe_time_step);
    assert!(assess(&s, &disks).warnings.is_empty(), "{:?}", assess(&s, &disks).warnings);
}

#[test]
fn tiny_stability_map_finds_blow_ups_and_warns_before_each() {
    let dir = fresh_dir("stability");
    let options = StabilityMapOptions {
        schemes: vec![IntegratorKind::AdamsBashforthMoulton, IntegratorKind::VelocityVerlet],
        youngs_moduli: vec![1e8],
        betas: vec![0.215, 10.0],
        frictions: vec![0.0, 0.5],
        coarsest_ratio: 1.0,
        finest_ratio: 64.0,
        per_halving: 1,
        count: 8,
        duration: 0.15,
        out_dir: dir.clone(),
    };
    let (rows, boundaries) = stability_map(&options).unwrap();
    assert_eq!(boundaries.len(), 8);
    assert!(rows.iter().any(|r| r.blew_up()) && rows.iter().any(|r| !r.blew_up()));
    for r in rows.iter().filter(|r| r.blew_up()) {
        assert!(r.warned, "{:?} blew up at dt/t_c = {} without a warning", r.column, r.dt_over_contact_time);
        assert!(!r.message.is_empty() && !r.failure().is_empty());
    }
    // Every frictionless column has a stable time step, and blows up at t_c.
    for b in boundaries.iter().filter(|b| b.column.friction == 0.0) {
        assert!(b.largest_stable.is_some(), "{:?}", b.column);
        assert!(b.smallest_unstable.is_some_and(|dt| dt <= b.contact_time), "{:?}", b.column);
    }
    assert_eq!(csv_lines(&dir.join("stability_map.csv")).len(), rows.len() + 1, "names, then the rows");
    assert!(std::fs::read(dir.join("stability_map.png")).unwrap().starts_with(b"\x89PNG"));
    std::fs::remove_dir_all(dir).unwrap();
}
