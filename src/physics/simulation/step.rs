//! The step loop: one step (integrator, neighbour list, forces, integrator again) and the run
//! from the first sample to the last.

use super::protocol::Protocol;
use super::run_loop::{Resumed, RunLoop};
use crate::physics::config::SceneConfig;
use crate::physics::contact::ContactLaw;
use crate::physics::contact_sums::ContactSums;
use crate::physics::diagnostics::{ContactTotals, SettleDetector};
use crate::physics::energy::EnergyLedger;
use crate::physics::forces::{self, ContactParameters, TouchingPairs};
use crate::physics::integrator::{Integrator, Moved, StepContext};
use crate::physics::memory_order::{self, MemoryOrder, Numbering};
use crate::physics::monitor::FrameSchedule;
use crate::physics::neighbors::NeighborList;
use crate::physics::parallel::{Team, Threads};
use crate::physics::particles::Particles;
use crate::physics::pour::Inlet;
use crate::physics::record::{RunRecord, RunStatus, Snapshot};
use crate::physics::rolling;
use crate::physics::run_state::{Checkpoints, NoCheckpoints};
use crate::physics::walls::{BoxWalls, Periodic, Sides, Walled, wrap};
use crate::physics::warning::ValidityWarning;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

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
/// go through [`crate::physics::run_scene`] or `super::contact::ContactConfig::dispatch`.)
pub struct Simulation<L: ContactLaw> {
    pub(super) law: L,
    /// The scene, with its time step resolved.
    pub(super) scene: SceneConfig,
    pub(super) time_step_warning: Option<ValidityWarning>,
    /// The disks, in the simulation's own numbering.
    pub(super) particles: Particles,
    /// Which scene disk each place of `particles` holds, and when it changes.
    pub(super) numbering: Numbering,
    pub(super) memory_order: MemoryOrder,
    pub(super) walls: BoxWalls,
    pub(super) neighbors: NeighborList<L::State>,
    pub(super) disk_contacts: ContactParameters,
    pub(super) wall_contacts: ContactParameters,
    pub(super) touching: Box<TouchingPairs<L::State>>,
    /// The parallel path's tables (one per part) and contact rows (see `contact_sums`).
    pub(super) tables: Vec<Mutex<TouchingPairs<L::State>>>,
    pub(super) sums: ContactSums,
    /// The threads the steps' work is shared with.
    pub(super) team: Team,
    /// The integrator's per-chunk reports (scratch).
    pub(super) moved: Vec<Moved>,
    pub(super) integrator: Integrator,
    pub(super) rolling_resistance: bool,
    /// Scratch of the rolling resistance on several threads.
    pub(super) rolling_removed: rolling::Removed,
    pub(super) step: u64,
    pub(super) context: StepContext,
    pub(super) energy: EnergyLedger,
    pub(super) totals: ContactTotals,
    /// The run's stages and where it is in them.
    pub(super) protocol: Protocol,
    /// A pour's inserter (`None` for other placements).
    pub(super) inlet: Option<Inlet>,
}

impl<L: ContactLaw> Simulation<L> {
    /// Sets when the disks are numbered afresh (see [`memory_order`]): before the first step (the
    /// numbering they came in) and at neighbour-list builds. The default renumbers large scenes
    /// whose neighbours have drifted apart in memory.
    pub fn set_memory_order(&mut self, policy: MemoryOrder) {
        self.memory_order = policy;
    }

