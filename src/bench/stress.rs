//! Stress scenarios: each ends with a clear status and message (or a clear error), never a panic,
//! a hang or silent garbage, and each has the status it is expected to end with.

use std::path::PathBuf;

use super::skipping::friction_rows;
use super::{BenchError, CsvRow, markdown_table, placed_disks, timed, write_csv, write_file};
use crate::physics::config::{PlacementKind, SceneConfig};
use crate::physics::contact::HertzMindlin;
use crate::physics::particles::InitialDisk;
use crate::physics::quantity;
use crate::physics::simulation::Simulation;
use crate::physics::{RunRecord, RunStatus};

/// How large the scenarios are.
#[derive(Clone, Debug)]
pub struct StressOptions {
    /// Disks in the deposition scenarios (the paper's scenes have 300).
    pub count: usize,
    /// Longest simulated time of a deposition scenario (s).
    pub duration: f64,
    /// Disks of the large scenario.
    pub large_count: usize,
    /// Time steps timed in the large scenario.
    pub large_steps: u64,
    /// Where `stress.csv` and `stress.md` go.
    pub out_dir: PathBuf,
}

impl Default for StressOptions {
    fn default() -> Self {
        Self {
            count: 300,
            duration: 1.5,
            large_count: 100_000,
            large_steps: 200,
            out_dir: PathBuf::from(super::LATEST_DIR),
        }
    }
}

/// How a scenario ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// The run ended with this status.
    Run(RunStatus),
    /// The scene was rejected before running, with a message.
    Error,
    /// The engine panicked (never expected).
    Panic,
}

impl Outcome {
    /// The snake_case name used in files.
    pub fn as_str(self) -> &'static str {
        match self {
            Outcome::Run(status) => status.as_str(),
            Outcome::Error => "error",
            Outcome::Panic => "panic",
        }
    }
}

/// One scenario's result.
#[derive(Clone, Debug, PartialEq)]
pub struct StressRow {
    /// Scenario name.
    pub scenario: &'static str,
    /// The status it should end with.
    pub expected: Outcome,
    /// How it ended.
    pub outcome: Outcome,
    /// The run's message or the error.
    pub message: String,
    /// Pre-run and run warnings.
    pub warnings: Vec<String>,
    /// Wall-clock time (s).
    pub run_time: f64,
    /// What else was measured, in words.
    pub note: String,
}

impl StressRow {
    /// Whether it ended as expected.
    pub fn as_expected(&self) -> bool {
        self.outcome == self.expected
    }
}

impl CsvRow for StressRow {
    const COLUMNS: &'static [(&'static str, &'static str)] = &[
        ("scenario", ""),
        ("expected", ""),
        ("outcome", ""),
        ("as_expected", ""),
        ("run_time", "s"),
        ("message", ""),
        ("warnings", ""),
        ("note", ""),
    ];
    fn values(&self) -> Vec<String> {
        vec![
            self.scenario.into(),
            self.expected.as_str().into(),
            self.outcome.as_str().into(),
            self.as_expected().to_string(),
            format!("{:.3}", self.run_time),
            self.message.clone(),
            self.warnings.join(" | "),
            self.note.clone(),
        ]
    }
}

