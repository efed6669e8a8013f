//! Does `demsweep tune` find what a brute-force grid finds, for less? On each tune file: tune's
//! verified recommendation against a full grid over the same levers (`levels` values per lever, the
//! same `search.seeds` seeds per point, the same reference runs and validity prediction), comparing the
//! cost ratio to the reference (tune's from its verification runs, the grid's from its best acceptable
//! point) and the total cost (particle-steps of every run, the reference included in both).

use std::fmt::Write as _;
use std::path::PathBuf;

use super::{CsvRow, markdown_table, write_csv, write_file};
use crate::stats;
use crate::tune::report::settings;
use crate::tune::search::{Candidate, Origin, State, assess};
use crate::tune::{self, Evaluator, Job, Role, RunEvaluator, TuneOptions};

/// What to compare.
#[derive(Clone, Debug)]
pub struct TuneBenchOptions {
    /// The tune files (scenes).
    pub tunes: Vec<PathBuf>,
    /// Grid values per lever (ends included).
    pub levels: usize,
    /// Worker threads (0: all cores).
    pub jobs: usize,
    /// Where `tune.csv` and `tune.md` go.
    pub out_dir: PathBuf,
    /// Where the runs' results files go.
    pub work_dir: PathBuf,
}

impl Default for TuneBenchOptions {
    fn default() -> Self {
        Self {
            tunes: vec![PathBuf::from("studies/tune_deposition.toml"), PathBuf::from("studies/tune_polydisperse.toml")],
            levels: 3,
            jobs: 0,
            out_dir: PathBuf::from(super::LATEST_DIR),
            work_dir: PathBuf::from(super::LATEST_DIR).join("tune_work"),
        }
    }
}

/// One scene's comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct TuneBenchRow {
    /// Tune name.
    pub scene: String,
    /// Levers.
    pub levers: usize,
    /// Grid points run (predicted-invalid ones are not run).
    pub grid_points: usize,
    /// Grid points predicted invalid.
    pub grid_skipped: usize,
    /// Grid runs, the reference included.
    pub grid_runs: usize,
    /// Particle-steps of every grid run, the reference included.
    pub grid_cost: f64,
    /// The grid's best acceptable point's cost over the reference's (NaN when none is acceptable).
    pub grid_best_ratio: f64,
    /// Its settings.
    pub grid_best: String,
    /// Whether it also passes on the fresh seeds tune verified on.
    pub grid_best_verified: String,
    /// Tune's runs, all included.
    pub tune_runs: usize,
    /// Tune's particle-steps, all included.
    pub tune_cost: f64,
    /// Tune's verified cost ratio (NaN when no recommendation).
    pub tune_ratio: f64,
    /// Its 95 % interval.
    pub tune_ratio_low: f64,
    /// Its 95 % interval.
    pub tune_ratio_high: f64,
    /// The reference's mean wall time over the verification runs' (the verified wall-clock speedup).
    pub tune_wall_speedup: f64,
    /// Tune's recommendation.
    pub tune_best: String,
    /// tune ratio ≤ 1.1 × grid ratio.
    pub ratio_ok: bool,
    /// tune cost ≤ grid cost / 3.
    pub cost_ok: bool,
}

impl CsvRow for TuneBenchRow {
    const HEADER: &'static [&'static str] = &[
        "scene",
        "levers",
        "grid_points",
        "grid_skipped",
        "grid_runs",
        "grid_particle_steps",
        "grid_best_cost_ratio",
        "grid_best",
        "grid_best_on_fresh_seeds",
        "tune_runs",
        "tune_particle_steps",
        "tune_cost_ratio",
        "tune_cost_ratio_low",
        "tune_cost_ratio_high",
        "tune_wall_time_speedup",
        "tune_best",
        "ratio_within_10_percent",
        "cost_at_most_a_third",
    ];

    fn values(&self) -> Vec<String> {
        let q = |s: &str| format!("\"{}\"", s.replace('"', "\"\""));
        vec![
            self.scene.clone(),
            self.levers.to_string(),
            self.grid_points.to_string(),
            self.grid_skipped.to_string(),
            self.grid_runs.to_string(),
            format!("{:.4e}", self.grid_cost),
            format!("{:.4}", self.grid_best_ratio),
            q(&self.grid_best),
            self.grid_best_verified.clone(),
            self.tune_runs.to_string(),
            format!("{:.4e}", self.tune_cost),
            format!("{:.4}", self.tune_ratio),
            format!("{:.4}", self.tune_ratio_low),
            format!("{:.4}", self.tune_ratio_high),
            format!("{:.3}", self.tune_wall_speedup),
            q(&self.tune_best),
            self.ratio_ok.to_string(),
            self.cost_ok.to_string(),
        ]
    }
}

