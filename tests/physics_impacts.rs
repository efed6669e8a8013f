//! Single contacts against theory: Hertz impacts, restitution, convergence, static overlap, oblique
//! Coulomb impacts.

mod common;

use common::*;
use demsweep::physics::config::{ContactLawKind, IntegratorKind};
use demsweep::physics::contact::normal::{HystereticNormal, LinearNormal};
use demsweep::physics::contact::{HertzMindlin, HystereticLinear, LinearSpringDashpot};
use demsweep::physics::material::restitution_from_beta;
use demsweep::physics::particles::InitialDisk;
use demsweep::physics::run_scene;
use demsweep::physics::simulation::{Control, Simulation};

const E: f64 = 1e7;
const NU: f64 = 0.3;
const R: f64 = 0.01;

/// Theory of the two-disk test impact: (max overlap, duration).
fn two_disk_theory() -> (f64, f64) {
    hertz_impact(same_material_e_star(E, NU), R / 2.0, disk_mass(R) / 2.0, 1.0)
}

/// Head-on impact of two equal disks approaching at 1 m/s; returns (duration, max overlap,
/// rebound speed) measured from per-step overlaps.
fn two_disk_impact(scheme: IntegratorKind, dt: f64) -> (f64, f64, f64) {
    let scene = free_scene(E, scheme, dt);
    let gap = 0.1 * R;
    let disks = [
        InitialDisk { x: 0.4, y: 0.5, r: R, vx: 0.5, ..Default::default() },
        InitialDisk { x: 0.4 + 2.0 * R + gap, y: 0.5, r: R, vx: -0.5, ..Default::default() },
    ];
    let mut sim = Simulation::<HertzMindlin>::new(&scene, &disks);
    let (mut t, mut overlap) = (vec![0.0], vec![-gap]);
    let mut separated_steps = 0;
    while separated_steps < 3 {
        sim.advance(false);
        let p = sim.particles();
        t.push(sim.time());
        overlap.push(2.0 * R - (p.x[1] - p.x[0]));
        if *overlap.last().unwrap() < 0.0 && overlap.iter().any(|d| *d > 0.0) {
            separated_steps += 1;
        }
    }
    let (duration, max_overlap) = contact_of(&t, &overlap);
    let p = sim.particles();
    (duration, max_overlap, p.vx[1] - p.vx[0])
}

#[test]
fn head_on_impact_matches_hertz_theory_for_both_integrators() {
    let (overlap_theory, duration_theory) = two_disk_theory();
    for scheme in SCHEMES {
        let (duration, max_overlap, rebound) = two_disk_impact(scheme, duration_theory / 50.0);
        let errors = [
            (duration - duration_theory) / duration_theory,
            (max_overlap - overlap_theory) / overlap_theory,
            rebound - 1.0,
        ];
        println!("{scheme:?}: duration, max overlap, rebound relative errors {errors:?}");
        assert!(errors.iter().all(|e| e.abs() < 0.005), "{scheme:?}: {errors:?}");
    }
}

#[test]
fn contact_duration_converges_at_second_order() {
    let (_, duration_theory) = two_disk_theory();
    for scheme in SCHEMES {
        let errors: Vec<f64> = [20.0, 40.0, 80.0, 160.0]
            .iter()
            .map(|n| ((two_disk_impact(scheme, duration_theory / n).0 - duration_theory) / duration_theory).abs())
            .collect();
        let ratios: Vec<f64> = errors.windows(2).map(|w| w[0] / w[1]).collect();
        println!("{scheme:?}: errors {errors:?}, ratios {ratios:?}");
        assert!(ratios.iter().all(|r| *r >= 3.5), "{scheme:?}: ratios {ratios:?}");
    }
}

/// A disk hitting the floor at 1 m/s (no gravity); returns the measured restitution.
fn wall_restitution(beta: f64) -> f64 {
    let (_, duration) = hertz_impact(same_material_e_star(E, NU), R, disk_mass(R), 1.0);
    let mut scene = free_scene(E, IntegratorKind::AdamsBashforthMoulton, duration / 100.0);
    scene.material.beta = Some(beta);
    scene.run.duration = 0.2 * R / 1.0 + 3.0 * duration;
    let disks = vec![InitialDisk { x: 0.5, y: 1.1 * R, r: R, vy: -1.0, ..Default::default() }];
    let rec = run_scene(&scene, Some(disks), &mut |_| Control::Continue).unwrap();
    rec.final_state.vy[0]
}

