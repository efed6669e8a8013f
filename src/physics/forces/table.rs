//! The table of one block's touching pairs, one array per quantity, and what all contacts of a class
//! share.

use super::kept_rows::KeptRows;
use crate::physics::contact::{
    self, Coefficients, ContactForce, ContactLaw, ContactOptions, Kinematics, PairProperties,
};
use crate::physics::contact_sums::BLOCK;
use crate::physics::material::ContactMaterial;
use std::ops::Range;

/// Whether a law's contact state takes memory (a law without state has `S = ()`: every use of it is
/// compiled out, bounds checks included).
#[inline(always)]
pub(super) const fn stateful<S>() -> bool {
    std::mem::size_of::<S>() != 0
}

/// The law states `range` of `states`; none for a law without state (so that its loops carry no
/// slice at all).
#[inline(always)]
pub(super) fn states_of<S>(states: &mut [S], range: Range<usize>) -> &mut [S] {
    if stateful::<S>() { &mut states[range] } else { &mut [] }
}

/// The tangential springs and law states of a run of candidates.
pub(super) type Histories<'a, S> = (&'a mut [f64], &'a mut [S]);

/// Longest candidate list whose narrow phase always branches on contact (see
/// `TouchingPairs::collect`): in lists this short the predictor learns which pairs touch from step
/// to step; in longer ones the loads a mispredicted branch waits on come from memory.
pub(super) const PREDICTED_CANDIDATES: usize = 20_000;

/// What all contacts of one class (disk-disk or disk-wall) share.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactParameters {
    /// Material constants of the contact.
    pub material: ContactMaterial,
    /// Law-independent options (tension, tangential forces, μ).
    pub options: ContactOptions,
    /// Whether torques are accumulated (false when nothing can spin).
    pub rotation: bool,
    /// Time step (s), for the tangential spring.
    pub dt: f64,
}

impl ContactParameters {
    /// The effective properties of a contact of this kind with `R*` and `m*`.
    #[inline(always)]
    pub(in crate::physics) fn pair_properties(&self, r_star: f64, m_star: f64) -> PairProperties {
        let m = &self.material;
        PairProperties { e_star: m.e_star, g_star: m.g_star, r_star, m_star, beta: m.beta }
    }

    /// The force of one contact of effective radius and mass `(R*, m*)` with `motion`, from its
    /// history (spring, law state) before the step, as the block stages compute it.
    pub(in crate::physics) fn force_of<L: ContactLaw>(
        &self,
        law: &L,
        (r_star, m_star): (f64, f64),
        motion: &Kinematics,
        (mut spring, mut state): (f64, L::State),
    ) -> ContactForce {
        let coefficients = law.coefficients(&self.pair_properties(r_star, m_star), motion.overlap, &mut state);
        self.resolve(&coefficients, motion, &mut spring)
    }

    /// Resolves one contact from its coefficients and relative motion, updating its `spring`.
    #[inline(always)]
    pub(in crate::physics) fn resolve(&self, c: &Coefficients, k: &Kinematics, spring: &mut f64) -> ContactForce {
        contact::resolve(c, &self.options, k, spring, self.dt)
    }
}

/// The touching pairs of one block, one array per quantity. Fixed-size arrays: indexing them all
/// with one row number costs one bounds check.
#[derive(Clone, Debug)]
pub struct TouchingPairs<S> {
    /// The rows' pairs and what of them stays from step to step (swapped for a block's own, see
    /// [`KeptRows`]).
    pub(super) rows: Box<KeptRows>,
    /// Each block's rows as the narrow phase left them at a previous step (short lists).
    pub(super) kept: Vec<Box<KeptRows>>,
    /// Calls of [`TouchingPairs::contacts`] so far (which call each block's rows are from).
    pub(super) calls: u64,
    /// Whether some kept rows are [`KeptRows::fresher`] than the list.
    pub(super) fresher: bool,
    /// Blocks whose touching pairs were gathered unchanged; gathers whose far pairs apart were
    /// not tested, and those whose far pairs were (the tests' view of those paths).
    #[cfg(test)]
    pub(super) unchanged_blocks: usize,
    #[cfg(test)]
    pub(super) apart_tests_skipped: usize,
    #[cfg(test)]
    pub(super) far_tests: usize,
    /// Touching pairs of each block at the previous step (a hint for the narrow phase).
    pub(super) touching_before: Vec<u8>,
    // Gathered by the narrow phase.
    pub(super) dx: [f64; BLOCK],
    pub(super) dy: [f64; BLOCK],
    /// `v_i − v_j`.
    pub(super) dvx: [f64; BLOCK],
    pub(super) dvy: [f64; BLOCK],
    /// `ω_i` and `ω_j` (a wall: 0); stage 2 takes `ω_i r_i` and `ω_j r_j` four at a time.
    pub(super) omega_i: [f64; BLOCK],
    pub(super) omega_j: [f64; BLOCK],
    /// The law's contact state, before and after the step.
    pub(super) state: [S; BLOCK],
    // Computed by the vector stage.
    /// Unit normal from disk i to disk j.
    pub(super) unit_x: [f64; BLOCK],
    pub(super) unit_y: [f64; BLOCK],
    /// The law's coefficients: elastic normal force, normal damping, tangential damping (the
    /// tangential stiffness has its own column below).
    pub(super) elastic: [f64; BLOCK],
    pub(super) normal_damping: [f64; BLOCK],
    pub(super) tangential_damping: [f64; BLOCK],
    /// Contact force on disk i (on j: the opposite).
    pub(super) force_x: [f64; BLOCK],
    pub(super) force_y: [f64; BLOCK],
    /// Torques on disks i and j.
    pub(super) torque_i: [f64; BLOCK],
    pub(super) torque_j: [f64; BLOCK],
    pub(super) overlap: [f64; BLOCK],
    pub(super) normal: [f64; BLOCK],
    pub(super) tangential: [f64; BLOCK],
    pub(super) tangential_stiffness: [f64; BLOCK],
}

impl<S: Copy + Default> Default for TouchingPairs<S> {
    fn default() -> Self {
        let column = [0.0; BLOCK];
        Self {
            rows: Box::default(),
            kept: Vec::new(),
            calls: 0,
            fresher: false,
            #[cfg(test)]
            unchanged_blocks: 0,
            #[cfg(test)]
            apart_tests_skipped: 0,
            #[cfg(test)]
            far_tests: 0,
            touching_before: Vec::new(),
            dx: column,
            dy: column,
            dvx: column,
            dvy: column,
            omega_i: column,
            omega_j: column,
            state: [S::default(); BLOCK],
            unit_x: column,
            unit_y: column,
            elastic: column,
            normal_damping: column,
            tangential_damping: column,
            force_x: column,
            force_y: column,
            torque_i: column,
            torque_j: column,
            overlap: column,
            normal: column,
            tangential: column,
            tangential_stiffness: column,
        }
    }
}

impl<S: Copy + Default + PartialEq> TouchingPairs<S> {
    /// The two disks of row `c` (a disk-wall contact: the disk twice).
    #[inline(always)]
    pub(super) fn bodies(&self, c: usize) -> (usize, usize) {
        let [i, j] = self.rows.bodies[c];
        (i as usize, j as usize)
    }
}
