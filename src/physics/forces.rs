//! Contact forces of one step: disk pairs in blocks, with the disk-wall contacts in between.
//!
//! Disk pairs are taken in blocks of `BLOCK` (128) neighbour-list candidates, each in three stages:
//! 1. **narrow phase**: which candidates touch. Their geometry, radii and relative velocities are
//!    copied into a small table, one array per quantity (branching on contact in short lists only,
//!    see `TouchingPairs::collect`). In short lists each block keeps its touching pairs' rows (which
//!    pairs, their disks, radii, `R*` and `m*`) from step to step: a block whose pairs touch as at
//!    the previous step (some 98 % of the blocks of a settling pile) only gathers positions and
//!    velocities (`TouchingPairs::gather_unchanged`; the springs are kept with the rows). The
//!    same touching test decides: for its pairs in contact, in stage 2's geometry loop; for its
//!    pairs apart, in the gather: at every step for the few nearly touching, for the others only
//!    once the disks may have moved far enough for them to touch;
//! 2. **forces**: distance, unit normal, overlap, the law's stiffness and damping, the tangential
//!    spring with its Coulomb limit, and the resulting force and torques, for every touching pair of
//!    the block, in branch-free loops over the table that the compiler vectorises. Their three
//!    square roots and two divisions per contact were the most expensive operations of a step done
//!    one contact at a time: the divide/square-root unit does two (SSE2) or four (AVX2) of them for
//!    the price of one. They depend on one another within a contact (distance, then overlap, then
//!    stiffness, then damping), so the work is split into three loops (geometry, the law's
//!    coefficients, the resolved forces), each short enough that the CPU overlaps many contacts'
//!    chains: 13 % faster on a settled 300-disk pile than one loop. On x86-64 CPUs with AVX2 the
//!    loops run in copies compiled for AVX2; both copies do the same IEEE operations in the same
//!    order, so results are bit-identical;
//! 3. **scatter**: the forces and torques are added to both disks, pair after pair in list order, so
//!    that every sum is always added up in the same order (determinism).
//!
//! Disk-wall contacts go through the same table and stages (the narrow phase puts the wall's normal
//! and the overlap in place of the geometry loop's), each disk's between the blocks, once no later
//! block can touch the disk (see [`TouchingPairs::contacts`]).

use super::contact::{self, Coefficients, ContactForce, ContactLaw, ContactOptions, Kinematics, PairProperties};
use super::contact_sums::{ADDED, BLOCK, ContactSums, DiskIndex, DiskSums, RowsMut, SumOptions};
use super::diagnostics::ContactTotals;
use super::material::ContactMaterial;
use super::neighbors::{Candidates, NeighborList, NeighborPair, WallPair};
use super::parallel::{Split, Team, split_slice};
use super::particles::{Forces, State};
use super::vector::{self, Width};
use super::walls::Wall;
use std::borrow::Cow;
use std::ops::Range;
use std::sync::Mutex;

/// Whether a law's contact state takes memory (a law without state has `S = ()`: every use of it is
/// compiled out, bounds checks included).
#[inline(always)]
const fn stateful<S>() -> bool {
    std::mem::size_of::<S>() != 0
}

/// The law states `range` of `states`; none for a law without state (so that its loops carry no
/// slice at all).
#[inline(always)]
fn states_of<S>(states: &mut [S], range: Range<usize>) -> &mut [S] {
    if stateful::<S>() { &mut states[range] } else { &mut [] }
}

/// The tangential springs and law states of a run of candidates.
type Histories<'a, S> = (&'a mut [f64], &'a mut [S]);

/// Longest candidate list whose narrow phase always branches on contact (see
/// `TouchingPairs::collect`): measured on settled piles, the branch was as fast or faster at 300
/// and 3 000 disks (700 and 7 000 candidates), slower at 10 000 and 30 000 (24 000 and 72 000).
const PREDICTED_CANDIDATES: usize = 20_000;

/// In longer lists, a block whose narrow phase found fewer touching pairs at the previous step
/// branches too: "not touching" is then the rule, which the predictor gets right (falling disks:
/// 100 000 disks' first 0.03 s took 15 % less time than branch-free).
const SPARSE_BLOCK: u8 = 16;

/// Where stage 2's normals and overlaps come from: in the table already (walls: the narrow phase
/// put them there), computed from the centres (disk pairs), or computed and checked (rows gathered
/// unchanged: whether their pairs all still touch).
const GIVEN: u8 = 0;
const COMPUTED: u8 = 1;
const CHECKED: u8 = 2;

/// Fewest disk-wall candidates evaluated together (see `TouchingPairs::contacts`).
const WALL_BATCH: usize = 64;

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
    pub(super) fn pair_properties(&self, r_star: f64, m_star: f64) -> PairProperties {
        let m = &self.material;
        PairProperties { e_star: m.e_star, g_star: m.g_star, r_star, m_star, beta: m.beta }
    }

    /// The force of one contact of effective radius and mass `(R*, m*)` with `motion`, from its
    /// history (spring, law state) before the step, as the block stages compute it.
    pub(super) fn force_of<L: ContactLaw>(
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
    pub(super) fn resolve(&self, c: &Coefficients, k: &Kinematics, spring: &mut f64) -> ContactForce {
        contact::resolve(c, &self.options, k, spring, self.dt)
    }
}

/// Unit normal from centre i to centre j and overlap of two disks `(dx, dy) = x_j − x_i` apart
/// (coincident centres: any unit normal will do). Shared by the block loops and the one-contact
/// evaluation, so that both compute the same bits.
#[inline(always)]
pub(super) fn unit_normal_and_overlap(dx: f64, dy: f64, ri: f64, rj: f64) -> ([f64; 2], f64) {
    let d = (dx * dx + dy * dy).sqrt();
    let inv_d = 1.0 / d;
    let unit = if d > 0.0 { [dx * inv_d, dy * inv_d] } else { [1.0, 0.0] };
    (unit, (ri + rj) - d)
}

/// Whether two disks `d²` apart (squared distance, m²) with radii summing to `reach` touch: the
/// one test of the narrow phase, whether it takes a block afresh or gathers it unchanged (so both
/// find the same rows). NaN distances count as touching, so a diverging state reaches the forces.
/// (Written as a negated comparison, which says just that in one instruction; `< || is_nan`
/// takes two.)
#[inline(always)]
#[allow(clippy::neg_cmp_op_on_partial_ord)]
fn touches(d2: f64, reach: f64) -> bool {
    !(d2 >= reach * reach)
}

/// Relative motion of a contact with unit normal `n`, `v_i − v_j` = `dv` and spin terms
/// `ω_i r_i`, `ω_j r_j` (conventions of [`super::contact`]).
#[inline(always)]
pub(super) fn relative_motion(overlap: f64, n: [f64; 2], dv: [f64; 2], spin: [f64; 2]) -> Kinematics {
    let ([nx, ny], [dvx, dvy]) = (n, dv);
    Kinematics {
        overlap,
        approach_speed: dvx * nx + dvy * ny,
        tangential_speed: -dvx * ny + dvy * nx + spin[0] + spin[1],
    }
}