#[test]
fn restitution_falls_with_beta_and_edem_relation_error_is_bounded() {
    let betas = [0.0, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7];
    let measured: Vec<f64> = betas.iter().map(|b| wall_restitution(*b)).collect();
    println!("beta   measured e   EDEM e   error");
    let mut worst: f64 = 0.0;
    for (b, e) in betas.iter().zip(&measured) {
        let edem = restitution_from_beta(*b);
        worst = worst.max((e - edem).abs());
        println!("{b:5.2}  {e:10.4}  {edem:8.4}  {:+.4}", e - edem);
    }
    println!("largest |measured - EDEM| = {worst:.4}");
    assert!((measured[0] - 1.0).abs() < 1e-3, "undamped impact must be elastic: {}", measured[0]);
    assert!(measured.windows(2).all(|w| w[1] < w[0]), "restitution must fall with beta: {measured:?}");
    // EDEM's relation is exact for a linear spring-dashpot; with Hertz stiffness and the Fn >= 0 clamp the
    // measured restitution lies above it, increasingly with beta.
    assert!(worst < 0.2, "EDEM relation off by {worst}");
}

/// Normal stiffness of the linear-law impacts (N/m).
const LINEAR_STIFFNESS: f64 = 1e5;

/// Duration of an undamped linear-law disk-wall contact, π √(m / k) (s).
fn linear_contact_time() -> f64 {
    std::f64::consts::PI * (disk_mass(R) / LINEAR_STIFFNESS).sqrt()
}

/// A disk hitting the floor at 1 m/s (no gravity) under the linear spring-dashpot law with damping
/// ratio `beta`; returns (restitution, contact duration) measured from per-step overlaps.
fn linear_wall_impact(beta: f64, allow_tension: bool) -> (f64, f64) {
    let mut scene = free_scene(E, IntegratorKind::AdamsBashforthMoulton, linear_contact_time() / 1000.0);
    scene.material.beta = Some(beta);
    scene.contact.allow_tension = allow_tension;
    scene.contact.law = ContactLawKind::Linear;
    scene.contact.linear = LinearNormal { normal_stiffness: Some(LINEAR_STIFFNESS), tangential_stiffness_ratio: 0.8 };
    floor_impact::<LinearSpringDashpot>(&scene, R)
}

#[test]
fn linear_law_impacts_follow_the_damped_oscillator_exactly_with_tension() {
    // Tension allowed, the contact is a damped harmonic oscillator of damping ratio β: it lasts
    // π / (ω √(1 − β²)) and EDEM's relation gives its restitution exactly. (The last step in contact
    // applies its damping force for the whole step: an error of order β ω dt in the restitution,
    // which depends on where the end falls within a step; up to 0.25 % at 1 000 steps per contact.)
    let omega = (LINEAR_STIFFNESS / disk_mass(R)).sqrt();
    for beta in [0.0, 0.1, 0.3, 0.5] {
        let (restitution, duration) = linear_wall_impact(beta, true);
        let duration_theory = std::f64::consts::PI / (omega * (1.0 - beta * beta).sqrt());
        let errors = [restitution / restitution_from_beta(beta) - 1.0, duration / duration_theory - 1.0];
        println!("beta {beta}: restitution {restitution:.5}, duration {duration:.4e} s; relative errors {errors:?}");
        assert!(errors[0].abs() < 0.003 && errors[1].abs() < 1e-4, "beta {beta}: {errors:?}");
    }
    // Clamped at Fn >= 0, a damped contact lets go before the overlap is gone, without the pull that
    // tension would have given: the rebound is faster than EDEM's relation says.
    assert_eq!(linear_wall_impact(0.0, false), linear_wall_impact(0.0, true));
    for beta in [0.1, 0.3, 0.5] {
        let (clamped, _) = linear_wall_impact(beta, false);
        println!("beta {beta}: clamped restitution {clamped:.5}, EDEM {:.5}", restitution_from_beta(beta));
        assert!(clamped > restitution_from_beta(beta) * 1.01, "beta {beta}: clamped restitution {clamped}");
    }
}

