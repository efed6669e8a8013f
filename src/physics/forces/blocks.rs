//! The one-thread block loop ([`TouchingPairs::contacts`]): the disk pairs block by block through
//! the three stages, with the disk-wall contacts in between, and the springs the kept rows hold
//! newer than the list.

use super::stages::{CHECKED, COMPUTED};
use super::table::{ContactParameters, PREDICTED_CANDIDATES, TouchingPairs, states_of};
use crate::physics::contact::ContactLaw;
use crate::physics::contact_sums::BLOCK;
use crate::physics::diagnostics::ContactTotals;
use crate::physics::neighbors::{Candidates, NeighborList, NeighborPair};
use crate::physics::particles::{Forces, State};
use crate::physics::walls::{Sides, Wall};
use std::borrow::Cow;

/// Fewest disk-wall candidates evaluated together (see `TouchingPairs::contacts`).
pub(super) const WALL_BATCH: usize = 64;

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
    /// contact sums to `totals`. The disk pairs' x separations are measured across `sides`.
    ///
    /// Every disk's sums come out as if all disk pairs were added first and then the walls (pairs
    /// are sorted by first disk, so no later block touches a disk below the block's first disk),
    /// but each disk's wall contacts are evaluated while its data is still in cache from the blocks
    /// just done: in large scenes, a separate pass over the disks at the walls (one in every dozen
    /// or so in a wide pile) would fetch each of them from memory again.
    #[allow(clippy::too_many_arguments)]
    pub fn contacts<L: ContactLaw<State = S>, X: Sides, const SAMPLE: bool>(
        &mut self,
        law: &L,
        kinds: [&ContactParameters; 2],
        (walls, sides, neighbors): (&[Wall], X, &mut NeighborList<S>),
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
                && self.gather_unchanged((s, sides), (build, travel), block, states)
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
                self.narrow_phase(b, (short, short), (s, sides), block, (springs, states));
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
}
