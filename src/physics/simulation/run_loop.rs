//! What the step loop keeps besides the simulation, and a run read back from a saved state (see
//! `resume`).

use crate::physics::diagnostics::SettleDetector;
use crate::physics::monitor::Monitor;
use crate::physics::record::{History, Snapshot};
use crate::physics::stability::StabilityReport;

/// What the step loop keeps besides the simulation.
pub(super) struct RunLoop {
    /// The pre-run stability estimate (of the initial state).
    pub(super) stability: StabilityReport,
    pub(super) monitor: Monitor,
    pub(super) settle: SettleDetector,
    pub(super) history: History,
    pub(super) frames: Vec<Snapshot>,
    /// Whether the loop goes on with steps (the sample of this step was taken, or the step lies
    /// between samples) rather than with a sample.
    pub(super) stepping: bool,
}

/// A simulation's run read back from a [`RunState`](crate::physics::run_state::RunState), ready to go on with
/// [`super::Simulation::run_resumable`].
pub struct Resumed(pub(super) RunLoop);