/// Runs the comparison on every tune file; writes `tune.csv` and `tune.md`.
pub fn tune_bench(options: &TuneBenchOptions) -> Result<Vec<TuneBenchRow>, String> {
    let mut rows = Vec::new();
    for path in &options.tunes {
        let mut spec = tune::load(path).map_err(|e| e.to_string())?;
        eprintln!("bench tune: {} — tune", spec.name);
        let tune_options = TuneOptions {
            jobs: options.jobs,
            out_dir: Some(options.work_dir.join(&spec.name).join("tune")),
            force: true,
            ..Default::default()
        };
        let report = tune::tune(&mut spec, &tune_options).map_err(|e| e.to_string())?;
        let result = &report.result;
        let paragraph = crate::tune::report::paragraph(&spec, result);
        eprintln!("{paragraph}");
        let tune_dir = options.work_dir.join(&spec.name).join("tune");
        let written = crate::tune::report::write_all(&spec, result, &tune_dir, &paragraph)?;
        std::fs::create_dir_all(&options.out_dir).map_err(|e| format!("{}: {e}", options.out_dir.display()))?;
        for chart in written.files.iter().filter(|f| f.extension().is_some_and(|e| e == "png")) {
            let name = chart.file_name().unwrap_or_default().to_string_lossy().into_owned();
            let name = if name.starts_with("tune") { name } else { format!("tune_{name}") };
            std::fs::copy(chart, options.out_dir.join(name)).map_err(|e| format!("{}: {e}", chart.display()))?;
        }
        eprintln!("bench tune: {} — grid", spec.name);
        // The grid: every combination of `levels` values per lever (list levers: every value).
        let per_lever: Vec<Vec<f64>> = spec
            .levers
            .iter()
            .map(|l| match &l.range {
                tune::LeverRange::List(values) => {
                    (0..values.len()).map(|k| (k as f64 + 0.5) / values.len() as f64).collect()
                }
                _ => (0..options.levels).map(|k| k as f64 / (options.levels - 1).max(1) as f64).collect(),
            })
            .collect();
        let count: usize = per_lever.iter().map(Vec::len).product();
        let grid_options = TuneOptions {
            jobs: options.jobs,
            out_dir: Some(options.work_dir.join(&spec.name).join("grid")),
            force: true,
            ..Default::default()
        };
        let mut evaluator = RunEvaluator::new(&spec, &grid_options);
        let seeds = spec.search.seeds as u64;
        let reference_jobs: Vec<Job> = (0..result.reference.len() as u64)
            .map(|seed| Job { candidate: 0, point: Vec::new(), role: Role::Reference, seed, standard: None, cap: None })
            .collect();
        let reference = evaluator.evaluate(&reference_jobs)?;
        let mut points = Vec::new();
        let mut skipped = 0;
        for index in 0..count {
            let mut rest = index;
            let mut point = vec![0.0; per_lever.len()];
            for d in (0..per_lever.len()).rev() {
                point[d] = per_lever[d][rest % per_lever[d].len()];
                rest /= per_lever[d].len();
            }
            if evaluator.screen(&point, None).invalid.is_some() {
                skipped += 1;
            } else {
                points.push(point);
            }
        }
        let jobs: Vec<Job> = points
            .iter()
            .enumerate()
            .flat_map(|(k, p)| {
                (0..seeds).map(move |seed| Job {
                    candidate: k + 1,
                    point: p.clone(),
                    role: Role::Search,
                    seed,
                    standard: None,
                    cap: None,
                })
            })
            .collect();
        let outcomes = evaluator.evaluate(&jobs)?;
        // The grid's cost: the reference and the grid points (not the check of its best below).
        let grid_cost = evaluator.particle_steps;
        let reference_mean = stats::describe(&reference.iter().map(|o| o.cost).collect::<Vec<_>>()).mean;
        let mut best: Option<(usize, f64)> = None;
        for (k, chunk) in outcomes.chunks(seeds as usize).enumerate() {
            let a = assess(&reference, chunk, &result.margins);
            if a.state == State::Feasible && best.is_none_or(|(_, c)| a.cost < c) {
                best = Some((k, a.cost));
            }
        }
        let as_candidate = |k: usize| Candidate {
            id: k + 1,
            point: points[k].clone(),
            standard: None,
            identity: String::new(),
            origin: Origin::Initial,
            predicted_invalid: None,
            runs: Vec::new(),
            verification: Vec::new(),
            verify_seeds: Vec::new(),
            relative_cost: None,
            stepped_from: None,
        };
        let recommended = result.recommended.map(|k| &result.candidates[k]);
        // The grid's best on the fresh seeds tune verified on (or on fresh seeds of its own).
        let grid_best_verified = match best {
            Some((k, _)) => {
                let fresh: Vec<u64> = match recommended {
                    Some(c) => c.verify_seeds.clone(),
                    None => {
                        let first = (spec.search.reference_seeds().max(spec.search.max_seeds)) as u64;
                        (first..first + spec.search.verify_seeds() as u64).collect()
                    }
                };
                let jobs: Vec<Job> = fresh
                    .iter()
                    .map(|&seed| Job {
                        candidate: k + 1,
                        point: points[k].clone(),
                        role: Role::Verify,
                        seed,
                        standard: None,
                        cap: None,
                    })
                    .collect();
                let runs = evaluator.evaluate(&jobs)?;
                assess(&reference, &runs, &result.margins).state.name().to_string()
            }
            None => String::new(),
        };
        let (tune_ratio, low, high, wall, tune_best) = match recommended {
            Some(c) => {
                let r = stats::ratio_interval(
                    &result.reference_costs(),
                    &c.verification.iter().map(|o| o.cost).collect::<Vec<_>>(),
                );
                let wall = wall_speedup(&report, c);
                (r.ratio, r.low, r.high, wall, settings(&spec, c))
            }
            None => (f64::NAN, f64::NAN, f64::NAN, f64::NAN, "none".to_string()),
        };
        let grid_best_ratio = best.map_or(f64::NAN, |(_, c)| c / reference_mean);
        rows.push(TuneBenchRow {
            scene: spec.name.clone(),
            levers: spec.levers.len(),
            grid_points: points.len(),
            grid_skipped: skipped,
            grid_runs: reference.len() + outcomes.len(),
            grid_cost,
            grid_best_ratio,
            grid_best: best.map_or("none".into(), |(k, _)| settings(&spec, &as_candidate(k))),
            grid_best_verified,
            tune_runs: result.runs,
            tune_cost: report.total_particle_steps,
            tune_ratio,
            tune_ratio_low: low,
            tune_ratio_high: high,
            tune_wall_speedup: wall,
            tune_best,
            ratio_ok: tune_ratio <= 1.1 * grid_best_ratio || (grid_best_ratio.is_nan() && tune_ratio.is_finite()),
            cost_ok: report.total_particle_steps <= grid_cost / 3.0,
        });
    }
    std::fs::create_dir_all(&options.out_dir).map_err(|e| format!("{}: {e}", options.out_dir.display()))?;
    write_csv(&options.out_dir.join("tune.csv"), &rows)?;
    write_file(&options.out_dir.join("tune.md"), &markdown(&rows, options))?;
    Ok(rows)
}

