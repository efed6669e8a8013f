//! Disk-wall contacts through the same table and stages as the disk pairs: the narrow phase puts
//! the wall's normal and the overlap in place of the geometry loop's.

use super::stages::GIVEN;
use super::table::{ContactParameters, Histories, TouchingPairs, stateful, states_of};
use crate::physics::contact::ContactLaw;
use crate::physics::contact_sums::BLOCK;
use crate::physics::diagnostics::ContactTotals;
use crate::physics::neighbors::{Candidates, WallPair};
use crate::physics::particles::{Forces, State};
use crate::physics::walls::Wall;
use std::ops::Range;

impl<S: Copy + Default + PartialEq> TouchingPairs<S> {
    /// Adds the disk-wall contacts of the candidates in `range` (and with `SAMPLE`, their contact
    /// sums to `totals`), through the same table and vector loops as the disk pairs, `BLOCK` at a time.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn wall_contacts<L: ContactLaw<State = S>, const SAMPLE: bool>(
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

    /// Stage 1 for disk-wall candidates: the table rows of those touching, with the wall's normal
    /// and the overlap already in place (a wall has no centre to measure a distance from); the
    /// wall is the second body, at rest, of infinite radius and mass (`R* = r`, `m* = m`).
    pub(super) fn collect_walls(
        &mut self,
        s: &State<'_>,
        walls: &[Wall],
        candidates: &[WallPair],
        histories: Histories<'_, S>,
    ) {
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
}
