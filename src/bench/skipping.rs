//! What skipping unneeded work saves, in numbers: stopping at settle, sampling diagnostics every k
//! steps instead of every step, and leaving out tangential and rotational work without friction.
//!
//! Stopping at settle is measured over a list of scenes (`demsweep bench skipping` passes every run of
//! `studies/damping_sweep.toml`); sampling and friction on the first of them. Without a study, the
//! scene is the base scene of `studies/damping_sweep.toml` (300 glass disks, E = 50 GPa, e = 0.5,
//! μ = 0.5, Δt = 7 µs), built in code.

use std::path::PathBuf;

use super::{BenchError, CsvRow, markdown_table, placed_disks, timed, write_csv, write_file};
use crate::physics::config::SceneConfig;

/// What to measure.
#[derive(Clone, Debug)]
pub struct SkippingOptions {
    /// What the scenes are, in words.
    pub source: String,
    /// The scenes (their `run.stop_at_settle`, `run.sample_interval` and friction are varied), with
    /// random or lattice placement.
    pub scenes: Vec<SceneConfig>,
    /// Simulated time of the sampling and friction comparisons (s).
    pub window: f64,
    /// Diagnostics every k steps, for each k.
    pub sample_every: Vec<u64>,
    /// Where `skipping.csv` and `skipping.md` go.
    pub out_dir: PathBuf,
}

impl Default for SkippingOptions {
    fn default() -> Self {
        Self {
            source: "the base scene of studies/damping_sweep.toml, built in code".into(),
            scenes: vec![damping_sweep_scene()],
            window: 0.5,
            sample_every: vec![1, 10, 100, 1000],
            out_dir: PathBuf::from(super::LATEST_DIR),
        }
    }
}

/// The base scene of `studies/damping_sweep.toml`.
pub fn damping_sweep_scene() -> SceneConfig {
    let mut s = SceneConfig::default();
    s.domain.width = 0.2;
    s.domain.height = 0.3;
    s.particles.count = 300;
    s.particles.radius = 0.005;
    s.placement.seed = 2024;
    s.material.density = 2500.0;
    s.material.youngs_modulus = 5e10;
    s.material.poisson_ratio = Some(0.3);
    s.material.restitution = Some(0.5);
    s.material.friction = 0.5;
    s.integrator.time_step = Some(7e-6);
    s.run.duration = 2.0;
    s.run.sample_interval = 1e-3;
    s
}

/// One timed run.
#[derive(Clone, Debug, PartialEq)]
pub struct SkippingRow {
    /// `stop_at_settle`, `sampling` or `friction`.
    pub measure: &'static str,
    /// The setting, in words.
    pub setting: String,
    /// Wall-clock time (s).
    pub run_time: f64,
    /// Scenes run.
    pub runs: usize,
    /// Time steps taken, all runs.
    pub steps: u64,
    /// Simulated time, all runs (s).
    pub simulated_time: f64,
    /// Disks times steps, all runs.
    pub particle_steps: f64,
    /// Run time saved against the measure's first (full-work) row, as a fraction.
    pub saved: f64,
}

impl CsvRow for SkippingRow {
    const COLUMNS: &'static [(&'static str, &'static str)] = &[
        ("measure", ""),
        ("setting", ""),
        ("runs", ""),
        ("run_time", "s"),
        ("steps", ""),
        ("simulated_time", "s"),
        ("ns_per_particle_step", "ns"),
        ("saved_fraction", ""),
    ];
    fn values(&self) -> Vec<String> {
        vec![
            self.measure.into(),
            self.setting.clone(),
            self.runs.to_string(),
            format!("{:.4}", self.run_time),
            self.steps.to_string(),
            format!("{:.4}", self.simulated_time),
            format!("{:.2}", self.ns_per_particle_step()),
            format!("{:.4}", self.saved),
        ]
    }
}

impl SkippingRow {
    /// Wall-clock nanoseconds per disk and step.
    fn ns_per_particle_step(&self) -> f64 {
        self.run_time * 1e9 / self.particle_steps.max(1.0)
    }
}

/// Timings of the short comparisons (sampling, friction): the shortest of this many runs.
const REPEATS: usize = 3;

