//! The switch from one stage of a run to the next (see [`super::protocol`]).

use super::step::Simulation;
use crate::physics::contact::ContactLaw;
use crate::physics::integrator::Integrator;

impl<L: ContactLaw> Simulation<L> {
    /// Ends the current stage now and continues with the next one's settings. The state carries
    /// over as it is (positions, velocities, spins, springs, law states); the forces of this state
    /// are evaluated afresh when the contact materials change, as a restart from it would. Where
    /// friction falls, that cuts each spring beyond the new Coulomb limit back to it: the elastic
    /// energy lost leaves the stored energy with no work done, which the ledger counts as
    /// dissipated (see [`crate::physics::energy`]). A multistep scheme starts afresh when the step
    /// or the scheme changes (its history holds accelerations of the old step), and continues
    /// otherwise. Returns whether any setting changed.
    pub(super) fn next_stage(&mut self) -> bool {
        let time = self.time();
        let now = self.protocol.now();
        let before = (now.dt, now.scheme, now.materials, now.damping);
        let powers = (self.contact_power(), self.damping_power());
        let protocol = &mut self.protocol;
        protocol.begin_next(self.step, time);
        let next = protocol.now();
        let (dt, scheme, materials) = (next.dt, next.scheme, next.materials);
        let changed = before != (dt, scheme, materials, next.damping);
        if changed {
            // The powers jump here: the step that ended closes with those before.
            self.energy.close_before_jump(powers, before.0);
        }
        self.context.dt = dt;
        self.context.damping = next.damping;
        (self.disk_contacts.material, self.wall_contacts.material) = (materials.particle, materials.wall);
        self.disk_contacts.options.friction = materials.particle.friction;
        self.wall_contacts.options.friction = materials.wall.friction;
        if before.2 != materials {
            self.forces_afresh();
        }
        (self.disk_contacts.dt, self.wall_contacts.dt) = (dt, dt);
        if (before.0, before.1) != (dt, scheme) {
            self.integrator = Integrator::new(scheme);
        }
        changed
    }

    /// Evaluates the forces of the current state again, with the springs as they are: the contact
    /// stage's spring update is held still by a zero step (the Coulomb limit still applies).
    fn forces_afresh(&mut self) {
        let steps = (self.disk_contacts.dt, self.wall_contacts.dt);
        (self.disk_contacts.dt, self.wall_contacts.dt) = (0.0, 0.0);
        let p = &mut self.particles;
        for column in [&mut p.fx, &mut p.fy, &mut p.torque, &mut p.rolling] {
            column.fill(0.0);
        }
        self.compute_forces::<true>();
        // The next step's contact stage sums the rolling resistances anew.
        self.particles.rolling.fill(0.0);
        (self.disk_contacts.dt, self.wall_contacts.dt) = steps;
    }

    /// Whether every disk touches a disk or a wall (as of the last sampled step).
    pub(super) fn all_in_contact(&self) -> bool {
        self.particles.contact_force.iter().all(|f| *f > 0.0)
    }
}
