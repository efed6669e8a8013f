//! Stage 3, the scatter: the table's forces, torques and rolling resistances added to the disks in
//! list order (so that every sum is added up in the same order), the histories stored, and on
//! sampled steps the contact sums.

use super::table::{ContactParameters, Histories, TouchingPairs, stateful};
use crate::physics::contact::{self, ContactForce, ContactLaw};
use crate::physics::contact_sums::DiskSums;
use crate::physics::diagnostics::ContactTotals;
use crate::physics::particles::Forces;

impl<S: Copy + Default + PartialEq> TouchingPairs<S> {
    /// Stage 3: adds the forces of the touching pairs to both disks (`PAIRS`; walls: to the disk),
    /// in list order, and stores the histories; with `SAMPLE`, adds the contact sums to `totals`;
    /// `KEPT`: see [`TouchingPairs::add_to`].
    pub(super) fn scatter<L: ContactLaw<State = S>, const SAMPLE: bool, const PAIRS: bool, const KEPT: bool>(
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
    pub(super) fn add_to<const PAIRS: bool, const KEPT: bool>(
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
    pub(super) fn add_rows<const PAIRS: bool, const KEPT: bool, const ROTATION: bool, const ROLLING: bool>(
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
    pub(super) fn sample<L: ContactLaw<State = S>, const PAIRS: bool>(
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
