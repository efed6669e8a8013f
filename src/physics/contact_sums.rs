//! The contact forces of a step on several threads. The blocks of candidates are shared out
//! between threads in parts; a part adds each contact's force itself to those of its disks all of
//! whose pairs are in the part (most of its disks: see [`DiskIndex::own_disks`]), in list order as
//! the one-thread scatter does, and stores it in the block's rows for the others (disks near the
//! part's ends). Then the rows are added to the disks, the disks shared out in runs: the thread of a
//! run goes through the rows in list order, from the first block that touches one of its disks,
//! adding each row to those of its disks that are in the run; then the wall rows of its disks. So
//! every disk gets the same terms in the same order as from the one-thread scatter (which adds
//! pairs in list order and the walls after them), whatever the parts and runs: the same bits on any
//! number of threads.

use super::neighbors::{NeighborPair, WallPair};
use super::parallel::{Split, Team, split_slice};
use std::ops::Range;

/// Candidates per block of the contact stages (`forces`): the block's table of touching pairs stays
/// in the L1 cache.
pub const BLOCK: usize = 128;

/// The disk index of a row's disk whose force the part that evaluated the contact added itself.
pub const ADDED: u32 = u32::MAX;

/// Disks per unit of the per-disk sums.
const DISKS_PER_UNIT: usize = 256;

/// The touching contacts of a candidate list, block by block: block `b`'s are rows
/// `b * BLOCK..b * BLOCK + touching[b]`, in list order, one array per quantity. A disk whose force
/// is already added has [`ADDED`] in place of its index.
#[derive(Clone, Debug, Default)]
pub struct ContactRows {
    /// Touching contacts per block.
    pub touching: Vec<u8>,
    /// First disk.
    pub disk_i: Vec<u32>,
    /// Second disk (walls: the disk).
    pub disk_j: Vec<u32>,
    /// Force on the first disk (on the second: the opposite) (N).
    pub fx: Vec<f64>,
    /// (N).
    pub fy: Vec<f64>,
    /// Torque on the first disk (N·m).
    pub torque_i: Vec<f64>,
    /// Torque on the second disk (N·m; unused for walls).
    pub torque_j: Vec<f64>,
    /// Total normal force (N), for rolling resistance.
    pub normal: Vec<f64>,
}

impl ContactRows {
    /// Rows for `len` candidates (allocates only when the list has grown).
    fn resize(&mut self, len: usize) {
        self.touching.resize(len.div_ceil(BLOCK), 0);
        self.disk_i.resize(len, 0);
        self.disk_j.resize(len, 0);
        for column in [&mut self.fx, &mut self.fy, &mut self.torque_i, &mut self.torque_j, &mut self.normal] {
            column.resize(len, 0.0);
        }
    }

    /// All rows, writable.
    pub fn rows(&mut self) -> RowsMut<'_> {
        RowsMut {
            touching: &mut self.touching,
            disk_i: &mut self.disk_i,
            disk_j: &mut self.disk_j,
            fx: &mut self.fx,
            fy: &mut self.fy,
            torque_i: &mut self.torque_i,
            torque_j: &mut self.torque_j,
            normal: &mut self.normal,
        }
    }

    /// The rows of block `b`.
    fn block(&self, b: usize) -> Range<usize> {
        b * BLOCK..b * BLOCK + usize::from(self.touching[b])
    }
}

/// Writable rows of [`ContactRows`] for a run of whole blocks.
pub struct RowsMut<'a> {
    /// See [`ContactRows`].
    pub touching: &'a mut [u8],
    /// See [`ContactRows`].
    pub disk_i: &'a mut [u32],
    /// See [`ContactRows`].
    pub disk_j: &'a mut [u32],
    /// See [`ContactRows`].
    pub fx: &'a mut [f64],
    /// See [`ContactRows`].
    pub fy: &'a mut [f64],
    /// See [`ContactRows`].
    pub torque_i: &'a mut [f64],
    /// See [`ContactRows`].
    pub torque_j: &'a mut [f64],
    /// See [`ContactRows`].
    pub normal: &'a mut [f64],
}

impl RowsMut<'_> {
    /// The first `blocks` blocks' rows and the rest.
    pub fn split_blocks(self, blocks: usize) -> (Self, Self) {
        let (t0, t1) = split_slice(self.touching, blocks, 1);
        let (i0, i1) = split_slice(self.disk_i, blocks, BLOCK);
        let (j0, j1) = split_slice(self.disk_j, blocks, BLOCK);
        let (fx0, fx1) = split_slice(self.fx, blocks, BLOCK);
        let (fy0, fy1) = split_slice(self.fy, blocks, BLOCK);
        let (ti0, ti1) = split_slice(self.torque_i, blocks, BLOCK);
        let (tj0, tj1) = split_slice(self.torque_j, blocks, BLOCK);
        let (n0, n1) = split_slice(self.normal, blocks, BLOCK);
        (
            RowsMut {
                touching: t0,
                disk_i: i0,
                disk_j: j0,
                fx: fx0,
                fy: fy0,
                torque_i: ti0,
                torque_j: tj0,
                normal: n0,
            },
            RowsMut {
                touching: t1,
                disk_i: i1,
                disk_j: j1,
                fx: fx1,
                fy: fy1,
                torque_i: ti1,
                torque_j: tj1,
                normal: n1,
            },
        )
    }
}

