//! The parallel path: the blocks of disk pairs and disk-wall candidates shared out between a
//! team's threads, each part through a table of its own, forces added to the disks the part owns
//! and stored per candidate for the others, then summed per disk in the one-thread order.

use super::stages::{COMPUTED, GIVEN};
use super::table::{ContactParameters, Histories, PREDICTED_CANDIDATES, TouchingPairs, stateful};
use crate::physics::contact::ContactLaw;
use crate::physics::contact_sums::{ADDED, BLOCK, ContactSums, DiskIndex, DiskSums, RowsMut, SumOptions};
use crate::physics::neighbors::{Candidates, NeighborPair, WallPair};
use crate::physics::parallel::{Split, Team, split_slice};
use crate::physics::particles::{Forces, State};
use crate::physics::walls::{Sides, Wall};
use std::ops::Range;
use std::sync::Mutex;

/// A run of whole blocks of candidates (the first is block `first_block` of its list) with their
/// histories and force rows: a part of the parallel path's work.
pub(super) struct CandidateBlocks<'a, T, S> {
    pub(super) first_block: usize,
    pub(super) entries: &'a [T],
    pub(super) springs: &'a mut [f64],
    pub(super) states: &'a mut [S],
    pub(super) rows: RowsMut<'a>,
}

impl<'a, T, S> CandidateBlocks<'a, T, S> {
    pub(super) fn new(entries: &'a [T], springs: &'a mut [f64], states: &'a mut [S], rows: RowsMut<'a>) -> Self {
        Self { first_block: 0, entries, springs, states, rows }
    }

    /// The first `at` blocks and the rest.
    pub(super) fn cut(self, at: usize) -> (Self, Self) {
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
pub(super) struct Blocks<'a, S> {
    pub(super) pairs: CandidateBlocks<'a, NeighborPair, S>,
    pub(super) walls: CandidateBlocks<'a, WallPair, S>,
    pub(super) sums: DiskSums<'a>,
    pub(super) index: DiskIndex<'a>,
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
/// disks shared out likewise (see [`super::contact_sums`]); the disk pairs' x separations measured
/// across `sides`. The same bits as [`TouchingPairs::contacts`].
#[allow(clippy::too_many_arguments)]
pub fn contacts_in_parts<L: ContactLaw, X: Sides>(
    tables: &mut Vec<Mutex<TouchingPairs<L::State>>>,
    law: &L,
    kinds: [&ContactParameters; 2],
    (pairs, sides): (&mut Candidates<NeighborPair, L::State>, X),
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
        table.pair_forces(law, disk_kind, part.pairs, (s, sides), short, (&mut part.sums, own.clone(), reaching));
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
    /// The stages for the disk-pair blocks of `part`: the forces added to the disks `own` of
    /// `sums` (all of whose pairs are in `part`), and stored in the part's rows for the others;
    /// `short`: whether the whole list is short (see `collect`); `reaching`: the first candidate
    /// whose second disk is `own.end` or above.
    pub(super) fn pair_forces<L: ContactLaw<State = S>, X: Sides>(
        &mut self,
        law: &L,
        kind: &ContactParameters,
        part: CandidateBlocks<'_, NeighborPair, S>,
        (s, sides): (&State<'_>, X),
        short: bool,
        (sums, own, reaching): (&mut DiskSums<'_>, Range<usize>, usize),
    ) {
        let mut rest = part;
        while !rest.entries.is_empty() {
            let (block, after) = rest.cut(1);
            let b = block.first_block;
            self.narrow_phase(b, (short, false), (s, sides), block.entries, (block.springs, block.states));
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
    pub(super) fn wall_forces<L: ContactLaw<State = S>>(
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
    pub(super) fn store_row(&self, rows: &mut RowsMut<'_>, at: usize, c: usize, [disk_i, disk_j]: [u32; 2]) {
        (rows.disk_i[at], rows.disk_j[at]) = (disk_i, disk_j);
        (rows.fx[at], rows.fy[at]) = (self.force_x[c], self.force_y[c]);
        (rows.torque_i[at], rows.torque_j[at]) = (self.torque_i[c], self.torque_j[c]);
        rows.normal[at] = self.normal[c];
    }

    /// Adds contact `c`'s force, torque and rolling resistance to disk `k` of `sums`, its first
    /// body (`FIRST`) or its second (the force subtracted), as the one-thread scatter does.
    #[inline(always)]
    pub(super) fn add_one<const FIRST: bool>(
        &self,
        kind: &ContactParameters,
        c: usize,
        k: usize,
        sums: &mut DiskSums<'_>,
    ) {
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
    pub(super) fn add_or_store(
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
    pub(super) fn keep_histories(&self, (springs, states): Histories<'_, S>) {
        for c in 0..self.rows.len {
            let k = self.rows.candidate[c];
            springs[k] = self.rows.spring[c];
            if stateful::<S>() {
                states[k] = self.state[c];
            }
        }
    }
}
