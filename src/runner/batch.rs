//! Runs without a results file: batches of runs, each batch to the sinks its caller chooses (the
//! Python module's in-memory results, one per scene of a batch).

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use super::writer_thread::Sinks;
use super::{CommitPolicy, ProgressMode, ProgressView, RunnerError, Todo, pool_threads, sweep, worker_count};
use crate::output::DynSink;
use crate::study::{PlannedRun, RunIdentity};

/// Runs that go to the same sinks.
pub struct Batch<'a> {
    /// The runs.
    pub runs: Vec<&'a PlannedRun>,
    /// Where each of them goes; at the end each sink receives the tables of the batch's runs.
    pub sinks: Vec<DynSink<'a>>,
}

/// Runs the runs of every batch together on `requested` worker threads (0 = one per core), the
/// costliest first; each batch's sinks receive its runs and then its tables. A run `stop`
/// interrupts goes to no sink. Results do not depend on `requested`, but for their wall and CPU
/// times.
pub fn run_batches(batches: Vec<Batch<'_>>, requested: usize, stop: &Arc<AtomicBool>) -> Result<(), RunnerError> {
    let (runs, sinks): (Vec<_>, Vec<_>) = batches.into_iter().map(|b| (b.runs, b.sinks)).unzip();
    let identities: Vec<Vec<String>> =
        runs.iter().map(|runs| runs.iter().map(|run| RunIdentity::of(run).to_string()).collect()).collect();
    let mut todo: Vec<Todo> = (runs.iter().zip(&identities).enumerate())
        .flat_map(|(group, (runs, ids))| runs.iter().zip(ids).map(move |(&run, id)| (run, id.as_str(), group)))
        .collect();
    todo.sort_by(|(a, ..), (b, ..)| b.estimated_cost.total_cmp(&a.estimated_cost));
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let (jobs, _) = worker_count(requested, todo.len(), cores);
    let view = ProgressView::new(ProgressMode::Quiet, todo.len(), 0, jobs);
    let groups = sinks.into_iter().map(Sinks::new).collect();
    sweep(&todo, groups, (jobs, pool_threads(requested, cores)), &view, (CommitPolicy::default(), None), stop).map(drop)
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::output::{MemorySink, SummaryTable, dyn_sink};

    #[test]
    fn each_batch_gets_its_own_runs_whatever_the_workers() {
        let scene = "particles.count = 12\nparticles.radius = 0.005\ndomain.width = 0.06\ndomain.height = 0.1\n\
                     material.youngs_modulus = 5e10\nintegrator.time_step = 7e-6\nrun.duration = 0.4\n";
        let plan = |seeds: Vec<i64>| {
            let table = crate::study::parse_table(Path::new("s"), scene.into()).unwrap();
            let text = crate::study::scene_study(table, &crate::study::Seeds::List(seeds));
            crate::study::load_text(Path::new("s"), text).unwrap()
        };
        let (three, one) = (plan(vec![5, 1, 3]), plan(vec![1]));
        let summaries = |jobs: usize| {
            let mut sinks = [MemorySink::default(), MemorySink::default()];
            let batches = [&three, &one]
                .iter()
                .zip(&mut sinks)
                .map(|(plan, sink)| Batch { runs: plan.runs.iter().collect(), sinks: vec![dyn_sink(sink)] })
                .collect();
            run_batches(batches, jobs, &Arc::new(AtomicBool::new(false))).unwrap();
            sinks.map(|sink| sink.into_summary().expect("finished").without_timing())
        };
        let [first, second] = summaries(1);
        let two = summaries(2);
        assert_eq!(format!("{two:?}"), format!("{:?}", [&first, &second]), "the same on two workers, NaN for NaN");
        assert_eq!((first.len(), second.len()), (3, 1));
        let seed = |table: &SummaryTable, i: usize| table.parameters()[0].data.param(i);
        assert_eq!(seed(&second, 0), seed(&first, 1), "each batch's runs, in its order");
        let kinetic = |table: &SummaryTable, i: usize| table.column("final_kinetic").unwrap().data.number(i);
        assert_eq!(kinetic(&second, 0), kinetic(&first, 1), "the same seed, the same pile");
        assert_ne!(kinetic(&first, 0), kinetic(&first, 1), "different seeds, different piles");
    }
}
