//! The rows a short list's blocks keep from step to step: which pairs touch, their disks, radii,
//! `R*`, `m*` and springs, and the pairs apart with the clearance that says when they must be tested
//! again (see `TouchingPairs::gather_unchanged`).

use crate::physics::contact_sums::BLOCK;
use crate::physics::neighbors::NeighborPair;
use crate::physics::walls::Sides;

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

/// The distance of `pair`'s disks (of positions and radii `(x, y, r)`, across `sides`) squared,
/// their radii's sum and the first disk's position.
#[inline(always)]
pub(super) fn apart_pair<X: Sides>(
    pair: &NeighborPair,
    (x, y, r): (&[f64], &[f64], &[f64]),
    sides: X,
) -> (f64, f64, (f64, f64)) {
    let (i, j) = (pair.i as usize, pair.j as usize);
    let (dx, dy) = (sides.dx(x[j] - x[i]), y[j] - y[i]);
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
