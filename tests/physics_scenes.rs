//! Whole depositions: energy conservation and balance, broad phase equivalence, determinism, and
//! the paper's Table 1 preset.

mod common;

use common::*;
use demsweep::physics::config::{BroadPhaseKind, IntegratorKind, SceneConfig};
use demsweep::physics::record::{RunRecord, RunStatus};
use demsweep::physics::simulation::Control;
use demsweep::physics::warning::WarningKind;
use demsweep::physics::{RunError, run_scene};

fn run(scene: &SceneConfig, disks: Option<Vec<demsweep::physics::particles::InitialDisk>>) -> RunRecord {
    run_scene(scene, disks, &mut |_| Control::Continue).unwrap()
}

/// 40 disks dropped in a 0.2 m box, no damping, no friction.
fn undamped_deposition(scheme: IntegratorKind, dt: f64) -> RunRecord {
    let mut s = SceneConfig::default();
    s.domain.width = 0.2;
    s.domain.height = 0.2;
    s.particles.count = 40;
    s.material.youngs_modulus = 1e8;
    s.material.beta = Some(0.0);
    s.material.friction = 0.0;
    s.integrator.scheme = scheme;
    s.integrator.time_step = Some(dt);
    s.run.duration = 0.25;
    s.run.sample_interval = 1e-3;
    s.run.stop_at_settle = false;
    run(&s, None)
}

#[test]
fn undamped_frictionless_deposition_conserves_energy_at_second_order() {
    for scheme in SCHEMES {
        let (drifts, balance_errors): (Vec<f64>, Vec<f64>) = [4e-5, 2e-5, 1e-5]
            .iter()
            .map(|dt| {
                let rec = undamped_deposition(scheme, *dt);
                assert_eq!(rec.status, RunStatus::NotSettled, "{:?}", rec.message);
                let e = &rec.history.mechanical;
                let contacts: u32 = rec.history.contacts.iter().sum();
                assert!(contacts > 100, "the disks must collide");
                (e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / e[0], rec.energy_balance_error)
            })
            .unzip();
        let ratios: Vec<f64> = drifts.windows(2).map(|w| w[0] / w[1]).collect();
        println!("{scheme:?}: largest relative energy drift {drifts:?}, ratios per halving {ratios:?}");
        assert!(drifts[0] < 1e-3, "{drifts:?}");
        assert!(ratios.iter().all(|r| *r > 3.0), "{scheme:?}: drift ratios {ratios:?}");
        // The run's energy-balance error (what tune fits the order of its error in dt from) falls
        // at second order too.
        let balance_ratios: Vec<f64> = balance_errors.windows(2).map(|w| w[0] / w[1]).collect();
        println!("{scheme:?}: energy_balance_error {balance_errors:?}, ratios per halving {balance_ratios:?}");
        assert!(balance_errors[0] > 0.0 && balance_errors[0] < 1e-2, "{balance_errors:?}");
        assert!(balance_ratios.iter().all(|r| *r > 3.0), "{scheme:?}: balance error ratios {balance_ratios:?}");
    }
}

#[test]
fn damped_frictional_deposition_balances_energy() {
    for scheme in SCHEMES {
        let mut scene = reference_scene();
        scene.integrator.scheme = scheme;
        scene.material.rolling_friction = 0.1;
        scene.run.duration = 0.4;
        let rec = run(&scene, Some(reference_disks()));
        let (h, worst) = (&rec.history, common::largest_balance_error(&rec.history));
        let initial = h.mechanical[0];
        let dissipated = *h.dissipated.last().unwrap();
        println!(
            "{scheme:?}: dissipated {dissipated:.3} J, largest balance error {worst:.3e} J of initial {initial:.3} J"
        );
        assert!(dissipated > 0.3 * initial, "most energy must be dissipated: {dissipated}");
        assert!(worst < 0.01 * initial && worst < 0.01 * dissipated);
        assert!(h.kinetic_rotational.iter().any(|k| *k > 0.0), "friction must spin disks");
    }
}

#[test]
fn grid_and_all_pairs_give_identical_trajectories() {
    let mut scene = reference_scene();
    scene.run.duration = 0.3;
    let grid = run(&scene, Some(reference_disks()));
    scene.neighbors.broad_phase = BroadPhaseKind::AllPairs;
    let brute = run(&scene, Some(reference_disks()));
    assert!(grid.history.contacts.last().unwrap() > &200);
    for (a, b) in [(&grid.final_state.x, &brute.final_state.x), (&grid.final_state.vy, &brute.final_state.vy)] {
        assert_eq!(bits(a), bits(b));
    }
    assert_eq!(bits(&grid.history.unbalanced_force_ratio), bits(&brute.history.unbalanced_force_ratio));
}

