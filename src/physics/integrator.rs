//! Time integration schemes. Each splits a step around the force evaluation:
//! [`Integrator::advance`] moves the state from `t` to `t + Δt` using the forces at `t`,
//! then the caller evaluates forces at the new state, then [`Integrator::finish`] completes the step.
//!
//! The force arrays hold contact forces only; gravity `g` enters as an acceleration. `advance`
//! is the last reader of the forces at `t`: it clears them for the next evaluation and reports their
//! power `Σ F·v + M·ω` at `t` (for the energy balance) and the longest move of a disk (for the
//! neighbour list), all in the same pass over the disks. It takes the disks a chunk at a time, so
//! that each chunk's arrays stay in cache from the power sum to the update, and shares the chunks
//! out between threads where it is given more than one.
//!
//! Numerical damping ([`DampingConfig`]) is added to the net force and torque of every disk
//! where the scheme reads them; its power is reported separately. Scenes without it run a copy of
//! each loop compiled without it (`DAMPED = false`), so they pay nothing for it.

use super::config::{DampingConfig, IntegratorKind};
use super::memory_order::gather;
use super::parallel::{Split, Team};
use super::particles::Particles;
use super::run_state::{Input, Persist, StateError, StateReason};
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

    /// Moves the positions (and velocities) of all disks from `t` to `t + dt` using the contact
    /// forces at `t` and clears their forces, `CHUNK` disks at a time, the chunks shared out in
    /// parts between the `team`'s threads; `moved` is scratch space for the chunks' reports, which
    /// are combined in chunk order (so the result does not depend on the threads).
    pub fn advance(&mut self, p: &mut Particles, c: &StepContext, team: &Team, moved: &mut Vec<Moved>) -> Moved {
        match self {
            Integrator::AdamsBashforthMoulton { previous } => {
                let prev = previous.get_or_insert_with(|| first_step_history(p, c));
                let disks = Moving::new(p, [&mut prev.ax, &mut prev.ay, &mut prev.alpha]);
                by_chunks(disks, team, moved, &|d| {
                    vector::widest(
                        #[inline(always)]
                        || adams_either(d, c),
                    )
                })
            }
            Integrator::VelocityVerlet => by_chunks(Moving::new(p, [&mut [], &mut [], &mut []]), team, moved, &|d| {
                vector::widest(
                    #[inline(always)]
                    || verlet_drift(d, c),
                )
            }),
        }
    }

    /// Numbers the disks of the stored history afresh, as [`Particles::renumber`] does.
    pub fn renumber(&mut self, order: &[u32], scratch: &mut Vec<f64>) {
        if let Integrator::AdamsBashforthMoulton { previous: Some(a) } = self {
            for column in [&mut a.ax, &mut a.ay, &mut a.alpha] {
                if !column.is_empty() {
                    gather(column, order, scratch);
                }
            }
        }
    }

    /// Takes in the disks of `p` from `first` on, added since the last step (a pour): their stored
    /// accelerations, where the scheme keeps them, as a first step would have them.
    pub fn add_disks(&mut self, p: &Particles, c: &StepContext, first: usize) {
        if let Integrator::AdamsBashforthMoulton { previous: Some(a) } = self {
            for i in first..p.len() {
                a.push(p, c, i);
            }
        }
    }

    /// Completes the step after forces at the new positions have been evaluated.
    pub fn finish(&mut self, p: &mut Particles, c: &StepContext, team: &Team, moved: &mut Vec<Moved>) {
        if let Integrator::VelocityVerlet = self {
            let disks = Moving::new(p, [&mut [], &mut [], &mut []]);
            by_chunks(disks, team, moved, &|d| {
                vector::widest(
                    #[inline(always)]
                    || kick_either(d, c, false),
                );
                Moved::default()
            });
        }
    }
}

/// Disks per chunk of the integrator's pass: their arrays stay in cache from the power sum to the
/// update. Chunks are also the units the pass is shared out in between threads.
const CHUNK: usize = 512;

/// The arrays the integrator reads and writes, for a run of disks; `previous`: the stored
/// accelerations `a_x`, `a_y`, `α` of the Adams-Bashforth step (empty for velocity Verlet, and
/// `α` without rotation).
pub struct Moving<'a> {
    x: &'a mut [f64],
    y: &'a mut [f64],
    vx: &'a mut [f64],
    vy: &'a mut [f64],
    omega: &'a mut [f64],
    angle: &'a mut [f64],
    fx: &'a mut [f64],
    fy: &'a mut [f64],
    torque: &'a mut [f64],
    mass: &'a [f64],
    inv_mass: &'a [f64],
    inv_inertia: &'a [f64],
    previous: [&'a mut [f64]; 3],
}

