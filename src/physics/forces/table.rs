//! The table of one block's touching pairs, one array per quantity, what all contacts of a class
//! share, and the one-thread block loop ([`TouchingPairs::contacts`]) that takes the disk pairs
//! block by block through the three stages, with the disk-wall contacts in between.

use super::narrow_phase::KeptRows;
use super::stages::{CHECKED, COMPUTED};
use crate::physics::contact::{
    self, Coefficients, ContactForce, ContactLaw, ContactOptions, Kinematics, PairProperties,
};
use crate::physics::contact_sums::BLOCK;
use crate::physics::diagnostics::ContactTotals;
use crate::physics::material::ContactMaterial;
use crate::physics::neighbors::{Candidates, NeighborList, NeighborPair};
use crate::physics::particles::{Forces, State};
use crate::physics::walls::Wall;
use std::borrow::Cow;
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

/// Fewest disk-wall candidates evaluated together (see `TouchingPairs::contacts`).
pub(super) const WALL_BATCH: usize = 64;

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
    /// Writes the springs that the kept rows hold newer than `pairs` (the list their steps ran
    /// on) back to it: before anything but [`TouchingPairs::contacts`] reads or changes the list's
    /// springs (a rebuild, a renumbering, the parallel path, a new table).
    pub fn write_back_springs(&mut self, pairs: &mut Candidates<NeighborPair, S>) {
        if !std::mem::take(&mut self.fresher) {
            return;
        }
        let build = pairs.build();
        for (rows, springs) in self.kept.iter_mut().zip(pairs.springs.chunks_mut(BLOCK)) {
            if rows.fresher {
                debug_assert_eq!(rows.build, build, "kept rows of another list");
                rows.copy_springs(springs);
                rows.fresher = false;
            }
        }
    }

    /// The springs of `pairs` as they are now: the list's, with those the kept rows hold newer
    /// (see [`TouchingPairs::write_back_springs`]).
    pub fn springs_of<'a>(&self, pairs: &'a Candidates<NeighborPair, S>) -> Cow<'a, [f64]> {
        if !self.fresher {
            return Cow::Borrowed(&pairs.springs);
        }
        let mut springs = pairs.springs.clone();
        for (rows, springs) in self.kept.iter().zip(springs.chunks_mut(BLOCK)) {
            if rows.fresher {
                rows.copy_springs(springs);
            }
        }
        Cow::Owned(springs)
    }

    /// Adds all contact forces: disk pairs block by block, and between blocks, in batches, the
    /// disk-wall contacts of disks below the next block's first disk; with `SAMPLE`, also the
    /// contact sums to `totals`.
    ///
    /// Every disk's sums come out as if all disk pairs were added first and then the walls (pairs
    /// are sorted by first disk, so no later block touches a disk below the block's first disk),
    /// but each disk's wall contacts are evaluated while its data is still in cache from the blocks
    /// just done: in large scenes, a separate pass over the disks at the walls (one in every dozen
    /// or so in a wide pile) would fetch each of them from memory again.
    #[allow(clippy::too_many_arguments)]
    pub fn contacts<L: ContactLaw<State = S>, const SAMPLE: bool>(
        &mut self,
        law: &L,
        kinds: [&ContactParameters; 2],
        (walls, neighbors): (&[Wall], &mut NeighborList<S>),
        s: &State<'_>,
        f: &mut Forces<'_>,
        totals: &mut ContactTotals,
    ) {
        let [disk_kind, wall_kind] = kinds;
        let travel = neighbors.travel();
        let (pairs, wall_candidates) = (&mut neighbors.pairs, &mut neighbors.walls);
        // Wall candidates `done..ready` have disks that no later block touches; they are evaluated
        // once there are `WALL_BATCH` of them (a short batch would cost more in loop overheads
        // than its vector loops save).
        let (mut done, mut ready) = (0, 0);
        let short = pairs.entries.len() <= PREDICTED_CANDIDATES;
        let block_count = pairs.entries.len().div_ceil(BLOCK);
        self.touching_before.resize(block_count, 0);
        self.calls += 1;
        if short && self.kept.len() < block_count {
            self.kept.resize_with(block_count, Box::default);
        }
        let build = pairs.build();
        let blocks = pairs.entries.chunks(BLOCK).zip(pairs.springs.chunks_mut(BLOCK));
        for (b, (block, springs)) in blocks.enumerate() {
            let states = states_of(&mut pairs.states, b * BLOCK..b * BLOCK + block.len());
            let below = block[0].i;
            ready += wall_candidates.entries[ready..].iter().take_while(|c| c.i < below).count();
            if ready - done >= WALL_BATCH {
                self.wall_contacts::<L, SAMPLE>(law, wall_kind, walls, wall_candidates, done..ready, s, f, totals);
                done = ready;
            }
            if short {
                std::mem::swap(&mut self.rows, &mut self.kept[b]);
            }
            // Sampled steps count every contact afresh (and are rare). Rows gathered unchanged
            // whose pairs no longer all touch go through the narrow phase after all.
            let unchanged = short
                && !SAMPLE
                && self.gather_unchanged(s, (build, travel), block, states)
                && self.compute_forces::<L, CHECKED>(law, disk_kind);
            if unchanged {
                #[cfg(test)]
                {
                    self.unchanged_blocks += 1;
                }
            } else {
                // The narrow phase reads the list's springs (the scatter marks the rows fresher).
                if self.rows.fresher {
                    self.rows.copy_springs(springs);
                }
                self.narrow_phase(b, (short, short), s, block, (springs, states));
                (self.rows.collected, self.rows.travel) = (self.calls, travel);
                self.compute_forces::<L, COMPUTED>(law, disk_kind);
            }
            if short {
                self.scatter::<L, SAMPLE, true, true>(law, disk_kind, (springs, states), f, totals);
                (self.rows.written, self.rows.build, self.rows.fresher) = (self.calls, build, true);
                self.fresher = true;
                std::mem::swap(&mut self.rows, &mut self.kept[b]);
            } else {
                self.scatter::<L, SAMPLE, true, false>(law, disk_kind, (springs, states), f, totals);
            }
        }
        let all = done..wall_candidates.entries.len();
        self.wall_contacts::<L, SAMPLE>(law, wall_kind, walls, wall_candidates, all, s, f, totals);
    }

    /// The two disks of row `c` (a disk-wall contact: the disk twice).
    #[inline(always)]
    pub(super) fn bodies(&self, c: usize) -> (usize, usize) {
        let [i, j] = self.rows.bodies[c];
        (i as usize, j as usize)
    }
}
