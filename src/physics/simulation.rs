//! The step loop: forces, integration, sampling, monitoring and stopping.
//!
//! One step: the integrator advances the state with the forces of the current state, the neighbour
//! list is refreshed if some disk moved far enough, forces are evaluated at the new state (with
//! contact sums only on sampled steps), and the integrator finishes the step. Diagnostics,
//! divergence checks and the settle criterion run on sampled steps only.

use super::config::SceneConfig;
use super::contact::{ContactLaw, ContactOptions, RegisteredLaw};
use super::contact_list;
use super::contact_network::ContactNetwork;
use super::contact_record::PileContact;
use super::contact_sums::ContactSums;
use super::diagnostics::{self, ContactTotals, Sample, SettleDetector};
use super::energy::EnergyLedger;
use super::forces::{self, ContactParameters, TouchingPairs};
use super::integrator::{Integrator, Moved, StepContext};
use super::material::{ContactMaterial, Materials};
use super::memory_order::{self, MemoryOrder, Numbering};
use super::monitor::{FrameSchedule, Monitor};
use super::neighbors::NeighborList;
use super::parallel::{Team, Threads};
use super::particles::{InitialContact, InitialDisk, Particles};
use super::pile::{PileGeometry, PileMetrics};
use super::record::{History, RunRecord, RunStatus, Snapshot};
use super::rolling;
use super::stability::{self, StabilityReport};
use super::time_step::{self, with_time_step};
use super::vector;
use super::walls::BoxWalls;
use super::warning::ValidityWarning;
use std::borrow::Cow;
use std::sync::Mutex;

/// What a running simulation tells its caller at every sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    /// Steps taken.
    pub step: u64,
    /// Simulated time (s).
    pub time: f64,
    /// The run's full duration (s).
    pub duration: f64,
    /// Current unbalanced force ratio (NaN without contacts).
    pub unbalanced_force_ratio: f64,
    /// Current kinetic energy (J).
    pub kinetic_energy: f64,
}

/// The caller's answer to a [`Progress`] report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Control {
    /// Keep going.
    Continue,
    /// Stop now; the run ends as [`RunStatus::Interrupted`].
    Stop,
}

/// One simulation of a scene with contact law `L`: the scene's own law when built by
/// [`Simulation::new`], any law with [`Simulation::with_law`]. (To run a scene whichever its law,
/// go through [`crate::physics::run_scene`] or [`super::contact::ContactConfig::dispatch`].)
pub struct Simulation<L: ContactLaw> {
    law: L,
    /// The scene, with its time step resolved.
    scene: SceneConfig,
    time_step_warning: Option<ValidityWarning>,
    /// The disks, in the simulation's own numbering.
    particles: Particles,
    /// Which scene disk each place of `particles` holds, and when it changes.
    numbering: Numbering,
    memory_order: MemoryOrder,
    walls: BoxWalls,
    neighbors: NeighborList<L::State>,
    materials: Materials,
    disk_contacts: ContactParameters,
    wall_contacts: ContactParameters,
    touching: Box<TouchingPairs<L::State>>,
    /// The parallel path's tables (one per part) and contact rows (see `contact_sums`).
    tables: Vec<Mutex<TouchingPairs<L::State>>>,
    sums: ContactSums,
    /// The threads the steps' work is shared with.
    team: Team,
    /// The integrator's per-chunk reports (scratch).
    moved: Vec<Moved>,
    integrator: Integrator,
    rolling_resistance: bool,
    /// Scratch of the rolling resistance on several threads.
    rolling_removed: rolling::Removed,
    step: u64,
    context: StepContext,
    energy: EnergyLedger,
    totals: ContactTotals,
}

impl<L: RegisteredLaw> Simulation<L> {
    /// A simulation of `scene` from `disks` at time zero, with forces evaluated at the initial
    /// state. Panics unless `L` is the law `scene.contact.law` names.
    pub fn new(scene: &SceneConfig, disks: &[InitialDisk]) -> Self {
        let law = L::chosen_in(&scene.contact)
            .unwrap_or_else(|| panic!("scene.contact.law is {:?}, not the Simulation's law", scene.contact.law));
        Self::with_law(scene, disks, law.clone())
    }
}

