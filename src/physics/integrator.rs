//! Time integration schemes. Each splits a step around the force evaluation:
//! [`Integrator::advance`] moves the state from `t` to `t + Δt` using the forces at `t`,
//! then the caller evaluates forces at the new state, then [`Integrator::finish`] completes the step.

use super::config::IntegratorKind;
use super::particles::Particles;

/// A time stepping scheme with whatever history it keeps.
#[derive(Clone, Debug)]
pub enum Integrator {
    /// The paper's scheme (eqs 19-24): velocities by Adams-Bashforth 2 (Adams-Bashforth 1 on the first
    /// step), positions by the trapezoid rule (Adams-Moulton 2) over the old and new velocities.
    AdamsBashforthMoulton {
        /// Accelerations of the previous step, `None` before the first step.
        previous: Option<Accelerations>,
    },
    /// Velocity Verlet: half kick, drift, forces, half kick. Damping forces see the half-step velocity.
    VelocityVerlet,
}

/// Stored accelerations `a_{i-1}`, `α_{i-1}` for the Adams-Bashforth step.
#[derive(Clone, Debug, Default)]
pub struct Accelerations {
    ax: Vec<f64>,
    ay: Vec<f64>,
    alpha: Vec<f64>,
}

impl Integrator {
    /// A fresh integrator of the given kind.
    pub fn new(kind: IntegratorKind) -> Self {
        match kind {
            IntegratorKind::AdamsBashforthMoulton => Integrator::AdamsBashforthMoulton { previous: None },
            IntegratorKind::VelocityVerlet => Integrator::VelocityVerlet,
        }
    }

    /// Moves positions (and velocities) from `t` to `t + dt` using the current forces.
    /// `rotation`: whether angular velocities can change (false when no torque can arise).
    pub fn advance(&mut self, p: &mut Particles, dt: f64, rotation: bool) {
        match self {
            Integrator::AdamsBashforthMoulton { previous } => {
                let prev = previous.get_or_insert_with(|| first_step_history(p, rotation));
                adams_step(p, prev, dt, rotation);
            }
            Integrator::VelocityVerlet => {
                kick(p, 0.5 * dt, rotation);
                for i in 0..p.len() {
                    p.x[i] += p.vx[i] * dt;
                    p.y[i] += p.vy[i] * dt;
                }
            }
        }
    }

    /// Completes the step after forces at the new positions have been evaluated.
    pub fn finish(&mut self, p: &mut Particles, dt: f64, rotation: bool) {
        if let Integrator::VelocityVerlet = self {
            kick(p, 0.5 * dt, rotation);
        }
    }
}

/// AB1 on the first step equals AB2 with `a_{-1} = a_0`.
fn first_step_history(p: &Particles, rotation: bool) -> Accelerations {
    Accelerations {
        ax: (0..p.len()).map(|i| p.fx[i] * p.inv_mass[i]).collect(),
        ay: (0..p.len()).map(|i| p.fy[i] * p.inv_mass[i]).collect(),
        alpha: if rotation { (0..p.len()).map(|i| p.torque[i] * p.inv_inertia[i]).collect() } else { Vec::new() },
    }
}

fn adams_step(p: &mut Particles, prev: &mut Accelerations, dt: f64, rotation: bool) {
    let h = 0.5 * dt;
    for i in 0..p.len() {
        let ax = p.fx[i] * p.inv_mass[i];
        let ay = p.fy[i] * p.inv_mass[i];
        let vx = p.vx[i] + (3.0 * ax - prev.ax[i]) * h;
        let vy = p.vy[i] + (3.0 * ay - prev.ay[i]) * h;
        p.x[i] += (p.vx[i] + vx) * h;
        p.y[i] += (p.vy[i] + vy) * h;
        p.vx[i] = vx;
        p.vy[i] = vy;
        prev.ax[i] = ax;
        prev.ay[i] = ay;
    }
    if rotation {
        for i in 0..p.len() {
            let alpha = p.torque[i] * p.inv_inertia[i];
            p.omega[i] += (3.0 * alpha - prev.alpha[i]) * h;
            prev.alpha[i] = alpha;
        }
    }
}

fn kick(p: &mut Particles, h: f64, rotation: bool) {
    for i in 0..p.len() {
        p.vx[i] += p.fx[i] * p.inv_mass[i] * h;
        p.vy[i] += p.fy[i] * p.inv_mass[i] * h;
    }
    if rotation {
        for i in 0..p.len() {
            p.omega[i] += p.torque[i] * p.inv_inertia[i] * h;
        }
    }
}
