//! Deposition protocols: a scene's stages run before its own physics, the state carrying over at
//! each switch.

use demsweep::physics::config::{IntegratorKind, SceneConfig, StageConfig};
use demsweep::physics::record::{RunRecord, RunStatus};
use demsweep::physics::simulation::Control;
use demsweep::physics::{predict_stability, run_scene, run_scene_with_history};

/// 200 polydisperse disks poured into a 0.25 m box from up to 0.4 m, restitution 0.4, a fixed step.
fn deposition(seed: u64) -> SceneConfig {
    let mut s = SceneConfig::default();
    (s.particles.count, s.particles.radius, s.particles.radius_max) = (200, 0.004, Some(0.008));
    (s.domain.width, s.domain.height) = (0.25, 0.4);
    s.material.restitution = Some(0.4);
    s.integrator.time_step = Some(2e-5);
    s.run.duration = 2.0;
    s.placement.seed = seed;
    s
}

fn stage(toml_text: &str) -> StageConfig {
    toml::from_str(toml_text).expect("a stage")
}

fn run(scene: &SceneConfig) -> RunRecord {
    run_scene(scene, None, &mut |_| Control::Continue).expect("runs")
}

fn bits(r: &RunRecord) -> Vec<u64> {
    let f = &r.final_state;
    [&f.x, &f.y, &f.vx, &f.vy, &f.omega].iter().flat_map(|c| c.iter().map(|v| v.to_bits())).collect()
}

#[test]
fn a_stage_that_changes_nothing_leaves_the_run_bit_identical() {
    let plain = deposition(7);
    let mut staged = plain.clone();
    staged.stages = vec![stage("name = \"same\"\nuntil.time = 0.15\n")];
    let (a, b) = (run(&plain), run(&staged));
    assert_eq!(bits(&a), bits(&b));
    assert_eq!((a.steps, a.settle_time, a.status), (b.steps, b.settle_time, b.status));
    assert_eq!(b.stage_ends.len(), 1);
    let end = b.stage_ends[0].time.expect("the stage ended");
    assert!((end - 0.15).abs() < 1e-9, "ended at {end} s");
    assert!(a.stage_ends.is_empty());
}

#[test]
fn a_damped_stage_runs_as_its_own_scene_would_then_hands_its_state_on() {
    let mut physics = deposition(8);
    physics.integrator.scheme = IntegratorKind::VelocityVerlet;
    let mut protocol = physics.clone();
    protocol.stages =
        vec![stage("name = \"fill\"\nuntil.time = 0.3\ndamping.local = 0.5\nmaterial.restitution = 0.2\n")];
    protocol.run.frame_times = vec![0.3, 0.3002];
    let staged = run(&protocol);
    // The fill alone, as a scene of its own, for the same time.
    let mut fill = physics.clone();
    (fill.damping.local, fill.material.restitution) = (0.5, Some(0.2));
    (fill.run.duration, fill.run.stop_at_settle) = (0.3, false);
    let alone = run(&fill);
    let at_switch = &staged.frames[0];
    assert_eq!(at_switch.time, alone.final_state.time);
    assert_eq!(at_switch.x, alone.final_state.x, "positions at the switch");
    assert_eq!(at_switch.vy, alone.final_state.vy, "velocities at the switch");
    // Chained by hand: the physics restarted from the fill's state.
    let mut rest = physics.clone();
    rest.placement.kind = demsweep::physics::config::PlacementKind::File;
    (rest.placement.file, rest.placement.contacts) = (Some("s.csv".into()), Some("c.csv".into()));
    rest.run.duration = physics.run.duration - 0.3;
    rest.run.frame_times = vec![0.0002];
    let state = &alone.final_state;
    let chained =
        run_scene_with_history(&rest, Some(state.initial_disks()), Some(&state.initial_contacts()), &mut |_| {
            Control::Continue
        })
        .expect("runs");
    assert_eq!((staged.status, chained.status), (RunStatus::Settled, RunStatus::Settled));
    // Ten steps after the switch the two agree closely: the restart adds one more increment to
    // the springs it is given (velocity Verlet: no multistep history that a restart would lose).
    // The pile is chaotic: later they part ways.
    let (soon, again) = (&staged.frames[1], &chained.frames[0]);
    let apart = soon.x.iter().zip(&again.x).chain(soon.y.iter().zip(&again.y)).map(|(a, b)| (a - b).abs());
    let apart = apart.fold(0.0, f64::max);
    println!("{apart:e} m apart ten steps after the switch");
    assert!(apart < 1e-4 * physics.particles.radius, "{apart} m apart ten steps after the switch");
    // And they end in piles alike.
    let (one, two) = (staged.settle_time.unwrap(), 0.3 + chained.settle_time.unwrap());
    let packing = |r: &RunRecord| r.pile.get("packing_fraction").unwrap();
    println!("settle at {one} / {two} s, packing {} / {}", packing(&staged), packing(&chained));
    assert!((one - two).abs() <= 0.25 * two, "staged settles at {one} s, chained at {two} s");
    assert!((packing(&staged) - packing(&chained)).abs() <= 0.01 * packing(&chained));
}