impl<L: ContactLaw> Simulation<L> {
    /// A simulation of `scene` with contact law `law` (whatever `scene.contact.law` says: for laws
    /// outside the registry), at time zero with forces evaluated at the initial state.
    pub fn with_law(scene: &SceneConfig, disks: &[InitialDisk], law: L) -> Self {
        Self::with_history(scene, disks, &[], law)
    }

    /// [`Self::with_law`], the contacts starting from the history `contacts` (a restart: the
    /// tangential springs and law states a pile's contacts had) instead of from none. Contacts whose
    /// bodies are too far apart to touch are dropped. The history is set once, at the first
    /// neighbour-list build: the step loop does not know of it.
    pub fn with_history(scene: &SceneConfig, disks: &[InitialDisk], contacts: &[InitialContact], law: L) -> Self {
        let resolved = time_step::resolve(&law, scene, Some(disks));
        let scene = &with_time_step(scene, resolved.dt);
        let materials = Materials::from_scene(scene);
        let particles = Particles::new(disks, materials.density, scene.particles.thickness);
        let walls = BoxWalls::new(&scene.domain);
        let tangential = materials.particle.friction > 0.0 || materials.wall.friction > 0.0;
        let spinning = particles.omega.iter().any(|w| *w != 0.0);
        let rotation = materials.has_friction() || spinning;
        let kind = |m: &ContactMaterial| ContactParameters {
            material: *m,
            options: ContactOptions { allow_tension: scene.contact.allow_tension, tangential, friction: m.friction },
            rotation,
            dt: resolved.dt,
        };
        let skin = scene.neighbors.skin_ratio * particles.max_radius();
        let mut sim = Self {
            law,
            scene: scene.clone(),
            time_step_warning: resolved.warning,
            neighbors: NeighborList::new(scene.neighbors.broad_phase, skin),
            disk_contacts: kind(&materials.particle),
            wall_contacts: kind(&materials.wall),
            touching: Box::default(),
            tables: Vec::new(),
            sums: ContactSums::default(),
            team: Team::new(1),
            moved: Vec::new(),
            rolling_resistance: materials.particle.rolling_friction > 0.0 || materials.wall.rolling_friction > 0.0,
            rolling_removed: rolling::Removed::default(),
            integrator: Integrator::new(scene.integrator.scheme),
            particles,
            numbering: Numbering::default(),
            memory_order: MemoryOrder::default(),
            walls,
            materials,
            step: 0,
            context: StepContext { dt: resolved.dt, gravity: scene.gravity, rotation, damping: scene.damping },
            energy: EnergyLedger::default(),
            totals: ContactTotals::default(),
        };
        sim.rebuild_neighbors();
        sim.neighbors.seed_histories(contacts);
        sim.compute_forces::<true>();
        sim.energy.initial_elastic = sim.totals.elastic;
        // No step reads the rolling resistances at the start: cleared for the first contact stage.
        sim.particles.rolling.fill(0.0);
        sim
    }

    /// Sets when the disks are numbered afresh (see [`memory_order`]): before the first step (the
    /// numbering they came in) and at neighbour-list builds. The default renumbers large scenes
    /// whose neighbours have drifted apart in memory.
    pub fn set_memory_order(&mut self, policy: MemoryOrder) {
        self.memory_order = policy;
    }

    /// Which scene disk each place of [`Self::particles`] holds.
    pub fn numbering(&self) -> &Numbering {
        &self.numbering
    }

    /// Lets the simulation use `threads` (results do not depend on it: see [`super::parallel`]).
    pub fn set_threads(&mut self, threads: Threads) {
        self.team = Team::new(threads.used_for(self.particles.len()));
        // The one-thread table keeps springs from step to step, which steps on several threads
        // would not update.
        self.touching.write_back_springs(&mut self.neighbors.pairs);
        *self.touching = TouchingPairs::default();
    }

    /// The disks, in the simulation's own numbering ([`Self::numbering`]: the scene's unless a
    /// large scene was numbered afresh); snapshots give them in the scene's.
    pub fn particles(&self) -> &Particles {
        &self.particles
    }