#[test]
fn disk_resting_on_floor_has_hertz_static_overlap_and_no_unbalanced_force() {
    let mut scene = free_scene(1e8, IntegratorKind::AdamsBashforthMoulton, 2e-6);
    scene.gravity = [0.0, -9.81];
    scene.material.restitution = Some(0.3);
    scene.material.beta = None;
    scene.run.duration = 0.3;
    let disks = vec![InitialDisk { x: 0.5, y: R, r: R, ..Default::default() }];
    let rec = run_scene(&scene, Some(disks), &mut |_| Control::Continue).unwrap();
    let weight = disk_mass(R) * 9.81;
    let e_star = same_material_e_star(1e8, NU);
    let theory = (weight / (4.0 / 3.0 * e_star * R.sqrt())).powf(2.0 / 3.0);
    let overlap = R - rec.final_state.y[0];
    let ubf = *rec.history.unbalanced_force_ratio.last().unwrap();
    println!("static overlap {overlap:.6e} m, Hertz {theory:.6e} m, UBF {ubf:.3e}");
    assert!(((overlap - theory) / theory).abs() < 1e-3);
    assert!(ubf < 1e-6, "UBF {ubf}");
}

#[test]
fn rolling_friction_decelerates_a_rolling_disk_as_theory_says_and_stops_it() {
    // Rolling without slip against the constant torque μ0 m g R: m a R + I a / R = −μ0 m g R with
    // I = m R²/2, so the disk slows at (2/3) μ0 g until it stops, and then stays put.
    let (mu0, v0, g) = (0.05, 0.2, 9.81);
    let deceleration_theory = 2.0 / 3.0 * mu0 * g;
    let mut scene = free_scene(1e8, IntegratorKind::AdamsBashforthMoulton, 2e-6);
    scene.gravity = [0.0, -g];
    scene.material.restitution = Some(0.3);
    scene.material.beta = None;
    scene.material.friction = 0.5;
    scene.material.rolling_friction = mu0;
    let disks = [InitialDisk { x: 0.5, y: R, r: R, vx: v0, omega: -v0 / R, ..Default::default() }];
    let mut sim = Simulation::<HertzMindlin>::new(&scene, &disks);
    let mut advance_to = |time: f64| {
        while sim.time() < time {
            sim.advance(false);
        }
        let p = sim.particles();
        (p.x[0], p.vx[0], p.omega[0])
    };
    let (_, v1, _) = advance_to(0.05);
    let (_, v2, w2) = advance_to(0.25);
    let deceleration = (v1 - v2) / 0.2;
    println!("deceleration {deceleration:.5} m/s² (theory {deceleration_theory:.5}), slip {:.2e} m/s", v2 + w2 * R);
    assert!((deceleration / deceleration_theory - 1.0).abs() < 0.01, "deceleration {deceleration}");
    // Stops after v0 / a ≈ 0.61 s and neither creeps nor rocks back.
    let (x3, v3, w3) = advance_to(0.9);
    let (x4, v4, w4) = advance_to(1.2);
    println!("at rest: x moved {:.2e} m in 0.3 s, vx {v4:.2e} m/s, omega {w4:.2e} rad/s", x4 - x3);
    assert!((x4 - x3).abs() < 1e-6 && v3.abs().max(v4.abs()) < 1e-5 && (w3.abs().max(w4.abs())) * R < 1e-5);
}

/// Steps `sim` to `time` (s) and returns the trapezoid sum of its disk 0's angular velocity over
/// the steps taken (rad).
fn integrate_spin<L: demsweep::physics::ContactLaw>(sim: &mut Simulation<L>, time: f64) -> f64 {
    let mut turned = 0.0;
    while sim.time() < time {
        let before = sim.particles().omega[0];
        sim.advance(false);
        turned += 0.5 * (before + sim.particles().omega[0]) * sim.time_step();
    }
    turned
}

#[test]
fn a_free_disk_turns_by_its_spin_times_the_time_and_without_rotation_keeps_its_angle() {
    for scheme in SCHEMES {
        let (theta0, omega0) = (0.7, -37.0);
        let mut scene = free_scene(E, scheme, 1e-5);
        scene.gravity = [0.0, -9.81];
        let spinning = InitialDisk { x: 0.3, y: 0.5, r: R, omega: omega0, angle: theta0, ..Default::default() };
        let still = InitialDisk { x: 0.6, omega: 0.0, ..spinning };
        let mut sim = Simulation::<HertzMindlin>::new(&scene, &[spinning, still]);
        integrate_spin(&mut sim, 0.2);
        let (t, p) = (sim.time(), sim.particles());
        let theory = theta0 + omega0 * t;
        println!("{scheme:?}: angle {} after {t} s, theory {theory}", p.angle[0]);
        assert!((p.angle[0] - theory).abs() < 1e-10 * theory.abs(), "{scheme:?}: {} vs {theory}", p.angle[0]);
        assert_eq!(p.angle[1], theta0, "{scheme:?}: a disk that does not spin keeps its angle");
        // Without friction nor spin no rotation is computed at all: the angle stays as it was.
        let mut still_scene = Simulation::<HertzMindlin>::new(&scene, &[still]);
        integrate_spin(&mut still_scene, 0.05);
        assert_eq!(still_scene.particles().angle[0], theta0);
    }
}

