//! Does `demsweep tune` answer where an answer exists? On each tune file: tune, then a brute-force
//! ladder of time steps on the same seeds as tune's reference: the first standard setting (the time
//! step alone at `limits.contact_time_fraction` of the contact time) at `LADDER_FACTORS` of that
//! fraction, each rung on every reference seed, judged exactly as tune judges (validity over the runs
//! together, held to the reference where it breaks a limit; every kept metric equivalent by two
//! one-sided tests). The goal: tune's verified cost is within [`GOAL_RATIO`] of the ladder's cheapest
//! valid, equivalent rung, or tune stops early naming a metric it cannot decide; and tune spends at
//! most its `search.max_spend`.

use std::fmt::Write as _;
use std::path::PathBuf;

use super::{BenchError, CsvRow, create_folder, markdown_table, write_csv, write_file};
use crate::stats;
use crate::tune::judge::predicted_breach;
use crate::tune::model::{Candidate, Origin, Rejection, SearchResult, State};
use crate::tune::report::{settings, spend};
use crate::tune::{self, Evaluator, Job, Role, RunEvaluator, TuneOptions, TuneSpec};

/// The ladder's fractions of the first standard setting's time step.
pub const LADDER_FACTORS: [f64; 7] = [1.0, 0.9, 0.8, 0.7, 0.6, 0.5, 0.4];

/// Tune's verified cost may be at most this times the ladder's cheapest.
pub const GOAL_RATIO: f64 = 1.25;

/// What to compare.
#[derive(Clone, Debug)]
pub struct TuneBenchOptions {
    /// The tune files (scenes).
    pub tunes: Vec<PathBuf>,
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
            jobs: 0,
            out_dir: PathBuf::from(super::LATEST_DIR),
            work_dir: PathBuf::from(super::LATEST_DIR).join("tune_work"),
        }
    }
}

/// One rung of the ladder.
#[derive(Clone, Debug, PartialEq)]
pub struct Rung {
    /// Its setting, in words.
    pub setting: String,
    /// Its cost over the reference's (mean over its runs; NaN when not run).
    pub cost_ratio: f64,
    /// Its standing (`equivalent`, `infeasible`, `undecided`, `not_run`).
    pub state: String,
    /// Why, when it is not valid and equivalent.
    pub reason: String,
}

/// The ladder on one tune file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Ladder {
    /// Its rungs, dearest first.
    pub rungs: Vec<Rung>,
    /// The cheapest valid, equivalent rung: cost ratio and setting.
    pub best: Option<(f64, String)>,
    /// Runs made.
    pub runs: usize,
}

/// One scene's comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct TuneBenchRow {
    /// Tune name.
    pub scene: String,
    /// Disks.
    pub disks: usize,
    /// Tune's answer, or why there is none.
    pub tune_answer: String,
    /// Tune's verified cost ratio (NaN when no recommendation).
    pub tune_ratio: f64,
    /// Its 95 % interval.
    pub tune_ratio_low: f64,
    /// Its 95 % interval.
    pub tune_ratio_high: f64,
    /// Tune's spend in reference depositions.
    pub tune_spend: f64,
    /// The kept metric tune could not decide, when it stopped for that.
    pub undecided_metric: String,
    /// The ladder's rungs, dearest first.
    pub rungs: Vec<Rung>,
    /// The ladder's cheapest valid, equivalent rung's cost ratio (NaN when none).
    pub ladder_ratio: f64,
    /// Its setting.
    pub ladder_best: String,
    /// Runs of the ladder.
    pub ladder_runs: usize,
    /// Tune answered within [`GOAL_RATIO`] of the ladder (or no cheaper rung exists and tune gave none),
    /// or stopped naming a metric, and spent at most its limit.
    pub goal_met: bool,
}

impl CsvRow for TuneBenchRow {
    const COLUMNS: &'static [(&'static str, &'static str)] = &[
        ("scene", ""),
        ("disks", ""),
        ("tune_answer", ""),
        ("tune_cost_ratio", ""),
        ("tune_cost_ratio_low", ""),
        ("tune_cost_ratio_high", ""),
        ("tune_spend", ""),
        ("undecided_metric", ""),
        ("ladder_best", ""),
        ("ladder_cost_ratio", ""),
        ("ladder_runs", ""),
        ("tune_over_ladder", ""),
        ("goal_met", ""),
    ];

    fn values(&self) -> Vec<String> {
        let q = |s: &str| format!("\"{}\"", s.replace('"', "\"\""));
        vec![
            self.scene.clone(),
            self.disks.to_string(),
            q(&self.tune_answer),
            format!("{:.4}", self.tune_ratio),
            format!("{:.4}", self.tune_ratio_low),
            format!("{:.4}", self.tune_ratio_high),
            format!("{:.2}", self.tune_spend),
            self.undecided_metric.clone(),
            q(&self.ladder_best),
            format!("{:.4}", self.ladder_ratio),
            self.ladder_runs.to_string(),
            format!("{:.3}", self.tune_ratio / self.ladder_ratio),
            self.goal_met.to_string(),
        ]
    }
}

