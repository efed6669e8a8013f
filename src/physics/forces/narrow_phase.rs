//! Stage 1, the narrow phase: which candidates of a block touch, their geometry, radii, motion and
//! histories copied into the table; and the rows a short list keeps from step to step, so that a
//! block whose pairs touch as before only gathers positions and velocities.

use super::stages::touches;
use super::table::{Histories, TouchingPairs, stateful};
use crate::physics::contact_sums::BLOCK;
use crate::physics::neighbors::NeighborPair;
use crate::physics::particles::State;

/// In longer lists, a block whose narrow phase found fewer touching pairs at the previous step
/// branches too: "not touching" is then the rule, which the branch predictor gets right (falling
/// disks in large scenes).
pub(super) const SPARSE_BLOCK: u8 = 16;

/// The touching pairs of a block, what of them does not change between neighbour-list builds:
/// kept from step to step, so that a block whose touching pairs are those of the previous step
/// (nearly all blocks of a settling pile) only gathers their positions and velocities.
#[derive(Clone, Debug)]
pub(super) struct KeptRows {
    pub(super) len: usize,
    /// The call of [`TouchingPairs::contacts`] whose narrow phase wrote them, and the build of
    /// the candidate list they are from.
    pub(super) written: u64,
    pub(super) build: u64,
    /// Index of the pair in its block.
    pub(super) candidate: [usize; BLOCK],
    /// Its two disks (a disk-wall contact: the disk twice), as the candidate has them: one
    /// 8-byte copy per touching pair instead of two stores.
    pub(super) bodies: [[u32; 2]; BLOCK],
    pub(super) ri: [f64; BLOCK],
    pub(super) rj: [f64; BLOCK],
    pub(super) r_star: [f64; BLOCK],
    pub(super) m_star: [f64; BLOCK],
    /// Tangential spring, before and after the step. Kept too: the list's springs change only at
    /// a build (a new build number) and from here, so a block gathered unchanged finds its pairs'
    /// springs in place.
    pub(super) spring: [f64; BLOCK],
    /// Whether `spring` is newer than the list's springs of these pairs: the scatter leaves them
    /// here only (one store per contact and step less), and they are written back to the list
    /// before anything reads it (see [`TouchingPairs::write_back_springs`]).
    pub(super) fresher: bool,
    /// The block's candidates out of contact (indices in the block): `near` of them, nearer to
    /// touching than [`NEAR_GAP`] of their radii's sum, from the start, and `far` from the end.
    pub(super) apart: [u8; BLOCK],
    pub(super) near: usize,
    pub(super) far: usize,
    /// A distance (m) that the far pairs (at the call `collected`, when the neighbour list's
    /// travel was `travel`) were farther from touching: they cannot touch before the disks have
    /// moved half of it (see `TouchingPairs::gather_unchanged`).
    pub(super) clearance: f64,
    pub(super) collected: u64,
    pub(super) travel: f64,
}

/// Pairs apart whose gap is below this share of `r_i + r_j` are tested at every step that gathers
/// their block unchanged; those farther only once the disks may have closed their gap (see
/// [`TouchingPairs::gather_unchanged`]). In a pile most pairs apart sit well off, and a few nearly
/// touch: the few would otherwise have all of them tested at every step (results/bench/performance.md
/// has the shares tried).
pub(super) const NEAR_GAP: f64 = 1.0 / 256.0;

/// The distance of `pair`'s disks (of positions and radii `(x, y, r)`) squared, their radii's sum
/// and the first disk's position.
#[inline(always)]
pub(super) fn apart_pair(pair: &NeighborPair, (x, y, r): (&[f64], &[f64], &[f64])) -> (f64, f64, (f64, f64)) {
    let (i, j) = (pair.i as usize, pair.j as usize);
    let (dx, dy) = (x[j] - x[i], y[j] - y[i]);
    (dx * dx + dy * dy, r[i] + r[j], (x[i], y[i]))
}

/// The nearest of some pairs apart, for their clearance ([`Nearest::clearance`]).
#[derive(Clone, Copy)]
pub(super) struct Nearest {
    /// The least `d² − (r_i + r_j)²` (m²), the largest `r_i + r_j` (m), the largest `|x| + |y|`
    /// of a first disk (m).
    pub(super) nearest: f64,
    pub(super) widest: f64,
    pub(super) farthest: f64,
}

