//! Predicted-unstable scenes are warned, and a tiny stability map has no blow-up without a warning.

mod bench_common;

use bench_common::*;
use demsweep::bench::placed_disks;
use demsweep::bench::stability_map::{Outcome, StabilityMapOptions, stability_map};
use demsweep::bench::stable_step::{StableStepOptions, stable_step};
use demsweep::physics::SceneConfig;
use demsweep::physics::config::IntegratorKind;
use demsweep::physics::predict_stability as assess;
use demsweep::physics::record::RunStatus;
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
        restart_at: Some(0.08),
        out_dir: dir.clone(),
    };
    let (rows, boundaries) = stability_map(&options).unwrap();
    assert_eq!(boundaries.len(), 8);
    assert!(rows.iter().any(|r| r.blew_up()) && rows.iter().any(|r| !r.blew_up()));
    // Failures are blow-ups of the run or of its restart, and limit cycles, each warned before the run.
    assert!(rows.iter().any(|r| r.outcome() == Outcome::LimitCycle), "a run that never comes to rest is a failure");
    for r in rows.iter().filter(|r| r.failed()) {
        let case = format!("{:?} at dt/t_c = {}: {:?}", r.column, r.dt_over_contact_time, r.outcome());
        assert!(r.warned, "{case} without a warning");
        assert!(!r.failure().is_empty(), "{case}");
        assert_eq!(r.message.is_empty(), r.status != RunStatus::Diverged, "{case}: {}", r.message);
    }
    for r in rows.iter().filter(|r| r.simulated_time > 0.08) {
        assert!(r.restart.is_some(), "{:?} at dt/t_c = {} restarted at 0.08 s", r.column, r.dt_over_contact_time);
    }
    // Every lightly damped frictionless column has a step that does not fail, and blows up at t_c.
    for b in boundaries.iter().filter(|b| b.column.friction == 0.0 && b.column.beta < 1.0) {
        assert!(b.largest_stable.is_some(), "{:?}", b.column);
        assert!(b.smallest_unstable.is_some_and(|dt| dt <= b.contact_time), "{:?}", b.column);
    }
    assert_eq!(csv_lines(&dir.join("stability_map.csv")).len(), rows.len() + 1, "names, then the rows");
    assert!(std::fs::read(dir.join("stability_map.png")).unwrap().starts_with(b"\x89PNG"));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn the_stable_step_bench_tells_a_settling_step_from_a_limit_cycle_straight_and_restarted() {
    let dir = fresh_dir("stable_step");
    let options = StableStepOptions {
        schemes: vec![(IntegratorKind::AdamsBashforthMoulton, vec![0.03, 0.4])],
        restitutions: vec![0.4],
        seeds: 1,
        count: 40,
        restart_at: 0.3,
        duration: 1.5,
        out_dir: dir.clone(),
    };
    let rows = stable_step(&options).unwrap();
    assert_eq!(rows.len(), 2);
    let (fine, coarse) = (&rows[0], &rows[1]);
    assert!(fine.settles(), "{fine:?}");
    assert!(coarse.settles_finer && !coarse.settles(), "{coarse:?}");
    assert!(coarse.step_ratio > 1.0, "the restart's own contact time is longer: {coarse:?}");
    assert_eq!(csv_lines(&dir.join("stable_step.csv")).len(), rows.len() + 1, "names, then the rows");
    let summary = std::fs::read_to_string(dir.join("stable_step.md")).unwrap();
    assert!(summary.contains("| adams_bashforth_moulton | 0.4 |") && summary.contains("| 0.03 |"), "{summary}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn the_stable_step_prediction_is_the_same_for_every_placement_seed_and_knows_the_damping() {
    // What tune clips lever ranges on holds for the seeds it runs, not only the reference's.
    let mut s = small_scene();
    s.integrator.contact_time_fraction = Some(0.1);
    s.material.restitution = Some(0.1);
    let report = |s: &SceneConfig| assess(s, &placed_disks(s).unwrap());
    let first = report(&s);
    let warned = |r: &demsweep::physics::stability::StabilityReport| {
        r.warnings.iter().any(|w| w.kind == WarningKind::IntegratorStability)
    };
    assert!(warned(&first), "{:?}", first.warnings);
    let kinds =
        |r: &demsweep::physics::stability::StabilityReport| r.warnings.iter().map(|w| w.kind).collect::<Vec<_>>();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs();
    for seed in 1..6 {
        s.placement.seed = seed;
        let other = report(&s);
        assert!(close(other.damping_ratio, first.damping_ratio), "seed {seed}: {other:?}");
        assert!(close(other.stable_fraction, first.stable_fraction), "seed {seed}: {other:?}");
        assert_eq!(kinds(&other), kinds(&first), "seed {seed}");
    }
    // Lighter damping and velocity Verlet each allow a larger step.
    s.material.restitution = Some(0.5);
    let light = report(&s);
    assert!(light.damping_ratio < first.damping_ratio && light.stable_fraction > first.stable_fraction);
    s.integrator.scheme = IntegratorKind::VelocityVerlet;
    assert!(report(&s).stable_fraction > light.stable_fraction);
    assert!((light.safe_time_step / light.contact_time - light.stable_fraction).abs() < 1e-9, "{light:?}");
}
