//! Checkpoints of the runs in progress: each run's state saved beside the results at least every
//! interval and when the sweep is stopped, read back by `--resume`, removed once the run is stored
//! (see [`crate::output::checkpoint`]).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::output::checkpoint;
use crate::output::terminal;
use crate::physics::run_state::{Checkpoints, RunState};

/// The checkpoints of a sweep: beside which results file, how often, whether old ones are read.
#[derive(Clone, Debug)]
pub struct Checkpointing {
    /// The results file.
    pub results: PathBuf,
    /// The interval between two checkpoints of a run (wall time).
    pub every: Duration,
    /// Whether a run continues from the checkpoint an earlier invocation left (`--resume`).
    pub resume: bool,
}

/// The checkpoint file of one run.
pub struct RunCheckpoint {
    path: PathBuf,
    identity: String,
    every: Duration,
    resume: bool,
    last: Instant,
    failed: bool,
}

impl RunCheckpoint {
    /// The checkpoint of run `id` (identity `identity`) of a sweep with `setting`.
    pub fn new(setting: &Checkpointing, id: &str, identity: &str) -> Self {
        let path = checkpoint::checkpoint_path(&setting.results, id);
        let (every, resume) = (setting.every, setting.resume);
        Self { path, identity: identity.to_string(), every, resume, last: Instant::now(), failed: false }
    }

    /// The state an earlier invocation saved, with `--resume`; a checkpoint that cannot be used is
    /// named in a warning and the run starts afresh.
    pub fn saved(&self) -> Option<RunState> {
        if !self.resume {
            return None;
        }
        match checkpoint::read(&self.path, &self.identity) {
            Ok(Some(state)) => {
                let (name, t) = (self.path.display(), state.time);
                terminal::err(format_args!("note: the run continues from {name} at t = {t:.6} s\n"));
                Some(state)
            }
            Ok(None) => None,
            Err(e) => {
                terminal::err(format_args!("warning: {e}; the run starts afresh\n"));
                None
            }
        }
    }
}

impl Checkpoints for RunCheckpoint {
    fn due(&mut self, _: u64) -> bool {
        self.last.elapsed() >= self.every
    }

    fn save(&mut self, state: RunState) {
        self.last = Instant::now();
        let written = checkpoint::write(&self.path, &self.identity, &state);
        if let Err(e) = written
            && !std::mem::replace(&mut self.failed, true)
        {
            terminal::err(format_args!("warning: {e}; checkpoints of this run fail\n"));
        }
    }
}

/// Removes the checkpoints of the runs `ids` (stored in the results file `results`).
pub fn remove_finished(results: &Path, ids: impl Iterator<Item = String>) {
    for id in ids {
        if let Err(e) = checkpoint::remove(&checkpoint::checkpoint_path(results, &id)) {
            terminal::err(format_args!("warning: {e}\n"));
        }
    }
}
