//! Deposition levers against theory: numerical damping (Cundall local, global viscous) on a linear
//! oscillator and in free fall, its energy bookkeeping and stability estimate, and the time step
//! tied to the contact time.

mod common;

use common::{SCHEMES, free_scene, reference_disks, reference_scene};
use demsweep::physics::config::{ContactLawKind, IntegratorKind, SceneConfig};
use demsweep::physics::contact::normal::LinearNormal;
use demsweep::physics::contact::{HertzMindlin, LinearSpringDashpot};
use demsweep::physics::particles::InitialDisk;
use demsweep::physics::run_scene;
use demsweep::physics::simulation::{Control, Simulation};
use demsweep::physics::warning::WarningKind;

const G: f64 = 9.81;

/// A disk resting on the floor of a linear contact (k = 1e5 N/m, no contact damping, no friction),
/// started at its equilibrium moving up: a linear oscillator about the equilibrium.
fn oscillator(scheme: IntegratorKind, alpha: f64) -> Simulation<LinearSpringDashpot> {
    let (r, k) = (0.01, 1e5);
    let mass = common::disk_mass(r);
    let static_overlap = mass * G / k;
    let omega = (k / mass).sqrt();
    let mut s = free_scene(1e9, scheme, 2.0 * std::f64::consts::PI / omega / 4000.0);
    s.gravity = [0.0, -G];
    s.contact.law = ContactLawKind::Linear;
    s.contact.linear = LinearNormal { normal_stiffness: Some(k), tangential_stiffness_ratio: 0.0 };
    s.damping.local = alpha;
    // Amplitude a third of the static overlap: the contact never opens.
    let speed = omega * static_overlap / 3.0;
    let disk = InitialDisk { x: 0.5, y: r - static_overlap, r, vy: speed, ..Default::default() };
    Simulation::new(&s, &[disk])
}

/// Successive extremes of the displacement from equilibrium (absolute values), refined by a parabola.
fn half_cycle_amplitudes(mut sim: Simulation<LinearSpringDashpot>, count: usize) -> Vec<f64> {
    let equilibrium = sim.particles().y[0];
    let mut trace = vec![0.0, 0.0];
    let mut amplitudes = Vec::new();
    while amplitudes.len() < count {
        sim.advance(false);
        trace.push(sim.particles().y[0] - equilibrium);
        let n = trace.len();
        let (a, b, c) = (trace[n - 3], trace[n - 2], trace[n - 1]);
        if n > 3 && (b - a) * (c - b) < 0.0 {
            let denom = a - 2.0 * b + c;
            amplitudes.push((b - 0.125 * (a - c) * (a - c) / denom).abs());
        }
    }
    amplitudes
}

#[test]
fn local_damping_scales_each_half_cycle_by_the_cundall_ratio() {
    for scheme in SCHEMES {
        for alpha in [0.1_f64, 0.3, 0.6] {
            let expected = ((1.0 - alpha) / (1.0 + alpha)).sqrt();
            let amplitudes = half_cycle_amplitudes(oscillator(scheme, alpha), 5);
            for pair in amplitudes.windows(2) {
                let ratio = pair[1] / pair[0];
                println!("{scheme:?} alpha {alpha}: half-cycle ratio {ratio:.5} (theory {expected:.5})");
                assert!((ratio / expected - 1.0).abs() < 0.01, "{scheme:?} alpha {alpha}: {ratio} vs {expected}");
            }
        }
        let undamped = half_cycle_amplitudes(oscillator(scheme, 0.0), 5);
        assert!((undamped[4] / undamped[0] - 1.0).abs() < 1e-3, "no damping, no decay: {undamped:?}");
    }
}

/// A disk falling freely from rest for `duration` with the scene's damping; returns (time, speed down).
fn free_fall(scheme: IntegratorKind, configure: impl Fn(&mut SceneConfig), duration: f64) -> (f64, f64) {
    let mut s = free_scene(1e9, scheme, 1e-4);
    s.gravity = [0.0, -G];
    s.domain.height = 10.0;
    configure(&mut s);
    let disk = InitialDisk { x: 0.5, y: 9.0, r: 0.01, ..Default::default() };
    let mut sim = Simulation::<HertzMindlin>::new(&s, &[disk]);
    while sim.time() < duration - 1e-9 {
        sim.advance(false);
    }
    (sim.time(), -sim.particles().vy[0])
}

#[test]
fn viscous_free_fall_approaches_g_over_c() {
    let c = 5.0;
    for scheme in SCHEMES {
        let (t, v) = free_fall(scheme, |s| s.damping.viscous = c, 0.5);
        let theory = G / c * (1.0 - (-c * t).exp());
        println!("{scheme:?}: v({t:.3}) = {v:.8} m/s, theory {theory:.8}");
        assert!((v / theory - 1.0).abs() < 1e-4, "{scheme:?}: {v} vs {theory}");
    }
}