/// The touching pairs of one block, one array per quantity. Fixed-size arrays: indexing them all
/// with one row number costs one bounds check.
#[derive(Clone, Debug)]
pub struct TouchingPairs<S> {
    /// The rows' pairs and what of them stays from step to step (swapped for a block's own, see
    /// [`KeptRows`]).
    rows: Box<KeptRows>,
    /// Each block's rows as the narrow phase left them at a previous step (short lists).
    kept: Vec<Box<KeptRows>>,
    /// Calls of [`TouchingPairs::contacts`] so far (which call each block's rows are from).
    calls: u64,
    /// Whether some kept rows are [`KeptRows::fresher`] than the list.
    fresher: bool,
    /// Blocks whose touching pairs were gathered unchanged; gathers whose far pairs apart were
    /// not tested, and those whose far pairs were (the tests' view of those paths).
    #[cfg(test)]
    unchanged_blocks: usize,
    #[cfg(test)]
    apart_tests_skipped: usize,
    #[cfg(test)]
    far_tests: usize,
    /// Touching pairs of each block at the previous step (a hint for the narrow phase).
    touching_before: Vec<u8>,
    // Gathered by the narrow phase.
    dx: [f64; BLOCK],
    dy: [f64; BLOCK],
    /// `v_i − v_j`.
    dvx: [f64; BLOCK],
    dvy: [f64; BLOCK],
    /// `ω_i` and `ω_j` (a wall: 0); stage 2 takes `ω_i r_i` and `ω_j r_j` four at a time.
    omega_i: [f64; BLOCK],
    omega_j: [f64; BLOCK],
    /// The law's contact state, before and after the step.
    state: [S; BLOCK],
    // Computed by the vector stage.
    /// Unit normal from disk i to disk j.
    unit_x: [f64; BLOCK],
    unit_y: [f64; BLOCK],
    /// The law's coefficients: elastic normal force, normal damping, tangential damping (the
    /// tangential stiffness has its own column below).
    elastic: [f64; BLOCK],
    normal_damping: [f64; BLOCK],
    tangential_damping: [f64; BLOCK],
    /// Contact force on disk i (on j: the opposite).
    force_x: [f64; BLOCK],
    force_y: [f64; BLOCK],
    /// Torques on disks i and j.
    torque_i: [f64; BLOCK],
    torque_j: [f64; BLOCK],
    overlap: [f64; BLOCK],
    normal: [f64; BLOCK],
    tangential: [f64; BLOCK],
    tangential_stiffness: [f64; BLOCK],
}

/// The touching pairs of a block, what of them does not change between neighbour-list builds:
/// kept from step to step, so that a block whose touching pairs are those of the previous step
/// (nearly all blocks of a settling pile) only gathers their positions and velocities.
#[derive(Clone, Debug)]
struct KeptRows {
    len: usize,
    /// The call of [`TouchingPairs::contacts`] whose narrow phase wrote them, and the build of
    /// the candidate list they are from.
    written: u64,
    build: u64,
    /// Index of the pair in its block.
    candidate: [usize; BLOCK],
    /// Its two disks (a disk-wall contact: the disk twice), as the candidate has them: one
    /// 8-byte copy per touching pair instead of two stores.
    bodies: [[u32; 2]; BLOCK],
    ri: [f64; BLOCK],
    rj: [f64; BLOCK],
    r_star: [f64; BLOCK],
    m_star: [f64; BLOCK],
    /// Tangential spring, before and after the step. Kept too: the list's springs change only at
    /// a build (a new build number) and from here, so a block gathered unchanged finds its pairs'
    /// springs in place.
    spring: [f64; BLOCK],
    /// Whether `spring` is newer than the list's springs of these pairs: the scatter leaves them
    /// here only (one store per contact and step less), and they are written back to the list
    /// before anything reads it (see [`TouchingPairs::write_back_springs`]).
    fresher: bool,
    /// The block's candidates out of contact (indices in the block): `near` of them, nearer to
    /// touching than [`NEAR_GAP`] of their radii's sum, from the start, and `far` from the end.
    apart: [u8; BLOCK],
    near: usize,
    far: usize,
    /// A distance (m) that the far pairs (at the call `collected`, when the neighbour list's
    /// travel was `travel`) were farther from touching: they cannot touch before the disks have
    /// moved half of it (see `TouchingPairs::gather_unchanged`).
    clearance: f64,
    collected: u64,
    travel: f64,
}

/// Pairs apart whose gap is below this share of `r_i + r_j` are tested at every step that gathers
/// their block unchanged; those farther only once the disks may have closed their gap (see
/// [`TouchingPairs::gather_unchanged`]). In a pile most pairs apart sit well off, and a few nearly
/// touch: the few would otherwise have all of them tested at every step. (1/32, 1/64, 1/128, 1/256
/// and 1/1024 measured on a 300-disk pile: the smaller the faster down to 1/256, 3 % in all.)
const NEAR_GAP: f64 = 1.0 / 256.0;

/// The distance of `pair`'s disks (of positions and radii `(x, y, r)`) squared, their radii's sum
/// and the first disk's position.
#[inline(always)]
fn apart_pair(pair: &NeighborPair, (x, y, r): (&[f64], &[f64], &[f64])) -> (f64, f64, (f64, f64)) {
    let (i, j) = (pair.i as usize, pair.j as usize);
    let (dx, dy) = (x[j] - x[i], y[j] - y[i]);
    (dx * dx + dy * dy, r[i] + r[j], (x[i], y[i]))
}

/// The nearest of some pairs apart, for their clearance ([`Nearest::clearance`]).
#[derive(Clone, Copy)]
struct Nearest {
    /// The least `d² − (r_i + r_j)²` (m²), the largest `r_i + r_j` (m), the largest `|x| + |y|`
    /// of a first disk (m).
    nearest: f64,
    widest: f64,
    farthest: f64,
}

impl Nearest {
    const NONE: Self = Self { nearest: f64::INFINITY, widest: 0.0, farthest: 0.0 };

    /// Adds a pair `d2` (m²) apart whose radii sum to `reach`, its first disk at `(x, y)`.
    #[inline(always)]
    fn add(&mut self, d2: f64, reach: f64, (x, y): (f64, f64)) {
        // Neither is NaN here: comparisons, which are one instruction (`f64::min` and `max` take
        // more, for NaNs).
        let (q, far) = (d2 - reach * reach, x.abs() + y.abs());
        self.nearest = if q < self.nearest { q } else { self.nearest };
        self.widest = if reach > self.widest { reach } else { self.widest };
        self.farthest = if far > self.farthest { far } else { self.farthest };
    }

    /// A distance (m) that all pairs added are farther from touching (infinite for none):
    /// `√(R² + q) − R` falls as `R` grows and rises with `q`, less a margin for rounding.
    fn clearance(&self) -> f64 {
        let (widest, nearest) = (self.widest, self.nearest);
        (widest * widest + nearest).sqrt() - widest - 1e-9 * (self.farthest + 4.0 * widest)
    }
}

/// Most calls after its narrow phase that a block's clearance is relied on: the rounding of the
/// positions' updates (`x + Δx` rounds by up to 1.1e-16 |x|) over these many steps stays below the
/// clearance's margin of 1e-9 of the disks' coordinates.
const CLEARANCE_CALLS: u64 = 1_000_000;

