//! The one writer thread: receives finished runs, hands them to the result sinks of their group and
//! commits in batches; at the end computes each group's statistics and hands its sinks the tables.

use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::thread::{Scope, ScopedJoinHandle};
use std::time::{Duration, Instant};

use crate::output::{DynSink, RunResult, SinkError, SummaryRow, Tables};
use crate::stats::points;

/// When staged runs are committed: once `interval` has passed since the last commit or `max_runs`
/// runs are staged, whichever comes first. The interval bounds what `kill -9` can lose (a finished
/// run waits at most the interval plus one commit); `max_runs` bounds the memory staged runs take
/// (the HDF5 library holds a staged run in memory until its commit). The runs waiting for the
/// writer are bounded too (`BACKLOG_PER_WORKER`): workers wait while the writer catches up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CommitPolicy {
    /// Commit once this many runs are staged.
    pub max_runs: usize,
    /// Commit staged runs at least this often.
    pub interval: Duration,
}

impl Default for CommitPolicy {
    fn default() -> Self {
        Self { max_runs: 500, interval: Duration::from_secs(2) }
    }
}

impl CommitPolicy {
    /// Whether to commit now, given the staged count and the time since the last commit.
    fn due(&self, pending: usize, since_commit: Duration) -> bool {
        pending > 0 && (pending >= self.max_runs || since_commit >= self.interval)
    }
}

/// Finished runs that may wait for the writer, per worker thread: a worker that finishes a run
/// while this many wait blocks until the writer takes one.
pub const BACKLOG_PER_WORKER: usize = 2;

/// The sinks of one group of runs (a plan's, or one scene's of a batch) and the rows of the runs
/// they already hold (when resuming).
pub struct Sinks<'a> {
    /// Where every run of the group goes, in this order.
    pub sinks: Vec<DynSink<'a>>,
    /// Rows of the runs committed before this sweep.
    pub committed: Vec<SummaryRow>,
    /// Planned runs that share the identity of a run this sweep makes, by identity: each gets that
    /// run's row (the same results) under its own index, id and parameters.
    pub aliases: HashMap<String, Vec<SummaryRow>>,
}

impl<'a> Sinks<'a> {
    /// Sinks of runs that none of them holds yet.
    pub fn new(sinks: Vec<DynSink<'a>>) -> Self {
        Self { sinks, committed: Vec::new(), aliases: HashMap::new() }
    }

    /// Hands `run` to every sink and keeps its row, and one per alias.
    fn accept(&mut self, run: RunResult) -> Result<(), SinkError> {
        self.sinks.iter_mut().try_for_each(|sink| sink.accept(&run))?;
        for alias in self.aliases.get(&run.row.identity).into_iter().flatten() {
            let row = SummaryRow { parameters: alias.parameters.clone(), id: alias.id.clone(), ..run.row.clone() };
            self.committed.push(SummaryRow { index: alias.index, ..row });
        }
        self.committed.push(run.row);
        Ok(())
    }

    /// Computes the group's tables and hands them to every sink in order, closing it: a sink's
    /// error leaves those after it unfinished.
    fn finish(self) -> Result<Tables, SinkError> {
        let tables = points::tables(&self.committed);
        drop(self.committed); // the tables hold what the sinks need: memory peaks while they are written
        self.sinks.into_iter().try_for_each(|mut sink| sink.finish(&tables))?;
        Ok(tables)
    }
}

/// What the writer thread returns: each group's tables and the time it spent writing.
pub type Written = Result<(Vec<Tables>, Duration), SinkError>;

/// Starts the writer thread in `scope`, which takes runs, each with the position of its group in
/// `groups`; it ends when every sender is dropped, returning each group's tables and the time it
/// spent writing (staging, committing, finishing). On an error it sets `stop` (so the sweep ends)
/// and returns the error.
pub fn spawn<'scope, 'env>(
    scope: &'scope Scope<'scope, 'env>,
    groups: Vec<Sinks<'env>>,
    runs: Receiver<(usize, RunResult)>,
    policy: CommitPolicy,
    stop: Arc<AtomicBool>,
) -> ScopedJoinHandle<'scope, Written> {
    scope.spawn(move || {
        let outcome = write_all(groups, &runs, policy);
        if outcome.is_err() {
            stop.store(true, Ordering::SeqCst);
        }
        outcome
    })
}

fn write_all(mut groups: Vec<Sinks<'_>>, runs: &Receiver<(usize, RunResult)>, policy: CommitPolicy) -> Written {
    let commit = |groups: &mut Vec<Sinks<'_>>| {
        groups.iter_mut().flat_map(|group| &mut group.sinks).try_for_each(|sink| sink.commit())
    };
    let mut last_commit = Instant::now();
    let mut busy = Duration::ZERO;
    let mut pending = 0;
    loop {
        match runs.recv_timeout(Duration::from_millis(200)) {
            Ok((group, run)) => {
                let started = Instant::now();
                groups[group].accept(run)?;
                pending += 1;
                busy += started.elapsed();
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
        if policy.due(pending, last_commit.elapsed()) {
            let started = Instant::now();
            commit(&mut groups)?;
            pending = 0;
            busy += started.elapsed();
            last_commit = Instant::now();
        }
    }
    let started = Instant::now();
    commit(&mut groups)?;
    let tables = groups.into_iter().map(Sinks::finish).collect::<Result<_, _>>()?;
    Ok((tables, busy + started.elapsed()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commits_on_count_or_interval_whatever_a_commit_costs() {
        let p = CommitPolicy { max_runs: 10, interval: Duration::from_secs(2) };
        let ms = Duration::from_millis;
        assert!(!p.due(0, ms(5000)), "nothing staged");
        assert!(!p.due(3, ms(100)), "few runs, interval not reached");
        assert!(p.due(10, ms(100)), "batch full");
        assert!(p.due(3, ms(2000)), "interval reached");
    }
}