/// The touching contacts of disk pairs and walls, and for each disk from which block its rows are.
#[derive(Clone, Debug, Default)]
pub struct ContactSums {
    /// Touching disk pairs.
    pub pairs: ContactRows,
    /// Touching disk-wall contacts.
    pub walls: ContactRows,
    /// For disk `d`: pairs `first_start[d]..first_start[d + 1]` have it as first disk.
    first_start: Vec<u32>,
    /// For disk `d`: the first pair whose second disk is `d` or above.
    earliest: Vec<u32>,
    /// For disk `d`: wall candidates `wall_start[d]..wall_start[d + 1]` are its.
    wall_start: Vec<u32>,
    /// Whether the index matches the current lists.
    indexed: bool,
}

/// Where each disk's candidates are (see [`ContactSums`]).
#[derive(Clone, Copy)]
pub struct DiskIndex<'a> {
    first_start: &'a [u32],
    earliest: &'a [u32],
    wall_start: &'a [u32],
}

impl DiskIndex<'_> {
    /// The disks all of whose pairs are among the pair candidates `candidates`: a part that
    /// evaluates those candidates in list order can add their forces to these disks itself, in the
    /// one-thread order (the walls come later, in the sums).
    pub fn own_disks(&self, candidates: Range<usize>) -> Range<usize> {
        let first = self.earliest.partition_point(|&k| (k as usize) < candidates.start);
        let end = self.first_start[1..].partition_point(|&k| k as usize <= candidates.end);
        first..end.max(first)
    }

    /// The first pair whose second disk is `d` or above (`d` up to the number of disks; the
    /// number of pairs if none).
    pub fn first_pair_reaching(&self, d: usize) -> usize {
        self.earliest[d] as usize
    }

    /// The first wall block of disk `d`.
    pub fn wall_block(&self, d: usize) -> usize {
        self.wall_start[d] as usize / BLOCK
    }
}

/// What the per-disk sums add besides the rows.
#[derive(Clone, Copy, Debug)]
pub struct SumOptions {
    /// Whether torques are added (false when nothing can spin).
    pub rotation: bool,
    /// Rolling friction coefficient of disk pairs and of walls.
    pub rolling_friction: [f64; 2],
}

/// The per-disk accumulators of a run of disks, starting at disk `first`.
pub struct DiskSums<'a> {
    /// The first disk.
    pub first: usize,
    /// Net force x (N).
    pub fx: &'a mut [f64],
    /// Net force y (N).
    pub fy: &'a mut [f64],
    /// Net torque (N·m).
    pub torque: &'a mut [f64],
    /// Summed rolling-resistance torque magnitude (N·m).
    pub rolling: &'a mut [f64],
}

impl<'a> DiskSums<'a> {
    /// The accumulators of all disks.
    pub fn new(fx: &'a mut [f64], fy: &'a mut [f64], torque: &'a mut [f64], rolling: &'a mut [f64]) -> Self {
        Self { first: 0, fx, fy, torque, rolling }
    }
}

impl DiskSums<'_> {
    /// The disks before disk `d` (at most all) and the rest.
    pub fn split_disks(self, d: usize) -> (Self, Self) {
        let at = d.saturating_sub(self.first).min(self.fx.len());
        let (fx0, fx1) = self.fx.split_at_mut(at);
        let (fy0, fy1) = self.fy.split_at_mut(at);
        let (t0, t1) = self.torque.split_at_mut(at);
        let (r0, r1) = self.rolling.split_at_mut(at);
        let second = DiskSums { first: self.first + at, fx: fx1, fy: fy1, torque: t1, rolling: r1 };
        (DiskSums { first: self.first, fx: fx0, fy: fy0, torque: t0, rolling: r0 }, second)
    }

    /// Adds contact `row` of `rows` to disk `k` of the run, its first disk (`FIRST`) or its second
    /// (the force subtracted), as the one-thread scatter does; `rolling`: the rolling friction
    /// coefficient (0: none) and the disk's radius.
    #[inline(always)]
    fn add<const FIRST: bool>(&mut self, k: usize, rows: &ContactRows, row: usize, rotation: bool, rolling: [f64; 2]) {
        if FIRST {
            self.fx[k] += rows.fx[row];
            self.fy[k] += rows.fy[row];
        } else {
            self.fx[k] -= rows.fx[row];
            self.fy[k] -= rows.fy[row];
        }
        if rotation {
            self.torque[k] += if FIRST { rows.torque_i[row] } else { rows.torque_j[row] };
        }
        let [coefficient, radius] = rolling;
        if coefficient > 0.0 {
            self.rolling[k] += coefficient * rows.normal[row].max(0.0) * radius;
        }
    }
}