impl KeptRows {
    /// Copies the springs to the candidates of their block (`springs`: the block's).
    fn copy_springs(&self, springs: &mut [f64]) {
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

/// A run of whole blocks of candidates (the first is block `first_block` of its list) with their
/// histories and force rows: a part of the parallel path's work.
struct CandidateBlocks<'a, T, S> {
    first_block: usize,
    entries: &'a [T],
    springs: &'a mut [f64],
    states: &'a mut [S],
    rows: RowsMut<'a>,
}

impl<'a, T, S> CandidateBlocks<'a, T, S> {
    fn new(entries: &'a [T], springs: &'a mut [f64], states: &'a mut [S], rows: RowsMut<'a>) -> Self {
        Self { first_block: 0, entries, springs, states, rows }
    }

    /// The first `at` blocks and the rest.
    fn cut(self, at: usize) -> (Self, Self) {
        let mid = (at * BLOCK).min(self.entries.len());
        let (e0, e1) = self.entries.split_at(mid);
        let (s0, s1) = self.springs.split_at_mut(mid);
        let (st0, st1) = split_slice(self.states, mid, 1);
        let (r0, r1) = self.rows.split_blocks(at);
        let first = CandidateBlocks { first_block: self.first_block, entries: e0, springs: s0, states: st0, rows: r0 };
        let rest =
            CandidateBlocks { first_block: self.first_block + at, entries: e1, springs: s1, states: st1, rows: r1 };
        (first, rest)
    }
}

impl<T: Sync, S: Send> Split for CandidateBlocks<'_, T, S> {
    fn units(&self) -> usize {
        self.entries.len().div_ceil(BLOCK)
    }

    fn split_at(self, at: usize) -> (Self, Self) {
        self.cut(at)
    }
}

/// The disk-pair blocks of a part, the wall blocks of about the same disks (so that the disks at
/// the walls are still in the thread's cache from its pairs) and the accumulators of those disks.
struct Blocks<'a, S> {
    pairs: CandidateBlocks<'a, NeighborPair, S>,
    walls: CandidateBlocks<'a, WallPair, S>,
    sums: DiskSums<'a>,
    index: DiskIndex<'a>,
}

impl<S: Send> Split for Blocks<'_, S> {
    fn units(&self) -> usize {
        self.pairs.units()
    }

    fn split_at(self, at: usize) -> (Self, Self) {
        // The disks before the first disk of pair block `at`, and their wall blocks, go with the
        // first part.
        let disk = self.pairs.entries.get(at * BLOCK).map_or(usize::MAX, |p| p.i as usize);
        let wall_block = if disk == usize::MAX { usize::MAX } else { self.index.wall_block(disk) };
        let wall_at = wall_block.saturating_sub(self.walls.first_block).min(self.walls.units());
        let (p0, p1) = self.pairs.cut(at);
        let (w0, w1) = self.walls.cut(wall_at);
        let (s0, s1) = self.sums.split_disks(disk);
        let index = self.index;
        (Blocks { pairs: p0, walls: w0, sums: s0, index }, Blocks { pairs: p1, walls: w1, sums: s1, index })
    }
}

