//! Disk state as structure-of-arrays.

use std::f64::consts::PI;

use super::contact_record::Partner;
use super::memory_order::gather;

/// Initial state of one disk (velocities default to rest).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InitialDisk {
    /// Centre x (m).
    pub x: f64,
    /// Centre y (m).
    pub y: f64,
    /// Radius (m).
    pub r: f64,
    /// Velocity x (m/s).
    pub vx: f64,
    /// Velocity y (m/s).
    pub vy: f64,
    /// Angular velocity (rad/s).
    pub omega: f64,
    /// Rotation angle (rad), counter-clockwise positive.
    pub angle: f64,
}

/// The history of one contact a simulation starts from (a restart): which bodies touch, the
/// tangential spring and the law's own state (see [`super::contact::ContactState`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InitialContact {
    /// The first disk.
    pub disk: usize,
    /// What it touches (for two disks, either order).
    pub partner: Partner,
    /// Tangential spring ξ (m).
    pub tangential_spring: f64,
    /// The contact law's state as a number (0 for laws without).
    pub law_state: f64,
}

/// All disks, one array per quantity.
#[derive(Clone, Debug, Default)]
pub struct Particles {
    /// Centre x (m).
    pub x: Vec<f64>,
    /// Centre y (m).
    pub y: Vec<f64>,
    /// Velocity x (m/s).
    pub vx: Vec<f64>,
    /// Velocity y (m/s).
    pub vy: Vec<f64>,
    /// Angular velocity (rad/s).
    pub omega: Vec<f64>,
    /// Rotation angle (rad), counter-clockwise positive: integrated from ω where rotation is computed
    /// (scenes with friction or an initial spin), else kept at its initial value.
    pub angle: Vec<f64>,
    /// Radius (m).
    pub r: Vec<f64>,
    /// Mass m = ρ π R² h (kg).
    pub mass: Vec<f64>,
    /// 1/m (1/kg).
    pub inv_mass: Vec<f64>,
    /// 1/I with I = m R²/2 (1/(kg·m²)).
    pub inv_inertia: Vec<f64>,
    /// Sum of contact forces x (N); gravity is applied by the integrator.
    pub fx: Vec<f64>,
    /// Sum of contact forces y (N).
    pub fy: Vec<f64>,
    /// Net torque (N·m).
    pub torque: Vec<f64>,
    /// Summed rolling-resistance torque magnitude before clamping (N·m).
    pub rolling: Vec<f64>,
    /// Sum of contact force magnitudes, filled on sampled steps only (N).
    pub contact_force: Vec<f64>,
}

impl Particles {
    /// Disks of density `density` and thickness `thickness` at the given initial states.
    pub fn new(disks: &[InitialDisk], density: f64, thickness: f64) -> Self {
        let mut p = Particles::default();
        for disk in disks {
            p.push(disk, density, thickness);
        }
        p
    }

    /// Adds a disk of density `density` and thickness `thickness` at its initial state, with no force.
    pub fn push(&mut self, d: &InitialDisk, density: f64, thickness: f64) {
        let m = density * PI * d.r * d.r * thickness;
        for (column, value) in [
            (&mut self.x, d.x),
            (&mut self.y, d.y),
            (&mut self.vx, d.vx),
            (&mut self.vy, d.vy),
            (&mut self.omega, d.omega),
            (&mut self.angle, d.angle),
            (&mut self.r, d.r),
            (&mut self.mass, m),
            (&mut self.inv_mass, 1.0 / m),
            (&mut self.inv_inertia, 2.0 / (m * d.r * d.r)),
        ] {
            column.push(value);
        }
        for column in [&mut self.fx, &mut self.fy, &mut self.torque, &mut self.rolling, &mut self.contact_force] {
            column.push(0.0);
        }
    }

    /// Number of disks.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether there are no disks.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Largest radius (m), 0 without disks.
    pub fn max_radius(&self) -> f64 {
        self.r.iter().cloned().fold(0.0, f64::max)
    }

    /// Numbers the disks afresh: the `k`-th disk afterwards is disk `order[k]` before (see
    /// [`super::memory_order`]); `scratch`: a buffer of any content.
    pub fn renumber(&mut self, order: &[u32], scratch: &mut Vec<f64>) {
        let columns = [
            &mut self.x,
            &mut self.y,
            &mut self.vx,
            &mut self.vy,
            &mut self.omega,
            &mut self.angle,
            &mut self.r,
            &mut self.mass,
            &mut self.inv_mass,
            &mut self.inv_inertia,
            &mut self.fx,
            &mut self.fy,
            &mut self.torque,
            &mut self.rolling,
            &mut self.contact_force,
        ];
        for column in columns {
            gather(column, order, scratch);
        }
    }

    /// Splits into read-only state and writable force accumulators, all slices of length `len()`
    /// (equal lengths let the compiler drop per-access bounds checks in the contact loops).
    #[inline(always)]
    pub fn split(&mut self) -> (State<'_>, Forces<'_>) {
        let n = self.len();
        (
            State {
                x: &self.x[..n],
                y: &self.y[..n],
                vx: &self.vx[..n],
                vy: &self.vy[..n],
                omega: &self.omega[..n],
                r: &self.r[..n],
            },
            Forces {
                fx: &mut self.fx[..n],
                fy: &mut self.fy[..n],
                torque: &mut self.torque[..n],
                rolling: &mut self.rolling[..n],
                contact_force: &mut self.contact_force[..n],
            },
        )
    }
}

/// Read-only view of positions, velocities and sizes (see [`Particles::split`]).
pub struct State<'a> {
    /// Centre x (m).
    pub x: &'a [f64],
    /// Centre y (m).
    pub y: &'a [f64],
    /// Velocity x (m/s).
    pub vx: &'a [f64],
    /// Velocity y (m/s).
    pub vy: &'a [f64],
    /// Angular velocity (rad/s).
    pub omega: &'a [f64],
    /// Radius (m).
    pub r: &'a [f64],
}

/// Writable force accumulators (see [`Particles::split`]).
pub struct Forces<'a> {
    /// Net force x (N).
    pub fx: &'a mut [f64],
    /// Net force y (N).
    pub fy: &'a mut [f64],
    /// Net torque (N·m).
    pub torque: &'a mut [f64],
    /// Summed rolling-resistance torque magnitude (N·m).
    pub rolling: &'a mut [f64],
    /// Sum of contact force magnitudes (N).
    pub contact_force: &'a mut [f64],
}

super::run_state::persist_fields!(Particles {
    x,
    y,
    vx,
    vy,
    omega,
    angle,
    r,
    mass,
    inv_mass,
    inv_inertia,
    fx,
    fy,
    torque,
    rolling,
    contact_force,
});