impl<'a> Moving<'a> {
    fn new(p: &'a mut Particles, previous: [&'a mut [f64]; 3]) -> Self {
        Self {
            x: &mut p.x,
            y: &mut p.y,
            vx: &mut p.vx,
            vy: &mut p.vy,
            omega: &mut p.omega,
            angle: &mut p.angle,
            fx: &mut p.fx,
            fy: &mut p.fy,
            torque: &mut p.torque,
            mass: &p.mass,
            inv_mass: &p.inv_mass,
            inv_inertia: &p.inv_inertia,
            previous,
        }
    }

    fn len(&self) -> usize {
        self.x.len()
    }

    /// The first `mid` disks and the rest.
    fn split_disks(self, mid: usize) -> (Self, Self) {
        let cut = |s: &'a mut [f64]| s.split_at_mut(mid.min(s.len()));
        let cut_shared = |s: &'a [f64]| s.split_at(mid.min(s.len()));
        let [ax, ay, alpha] = self.previous;
        let ((x0, x1), (y0, y1), (vx0, vx1), (vy0, vy1)) = (cut(self.x), cut(self.y), cut(self.vx), cut(self.vy));
        let ((w0, w1), (a0, a1), (fx0, fx1), (fy0, fy1)) =
            (cut(self.omega), cut(self.angle), cut(self.fx), cut(self.fy));
        let ((t0, t1), (m0, m1), (im0, im1)) = (cut(self.torque), cut_shared(self.mass), cut_shared(self.inv_mass));
        let ((ii0, ii1), (ax0, ax1), (ay0, ay1), (al0, al1)) =
            (cut_shared(self.inv_inertia), cut(ax), cut(ay), cut(alpha));
        let part = |x, y, vx, vy, omega, angle, fx, fy, torque, mass, inv_mass, inv_inertia, previous| Moving {
            x,
            y,
            vx,
            vy,
            omega,
            angle,
            fx,
            fy,
            torque,
            mass,
            inv_mass,
            inv_inertia,
            previous,
        };
        (
            part(x0, y0, vx0, vy0, w0, a0, fx0, fy0, t0, m0, im0, ii0, [ax0, ay0, al0]),
            part(x1, y1, vx1, vy1, w1, a1, fx1, fy1, t1, m1, im1, ii1, [ax1, ay1, al1]),
        )
    }
}

/// The disks of a pass with a report slot per chunk.
struct Chunks<'a> {
    disks: Moving<'a>,
    moved: &'a mut [Moved],
}

impl Split for Chunks<'_> {
    fn units(&self) -> usize {
        self.moved.len()
    }

    fn split_at(self, at: usize) -> (Self, Self) {
        let (d0, d1) = self.disks.split_disks(at * CHUNK);
        let (m0, m1) = self.moved.split_at_mut(at);
        (Chunks { disks: d0, moved: m0 }, Chunks { disks: d1, moved: m1 })
    }
}

/// Runs `step` on each `CHUNK` disks of `disks` (the chunks shared out between the `team`'s
/// threads) and combines their reports in chunk order: powers summed, the longest move kept.
fn by_chunks(
    disks: Moving<'_>,
    team: &Team,
    moved: &mut Vec<Moved>,
    step: &(impl Fn(&mut Moving<'_>) -> Moved + Sync),
) -> Moved {
    let mut total = Moved::default();
    let mut combine = |m: Moved| {
        total.power += m.power;
        total.damping_power += m.damping_power;
        total.longest = total.longest.max(m.longest);
    };
    if team.parts() <= 1 {
        each_chunk(disks, step, &mut combine);
        return total;
    }
    moved.clear();
    moved.resize(disks.len().div_ceil(CHUNK), Moved::default());
    team.for_each_part(Chunks { disks, moved }, &|chunks: Chunks<'_>, _| {
        let mut slots = chunks.moved.iter_mut();
        each_chunk(chunks.disks, step, &mut |m| *slots.next().expect("a slot per chunk") = m);
    });
    moved.iter().for_each(|m| combine(*m));
    total
}

/// Hands `step`'s report on each `CHUNK` disks of `disks`, in order, to `report`.
fn each_chunk(disks: Moving<'_>, step: &impl Fn(&mut Moving<'_>) -> Moved, report: &mut impl FnMut(Moved)) {
    let mut rest = disks;
    while rest.len() > CHUNK {
        let (mut chunk, after) = rest.split_disks(CHUNK);
        report(step(&mut chunk));
        rest = after;
    }
    if rest.len() > 0 {
        report(step(&mut rest));
    }
}

/// Velocity Verlet's first half of a step for one chunk: half kick, then drift (and turn).
#[inline(always)]
fn verlet_drift(d: &mut Moving<'_>, c: &StepContext) -> Moved {
    let (power, damping_power) = kick_either(d, c, true);
    let n = d.len();
    let (x, y, vx, vy) = (&mut d.x[..n], &mut d.y[..n], &d.vx[..n], &d.vy[..n]);
    let mut longest = vector::LargestSquare::default();
    for i in 0..n {
        let (step_x, step_y) = (vx[i] * c.dt, vy[i] * c.dt);
        x[i] += step_x;
        y[i] += step_y;
        longest.add(step_x, step_y);
    }
    if c.rotation {
        turn(d, c.dt);
    }
    Moved { power, longest, damping_power }
}

/// AB1 on the first step equals AB2 with `a_{-1} = a_0`.
fn first_step_history(p: &Particles, c: &StepContext) -> Accelerations {
    let mut history = Accelerations::default();
    for i in 0..p.len() {
        history.push(p, c, i);
    }
    history
}