/// Runs tune and the ladder on every tune file; writes `tune.csv` and `tune.md`.
pub fn tune_bench(options: &TuneBenchOptions) -> Result<Vec<TuneBenchRow>, BenchError> {
    let mut rows = Vec::new();
    for path in &options.tunes {
        let mut spec = tune::load(path)?;
        crate::output::terminal::err(format_args!("bench tune: {} — tune\n", spec.name));
        let tune_dir = options.work_dir.join(&spec.name).join("tune");
        let tune_options =
            TuneOptions { jobs: options.jobs, out_dir: Some(tune_dir.clone()), force: true, ..Default::default() };
        let report = tune::tune(&mut spec, &tune_options)?;
        let result = &report.result;
        let paragraph = crate::tune::report::paragraph(&spec, result);
        crate::output::terminal::err(format_args!("{paragraph}\n"));
        let written = crate::tune::report::write_all(&spec, result, &tune_dir, &paragraph)?;
        create_folder(&options.out_dir)?;
        for chart in written.files.iter().filter(|f| f.extension().is_some_and(|e| e == "png")) {
            let name = chart.file_name().unwrap_or_default().to_string_lossy().into_owned();
            let name = if name.starts_with("tune") { name } else { format!("tune_{name}") };
            std::fs::copy(chart, options.out_dir.join(name))
                .map_err(|error| BenchError::Copy { path: chart.clone(), error })?;
        }
        rows.push(compare(&spec, result, options)?);
    }
    create_folder(&options.out_dir)?;
    write_csv(&options.out_dir.join("tune.csv"), &rows)?;
    write_file(&options.out_dir.join("tune.md"), &markdown(&rows))?;
    Ok(rows)
}

/// Tune's result against the ladder on one tune file.
fn compare(spec: &TuneSpec, result: &SearchResult, options: &TuneBenchOptions) -> Result<TuneBenchRow, BenchError> {
    let spent = spend(result);
    let undecided_metric =
        result.undecidable.iter().map(|u| spec.keep[u.metric].metric.clone()).collect::<Vec<_>>().join(" ");
    let (tune_answer, ratio) = match result.recommended {
        Some(k) => {
            let c = &result.candidates[k];
            let costs: Vec<f64> = c.verification.iter().map(|o| o.cost).collect();
            (settings(spec, c), stats::ratio_interval(&result.reference_costs(), &costs))
        }
        None if !undecided_metric.is_empty() => (format!("stopped: cannot decide {undecided_metric}"), nan_ratio()),
        None => ("none".to_string(), nan_ratio()),
    };
    let Ladder { rungs, best, runs: ladder_runs } = match undecided_metric.is_empty() {
        true => ladder(spec, result, options)?,
        false => Ladder::default(),
    };
    let (ladder_ratio, ladder_best) = best.unwrap_or((f64::NAN, "none".to_string()));
    let answered = match (ratio.ratio.is_finite(), ladder_ratio.is_finite()) {
        (true, true) => ratio.ratio <= GOAL_RATIO * ladder_ratio,
        (true, false) => true,
        (false, ladder) => !undecided_metric.is_empty() || !ladder,
    };
    Ok(TuneBenchRow {
        scene: spec.name.clone(),
        disks: spec.reference.particles.count,
        tune_answer,
        tune_ratio: ratio.ratio,
        tune_ratio_low: ratio.low,
        tune_ratio_high: ratio.high,
        tune_spend: spent,
        undecided_metric,
        rungs,
        ladder_ratio,
        ladder_best,
        ladder_runs,
        goal_met: answered && spent <= spec.search.max_spend,
    })
}

fn nan_ratio() -> stats::Ratio {
    stats::ratio_interval(&[], &[])
}

