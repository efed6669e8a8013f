//! Checkpoints of the runs in progress: each run's state saved beside the results at least every
//! interval and when the sweep is stopped, read back by `--resume`, removed as soon as the run is
//! stored (see [`crate::output::checkpoint`]).

use std::convert::Infallible;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::output::table::ColumnData;
use crate::output::terminal;
use crate::output::{ResultSink, RunResult, Tables, checkpoint};
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

/// Removes the checkpoint of each run once it is stored, and at the end those of every run in the
/// tables (left by an earlier invocation): a sink handed the runs after the results file, so that
/// its commit follows the file's (a commit of the file that fails ends the sweep before this one
/// runs). Only checkpoint files go ([`checkpoint::remove`]).
pub struct RemoveStored {
    results: PathBuf,
    accepted: Vec<String>,
}

impl RemoveStored {
    /// The sink removing the checkpoints of the runs stored in the results file `results`.
    pub fn new(results: &Path) -> Self {
        Self { results: results.to_path_buf(), accepted: Vec::new() }
    }
}

impl ResultSink for RemoveStored {
    type Error = Infallible;

    fn accept(&mut self, run: &RunResult) -> Result<(), Infallible> {
        self.accepted.push(run.row.id.clone());
        Ok(())
    }

    fn commit(&mut self) -> Result<(), Infallible> {
        remove_finished(&self.results, self.accepted.drain(..));
        Ok(())
    }

    fn finish(&mut self, tables: &Tables) -> Result<(), Infallible> {
        if let Some(ColumnData::Text(ids)) = tables.summary.column("run_id").map(|c| &c.data) {
            remove_finished(&self.results, ids.iter().cloned());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::SummaryRow;
    use crate::physics::SceneConfig;

    fn stored(id: &str) -> RunResult {
        RunResult { row: SummaryRow::failed(0, id, &[], "stored"), scene: SceneConfig::default(), record: None }
    }

    #[test]
    fn a_checkpoint_goes_at_the_commit_after_its_run_is_stored_and_other_files_stay() {
        let dir = std::env::temp_dir().join(format!("demsweep_remove_stored_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let results = dir.join("study.h5");
        let state = RunState { step: 7, time: 0.5, bytes: vec![1, 2, 3] };
        for id in ["r0000", "r0001"] {
            checkpoint::write(&checkpoint::checkpoint_path(&results, id), id, &state).unwrap();
        }
        let foreign = checkpoint::checkpoint_path(&results, "r0002");
        std::fs::write(&foreign, "not written by demsweep").unwrap();
        let mut sink = RemoveStored::new(&results);
        sink.accept(&stored("r0000")).unwrap();
        assert!(checkpoint::checkpoint_path(&results, "r0000").exists(), "kept until the run is committed");
        sink.commit().unwrap();
        assert!(!checkpoint::checkpoint_path(&results, "r0000").exists(), "removed once stored");
        assert!(checkpoint::checkpoint_path(&results, "r0001").exists(), "a run in progress keeps its checkpoint");
        sink.accept(&stored("r0002")).unwrap();
        sink.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&foreign).unwrap(), "not written by demsweep");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