#[test]
fn same_scene_and_seed_give_bit_identical_runs() {
    let mut scene = SceneConfig::default();
    scene.particles.count = 120;
    scene.particles.radius_max = Some(0.015);
    scene.run.duration = 0.2;
    let (a, b) = (run(&scene, None), run(&scene, None));
    let s = |r: &RunRecord| {
        let f = &r.final_state;
        [&f.x, &f.y, &f.vx, &f.vy, &f.omega, &f.r, &r.history.mechanical, &r.history.unbalanced_force_ratio]
            .map(|v| bits(v))
    };
    assert_eq!(s(&a), s(&b));
    scene.placement.seed += 1;
    assert_ne!(bits(&run(&scene, None).final_state.x), bits(&a.final_state.x));
}

#[test]
fn paper_table1_runs_to_the_end_and_flags_the_overlap() {
    let mut s = SceneConfig::default();
    s.material.youngs_modulus = 20000.0;
    s.material.shear_modulus = Some(20000.0);
    s.material.beta = Some(10.0);
    s.material.friction = 0.5;
    s.material.rolling_friction = 0.5;
    s.integrator.time_step = Some(1e-4);
    s.run.duration = 3.0;
    s.run.stop_at_settle = false;
    s.limits.max_overlap_ratio = 10.0;
    let rec = run(&s, None);
    assert_ne!(rec.status, RunStatus::Diverged, "{:?}", rec.message);
    assert!((rec.simulated_time - 3.0).abs() < 1e-9);
    let worst = rec.history.max_overlap_ratio.iter().cloned().fold(0.0, f64::max);
    let texts: Vec<String> = rec.warnings.iter().map(ToString::to_string).collect();
    println!("largest overlap {worst:.3} radii; warnings:\n{}", texts.join("\n"));
    assert!(worst > 1.0);
    // The measured warning is a value: kind, limit key, the largest overlap, its limit and when.
    let overlap = rec.warnings.iter().find(|w| w.kind == WarningKind::Overlap).expect("a measured overlap warning");
    assert_eq!((overlap.value, overlap.limit), (worst, s.limits.overlap_warning_ratio));
    assert_eq!((overlap.kind.limit_key(), rec.largest_overlap_ratio), ("limits.overlap_warning_ratio", worst));
    let at = rec.history.max_overlap_ratio.iter().position(|&o| o == worst).unwrap();
    assert_eq!(overlap.time, Some(rec.history.time[at]));
    assert!(texts.iter().any(|w| w.contains("largest overlap") && w.contains("radii")));
    let predicted = [WarningKind::ImpactOverlap, WarningKind::StaticOverlap];
    assert!(rec.stability.warnings.iter().any(|w| predicted.contains(&w.kind) && w.to_string().contains("too soft")));
    // With the default limit the same scene is stopped as diverged, with the reason.
    s.limits = Default::default();
    let stopped = run(&s, None);
    assert_eq!(stopped.status, RunStatus::Diverged);
    assert!(stopped.message.unwrap().contains("limits.max_overlap_ratio"));
}

#[test]
fn strong_damping_with_friction_creates_no_energy() {
    // β = 10 with μ = 0.5: a sliding contact's trial force passes the Coulomb limit through its
    // damping part; the tangential spring must not be enlarged to the limit (that stored energy no
    // work put there, and such runs gained energy and diverged at every time step).
    let mut s = SceneConfig::default();
    s.domain.width = 0.12;
    s.particles.count = 24;
    s.material.beta = Some(10.0);
    s.material.friction = 0.5;
    s.run.duration = 0.4;
    s.run.stop_at_settle = false;
    let disks = demsweep::physics::placement::generate(&s).unwrap();
    s.integrator.time_step = Some(demsweep::physics::predict_stability(&s, &disks).safe_time_step);
    let rec = run(&s, None);
    assert_ne!(rec.status, RunStatus::Diverged, "{:?}", rec.message);
    let h = &rec.history;
    let highest = h.mechanical.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    assert!(highest <= h.mechanical[0] * (1.0 + 1e-3), "energy grew: {highest} > {}", h.mechanical[0]);
    let balance = common::largest_balance_error(h);
    assert!(balance < 0.01 * h.mechanical[0], "energy balance off by {balance}");
}

#[test]
fn a_scene_that_cannot_run_gives_a_typed_error_naming_its_key() {
    let mut invalid = SceneConfig::default();
    invalid.run.duration = -1.0;
    match run_scene(&invalid, None, &mut |_| Control::Continue) {
        Err(RunError::InvalidScene(issues)) => assert!(issues.iter().any(|i| i.key == "run.duration"), "{issues:?}"),
        other => panic!("expected InvalidScene, got {:?}", other.err()),
    }
    let empty = run_scene(&SceneConfig::default(), Some(Vec::new()), &mut |_| Control::Continue);
    assert_eq!(empty.err(), Some(RunError::NoDisks));
}