/// Rows of one measure: each setting's scenes run and timed together, each scene's time the
/// shortest of `repeats` runs (the machine may be shared); `saved` against the first.
fn measure(
    name: &'static str,
    settings: Vec<(String, Vec<SceneConfig>)>,
    repeats: usize,
) -> Result<Vec<SkippingRow>, BenchError> {
    let mut rows: Vec<SkippingRow> = Vec::new();
    for (setting, scenes) in settings {
        let mut row = SkippingRow {
            measure: name,
            setting,
            runs: scenes.len(),
            run_time: 0.0,
            steps: 0,
            simulated_time: 0.0,
            particle_steps: 0.0,
            saved: 0.0,
        };
        for scene in &scenes {
            let disks = placed_disks(scene)?;
            let (rec, mut seconds) = timed(|| super::run(scene, &disks));
            for _ in 1..repeats {
                seconds = seconds.min(timed(|| super::run(scene, &disks)).1);
            }
            let rec = rec?;
            row.run_time += seconds;
            row.steps += rec.steps;
            row.simulated_time += rec.simulated_time;
            row.particle_steps += rec.steps as f64 * disks.len() as f64;
        }
        row.saved = rows.first().map_or(0.0, |first| 1.0 - row.run_time / first.run_time);
        rows.push(row);
    }
    Ok(rows)
}

/// Time saved by skipping tangential and rotational work: the scene without friction against the
/// same scene with μ = 1e-9 (the same physics, with the full work), over its duration.
pub fn friction_rows(scene: &SceneConfig) -> Result<Vec<SkippingRow>, BenchError> {
    let with = |mu: f64| {
        let mut s = scene.clone();
        s.material.friction = mu;
        s.material.rolling_friction = 0.0;
        s
    };
    measure(
        "friction",
        vec![
            ("μ = 1e-9 (tangential and rotational work done)".into(), vec![with(1e-9)]),
            ("μ = 0 (skipped)".into(), vec![with(0.0)]),
        ],
        REPEATS,
    )
}

/// The scene with stopping and sampling (every `every` steps) set and the given duration.
fn configured(scene: &SceneConfig, stop: bool, every: Option<u64>, duration: f64) -> SceneConfig {
    let mut s = scene.clone();
    s.run.stop_at_settle = stop;
    if let Some(k) = every {
        s.run.sample_interval = k as f64 * s.integrator.fixed_time_step().unwrap_or_default();
    }
    s.run.duration = duration;
    s
}

/// Runs the three measures; writes `skipping.csv` and `skipping.md`.
pub fn skipping(options: &SkippingOptions) -> Result<Vec<SkippingRow>, BenchError> {
    let first = options.scenes.first().ok_or(BenchError::Nothing("skipping: no scene to measure"))?;
    let all = |stop: bool| options.scenes.iter().map(|s| configured(s, stop, None, s.run.duration)).collect();
    let mut rows = measure(
        "stop_at_settle",
        vec![("run the full duration".into(), all(false)), ("stop once settled".into(), all(true))],
        1,
    )?;
    let sampling = options
        .sample_every
        .iter()
        .map(|k| (format!("diagnostics every {k} steps"), vec![configured(first, false, Some(*k), options.window)]))
        .collect();
    rows.extend(measure("sampling", sampling, REPEATS)?);
    rows.extend(friction_rows(&configured(first, false, None, options.window))?);
    write_csv(&options.out_dir.join("skipping.csv"), &rows)?;
    write_file(&options.out_dir.join("skipping.md"), &summary(options, &rows))?;
    Ok(rows)
}

/// The Markdown summary.
fn summary(options: &SkippingOptions, rows: &[SkippingRow]) -> String {
    let table: Vec<Vec<String>> = rows.iter().map(CsvRow::values).collect();
    let s = &options.scenes[0];
    format!(
        "# Skipping what a scene does not need\n\n\
         Regenerate: `demsweep bench skipping --update-results` (the stop-at-settle rows run every run of \
         `studies/damping_sweep.toml`).\n\n\
         Scenes: {} ({} scenes; the first has {} disks, E = {:e} Pa, Δt = {:e} s). Stopping at settle: every \
         scene run to its full duration against stopped once settled, times summed. Sampling and friction: the \
         first scene over its first {} s without stopping, each timing the shortest of {REPEATS} runs (friction: μ = 0 against μ = 1e-9, the same physics with \
         the tangential and rotational work done). Saved: run time saved against the first row of each measure. \
         Wall clock, one thread, on the machine that wrote this file.\n\n{}",
        options.source,
        options.scenes.len(),
        s.particles.count,
        s.material.youngs_modulus,
        s.integrator.fixed_time_step().unwrap_or_default(),
        options.window,
        markdown_table(&SkippingRow::labels(), &table)
    )
}
