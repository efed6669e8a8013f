//! Head-on impacts integrated finely with any law, for time-step and stability estimates that need
//! no law-specific formulas.

use super::law::{ContactLaw, PairProperties};

/// Outcome of a simulated head-on impact, used for time-step estimates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactEstimate {
    /// Contact duration (s).
    pub duration: f64,
    /// Largest overlap of the damped impact (m).
    pub max_overlap: f64,
    /// Largest normal damping rate `c_n / m*` during the impact (1/s).
    pub max_damping_rate: f64,
}

/// Integrates a head-on impact at `speed` with any law (fine steps), so stability estimates work
/// for every law without law-specific formulas: duration from the undamped impact, damping rate at its deepest overlap,
/// the largest overlap from the damped one.
pub fn estimate_impact<L: ContactLaw>(law: &L, pair: &PairProperties, speed: f64) -> ImpactEstimate {
    let undamped = PairProperties { beta: 0.0, ..*pair };
    let mut state = L::State::default();
    let elastic = |d: f64, state: &mut L::State| {
        if d > 0.0 { law.coefficients(&undamped, d, state).normal_force } else { 0.0 }
    };
    // First guess of the duration from a linear spring at the overlap where all energy is stored.
    let mut dt = 1e-3 * guess_duration(law, &undamped, speed);
    let (mut d, mut v, mut t, mut dmax) = (0.0_f64, speed, 0.0_f64, 0.0_f64);
    let mut steps = 0;
    // Until the bodies part: the overlap is gone, or (a plastic law) the force has vanished on the way out.
    let mut touching = true;
    while (touching || t == 0.0) && steps < 100_000 {
        // RK4 stages at trial overlaps on a copy of the state; the state follows the accepted step.
        let accel = |d: f64| -elastic(d, &mut state.clone()) / pair.m_star;
        let (k1d, k1v) = (v, accel(d));
        let (k2d, k2v) = (v + 0.5 * dt * k1v, accel(d + 0.5 * dt * k1d));
        let (k3d, k3v) = (v + 0.5 * dt * k2v, accel(d + 0.5 * dt * k2d));
        let (k4d, k4v) = (v + dt * k3v, accel(d + dt * k3d));
        d += dt / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
        v += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        t += dt;
        dmax = dmax.max(d);
        touching = d > 0.0 && (v > 0.0 || elastic(d, &mut state) > 0.0);
        steps += 1;
        if steps == 10 && dmax <= 0.0 {
            dt *= 10.0;
        }
    }
    let damped_overlap = if pair.beta > 0.0 { damped_max_overlap(law, pair, speed, dt) } else { dmax };
    let at_max = law.loading_coefficients(pair, dmax);
    ImpactEstimate { duration: t, max_overlap: damped_overlap, max_damping_rate: at_max.normal_damping / pair.m_star }
}

/// Largest overlap of the damped impact (semi-implicit Euler with step `dt`, until it recedes).
fn damped_max_overlap<L: ContactLaw>(law: &L, pair: &PairProperties, speed: f64, dt: f64) -> f64 {
    let (mut d, mut v, mut state) = (0.0_f64, speed, L::State::default());
    for _ in 0..1_000_000 {
        let c = law.coefficients(pair, d.max(1e-300), &mut state);
        v -= (c.normal_force + c.normal_damping * v).max(0.0) / pair.m_star * dt;
        if v <= 0.0 {
            break;
        }
        d += v * dt;
    }
    d
}

/// Rough contact duration: bisect the overlap that stores the impact energy, then π/ω of the secant.
fn guess_duration<L: ContactLaw>(law: &L, pair: &PairProperties, speed: f64) -> f64 {
    let energy = 0.5 * pair.m_star * speed * speed;
    let loaded = |d: f64| {
        let mut state = L::State::default();
        law.coefficients(pair, d, &mut state);
        law.normal_elastic_energy(pair, d, &state)
    };
    let (mut lo, mut hi) = (0.0_f64, pair.r_star.max(1e-12));
    while loaded(hi) < energy && hi < 1e6 {
        hi *= 2.0;
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if loaded(mid) < energy { lo = mid } else { hi = mid }
    }
    let stiffness = law.loading_coefficients(pair, hi).normal_force / hi;
    std::f64::consts::PI * (pair.m_star / stiffness).sqrt()
}
