//! Stage 1, the narrow phase: which candidates of a block touch, their geometry, radii, motion and
//! histories copied into the table; in short lists with the rows kept from step to step
//! ([`super::kept_rows`]), so that a block whose pairs touch as before only gathers positions and
//! velocities.

use super::kept_rows::{CLEARANCE_CALLS, NEAR_GAP, Nearest, apart_pair};
use super::stages::touches;
use super::table::{Histories, TouchingPairs, stateful};
use crate::physics::contact_sums::BLOCK;
use crate::physics::neighbors::NeighborPair;
use crate::physics::particles::State;
use crate::physics::walls::Sides;

/// In longer lists, a block whose narrow phase found fewer touching pairs at the previous step
/// branches too: "not touching" is then the rule, which the branch predictor gets right (falling
/// disks in large scenes).
pub(super) const SPARSE_BLOCK: u8 = 16;

impl<S: Copy + Default + PartialEq> TouchingPairs<S> {
    /// Stage 1 for block `b` of the candidate list, `short` or not (see `collect`); `keep`: whether
    /// the rows are to be kept for the next step (a short list's, on one thread).
    pub(super) fn narrow_phase<X: Sides>(
        &mut self,
        b: usize,
        (short, keep): (bool, bool),
        (s, sides): (&State<'_>, X),
        block: &[NeighborPair],
        histories: Histories<'_, S>,
    ) {
        if keep {
            self.collect::<X, true, true>((s, sides), block, histories);
        } else if short || self.touching_before[b] < SPARSE_BLOCK {
            self.collect::<X, true, false>((s, sides), block, histories);
        } else {
            self.collect::<X, false, false>((s, sides), block, histories);
        }
        self.touching_before[b] = self.rows.len as u8; // at most BLOCK = 128
    }

    /// Stage 1 for a block whose touching pairs are those the narrow phase found at the previous
    /// step (the rows swapped in, of a list of `build`, the block's candidates `block` of them):
    /// their positions, velocities and histories gathered into the table. Returns false, having
    /// gathered some or none, when the rows are not the block's of the previous call, or a pair
    /// apart now touches (the narrow phase then takes the block). Whether the rows' pairs all
    /// still touch, stage 2 checks ([`CHECKED`]), in its vector loop; both with the same touching
    /// test as `collect`'s, so the same rows in the same order.
    pub(super) fn gather_unchanged<X: Sides>(
        &mut self,
        (s, sides): (&State<'_>, X),
        (build, travel): (u64, f64),
        block: &[NeighborPair],
        states: &[S],
    ) -> bool {
        let calls = self.calls;
        let rows = &mut *self.rows;
        let current = rows.written + 1 == calls && rows.len + rows.near + rows.far == block.len();
        if build == 0 || rows.build != build || !current {
            return false;
        }
        let n = s.x.len();
        // Slices of one known length: the asserts below cover all their bounds checks.
        let (x, y, r, vx, vy, omega) = (&s.x[..n], &s.y[..n], &s.r[..n], &s.vx[..n], &s.vy[..n], &s.omega[..n]);
        let apart = |k: u8| apart_pair(&block[usize::from(k)], (x, y, r), sides);
        for &k in &rows.apart[..rows.near] {
            let (d2, reach, _) = apart(k);
            if touches(d2, reach) {
                return false;
            }
        }
        // Two disks come closer by at most twice the longest move of a disk, which the list's
        // travel adds up (plus its rounding, 1e-8 of it): while that is below the far pairs'
        // clearance, none of them can touch, and their tests are skipped. Tested, they give it
        // afresh.
        let moved = travel - rows.travel;
        let clear = calls - rows.collected <= CLEARANCE_CALLS && 2.000_000_02 * moved < rows.clearance;
        #[cfg(test)]
        {
            self.apart_tests_skipped += usize::from(clear);
            self.far_tests += usize::from(!clear && rows.far > 0);
        }
        if !clear {
            let mut nearest = Nearest::NONE;
            for &k in &rows.apart[BLOCK - rows.far..] {
                let (d2, reach, first) = apart(k);
                if touches(d2, reach) {
                    return false;
                }
                nearest.add(d2, reach, first);
            }
            (rows.clearance, rows.collected, rows.travel) = (nearest.clearance(), calls, travel);
        }
        for c in 0..rows.len {
            let [i, j] = rows.bodies[c].map(|b| b as usize);
            assert!(i < n && j < n, "neighbour pair out of range");
            (self.dx[c], self.dy[c]) = (sides.dx(x[j] - x[i]), y[j] - y[i]);
            (self.dvx[c], self.dvy[c]) = (vx[i] - vx[j], vy[i] - vy[j]);
            (self.omega_i[c], self.omega_j[c]) = (omega[i], omega[j]);
            if stateful::<S>() {
                self.state[c] = states[rows.candidate[c]];
            }
        }
        true
    }

    /// Stage 1: appends the touching pairs of `block` to the table with what stage 2 needs; pairs
    /// out of contact lose their spring.
    ///
    /// Many candidates do not touch. With `PREDICTED`, the loop branches on it: in a short
    /// list whose contacts change slowly, the CPU's branch predictor learns the pattern from step
    /// to step and the branch costs nearly nothing. In a long list it cannot, and each mispredicted
    /// branch also waits for the loads of both disks' positions, from L3 or memory when the list is
    /// long; without `PREDICTED` there is no branch: every candidate is written to the next row of
    /// the table, which only a touching one keeps. With `KEEP` (and `PREDICTED`), also the pairs
    /// apart and their clearance, for [`TouchingPairs::gather_unchanged`]. The x separations are
    /// measured across `sides`.
    pub(super) fn collect<X: Sides, const PREDICTED: bool, const KEEP: bool>(
        &mut self,
        (s, sides): (&State<'_>, X),
        block: &[NeighborPair],
        histories: Histories<'_, S>,
    ) {
        let n = s.x.len();
        // Slices of one known length: the assert below covers all their bounds checks.
        let (x, y, r, vx, vy, omega) = (&s.x[..n], &s.y[..n], &s.r[..n], &s.vx[..n], &s.vy[..n], &s.omega[..n]);
        let (springs, states) = histories;
        let springs = &mut springs[..block.len()];
        let (mut len, mut near, mut far) = (0, 0, 0);
        let mut nearest = Nearest::NONE;
        for k in 0..block.len() {
            let (pair, spring) = (&block[k], &mut springs[k]);
            let (i, j) = (pair.i as usize, pair.j as usize);
            assert!(i < n && j < n, "neighbour pair out of range");
            let (dx, dy) = (sides.dx(x[j] - x[i]), y[j] - y[i]);
            let (ri, rj) = (r[i], r[j]);
            let reach = ri + rj;
            let d2 = dx * dx + dy * dy;
            let touching = touches(d2, reach);
            if PREDICTED && !touching {
                if KEEP {
                    // Without a branch (which side a pair falls is no pattern): written to the
                    // next slot of both ends (free: near + far < BLOCK), kept by one. The
                    // clearance's radii and coordinates are taken over all (a smaller clearance).
                    let gap = reach * (1.0 + NEAR_GAP);
                    let is_near = d2 < gap * gap;
                    (self.rows.apart[near], self.rows.apart[BLOCK - 1 - far]) = (k as u8, k as u8); // k < 128
                    (near, far) = (near + usize::from(is_near), far + usize::from(!is_near));
                    nearest.add(if is_near { f64::INFINITY } else { d2 }, reach, (x[i], y[i]));
                }
                // Written only when set, so pairs out of contact leave their cache line clean.
                if *spring != 0.0 {
                    *spring = 0.0;
                }
                if stateful::<S>() && states[k] != S::default() {
                    states[k] = S::default();
                }
                continue;
            }
            // Without the branch, every candidate is written to row `len`, which only a touching
            // one keeps.
            self.rows.candidate[len] = k;
            self.rows.bodies[len] = [pair.i, pair.j];
            self.dx[len] = dx;
            self.dy[len] = dy;
            self.rows.ri[len] = ri;
            self.rows.rj[len] = rj;
            self.rows.r_star[len] = pair.r_star;
            self.rows.m_star[len] = pair.m_star;
            self.dvx[len] = vx[i] - vx[j];
            self.dvy[len] = vy[i] - vy[j];
            self.omega_i[len] = omega[i];
            self.omega_j[len] = omega[j];
            self.rows.spring[len] = *spring;
            if stateful::<S>() {
                self.state[len] = states[k];
            }
            if !PREDICTED {
                // Cleared unconditionally (a conditional store would be a branch): pairs out of
                // contact lose their history, touching ones get their new one from the scatter.
                *spring = 0.0;
                if stateful::<S>() {
                    states[k] = S::default();
                }
            }
            len += usize::from(touching);
        }
        (self.rows.len, self.rows.near, self.rows.far) = (len, near, far);
        self.rows.clearance = if KEEP { nearest.clearance() } else { 0.0 };
    }
}