/// The parallel path of a step's contact forces (not sampled: no contact sums): the blocks of
/// disk pairs and of disk-wall candidates shared out in the `team`'s parts between its threads, each
/// piece through one of `tables`, the forces stored per candidate in `sums`; then each disk's sum,
/// disks shared out likewise (see [`super::contact_sums`]). The same bits as
/// [`TouchingPairs::contacts`].
#[allow(clippy::too_many_arguments)]
pub fn contacts_in_parts<L: ContactLaw>(
    tables: &mut Vec<Mutex<TouchingPairs<L::State>>>,
    law: &L,
    kinds: [&ContactParameters; 2],
    pairs: &mut Candidates<NeighborPair, L::State>,
    walls: (&[Wall], &mut Candidates<WallPair, L::State>),
    s: &State<'_>,
    f: &mut Forces<'_>,
    sums: &mut ContactSums,
    team: &Team,
) {
    let [disk_kind, wall_kind] = kinds;
    let (walls, wall_candidates) = walls;
    while tables.len() < team.parts() {
        tables.push(Mutex::new(TouchingPairs::default()));
    }
    let tables = &tables[..];
    sums.prepare(&pairs.entries, &wall_candidates.entries, s.x.len());
    let short = pairs.entries.len() <= PREDICTED_CANDIDATES;
    let blocks = pairs.entries.len().div_ceil(BLOCK);
    let c = wall_candidates;
    let (pair_rows, wall_rows, index) = sums.rows();
    let part = Blocks {
        pairs: CandidateBlocks::new(&pairs.entries, &mut pairs.springs, &mut pairs.states, pair_rows),
        walls: CandidateBlocks::new(&c.entries, &mut c.springs, &mut c.states, wall_rows),
        sums: DiskSums::new(f.fx, f.fy, f.torque, f.rolling),
        index,
    };
    team.for_each_part(part, &|mut part, number| {
        let mut table = tables[number].lock().expect("a table per part");
        table.touching_before.resize(blocks, 0);
        let start = part.pairs.first_block * BLOCK;
        let own = index.own_disks(start..start + part.pairs.entries.len());
        let own = own.start.max(part.sums.first)..own.end.min(part.sums.first + part.sums.fx.len());
        let reaching = index.first_pair_reaching(own.end);
        table.pair_forces(law, disk_kind, part.pairs, s, short, (&mut part.sums, own.clone(), reaching));
        table.wall_forces(law, wall_kind, walls, part.walls, s, (&mut part.sums, &own));
    });
    let options = SumOptions {
        rotation: disk_kind.rotation,
        rolling_friction: [disk_kind.material.rolling_friction, wall_kind.material.rolling_friction],
    };
    let accumulators = DiskSums::new(f.fx, f.fy, f.torque, f.rolling);
    sums.add_up(accumulators, s.r, options, team);
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

    /// The stages for the disk-pair blocks of `part`: the forces added to the disks `own` of
    /// `sums` (all of whose pairs are in `part`), and stored in the part's rows for the others;
    /// `short`: whether the whole list is short (see `collect`); `reaching`: the first candidate
    /// whose second disk is `own.end` or above.
    fn pair_forces<L: ContactLaw<State = S>>(
        &mut self,
        law: &L,
        kind: &ContactParameters,
        part: CandidateBlocks<'_, NeighborPair, S>,
        s: &State<'_>,
        short: bool,
        (sums, own, reaching): (&mut DiskSums<'_>, Range<usize>, usize),
    ) {
        let mut rest = part;
        while !rest.entries.is_empty() {
            let (block, after) = rest.cut(1);
            let b = block.first_block;
            self.narrow_phase(b, (short, false), s, block.entries, (block.springs, block.states));
            self.compute_forces::<L, COMPUTED>(law, kind);
            // Candidates are sorted by first disk, the second the larger: a block whose first
            // disk is the part's own and that ends before `reaching` has only the part's own disks.
            let end = b * BLOCK + block.entries.len();
            let all_own = block.entries[0].i as usize >= own.start && end <= reaching;
            self.add_or_store(kind, block.rows, (block.springs, block.states), sums, (own.clone(), all_own));
            rest = after;
        }
    }

    /// The stages for the disk-wall blocks of `part`: each force added to its disk if that is in
    /// `own` of `sums` (whose pairs this part has added: its walls come after them, as in the
    /// one-thread order), else stored in the part's rows.
    fn wall_forces<L: ContactLaw<State = S>>(
        &mut self,
        law: &L,
        kind: &ContactParameters,
        walls: &[Wall],
        part: CandidateBlocks<'_, WallPair, S>,
        s: &State<'_>,
        (sums, own): (&mut DiskSums<'_>, &Range<usize>),
    ) {
        let mut rest = part;
        while !rest.entries.is_empty() {
            let (block, after) = rest.cut(1);
            self.collect_walls(s, walls, block.entries, (block.springs, block.states));
            self.compute_forces::<L, GIVEN>(law, kind);
            self.keep_histories((block.springs, block.states));
            let mut rows = block.rows;
            let mut stored = 0;
            for c in 0..self.rows.len {
                let (i, _) = self.bodies(c);
                if own.contains(&i) {
                    self.add_one::<true>(kind, c, i - sums.first, sums);
                    continue;
                }
                self.store_row(&mut rows, stored, c, [i as u32, ADDED]);
                stored += 1;
            }
            rows.touching[0] = stored as u8; // at most BLOCK = 128
            rest = after;
        }
    }

    /// Stores contact `c` in row `at` of `rows`, with `disks` in place of its bodies' indices
    /// ([`ADDED`] for a body whose force is already added, or a wall's).
    #[inline(always)]
    fn store_row(&self, rows: &mut RowsMut<'_>, at: usize, c: usize, [disk_i, disk_j]: [u32; 2]) {
        (rows.disk_i[at], rows.disk_j[at]) = (disk_i, disk_j);
        (rows.fx[at], rows.fy[at]) = (self.force_x[c], self.force_y[c]);
        (rows.torque_i[at], rows.torque_j[at]) = (self.torque_i[c], self.torque_j[c]);
        rows.normal[at] = self.normal[c];
    }

    /// Adds contact `c`'s force, torque and rolling resistance to disk `k` of `sums`, its first
    /// body (`FIRST`) or its second (the force subtracted), as the one-thread scatter does.
    #[inline(always)]
    fn add_one<const FIRST: bool>(&self, kind: &ContactParameters, c: usize, k: usize, sums: &mut DiskSums<'_>) {
        let (force_x, force_y) = (self.force_x[c], self.force_y[c]);
        if FIRST {
            sums.fx[k] += force_x;
            sums.fy[k] += force_y;
        } else {
            sums.fx[k] -= force_x;
            sums.fy[k] -= force_y;
        }
        if kind.rotation {
            sums.torque[k] += if FIRST { self.torque_i[c] } else { self.torque_j[c] };
        }
        let rolling_friction = kind.material.rolling_friction;
        if rolling_friction > 0.0 {
            let resistance = rolling_friction * self.normal[c].max(0.0);
            sums.rolling[k] += resistance * if FIRST { self.rows.ri[c] } else { self.rows.rj[c] };
        }
    }

    /// The parallel path's stage 3 for disk pairs: each contact's force added to those of its disks
    /// that are in `own` (as the scatter does), and stored in the block's rows for the others; the
    /// springs and states kept. A block `all_own` (most blocks) is added as the scatter adds it.
    fn add_or_store(
        &self,
        kind: &ContactParameters,
        mut rows: RowsMut<'_>,
        histories: Histories<'_, S>,
        sums: &mut DiskSums<'_>,
        (own, all_own): (Range<usize>, bool),
    ) {
        if all_own {
            rows.touching[0] = 0;
            return self.add_to::<true, false>(kind, sums, histories);
        }
        self.keep_histories(histories);
        let mut stored = 0;
        for c in 0..self.rows.len {
            let (i, j) = self.bodies(c);
            let (i_own, j_own) = (own.contains(&i), own.contains(&j));
            if i_own {
                self.add_one::<true>(kind, c, i - sums.first, sums);
            }
            if j_own {
                self.add_one::<false>(kind, c, j - sums.first, sums);
            }
            if !(i_own && j_own) {
                let disks = [if i_own { ADDED } else { i as u32 }, if j_own { ADDED } else { j as u32 }];
                self.store_row(&mut rows, stored, c, disks);
                stored += 1;
            }
        }
        rows.touching[0] = stored as u8; // at most BLOCK = 128
    }

    /// Writes the touching contacts' springs and states back to their candidates.
    fn keep_histories(&self, (springs, states): Histories<'_, S>) {
        for c in 0..self.rows.len {
            let k = self.rows.candidate[c];
            springs[k] = self.rows.spring[c];
            if stateful::<S>() {
                states[k] = self.state[c];
            }
        }
    }

    /// Adds the disk-wall contacts of the candidates in `range` (and with `SAMPLE`, their contact
    /// sums to `totals`), through the same table and vector loops as the disk pairs, `BLOCK` at a time.
    #[allow(clippy::too_many_arguments)]
    fn wall_contacts<L: ContactLaw<State = S>, const SAMPLE: bool>(
        &mut self,
        law: &L,
        kind: &ContactParameters,
        walls: &[Wall],
        candidates: &mut Candidates<WallPair, S>,
        range: Range<usize>,
        s: &State<'_>,
        f: &mut Forces<'_>,
        totals: &mut ContactTotals,
    ) {
        let (entries, springs) = (&candidates.entries[range.clone()], &mut candidates.springs[range.clone()]);
        for (k, (chunk, springs)) in entries.chunks(BLOCK).zip(springs.chunks_mut(BLOCK)).enumerate() {
            let first = range.start + k * BLOCK;
            let states = states_of(&mut candidates.states, first..first + chunk.len());
            self.collect_walls(s, walls, chunk, (springs, states));
            self.compute_forces::<L, GIVEN>(law, kind);
            self.scatter::<L, SAMPLE, false, false>(law, kind, (springs, states), f, totals);
        }
    }

    /// The two disks of row `c` (a disk-wall contact: the disk twice).
    #[inline(always)]
    fn bodies(&self, c: usize) -> (usize, usize) {
        let [i, j] = self.rows.bodies[c];
        (i as usize, j as usize)
    }

    /// Stage 1 for block `b` of the candidate list, `short` or not (see `collect`); `keep`: whether
    /// the rows are to be kept for the next step (a short list's, on one thread).
    fn narrow_phase(
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
    fn gather_unchanged(
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

    /// Stage 1 for disk-wall candidates: the table rows of those touching, with the wall's normal
    /// and the overlap already in place (a wall has no centre to measure a distance from); the
    /// wall is the second body, at rest, of infinite radius and mass (`R* = r`, `m* = m`).
    fn collect_walls(&mut self, s: &State<'_>, walls: &[Wall], candidates: &[WallPair], histories: Histories<'_, S>) {
        let n = s.x.len();
        let mut len = 0;
        let (springs, states) = histories;
        for (k, (candidate, spring)) in candidates.iter().zip(springs.iter_mut()).enumerate() {
            let (i, wall) = (candidate.i as usize, &walls[candidate.wall as usize]);
            assert!(i < n, "wall candidate out of range");
            let r = s.r[i];
            let overlap = wall.overlap(s.x[i], s.y[i], r);
            if overlap <= 0.0 {
                *spring = 0.0;
                if stateful::<S>() {
                    states[k] = S::default();
                }
                continue;
            }
            self.rows.candidate[len] = k;
            self.rows.bodies[len] = [candidate.i; 2];
            [self.unit_x[len], self.unit_y[len]] = wall.normal;
            self.overlap[len] = overlap;
            // The disk's radius twice: `ω_j r_j` is 0, the smaller radius the disk's.
            (self.rows.ri[len], self.rows.rj[len]) = (r, r);
            (self.rows.r_star[len], self.rows.m_star[len]) = (r, candidate.m_star);
            (self.dvx[len], self.dvy[len]) = (s.vx[i], s.vy[i]);
            (self.omega_i[len], self.omega_j[len]) = (s.omega[i], 0.0);
            self.rows.spring[len] = *spring;
            if stateful::<S>() {
                self.state[len] = states[k];
            }
            len += 1;
        }
        self.rows.len = len;
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
    fn collect<const PREDICTED: bool, const KEEP: bool>(
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

    /// Stage 2: normals, overlaps, coefficients and forces of all touching pairs, in the widest
    /// vector instructions the CPU runs well ([`vector::width`]). (Dispatched here rather than
    /// through [`vector::widest`]: behind its closure these loops no longer vectorise.)
    /// `GEOMETRY`: where normals and overlaps come from ([`GIVEN`], [`COMPUTED`], [`CHECKED`]).
    /// Returns whether the rows' pairs all touch (always, unless `CHECKED`; if not, the forces are
    /// not computed).
    fn compute_forces<L: ContactLaw<State = S>, const GEOMETRY: u8>(
        &mut self,
        law: &L,
        kind: &ContactParameters,
    ) -> bool {
        #[cfg(target_arch = "x86_64")]
        #[allow(unsafe_code)]
        match vector::width() {
            // SAFETY: `vector::width` names only widths the CPU supports.
            Width::Avx512 => return unsafe { self.forces_avx512::<L, GEOMETRY>(law, kind) },
            // SAFETY: as above.
            Width::Avx2 => return unsafe { self.forces_avx2::<L, GEOMETRY>(law, kind) },
            Width::Baseline => {}
        }
        self.forces_portable::<L, GEOMETRY>(law, kind)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512vl,avx512dq")]
    fn forces_avx512<L: ContactLaw<State = S>, const GEOMETRY: u8>(
        &mut self,
        law: &L,
        kind: &ContactParameters,
    ) -> bool {
        self.forces_portable::<L, GEOMETRY>(law, kind)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn forces_avx2<L: ContactLaw<State = S>, const GEOMETRY: u8>(&mut self, law: &L, kind: &ContactParameters) -> bool {
        self.forces_portable::<L, GEOMETRY>(law, kind)
    }

    #[inline(always)]
    fn forces_portable<L: ContactLaw<State = S>, const GEOMETRY: u8>(
        &mut self,
        law: &L,
        kind: &ContactParameters,
    ) -> bool {
        let all_touch = match GEOMETRY {
            CHECKED => self.geometry::<true>(),
            COMPUTED => self.geometry::<false>(),
            _ => true,
        };
        if !all_touch {
            return false;
        }
        self.coefficients(law, kind);
        self.resolve_all(kind);
        true
    }

    /// Distances, unit normals and overlaps: a loop of its own, short enough that the CPU overlaps
    /// many contacts' square root and division, which follow one another within a contact. With
    /// `CHECK`, returns whether all rows' pairs touch (else true).
    #[inline(always)]
    fn geometry<const CHECK: bool>(&mut self) -> bool {
        let n = self.rows.len;
        // Equal-length slices: no bounds checks, so the loop vectorises.
        let (dx, dy, ri, rj) = (&self.dx[..n], &self.dy[..n], &self.rows.ri[..n], &self.rows.rj[..n]);
        let (unit_x, unit_y, overlap) = (&mut self.unit_x[..n], &mut self.unit_y[..n], &mut self.overlap[..n]);
        let mut all_touch = true;
        for c in 0..n {
            let ([ux, uy], o) = unit_normal_and_overlap(dx[c], dy[c], ri[c], rj[c]);
            (unit_x[c], unit_y[c], overlap[c]) = (ux, uy, o);
            if CHECK {
                all_touch &= touches(dx[c] * dx[c] + dy[c] * dy[c], ri[c] + rj[c]);
            }
        }
        all_touch
    }

    /// The law's stiffness and damping at each overlap: a loop of its own, for the same reason.
    #[inline(always)]
    fn coefficients<L: ContactLaw<State = S>>(&mut self, law: &L, kind: &ContactParameters) {
        let n = self.rows.len;
        let (overlap, r_star, m_star) = (&self.overlap[..n], &self.rows.r_star[..n], &self.rows.m_star[..n]);
        let state = &mut self.state[..n];
        let (elastic, normal_damping) = (&mut self.elastic[..n], &mut self.normal_damping[..n]);
        let (stiffness, tangential_damping) = (&mut self.tangential_stiffness[..n], &mut self.tangential_damping[..n]);
        for c in 0..n {
            let k = law.coefficients(&kind.pair_properties(r_star[c], m_star[c]), overlap[c], &mut state[c]);
            (elastic[c], normal_damping[c], stiffness[c], tangential_damping[c]) =
                (k.normal_force, k.normal_damping, k.tangential_stiffness, k.tangential_damping);
        }
    }

    /// The resolved forces and torques, from the geometry and coefficients.
    #[inline(always)]
    fn resolve_all(&mut self, kind: &ContactParameters) {
        let n = self.rows.len;
        // Equal-length slices: no bounds checks, so the loop vectorises.
        let (nx, ny, overlap) = (&self.unit_x[..n], &self.unit_y[..n], &self.overlap[..n]);
        let (elastic, normal_damping) = (&self.elastic[..n], &self.normal_damping[..n]);
        let (stiffness, tangential_damping) = (&self.tangential_stiffness[..n], &self.tangential_damping[..n]);
        let (ri, rj) = (&self.rows.ri[..n], &self.rows.rj[..n]);
        let (dvx, dvy, omega_i, omega_j) = (&self.dvx[..n], &self.dvy[..n], &self.omega_i[..n], &self.omega_j[..n]);
        let (force_x, force_y) = (&mut self.force_x[..n], &mut self.force_y[..n]);
        let (torque_i, torque_j) = (&mut self.torque_i[..n], &mut self.torque_j[..n]);
        let (normal, tangential, spring) =
            (&mut self.normal[..n], &mut self.tangential[..n], &mut self.rows.spring[..n]);
        for c in 0..n {
            let coefficients = Coefficients {
                normal_force: elastic[c],
                normal_damping: normal_damping[c],
                tangential_stiffness: stiffness[c],
                tangential_damping: tangential_damping[c],
            };
            let spin = [omega_i[c] * ri[c], omega_j[c] * rj[c]];
            let motion = relative_motion(overlap[c], [nx[c], ny[c]], [dvx[c], dvy[c]], spin);
            let force = kind.resolve(&coefficients, &motion, &mut spring[c]);
            // Torque `F_t r` on both disks.
            [force_x[c], force_y[c]] = force.on_first_body(nx[c], ny[c]);
            torque_i[c] = force.tangential * ri[c];
            torque_j[c] = force.tangential * rj[c];
            (normal[c], tangential[c]) = (force.normal, force.tangential);
        }
    }

    /// Stage 3: adds the forces of the touching pairs to both disks (`PAIRS`; walls: to the disk),
    /// in list order, and stores the histories; with `SAMPLE`, adds the contact sums to `totals`;
    /// `KEPT`: see [`TouchingPairs::add_to`].
    fn scatter<L: ContactLaw<State = S>, const SAMPLE: bool, const PAIRS: bool, const KEPT: bool>(
        &self,
        law: &L,
        kind: &ContactParameters,
        histories: Histories<'_, S>,
        f: &mut Forces<'_>,
        totals: &mut ContactTotals,
    ) {
        self.add_to::<PAIRS, KEPT>(kind, &mut DiskSums::new(f.fx, f.fy, f.torque, f.rolling), histories);
        if SAMPLE {
            self.sample::<L, PAIRS>(law, kind, f.contact_force, totals);
        }
    }

    /// Adds the table's forces, torques and rolling resistances to the disks of `sums`, which
    /// holds all of them, row after row: to both disks (`PAIRS`; the second gets the opposite
    /// force), or to the disk (walls); writes the states back to their candidates, and the
    /// springs unless the rows are `KEPT` (in the same loop: one pass over the table).
    ///
    /// The rows come in runs of one first disk (the list is sorted by it). With `KEPT` (a short
    /// list's rows, the same from step to step), its sums are held in registers over the run:
    /// added to in memory, each row would wait for the previous row's store to reach the next
    /// load. The same additions in the same order (a pair's second disk is never its first), so
    /// the same bits. Without, each row is a run of its own: the test of a new run is a branch,
    /// which the predictor learns in a short list (its blocks' rows are the same from step to
    /// step), not in a long one.
    ///
    /// Torques and rolling resistances are added by a copy of the loop that has them, so that
    /// rows without them test nothing.
    #[inline(always)]
    fn add_to<const PAIRS: bool, const KEPT: bool>(
        &self,
        kind: &ContactParameters,
        sums: &mut DiskSums<'_>,
        histories: Histories<'_, S>,
    ) {
        let rolling_friction = kind.material.rolling_friction;
        match (kind.rotation, rolling_friction > 0.0) {
            (false, false) => self.add_rows::<PAIRS, KEPT, false, false>(rolling_friction, sums, histories),
            (true, false) => self.add_rows::<PAIRS, KEPT, true, false>(rolling_friction, sums, histories),
            (false, true) => self.add_rows::<PAIRS, KEPT, false, true>(rolling_friction, sums, histories),
            (true, true) => self.add_rows::<PAIRS, KEPT, true, true>(rolling_friction, sums, histories),
        }
    }

    /// [`TouchingPairs::add_to`]'s loop, with torques (`ROTATION`) and rolling resistances
    /// (`ROLLING`, of `rolling_friction`) or without.
    #[inline(always)]
    fn add_rows<const PAIRS: bool, const KEPT: bool, const ROTATION: bool, const ROLLING: bool>(
        &self,
        rolling_friction: f64,
        sums: &mut DiskSums<'_>,
        histories: Histories<'_, S>,
    ) {
        let (first, n) = (sums.first, sums.fx.len());
        // Slices of one known length: the assert below covers all their bounds checks.
        let (fx, fy) = (&mut sums.fx[..n], &mut sums.fy[..n]);
        let (torque, rolling) = (&mut sums.torque[..n], &mut sums.rolling[..n]);
        let (springs, states) = histories;
        let (mut held, mut sum) = (usize::MAX, [0.0; 4]);
        for c in 0..self.rows.len {
            let (i, j) = self.bodies(c);
            let (i, j) = (i.wrapping_sub(first), j.wrapping_sub(first));
            assert!(i < n && j < n, "contact out of range");
            if !KEPT || i != held {
                if held < n {
                    [fx[held], fy[held], torque[held], rolling[held]] = sum;
                }
                (held, sum) = (i, [fx[i], fy[i], torque[i], rolling[i]]);
            }
            let (force_x, force_y) = (self.force_x[c], self.force_y[c]);
            sum[0] += force_x;
            sum[1] += force_y;
            if PAIRS {
                fx[j] -= force_x;
                fy[j] -= force_y;
            }
            if ROTATION {
                sum[2] += self.torque_i[c];
                if PAIRS {
                    torque[j] += self.torque_j[c];
                }
            }
            if ROLLING {
                let resistance = rolling_friction * self.normal[c].max(0.0);
                sum[3] += resistance * self.rows.ri[c];
                if PAIRS {
                    rolling[j] += resistance * self.rows.rj[c];
                }
            }
            if !KEPT {
                springs[self.rows.candidate[c]] = self.rows.spring[c];
            }
            if stateful::<S>() {
                states[self.rows.candidate[c]] = self.state[c];
            }
        }
        if held < n {
            [fx[held], fy[held], torque[held], rolling[held]] = sum;
        }
    }

    /// Adds the table's contacts to the contact sums: force magnitudes to both disks' (`PAIRS`) or
    /// the disk's `contact_force`, elastic energy, force and overlap to `totals`.
    fn sample<L: ContactLaw<State = S>, const PAIRS: bool>(
        &self,
        law: &L,
        kind: &ContactParameters,
        contact_force: &mut [f64],
        totals: &mut ContactTotals,
    ) {
        for c in 0..self.rows.len {
            let force = ContactForce {
                normal: self.normal[c],
                tangential: self.tangential[c],
                tangential_stiffness: self.tangential_stiffness[c],
            };
            let magnitude = force.magnitude();
            let (i, j) = self.bodies(c);
            contact_force[i] += magnitude;
            if PAIRS {
                contact_force[j] += magnitude;
            }
            let pair = kind.pair_properties(self.rows.r_star[c], self.rows.m_star[c]);
            let overlap = self.overlap[c];
            let energy = contact::elastic_energy(law, &pair, overlap, &force, (self.rows.spring[c], &self.state[c]));
            totals.add(energy, magnitude, overlap / self.rows.ri[c].min(self.rows.rj[c]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::contact::HertzMindlin;
    use crate::physics::particles::{InitialDisk, Particles};

    fn kind(allow_tension: bool) -> ContactParameters {
        let material = ContactMaterial { e_star: 5e8, g_star: 2e8, beta: 0.4, friction: 0.5, rolling_friction: 0.0 };
        let options = ContactOptions { allow_tension, tangential: true, friction: material.friction };
        ContactParameters { material, options, rotation: true, dt: 1e-5 }
    }

    /// The walls of an open box 1 m wide, 4 m high.
    fn open_box() -> crate::physics::walls::BoxWalls {
        crate::physics::walls::BoxWalls::new(&crate::physics::config::DomainConfig {
            width: 1.0,
            height: 4.0,
            lid: false,
        })
    }

    /// Touching pairs with assorted geometry and motion: sticking, sliding both ways, separating
    /// fast (normal force clamped or tensile), coincident centres.
    fn table() -> TouchingPairs<()> {
        let mut t = TouchingPairs::default();
        t.rows.len = 101;
        for c in 0..t.rows.len {
            let (a, w) = (c as f64 * 0.37, (c as f64 * 0.91).sin());
            let d = if c == 7 { 0.0 } else { 0.0199 - 1e-6 * (c % 13) as f64 };
            (t.dx[c], t.dy[c]) = (d * a.cos(), d * a.sin());
            (t.rows.ri[c], t.rows.rj[c]) = (0.01, 0.01 - 1e-5 * (c % 3) as f64);
            (t.rows.r_star[c], t.rows.m_star[c]) = (0.005, 0.15);
            (t.dvx[c], t.dvy[c]) = (3.0 * w * a.cos(), -2.0 * w);
            (t.omega_i[c], t.omega_j[c]) = (50.0 * w, -20.0);
            t.rows.spring[c] = 1e-6 * (c as f64 - 50.0);
        }
        t
    }

    #[test]
    fn narrow_phase_with_and_without_branch_agree() {
        // A 6 x 6 lattice squeezed so that neighbours overlap, shaken, with assorted velocities.
        let disks: Vec<_> = (0..36)
            .map(|k| {
                let w = (k as f64 * 1.7).sin();
                InitialDisk {
                    x: 0.0195 * (k % 6) as f64 + 0.002 * w,
                    y: 0.0195 * (k / 6) as f64 - 0.001 * w,
                    r: 0.01,
                    vx: w,
                    vy: -0.5 * w,
                    omega: 3.0 * w,
                    angle: 0.0,
                }
            })
            .collect();
        let mut particles = Particles::new(&disks, 1000.0, 1.0);
        let (s, _) = particles.split();
        let near = |i: u32, j: u32| {
            let (a, b) = (&disks[i as usize], &disks[j as usize]);
            (a.x - b.x).hypot(a.y - b.y) < 0.026
        };
        let pairs: Vec<_> = (0..36u32)
            .flat_map(|i| (i + 1..36).map(move |j| (i, j)))
            .filter(|&(i, j)| near(i, j))
            .map(|(i, j)| NeighborPair { i, j, r_star: 0.005, m_star: 0.1 + f64::from(j) })
            .collect();
        let springs: Vec<f64> = (0..pairs.len()).map(|k| 1e-6 * (k % 5) as f64).collect();
        let (mut branchy, mut branch_free) = (TouchingPairs::<()>::default(), TouchingPairs::<()>::default());
        let (mut springs_branchy, mut springs_branch_free) = (springs.clone(), springs);
        let mut states = vec![(); pairs.len()];
        branchy.collect::<true, true>(&s, &pairs, (&mut springs_branchy, &mut states));
        branch_free.collect::<false, false>(&s, &pairs, (&mut springs_branch_free, &mut states));
        let touching = branchy.rows.len;
        assert!(touching > 10 && touching < pairs.len() - 10, "{touching} of {} touch", pairs.len());
        assert_eq!(branch_free.rows.len, touching);
        let rows = |t: &TouchingPairs<()>| {
            let columns = [
                t.dx,
                t.dy,
                t.rows.ri,
                t.rows.rj,
                t.rows.r_star,
                t.rows.m_star,
                t.dvx,
                t.dvy,
                t.omega_i,
                t.omega_j,
                t.rows.spring,
            ];
            (0..t.rows.len)
                .map(|c| (t.rows.candidate[c], t.bodies(c), columns.map(|column| column[c].to_bits())))
                .collect::<Vec<_>>()
        };
        assert_eq!(rows(&branchy), rows(&branch_free));
        // Out of contact: spring cleared; touching: the scatter stores the new one.
        let cleared_out_of_contact = |springs: &[f64]| {
            springs
                .iter()
                .enumerate()
                .filter(|(k, _)| !branchy.rows.candidate[..touching].contains(k))
                .all(|(_, &s)| s == 0.0)
        };
        assert!(cleared_out_of_contact(&springs_branchy) && cleared_out_of_contact(&springs_branch_free));
    }

    #[test]
    fn blocks_gathered_unchanged_give_the_narrow_phase_bits_as_contacts_come_and_go() {
        // A 16 x 16 lattice of disks that just touch (four blocks of candidates), its columns 7
        // and 8 a tenth of a millimetre apart, its rows 13 and 14 0.8 mm; four disks of the first
        // three blocks wobble on circles larger than the overlap: their pairs come into and out of
        // contact from step to step (pairs apart near touching), the others stay; the right half
        // of row 3 closes its gap, slowly, and the rows from 14 up theirs, faster (far pairs).
        let disks: Vec<_> = (0..256)
            .map(|k| {
                let w = (k as f64 * 1.3).sin();
                let column = 0.01998 * (k % 16) as f64 + if k % 16 > 7 { 1.2e-4 } else { 0.0 };
                let row = 0.01998 * (k / 16) as f64 + if k / 16 > 13 { 8e-4 } else { 0.0 };
                let (x, y) = (0.05 + column, 0.05 + row);
                InitialDisk { x, y, r: 0.01, vx: w, vy: -0.5 * w, omega: 3.0 * w, angle: 0.0 }
            })
            .collect();
        let mut particles = Particles::new(&disks, 1000.0, 1.0);
        let walls = open_box();
        let team = crate::physics::parallel::Team::new(1);
        let mut list = NeighborList::<()>::new(crate::physics::config::BroadPhaseKind::Grid, 0.004);
        list.rebuild(&particles, &walls, &team);
        let (law, kind) = (HertzMindlin {}, kind(false));
        let (mut kept, mut totals) = (TouchingPairs::<()>::default(), ContactTotals::default());
        let mut blocks = 0;
        for step in 0..80 {
            // The disks moved, and the list told how far (as the integrator tells it).
            let mut longest = 0.0_f64;
            for (k, disk) in disks.iter().enumerate() {
                let wobble = if k % 50 == 7 && k < 192 { 3e-5 } else { 0.0 };
                let phase = 0.3 * step as f64 + k as f64;
                let closing = if k / 16 == 3 && k % 16 > 7 { 2e-6 * step as f64 } else { 0.0 };
                let falling = if k / 16 > 13 { 1.2e-5 * step as f64 } else { 0.0 };
                let (x, y) = (disk.x - closing + wobble * phase.cos(), disk.y - falling + wobble * phase.sin());
                longest = longest.max((x - particles.x[k]).hypot(y - particles.y[k]));
                (particles.x[k], particles.y[k]) = (x, y);
            }
            assert!(!list.note_step(longest), "no build needed");
            // The same step through a table that has no rows of earlier steps (and a list with
            // the springs the kept rows hold newer).
            let mut afresh = list.clone();
            afresh.pairs.springs = kept.springs_of(&list.pairs).into_owned();
            let mut forces = Vec::new();
            for (table, list) in [(&mut kept, &mut list), (&mut TouchingPairs::default(), &mut afresh)] {
                let (s, mut f) = particles.split();
                table.contacts::<_, false>(&law, [&kind, &kind], (&walls.walls, &mut *list), &s, &mut f, &mut totals);
                let columns = [&f.fx, &f.fy, &f.torque].map(|c| c.iter().map(|v| v.to_bits()).collect::<Vec<_>>());
                let springs = table.springs_of(&list.pairs).iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                forces.push((columns, springs));
                for column in [f.fx, f.fy, f.torque] {
                    column.fill(0.0);
                }
            }
            assert!(forces[0] == forces[1], "step {step}: forces or springs differ");
            assert!(forces[0].1.iter().any(|&b| b != 0), "tangential springs");
            blocks += list.pairs.entries.len().div_ceil(BLOCK);
        }
        let (unchanged, skipped, far_tests) = (kept.unchanged_blocks, kept.apart_tests_skipped, kept.far_tests);
        assert!(
            unchanged >= blocks / 4 && blocks - unchanged >= blocks / 20,
            "{unchanged} of {blocks} blocks unchanged"
        );
        assert!(skipped >= 10 && far_tests >= 5, "far pairs apart: {skipped} gathers skipped, {far_tests} tested");
    }

    #[test]
    fn vector_stage_equals_one_contact_at_a_time_bit_for_bit() {
        for allow_tension in [false, true] {
            let (law, kind) = (HertzMindlin {}, kind(allow_tension));
            let mut t = table();
            let before = t.rows.spring;
            t.compute_forces::<_, COMPUTED>(&law, &kind);
            let (mut sliding, mut clamped) = (0, 0);
            for (c, &spring_before) in before.iter().enumerate().take(t.rows.len) {
                // One contact at a time, opaque to the compiler, so it cannot be vectorised.
                let d = std::hint::black_box(t.dx[c] * t.dx[c] + t.dy[c] * t.dy[c]).sqrt();
                let (nx, ny) = if d > 0.0 { (t.dx[c] * (1.0 / d), t.dy[c] * (1.0 / d)) } else { (1.0, 0.0) };
                let motion = Kinematics {
                    overlap: (t.rows.ri[c] + t.rows.rj[c]) - d,
                    approach_speed: t.dvx[c] * nx + t.dvy[c] * ny,
                    tangential_speed: -t.dvx[c] * ny
                        + t.dvy[c] * nx
                        + t.omega_i[c] * t.rows.ri[c]
                        + t.omega_j[c] * t.rows.rj[c],
                };
                let coefficients = law.coefficients(
                    &kind.pair_properties(t.rows.r_star[c], t.rows.m_star[c]),
                    motion.overlap,
                    &mut (),
                );
                let mut spring = spring_before;
                let force = contact::resolve(&coefficients, &kind.options, &motion, &mut spring, kind.dt);
                let expect = force.on_first_body(nx, ny);
                assert_eq!([t.force_x[c].to_bits(), t.force_y[c].to_bits()], expect.map(f64::to_bits), "force {c}");
                assert_eq!(t.torque_j[c].to_bits(), (force.tangential * t.rows.rj[c]).to_bits(), "torque {c}");
                assert_eq!(t.rows.spring[c].to_bits(), spring.to_bits(), "spring {c}");
                assert_eq!(t.normal[c].to_bits(), force.normal.to_bits(), "normal {c}");
                sliding += usize::from(force.tangential.abs() == kind.options.friction * force.normal.max(0.0));
                clamped += usize::from(force.normal <= 0.0);
            }
            assert!(sliding > 5 && sliding < 95 && clamped > 5, "cases covered: {sliding} sliding, {clamped} clamped");
            assert_eq!(t.force_x[7].to_bits(), (-t.normal[7] - 0.0 * t.tangential[7]).to_bits());
        }
    }

    #[test]
    fn wall_contacts_equal_one_contact_at_a_time_bit_for_bit() {
        // 150 disks (more than a block), half along the floor, half up the left wall, every third
        // one clear of its wall, with assorted velocities and spins; candidates for both walls.
        let disks: Vec<_> = (0..150)
            .map(|k| {
                let w = (k as f64 * 0.77).sin();
                let off_wall = 0.01 + if k % 3 == 0 { 1e-3 } else { -1e-5 * (1.0 + w) };
                let along = 0.05 + 0.02 * (k % 75) as f64;
                let (x, y) = if k < 75 { (along, off_wall) } else { (off_wall, along) };
                InitialDisk { x, y, r: 0.01, vx: w, vy: 0.3 * w - 0.1, omega: 20.0 * w, angle: 0.0 }
            })
            .collect();
        let mut particles = Particles::new(&disks, 1000.0, 1.0);
        let walls = open_box();
        let mut candidates = Candidates::<WallPair>::default();
        let m_star = particles.mass[0];
        candidates.entries = (0..150u32).flat_map(|i| [0, 1].map(|wall| WallPair { i, wall, m_star })).collect();
        candidates.springs = (0..300).map(|k| 1e-6 * ((k % 7) as f64 - 3.0)).collect();
        candidates.states = vec![(); 300];
        let before = candidates.springs.clone();
        let (law, kind) = (HertzMindlin {}, kind(false));
        let (s, mut f) = particles.split();
        let mut totals = ContactTotals::default();
        let mut t = TouchingPairs::<()>::default();
        t.wall_contacts::<_, true>(&law, &kind, &walls.walls, &mut candidates, 0..300, &s, &mut f, &mut totals);
        let mut touching = 0;
        for i in 0..150 {
            let (mut fx, mut fy, mut torque) = (0.0, 0.0, 0.0);
            for k in [2 * i, 2 * i + 1] {
                let wall = &walls.walls[candidates.entries[k].wall as usize];
                let overlap = wall.overlap(s.x[i], s.y[i], s.r[i]);
                if overlap <= 0.0 {
                    assert_eq!(candidates.springs[k], 0.0);
                    continue;
                }
                touching += 1;
                let [nx, ny] = wall.normal;
                let motion = Kinematics {
                    overlap,
                    approach_speed: s.vx[i] * nx + s.vy[i] * ny,
                    tangential_speed: -s.vx[i] * ny + s.vy[i] * nx + s.omega[i] * s.r[i],
                };
                let c = law.coefficients(&kind.pair_properties(s.r[i], m_star), overlap, &mut ());
                let mut spring = before[k];
                let force = contact::resolve(&c, &kind.options, &motion, &mut spring, kind.dt);
                let [force_x, force_y] = force.on_first_body(nx, ny);
                (fx, fy, torque) = (fx + force_x, fy + force_y, torque + force.tangential * s.r[i]);
                assert_eq!(candidates.springs[k].to_bits(), spring.to_bits(), "spring {k}");
            }
            assert_eq!(
                [f.fx[i], f.fy[i], f.torque[i]].map(f64::to_bits),
                [fx, fy, torque].map(f64::to_bits),
                "disk {i}"
            );
        }
        assert_eq!((touching, totals.contacts), (100, 100), "all but every third disk touch one wall");
    }
}