#[test]
fn local_damping_of_a_free_fall_acts_on_gravity_only_when_asked() {
    let alpha = 0.4;
    for scheme in SCHEMES {
        // At rest sign(v) = 0: the first step falls undamped, an error of order alpha dt / t.
        let (t, v) = free_fall(scheme, |s| s.damping.local = alpha, 0.2);
        assert!((v / ((1.0 - alpha) * G * t) - 1.0).abs() < 1e-3, "{scheme:?}: weight damped: {v}");
        let without_gravity = |s: &mut SceneConfig| {
            s.damping.local = alpha;
            s.damping.local_gravity = false;
        };
        let (t, v) = free_fall(scheme, without_gravity, 0.2);
        assert!((v / (G * t) - 1.0).abs() < 1e-9, "{scheme:?}: no contact force, nothing to damp: {v}");
    }
}

#[test]
fn numerical_damping_work_closes_the_energy_balance() {
    for scheme in SCHEMES {
        let mut scene = reference_scene();
        scene.integrator.scheme = scheme;
        scene.damping.local = 0.2;
        scene.damping.viscous = 2.0;
        scene.run.duration = 0.4;
        let rec = run_scene(&scene, Some(reference_disks()), &mut |_| Control::Continue).unwrap();
        let (h, worst) = (&rec.history, common::largest_balance_error(&rec.history));
        let initial = h.mechanical[0];
        let (dissipated, numerical) = (*h.dissipated.last().unwrap(), *h.numerical_damping_dissipated.last().unwrap());
        println!(
            "{scheme:?}: dissipated {dissipated:.3} J, of it numerical damping {numerical:.3} J; balance error {worst:.3e} J of {initial:.3} J"
        );
        assert!(numerical > 0.05 * dissipated && numerical < dissipated, "numerical damping did work: {numerical}");
        assert!(h.numerical_damping_dissipated.windows(2).all(|w| w[1] >= w[0] - 1e-9), "it only removes energy");
        assert!(worst < 0.01 * initial, "{scheme:?}: balance off by {worst}");
    }
}

#[test]
fn stability_estimate_counts_the_viscous_rate() {
    let base = reference_scene();
    let mut viscous = base.clone();
    viscous.damping.viscous = 60_000.0;
    let disks = reference_disks();
    let plain = Simulation::<HertzMindlin>::new(&base, &disks).stability();
    let damped = Simulation::<HertzMindlin>::new(&viscous, &disks).stability();
    assert!((damped.damping_rate - plain.damping_rate - 60_000.0).abs() < 1e-6 * damped.damping_rate);
    assert!(plain.warnings.iter().all(|w| w.kind != WarningKind::DampingRate), "{:?}", plain.warnings);
    let rate = damped.warnings.iter().find(|w| w.kind == WarningKind::DampingRate).expect("a damping-rate warning");
    assert_eq!(rate.kind.limit_key(), "limits.damping_rate_fraction");
    assert!(rate.to_string().contains("damping.viscous"), "{rate}");
}

#[test]
fn a_step_capped_by_the_damping_limit_says_so_in_the_run() {
    let mut scene = reference_scene();
    scene.integrator.time_step = None;
    scene.integrator.contact_time_fraction = Some(0.1);
    scene.damping.viscous = 20_000.0;
    scene.run.duration = 0.01;
    let rec = run_scene(&scene, Some(reference_disks()), &mut |_| Control::Continue).unwrap();
    assert!(rec.time_step <= 0.5 / 20_000.0, "{}", rec.time_step);
    let capped = &rec.warnings[0];
    assert_eq!((capped.kind, capped.limit), (WarningKind::TimeStepCapped, rec.time_step), "{capped:?}");
    assert!(capped.value > capped.limit && capped.to_string().starts_with("time step capped at"), "{capped}");
}

#[test]
fn contact_time_fraction_makes_soft_runs_take_fewer_steps() {
    let steps = |e: f64| {
        let mut s = SceneConfig::default();
        s.particles.count = 40;
        s.domain.width = 0.2;
        s.domain.height = 0.15;
        s.run.duration = 0.1;
        s.run.stop_at_settle = false;
        s.material.youngs_modulus = e;
        s.integrator.contact_time_fraction = Some(0.1);
        let rec = run_scene(&s, None, &mut |_| Control::Continue).unwrap();
        (rec.steps, rec.time_step)
    };
    let (soft, stiff) = (steps(1e8), steps(1e10));
    // Hertz: t_c ∝ E^(−2/5), so two decades of E change the step by 100^0.4 = 6.3.
    assert!((stiff.0 as f64 / soft.0 as f64 / 100f64.powf(0.4) - 1.0).abs() < 0.01, "{soft:?} {stiff:?}");
    assert!((soft.1 / stiff.1 - 100f64.powf(0.4)).abs() < 1e-3, "{soft:?} {stiff:?}");
}
