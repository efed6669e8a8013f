//! The one writer thread: receives finished runs, hands them to the result sinks and commits in
//! batches; at the end computes the statistics and hands every sink the tables.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};

use crate::output::{OutputError, ResultSink, RunResult, SummaryRow, Tables};
use crate::stats::points;

/// When staged runs are committed: after `max_runs` runs or `interval`, whichever comes first, but
/// never so often that committing takes more than `max_overhead` of the time (a commit's cost grows
/// with the file, so late in a large sweep commits space out).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CommitPolicy {
    /// Commit once this many runs are staged.
    pub max_runs: usize,
    /// Commit staged runs at least this often (unless that would exceed `max_overhead`).
    pub interval: Duration,
    /// Largest fraction of the time spent committing.
    pub max_overhead: f64,
}

impl Default for CommitPolicy {
    fn default() -> Self {
        Self { max_runs: 100, interval: Duration::from_secs(2), max_overhead: 0.03 }
    }
}

impl CommitPolicy {
    /// Whether to commit now, given the staged count, time since the last commit and its cost.
    fn due(&self, pending: usize, since_commit: Duration, last_cost: Duration) -> bool {
        pending > 0
            && (pending >= self.max_runs || since_commit >= self.interval)
            && since_commit.as_secs_f64() * self.max_overhead >= last_cost.as_secs_f64()
    }
}

/// The sinks of a sweep and the rows of the runs they already hold (when resuming).
pub struct Sinks {
    /// Where every run goes (the results file first).
    pub sinks: Vec<Box<dyn ResultSink>>,
    /// Rows of the runs committed before this sweep.
    pub committed: Vec<SummaryRow>,
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
    let Sinks { mut sinks, committed: mut rows } = sinks;
    let mut last_commit = Instant::now();
    let mut last_cost = Duration::ZERO;
    let mut busy = Duration::ZERO;
    let mut pending = 0;
    loop {
        match runs.recv_timeout(Duration::from_millis(200)) {
            Ok(run) => {
                let started = Instant::now();
                sinks.iter_mut().try_for_each(|sink| sink.accept(&run))?;
                rows.push(run.row);
                pending += 1;
                busy += started.elapsed();
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
        if policy.due(pending, last_commit.elapsed(), last_cost) {
            let started = Instant::now();
            sinks.iter_mut().try_for_each(|sink| sink.commit())?;
            pending = 0;
            last_cost = started.elapsed();
            busy += last_cost;
            last_commit = Instant::now();
        }
    }
    let started = Instant::now();
    sinks.iter_mut().try_for_each(|sink| sink.commit())?;
    let tables = points::tables(&rows);
    sinks.into_iter().try_for_each(|sink| sink.finish(&tables))?;
    Ok((tables, busy + started.elapsed()))
}

#[cfg(test)]
mod tests {
    use std::sync::Mutex;
    use std::sync::mpsc;

    use super::*;
    use crate::physics::SceneConfig;
    use crate::study::ParamValue;

    /// What a sink was handed, in order.
    #[derive(Clone, Debug, Default, PartialEq)]
    struct Seen {
        accepted: Vec<String>,
        commits: usize,
        finished: Option<Tables>,
    }

    /// A sink that records what it is handed (as an export format's sink would use it).
    struct Recorder(Arc<Mutex<Seen>>);

    impl ResultSink for Recorder {
        fn accept(&mut self, run: &RunResult) -> Result<(), OutputError> {
            self.0.lock().unwrap().accepted.push(run.row.id.clone());
            Ok(())
        }
        fn commit(&mut self) -> Result<(), OutputError> {
            self.0.lock().unwrap().commits += 1;
            Ok(())
        }
        fn finish(self: Box<Self>, tables: &Tables) -> Result<(), OutputError> {
            self.0.lock().unwrap().finished = Some(tables.clone());
            Ok(())
        }
    }

    fn row(index: usize, restitution: f64) -> SummaryRow {
        let parameters = [("material.restitution".to_string(), ParamValue::Float(restitution))];
        SummaryRow::failed(index, &format!("r{index:04}"), &parameters, "no scene")
    }

    #[test]
    fn every_sink_gets_every_run_and_the_tables_of_all_rows() {
        let seen: Vec<Arc<Mutex<Seen>>> = (0..2).map(|_| Arc::default()).collect();
        let sinks: Vec<Box<dyn ResultSink>> =
            seen.iter().map(|s| Box::new(Recorder(s.clone())) as Box<dyn ResultSink>).collect();
        let earlier = vec![row(0, 0.3)];
        let (sender, receiver) = mpsc::channel();
        for (index, restitution) in [(2, 0.5), (1, 0.3)] {
            let run = RunResult { row: row(index, restitution), scene: SceneConfig::default(), record: None };
            sender.send(run).unwrap();
        }
        drop(sender);
        let policy = CommitPolicy { max_runs: 1, interval: Duration::ZERO, max_overhead: 1.0 };
        let (tables, _) = write_all(Sinks { sinks, committed: earlier }, &receiver, policy).unwrap();
        assert_eq!(tables, points::tables(&[row(0, 0.3), row(1, 0.3), row(2, 0.5)]));
        assert_eq!(tables.summary.len(), 3, "earlier rows and new ones, sorted by index");
        assert_eq!(tables.points.len(), 2, "two restitutions");
        for seen in &seen {
            let seen = seen.lock().unwrap();
            assert_eq!(seen.accepted, ["r0002", "r0001"]);
            assert!(seen.commits >= 2, "one commit per run with max_runs = 1, then the last");
            assert_eq!(seen.finished.as_ref(), Some(&tables));
        }
    }

    #[test]
    fn commits_on_count_or_interval_within_the_overhead_budget() {
        let p = CommitPolicy { max_runs: 10, interval: Duration::from_secs(2), max_overhead: 0.05 };
        let ms = Duration::from_millis;
        assert!(!p.due(0, ms(5000), ms(1)), "nothing staged");
        assert!(!p.due(3, ms(100), ms(1)), "few runs, interval not reached");
        assert!(p.due(10, ms(100), ms(1)), "batch full");
        assert!(p.due(3, ms(2000), ms(1)), "interval reached");
        assert!(!p.due(10, ms(2000), ms(500)), "a 0.5 s commit waits 10 s");
        assert!(p.due(10, ms(10_000), ms(500)));
    }
}