/// Runs every scenario; writes `stress.csv` and `stress.md`.
pub fn stress(options: &StressOptions) -> Result<Vec<StressRow>, BenchError> {
    let scenarios: [(&'static str, Outcome, Scenario); 10] = [
        ("paper_table1", Outcome::Run(RunStatus::Diverged), paper_table1),
        ("very_stiff_large_dt", Outcome::Run(RunStatus::Diverged), very_stiff_large_dt),
        ("impact_50_m_per_s", Outcome::Run(RunStatus::Diverged), impact_50),
        ("dense_lattice_0.6", Outcome::Run(RunStatus::Settled), dense_lattice),
        ("one_disk", Outcome::Run(RunStatus::Settled), one_disk),
        ("zero_disks", Outcome::Error, zero_disks),
        ("beta_50", Outcome::Run(RunStatus::Diverged), beta_50),
        ("beta_50_frictionless_safe_dt", Outcome::Run(RunStatus::Settled), beta_50_frictionless_safe_dt),
        ("frictionless", Outcome::Run(RunStatus::NotSettled), frictionless),
        ("large_100000", Outcome::Run(RunStatus::NotSettled), large),
    ];
    let rows: Vec<StressRow> = scenarios
        .into_iter()
        .map(|(scenario, expected, run)| {
            let ((outcome, message, warnings, note), run_time) = timed(|| guarded(run, options));
            StressRow { scenario, expected, outcome, message, warnings, run_time, note }
        })
        .collect();
    write_csv(&options.out_dir.join("stress.csv"), &rows)?;
    write_file(&options.out_dir.join("stress.md"), &summary(options, &rows))?;
    Ok(rows)
}

/// What a scenario reports: outcome, message, warnings, note.
type Report = (Outcome, String, Vec<String>, String);

/// A scenario.
type Scenario = fn(&StressOptions) -> Report;

/// Runs a scenario, turning a panic into [`Outcome::Panic`] with its message.
fn guarded(run: Scenario, options: &StressOptions) -> Report {
    std::panic::catch_unwind(|| run(options)).unwrap_or_else(|panic| {
        let text = panic.downcast_ref::<String>().cloned().or(panic.downcast_ref::<&str>().map(|s| s.to_string()));
        (Outcome::Panic, text.unwrap_or_else(|| "panic".into()), Vec::new(), String::new())
    })
}

/// The report of a finished run (or of a rejected scene), with a note.
fn report(result: Result<RunRecord, BenchError>, note: String) -> Report {
    match result {
        Ok(rec) => {
            let message = rec.message.clone().unwrap_or_else(|| match rec.settle_time {
                Some(t) => format!("settled at t = {t:.4} s after {} steps", rec.steps),
                None => format!("ran {:.4} s ({} steps) without settling", rec.simulated_time, rec.steps),
            });
            (Outcome::Run(rec.status), message, rec.warnings.iter().map(ToString::to_string).collect(), note)
        }
        Err(error) => (Outcome::Error, error.to_string(), Vec::new(), note),
    }
}

/// Runs a scene with generated disks.
fn run_generated(scene: &SceneConfig) -> Result<RunRecord, BenchError> {
    super::run(scene, &placed_disks(scene)?)
}

/// The default deposition scene at the options' size.
fn deposition(options: &StressOptions) -> SceneConfig {
    let mut s = SceneConfig::default();
    s.particles.count = options.count;
    s.run.duration = options.duration;
    s
}

/// The paper's Table 1 preset (E = 20 kPa, G = 20 kPa, β = 10, μ = 0.5, μ0 = 0.5, Δt = 1e-4 s).
fn paper_table1(options: &StressOptions) -> Report {
    let mut s = deposition(options);
    s.material.youngs_modulus = 20_000.0;
    s.material.shear_modulus = Some(20_000.0);
    s.material.beta = Some(10.0);
    s.material.rolling_friction = 0.5;
    s.integrator.time_step = Some(1e-4);
    s.run.duration = 2.0 * options.duration;
    let (outcome, message, warnings, _) = report(run_generated(&s), String::new());
    let collapsed = outcome == Outcome::Run(RunStatus::Diverged) && message.contains("overlap");
    let note = if collapsed {
        "collapse: the material is far too soft for its weight (Hertz theory invalid), the pile sinks into itself and the floor".into()
    } else {
        String::new()
    };
    (outcome, message, warnings, note)
}

/// E = 1e12 Pa with the default time step ten times too large (Δt = 1e-4 s).
fn very_stiff_large_dt(options: &StressOptions) -> Report {
    let mut s = deposition(options);
    s.material.youngs_modulus = 1e12;
    s.integrator.time_step = Some(1e-4);
    report(run_generated(&s), String::new())
}

/// One disk shot at the floor at 50 m/s (E = 1e9 Pa, the default time step).
fn impact_50(_: &StressOptions) -> Report {
    let mut s = SceneConfig::default();
    s.placement.kind = PlacementKind::File;
    s.placement.file = Some("in-memory".into());
    s.run.duration = 0.05;
    let disk = InitialDisk { x: 0.2, y: 0.05, r: 0.01, vy: -50.0, ..Default::default() };
    report(super::run(&s, &[disk]), String::new())
}

/// Disks on a square lattice at packing fraction 0.6, released under gravity.
fn dense_lattice(options: &StressOptions) -> Report {
    let mut s = deposition(options);
    s.placement.kind = PlacementKind::Lattice;
    // Square lattice: φ = π / (4 (1 + gap)²) = 0.6.
    s.placement.lattice_gap = (std::f64::consts::PI / (4.0 * 0.6)).sqrt() - 1.0;
    report(run_generated(&s), format!("lattice gap {:.4} of a diameter", s.placement.lattice_gap))
}

/// One disk dropped from 5 cm.
fn one_disk(options: &StressOptions) -> Report {
    let mut s = deposition(options);
    s.placement.kind = PlacementKind::File;
    s.placement.file = Some("in-memory".into());
    let disk = InitialDisk { x: 0.2, y: 0.05, r: 0.01, ..Default::default() };
    report(super::run(&s, &[disk]), String::new())
}

/// A scene without disks.
fn zero_disks(options: &StressOptions) -> Report {
    let mut s = deposition(options);
    s.particles.count = 0;
    report(run_generated(&s), String::new())
}

/// β = 50 with friction at the default time step.
fn beta_50(options: &StressOptions) -> Report {
    let mut s = deposition(options);
    s.material.beta = Some(50.0);
    report(run_generated(&s), String::new())
}

/// β = 50 without friction at the engine's suggested safe time step.
fn beta_50_frictionless_safe_dt(options: &StressOptions) -> Report {
    let mut s = deposition(options);
    s.material.beta = Some(50.0);
    s.material.friction = 0.0;
    let disks = match placed_disks(&s) {
        Ok(d) => d,
        Err(e) => return (Outcome::Error, e.to_string(), Vec::new(), String::new()),
    };
    s.integrator.time_step = Some(crate::physics::predict_stability(&s, &disks).safe_time_step);
    report(
        super::run(&s, &disks),
        format!("time step {:.3e} s (the predicted safe step)", s.integrator.fixed_time_step().unwrap_or_default()),
    )
}

/// No friction: rotation and tangential forces are skipped; the time saved against μ = 1e-9.
fn frictionless(options: &StressOptions) -> Report {
    let mut s = deposition(options);
    s.run.duration = options.duration / 3.0;
    s.run.stop_at_settle = false;
    let timed_pair = friction_rows(&s);
    let note = match &timed_pair {
        Ok(rows) => format!(
            "{:.3} s with μ = 1e-9 (tangential and rotational work done), {:.3} s with μ = 0: {:.1} % saved",
            rows[0].run_time,
            rows[1].run_time,
            100.0 * rows[1].saved
        ),
        Err(e) => e.to_string(),
    };
    s.material.friction = 0.0;
    report(run_generated(&s), note)
}

/// Resident memory of this process (bytes), from `/proc/self/status` (Linux); `None` elsewhere.
fn resident_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Many disks (default 100 000) in a box widened so the pile depth stays that of 300 disks:
/// memory of the simulation and time per step over a few steps of the fall.
fn large(options: &StressOptions) -> Report {
    let mut s = SceneConfig::default();
    s.particles.count = options.large_count;
    s.domain.width = 0.4 * options.large_count as f64 / 300.0;
    s.run.stop_at_settle = false;
    s.run.duration = options.large_steps as f64 * s.integrator.fixed_time_step().unwrap_or_default();
    let disks = match placed_disks(&s) {
        Ok(d) => d,
        Err(e) => return (Outcome::Error, e.to_string(), Vec::new(), String::new()),
    };
    let before = resident_memory();
    let sim = Simulation::<HertzMindlin>::new(&s, &disks);
    let memory = resident_memory().zip(before).map(|(after, before)| after.saturating_sub(before));
    let (rec, seconds) = timed(|| sim.run(&mut |_| crate::physics::Control::Continue));
    let per_step = seconds / rec.steps.max(1) as f64;
    let memory_text = memory.map_or("memory unknown (no /proc)".into(), |m| {
        format!("{:.1} MB for the simulation ({:.0} bytes per disk)", m as f64 / 1e6, m as f64 / disks.len() as f64)
    });
    let note = format!(
        "{} disks: {memory_text}; {:.2} ms per step ({:.1} ns per particle-step) over {} steps",
        disks.len(),
        per_step * 1e3,
        per_step * 1e9 / disks.len() as f64,
        rec.steps
    );
    report(Ok(rec), note)
}

/// The Markdown summary.
fn summary(options: &StressOptions, rows: &[StressRow]) -> String {
    let table: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.scenario.into(),
                r.expected.as_str().into(),
                r.outcome.as_str().into(),
                format!("{:.2}", r.run_time),
                r.message.replace('|', "/"),
                r.warnings.len().to_string(),
                r.note.replace('|', "/"),
            ]
        })
        .collect();
    let unexpected = rows.iter().filter(|r| !r.as_expected()).count();
    format!(
        "# Stress scenarios\n\n\
         Regenerate: `demsweep bench stress --update-results`.\n\n\
         {} scenarios ({} disks in the depositions, up to {} s; large scene {} disks over {} steps), {unexpected} \
         ended otherwise than expected. Every warning is in `stress.csv`.\n\n{}",
        rows.len(),
        options.count,
        options.duration,
        options.large_count,
        options.large_steps,
        markdown_table(
            &[
                "scenario",
                "expected",
                "outcome",
                quantity::labelled("run_time", "s").as_str(),
                "message",
                "warnings",
                "note"
            ],
            &table
        )
    )
}