#[test]
fn the_energy_balance_holds_across_switches_of_damping_step_and_scheme() {
    let mut scene = deposition(9);
    scene.stages = vec![
        stage(
            "name = \"fill\"\nuntil.time = 0.25\ndamping.viscous = 5.0\nintegrator.scheme = \"velocity_verlet\"\nintegrator.time_step = 1e-5\n",
        ),
        stage("name = \"calm\"\nuntil.kinetic_energy_per_disk = 1e-6\ndamping.local = 0.3\n"),
    ];
    let r = run(&scene);
    let tolerance = scene.limits.energy_balance_tolerance;
    assert_eq!(r.status, RunStatus::Settled, "{:?}", r.message);
    assert!(r.energy_balance_error.abs() <= tolerance, "energy balance off by {}", r.energy_balance_error);
    let ends: Vec<f64> = r.stage_ends.iter().map(|e| e.time.expect("every stage ended")).collect();
    assert!((ends[0] - 0.25).abs() < 1e-9 && ends[1] > ends[0], "{ends:?}");
    assert!(r.settle_time.unwrap() >= ends[1]);
    assert_eq!(r.time_step, 2e-5, "the physical stage's step");
}

#[test]
fn each_end_condition_ends_its_stage_when_it_first_holds() {
    for (until, check) in [
        ("unbalanced_force_ratio = 0.05", "ubf"),
        ("kinetic_energy_per_disk = 1e-5", "kinetic"),
        ("all_in_contact = true", "contact"),
    ] {
        let mut scene = deposition(10);
        scene.stages = vec![stage(&format!("name = \"s\"\ndamping.local = 0.4\n[until]\n{until}\n"))];
        scene.run.sample_interval = 1e-3;
        let r = run(&scene);
        let end = r.stage_ends[0].time.unwrap_or_else(|| panic!("{check}: the stage never ended"));
        let at = r.history.time.iter().position(|t| *t == end).expect("a sample at the switch");
        let n = scene.particles.count as f64;
        let held = match check {
            "ubf" => r.history.unbalanced_force_ratio[at] < 0.05,
            "kinetic" => (r.history.kinetic_translational[at] + r.history.kinetic_rotational[at]) / n < 1e-5,
            _ => true,
        };
        assert!(held, "{check}: the condition does not hold at the switch ({end} s)");
        let before = match check {
            "ubf" => r.history.unbalanced_force_ratio[..at].iter().any(|u| *u < 0.05),
            "kinetic" => {
                (0..at).any(|k| (r.history.kinetic_translational[k] + r.history.kinetic_rotational[k]) / n < 1e-5)
            }
            _ => false,
        };
        assert!(!before, "{check}: the condition held before the switch");
        assert_eq!(r.status, RunStatus::Settled, "{check}");
    }
}

