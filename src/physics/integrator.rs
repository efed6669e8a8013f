//! Time integration schemes. Each splits a step around the force evaluation:
//! [`Integrator::advance`] moves the state from `t` to `t + Δt` using the forces at `t`,
//! then the caller evaluates forces at the new state, then [`Integrator::finish`] completes the step.
//!
//! The force arrays hold contact forces only; gravity `g` enters as an acceleration. `advance`
//! is the last reader of the forces at `t`: it clears them for the next evaluation and reports their
//! power `Σ F·v + M·ω` at `t` (for the energy balance) and the longest move of a disk (for the
//! neighbour list), all in the same pass over the disks. It takes the disks a range at a time, so
//! that each range's arrays stay in cache from the power sum to the update.
//!
//! Numerical damping ([`DampingConfig`]) is added to the net force and torque of every disk
//! where the scheme reads them; its power is reported separately. Scenes without it run a copy of
//! each loop compiled without it (`DAMPED = false`), so they pay nothing for it.

use std::ops::Range;

use super::config::{DampingConfig, IntegratorKind};
use super::particles::Particles;
use super::vector;

/// What [`Integrator::advance`] reports about the disks it moved.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Moved {
    /// Power of the contact forces and torques at the start of the step (W).
    pub power: f64,
    /// The longest move of a disk (`root()`: its length in m, NaN if some move was NaN).
    pub longest: vector::LargestSquare,
    /// Power of the numerical damping forces and torques at the start of the step (W, ≤ 0).
    pub damping_power: f64,
}

/// A time stepping scheme with whatever history it keeps.
#[derive(Clone, Debug)]
pub enum Integrator {
    /// The paper's scheme (eqs 19-24): velocities by Adams-Bashforth 2 (Adams-Bashforth 1 on the first
    /// step), positions by the trapezoid rule (Adams-Moulton 2) over the old and new velocities, and
    /// so the spins and rotation angles where rotation is computed.
    AdamsBashforthMoulton {
        /// Accelerations of the previous step, `None` before the first step.
        previous: Option<Accelerations>,
    },
    /// Velocity Verlet: half kick, drift, forces, half kick. Damping forces see the half-step velocity.
    /// The rotation angle drifts with the half-step angular velocity, as the positions do.
    VelocityVerlet,
}

/// Stored accelerations `a_{i-1}`, `α_{i-1}` for the Adams-Bashforth step.
#[derive(Clone, Debug, Default)]
pub struct Accelerations {
    ax: Vec<f64>,
    ay: Vec<f64>,
    alpha: Vec<f64>,
}

/// What a step needs besides the particles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepContext {
    /// Time step (s).
    pub dt: f64,
    /// Gravitational acceleration (m/s²).
    pub gravity: [f64; 2],
    /// Whether angular velocities and rotation angles can change (false when no torque can arise and
    /// nothing spins).
    pub rotation: bool,
    /// Numerical damping.
    pub damping: DampingConfig,
}

/// The forces of the numerical damping (see [`DampingConfig`]): Cundall's local damping
/// `−α |F| sign(v)` per component, of the contact force plus (with `local_gravity`) the weight, and
/// viscous damping `−c m v` (`−c I ω`).
impl DampingConfig {
    /// The damping force of one component (N, or N·m for a torque): `contact` is the contact force,
    /// `weight` the gravity force (0 for torques), `inertia` the mass (or moment of inertia) and `v`
    /// the velocity (or angular velocity) it acts against.
    #[inline(always)]
    pub fn force(&self, contact: f64, weight: f64, inertia: f64, v: f64) -> f64 {
        let damped = if self.local_gravity { contact + weight } else { contact };
        let sign = f64::from(i8::from(v > 0.0) - i8::from(v < 0.0));
        -self.local * damped.abs() * sign - self.viscous * inertia * v
    }

    /// Power of the damping at the current state of `disks` (W): the forces in `p` are the contact
    /// forces of this state.
    pub fn power(&self, p: &Particles, gravity: [f64; 2], rotation: bool) -> f64 {
        let mut power = 0.0;
        for i in 0..p.len() {
            let m = p.mass[i];
            power += self.force(p.fx[i], m * gravity[0], m, p.vx[i]) * p.vx[i]
                + self.force(p.fy[i], m * gravity[1], m, p.vy[i]) * p.vy[i];
            if rotation {
                power += self.force(p.torque[i], 0.0, 1.0 / p.inv_inertia[i], p.omega[i]) * p.omega[i];
            }
        }
        power
    }
}

