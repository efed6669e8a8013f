//! Does `demsweep tune` answer where an answer exists? On each tune file: tune, then the brute-force
//! ladder over the same levers on fresh seeds ([`super::tune_ladder`]). The goal: tune's verified
//! cost is within [`GOAL_RATIO`] of the ladder's cheapest valid, equivalent rung, or tune stops early
//! naming a metric it cannot decide (no answer keeps the reference's settings, at cost 1); and tune
//! spends at most its `search.max_spend`. Tune's answer is
//! also run on the ladder's seeds, so that it is judged on the same runs as the ladder.

use std::fmt::Write as _;
use std::path::PathBuf;

use super::tune_ladder::{DEAR, GridLadder, LADDER_FACTORS, LADDER_SEEDS, MAX_GRID, Rung, grid_ladder};
use super::{BenchError, CsvRow, create_folder, markdown_table, write_csv, write_file};
use crate::stats;
use crate::tune::model::SearchResult;
use crate::tune::report::{settings, spend};
use crate::tune::{self, TuneOptions, TuneSpec};

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
    /// Fresh seeds of the ladder (at least; the reference's count when larger).
    pub ladder_seeds: usize,
}

impl Default for TuneBenchOptions {
    fn default() -> Self {
        Self {
            tunes: vec![PathBuf::from("studies/tune_deposition.toml"), PathBuf::from("studies/tune_polydisperse.toml")],
            jobs: 0,
            out_dir: PathBuf::from(super::LATEST_DIR),
            work_dir: PathBuf::from(super::LATEST_DIR).join("tune_work"),
            ladder_seeds: LADDER_SEEDS,
        }
    }
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
    /// The ladder's rungs.
    pub rungs: Vec<Rung>,
    /// The ladder's cheapest valid, equivalent rung's cost ratio (NaN when none).
    pub ladder_ratio: f64,
    /// Its setting.
    pub ladder_best: String,
    /// Its cost ratio on its confirmation seeds alone (NaN when none).
    pub ladder_confirmation_ratio: f64,
    /// Runs of the ladder.
    pub ladder_runs: usize,
    /// Fresh seeds each rung of the ladder may run on.
    pub ladder_seeds: usize,
    /// Tune's answer on the ladder's fresh seeds: its cost ratio (NaN when there is no answer).
    pub answer_on_ladder_ratio: f64,
    /// Its standing there (`equivalent`, `infeasible`, …; empty when there is no answer).
    pub answer_on_ladder_state: String,
    /// Tune answered within [`GOAL_RATIO`] of the ladder (or no cheaper rung exists and tune gave none),
    /// or stopped naming a metric, and spent at most its limit.
    pub goal_met: bool,
}

impl TuneBenchRow {
    /// Tune's answer on the ladder's seeds over the ladder's best on its confirmation seeds: two
    /// settings each measured on runs that did not choose it (NaN without both).
    pub fn like_with_like(&self) -> f64 {
        self.answer_on_ladder_ratio / self.ladder_confirmation_ratio
    }
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
        ("ladder_seeds", ""),
        ("answer_on_ladder_cost_ratio", ""),
        ("answer_on_ladder_state", ""),
        ("ladder_confirmation_cost_ratio", ""),
        ("tune_over_ladder", ""),
        ("answer_on_ladder_over_confirmation", ""),
        ("goal_met", ""),
    ];

    fn values(&self) -> Vec<String> {
        vec![
            self.scene.clone(),
            self.disks.to_string(),
            self.tune_answer.clone(),
            format!("{:.4}", self.tune_ratio),
            format!("{:.4}", self.tune_ratio_low),
            format!("{:.4}", self.tune_ratio_high),
            format!("{:.2}", self.tune_spend),
            self.undecided_metric.clone(),
            self.ladder_best.clone(),
            format!("{:.4}", self.ladder_ratio),
            self.ladder_runs.to_string(),
            self.ladder_seeds.to_string(),
            format!("{:.4}", self.answer_on_ladder_ratio),
            self.answer_on_ladder_state.clone(),
            format!("{:.4}", self.ladder_confirmation_ratio),
            format!("{:.3}", self.tune_ratio / self.ladder_ratio),
            format!("{:.3}", self.like_with_like()),
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
        let paragraph = crate::tune::report::paragraph(&spec, result, Some(&tune_dir));
        crate::output::terminal::err(format_args!("{paragraph}\n"));
        let written =
            crate::tune::report::write_all(&spec, result, &tune_dir, &paragraph, crate::output::guard::Existing::Any)?;
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
    let ladder_options = TuneOptions {
        jobs: options.jobs,
        out_dir: Some(options.work_dir.join(&spec.name).join("ladder")),
        force: true,
        ..Default::default()
    };
    let GridLadder { rungs, best, answer, runs: ladder_runs, seeds: ladder_seeds } = match undecided_metric.is_empty() {
        true => grid_ladder(spec, result, ladder_options, options.ladder_seeds)?,
        false => GridLadder::default(),
    };
    let answer_on_ladder = answer.map(|r| (r.cost_ratio, r.state)).unwrap_or((f64::NAN, String::new()));
    let (ladder_ratio, ladder_best, ladder_confirmation_ratio) = match best {
        Some(b) => (b.cost_ratio, b.setting, b.confirmation_cost_ratio),
        None => (f64::NAN, "none".to_string(), f64::NAN),
    };
    let answered = match (ratio.ratio.is_finite(), ladder_ratio.is_finite()) {
        (true, true) => ratio.ratio <= GOAL_RATIO * ladder_ratio,
        (true, false) => true,
        // No answer keeps the reference's settings: cost 1.
        (false, ladder) => !undecided_metric.is_empty() || !ladder || 1.0 <= GOAL_RATIO * ladder_ratio,
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
        ladder_confirmation_ratio,
        ladder_runs,
        ladder_seeds,
        answer_on_ladder_ratio: answer_on_ladder.0,
        answer_on_ladder_state: answer_on_ladder.1,
        goal_met: answered && spent <= spec.search.max_spend,
    })
}

