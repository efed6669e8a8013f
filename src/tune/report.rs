//! What a tune tells: the answer sheet (the recommendation or why there is none, said up front when
//! the reference itself breaks a rule of thumb), `<name>_best.toml` (a runnable study of the
//! recommended scene), `<name>_scene_change.toml` (the `[scene]` keys to set in the user's file),
//! `<name>_candidates.csv` (every setting that ran), `<name>_skipped.csv` (those predicted invalid
//! and not run) and the charts.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::judge::broken_by_reference;
use super::model::{
    Assessment, Candidate, CheckFigure, Outcome, PathEnd, Rejection, RunFailure, SearchEnd, SearchResult, State,
};
use super::search::PRICE_MARGIN;
use super::{TuneSpec, seed_text};
use crate::output::guard::Existing;
use crate::output::{csv, guard};
use crate::physics::SceneConfig;
use crate::physics::number::short;
use crate::physics::quantity::{self, PILE_METRICS};
use crate::plot::tune::{CostPoint, LeverSeries, cost_along_levers_chart, cost_vs_difference_chart};
use crate::plot::{ChartOptions, Format, PlotError};
use crate::report::{Cell, Table, TuneSection};
use crate::stats;
use crate::study::ParamValue;

/// Why a tune's files could not be written.
#[derive(Debug)]
pub enum WriteError {
    /// The output folder could not be made.
    CreateDir {
        /// The folder.
        dir: PathBuf,
        /// Why.
        error: std::io::Error,
    },
    /// A file was refused or could not be written.
    File(guard::GuardError),
    /// The report section's chart could not be drawn.
    Chart(PlotError),
}

