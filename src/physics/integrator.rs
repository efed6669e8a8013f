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
                for (x, vx) in p.x.iter_mut().zip(&p.vx) {
                    *x += vx * dt;
                }
                for (y, vy) in p.y.iter_mut().zip(&p.vy) {
                    *y += vy * dt;
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
    let n = p.len();
    // Equal-length slices: no bounds checks, and the loop vectorises.
    let (x, y, vx, vy) = (&mut p.x[..n], &mut p.y[..n], &mut p.vx[..n], &mut p.vy[..n]);
    let (fx, fy, inv_mass) = (&p.fx[..n], &p.fy[..n], &p.inv_mass[..n]);
    let (prev_ax, prev_ay) = (&mut prev.ax[..n], &mut prev.ay[..n]);
    for i in 0..n {
        let ax = fx[i] * inv_mass[i];
        let ay = fy[i] * inv_mass[i];
        let new_vx = vx[i] + (3.0 * ax - prev_ax[i]) * h;
        let new_vy = vy[i] + (3.0 * ay - prev_ay[i]) * h;
        x[i] += (vx[i] + new_vx) * h;
        y[i] += (vy[i] + new_vy) * h;
        vx[i] = new_vx;
        vy[i] = new_vy;
        prev_ax[i] = ax;
        prev_ay[i] = ay;
    }
    if rotation {
        let (omega, torque, inv_inertia) = (&mut p.omega[..n], &p.torque[..n], &p.inv_inertia[..n]);
        let prev_alpha = &mut prev.alpha[..n];
        for i in 0..n {
            let alpha = torque[i] * inv_inertia[i];
            omega[i] += (3.0 * alpha - prev_alpha[i]) * h;
            prev_alpha[i] = alpha;
        }
    }
}

fn kick(p: &mut Particles, h: f64, rotation: bool) {
    let n = p.len();
    let (vx, vy, fx, fy, inv_mass) = (&mut p.vx[..n], &mut p.vy[..n], &p.fx[..n], &p.fy[..n], &p.inv_mass[..n]);
    for i in 0..n {
        vx[i] += fx[i] * inv_mass[i] * h;
        vy[i] += fy[i] * inv_mass[i] * h;
    }
    if rotation {
        let (omega, torque, inv_inertia) = (&mut p.omega[..n], &p.torque[..n], &p.inv_inertia[..n]);
        for i in 0..n {
            omega[i] += torque[i] * inv_inertia[i] * h;
        }
    }
}