/// The reference's mean wall time over the recommendation's verification runs' mean wall time.
fn wall_speedup(report: &tune::TuneReport, candidate: &Candidate) -> f64 {
    let Ok(table) = crate::output::summary::read(&report.results) else { return f64::NAN };
    let column = |name: &str| table.column(name).map(|c| &c.data);
    let (Some(crate::output::table::ColumnData::Float(wall)), Some(candidates), Some(roles)) =
        (column("wall_time"), column("tune.candidate"), column("tune.role"))
    else {
        return f64::NAN;
    };
    let pick = |want_candidate: usize, want_role: &str| {
        let times: Vec<f64> = (0..wall.len())
            .filter(|&i| candidates.text(i) == want_candidate.to_string() && roles.text(i) == want_role)
            .map(|i| wall[i])
            .collect();
        stats::describe(&times).mean
    };
    pick(0, "reference") / pick(candidate.id, "verify")
}

fn markdown(rows: &[TuneBenchRow], options: &TuneBenchOptions) -> String {
    let mut text = String::from("# Tune against a brute-force grid\n\n");
    let _ = writeln!(
        text,
        "Regenerate with `demsweep bench tune --update-results` ({} tune files, {} grid values per lever). \
         Cost ratio: mean particle-steps per run over the reference's (tune: on its fresh verification \
         seeds; grid: its cheapest point equivalent on every kept metric with `search.seeds` seeds). \
         Total cost: particle-steps of every run, the reference included in both. The grid runs the same \
         reference runs and skips the points the validity prediction rejects, as tune does.\n",
        options.tunes.len(),
        options.levels
    );
    let header = [
        "scene",
        "grid runs",
        "grid total (particle-steps)",
        "grid best ratio",
        "grid best on fresh seeds",
        "tune runs",
        "tune total",
        "tune total / grid total",
        "tune ratio (95 % interval)",
        "speedup (particle-steps / wall time)",
        "ratio within 10 %",
    ];
    let table: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.scene.clone(),
                format!("{} ({} points x seeds, {} predicted invalid)", r.grid_runs, r.grid_points, r.grid_skipped),
                format!("{:.3e}", r.grid_cost),
                format!("{:.3}", r.grid_best_ratio),
                r.grid_best_verified.clone(),
                r.tune_runs.to_string(),
                format!("{:.3e}", r.tune_cost),
                format!("{:.3}", r.tune_cost / r.grid_cost),
                format!("{:.3} ({:.3}-{:.3})", r.tune_ratio, r.tune_ratio_low, r.tune_ratio_high),
                format!("{:.2}x / {:.2}x", 1.0 / r.tune_ratio, r.tune_wall_speedup),
                r.ratio_ok.to_string(),
            ]
        })
        .collect();
    text.push_str(&markdown_table(&header, &table));
    text.push('\n');
    for r in rows {
        let _ =
            writeln!(text, "- **{}**: tune recommends {}; the grid's best is {}.", r.scene, r.tune_best, r.grid_best);
    }
    text
}
