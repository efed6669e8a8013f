//! Running one planned run: the simulation on this thread, panics caught, wall and CPU time measured.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use super::checkpoints::RunCheckpoint;
use crate::output::terminal;
use crate::output::{RunResult, SummaryRow};
use crate::physics::RunStatus;
use crate::physics::run_state::{Checkpoints, NoCheckpoints};
use crate::physics::simulation::{Control, Progress};
use crate::physics::{RunError, Threads, run_scene_resumable};
use crate::study::PlannedRun;

/// Runs one simulation on `threads` (of the current pool); `observe` sees every progress sample;
/// `checkpoint`: where its state is saved as it runs and read back from (see [`RunCheckpoint`]).
/// Returns `None` when `stop` interrupted it (within a step of being set; an interrupted run is not
/// a result: it runs again on `--resume`, from its checkpoint if it has one). Errors and panics
/// become results with status `error` and the message.
pub fn run_one(
    run: &PlannedRun,
    stop: &AtomicBool,
    threads: Threads,
    observe: &mut dyn FnMut(&Progress),
    checkpoint: Option<RunCheckpoint>,
) -> Option<RunResult> {
    let started = Instant::now();
    let cpu_started = thread_cpu_time();
    let initial = run.initial.as_ref().map(|disks| disks.as_ref().clone());
    let mut observer = |p: &Progress| {
        observe(p);
        Control::Continue
    };
    let contacts = run.initial_contacts.as_deref().map(Vec::as_slice);
    let saved = checkpoint.as_ref().and_then(RunCheckpoint::saved);
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let mut checkpoint = checkpoint;
        let sink: &mut dyn Checkpoints = match checkpoint.as_mut() {
            Some(file) => file,
            None => &mut NoCheckpoints,
        };
        let start = (initial.clone(), contacts);
        match run_scene_resumable(&run.scene, start, threads, stop, &mut observer, (saved.as_ref(), &mut *sink)) {
            Err(RunError::Checkpoint(e)) => {
                let id = &run.id;
                terminal::err(format_args!("warning: run {id}: its checkpoint does not fit: {e}; it starts afresh\n"));
                run_scene_resumable(&run.scene, (initial, contacts), threads, stop, &mut observer, (None, sink))
            }
            other => other,
        }
    }));
    let (mut row, record) = match outcome {
        Ok(Ok(record)) if record.status == RunStatus::Interrupted => return None,
        Ok(Ok(record)) => (SummaryRow::finished(run.index, &run.id, &run.parameters, &record), Some(record)),
        Ok(Err(error)) => (SummaryRow::failed(run.index, &run.id, &run.parameters, &error.to_string()), None),
        Err(panic) => {
            let message = format!("the simulation panicked: {}", panic_text(panic.as_ref()));
            (SummaryRow::failed(run.index, &run.id, &run.parameters, &message), None)
        }
    };
    row.wall_time = started.elapsed().as_secs_f64();
    row.cpu_time = match (cpu_started, thread_cpu_time()) {
        (Some(start), Some(end)) => end.saturating_sub(start).as_secs_f64(),
        _ => f64::NAN,
    };
    Some(RunResult { row, scene: run.scene.clone(), record })
}

/// CPU time this thread has spent (s), from `clock_gettime(CLOCK_THREAD_CPUTIME_ID)` (through the
/// `cpu-time` crate: exact to the nanosecond, where Linux's `/proc/thread-self/schedstat` is only
/// brought up to date at scheduler ticks); `None` where the platform has no thread clock.
fn thread_cpu_time() -> Option<std::time::Duration> {
    cpu_time::ThreadTime::try_now().ok().map(|t| t.as_duration())
}

fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(no message)".to_string())
}
