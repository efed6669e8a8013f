//! What the user sees while a sweep runs: indicatif bars on a terminal (overall and one line per
//! worker), otherwise one plain line per finished run.

use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::warnings::WarningDigest;
use crate::output::SummaryRow;
use crate::physics::simulation::Progress;

/// How progress is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ProgressMode {
    /// Bars when stderr is a terminal, plain lines otherwise.
    #[default]
    Auto,
    /// Always bars (on stderr).
    Bars,
    /// One plain line per finished run (on stdout).
    Lines,
    /// Nothing.
    Quiet,
}

/// Shortest time between two updates of a worker's line.
const WORKER_UPDATE_INTERVAL: Duration = Duration::from_millis(100);

/// Progress display of one sweep.
pub struct ProgressView {
    mode: ProgressMode,
    overall: ProgressBar,
    workers: Vec<(ProgressBar, Mutex<Option<Instant>>)>,
    warnings: Mutex<WarningDigest>,
}

impl ProgressView {
    /// A display for `total` runs of which `done` are already finished, run by `jobs` workers.
    pub fn new(mode: ProgressMode, total: usize, done: usize, jobs: usize) -> Self {
        let mode = match mode {
            ProgressMode::Auto if std::io::stderr().is_terminal() => ProgressMode::Bars,
            ProgressMode::Auto => ProgressMode::Lines,
            other => other,
        };
        if mode != ProgressMode::Bars {
            return Self { mode, overall: ProgressBar::hidden(), workers: Vec::new(), warnings: Mutex::default() };
        }
        let multi = MultiProgress::with_draw_target(ProgressDrawTarget::stderr_with_hz(10));
        let overall = multi.add(ProgressBar::new(total as u64).with_position(done as u64));
        overall.set_style(
            ProgressStyle::with_template(
                "{bar:40.cyan/blue} {pos}/{len} runs  {per_sec}  elapsed {elapsed}  ETA {eta}",
            )
            .expect("valid template"),
        );
        let workers = (0..jobs)
            .map(|_| {
                let bar = multi.add(ProgressBar::new_spinner());
                bar.set_style(ProgressStyle::with_template("  {msg}").expect("valid template"));
                bar.set_message("idle");
                (bar, Mutex::new(None))
            })
            .collect();
        Self { mode, overall, workers, warnings: Mutex::default() }
    }

    /// A worker reports a sample of its running simulation (throttled to 10 updates a second).
    pub fn sample(&self, worker: usize, id: &str, p: &Progress) {
        let Some((bar, last)) = self.workers.get(worker) else { return };
        let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
        if last.is_some_and(|t| t.elapsed() < WORKER_UPDATE_INTERVAL) {
            return;
        }
        *last = Some(Instant::now());
        bar.set_message(format!(
            "{id}  t = {:.3} / {:.3} s  UBF {:.2e}  KE {:.3e} J",
            p.time, p.duration, p.unbalanced_force_ratio, p.kinetic_energy
        ));
    }

    /// A worker finished a run.
    pub fn finished(&self, worker: usize, row: &SummaryRow) {
        self.warnings.lock().unwrap_or_else(|e| e.into_inner()).add(&row.id, &row.warnings);
        self.overall.inc(1);
        if let Some((bar, _)) = self.workers.get(worker) {
            bar.set_message("idle");
        }
        if self.mode == ProgressMode::Lines {
            let settle = row.settle_time.map_or("-".to_string(), |t| format!("{t:.4} s"));
            let count = match row.warnings.len() {
                1 => "1 warning".to_string(),
                n => format!("{n} warnings"),
            };
            let mut line = format!("{}  {}  settle {settle}  wall {:.2} s  {count}", row.id, row.status, row.wall_time);
            if !row.message.is_empty() {
                line.push_str(&format!("  ({})", row.message));
            }
            crate::output::terminal::out(format_args!("{line}\n"));
        }
    }

    /// Clears the bars; returns the warnings of the runs finished, by kind.
    pub fn finish(&self) -> WarningDigest {
        for (bar, _) in &self.workers {
            bar.finish_and_clear();
        }
        self.overall.finish();
        self.warnings.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }
}