/// The multistep scheme restarts when the step changes mid-deposition: at each integrator's largest
/// valid step (the stability prediction's), the run still settles like the uninterrupted one.
#[test]
fn a_step_change_mid_deposition_at_each_integrators_largest_valid_step_settles_like_the_straight_run() {
    for scheme in [IntegratorKind::AdamsBashforthMoulton, IntegratorKind::VelocityVerlet] {
        for seed in 20..22 {
            let mut probe = deposition(seed);
            (probe.integrator.scheme, probe.integrator.time_step) = (scheme, None);
            probe.integrator.contact_time_fraction = Some(0.01);
            let report = predict_stability(&probe, &demsweep::physics::placement::generate(&probe).unwrap());
            let largest = report.safe_time_step / report.contact_time;
            let mut straight = probe.clone();
            straight.integrator.contact_time_fraction = Some(largest);
            let mut staged = straight.clone();
            staged.stages = vec![stage(&format!(
                "name = \"half\"\nuntil.time = 0.3\nintegrator.contact_time_fraction = {}\n",
                largest / 2.0
            ))];
            let (a, b) = (run(&straight), run(&staged));
            let case = format!("{scheme:?} seed {seed} at {largest:.3} t_c");
            println!(
                "{case}: straight {:?} s, staged {:?} s, energy balance {:.1e}",
                a.settle_time, b.settle_time, b.energy_balance_error
            );
            assert_eq!((a.status, b.status), (RunStatus::Settled, RunStatus::Settled), "{case}");
            assert!(b.energy_balance_error.abs() <= straight.limits.energy_balance_tolerance, "{case}");
            let (t, u) = (a.settle_time.unwrap(), b.settle_time.unwrap());
            assert!((t - u).abs() <= 0.5 * t, "{case}: staged settles at {u} s, straight at {t} s");
        }
    }
}

#[test]
fn a_run_that_ends_inside_a_stage_never_settles_and_says_the_stage_did_not_end() {
    let mut scene = deposition(11);
    scene.run.duration = 0.2;
    scene.stages = vec![stage("name = \"long\"\nuntil.time = 1.0\ndamping.local = 0.6\n")];
    let r = run(&scene);
    assert_eq!(r.status, RunStatus::NotSettled);
    assert_eq!(r.stage_ends[0].time, None);
    // A later stage's time too long to count in steps does not end it at once either.
    scene.stages.insert(0, stage("name = \"first\"\nuntil.time = 0.05\n"));
    scene.stages[1].until.time = Some(1e200);
    let r = run(&scene);
    assert!((r.stage_ends[0].time.unwrap() - 0.05).abs() < 1e-9);
    assert_eq!((r.status, r.stage_ends[1].time), (RunStatus::NotSettled, None));
    assert!((r.simulated_time - 0.2).abs() < 1e-9);
}

/// The sample at `time` (s) exactly, and the next one.
fn at_switch(r: &RunRecord, time: f64) -> usize {
    r.history.time.iter().position(|t| *t == time).expect("a sample at the switch")
}

#[test]
fn a_fall_of_friction_cuts_springs_back_counting_their_energy_as_dissipated_and_a_rise_cuts_none() {
    let mut scene = deposition(12);
    scene.integrator.scheme = IntegratorKind::VelocityVerlet;
    // Every step sampled, so that each switch shows as one step's change.
    scene.run.sample_interval = scene.integrator.time_step.unwrap();
    scene.stages = vec![
        stage("name = \"pour\"\nuntil.time = 0.8\n"),
        // Slipping, the pile sinks; it is brought to rest before friction rises again, so that no
        // contact is sliding fast then (it would store energy at once as it sticks).
        stage("name = \"slip\"\nuntil.time = 0.05\nmaterial.friction = 0.05\n"),
        stage("name = \"rest\"\nuntil.unbalanced_force_ratio = 0.01\nmaterial.friction = 0.05\ndamping.local = 0.3\n"),
    ];
    let r = run(&scene);
    assert_eq!(r.status, RunStatus::Settled, "{:?}", r.message);
    let tolerance = scene.limits.energy_balance_tolerance;
    assert!(r.energy_balance_error.abs() <= tolerance, "energy balance off by {}", r.energy_balance_error);
    let h = &r.history;
    let step_change = |k: usize| (h.elastic[k] - h.elastic[k + 1], h.dissipated[k + 1] - h.dissipated[k]);
    let (fall, rise) = (at_switch(&r, r.stage_ends[0].time.unwrap()), at_switch(&r, r.stage_ends[2].time.unwrap()));
    // A step's largest change of the stored energy in the 50 steps before step `k`.
    let usual = |k: usize| (k - 50..k).map(|j| step_change(j).0.abs()).fold(0.0, f64::max);
    let (lost, dissipated) = step_change(fall);
    let stored = h.elastic[fall];
    println!("fall: {lost:e} J of {stored:e} J stored lost, {dissipated:e} J dissipated; usual {:e} J", usual(fall));
    assert!(lost > 0.01 * stored && lost > 20.0 * usual(fall), "the springs were cut: {lost} J of {stored} J");
    assert!((dissipated - lost).abs() <= 0.01 * lost, "{lost} J lost, {dissipated} J dissipated");
    let (changed, _) = step_change(rise);
    println!("rise: {changed:e} J stored energy change; usual {:e} J", usual(rise));
    assert!(changed.abs() <= 2.0 * usual(rise), "the rise changed the stored energy by {changed} J");
}

