//! What a contact law is ([`ContactLaw`]: stiffness and damping at an overlap, elastic energy,
//! its own per-contact state) and the shared machinery that turns a law's coefficients into forces:
//! damping, the `Fn ≥ 0` clamp, the tangential spring with its history and the Coulomb limit.
//!
//! Sign conventions (spec): `n` is the unit normal from body i to body j, `t = (-n_y, n_x)`;
//! the approach speed `v_n = (v_i - v_j)·n` is positive when the bodies close in; the force on i is
//! `-F_n n + F_t t` (on j the opposite) and the torque from the tangential force is `F_t R` on each.

/// Effective properties of one contact (walls: infinite radius and mass, so `R* = R_i`, `m* = m_i`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairProperties {
    /// Effective Young's modulus E* (Pa).
    pub e_star: f64,
    /// Effective shear modulus G* (Pa).
    pub g_star: f64,
    /// Effective radius R* (m).
    pub r_star: f64,
    /// Effective mass m* (kg).
    pub m_star: f64,
    /// Damping factor β.
    pub beta: f64,
}

/// Stiffness and damping of a contact at one overlap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coefficients {
    /// Elastic normal force (N), ≥ 0.
    pub normal_force: f64,
    /// Normal damping coefficient (N·s/m): damping force = coefficient × approach speed.
    pub normal_damping: f64,
    /// Tangential spring stiffness (N/m).
    pub tangential_stiffness: f64,
    /// Tangential damping coefficient (N·s/m).
    pub tangential_damping: f64,
}

/// A normal-tangential contact force law: here a composition of sub-models ([`super::Composed`]).
pub trait ContactLaw: Clone + Send + Sync + 'static {
    /// Per-contact history of the law's own besides the tangential spring (`()` for none): it
    /// starts as `Default` when two bodies first touch and is dropped when they part.
    type State: ContactState;
    /// Stiffness and damping at overlap `overlap > 0` (m), updating the contact's `state`.
    fn coefficients(&self, pair: &PairProperties, overlap: f64, state: &mut Self::State) -> Coefficients;
    /// Elastic energy stored by the normal spring at overlap `overlap` in `state` (J).
    fn normal_elastic_energy(&self, pair: &PairProperties, overlap: f64, state: &Self::State) -> f64;
    /// Coefficients of a fresh contact pressed monotonically to `overlap` (for estimates).
    fn loading_coefficients(&self, pair: &PairProperties, overlap: f64) -> Coefficients {
        self.coefficients(pair, overlap, &mut Self::State::default())
    }
}

/// A law's per-contact state ([`ContactLaw::State`]) as results and restart files hold it: one
/// number per contact.
pub trait ContactState: Copy + Default + PartialEq + Send + Sync + std::fmt::Debug {
    /// The state as a number (0 for a law without state).
    fn to_number(self) -> f64;
    /// The state a number of [`Self::to_number`] stands for.
    fn from_number(value: f64) -> Self;
}

impl ContactState for () {
    fn to_number(self) -> f64 {
        0.0
    }
    fn from_number(_: f64) -> Self {}
}

/// Contact options shared by all laws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactOptions {
    /// Keep a negative (tensile) total normal force instead of clamping it to zero.
    pub allow_tension: bool,
    /// Compute tangential forces (false when there is no friction: skips that work).
    pub tangential: bool,
    /// Sliding friction coefficient μ.
    pub friction: f64,
}

/// Relative motion of a contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kinematics {
    /// Overlap δ > 0 (m).
    pub overlap: f64,
    /// Approach speed `v_n` (m/s), positive when closing.
    pub approach_speed: f64,
    /// Relative tangential speed of the contact points `v_t` (m/s).
    pub tangential_speed: f64,
}

/// The resolved force of one contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactForce {
    /// Total normal force `F_n` (N); repulsive when positive.
    pub normal: f64,
    /// Tangential force `F_t` along `t` on body i (N).
    pub tangential: f64,
    /// Tangential spring stiffness used (N/m), for the spring's stored energy.
    pub tangential_stiffness: f64,
}

impl ContactForce {
    /// Magnitude of the contact force vector (N). (A plain square root: contact forces are far
    /// from overflowing when squared, and `hypot`'s guard against it is a slow library call.)
    #[inline]
    pub fn magnitude(&self) -> f64 {
        (self.normal * self.normal + self.tangential * self.tangential).sqrt()
    }

    /// The force vector on body i, `−F_n n + F_t t` with `t = (−n_y, n_x)`, for the unit normal
    /// `(nx, ny)` from i to j (on j: the same with `−n`, which is the opposite vector).
    #[inline(always)]
    pub fn on_first_body(&self, nx: f64, ny: f64) -> [f64; 2] {
        [-self.normal * nx - self.tangential * ny, -self.normal * ny + self.tangential * nx]
    }
}

/// Resolves one contact with coefficients `c` (from [`ContactLaw::coefficients`] at `k.overlap`):
/// normal force with damping and clamp, tangential spring update (`spring` is the accumulated
/// tangential displacement ξ, m) with the Coulomb limit `|F_t| ≤ μ F_n`.
///
/// Written without data-dependent branches (both outcomes computed, one selected), so that a loop
/// over many contacts vectorises.
#[inline(always)]
pub fn resolve(c: &Coefficients, options: &ContactOptions, k: &Kinematics, spring: &mut f64, dt: f64) -> ContactForce {
    let damped = c.normal_force + c.normal_damping * k.approach_speed;
    let normal = if options.allow_tension { damped } else { damped.max(0.0) };
    let mut tangential = 0.0;
    if options.tangential {
        let stretched = *spring + k.tangential_speed * dt;
        let damping = -c.tangential_damping * k.tangential_speed;
        let trial = -c.tangential_stiffness * stretched + damping;
        let limit = options.friction * normal.max(0.0);
        // Sliding (spec fix of eq 13): the force sits on the Coulomb limit and the spring is cut
        // back to carry at most the limit. It is never enlarged to it: when the trial force passes
        // the limit through its damping part (strong β), enlarging the spring would store energy
        // that no work put there, and the contact would hand it back as motion.
        let sliding = trial.abs() > limit;
        let spring_limit = if c.tangential_stiffness > 0.0 { limit / c.tangential_stiffness } else { 0.0 };
        *spring = if sliding { stretched.max(-spring_limit).min(spring_limit) } else { stretched };
        tangential = if sliding { limit.copysign(trial) } else { trial };
    }
    ContactForce { normal, tangential, tangential_stiffness: c.tangential_stiffness }
}

/// Elastic energy of a contact: the law's normal spring plus the tangential spring ½ S_t ξ² (J).
#[inline]
pub fn elastic_energy<L: ContactLaw>(
    law: &L,
    pair: &PairProperties,
    overlap: f64,
    force: &ContactForce,
    history: (f64, &L::State),
) -> f64 {
    let (spring, state) = history;
    law.normal_elastic_energy(pair, overlap, state) + 0.5 * force.tangential_stiffness * spring * spring
}