fn nan_ratio() -> stats::Ratio {
    stats::ratio_interval(&[], &[])
}

/// `x` to `decimals` places, "-" where there is no figure (no answer, no rung run).
fn figure(x: f64, decimals: usize) -> String {
    if x.is_finite() { format!("{x:.decimals$}") } else { "-".to_string() }
}

fn interval(ratio: f64, low: f64, high: f64) -> String {
    if ratio.is_finite() { format!("{ratio:.3} ({}-{})", figure(low, 3), figure(high, 3)) } else { "-".to_string() }
}

fn on_ladder(ratio: f64, state: &str) -> String {
    if ratio.is_finite() { format!("{ratio:.3}, {state}") } else { "-".to_string() }
}

fn markdown(rows: &[TuneBenchRow]) -> String {
    let mut text = String::from("# Tune against a brute-force ladder over its levers\n\n");
    let _ = writeln!(
        text,
        "Regenerate with `demsweep bench tune --update-results` (or on any tune file: `demsweep bench tune --tune \
         FILE`). The ladder, on fresh seeds (a reference of its own on the same seeds; {} or the reference's count): tune's answer, the \
         standard settings and the time step at {} of the first, a grid over the levers (at most {MAX_GRID} \
         points) and the half-steps around its best point, judged as tune judges; runs stop at {DEAR} times the \
         reference's cost. The ladder's best is the cheapest valid, equivalent rung that is so again on as many \
         further fresh seeds (confirmed, as tune verifies). Cost ratio: mean particle-steps per run over the \
         reference's (tune: on its fresh verification seeds; the ladder's best: over both sets). Goal: tune \
         within {GOAL_RATIO}x of the ladder's best (no answer counts as 1), or it stops naming a metric it \
         cannot decide, spending at most its limit. Like with like: tune's answer on the ladder's seeds \
         over the ladder's best on its confirmation seeds alone, each measured on runs that did not choose \
         it (the ladder's best over both sets is biased low by its choice among many rungs).\n",
        rows.first().map_or(LADDER_SEEDS, |r| r.ladder_seeds),
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
        "tune's answer on the ladder's seeds",
        "like with like",
        "goal met",
    ];
    let table: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.scene.clone(),
                r.disks.to_string(),
                r.tune_answer.clone(),
                interval(r.tune_ratio, r.tune_ratio_low, r.tune_ratio_high),
                format!("{:.1}", r.tune_spend),
                r.ladder_best.clone(),
                figure(r.ladder_ratio, 3),
                figure(r.tune_ratio / r.ladder_ratio, 2),
                on_ladder(r.answer_on_ladder_ratio, &r.answer_on_ladder_state),
                figure(r.like_with_like(), 2),
                r.goal_met.to_string(),
            ]
        })
        .collect();
    text.push_str(&markdown_table(&header, &table));
    text.push('\n');
    for r in rows {
        let _ = writeln!(text, "- **{}** ladder ({} runs):", r.scene, r.ladder_runs);
        for rung in &r.rungs {
            let _ = writeln!(
                text,
                "  - {}: cost {}, {} {}",
                rung.setting,
                figure(rung.cost_ratio, 3),
                rung.state,
                rung.reason
            );
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scene_without_an_answer_or_ladder_shows_dashes_not_nan() {
        assert_eq!(interval(f64::NAN, f64::NAN, f64::NAN), "-");
        assert_eq!(interval(0.2513, 0.224, 0.2819), "0.251 (0.224-0.282)");
        assert_eq!(figure(0.2513 / f64::NAN, 2), "-");
        assert_eq!(figure(0.885, 2), "0.89");
        assert_eq!(on_ladder(f64::NAN, ""), "-");
        assert_eq!(on_ladder(0.282, "equivalent"), "0.282, equivalent");
    }
}