impl Integrator {
    /// A fresh integrator of the given kind.
    pub fn new(kind: IntegratorKind) -> Self {
        match kind {
            IntegratorKind::AdamsBashforthMoulton => Integrator::AdamsBashforthMoulton { previous: None },
            IntegratorKind::VelocityVerlet => Integrator::VelocityVerlet,
        }
    }

    /// Moves the positions (and velocities) of `disks` from `t` to `t + dt` using the contact forces
    /// at `t` and clears their forces.
    pub fn advance(&mut self, p: &mut Particles, c: &StepContext, disks: Range<usize>) -> Moved {
        match self {
            Integrator::AdamsBashforthMoulton { previous } => {
                let prev = previous.get_or_insert_with(|| first_step_history(p, c));
                if c.damping.is_active() {
                    adams_step::<true>(p, prev, c, disks)
                } else {
                    vector::widest(
                        #[inline(always)]
                        || adams_step::<false>(p, prev, c, disks),
                    )
                }
            }
            Integrator::VelocityVerlet => {
                let (power, damping_power) = kick_either(p, c, true, disks.clone());
                let n = disks.len();
                let (x, y) = (&mut p.x[disks.clone()][..n], &mut p.y[disks.clone()][..n]);
                let (vx, vy) = (&p.vx[disks.clone()][..n], &p.vy[disks.clone()][..n]);
                let mut longest = vector::LargestSquare::default();
                for i in 0..n {
                    let (step_x, step_y) = (vx[i] * c.dt, vy[i] * c.dt);
                    x[i] += step_x;
                    y[i] += step_y;
                    longest.add(step_x, step_y);
                }
                if c.rotation {
                    turn(p, c.dt, disks);
                }
                Moved { power, longest, damping_power }
            }
        }
    }

    /// Completes the step after forces at the new positions have been evaluated.
    pub fn finish(&mut self, p: &mut Particles, c: &StepContext) {
        if let Integrator::VelocityVerlet = self {
            kick_either(p, c, false, 0..p.len());
        }
    }
}

/// AB1 on the first step equals AB2 with `a_{-1} = a_0`.
fn first_step_history(p: &Particles, c: &StepContext) -> Accelerations {
    let n = p.len();
    let d = &c.damping;
    let linear = |f: &[f64], v: &[f64], g: f64| -> Vec<f64> {
        (0..n).map(|i| (f[i] + d.force(f[i], p.mass[i] * g, p.mass[i], v[i])) * p.inv_mass[i] + g).collect()
    };
    let angular = |i: usize| {
        let torque = p.torque[i] + d.force(p.torque[i], 0.0, 1.0 / p.inv_inertia[i], p.omega[i]);
        torque * p.inv_inertia[i]
    };
    Accelerations {
        ax: linear(&p.fx, &p.vx, c.gravity[0]),
        ay: linear(&p.fy, &p.vy, c.gravity[1]),
        alpha: if c.rotation { (0..n).map(angular).collect() } else { Vec::new() },
    }
}

/// One Adams-Bashforth-Moulton step of `disks`; with `DAMPED`, the numerical damping acts on the
/// net forces and torques at `t`.
#[inline(always)]
fn adams_step<const DAMPED: bool>(
    p: &mut Particles,
    prev: &mut Accelerations,
    c: &StepContext,
    disks: Range<usize>,
) -> Moved {
    let h = 0.5 * c.dt;
    let [gx, gy] = c.gravity;
    let n = disks.len();
    let d = || disks.clone();
    // Equal-length slices: no bounds checks, and the loop vectorises.
    let (x, y, vx, vy) = (&mut p.x[d()][..n], &mut p.y[d()][..n], &mut p.vx[d()][..n], &mut p.vy[d()][..n]);
    let (fx, fy, inv_mass) = (&mut p.fx[d()][..n], &mut p.fy[d()][..n], &p.inv_mass[d()][..n]);
    let mass = &p.mass[d()][..n];
    let (prev_ax, prev_ay) = (&mut prev.ax[d()][..n], &mut prev.ay[d()][..n]);
    // The power first, in a loop of its own: a running sum would keep the update from vectorising.
    let mut power = vector::lane_sum(n, |i| fx[i] * vx[i] + fy[i] * vy[i]);
    let mut longest = vector::LargestSquare::default();
    let mut damping_power = 0.0;
    for i in 0..n {
        if DAMPED {
            let damping_x = c.damping.force(fx[i], mass[i] * gx, mass[i], vx[i]);
            let damping_y = c.damping.force(fy[i], mass[i] * gy, mass[i], vy[i]);
            damping_power += damping_x * vx[i] + damping_y * vy[i];
            fx[i] += damping_x;
            fy[i] += damping_y;
        }
        let ax = fx[i] * inv_mass[i] + gx;
        let ay = fy[i] * inv_mass[i] + gy;
        let new_vx = vx[i] + (3.0 * ax - prev_ax[i]) * h;
        let new_vy = vy[i] + (3.0 * ay - prev_ay[i]) * h;
        let (step_x, step_y) = ((vx[i] + new_vx) * h, (vy[i] + new_vy) * h);
        x[i] += step_x;
        y[i] += step_y;
        longest.add(step_x, step_y);
        vx[i] = new_vx;
        vy[i] = new_vy;
        prev_ax[i] = ax;
        prev_ay[i] = ay;
        fx[i] = 0.0;
        fy[i] = 0.0;
    }
    if c.rotation {
        let (omega, torque, inv_inertia) = (&mut p.omega[d()][..n], &mut p.torque[d()][..n], &p.inv_inertia[d()][..n]);
        let (angle, prev_alpha) = (&mut p.angle[d()][..n], &mut prev.alpha[d()][..n]);
        power += vector::lane_sum(n, |i| torque[i] * omega[i]);
        for i in 0..n {
            if DAMPED {
                let damping = c.damping.force(torque[i], 0.0, 1.0 / inv_inertia[i], omega[i]);
                damping_power += damping * omega[i];
                torque[i] += damping;
            }
            let alpha = torque[i] * inv_inertia[i];
            let new_omega = omega[i] + (3.0 * alpha - prev_alpha[i]) * h;
            // The angle as the positions: trapezoid rule over the old and new angular velocities.
            angle[i] += (omega[i] + new_omega) * h;
            omega[i] = new_omega;
            prev_alpha[i] = alpha;
            torque[i] = 0.0;
        }
    }
    Moved { power, longest, damping_power }
}

