//! The contacts of a state one at a time, with their forces: what pile metrics (and exports) read.
//! It uses the same per-contact arithmetic as the step's block stages
//! ([`forces`](super::forces)), so it gives the forces the next step would compute, to the bit.

use super::contact::{ContactForce, ContactLaw, ContactState};
use super::contact_record::{Partner, PileContact};
use super::forces::{ContactParameters, relative_motion, unit_normal_and_overlap};
use super::neighbors::NeighborList;
use super::particles::Particles;
use super::walls::BoxWalls;

/// Every touching disk pair (in neighbour-list order, across periodic sides to the nearest image), then every disk-wall contact, with the
/// force the law gives it at this state (springs and law states are left as they are). The disk
/// pairs' springs are `pair_springs` (the list's as the steps left them, see
/// [`super::forces::TouchingPairs::springs_of`]).
pub(super) fn contacts<L: ContactLaw>(
    law: &L,
    kinds: [&ContactParameters; 2],
    (neighbors, pair_springs): (&NeighborList<L::State>, &[f64]),
    p: &Particles,
    walls: &BoxWalls,
) -> Vec<PileContact> {
    let [disk_kind, wall_kind] = kinds;
    let mut contacts = Vec::new();
    let pairs = &neighbors.pairs;
    for (k, pair) in pairs.entries.iter().enumerate() {
        let (i, j) = (pair.i as usize, pair.j as usize);
        let (normal, overlap) = unit_normal_and_overlap(walls.dx(p.x[j] - p.x[i]), p.y[j] - p.y[i], p.r[i], p.r[j]);
        // The block stage's test: not "apart" (NaN counts as touching there; here it is skipped).
        if overlap > 0.0 {
            let motion = relative_motion(
                overlap,
                normal,
                [p.vx[i] - p.vx[j], p.vy[i] - p.vy[j]],
                [p.omega[i] * p.r[i], p.omega[j] * p.r[j]],
            );
            let history = (pair_springs[k], pairs.states[k]);
            let force = disk_kind.force_of(law, (pair.r_star, pair.m_star), &motion, history);
            let ratio = overlap / p.r[i].min(p.r[j]);
            contacts.push(pile_contact(i, Partner::Disk(j), normal, (force, history), disk_kind, ratio));
        }
    }
    let candidates = &neighbors.walls;
    for (k, candidate) in candidates.entries.iter().enumerate() {
        let (i, w) = (candidate.i as usize, candidate.wall as usize);
        let wall = &walls.walls[w];
        let overlap = wall.overlap(p.x[i], p.y[i], p.r[i]);
        if overlap > 0.0 {
            let motion = relative_motion(overlap, wall.normal, [p.vx[i], p.vy[i]], [p.omega[i] * p.r[i], 0.0]);
            let history = (candidates.springs[k], candidates.states[k]);
            let force = wall_kind.force_of(law, (p.r[i], candidate.m_star), &motion, history);
            let resolved = (force, history);
            contacts.push(pile_contact(i, Partner::Wall(w), wall.normal, resolved, wall_kind, overlap / p.r[i]));
        }
    }
    contacts
}

/// A contact with its force and the history it was computed from (tangential spring, law state).
fn pile_contact<S: ContactState>(
    disk: usize,
    partner: Partner,
    normal: [f64; 2],
    (force, (spring, state)): (ContactForce, (f64, S)),
    kind: &ContactParameters,
    overlap_ratio: f64,
) -> PileContact {
    PileContact {
        disk,
        partner,
        normal,
        normal_force: force.normal,
        tangential_force: force.tangential,
        friction: if kind.options.tangential { kind.options.friction } else { 0.0 },
        overlap_ratio,
        history: (spring, state.to_number()),
    }
}