    /// Lets the simulation use `threads` (results do not depend on it: see `super::parallel`).
    pub fn set_threads(&mut self, threads: Threads) {
        self.team = Team::new(threads.used_for(self.particles.len()));
        // The one-thread table keeps springs from step to step, which steps on several threads
        // would not update.
        self.touching.write_back_springs(&mut self.neighbors.pairs);
        *self.touching = TouchingPairs::default();
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
    pub(super) fn move_disks(&mut self) -> (f64, f64, bool) {
        let moved = self.integrator.advance(&mut self.particles, &self.context, &self.team, &mut self.moved);
        if let Some(width) = self.walls.period() {
            wrap(&mut self.particles.x, width);
        }
        (moved.power, moved.damping_power, self.neighbors.note_step(moved.longest.root()))
    }

    /// Inserts the pour's disks due by now, and takes them into the integrator, the numbering and
    /// the neighbour list.
    fn pour(&mut self) {
        let (time, first) = (self.time(), self.particles.len());
        let Some(inlet) = &mut self.inlet else { return };
        if inlet.pour(&mut self.particles, time, self.step, self.scene.gravity) == 0 {
            return;
        }
        self.integrator.add_disks(&self.particles, &self.context, first);
        for _ in first..self.particles.len() {
            self.numbering.add_disk();
        }
        self.rebuild_neighbors();
    }

    /// Whether a pour has disks still to come.
    fn pouring(&self) -> bool {
        self.inlet.as_ref().is_some_and(|inlet| !inlet.done())
    }

    /// Builds the neighbour list afresh from the current positions.
    pub(super) fn rebuild_neighbors(&mut self) {
        self.touching.write_back_springs(&mut self.neighbors.pairs);
        self.neighbors.rebuild(&self.particles, &self.walls, &self.team);
        self.sums.invalidate();
    }

    /// Numbers the disks afresh where the memory order asks, judged by the current list.
    pub(super) fn follow_memory_order(&mut self) {
        let (far, pairs) = (self.neighbors.far_pairs(), self.neighbors.pairs.entries.len());
        if self.memory_order.due(self.particles.len(), far, pairs, &self.numbering) {
            self.renumber_disks();
            self.sums.invalidate();
        }
    }

    /// Numbers the disks afresh in strips at their current positions (see [`memory_order`]).
    pub(super) fn renumber_disks(&mut self) {
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

    /// Evaluates all forces and torques at the current state. With `SAMPLE`, also fills the
    /// contact sums and per-disk contact force magnitudes (on one thread; other steps share the
    /// work between the threads the simulation is given, with the same bits).
    pub(super) fn compute_forces<const SAMPLE: bool>(&mut self) {
        match self.walls.period() {
            Some(width) => self.compute_forces_across::<SAMPLE, _>(Periodic::new(width)),
            None => self.compute_forces_across::<SAMPLE, _>(Walled),
        }
    }

    /// [`Self::compute_forces`] with the disk pairs' x separations measured across `sides`.
    fn compute_forces_across<const SAMPLE: bool, X: Sides>(&mut self, sides: X) {
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
                (&mut self.neighbors.pairs, sides),
                walls,
                &s,
                &mut f,
                sums,
                &self.team,
            );
            return;
        }
        self.touching.contacts::<L, X, SAMPLE>(
            &self.law,
            [&self.disk_contacts, &self.wall_contacts],
            (&self.walls.walls, sides, &mut self.neighbors),
            &s,
            &mut f,
            &mut self.totals,
        );
    }

    /// Runs to the end, to settling, to divergence, or until the observer says stop; through the
    /// scene's stages first, if it has any (settling counts in the physical stage only).
    pub fn run(self, observer: &mut dyn FnMut(&Progress) -> Control) -> RunRecord {
        self.run_until(&AtomicBool::new(false), observer)
    }

    /// [`Self::run`] that also ends, as [`RunStatus::Interrupted`], within a step of `stop` being set
    /// (the step loop reads it after every step: samples may be far apart, steps never are).
    pub fn run_until(self, stop: &AtomicBool, observer: &mut dyn FnMut(&Progress) -> Control) -> RunRecord {
        self.run_resumable(None, stop, observer, &mut NoCheckpoints)
    }

    /// [`Self::run_until`] from the start, or from where `resumed` left off (see
    /// [`Self::resume`]), handing `checkpoints` the run's state at the samples it asks for and when
    /// the run is stopped early: a run resumed from a state ends with the bits of the run that saved
    /// it had it gone on.
    pub fn run_resumable(
        mut self,
        resumed: Option<Resumed>,
        stop: &AtomicBool,
        observer: &mut dyn FnMut(&Progress) -> Control,
        checkpoints: &mut dyn Checkpoints,
    ) -> RunRecord {
        let mut segment = self.segment();
        let fresh = resumed.is_none();
        let mut run = resumed.map_or_else(|| self.start(), |Resumed(run)| run);
        if fresh && segment.frames.due(self.step) {
            run.frames.push(self.snapshot());
        }
        let (status, message) = loop {
            if !run.stepping {
                if stop.load(Ordering::Relaxed) {
                    run.stepping = !segment.is_sample(self.step) && self.energy.power_finite();
                    checkpoints.save(self.state(&mut run));
                    break (RunStatus::Interrupted, Some(stopped_at(self.time())));
                }
                match self.take_sample(&mut run, &mut segment, observer) {
                    Ok(()) if checkpoints.due(self.step) => checkpoints.save(self.state(&mut run)),
                    Ok(()) => {}
                    Err(end) => {
                        if end.0 == RunStatus::Interrupted {
                            checkpoints.save(self.state(&mut run));
                        }
                        break end;
                    }
                }
            }
            self.step_to_next_sample(&mut segment, &mut run.settle, &mut run.frames, stop);
            run.stepping = false;
        };
        self.record(run, status, message)
    }