/// The velocity Verlet drift of the angles of `disks`: `θ += ω Δt` with the half-step ω.
fn turn(p: &mut Particles, dt: f64, disks: Range<usize>) {
    let n = disks.len();
    let (angle, omega) = (&mut p.angle[disks.clone()][..n], &p.omega[disks][..n]);
    for i in 0..n {
        angle[i] += omega[i] * dt;
    }
}

/// [`kick`] with or without numerical damping, as the scene asks; returns the contact and damping powers.
fn kick_either(p: &mut Particles, c: &StepContext, clear: bool, disks: Range<usize>) -> (f64, f64) {
    if c.damping.is_active() { kick::<true>(p, c, clear, disks) } else { kick::<false>(p, c, clear, disks) }
}

/// Half kick `v += (F/m + g) dt/2` of `disks` (with `DAMPED`, the numerical damping at the current
/// velocities added to `F`); with `clear`, also clears their forces and returns the contact forces'
/// power and the damping's.
fn kick<const DAMPED: bool>(p: &mut Particles, c: &StepContext, clear: bool, disks: Range<usize>) -> (f64, f64) {
    let h = 0.5 * c.dt;
    let [gx, gy] = c.gravity;
    let n = disks.len();
    let d = || disks.clone();
    let (vx, vy, inv_mass, mass) = (&mut p.vx[d()][..n], &mut p.vy[d()][..n], &p.inv_mass[d()][..n], &p.mass[d()][..n]);
    let (fx, fy) = (&mut p.fx[d()][..n], &mut p.fy[d()][..n]);
    let (mut power, mut damping_power) = (0.0, 0.0);
    for i in 0..n {
        if clear {
            power += fx[i] * vx[i] + fy[i] * vy[i];
        }
        let (mut force_x, mut force_y) = (fx[i], fy[i]);
        if DAMPED {
            let damping_x = c.damping.force(force_x, mass[i] * gx, mass[i], vx[i]);
            let damping_y = c.damping.force(force_y, mass[i] * gy, mass[i], vy[i]);
            damping_power += damping_x * vx[i] + damping_y * vy[i];
            force_x += damping_x;
            force_y += damping_y;
        }
        vx[i] += (force_x * inv_mass[i] + gx) * h;
        vy[i] += (force_y * inv_mass[i] + gy) * h;
        if clear {
            fx[i] = 0.0;
            fy[i] = 0.0;
        }
    }
    if c.rotation {
        let (omega, torque, inv_inertia) = (&mut p.omega[d()][..n], &mut p.torque[d()][..n], &p.inv_inertia[d()][..n]);
        for i in 0..n {
            if clear {
                power += torque[i] * omega[i];
            }
            let mut moment = torque[i];
            if DAMPED {
                let damping = c.damping.force(moment, 0.0, 1.0 / inv_inertia[i], omega[i]);
                damping_power += damping * omega[i];
                moment += damping;
            }
            omega[i] += moment * inv_inertia[i] * h;
            if clear {
                torque[i] = 0.0;
            }
        }
    }
    (power, damping_power)
}