impl Split for DiskSums<'_> {
    fn units(&self) -> usize {
        self.fx.len().div_ceil(DISKS_PER_UNIT)
    }

    fn split_at(self, at: usize) -> (Self, Self) {
        let (fx0, fx1) = split_slice(self.fx, at, DISKS_PER_UNIT);
        let (fy0, fy1) = split_slice(self.fy, at, DISKS_PER_UNIT);
        let (t0, t1) = split_slice(self.torque, at, DISKS_PER_UNIT);
        let (r0, r1) = split_slice(self.rolling, at, DISKS_PER_UNIT);
        let second = DiskSums { first: self.first + fx0.len(), fx: fx1, fy: fy1, torque: t1, rolling: r1 };
        (DiskSums { first: self.first, fx: fx0, fy: fy0, torque: t0, rolling: r0 }, second)
    }
}

impl ContactSums {
    /// The lists have changed (a neighbour-list build): the index is made again before next use.
    pub fn invalidate(&mut self) {
        self.indexed = false;
    }

    /// The rows of the pairs and of the walls, writable, and the index of the lists by disk.
    pub fn rows(&mut self) -> (RowsMut<'_>, RowsMut<'_>, DiskIndex<'_>) {
        let index =
            DiskIndex { first_start: &self.first_start, earliest: &self.earliest, wall_start: &self.wall_start };
        (self.pairs.rows(), self.walls.rows(), index)
    }

    /// Sizes the rows for the lists and indexes them if they changed.
    pub fn prepare(&mut self, pairs: &[NeighborPair], walls: &[WallPair], disks: usize) {
        self.pairs.resize(pairs.len());
        self.walls.resize(walls.len());
        if self.indexed && self.first_start.len() == disks + 1 {
            return;
        }
        // Counting sorts: by first disk, by wall disk (both lists are sorted by disk).
        let count = |start: &mut Vec<u32>, keys: &mut dyn Iterator<Item = u32>| {
            start.clear();
            start.resize(disks + 1, 0);
            for d in keys {
                start[d as usize + 1] += 1;
            }
            for d in 0..disks {
                start[d + 1] += start[d];
            }
        };
        count(&mut self.first_start, &mut pairs.iter().map(|p| p.i));
        count(&mut self.wall_start, &mut walls.iter().map(|w| w.i));
        let none = pairs.len() as u32;
        self.earliest.clear();
        self.earliest.resize(disks + 1, none);
        for (k, p) in pairs.iter().enumerate().rev() {
            self.earliest[p.j as usize] = k as u32;
        }
        for d in (0..disks).rev() {
            self.earliest[d] = self.earliest[d].min(self.earliest[d + 1]);
        }
        self.indexed = true;
    }

    /// Adds the rows to the disks' accumulators (which hold zeros: the integrator cleared them),
    /// disks shared out in runs between the `team`'s threads; `r`: the radii.
    pub fn add_up(&self, sums: DiskSums<'_>, r: &[f64], options: SumOptions, team: &Team) {
        team.for_each_part(sums, &|run: DiskSums<'_>, _| self.add_up_run(run, r, options));
    }

    fn add_up_run(&self, mut sums: DiskSums<'_>, r: &[f64], options: SumOptions) {
        let (first, n) = (sums.first, sums.fx.len());
        if n == 0 {
            return;
        }
        let [pair_rolling, wall_rolling] = options.rolling_friction;
        let blocks = |start: u32, end: u32| start as usize / BLOCK..(end as usize).div_ceil(BLOCK);
        let p = &self.pairs;
        // Rows of other disks in the first and last blocks fall outside `0..n`, and are skipped.
        for b in blocks(self.earliest[first], self.first_start[first + n]) {
            for row in p.block(b) {
                let (i, j) =
                    ((p.disk_i[row] as usize).wrapping_sub(first), (p.disk_j[row] as usize).wrapping_sub(first));
                if i < n {
                    sums.add::<true>(i, p, row, options.rotation, [pair_rolling, r[first + i]]);
                }
                if j < n {
                    sums.add::<false>(j, p, row, options.rotation, [pair_rolling, r[first + j]]);
                }
            }
        }
        let w = &self.walls;
        for b in blocks(self.wall_start[first], self.wall_start[first + n]) {
            for row in w.block(b) {
                let i = (w.disk_i[row] as usize).wrapping_sub(first);
                if i < n {
                    sums.add::<true>(i, w, row, options.rotation, [wall_rolling, r[first + i]]);
                }
            }
        }
    }
}