/// The brute-force ladder on the reference's seeds (tune's reference runs are the yardstick: the same
/// seeds give the same runs): every rung, its standing, and the cheapest valid, equivalent one (cost
/// ratio, setting), with the runs made.
fn ladder(spec: &TuneSpec, result: &SearchResult, options: &TuneBenchOptions) -> Result<Ladder, BenchError> {
    crate::output::terminal::err(format_args!("bench tune: {} — ladder\n", spec.name));
    let ladder_options = TuneOptions {
        jobs: options.jobs,
        out_dir: Some(options.work_dir.join(&spec.name).join("ladder")),
        force: true,
        ..Default::default()
    };
    let mut ladder_spec = spec.clone();
    ladder_spec.standards.truncate(1);
    let mut evaluator = RunEvaluator::new(&ladder_spec, &ladder_options);
    let reference = result.reference_cost();
    let seeds = result.reference.len() as u64;
    let (mut rungs, mut best, mut runs) = (Vec::new(), None, 0);
    for (index, &factor) in LADDER_FACTORS.iter().enumerate() {
        let standard = if factor == 1.0 { Some(0) } else { evaluator.step_down(0, factor) };
        let Some(standard) = standard else { continue };
        let screen = evaluator.screen(&[], Some(standard));
        let setting = evaluator.standards[standard].name.clone();
        let candidate = Candidate {
            id: index + 1,
            point: Vec::new(),
            standard: Some(standard),
            identity: screen.identity.clone(),
            origin: Origin::Path,
            predicted_invalid: None,
            runs: Vec::new(),
            verification: Vec::new(),
            verify_seeds: Vec::new(),
            relative_cost: screen.relative_cost,
            stepped_from: None,
        };
        if screen.relative_cost.is_some_and(|r| r >= 1.0) {
            continue;
        }
        let mut judged = result.clone();
        judged.candidates = vec![candidate];
        let predicted = screen.predicted.ok().and_then(|w| predicted_breach(&w, &result.reference_checks));
        if let Some((check, _)) = predicted {
            let reason = Rejection::Invalid(check).to_string();
            rungs.push(Rung { setting, cost_ratio: f64::NAN, state: "not_run".into(), reason });
            continue;
        }
        let jobs: Vec<Job> = (0..seeds)
            .map(|seed| Job {
                candidate: index + 1,
                point: Vec::new(),
                role: Role::Search,
                seed,
                standard: Some(standard),
                cap: None,
            })
            .collect();
        let outcomes = evaluator.evaluate(&jobs)?;
        runs += jobs.len();
        let a = judged.assess_runs(&outcomes);
        let cost_ratio = a.cost / reference;
        if a.state == State::Feasible && best.as_ref().is_none_or(|(r, _)| cost_ratio < *r) {
            best = Some((cost_ratio, setting.clone()));
        }
        let reason = match &a.state {
            State::Feasible => String::new(),
            State::Infeasible(why) => why.to_string(),
            other => other.name().to_string(),
        };
        rungs.push(Rung { setting, cost_ratio, state: a.state.name().to_string(), reason });
    }
    Ok(Ladder { rungs, best, runs })
}

fn markdown(rows: &[TuneBenchRow]) -> String {
    let mut text = String::from("# Tune against a brute-force ladder of time steps\n\n");
    let _ = writeln!(
        text,
        "Regenerate with `demsweep bench tune --update-results` (or on any tune file: `demsweep bench tune --tune \
         FILE`). The ladder: the time step alone at {} of `limits.contact_time_fraction` of the contact time, each \
         rung on the reference's seeds, judged as tune judges. Cost ratio: mean particle-steps per run over the \
         reference's (tune: on its fresh verification seeds). Goal: tune within {GOAL_RATIO}x of the ladder's \
         cheapest valid, equivalent rung (or it stops naming a metric it cannot decide), spending at most its \
         limit.\n",
        LADDER_FACTORS.map(|f| f.to_string()).join(", ")
    );
    let header = [
        "scene",
        "disks",
        "tune: answer",
        "tune: cost (95 % interval)",
        "tune: spend",
        "ladder: cheapest valid & equivalent",
        "ladder: cost",
        "tune / ladder",
        "goal met",
    ];
    let table: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.scene.clone(),
                r.disks.to_string(),
                r.tune_answer.clone(),
                format!("{:.3} ({:.3}-{:.3})", r.tune_ratio, r.tune_ratio_low, r.tune_ratio_high),
                format!("{:.1}", r.tune_spend),
                r.ladder_best.clone(),
                format!("{:.3}", r.ladder_ratio),
                format!("{:.2}", r.tune_ratio / r.ladder_ratio),
                r.goal_met.to_string(),
            ]
        })
        .collect();
    text.push_str(&markdown_table(&header, &table));
    text.push('\n');
    for r in rows {
        let _ = writeln!(text, "- **{}** ladder ({} runs):", r.scene, r.ladder_runs);
        for rung in &r.rungs {
            let _ = writeln!(text, "  - {}: cost {:.3}, {} {}", rung.setting, rung.cost_ratio, rung.state, rung.reason);
        }
    }
    text
}
