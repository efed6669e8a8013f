//! What a simulation tells at its current state: diagnostics, snapshots, the contacts with their
//! forces and the pile measures, all in the scene's numbering.

use super::step::Simulation;
use crate::physics::contact::ContactLaw;
use crate::physics::contact_list;
use crate::physics::contact_network::ContactNetwork;
use crate::physics::contact_record::PileContact;
use crate::physics::diagnostics::{self, Sample};
use crate::physics::memory_order::Numbering;
use crate::physics::particles::Particles;
use crate::physics::pile::{PileGeometry, PileMetrics};
use crate::physics::record::Snapshot;
use crate::physics::stability::{self, StabilityReport};
use crate::physics::vector;
use std::borrow::Cow;

impl<L: ContactLaw> Simulation<L> {
    /// Which scene disk each place of [`Self::particles`] holds.
    pub fn numbering(&self) -> &Numbering {
        &self.numbering
    }

    /// The disks, in the simulation's own numbering ([`Self::numbering`]: the scene's unless a
    /// large scene was numbered afresh); snapshots give them in the scene's.
    pub fn particles(&self) -> &Particles {
        &self.particles
    }

    /// The disks in the scene's numbering.
    pub(super) fn scene_particles(&self) -> Cow<'_, Particles> {
        let Some(places) = self.numbering.places() else { return Cow::Borrowed(&self.particles) };
        let mut p = self.particles.clone();
        p.renumber(&places, &mut Vec::new());
        Cow::Owned(p)
    }

    /// The disks the run's estimates see (stability, energy scale): the scene's, or a pour's
    /// reference disks.
    pub(super) fn estimated_particles(&self) -> Cow<'_, Particles> {
        match &self.inlet {
            Some(inlet) => Cow::Owned(inlet.reference(&self.scene)),
            None => self.scene_particles(),
        }
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.step
    }

    /// The time step (s), as resolved.
    pub fn time_step(&self) -> f64 {
        self.context.dt
    }

    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        let (step, time) = self.protocol.clock;
        time + (self.step - step) as f64 * self.context.dt
    }

    /// The pre-run stability estimate for this scene.
    pub fn stability(&self) -> StabilityReport {
        let physical = self.protocol.physical();
        stability::assess(&self.law, &self.scene, &self.estimated_particles(), &physical.materials, &self.walls)
    }

    /// Diagnostics at the current state; valid after a sampled step (or at time zero).
    pub fn sample(&self) -> Sample {
        let (kt, kr) = diagnostics::kinetic_energies(&self.particles);
        // Works up to now: the stored trapezoids end one step back; close the last one.
        let works = self.energy.works_now(|| (self.contact_power(), self.damping_power()), self.context.dt);
        Sample {
            time: self.time(),
            kinetic_translational: kt,
            kinetic_rotational: kr,
            potential: diagnostics::potential_energy(&self.particles, self.scene.gravity),
            elastic: self.totals.elastic,
            dissipated: self.energy.dissipated(self.totals.elastic, works),
            numerical_damping_dissipated: -works.1,
            unbalanced_force_ratio: diagnostics::unbalanced_force_ratio(
                &self.particles,
                self.scene.gravity,
                &self.totals,
            ),
            contacts: self.totals.contacts,
            max_overlap_ratio: self.totals.max_overlap_ratio,
        }
    }

    /// Full state now (contact force sums as of the last sampled step), with the contact network.
    pub fn snapshot(&self) -> Snapshot {
        self.snapshot_with(&self.contacts())
    }

    /// Full state now with `contacts` (those of [`Self::contacts`]) as its network.
    pub(super) fn snapshot_with(&self, contacts: &[PileContact]) -> Snapshot {
        let p = &*self.scene_particles();
        Snapshot {
            time: self.time(),
            x: p.x.clone(),
            y: p.y.clone(),
            vx: p.vx.clone(),
            vy: p.vy.clone(),
            omega: p.omega.clone(),
            angle: p.angle.clone(),
            r: p.r.clone(),
            contact_force: p.contact_force.clone(),
            contacts: ContactNetwork::new(contacts, p),
        }
    }

    /// Power of the contact forces and torques at the current velocities (W). Integrated by the
    /// trapezoid rule over steps it gives the work of the contacts, and with it the energy dissipated.
    /// Each step gets it from the integrator's pass; this is for closing the last step at a sample.
    pub(super) fn contact_power(&self) -> f64 {
        let p = &self.particles;
        let n = p.len();
        let (fx, fy, vx, vy) = (&p.fx[..n], &p.fy[..n], &p.vx[..n], &p.vy[..n]);
        let mut power = vector::lane_dot([fx, fy], [vx, vy]);
        if self.context.rotation {
            let (torque, omega) = (&p.torque[..n], &p.omega[..n]);
            power += vector::lane_dot([torque], [omega]);
        }
        power
    }

    /// Power of the numerical damping at the current state (W; zero when it is off).
    pub(super) fn damping_power(&self) -> f64 {
        let d = &self.context.damping;
        if d.is_active() { d.power(&self.particles, self.context.gravity, self.context.rotation) } else { 0.0 }
    }

    /// The contacts at the current state with their forces, in the scene's numbering: those the
    /// next step's force stage would compute from the current springs (see `contact_list`).
    pub fn contacts(&self) -> Vec<PileContact> {
        let kinds = [&self.disk_contacts, &self.wall_contacts];
        let springs = self.touching.springs_of(&self.neighbors.pairs);
        let lists = (&self.neighbors, &springs[..]);
        let mut contacts = contact_list::contacts(&self.law, kinds, lists, &self.particles, &self.walls);
        self.numbering.scene_contacts(&mut contacts);
        contacts
    }

    /// The pile measures of the current state (see [`Self::contacts`]).
    pub fn pile_metrics(&self) -> PileMetrics {
        self.pile_metrics_of(&self.contacts())
    }

    /// The pile measures of the current state with its `contacts`.
    pub(super) fn pile_metrics_of(&self, contacts: &[PileContact]) -> PileMetrics {
        let p = &*self.scene_particles();
        let g = self.scene.gravity[0].hypot(self.scene.gravity[1]);
        let weight = p.mass.iter().sum::<f64>() * g;
        let (width, thickness) = (self.walls.width, self.scene.particles.thickness);
        let periodic = self.walls.periodic;
        let geometry = PileGeometry { x: &p.x, y: &p.y, r: &p.r, weight, width, thickness, periodic };
        PileMetrics::measure(&geometry, contacts)
    }
}