impl Accelerations {
    /// Appends the accelerations of disk `i` of `p` at its current forces (as a first step reads them).
    fn push(&mut self, p: &Particles, c: &StepContext, i: usize) {
        let d = &c.damping;
        let linear = |f: f64, v: f64, g: f64| (f + d.force(f, p.mass[i] * g, p.mass[i], v)) * p.inv_mass[i] + g;
        self.ax.push(linear(p.fx[i], p.vx[i], c.gravity[0]));
        self.ay.push(linear(p.fy[i], p.vy[i], c.gravity[1]));
        if c.rotation {
            let torque = p.torque[i] + d.force(p.torque[i], 0.0, 1.0 / p.inv_inertia[i], p.omega[i]);
            self.alpha.push(torque * p.inv_inertia[i]);
        }
    }
}

/// [`adams_step`] with or without numerical damping, as the scene asks.
#[inline(always)]
fn adams_either(d: &mut Moving<'_>, c: &StepContext) -> Moved {
    if c.damping.is_active() { adams_step::<true>(d, c) } else { adams_step::<false>(d, c) }
}

/// One Adams-Bashforth-Moulton step of `d`; with `DAMPED`, the numerical damping acts on the net
/// forces and torques at `t`.
#[inline(always)]
fn adams_step<const DAMPED: bool>(d: &mut Moving<'_>, c: &StepContext) -> Moved {
    let h = 0.5 * c.dt;
    let [gx, gy] = c.gravity;
    let n = d.len();
    // Equal-length slices: no bounds checks, and the loop vectorises.
    let (x, y, vx, vy) = (&mut d.x[..n], &mut d.y[..n], &mut d.vx[..n], &mut d.vy[..n]);
    let (fx, fy, inv_mass, mass) = (&mut d.fx[..n], &mut d.fy[..n], &d.inv_mass[..n], &d.mass[..n]);
    let [prev_ax, prev_ay, prev_alpha] = &mut d.previous;
    let (prev_ax, prev_ay) = (&mut prev_ax[..n], &mut prev_ay[..n]);
    // The power first, in a loop of its own: a running sum would keep the update from vectorising.
    let mut power = vector::lane_dot([fx, fy], [vx, vy]);
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
        let (omega, torque, inv_inertia) = (&mut d.omega[..n], &mut d.torque[..n], &d.inv_inertia[..n]);
        let (angle, prev_alpha) = (&mut d.angle[..n], &mut prev_alpha[..n]);
        power += vector::lane_dot([torque], [omega]);
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

/// The velocity Verlet drift of the angles of `d`: `θ += ω Δt` with the half-step ω.
#[inline(always)]
fn turn(d: &mut Moving<'_>, dt: f64) {
    let n = d.len();
    let (angle, omega) = (&mut d.angle[..n], &d.omega[..n]);
    for i in 0..n {
        angle[i] += omega[i] * dt;
    }
}

/// [`kick`] with or without numerical damping, as the scene asks; returns the contact and damping powers.
#[inline(always)]
fn kick_either(d: &mut Moving<'_>, c: &StepContext, clear: bool) -> (f64, f64) {
    if c.damping.is_active() { kick::<true>(d, c, clear) } else { kick::<false>(d, c, clear) }
}

/// Half kick `v += (F/m + g) dt/2` of `d` (with `DAMPED`, the numerical damping at the current
/// velocities added to `F`); with `clear`, also clears their forces and returns the contact forces'
/// power and the damping's.
#[inline(always)]
fn kick<const DAMPED: bool>(d: &mut Moving<'_>, c: &StepContext, clear: bool) -> (f64, f64) {
    let h = 0.5 * c.dt;
    let [gx, gy] = c.gravity;
    let n = d.len();
    let (vx, vy, inv_mass, mass) = (&mut d.vx[..n], &mut d.vy[..n], &d.inv_mass[..n], &d.mass[..n]);
    let (fx, fy) = (&mut d.fx[..n], &mut d.fy[..n]);
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
        let (omega, torque, inv_inertia) = (&mut d.omega[..n], &mut d.torque[..n], &d.inv_inertia[..n]);
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

super::run_state::persist_fields!(Accelerations { ax, ay, alpha });

/// The scheme (a tag) and its history.
impl Persist for Integrator {
    fn save(&self, out: &mut Vec<u8>) {
        match self {
            Integrator::AdamsBashforthMoulton { previous } => {
                0u64.save(out);
                previous.save(out);
            }
            Integrator::VelocityVerlet => 1u64.save(out),
        }
    }
    fn load(&mut self, input: &mut Input<'_>) -> Result<(), StateError> {
        let mut tag = 0u64;
        tag.load(input)?;
        *self = match tag {
            0 => {
                let mut previous = None;
                previous.load(input)?;
                Integrator::AdamsBashforthMoulton { previous }
            }
            1 => Integrator::VelocityVerlet,
            found => return Err(input.error(StateReason::Invalid { found, expected: 1 })),
        };
        Ok(())
    }
}
