//! The one writer thread: receives finished runs, hands them to the result sinks and commits in
//! batches; at the end computes the statistics and hands every sink the tables.

use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};

use crate::output::{OutputError, ResultSink, RunResult, SummaryRow, Tables};
use crate::stats::points;

/// When staged runs are committed: once `interval` has passed since the last commit or `max_runs`
/// runs are staged, whichever comes first. The interval bounds what `kill -9` can lose (a finished
/// run waits at most the interval plus one commit); `max_runs` bounds the memory staged runs take
/// (the HDF5 library holds a staged run in memory until its commit). The runs waiting for the
/// writer are bounded too ([`BACKLOG_PER_WORKER`]): workers wait while the writer catches up.
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

/// The sinks of a sweep and the rows of the runs they already hold (when resuming).
pub struct Sinks {
    /// Where every run goes (the results file first).
    pub sinks: Vec<Box<dyn ResultSink>>,
    /// Rows of the runs committed before this sweep.
    pub committed: Vec<SummaryRow>,
    /// Planned runs that share the identity of a run this sweep makes, by identity: each gets that
    /// run's row (the same results) under its own index, id and parameters.
    pub aliases: HashMap<String, Vec<SummaryRow>>,
}

/// Starts the writer thread; it ends when every sender is dropped, returning the tables and the
/// time it spent writing (staging, committing, finishing). On an error it sets `stop` (so the sweep
/// ends) and returns the error.
pub fn spawn(
    sinks: Sinks,
    runs: Receiver<RunResult>,
    policy: CommitPolicy,
    stop: Arc<AtomicBool>,
) -> JoinHandle<Result<(Tables, Duration), OutputError>> {
    thread::spawn(move || {
        let outcome = write_all(sinks, &runs, policy);
        if outcome.is_err() {
            stop.store(true, Ordering::SeqCst);
        }
        outcome
    })
}

fn write_all(
    sinks: Sinks,
    runs: &Receiver<RunResult>,
    policy: CommitPolicy,
) -> Result<(Tables, Duration), OutputError> {
    let Sinks { mut sinks, committed: mut rows, aliases } = sinks;
    let mut last_commit = Instant::now();
    let mut busy = Duration::ZERO;
    let mut pending = 0;
    loop {
        match runs.recv_timeout(Duration::from_millis(200)) {
            Ok(run) => {
                let started = Instant::now();
                sinks.iter_mut().try_for_each(|sink| sink.accept(&run))?;
                for alias in aliases.get(&run.row.identity).into_iter().flatten() {
                    rows.push(SummaryRow {
                        parameters: alias.parameters.clone(),
                        id: alias.id.clone(),
                        ..run.row.clone()
                    });
                    rows.last_mut().expect("pushed").index = alias.index;
                }
                rows.push(run.row);
                pending += 1;
                busy += started.elapsed();
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
        if policy.due(pending, last_commit.elapsed()) {
            let started = Instant::now();
            sinks.iter_mut().try_for_each(|sink| sink.commit())?;
            pending = 0;
            busy += started.elapsed();
            last_commit = Instant::now();
        }
    }
    let started = Instant::now();
    sinks.iter_mut().try_for_each(|sink| sink.commit())?;
    let tables = points::tables(&rows);
    drop(rows); // the tables hold what the sinks need: memory peaks while they are written
    sinks.into_iter().try_for_each(|sink| sink.finish(&tables))?;
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