    /// Samples the state, watches it and tells the observer; `Err` with how the run ends where it
    /// ends here.
    fn take_sample(
        &mut self,
        run: &mut RunLoop,
        segment: &mut Segment,
        observer: &mut dyn FnMut(&Progress) -> Control,
    ) -> Result<(), (RunStatus, Option<String>)> {
        let s = self.sample();
        run.history.push(&s);
        if let Some(inlet) = &self.inlet {
            run.monitor.bring_in(inlet.energy_in());
        }
        run.monitor.observe(&s);
        let power_finite = self.energy.power_finite();
        if let Some(reason) = run.monitor.divergence(&s, &self.particles, power_finite, &self.scene.limits) {
            return Err((RunStatus::Diverged, Some(reason)));
        }
        // Nothing ends a stage or settles the pile before the pour's last disk.
        let pouring = self.pouring();
        while !pouring && self.protocol.stage_over(self.step, &s, self.particles.len(), || self.all_in_contact()) {
            self.switch_stage(segment, &mut run.settle);
        }
        let settled = run.settle.update(&s, self.protocol.in_physical_stage() && !pouring);
        let progress = Progress {
            step: self.step,
            time: s.time,
            duration: self.scene.run.duration,
            unbalanced_force_ratio: s.unbalanced_force_ratio,
            kinetic_energy: s.kinetic(),
        };
        run.stepping = true;
        if observer(&progress) == Control::Stop {
            return Err((RunStatus::Interrupted, Some(stopped_at(s.time))));
        }
        if settled && self.scene.run.stop_at_settle {
            return Err((RunStatus::Settled, None));
        }
        if self.step >= segment.last_step {
            return Err((if settled { RunStatus::Settled } else { RunStatus::NotSettled }, None));
        }
        Ok(())
    }

    /// The record of the run ended with `status` and `message`.
    fn record(self, run: RunLoop, status: RunStatus, message: Option<String>) -> RunRecord {
        let mut warnings: Vec<ValidityWarning> = self.time_step_warning.iter().cloned().collect();
        warnings.extend(run.stability.warnings.iter().cloned());
        warnings.extend(run.monitor.warnings(&self.scene.limits));
        let contacts = self.contacts();
        RunRecord {
            status,
            message,
            warnings,
            settle_time: run.settle.settle_time,
            steps: self.step,
            time_step: self.protocol.physical().dt,
            simulated_time: self.time(),
            energy_balance_error: run.monitor.energy_balance_error(),
            largest_overlap_ratio: run.monitor.largest_overlap_ratio(),
            pile: self.pile_metrics_of(&contacts),
            stability: run.stability,
            history: run.history,
            final_state: self.snapshot_with(&contacts),
            frames: run.frames,
            stage_ends: self.protocol.end_times(),
            pour: self.inlet.as_ref().map(|inlet| inlet.count(self.step, self.particles.len())),
        }
    }

    /// Steps to the next sample of the grid (or the run's last step), recording frames on the way.
    /// A stage whose time is up between samples ends on its step, with no sample there, so that a
    /// stage that changes nothing leaves the samples as they were. A non-finite power or `stop` ends
    /// early.
    fn step_to_next_sample(
        &mut self,
        segment: &mut Segment,
        settle: &mut SettleDetector,
        frames: &mut Vec<Snapshot>,
        stop: &AtomicBool,
    ) {
        loop {
            let sample = segment.next_sample(self.step);
            let next = sample.min(self.protocol.time_limit);
            while self.step < next {
                let frame_due = segment.frames.due(self.step + 1);
                self.advance(frame_due || self.step + 1 == sample);
                if self.inlet.as_ref().is_some_and(|inlet| inlet.due_by(self.time())) {
                    self.pour();
                }
                if frame_due {
                    frames.push(self.snapshot());
                }
                if !self.energy.power_finite() || stop.load(Ordering::Relaxed) {
                    return;
                }
            }
            if self.step == sample {
                return;
            }
            self.switch_stage(segment, settle);
        }
    }

    /// Ends the current stage and begins the next: the segment follows the next stage's step, and
    /// the quiet stretch of the settle criterion starts afresh where the settings change.
    fn switch_stage(&mut self, segment: &mut Segment, settle: &mut SettleDetector) {
        if self.next_stage() {
            settle.restart();
        }
        *segment = self.segment();
    }

    /// The step counts of the current time step, on the grid of the run's clock (see
    /// [`Protocol::clock`]): its sampling, its frames, the run's last step.
    fn segment(&self) -> Segment {
        let (dt, clock) = (self.context.dt, self.protocol.clock);
        let last_step = clock.0 + ((self.scene.run.duration - clock.1) / dt).round().max(1.0) as u64;
        Segment {
            first: clock.0,
            sample_every: ((self.scene.run.sample_interval / dt).round() as u64).max(1),
            frames: FrameSchedule::new(&self.scene, clock, dt, last_step),
            last_step,
        }
    }
}

/// The message of a run stopped at time `t` (s).
fn stopped_at(t: f64) -> String {
    format!("stopped by request at t = {t:.6} s")
}

/// The step counts of a stretch of a run with one time step.
struct Segment {
    /// The step the grid of samples starts at.
    first: u64,
    /// Steps between samples.
    sample_every: u64,
    /// The steps at which frames are recorded.
    frames: FrameSchedule,
    /// The step at which the run's duration is reached.
    last_step: u64,
}

impl Segment {
    /// Whether `step` is one of the samples (the grid's or the last step).
    fn is_sample(&self, step: u64) -> bool {
        step == self.last_step || (step - self.first).is_multiple_of(self.sample_every)
    }

    /// The first sample after `step` (the last step at the latest).
    fn next_sample(&self, step: u64) -> u64 {
        let past = (step - self.first) % self.sample_every;
        (step + self.sample_every - past).min(self.last_step)
    }
}