#[test]
fn a_stage_with_friction_in_a_frictionless_scene_runs_as_its_own_scene_would() {
    let mut rough = deposition(13);
    rough.integrator.scheme = IntegratorKind::VelocityVerlet;
    let mut smooth = rough.clone();
    smooth.material.friction = 0.0;
    smooth.stages = vec![stage("name = \"rough\"\nuntil.time = 0.3\nmaterial.friction = 0.5\n")];
    smooth.run.frame_times = vec![0.3];
    let staged = run(&smooth);
    (rough.run.duration, rough.run.stop_at_settle) = (0.3, false);
    let alone = run(&rough);
    let at_switch = &staged.frames[0];
    assert_eq!(at_switch.time, alone.final_state.time);
    assert_eq!(at_switch.x, alone.final_state.x, "positions at the switch");
    assert_eq!(at_switch.omega, alone.final_state.omega, "spins at the switch");
    assert!(at_switch.omega.iter().any(|w| *w != 0.0), "the disks spin while friction holds");
    assert_eq!(staged.status, RunStatus::Settled, "{:?}", staged.message);
}

/// A rise of friction while disks slide fast jumps the tangential forces: the step before it is
/// closed with the forces before the jump, so that the switch adds no error to the energy balance
/// beyond what the integrator makes of the same deposition without it.
#[test]
fn a_rise_of_friction_while_disks_slide_keeps_the_energy_balance_to_the_integrators_accuracy() {
    let mut rough = deposition(14);
    rough.placement.kind = demsweep::physics::config::PlacementKind::Dropped;
    rough.integrator.scheme = IntegratorKind::VelocityVerlet;
    (rough.run.duration, rough.run.stop_at_settle) = (0.3, false);
    let mut smooth = rough.clone();
    smooth.material.friction = 0.0;
    let mut staged = rough.clone();
    staged.stages = vec![stage("name = \"slip\"\nuntil.time = 0.06\nmaterial.friction = 0.0\n")];
    let (a, b) = (run(&smooth), run(&staged));
    println!(
        "energy balance: frictionless {:e}, friction rising at 0.06 s {:e}",
        a.energy_balance_error, b.energy_balance_error
    );
    assert!(b.energy_balance_error.abs() <= 5.0 * a.energy_balance_error.abs(), "{b:?}", b = b.energy_balance_error);
}

/// A record as text, every number to its last bit (`{:?}` prints the shortest round-trip form),
/// the stage ends left out.
fn whole(r: &RunRecord) -> String {
    format!("{:?}", RunRecord { stage_ends: Vec::new(), ..r.clone() })
}

#[test]
fn a_no_op_stage_ending_off_the_sampling_grid_leaves_the_whole_record_bit_identical_settle_time_included() {
    for seed in [1, 2, 3] {
        let mut plain = deposition(seed);
        plain.integrator.time_step = None;
        let mut staged = plain.clone();
        staged.stages = vec![stage("name = \"fill\"\nuntil.time = 0.3\ndamping.local = 0.0\n")];
        let (a, b) = (run(&plain), run(&staged));
        assert!(a.settle_time.is_some(), "seed {seed} settles");
        assert_eq!(a.settle_time, b.settle_time, "seed {seed}");
        assert_eq!(whole(&a), whole(&b), "seed {seed}");
    }
}