#[test]
fn a_disk_sliding_into_rolling_turns_by_the_integral_of_its_spin() {
    // Thrown along the floor without spin: friction μ m g slows it (v = v0 − μ g t) and spins it up
    // (ω = −2 μ g t / R) until it rolls, at t_s = v0 / (3 μ g), with v = 2 v0 / 3; then
    // θ(t) = −μ g t_s² / R − (2 v0 / 3R) (t − t_s).
    let (mu, v0, g, end) = (0.3, 0.2, 9.81, 0.1);
    let slip_end = v0 / (3.0 * mu * g);
    let theory = -mu * g * slip_end * slip_end / R - 2.0 * v0 / (3.0 * R) * (end - slip_end);
    for scheme in SCHEMES {
        let mut scene = free_scene(1e8, scheme, 2e-6);
        scene.gravity = [0.0, -g];
        scene.material.restitution = Some(0.3);
        scene.material.beta = None;
        scene.material.friction = mu;
        let disks = [InitialDisk { x: 0.3, y: R, r: R, vx: v0, ..Default::default() }];
        let mut sim = Simulation::<HertzMindlin>::new(&scene, &disks);
        let turned = integrate_spin(&mut sim, end);
        let p = sim.particles();
        let (angle, rolled) = (p.angle[0], (p.x[0] - 0.3) / R);
        println!(
            "{scheme:?}: angle {angle:.6} rad, trapezoid of ω {turned:.6}, theory {theory:.6}; ω R / v {:.5}",
            -p.omega[0] * R / p.vx[0]
        );
        // The scheme's own integral of ω: the paper's trapezoid rule exactly; velocity Verlet's
        // half-step spins to second order in Δt.
        assert!((angle - turned).abs() < 1e-9 * theory.abs(), "{scheme:?}: {angle} vs {turned}");
        // The rigid-body answer, to the contact model: the normal force builds up over the first
        // contact time (the disk starts just touching), and the tangential spring slips elastically
        // (measured: 2.1e-3 low).
        assert!((angle / theory - 1.0).abs() < 5e-3, "{scheme:?}: {angle} vs {theory}");
        // While it slid, the centre went v0 t_s − μ g t_s²/2 and the rim turned μ g t_s²: the centre
        // is ahead by v0 t_s / 2 for good.
        let slip = (rolled + angle) / (0.5 * v0 * slip_end / R);
        println!("{scheme:?}: slip {slip:.5} of theory");
        assert!((slip - 1.0).abs() < 0.03, "{scheme:?}: slip {slip} of theory (measured 1.017)");
    }
}

#[test]
fn oblique_sliding_impact_matches_rigid_body_coulomb_theory() {
    // The rigid-body result holds whatever the normal law: both laws are checked.
    let (mu, vx0, vy0) = (0.1, 2.0, 1.0);
    let hertz_duration = hertz_impact(same_material_e_star(E, NU), R, disk_mass(R), vy0).1;
    let cases = [(ContactLawKind::HertzMindlin, hertz_duration), (ContactLawKind::Linear, linear_contact_time())];
    for (scheme, (law, duration)) in SCHEMES.into_iter().flat_map(|scheme| cases.map(|case| (scheme, case))) {
        let mut scene = free_scene(E, scheme, duration / 100.0);
        scene.contact.law = law;
        scene.contact.linear.normal_stiffness = Some(LINEAR_STIFFNESS);
        scene.material.friction = mu;
        scene.run.duration = 0.2 * R / vy0 + 3.0 * duration;
        let disks = vec![InitialDisk { x: 0.5, y: 1.1 * R, r: R, vx: vx0, vy: -vy0, ..Default::default() }];
        let rec = run_scene(&scene, Some(disks), &mut |_| Control::Continue).unwrap();
        let s = &rec.final_state;
        // Sliding throughout (vx0 > 3 μ (1+e) vy0): tangential impulse μ·(1+e)·m·vy0.
        let e = s.vy[0] / vy0;
        let vx_theory = vx0 - mu * (1.0 + e) * vy0;
        let omega_theory = -2.0 * mu * (1.0 + e) * vy0 / R;
        println!(
            "{scheme:?}, {law:?}: vx {:.5} (theory {vx_theory:.5}), omega {:.4} (theory {omega_theory:.4})",
            s.vx[0], s.omega[0]
        );
        assert!(((s.vx[0] - vx_theory) / (vx0 - vx_theory)).abs() < 0.02);
        assert!(((s.omega[0] - omega_theory) / omega_theory).abs() < 0.02);
    }
}

