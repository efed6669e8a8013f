//! The contact network of a state as columns (one entry per contact): what is stored with final
//! states and frames, and what exports read.

use serde::{Deserialize, Serialize};

use super::contact_record::{Partner, PileContact};
use super::particles::Particles;

/// Every contact carrying force at one time: disk pairs first (ordered by first disk), then disk-wall
/// contacts. Forces act on `first`; on `second` (a disk) they act the other way.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactNetwork {
    /// The first body: a disk index.
    pub first: Vec<u32>,
    /// The second body: a disk index `≥ 0`, or a wall `−1 − k` (k: index of the wall; 0 floor,
    /// 1 left, 2 right, 3 lid).
    pub second: Vec<i64>,
    /// Unit normal from the first body to the second, x and y.
    pub normal_x: Vec<f64>,
    /// See `normal_x`.
    pub normal_y: Vec<f64>,
    /// Normal force (N), repulsive positive.
    pub normal_force: Vec<f64>,
    /// Tangential force on the first body along `t = (−n_y, n_x)` (N).
    pub tangential_force: Vec<f64>,
    /// Overlap δ (m).
    pub overlap: Vec<f64>,
    /// Contact point x (m): on the line of centres, in the middle of the overlap.
    pub point_x: Vec<f64>,
    /// Contact point y (m).
    pub point_y: Vec<f64>,
    /// Whether the tangential force sits on the Coulomb limit `μ F_n` ([`PileContact::is_sliding`]).
    pub sliding: Vec<bool>,
    /// Tangential spring ξ (m), the contact's history as the next step starts from it.
    #[serde(default)]
    pub tangential_spring: Vec<f64>,
    /// The contact law's own state as a number ([`super::contact::ContactState`]; `hysteretic_linear`:
    /// the largest overlap so far, m; 0 for laws without).
    #[serde(default)]
    pub law_state: Vec<f64>,
}

impl ContactNetwork {
    /// The network of `contacts` (see [`super::simulation::Simulation::contacts`]) in state `p`.
    pub fn new(contacts: &[PileContact], p: &Particles) -> Self {
        let mut network = Self::default();
        for c in contacts {
            let i = c.disk;
            let [nx, ny] = c.normal;
            let second = match c.partner {
                Partner::Disk(j) => j as i64,
                Partner::Wall(k) => -1 - k as i64,
            };
            let overlap = c.overlap_ratio
                * match c.partner {
                    Partner::Disk(j) => p.r[i].min(p.r[j]),
                    Partner::Wall(_) => p.r[i],
                };
            let reach = p.r[i] - 0.5 * overlap;
            network.first.push(i as u32);
            network.second.push(second);
            network.normal_x.push(nx);
            network.normal_y.push(ny);
            network.normal_force.push(c.normal_force);
            network.tangential_force.push(c.tangential_force);
            network.overlap.push(overlap);
            network.point_x.push(p.x[i] + reach * nx);
            network.point_y.push(p.y[i] + reach * ny);
            network.sliding.push(c.is_sliding());
            network.tangential_spring.push(c.history.0);
            network.law_state.push(c.history.1);
        }
        network
    }

    /// The contacts as the pile measures see them, for disks of radii `r` (a stored state's
    /// network back into [`PileContact`]s; friction reads 0: the network keeps only whether a contact
    /// slides). A contact naming a disk the state lacks (a damaged file) is left out.
    pub fn pile_contacts(&self, r: &[f64]) -> Vec<PileContact> {
        (0..self.len())
            .filter_map(|k| {
                let disk = self.first[k] as usize;
                let (partner, smaller) = match usize::try_from(self.second[k]) {
                    Ok(j) => (Partner::Disk(j), r.get(disk)?.min(*r.get(j)?)),
                    Err(_) => (Partner::Wall((-1 - self.second[k]) as usize), *r.get(disk)?),
                };
                Some(PileContact {
                    disk,
                    partner,
                    normal: [self.normal_x[k], self.normal_y[k]],
                    normal_force: self.normal_force[k],
                    tangential_force: self.tangential_force[k],
                    friction: 0.0,
                    overlap_ratio: self.overlap[k] / smaller,
                    history: (self.tangential_spring[k], self.law_state[k]),
                })
            })
            .collect()
    }

    /// Number of contacts.
    pub fn len(&self) -> usize {
        self.first.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.first.is_empty()
    }
}

super::run_state::persist_fields!(ContactNetwork {
    first,
    second,
    normal_x,
    normal_y,
    normal_force,
    tangential_force,
    overlap,
    point_x,
    point_y,
    sliding,
    tangential_spring,
    law_state,
});