impl std::fmt::Display for WriteError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            WriteError::CreateDir { dir, error } => write!(f, "{}: {error}", dir.display()),
            WriteError::File(e) => write!(f, "{e}"),
            WriteError::Chart(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for WriteError {}

impl From<guard::GuardError> for WriteError {
    fn from(error: guard::GuardError) -> Self {
        WriteError::File(error)
    }
}

/// Files a tune wrote.
#[derive(Clone, Debug, Default)]
pub struct Written {
    /// Every file, in the order written.
    pub files: Vec<PathBuf>,
    /// Charts that could not be drawn.
    pub chart_errors: Vec<PlotError>,
}

/// The settings of a candidate: `key = value, ...` (a standard setting: its name and keys).
pub fn settings(spec: &TuneSpec, candidate: &Candidate) -> String {
    let values = spec.setting_values(&candidate.point, candidate.standard);
    let text = values.iter().map(|(k, v)| format!("{k} = {v}")).collect::<Vec<_>>().join(", ");
    match candidate.standard {
        Some(k) => format!("the standard setting \"{}\" ({text})", spec.standards[k].name),
        None => text,
    }
}

/// The time step a candidate's runs actually use, and what it is of the contact time (unless its
/// settings give that fraction: one figure per fraction); then each stage's that differs from it.
fn resolved_time_step(spec: &TuneSpec, candidate: &Candidate) -> String {
    let Ok(scene) = super::candidate_scene(spec, candidate) else { return String::new() };
    let given = spec.setting_values(&candidate.point, candidate.standard);
    let fraction_given =
        |prefix: &str| given.iter().any(|(k, _)| k.strip_prefix(prefix) == Some("integrator.contact_time_fraction"));
    let (dt, mut text) = step_text(spec, &scene, fraction_given(""));
    for stage in &scene.stages {
        let (stage_dt, stage_text) =
            step_text(spec, &scene.in_stage(stage), fraction_given(&format!("stages.{}.", stage.name)));
        if stage_dt != dt {
            let _ = write!(text, "; in stage \"{}\": {stage_text}", stage.name);
        }
    }
    text
}

/// The time step `scene` runs with, and its text: `time step DT s (F of the contact time)`, the
/// fraction left out where `fraction_given`.
fn step_text(spec: &TuneSpec, scene: &SceneConfig, fraction_given: bool) -> (f64, String) {
    let disks = spec.initial.as_deref().map(Vec::as_slice);
    let dt = crate::physics::scene_time_step(scene, disks).dt;
    let text = match super::validity::predicted_report(scene, disks).map(|r| r.dt_over_contact_time) {
        Ok(f) if !fraction_given => format!("time step {} s ({} of the contact time)", short(dt), short(f)),
        _ => format!("time step {} s", short(dt)),
    };
    (dt, text)
}

/// The 95 % upper bound of a rate seen `failed` times in `n` trials (Clopper-Pearson).
pub fn rate_upper_bound(failed: usize, n: usize) -> f64 {
    if n == 0 || failed >= n {
        return 1.0;
    }
    // P(X ≤ failed | n, p) = 0.05, by bisection on p (the binomial tail falls as p grows).
    let tail = |p: f64| {
        let mut term = (1.0 - p).powi(n as i32);
        let mut sum = term;
        for k in 0..failed {
            term *= (n - k) as f64 / (k + 1) as f64 * p / (1.0 - p);
            sum += term;
        }
        sum
    };
    let (mut low, mut high) = (failed as f64 / n as f64, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (low + high);
        if tail(mid) > 0.05 { low = mid } else { high = mid }
    }
    high
}

/// The whole cost of the tune in mean reference runs.
pub fn spend(result: &SearchResult) -> f64 {
    let reference = stats::describe(&result.reference_costs()).mean;
    let runs =
        result.reference.iter().chain(result.candidates.iter().flat_map(|c| c.runs.iter().chain(&c.verification)));
    runs.map(|o| o.cost).sum::<f64>() / reference
}

/// Runs by role, in words that add up: `211 runs: 10 reference, 9 standard settings (2 cut once they
/// could no longer win), 180 search (12 cut …, 3 failed: did not settle), 12 verification`.
pub fn run_counts(result: &SearchResult) -> String {
    let runs = |standard: bool| -> Vec<&Outcome> {
        let of = result.candidates.iter().filter(|c| c.standard.is_some() == standard);
        of.flat_map(|c| &c.runs).collect()
    };
    let (standard, search) = (runs(true), runs(false));
    let verify: usize = result.candidates.iter().map(|c| c.verification.len()).sum();
    let search_text = match search.len() {
        0 => "no search run was made".to_string(),
        n => format!("{n} search{}", ended(&search)),
    };
    format!(
        "{} runs: {} reference, {} standard settings{}, {search_text}, {verify} verification",
        result.reference.len() + standard.len() + search.len() + verify,
        result.reference.len(),
        standard.len(),
        ended(&standard)
    )
}

/// How many of `runs` were cut and how many failed, and why: ` (2 cut once they could no longer
/// win; 3 failed: 2 did not settle, 1 diverged)`; empty when none.
fn ended(runs: &[&Outcome]) -> String {
    let cut = runs.iter().filter(|o| o.is_cut()).count();
    let mut why: Vec<(String, usize)> = Vec::new();
    for failure in runs.iter().filter_map(|o| o.failure.as_ref()).filter(|f| !matches!(f, RunFailure::Cut { .. })) {
        let name = match failure {
            RunFailure::NotSettled => "did not settle",
            RunFailure::Diverged(_) => "diverged",
            _ => "failed to run",
        };
        match why.iter_mut().find(|(n, _)| n == name) {
            Some((_, count)) => *count += 1,
            None => why.push((name.to_string(), 1)),
        }
    }
    let failed: usize = why.iter().map(|(_, c)| c).sum();
    let mut parts = Vec::new();
    if cut > 0 {
        parts.push(format!("{cut} cut once they could no longer win"));
    }
    if failed > 0 {
        let each: Vec<String> = why.iter().map(|(n, c)| format!("{c} {n}")).collect();
        parts.push(format!("{failed} failed: {}", each.join(", ")));
    }
    if parts.is_empty() { String::new() } else { format!(" ({})", parts.join("; ")) }
}

/// With wall time as the objective: how runs were priced, and each configuration's rate with its
/// spread between batches (empty otherwise).
fn wall_rate_lines(result: &SearchResult) -> String {
    if result.wall_rates.is_empty() {
        return String::new();
    }
    let mut text = String::from(
        "Wall time is priced as each run's particle-steps times its configuration's wall time per particle-step, \
         measured on the first batch that ran it (settings of one configuration compare as their particle-steps; \
         between configurations the ratio holds as far as the batches' rates agree):\n",
    );
    for r in &result.wall_rates {
        let spread = match r.batches {
            1 => "measured in one batch".to_string(),
            n => format!(
                "{}-{} ns between {n} batches ({}x)",
                short(r.low * 1e9),
                short(r.high * 1e9),
                short(r.high / r.low)
            ),
        };
        let _ = writeln!(text, "- {}: {} ns per particle-step, {spread}", r.configuration, short(r.rate * 1e9));
    }
    text
}

/// The answer sheet: the recommendation (or why there is none) first, then what it was checked on.
/// `out_dir`: the `--out` folder the tune was given, which the `--resume` command it suggests names.
pub fn paragraph(spec: &TuneSpec, result: &SearchResult, out_dir: Option<&Path>) -> String {
    if !result.undecidable.is_empty() {
        return undecidable_text(spec, result);
    }
    let mut text = reference_breaks(result);
    let objective = spec.search.objective.name();
    let reference = result.reference_costs();
    let evaluated = result.candidates.iter().filter(|c| !c.runs.is_empty()).count();
    let skipped = result.candidates.iter().filter(|c| c.predicted_invalid.is_some()).count();
    let spent = spend(result);
    let budget_line = format!(
        "{} The tune evaluated {evaluated} settings ({skipped} more were predicted to break a validity limit and \
         not run) in {} of a budget of {} runs, and spent {} reference depositions ({objective}; limit {}); the \
         reference ran on seeds {}.",
        path_line(spec, result),
        run_counts(result),
        result.budget,
        short(spent),
        short(spec.search.max_spend),
        seed_text(spec, &(0..result.reference.len() as u64).collect::<Vec<_>>())
    );
    match result.recommended {
        Some(k) => {
            let cand = &result.candidates[k];
            let costs: Vec<f64> = cand.verification.iter().map(|o| o.cost).collect();
            let ratio = stats::ratio_interval(&reference, &costs);
            let _ = writeln!(
                text,
                "Recommendation for {}: {} (candidate {}), as resolved: {}.",
                spec.name,
                settings(spec, cand),
                cand.id,
                resolved_time_step(spec, cand)
            );
            let undecided = undecided_lines(spec, result, result.assess(cand).cost, out_dir);
            if cand.standard.is_some() {
                let searched = result.candidates.iter().any(|c| c.standard.is_none() && !c.runs.is_empty());
                text.push_str(match (searched, undecided.is_empty()) {
                    (true, true) => "The search found nothing cheaper than this standard setting: it is the answer.\n",
                    (true, false) => {
                        "The search left cheaper settings undecided: this standard setting is the answer so far.\n"
                    }
                    (false, _) => "No search run was made: this standard setting is the answer.\n",
                });
            }
            text.push_str(&undecided);
            let _ = writeln!(
                text,
                "Cost ({objective}, on the fresh verification seeds): {} of the reference (95 % interval {}-{}), a \
                 speedup of {}x; {}.",
                short(ratio.ratio),
                short(ratio.low),
                short(ratio.high),
                short(1.0 / ratio.ratio),
                against_standard(spec, result, &costs)
            );
            let _ = writeln!(text, "{}", payback(result, ratio.ratio, spent));
            text.push_str(&wall_rate_lines(result));
            let _ = writeln!(
                text,
                "Pile metrics, recommendation minus reference with 90 % interval and in the reference's \
                 seed-to-seed spread (σ):"
            );
            text.push_str(&pile_lines(spec, result, cand));
            text.push_str(&check_lines(result, cand));
            text.push_str(&bound_line(spec, cand));
            let runs = cand.runs.len() + cand.verification.len();
            let unsettled = cand.runs.iter().chain(&cand.verification).filter(|o| o.failure.is_some()).count();
            let _ = writeln!(
                text,
                "Runs that did not settle: {unsettled} of its {runs} runs (95 % upper bound on the rate: {} %).",
                short(100.0 * rate_upper_bound(unsettled, runs))
            );
            let checks = result.assess_verification(cand).map(|a| a.checks).unwrap_or_default();
            let _ = writeln!(text, "{}", validity_line(spec, cand, &checks));
            let _ = writeln!(
                text,
                "Verified on {} fresh placement seeds {} never used during the search. {budget_line}",
                cand.verification.len(),
                seed_text(spec, &cand.verify_seeds),
            );
        }
        None => {
            let _ = write!(text, "No acceptable setting was found for {}. ", spec.name);
            let failed_verification: Vec<&Candidate> =
                result.candidates.iter().filter(|c| !c.verification.is_empty()).collect();
            for cand in &failed_verification {
                let a = result.assess_verification(cand).expect("verified");
                if a.state == State::Feasible {
                    let _ = write!(
                        text,
                        "Candidate {} ({}) passed verification on seeds {} but cost {} of the reference there: it \
                         saves nothing. ",
                        cand.id,
                        settings(spec, cand),
                        seed_text(spec, &cand.verify_seeds),
                        short(a.cost / stats::describe(&reference).mean),
                    );
                    continue;
                }
                let _ = write!(
                    text,
                    "Candidate {} ({}) was equivalent during the search but failed verification on seeds {}: {}. ",
                    cand.id,
                    settings(spec, cand),
                    seed_text(spec, &cand.verify_seeds),
                    failure_reason(spec, result, &a)
                );
            }
            match result.closest() {
                Some(k) => {
                    let cand = &result.candidates[k];
                    let a = result.assess(cand);
                    let _ = write!(
                        text,
                        "The closest candidate was {} ({}): cost {} of the reference; {}; metrics: {}. ",
                        cand.id,
                        settings(spec, cand),
                        short(a.cost / stats::describe(&reference).mean),
                        failure_reason(spec, result, &a),
                        metric_lines(spec, result, &a)
                    );
                }
                None => {
                    let other = if failed_verification.is_empty() { "" } else { " other" };
                    let _ = write!(text, "No{other} candidate's runs all settled and passed the validity checks. ");
                }
            }
            text.push_str(&end_line(result.end, result.budget, spec.search.max_spend - spent));
            text.push_str(&budget_line);
            let undecided = undecided_lines(spec, result, result.reference_cost(), out_dir);
            if !undecided.is_empty() {
                text.push('\n');
                text.push_str(&undecided);
            }
        }
    }
    text.trim_end().to_string()
}

/// Why the search over the levers ended, as a sentence (empty when it did not start); `left`: the
/// reference depositions of the spend limit that the whole tune left unspent.
fn end_line(end: SearchEnd, budget: usize, left: f64) -> String {
    match end {
        SearchEnd::NotSearched => String::new(),
        SearchEnd::SpendLimit => format!(
            "The search ended with the spend limit too near for another setting's first seeds or the seeds \
             that would decide one, with a verification round in reserve: {} reference depositions were left. ",
            (10.0 * left.max(0.0)).floor() / 10.0
        ),
        SearchEnd::RunBudget => {
            format!("The search ended at the run budget ({budget} runs, less what verification keeps back). ")
        }
        SearchEnd::Exhausted => "The search ended when it proposed no new setting that could still win. ".into(),
    }
}

/// The recommendation's cost against the best valid standard setting's, with its interval.
fn against_standard(spec: &TuneSpec, result: &SearchResult, costs: &[f64]) -> String {
    match result.best_standard() {
        Some(s) if result.recommended == Some(s) => "it is the best valid standard setting".into(),
        Some(s) => {
            let standard = &result.candidates[s];
            let runs: Vec<f64> = standard.runs.iter().chain(&standard.verification).map(|o| o.cost).collect();
            let r = stats::ratio_interval(&runs, costs);
            format!(
                "{} of the best valid standard setting, {} (95 % interval {}-{})",
                short(r.ratio),
                spec.standards[standard.standard.unwrap_or(0)].name,
                short(r.low),
                short(r.high)
            )
        }
        None => "no standard setting was both valid and equivalent to the reference".into(),
    }
}

/// After how many depositions the answer has saved more than the tune cost.
fn payback(result: &SearchResult, ratio: f64, spent: f64) -> String {
    let count = |saving: f64| if saving > 0.0 { short((spent / saving).ceil()) } else { "never".into() };
    let reference = stats::describe(&result.reference_costs()).mean;
    let standard = result.best_standard().map(|s| result.assess(&result.candidates[s]).cost / reference);
    let against = match standard {
        _ if result.recommended.is_some() && result.recommended == result.best_standard() => {
            " (it is the best standard setting: no search was needed to find it)".to_string()
        }
        Some(s) => format!(", {} against the best standard setting", count(s - ratio)),
        None => String::new(),
    };
    format!(
        "Payback: the tune spent {} reference depositions; it has saved more than that after {} depositions \
         against the reference{against}.",
        short(spent),
        count(1.0 - ratio)
    )
}

/// Every pile metric of the summary, kept or not: the recommendation's verification runs against the
/// reference, flagged beyond 2σ of the reference's spread.
fn pile_lines(spec: &TuneSpec, result: &SearchResult, cand: &Candidate) -> String {
    let names = super::file::keepable_metrics();
    let mut text = String::new();
    let pile = |name: &str| PILE_METRICS.iter().any(|q| q.name == name);
    for (k, name) in names.iter().enumerate().filter(|(_, n)| pile(n)) {
        let column = |runs: &[super::Outcome]| runs.iter().filter_map(|o| o.pile.get(k).copied()).collect::<Vec<f64>>();
        let (reference, runs) = (column(&result.reference), column(&cand.verification));
        if reference.iter().chain(&runs).any(|x| !x.is_finite()) || reference.len() < 2 || runs.len() < 2 {
            continue;
        }
        let spread = stats::describe(&reference).std;
        let t = stats::equivalence(&reference, &runs, f64::INFINITY);
        let sigmas = if spread > 0.0 { t.difference / spread } else { t.difference * f64::INFINITY };
        let kept = spec.keep.iter().position(|keep| keep.metric == *name);
        let tolerance = kept.map(|i| format!(", kept within ±{}", short(result.margins[i]))).unwrap_or_default();
        let flag = match (sigmas.abs() > 2.0, kept) {
            (false, _) => String::new(),
            (true, Some(_)) => " — beyond 2σ".into(),
            (true, None) => format!(
                " — beyond 2σ; to hold it within 2σ, add `{name} = {{ absolute = {} }}` to [keep]",
                short(2.0 * spread)
            ),
        };
        let in_sigmas =
            if sigmas.is_finite() { format!("{}σ", short(sigmas)) } else { "the reference does not vary".into() };
        let _ = writeln!(
            text,
            "  {name}: {} ({} to {}), {in_sigmas}{tolerance}{flag}",
            short(t.difference),
            short(t.low),
            short(t.high),
        );
    }
    text
}

/// The levers that sit on a bound of their range.
fn bound_line(spec: &TuneSpec, cand: &Candidate) -> String {
    let edge = 1.0 / super::design::QUANT;
    let on: Vec<String> = spec
        .levers
        .iter()
        .zip(&cand.point)
        .filter(|(l, _)| !matches!(l.range, super::LeverRange::List(_)))
        .filter_map(|(l, &u)| {
            let end = if u <= edge {
                "low"
            } else if u >= 1.0 - edge {
                "high"
            } else {
                return None;
            };
            Some(format!("{} at the {end} end of its range ({})", l.key, l.value(u)))
        })
        .collect();
    if on.is_empty() { String::new() } else { format!("Levers on a range bound: {}.\n", on.join("; ")) }
}

/// The per-run quantities that are not pile metrics (settle time, final energies, energy-balance
/// error, largest overlap): shown as checks, the recommendation's verification mean and largest
/// against the reference's, never in units of the reference's spread.
fn check_lines(result: &SearchResult, cand: &Candidate) -> String {
    let names = super::file::keepable_metrics();
    let mut text =
        String::from("Checks (not pile metrics), reference mean and largest against the recommendation's:\n");
    for (k, name) in names.iter().enumerate().filter(|(_, n)| !PILE_METRICS.iter().any(|q| q.name == n.as_str())) {
        let column =
            |runs: &[Outcome]| stats::describe(&runs.iter().filter_map(|o| o.pile.get(k).copied()).collect::<Vec<_>>());
        let (r, c) = (column(&result.reference), column(&cand.verification));
        if r.n == 0 || c.n == 0 {
            continue;
        }
        let _ = writeln!(
            text,
            "  {name}: {} (largest {}) against {} (largest {})",
            short(r.mean),
            short(r.max),
            short(c.mean),
            short(c.max)
        );
    }
    text
}

/// The validity rule and each check's figure over the recommendation's verification runs, with its
/// worst run and the limit it was held to.
fn validity_line(spec: &TuneSpec, cand: &Candidate, checks: &[CheckFigure]) -> String {
    let figures: Vec<String> = checks
        .iter()
        .map(|c| {
            let seed = cand.verify_seeds.get(c.worst_run).map(|&s| seed_text(spec, &[s])).unwrap_or_default();
            let held = if c.held_to > c.limit {
                format!(", the reference's own figure (limit {})", short(c.limit))
            } else {
                String::new()
            };
            format!(
                "{} ({}): figure {}, worst run {} (seed {seed}), held to {}{held}",
                c.kind.name(),
                c.kind.limit_key(),
                short(c.figure),
                short(c.worst),
                short(c.held_to)
            )
        })
        .collect();
    format!(
        "Validity over its {} verification runs (rule: a measured check's 75th percentile within its limit and no \
         run beyond twice it; a predicted check within its limit on every run; a limit the reference breaks is \
         replaced by the reference's own figure): {}.",
        cand.verification.len(),
        if figures.is_empty() { "no check reported".to_string() } else { figures.join("; ") }
    )
}

/// Up front, loudly: the rules of thumb the reference itself breaks, and that candidates are held
/// to no worse than it on them (empty when it breaks none).
pub fn reference_breaks(result: &SearchResult) -> String {
    let broken = broken_by_reference(&result.reference_checks);
    if broken.is_empty() {
        return String::new();
    }
    let each: Vec<String> = broken
        .iter()
        .map(|c| format!("{} {} against {} ({})", c.kind.name(), short(c.figure), short(c.limit), c.kind.limit_key()))
        .collect();
    format!(
        "WARNING: the reference itself breaks {} rule(s) of thumb: {}. Every candidate is held to no worse than the \
         reference on {}.\n",
        broken.len(),
        each.join("; "),
        if broken.len() == 1 { "it" } else { "them" }
    )
}

/// How the time-step path ended, in one sentence.
fn path_line(spec: &TuneSpec, result: &SearchResult) -> String {
    let (rungs, end) = &result.path;
    let fractions: Vec<String> = rungs.iter().map(|&k| resolved_time_step(spec, &result.candidates[k])).collect();
    let tried = if fractions.is_empty() { String::new() } else { format!(" (tried: {})", fractions.join("; ")) };
    match end {
        PathEnd::NotRun => "The time-step path did not run.".into(),
        PathEnd::Verified(k) => {
            format!("The time-step path ended at candidate {}, verified{tried}.", result.candidates[*k].id)
        }
        PathEnd::NothingCheaper => {
            format!(
                "The time-step path found no time step cheaper than the reference's that is valid and equivalent{tried}."
            )
        }
        PathEnd::OutOfBudget => format!("The spend limit or the run budget stopped the time-step path{tried}."),
        PathEnd::Undecided(k) => {
            let cand = &result.candidates[*k];
            let why = result.assess_verification(cand).map(|a| failure_reason(spec, result, &a)).unwrap_or_default();
            format!(
                "The time-step path stopped at candidate {}: on {} fresh seeds {why}, more than the spend limit \
                 leaves{tried}.",
                cand.id,
                cand.verification.len()
            )
        }
    }
}

/// Why the tune stopped before searching: a kept metric the reference's own spread cannot decide.
fn undecidable_text(spec: &TuneSpec, result: &SearchResult) -> String {
    let mut text = format!(
        "Cannot decide for {}: after the {} reference runs, stopped before searching (nothing else was run).",
        spec.name,
        result.reference.len()
    );
    for u in &result.undecidable {
        let keep = &spec.keep[u.metric];
        let relative = |m: f64| {
            if u.mean != 0.0 { format!(" ({} % of the mean)", short(100.0 * m / u.mean.abs())) } else { String::new() }
        };
        let seeds = match u.seeds_needed {
            Some(n) => format!("the asked tolerance would need about {n} seeds per candidate (search.max_seeds)"),
            None => "no number of candidate seeds would decide the asked tolerance with this reference: it needs \
                     more seeds too (search.reference_seeds)"
                .into(),
        };
        let _ = write!(
            text,
            " {}: the reference spreads {} between seeds{} against a tolerance of ±{}{}; with search.max_seeds = {} \
             the smallest decidable tolerance is ±{}{}; {seeds}.",
            keep.metric,
            short(u.spread),
            relative(u.spread),
            short(u.margin),
            relative(u.margin),
            spec.search.max_seeds,
            short(u.decidable_margin),
            relative(u.decidable_margin),
        );
    }
    text
}

/// `metric difference (low to high, tolerance ±m) decision; ...`.
fn metric_lines(spec: &TuneSpec, result: &SearchResult, a: &Assessment) -> String {
    if a.tests.is_empty() {
        return "not compared (a run failed)".into();
    }
    spec.keep
        .iter()
        .zip(&a.tests)
        .zip(&result.margins)
        .map(|((keep, t), m)| {
            format!(
                "{} {} ({} to {}, tolerance ±{}) {}",
                keep.metric,
                short(t.difference),
                short(t.low),
                short(t.high),
                short(*m),
                decision_name(t.decision)
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

fn decision_name(d: stats::Decision) -> &'static str {
    match d {
        stats::Decision::Equivalent => "equivalent",
        stats::Decision::Different => "different",
        stats::Decision::Undecided => "undecided",
    }
}

/// The cheapest candidates (up to [`UNDECIDED_LISTED`]) that cost less than `bound` in the search
/// and were left undecided, unverified: each with its cost, the metric, the seeds a side that would
/// decide it and the `max_spend` that pays for them and a verification on as many fresh seeds; then
/// the command that continues from the stored runs (with `--out` where the tune was given one).
/// Empty when there are none.
fn undecided_lines(spec: &TuneSpec, result: &SearchResult, bound: f64, out_dir: Option<&Path>) -> String {
    // Undecided in the search and not verified, or on its fresh seeds.
    let standing = |c: &Candidate| result.assess_verification(c).unwrap_or_else(|| result.assess(c));
    let mut open: Vec<(&Candidate, Assessment)> = result
        .candidates
        .iter()
        .map(|c| (c, standing(c)))
        .filter(|(_, a)| a.state == State::Undecided && a.cost < bound && !a.tests.is_empty())
        .collect();
    open.sort_by(|x, y| x.1.cost.total_cmp(&y.1.cost).then(x.0.id.cmp(&y.0.id)));
    let (spent, reference) = (spend(result), result.reference_cost());
    let mut text = String::new();
    let mut most: f64 = 0.0;
    for (cand, a) in open.iter().take(UNDECIDED_LISTED) {
        let Some((k, t)) = worst_test(result, a) else { continue };
        let cost = a.cost / reference;
        let verified = !cand.verification.is_empty();
        let _ = write!(
            text,
            "Undecided, cheaper: candidate {} ({}) at {} of the reference on {} {}seeds, {} undecided (difference {}, \
             90 % interval {} to {}, tolerance ±{})",
            cand.id,
            settings(spec, cand),
            short(cost),
            a.n,
            if verified { "fresh verification " } else { "" },
            spec.keep[k].metric,
            short(t.difference),
            short(t.low),
            short(t.high),
            short(result.margins[k])
        );
        match t.seeds_needed {
            Some(n) => {
                let more = n.saturating_sub(a.n) as f64 * cost + n.saturating_sub(result.reference.len()) as f64;
                let verify = if verified { 0.0 } else { n.max(spec.search.verify_seeds()) as f64 * cost };
                let needed = (10.0 * (spent + PRICE_MARGIN * (more + verify))).ceil() / 10.0;
                most = most.max(needed);
                let _ = writeln!(
                    text,
                    ": about {n} seeds a side, the reference's included, would decide it; {} needs max_spend = {}.",
                    if verified { "that" } else { "with its verification on as many fresh seeds that" },
                    short(needed)
                );
            }
            None => {
                let _ = writeln!(text, ": no number of seeds would decide it.");
            }
        }
    }
    if most > spec.search.max_spend {
        let _ = writeln!(
            text,
            "`demsweep tune {}{} --resume --max-spend {}` continues from the stored runs, repeating none.",
            spec.path.display(),
            out_dir.map_or(String::new(), |d| format!(" --out {}", d.display())),
            short(most)
        );
    }
    text
}

/// Most undecided cheaper candidates the answer sheet lists.
const UNDECIDED_LISTED: usize = 2;

/// The kept metric furthest from equivalence (|difference| over its margin) among those not
/// equivalent, with its test.
fn worst_test<'a>(result: &SearchResult, a: &'a Assessment) -> Option<(usize, &'a stats::Equivalence)> {
    a.tests
        .iter()
        .zip(&result.margins)
        .enumerate()
        .filter(|(_, (t, _))| t.decision != stats::Decision::Equivalent)
        .max_by(|x, y| (x.1.0.difference.abs() / x.1.1).total_cmp(&(y.1.0.difference.abs() / y.1.1)))
        .map(|(k, (t, _))| (k, t))
}

/// Why an assessment is not acceptable, naming the failing metric.
pub fn failure_reason(spec: &TuneSpec, result: &SearchResult, a: &Assessment) -> String {
    match &a.state {
        State::NotRun(reason) => format!("not run: {reason}"),
        State::Feasible if a.cost >= result.reference_cost() => {
            "valid and equivalent, but no cheaper than the reference (only cheaper settings are verified)".into()
        }
        State::Feasible => "acceptable during the search, but the budget ran out before it was verified".into(),
        State::Cut => {
            "cut: its runs were stopped at their cost cap once it could no longer win, before they settled".into()
        }
        State::Infeasible(reason @ (Rejection::Failed(_) | Rejection::Invalid(_))) => reason.to_string(),
        _ => match worst_test(result, a) {
            Some((k, t)) => format!(
                "{} is {} (difference {}, 90 % interval {} to {}, tolerance ±{}{})",
                spec.keep[k].metric,
                decision_name(t.decision),
                short(t.difference),
                short(t.low),
                short(t.high),
                short(result.margins[k]),
                t.seeds_needed
                    .map(|n| format!("; about {n} seeds a side, the reference's included, would decide it"))
                    .unwrap_or_default()
            ),
            None => a.state.name().into(),
        },
    }
}

/// The files [`write_all`] writes into `dir` (the charts aside): `<name>_candidates.csv`,
/// `<name>_skipped.csv` (each with its sidecar), `<name>_best.toml`, `<name>_scene_change.toml`
/// and `<name>_recommendation.txt`.
pub fn files(spec: &TuneSpec, dir: &Path) -> [PathBuf; 5] {
    ["candidates.csv", "skipped.csv", "best.toml", "scene_change.toml", "recommendation.txt"]
        .map(|what| dir.join(format!("{}_{what}", spec.name)))
}

/// Writes `<name>_candidates.csv`, `<name>_best.toml` (when there is a recommendation), the charts and
/// `<name>_recommendation.txt` into `dir` ([`files`]), replacing files there as `existing` allows (the
/// text files stamped as demsweep's: [`guard::stamp`]).
pub fn write_all(
    spec: &TuneSpec,
    result: &SearchResult,
    dir: &Path,
    text: &str,
    existing: Existing,
) -> Result<Written, WriteError> {
    let mut written = Written::default();
    std::fs::create_dir_all(dir).map_err(|error| WriteError::CreateDir { dir: dir.to_path_buf(), error })?;
    let [csv, skipped, best, change, note] = files(spec, dir);
    write_records(&candidate_records(spec, result), &csv, existing)?;
    write_records(&skipped_records(spec, result), &skipped, existing)?;
    written.files.extend([csv, skipped]);
    let mut write = |path: PathBuf, text: &str| -> Result<(), WriteError> {
        guard::write_with(&path, &[], existing, |out| out.write_all(guard::stamp(text).as_bytes()))?;
        written.files.push(path);
        Ok(())
    };
    if let Some(k) = result.recommended {
        write(best, &best_study(spec, result, k))?;
        write(change, &scene_change(spec, &result.candidates[k]))?;
    }
    write(note, &format!("{text}\n"))?;
    let plots = dir.join("plots");
    let options = ChartOptions { format: Format::Png, subject: Some(spec.name.clone()), ..Default::default() };
    let (points, recommended) = cost_points(result);
    let chart = plots.join(format!("{}_cost_vs_difference.png", spec.name));
    match cost_vs_difference_chart(&points, recommended, &options, &chart) {
        Ok(()) => written.files.push(chart),
        Err(e) => written.chart_errors.push(e),
    }
    let series = lever_series(spec, result);
    let chart = plots.join(format!("{}_cost_along_levers.png", spec.name));
    match cost_along_levers_chart(&series, &options, &chart) {
        Ok(()) => written.files.push(chart),
        Err(e) => written.chart_errors.push(e),
    }
    Ok(written)
}

/// One point per evaluated candidate: (largest |difference|/tolerance, cost ratio, feasible).
fn cost_points(result: &SearchResult) -> (Vec<CostPoint>, Option<CostPoint>) {
    let reference = stats::describe(&result.reference_costs()).mean;
    let point = |c: &Candidate| {
        let a = result.assess(c);
        CostPoint {
            worst: if a.worst.is_finite() { a.worst } else { f64::NAN },
            cost_ratio: a.cost / reference,
            feasible: a.state == State::Feasible,
            failed: a.tests.is_empty(),
        }
    };
    let points = result.candidates.iter().filter(|c| !c.runs.is_empty()).map(point).collect();
    (points, result.recommended.map(|k| point(&result.candidates[k])))
}

/// Per lever: every candidate that ran (standard settings at the values their scene has), the
/// reference's value and the recommendation's.
fn lever_series(spec: &TuneSpec, result: &SearchResult) -> Vec<LeverSeries> {
    let reference = result.reference_cost();
    let number = |v: &ParamValue| match v {
        ParamValue::Float(x) => Some(*x),
        ParamValue::Int(i) => Some(*i as f64),
        _ => None,
    };
    let reference_values = spec.reference_values();
    let at = |c: &Candidate, d: usize| lever_values(spec, c)[d].as_ref().and_then(number);
    spec.levers
        .iter()
        .enumerate()
        .map(|(d, lever)| {
            let points = result
                .candidates
                .iter()
                .filter(|c| !c.runs.is_empty())
                .filter_map(|c| {
                    let a = result.assess(c);
                    Some((at(c, d)?, a.cost / reference, a.state == State::Feasible))
                })
                .collect();
            let best = result.recommended.and_then(|k| at(&result.candidates[k], d));
            let reference = reference_values.iter().find(|(k, _, _)| *k == lever.key).and_then(|(_, v, _)| number(v));
            LeverSeries { name: lever.key.clone(), log: lever.is_log(), points, best, reference }
        })
        .collect()
}

/// Each lever's value in a candidate's runs: the value it sets, else the reference's (a standard
/// setting sets only some levers); None where the reference has none.
fn lever_values(spec: &TuneSpec, cand: &Candidate) -> Vec<Option<ParamValue>> {
    let set = spec.setting_values(&cand.point, cand.standard);
    let reference = spec.reference_values();
    let value = |key: &str| {
        let given = set.iter().find(|(k, _)| k == key).map(|(_, v)| v.clone());
        given.or_else(|| reference.iter().find(|(k, _, _)| k == key).map(|(_, v, _)| v.clone()))
    };
    spec.levers.iter().map(|l| value(&l.key)).collect()
}

/// Writes a table as CSV (the column names, then the rows), whole or not at all
/// ([`guard::write_with`]), and its metadata sidecar (units, datatypes from the cells' types).
fn write_records(table: &Table, path: &Path, existing: Existing) -> Result<(), guard::GuardError> {
    let columns: Vec<csv::ColumnMeta> =
        table.columns.iter().enumerate().map(|(k, name)| csv::ColumnMeta::declared(name, table.datatype(k))).collect();
    csv::write_file(path, &columns, existing, |out| {
        csv::write_record(&mut *out, &table.columns)?;
        table.rows.iter().try_for_each(|row| {
            let fields: Vec<String> = row.iter().map(ToString::to_string).collect();
            csv::write_record(&mut *out, &fields)
        })
    })
}

/// The settings that were not run (`<name>_skipped.csv`): candidate, origin, settings and why.
pub fn skipped_records(spec: &TuneSpec, result: &SearchResult) -> Table {
    let columns = ["candidate", "origin", "settings", "reason"].map(String::from).to_vec();
    let rows = result.candidates.iter().filter(|c| c.runs.is_empty()).map(|c| {
        let reason = match &c.predicted_invalid {
            Some(why) => why.to_string(),
            None => "not run: the budget or the spend limit ran out first".into(),
        };
        vec![Cell::Whole(c.id as i64), Cell::text(c.origin.name()), Cell::Text(settings(spec, c)), Cell::Text(reason)]
    });
    Table { columns, rows: rows.collect() }
}

/// The recommendation as a change to the tune file: the `[scene]` keys to set, levers only.
pub fn scene_change(spec: &TuneSpec, cand: &Candidate) -> String {
    let values = spec.setting_values(&cand.point, cand.standard);
    let mut text = format!(
        "# The recommendation of `demsweep tune {}` as a change to its [scene] table: set these keys\n",
        spec.path.display()
    );
    text.push_str("[scene]\n");
    for (key, value) in values.iter().filter(|(key, _)| in_stage(key).is_none()) {
        let _ = writeln!(text, "{} = {}", key, value.to_toml());
    }
    // A stage's keys belong in its own [[scene.stages]] table, which a [scene] table cannot name.
    let mut stages: Vec<&str> = values.iter().filter_map(|(key, _)| Some(in_stage(key)?.0)).collect();
    stages.dedup();
    for stage in stages {
        let _ = writeln!(text, "# and in the stage named {stage:?} (its [[scene.stages]] table):");
        for (key, value) in &values {
            if let Some((_, inner)) = in_stage(key).filter(|(name, _)| *name == stage) {
                let _ = writeln!(text, "#   {} = {}", inner, value.to_toml());
            }
        }
    }
    text
}

/// The stage and the key within it of a stage's key (`stages.NAME.KEY`).
fn in_stage(key: &str) -> Option<(&str, &str)> {
    key.strip_prefix("stages.")?.split_once('.')
}

/// The candidates table (`<name>_candidates.csv`): the reference, then every setting that ran with
/// its levers, n, cost (the objective's mean, and its ratio to the reference's), metric means,
/// decisions and verification (the settings not run are in [`skipped_records`]).
pub fn candidate_records(spec: &TuneSpec, result: &SearchResult) -> Table {
    let reference = stats::describe(&result.reference_costs());
    let mut columns: Vec<String> = vec!["candidate".into(), "origin".into()];
    columns.extend(spec.levers.iter().map(|l| l.key.clone()));
    columns.extend(["n".into(), format!("{}_mean", spec.search.objective.name()), "cost_ratio".into()]);
    for keep in &spec.keep {
        columns.extend([
            format!("{}_mean", keep.metric),
            format!("{}_difference", keep.metric),
            format!("{}_decision", keep.metric),
        ]);
    }
    columns.extend([
        "worst_difference_over_tolerance".into(),
        "decision".into(),
        "reason".into(),
        "verify_n".into(),
        "verify_cost_ratio".into(),
        "verify_decision".into(),
        "recommended".into(),
    ]);
    let mean_of = |runs: &[super::Outcome], k: usize| {
        stats::describe(&runs.iter().map(|o| o.metrics[k]).collect::<Vec<_>>()).mean
    };
    let count = |n: usize| Cell::Whole(n as i64);
    let reference_row: Vec<Cell> =
        {
            let mut row = vec![Cell::Whole(0), Cell::text("reference")];
            let values = spec.reference_values();
            row.extend(spec.levers.iter().map(|l| {
                values.iter().find(|(k, _, _)| *k == l.key).map_or(Cell::Empty, |(_, v, _)| Cell::of_param(v))
            }));
            row.extend([count(result.reference.len()), Cell::number(reference.mean), Cell::Number(1.0)]);
            for k in 0..spec.keep.len() {
                row.extend([Cell::number(mean_of(&result.reference, k)), Cell::Number(0.0), Cell::Empty]);
            }
            row.extend([Cell::Number(0.0), Cell::text("reference")]);
            row.extend(std::iter::repeat_n(Cell::Empty, 5));
            row
        };
    let mut rows = vec![reference_row];
    for (index, cand) in result.candidates.iter().enumerate().filter(|(_, c)| !c.runs.is_empty()) {
        let a = result.assess(cand);
        let mut row = vec![count(cand.id), Cell::text(cand.origin.name())];
        row.extend(lever_values(spec, cand).iter().map(|v| v.as_ref().map_or(Cell::Empty, Cell::of_param)));
        row.extend([count(a.n), Cell::number(a.cost), Cell::number(a.cost / reference.mean)]);
        for k in 0..spec.keep.len() {
            let mean = Cell::number(if cand.runs.is_empty() { f64::NAN } else { mean_of(&cand.runs, k) });
            match a.tests.get(k) {
                Some(t) => row.extend([mean, Cell::number(t.difference), Cell::text(decision_name(t.decision))]),
                None => row.extend([mean, Cell::Empty, Cell::Empty]),
            }
        }
        let reason = match &a.state {
            State::Feasible => Cell::Empty,
            _ => Cell::Text(failure_reason(spec, result, &a)),
        };
        row.extend([Cell::number(a.worst), Cell::text(a.state.name()), reason]);
        match result.assess_verification(cand) {
            Some(v) => row.extend([count(v.n), Cell::number(v.cost / reference.mean), Cell::text(v.state.name())]),
            None => row.extend([Cell::Empty, Cell::Empty, Cell::Empty]),
        }
        row.push(Cell::Flag(result.recommended == Some(index)));
        rows.push(row);
    }
    Table { columns, rows }
}

/// The tune's section of the report page: the recommendation, the cost-versus-deviation chart (SVG)
/// and the candidates table.
pub fn report_section(spec: &TuneSpec, result: &SearchResult, text: &str) -> Result<TuneSection, PlotError> {
    let options = ChartOptions { subject: Some(spec.name.clone()), ..Default::default() };
    let (points, recommended) = cost_points(result);
    let mut chart_svg = String::new();
    cost_vs_difference_chart(&points, recommended, &options, &mut chart_svg)?;
    let mut candidates = candidate_records(spec, result);
    candidates.columns.iter_mut().for_each(|name| *name = quantity::label(name));
    Ok(TuneSection { recommendation: text.to_string(), chart_svg, candidates })
}

/// A runnable study of the recommended scene: the reference scene with the lever values set, run on
/// the verification seeds.
pub fn best_study(spec: &TuneSpec, result: &SearchResult, k: usize) -> String {
    let cand = &result.candidates[k];
    let mut scene = spec.setting_tree(&cand.point, cand.standard).unwrap_or_else(|_| spec.base.clone());
    let first_seed = spec.reference.placement.seed.wrapping_add(cand.verify_seeds.first().copied().unwrap_or(0));
    let _ = crate::study::file::set_path(
        &mut scene,
        &["placement".to_string(), "seed".to_string()],
        toml::Value::Integer(first_seed as i64),
    );
    let mut doc = toml::Table::new();
    doc.insert("name".into(), toml::Value::String(format!("{}_best", spec.name)));
    doc.insert(
        "description".into(),
        toml::Value::String(format!(
            "the recommendation of `demsweep tune {}`: {}",
            spec.path.display(),
            settings(spec, cand)
        )),
    );
    doc.insert("scene".into(), toml::Value::Table(scene));
    let mut sweep = toml::Table::new();
    sweep.insert("replicates".into(), toml::Value::Integer(cand.verification.len().max(1) as i64));
    doc.insert("sweep".into(), toml::Value::Table(sweep));
    let header = format!(
        "# Written by `demsweep tune {}`: the reference scene with the recommended levers\n# ({}), \
         on its verification seeds. Run it with: demsweep run {}_best.toml\n",
        spec.path.display(),
        spec.levers.iter().map(|l| l.key.as_str()).collect::<Vec<_>>().join(", "),
        spec.name
    );
    format!("{header}{}", toml::to_string(&doc).unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tune::model::{Origin, PathEnd, SearchEnd};

    fn candidate(id: usize, standard: Option<usize>, runs: Vec<Outcome>) -> Candidate {
        Candidate {
            id,
            point: if standard.is_some() { Vec::new() } else { vec![0.5] },
            standard,
            identity: id.to_string(),
            origin: if standard.is_some() { Origin::Standard } else { Origin::Initial },
            predicted_invalid: None,
            runs,
            verification: Vec::new(),
            verify_seeds: Vec::new(),
            relative_cost: Some(0.5),
            stepped_from: None,
        }
    }

    fn result(candidates: Vec<Candidate>) -> SearchResult {
        SearchResult {
            reference: vec![Outcome::settled(1.0, vec![1.0]); 4],
            margins: vec![0.1],
            reference_checks: Vec::new(),
            candidates,
            recommended: None,
            runs: 0,
            budget: 100,
            undecidable: Vec::new(),
            path: (Vec::new(), PathEnd::NotRun),
            end: SearchEnd::NotSearched,
            wall_rates: Vec::new(),
        }
    }

    /// A tune whose levers are two stages' steps: a contact-time fraction and a time step.
    const STAGED: &str = r#"
[scene]
particles.count = 30
particles.radius = 0.005
domain.width = 0.1
domain.height = 0.15
material.youngs_modulus = 5e10
integrator.time_step = 7e-6
run.duration = 1.0
[[scene.stages]]
name = "fill"
until.time = 0.1
damping.local = 0.5
[[scene.stages]]
name = "calm"
until.time = 0.1
damping.local = 0.3
[levers]
"stages.fill.integrator.contact_time_fraction" = [0.02, 0.04]
"stages.calm.integrator.time_step" = [2e-6, 3e-6]
[keep]
pile_height = 0.25
"#;

    #[test]
    fn the_sheet_states_the_step_of_a_stage_whose_step_a_lever_sets() {
        let path = std::env::temp_dir().join(format!("demsweep-staged-tune-{}.toml", std::process::id()));
        std::fs::write(&path, STAGED).unwrap();
        let spec = crate::tune::load(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        let cand = Candidate { point: vec![0.0, 0.0], ..candidate(1, None, Vec::new()) };
        let scene = crate::tune::candidate_scene(&spec, &cand).unwrap();
        let dt = |k: usize| crate::physics::scene_time_step(&scene.in_stage(&scene.stages[k]), None).dt;
        let text = resolved_time_step(&spec, &cand);
        assert!(text.starts_with(&format!("time step {} s (", short(7e-6))), "{text}");
        assert!(text.contains(&format!("; in stage \"fill\": time step {} s;", short(dt(0)))), "{text}");
        assert!(text.contains(&format!("; in stage \"calm\": time step {} s (", short(2e-6))), "{text}");
        assert!(text.ends_with(" of the contact time)") && dt(0) != 7e-6 && dt(1) == 2e-6, "{text}");
    }

    #[test]
    fn the_sheet_says_why_the_search_ended_never_overstating_what_was_left() {
        assert_eq!(end_line(SearchEnd::NotSearched, 150, 14.0), "");
        let spend = end_line(SearchEnd::SpendLimit, 150, 6.27);
        assert!(spend.contains("spend limit") && spend.ends_with("6.2 reference depositions were left. "), "{spend}");
        assert!(end_line(SearchEnd::SpendLimit, 150, -0.3).contains(": 0 reference depositions were left"));
        assert!(end_line(SearchEnd::RunBudget, 150, 9.0).contains("the run budget (150 runs"));
        assert!(end_line(SearchEnd::Exhausted, 150, 9.0).contains("no new setting that could still win"));
    }

    #[test]
    fn run_counts_say_which_runs_failed_and_why_and_when_no_search_run_was_made() {
        let unsettled = Outcome { failure: Some(RunFailure::NotSettled), ..Outcome::settled(2.0, vec![1.0]) };
        let cut = Outcome { failure: Some(RunFailure::Cut { cap: 1.0 }), ..Outcome::settled(1.0, vec![1.0]) };
        let standard = candidate(1, Some(0), vec![unsettled.clone(), unsettled.clone(), cut.clone()]);
        let counts = run_counts(&result(vec![standard.clone()]));
        assert_eq!(
            counts,
            "7 runs: 4 reference, 3 standard settings (1 cut once they could no longer win; 2 failed: 2 did not \
             settle), no search run was made, 0 verification"
        );
        let searched = result(vec![standard, candidate(2, None, vec![cut.clone(), cut])]);
        assert!(run_counts(&searched).contains(", 2 search (2 cut once they could no longer win), "));
        let a = searched.assess(&searched.candidates[0]);
        assert!(matches!(a.state, State::Infeasible(Rejection::Failed(RunFailure::NotSettled))), "{:?}", a.state);
    }
}