    /// The disks in the scene's numbering.
    fn scene_particles(&self) -> Cow<'_, Particles> {
        let Some(places) = self.numbering.places() else { return Cow::Borrowed(&self.particles) };
        let mut p = self.particles.clone();
        p.renumber(&places, &mut Vec::new());
        Cow::Owned(p)
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
        self.step as f64 * self.context.dt
    }

    /// The pre-run stability estimate for this scene.
    pub fn stability(&self) -> StabilityReport {
        stability::assess(&self.law, &self.scene, &self.scene_particles(), &self.materials, &self.walls)
    }

    /// Advances one time step; `sample` requests contact sums for diagnostics at the new state.
    pub fn advance(&mut self, sample: bool) {
        if self.step == 0 {
            // The numbering the disks came in, checked with the policy set by now.
            self.follow_memory_order();
        }
        let (power, damping_power, stale) = self.move_disks();
        self.energy.record_step(power, damping_power, self.context.dt);
        if stale {
            self.rebuild_neighbors();
            self.follow_memory_order();
        }
        if sample {
            self.compute_forces::<true>();
        } else {
            self.compute_forces::<false>();
        }
        self.integrator.finish(&mut self.particles, &self.context, &self.team, &mut self.moved);
        if self.rolling_resistance {
            self.energy.remove(rolling::apply(
                &mut self.particles,
                self.context.dt,
                &self.team,
                &mut self.rolling_removed,
            ));
        }
        self.step += 1;
    }

    /// The integrator's update. Returns the power of the contact forces and of the numerical damping
    /// at the start of the step, and whether the neighbour list must be rebuilt.
    fn move_disks(&mut self) -> (f64, f64, bool) {
        let moved = self.integrator.advance(&mut self.particles, &self.context, &self.team, &mut self.moved);
        (moved.power, moved.damping_power, self.neighbors.note_step(moved.longest.root()))
    }

    /// Builds the neighbour list afresh from the current positions.
    fn rebuild_neighbors(&mut self) {
        self.touching.write_back_springs(&mut self.neighbors.pairs);
        self.neighbors.rebuild(&self.particles, &self.walls, &self.team);
        self.sums.invalidate();
    }

    /// Numbers the disks afresh where the memory order asks, judged by the current list.
    fn follow_memory_order(&mut self) {
        let (far, pairs) = (self.neighbors.far_pairs(), self.neighbors.pairs.entries.len());
        if self.memory_order.due(self.particles.len(), far, pairs, &self.numbering) {
            self.renumber_disks();
            self.sums.invalidate();
        }
    }

    /// Numbers the disks afresh in strips at their current positions (see [`memory_order`]).
    fn renumber_disks(&mut self) {
        self.touching.write_back_springs(&mut self.neighbors.pairs);
        let p = &mut self.particles;
        let order = memory_order::strip_order(&p.x, &p.y, 2.0 * p.max_radius());
        let mut scratch = Vec::new();
        p.renumber(&order, &mut scratch);
        self.integrator.renumber(&order, &mut scratch);
        self.neighbors.renumber_disks(&memory_order::inverse(&order));
        let left = self.neighbors.far_pairs() as f64 / self.neighbors.pairs.entries.len().max(1) as f64;
        self.numbering.renumber(&order, left);
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
    fn snapshot_with(&self, contacts: &[PileContact]) -> Snapshot {
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
    fn contact_power(&self) -> f64 {
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
    fn damping_power(&self) -> f64 {
        let d = &self.context.damping;
        if d.is_active() { d.power(&self.particles, self.context.gravity, self.context.rotation) } else { 0.0 }
    }

    /// The contacts at the current state with their forces, in the scene's numbering: those the
    /// next step's force stage would compute from the current springs (see [`contact_list`]).
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
    fn pile_metrics_of(&self, contacts: &[PileContact]) -> PileMetrics {
        let p = &*self.scene_particles();
        let g = self.scene.gravity[0].hypot(self.scene.gravity[1]);
        let geometry =
            PileGeometry { x: &p.x, y: &p.y, r: &p.r, weight: p.mass.iter().sum::<f64>() * g, width: self.walls.width };
        PileMetrics::measure(&geometry, contacts)
    }

    /// Evaluates all forces and torques at the current state. With `SAMPLE`, also fills the
    /// contact sums and per-disk contact force magnitudes (on one thread; other steps share the
    /// work between the threads the simulation is given, with the same bits).
    fn compute_forces<const SAMPLE: bool>(&mut self) {
        // Forces and torques were cleared by the integrator, which read them last, the rolling
        // resistances by `rolling::apply` (or at the start).
        let p = &mut self.particles;
        if SAMPLE {
            p.contact_force.fill(0.0);
            self.totals = ContactTotals::default();
        }
        let (s, mut f) = p.split();
        if !SAMPLE && self.team.parts() > 1 {
            self.touching.write_back_springs(&mut self.neighbors.pairs);
            let kinds = [&self.disk_contacts, &self.wall_contacts];
            let walls = (&self.walls.walls[..], &mut self.neighbors.walls);
            let (tables, sums) = (&mut self.tables, &mut self.sums);
            forces::contacts_in_parts(
                tables,
                &self.law,
                kinds,
                &mut self.neighbors.pairs,
                walls,
                &s,
                &mut f,
                sums,
                &self.team,
            );
            return;
        }
        self.touching.contacts::<L, SAMPLE>(
            &self.law,
            [&self.disk_contacts, &self.wall_contacts],
            (&self.walls.walls, &mut self.neighbors),
            &s,
            &mut f,
            &mut self.totals,
        );
    }

    /// Runs to the end, to settling, to divergence, or until the observer says stop.
    pub fn run(mut self, observer: &mut dyn FnMut(&Progress) -> Control) -> RunRecord {
        let stability = self.stability();
        let mut warnings: Vec<ValidityWarning> = self.time_step_warning.iter().cloned().collect();
        warnings.extend(stability.warnings.iter().cloned());
        let total_steps = self.scene.total_steps(self.context.dt);
        let sample_every = ((self.scene.run.sample_interval / self.context.dt).round() as u64).max(1);
        let mut frames = FrameSchedule::new(&self.scene, self.context.dt, total_steps);
        let mut monitor =
            Monitor::new(&self.scene_particles(), &self.walls, self.scene.gravity, self.energy.initial_elastic);
        let mut settle = SettleDetector::new(&self.scene.settle);
        let mut history = History::default();
        let mut recorded_frames = Vec::new();
        let (status, message) = loop {
            let s = self.sample();
            if frames.due(self.step) {
                recorded_frames.push(self.snapshot());
            }
            history.push(&s);
            monitor.observe(&s);
            let power_finite = self.energy.power_finite();
            if let Some(reason) = monitor.divergence(&s, &self.particles, power_finite, &self.scene.limits) {
                break (RunStatus::Diverged, Some(reason));
            }
            let settled = settle.update(&s);
            let progress = Progress {
                step: self.step,
                time: s.time,
                duration: self.scene.run.duration,
                unbalanced_force_ratio: s.unbalanced_force_ratio,
                kinetic_energy: s.kinetic(),
            };
            if observer(&progress) == Control::Stop {
                break (RunStatus::Interrupted, Some(format!("stopped by request at t = {:.6} s", s.time)));
            }
            if settled && self.scene.run.stop_at_settle {
                break (RunStatus::Settled, None);
            }
            if self.step >= total_steps {
                break (if settled { RunStatus::Settled } else { RunStatus::NotSettled }, None);
            }
            // Step to the next sample, recording frames on the way; a non-finite power ends early.
            let next = (self.step + sample_every).min(total_steps);
            while self.step < next {
                let frame_due = self.step + 1 < next && frames.due(self.step + 1);
                self.advance(frame_due || self.step + 1 == next);
                if frame_due {
                    recorded_frames.push(self.snapshot());
                }
                if !self.energy.power_finite() {
                    break;
                }
            }
        };
        warnings.extend(monitor.warnings(&self.scene.limits));
        let contacts = self.contacts();
        RunRecord {
            status,
            message,
            warnings,
            settle_time: settle.settle_time,
            steps: self.step,
            time_step: self.context.dt,
            simulated_time: self.time(),
            energy_balance_error: monitor.energy_balance_error(),
            largest_overlap_ratio: monitor.largest_overlap_ratio(),
            pile: self.pile_metrics_of(&contacts),
            stability,
            history,
            final_state: self.snapshot_with(&contacts),
            frames: recorded_frames,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::contact::{ContactForce, ContactLawKind, LawVisitor};
    use crate::physics::contact_record::Partner;

    /// Settles a small frictional pile with law `L`, then compares at that state the one-contact
    /// evaluation with the block stages: per-disk force, torque and force-magnitude sums, each
    /// added up in the block stages' order, to the bit.
    fn one_contact_path_matches_block_path<L: RegisteredLaw>(scene: &SceneConfig) {
        let disks = crate::physics::placement::generate(scene).expect("placement");
        let mut sim = Simulation::<L>::new(scene, &disks);
        let steps = (0.4 / sim.time_step()).round() as u64;
        for _ in 0..steps {
            sim.advance(false);
        }
        let contacts = sim.contacts();
        let n = sim.particles.len();
        let (mut fx, mut fy, mut torque, mut magnitude) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let r = sim.particles.r.clone();
        for c in &contacts {
            let force =
                ContactForce { normal: c.normal_force, tangential: c.tangential_force, tangential_stiffness: 0.0 };
            let [x, y] = force.on_first_body(c.normal[0], c.normal[1]);
            let i = c.disk;
            (fx[i], fy[i], torque[i], magnitude[i]) =
                (fx[i] + x, fy[i] + y, torque[i] + force.tangential * r[i], magnitude[i] + force.magnitude());
            if let Partner::Disk(j) = c.partner {
                (fx[j], fy[j], torque[j], magnitude[j]) =
                    (fx[j] - x, fy[j] - y, torque[j] + force.tangential * r[j], magnitude[j] + force.magnitude());
            }
        }
        let p = &mut sim.particles;
        for column in [&mut p.fx, &mut p.fy, &mut p.torque] {
            column.fill(0.0);
        }
        sim.compute_forces::<true>();
        let p = &sim.particles;
        let sliding = contacts.iter().filter(|c| c.is_sliding()).count();
        assert!(contacts.len() > n && sliding > 0, "{} contacts, {sliding} sliding", contacts.len());
        assert_eq!(sim.totals.contacts as usize, contacts.len());
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&p.fx), bits(&fx), "fx");
        assert_eq!(bits(&p.fy), bits(&fy), "fy");
        assert_eq!(bits(&p.torque), bits(&torque), "torque");
        assert_eq!(bits(&p.contact_force), bits(&magnitude), "force magnitudes");
    }

    #[test]
    fn rolling_resistances_are_cleared_from_the_start_and_by_their_last_reader() {
        // Three spinning disks pressed into the floor and into each other at time zero, so that
        // the first force evaluation (at construction) already sums rolling resistances.
        let mut scene = SceneConfig::default();
        scene.material.rolling_friction = 0.1;
        let r = 0.01;
        let disk =
            |k: u32| InitialDisk { x: 0.1 + 1.9 * r * f64::from(k), y: 0.98 * r, r, omega: 5.0, ..Default::default() };
        let disks: Vec<InitialDisk> = (0..3).map(disk).collect();
        let mut sim = Simulation::<crate::physics::contact::HertzMindlin>::new(&scene, &disks);
        assert!(sim.totals.contacts >= 5, "{} contacts at the start", sim.totals.contacts);
        let cleared = |sim: &Simulation<_>| sim.particles.rolling.iter().all(|&m| m == 0.0);
        assert!(cleared(&sim), "the next contact stage starts from zero");
        for _ in 0..20 {
            sim.advance(false);
            assert!(cleared(&sim), "cleared by the pass that applied them");
        }
    }

    #[test]
    fn one_contact_evaluation_gives_the_block_stages_forces_to_the_bit_for_every_law() {
        struct Check<'a>(&'a SceneConfig);
        impl LawVisitor for Check<'_> {
            type Output = ();
            fn visit<L: RegisteredLaw>(self, _: &L) {
                one_contact_path_matches_block_path::<L>(self.0);
            }
        }
        let mut scene = SceneConfig::default();
        scene.particles.count = 120;
        scene.domain.width = 0.2;
        scene.material.restitution = Some(0.5);
        scene.material.friction = 0.5;
        scene.integrator.contact_time_fraction = Some(0.05);
        for &law in ContactLawKind::ALL {
            scene.contact.law = law;
            scene.contact.dispatch(Check(&scene));
        }
    }
}