/// A disk hitting the floor at 1 m/s (no gravity, no dashpot) under the hysteretic linear law with
/// loading stiffness `LINEAR_STIFFNESS` and unloading ratio `ratio`, time step `dt`; returns
/// (restitution, duration of the force) measured from per-step states.
fn hysteretic_wall_impact(ratio: f64, dt: f64) -> (f64, f64) {
    let mut scene = free_scene(E, IntegratorKind::VelocityVerlet, dt);
    scene.material.beta = Some(0.0);
    scene.material.friction = 0.0;
    scene.contact.law = ContactLawKind::HystereticLinear;
    scene.contact.hysteretic_linear = HystereticNormal {
        loading_stiffness: Some(LINEAR_STIFFNESS),
        unloading_stiffness_ratio: ratio,
        ..Default::default()
    };
    let gap = 0.01 * R;
    let disks = [InitialDisk { x: 0.5, y: R + gap, r: R, vy: -1.0, ..Default::default() }];
    let mut sim = Simulation::<HystereticLinear>::new(&scene, &disks);
    // The force acts from first touch until the disk leaves its plastic dent (it moves at its
    // rebound speed from then on: the speed changes no more).
    let (mut first, mut last, mut previous) = (None, 0.0, -1.0);
    while sim.time() < 1.0 {
        sim.advance(false);
        let vy = sim.particles().vy[0];
        if vy != previous {
            first.get_or_insert(sim.time() - dt);
            last = sim.time();
        } else if first.is_some() {
            break;
        }
        previous = vy;
    }
    (sim.particles().vy[0], last - first.expect("an impact"))
}

#[test]
fn hysteretic_law_rebounds_with_the_root_of_its_stiffness_ratio() {
    let m = disk_mass(R);
    for ratio in [1.0, 4.0, 16.0] {
        let k2 = LINEAR_STIFFNESS * ratio;
        let duration = 0.5 * std::f64::consts::PI * ((m / LINEAR_STIFFNESS).sqrt() + (m / k2).sqrt());
        let dt = duration / 2000.0;
        let (restitution, measured) = hysteretic_wall_impact(ratio, dt);
        let expected = 1.0 / ratio.sqrt();
        println!(
            "k2/k1 = {ratio}: e = {restitution:.5} (theory {expected:.5}), contact {measured:.4e} s (theory {duration:.4e})"
        );
        assert!((restitution - expected).abs() < 2e-3, "restitution {restitution} against {expected}");
        assert!((measured - duration).abs() < 4.0 * dt, "duration {measured} against {duration}");
    }
}

#[test]
fn hysteretic_law_keeps_its_energy_balance_in_a_pile() {
    // A small deposition: the plastic work is part of the dissipated energy, so the balance closes.
    let mut scene = demsweep::physics::SceneConfig::default();
    scene.particles.count = 60;
    scene.domain.width = 0.2;
    scene.contact.law = ContactLawKind::HystereticLinear;
    scene.integrator.contact_time_fraction = Some(0.02);
    scene.run.duration = 0.6;
    scene.run.stop_at_settle = false;
    let rec = run_scene(&scene, None, &mut |_| Control::Continue).unwrap();
    let worst = largest_balance_error(&rec.history);
    let dissipated = *rec.history.dissipated.last().unwrap();
    println!("hysteretic pile: {:?}, balance error {worst:.3e} J of {dissipated:.3e} J dissipated", rec.status);
    assert!(dissipated > 0.0 && worst < 0.01 * dissipated, "balance off by {worst} J of {dissipated} J");
}
