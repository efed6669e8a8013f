//! A run's state saved between steps and read back into a simulation of the same scene, so that the
//! run continues with the bits it would have had (see [`crate::physics::run_state`]).

use super::run_loop::{Resumed, RunLoop};
use super::step::Simulation;
use crate::physics::contact::ContactLaw;
use crate::physics::diagnostics::SettleDetector;
use crate::physics::forces::TouchingPairs;
use crate::physics::monitor::Monitor;
use crate::physics::pour::Inlet;
use crate::physics::record::History;
use crate::physics::run_state::{Input, RunState, StateError, StateReason, Visit};

impl<L: ContactLaw> Simulation<L> {
    /// Every piece of a run's state, in file order, saved or loaded by `v`: one line per piece.
    fn pieces(&mut self, run: &mut RunLoop, v: &mut dyn Visit) -> Result<(), StateError> {
        v.piece("step", &mut self.step)?;
        v.piece("particles", &mut self.particles)?;
        v.piece("numbering", &mut self.numbering)?;
        v.piece("neighbors", &mut self.neighbors)?;
        v.piece("integrator", &mut self.integrator)?;
        v.piece("energy", &mut self.energy)?;
        v.piece("contact totals", &mut self.totals)?;
        v.piece("stages", &mut self.protocol)?;
        v.piece("monitor", &mut run.monitor)?;
        v.piece("settle", &mut run.settle)?;
        v.piece("history", &mut run.history)?;
        v.piece("frames", &mut run.frames)?;
        if let Some(inlet) = &mut self.inlet {
            v.piece("pour", inlet)?;
        }
        v.piece("stepping", &mut run.stepping)
    }

    /// The loop of a run starting now, from this state.
    pub(super) fn start(&self) -> RunLoop {
        let monitor =
            Monitor::new(&self.estimated_particles(), &self.walls, self.scene.gravity, self.energy.initial_elastic);
        RunLoop {
            stability: self.stability(),
            monitor,
            settle: SettleDetector::new(&self.scene.settle),
            history: History::default(),
            frames: Vec::new(),
            stepping: false,
        }
    }

    /// The state of this run now, `run` being its loop.
    pub(super) fn state(&mut self, run: &mut RunLoop) -> RunState {
        // The one-thread table may hold springs newer than the list's.
        self.touching.write_back_springs(&mut self.neighbors.pairs);
        let mut bytes = Vec::new();
        self.pieces(run, &mut bytes).expect("saving cannot fail");
        RunState { step: self.step, time: self.time(), bytes }
    }

    /// Reads `state` (saved by a run of this scene with these initial disks) into this simulation,
    /// which must not have stepped yet. An error leaves the simulation unusable: build it afresh.
    pub fn resume(&mut self, state: &RunState) -> Result<Resumed, StateError> {
        let mut run = self.start();
        let disks = self.particles.len();
        let mut input = Input::new(&state.bytes);
        self.pieces(&mut run, &mut input)?;
        if !input.finished() {
            return Err(input.error(StateReason::TrailingBytes));
        }
        let disks = disks + self.inlet.as_ref().map_or(0, Inlet::inserted);
        let p = &self.particles;
        let columns = [&p.x, &p.y, &p.vx, &p.vy, &p.omega, &p.angle, &p.r, &p.mass, &p.inv_mass, &p.inv_inertia];
        let wrong = |found: usize| StateError {
            piece: "particles",
            reason: StateReason::Invalid { found: found as u64, expected: disks as u64 },
        };
        let others = [&p.fx, &p.fy, &p.torque, &p.rolling, &p.contact_force];
        if let Some(column) = columns.iter().chain(&others).find(|c| c.len() != disks) {
            return Err(wrong(column.len()));
        }
        let stages = self.protocol.stages.len();
        if self.protocol.current >= stages {
            let found = self.protocol.current as u64;
            return Err(StateError {
                piece: "stages",
                reason: StateReason::Invalid { found, expected: stages as u64 },
            });
        }
        self.follow_stage();
        *self.touching = TouchingPairs::default();
        self.sums.invalidate();
        Ok(Resumed(run))
    }

    /// Sets the time step, damping and contact materials of the current stage (as the switches up
    /// to it did).
    fn follow_stage(&mut self) {
        let now = self.protocol.now();
        let (dt, materials) = (now.dt, now.materials);
        self.context.dt = dt;
        self.context.damping = now.damping;
        for (kind, material) in
            [(&mut self.disk_contacts, materials.particle), (&mut self.wall_contacts, materials.wall)]
        {
            kind.material = material;
            kind.options.friction = material.friction;
            kind.dt = dt;
        }
    }
}
