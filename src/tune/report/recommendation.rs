//! What the answer sheet says of a recommendation: its cost against the reference and the best
//! standard setting, the payback, its pile metrics and checks against the reference's, the levers on
//! a range bound, the runs that did not settle and its validity.

use std::fmt::Write as _;

use super::super::model::{Candidate, CheckFigure, Outcome, SearchResult};
use super::super::{LeverRange, TuneSpec, design, keepable_metrics, seed_text};
use crate::physics::number::short;
use crate::physics::quantity::PILE_METRICS;
use crate::stats;

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

/// With wall time as the objective: how runs were priced, and each configuration's rate with its
/// spread between batches (empty otherwise).
pub(super) fn wall_rate_lines(result: &SearchResult) -> String {
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

/// The recommendation's cost against the best valid standard setting's, with its interval.
pub(super) fn against_standard(spec: &TuneSpec, result: &SearchResult, costs: &[f64]) -> String {
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
pub(super) fn payback(result: &SearchResult, ratio: f64, spent: f64) -> String {
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
pub(super) fn pile_lines(spec: &TuneSpec, result: &SearchResult, cand: &Candidate) -> String {
    let names = keepable_metrics();
    let mut text = String::new();
    let pile = |name: &str| PILE_METRICS.iter().any(|q| q.name == name);
    for (k, name) in names.iter().enumerate().filter(|(_, n)| pile(n)) {
        let column = |runs: &[Outcome]| runs.iter().filter_map(|o| o.pile.get(k).copied()).collect::<Vec<f64>>();
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
pub(super) fn bound_line(spec: &TuneSpec, cand: &Candidate) -> String {
    let edge = 1.0 / design::QUANT;
    let on: Vec<String> = spec
        .levers
        .iter()
        .zip(&cand.point)
        .filter(|(l, _)| !matches!(l.range, LeverRange::List(_)))
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
pub(super) fn check_lines(result: &SearchResult, cand: &Candidate) -> String {
    let names = keepable_metrics();
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
pub(super) fn validity_line(spec: &TuneSpec, cand: &Candidate, checks: &[CheckFigure]) -> String {
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
