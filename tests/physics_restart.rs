//! A deposition restarted from its own state mid-way (disks and contact history, the same scene)
//! comes to rest as the uninterrupted run does, under each integrator at its default limit: the
//! largest time step the stability prediction accepts.

use demsweep::physics::config::{IntegratorKind, PlacementKind, SceneConfig};
use demsweep::physics::record::{RunRecord, RunStatus};
use demsweep::physics::simulation::Control;
use demsweep::physics::{predict_stability, run_scene, run_scene_with_history};

/// When the deposition is interrupted (s): most disks have landed and the pile still bounces.
const RESTART_AT: f64 = 0.3;

/// 300 polydisperse disks poured into a box from up to 0.5 m, restitution 0.4, the step at `fraction` of
/// the contact time.
fn deposition(scheme: IntegratorKind, seed: u64, fraction: f64) -> SceneConfig {
    let mut s = SceneConfig::default();
    (s.particles.count, s.particles.radius, s.particles.radius_max) = (300, 0.004, Some(0.008));
    (s.domain.width, s.domain.height) = (0.3, 0.5);
    s.material.restitution = Some(0.4);
    s.integrator.scheme = scheme;
    s.integrator.contact_time_fraction = Some(fraction);
    s.run.duration = 3.0;
    s.placement.seed = seed;
    s
}

/// The run of `scene` interrupted at [`RESTART_AT`] and restarted from its state with the same scene.
fn restarted(scene: &SceneConfig) -> RunRecord {
    let go = &mut |_: &_| Control::Continue;
    let mut first = scene.clone();
    (first.run.duration, first.run.stop_at_settle) = (RESTART_AT, false);
    let state = run_scene(&first, None, go).unwrap().final_state;
    let mut rest = scene.clone();
    rest.placement.kind = PlacementKind::File;
    (rest.placement.file, rest.placement.contacts) = (Some("state.csv".into()), Some("state_contacts.csv".into()));
    rest.run.duration = scene.run.duration - RESTART_AT;
    run_scene_with_history(&rest, Some(state.initial_disks()), Some(&state.initial_contacts()), go).unwrap()
}

#[test]
fn a_deposition_restarted_mid_way_at_each_integrators_default_limit_settles_like_the_uninterrupted_run() {
    for scheme in [IntegratorKind::AdamsBashforthMoulton, IntegratorKind::VelocityVerlet] {
        for seed in 1000..1003 {
            let probe = deposition(scheme, seed, 0.01);
            let report = predict_stability(&probe, &demsweep::physics::placement::generate(&probe).unwrap());
            let scene = deposition(scheme, seed, report.safe_time_step / report.contact_time);
            let tolerance = scene.limits.energy_balance_tolerance;
            let straight = run_scene(&scene, None, &mut |_| Control::Continue).unwrap();
            let again = restarted(&scene);
            let case = format!("{scheme:?} seed {seed} at {:.3} t_c", report.safe_time_step / report.contact_time);
            println!(
                "{case}: straight settles at {:?} s (energy balance {:.1e}), restarted at {:?} s + {RESTART_AT} s \
                 ({:.1e}, time step {:.2}x)",
                straight.settle_time,
                straight.energy_balance_error,
                again.settle_time,
                again.energy_balance_error,
                again.time_step / straight.time_step
            );
            assert_eq!(straight.status, RunStatus::Settled, "{case}: {:?}", straight.message);
            assert!(straight.energy_balance_error.abs() <= tolerance, "{case}: {}", straight.energy_balance_error);
            assert_eq!(again.status, RunStatus::Settled, "{case} restarted: {:?}", again.message);
            assert!(again.energy_balance_error.abs() <= tolerance, "{case} restarted: {}", again.energy_balance_error);
            let (alone, total) = (straight.settle_time.unwrap(), RESTART_AT + again.settle_time.unwrap());
            assert!((total - alone).abs() <= 0.5 * alone, "{case}: settled at {total} s, uninterrupted {alone} s");
        }
    }
}