impl Nearest {
    pub(super) const NONE: Self = Self { nearest: f64::INFINITY, widest: 0.0, farthest: 0.0 };

    /// Adds a pair `d2` (m²) apart whose radii sum to `reach`, its first disk at `(x, y)`.
    #[inline(always)]
    pub(super) fn add(&mut self, d2: f64, reach: f64, (x, y): (f64, f64)) {
        // Neither is NaN here: comparisons, which are one instruction (`f64::min` and `max` take
        // more, for NaNs).
        let (q, far) = (d2 - reach * reach, x.abs() + y.abs());
        self.nearest = if q < self.nearest { q } else { self.nearest };
        self.widest = if reach > self.widest { reach } else { self.widest };
        self.farthest = if far > self.farthest { far } else { self.farthest };
    }

    /// A distance (m) that all pairs added are farther from touching (infinite for none):
    /// `√(R² + q) − R` falls as `R` grows and rises with `q`, less a margin for rounding.
    pub(super) fn clearance(&self) -> f64 {
        let (widest, nearest) = (self.widest, self.nearest);
        (widest * widest + nearest).sqrt() - widest - 1e-9 * (self.farthest + 4.0 * widest)
    }
}

/// Most calls after its narrow phase that a block's clearance is relied on: the rounding of the
/// positions' updates (`x + Δx` rounds by up to 1.1e-16 |x|) over these many steps stays below the
/// clearance's margin of 1e-9 of the disks' coordinates.
pub(super) const CLEARANCE_CALLS: u64 = 1_000_000;

impl KeptRows {
    /// Copies the springs to the candidates of their block (`springs`: the block's).
    pub(super) fn copy_springs(&self, springs: &mut [f64]) {
        for c in 0..self.len {
            springs[self.candidate[c]] = self.spring[c];
        }
    }
}

impl Default for KeptRows {
    fn default() -> Self {
        let column = [0.0; BLOCK];
        Self {
            len: 0,
            written: 0,
            build: 0,
            candidate: [0; BLOCK],
            bodies: [[0; 2]; BLOCK],
            ri: column,
            rj: column,
            r_star: column,
            m_star: column,
            spring: column,
            fresher: false,
            apart: [0; BLOCK],
            near: 0,
            far: 0,
            clearance: 0.0,
            collected: 0,
            travel: 0.0,
        }
    }
}

impl<S: Copy + Default + PartialEq> TouchingPairs<S> {
    /// Stage 1 for block `b` of the candidate list, `short` or not (see `collect`); `keep`: whether
    /// the rows are to be kept for the next step (a short list's, on one thread).
    pub(super) fn narrow_phase(
        &mut self,
        b: usize,
        (short, keep): (bool, bool),
        s: &State<'_>,
        block: &[NeighborPair],
        histories: Histories<'_, S>,
    ) {
        if keep {
            self.collect::<true, true>(s, block, histories);
        } else if short || self.touching_before[b] < SPARSE_BLOCK {
            self.collect::<true, false>(s, block, histories);
        } else {
            self.collect::<false, false>(s, block, histories);
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
    pub(super) fn gather_unchanged(
        &mut self,
        s: &State<'_>,
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
        let apart = |k: u8| apart_pair(&block[usize::from(k)], (x, y, r));
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
            (self.dx[c], self.dy[c]) = (x[j] - x[i], y[j] - y[i]);
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
    /// Some 30 % of candidates do not touch. With `PREDICTED`, the loop branches on it: in a short
    /// list whose contacts change slowly, the CPU's branch predictor learns the pattern from step
    /// to step and the branch costs nearly nothing. In a long list it cannot, and each mispredicted
    /// branch also waits for the loads of both disks' positions, from L3 or memory when the list is
    /// long; without `PREDICTED` there is no branch: every candidate is written to the next row of
    /// the table, which only a touching one keeps. With `KEEP` (and `PREDICTED`), also the pairs
    /// apart and their clearance, for [`TouchingPairs::gather_unchanged`].
    pub(super) fn collect<const PREDICTED: bool, const KEEP: bool>(
        &mut self,
        s: &State<'_>,
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
            let (dx, dy) = (x[j] - x[i], y[j] - y[i]);
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
