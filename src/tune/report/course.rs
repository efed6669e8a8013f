//! How the tune went, in the answer sheet's words: the rules of thumb the reference breaks, the
//! time-step path, why the search ended, why it could not start, and the cheaper settings it left
//! undecided.

use std::fmt::Write as _;
use std::path::Path;

use super::super::TuneSpec;
use super::super::judge::broken_by_reference;
use super::super::model::{Assessment, Candidate, PathEnd, SearchEnd, SearchResult, State};
use super::super::search::{KEPT_ROUNDS, PRICE_MARGIN};
use super::phrases::{decision_name, failure_reason, resolved_time_step, settings, spend, worst_test};
use crate::physics::number::short;

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
pub(super) fn path_line(spec: &TuneSpec, result: &SearchResult) -> String {
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

/// Why the search over the levers ended, as a sentence (empty when it did not start); `left`: the
/// reference depositions of the spend limit that the whole tune left unspent.
pub(super) fn end_line(end: SearchEnd, budget: usize, left: f64) -> String {
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

/// Why the tune stopped before searching: a kept metric the reference's own spread cannot decide.
pub(super) fn undecidable_text(spec: &TuneSpec, result: &SearchResult) -> String {
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
pub(super) fn metric_lines(spec: &TuneSpec, result: &SearchResult, a: &Assessment) -> String {
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

/// The cheapest candidates (up to [`UNDECIDED_LISTED`]) that cost less than `bound` in the search
/// and were left undecided, unverified: each with its cost, the metric, the seeds a side that would
/// decide it and the `max_spend` that pays for them and a verification on as many fresh seeds; then
/// the command that continues from the stored runs (with `--out` where the tune was given one).
/// Empty when there are none.
pub(super) fn undecided_lines(spec: &TuneSpec, result: &SearchResult, bound: f64, out_dir: Option<&Path>) -> String {
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
    let (mut most, mut most_runs): (f64, usize) = (0.0, 0);
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
                let (own, reference_runs) = (n.saturating_sub(a.n), n.saturating_sub(result.reference.len()));
                let more = own as f64 * cost + reference_runs as f64;
                let verify_runs = if verified { 0 } else { n.max(spec.search.verify_seeds()) };
                let needed = (10.0 * (spent + PRICE_MARGIN * (more + verify_runs as f64 * cost))).ceil() / 10.0;
                let runs = budget_to_decide(spec, result, own + reference_runs, verify_runs, verified);
                most = most.max(needed);
                let budget = if runs > result.budget {
                    most_runs = most_runs.max(runs);
                    format!(" and budget = {runs} (more runs than the run budget of {} leaves)", result.budget)
                } else {
                    String::new()
                };
                let _ = writeln!(
                    text,
                    ": about {n} seeds a side, the reference's included, would decide it; {} needs max_spend = {}{budget}.",
                    if verified { "that" } else { "with its verification on as many fresh seeds that" },
                    short(needed)
                );
            }
            None => {
                let _ = writeln!(text, ": no number of seeds would decide it.");
            }
        }
    }
    if most_runs > result.budget {
        let what = format!(
            "once `[search] budget = {most_runs}` is set in the file (the fresh verification seeds start past the \
             budget: a new budget draws new ones, so verifications run again on them)"
        );
        text.push_str(&resume_line(spec, out_dir, most.max(spec.search.max_spend), &what));
    } else if most > spec.search.max_spend {
        text.push_str(&resume_line(spec, out_dir, most, "repeating none"));
    }
    text
}

/// The run budget that pays for `searched` more search and reference runs and `verify_runs`
/// verification runs after the runs made so far: search runs stop [`KEPT_ROUNDS`] verification
/// rounds short of the budget, and a candidate verified already is decided on further fresh seeds
/// (`verified`, its further runs counted in `searched`).
fn budget_to_decide(
    spec: &TuneSpec,
    result: &SearchResult,
    searched: usize,
    verify_runs: usize,
    verified: bool,
) -> usize {
    let kept_back = if verified { 0 } else { KEPT_ROUNDS * spec.search.verify_seeds() };
    result.runs + searched + verify_runs.max(kept_back)
}

/// The candidates (up to [`UNDECIDED_LISTED`]) whose runs were cut before they settled at a cost
/// below `bound` (the answer's cost in the search, else the reference's): nothing shows they cost
/// more than the answer. Each with its cap; then the `max_spend` that runs them whole at `bound` and
/// verifies one, and the command that continues. Empty when there are none.
pub(super) fn cut_lines(spec: &TuneSpec, result: &SearchResult, bound: f64, out_dir: Option<&Path>) -> String {
    let mut open: Vec<(&Candidate, f64)> = result
        .candidates
        .iter()
        .filter(|c| result.assess(c).state == State::Cut)
        .filter_map(|c| Some((c, c.runs.iter().filter(|o| o.is_cut()).map(|o| o.cost).reduce(f64::max)?)))
        .filter(|&(_, cap)| cap < bound)
        .collect();
    open.sort_by(|x, y| x.1.total_cmp(&y.1).then(x.0.id.cmp(&y.0.id)));
    let reference = result.reference_cost();
    let mut text = String::new();
    for (cand, cap) in open.iter().take(UNDECIDED_LISTED) {
        let _ = writeln!(
            text,
            "Cut before it settled, perhaps cheaper: candidate {} ({}) on {} seed{}, cut at {} of the reference, \
             below the {} ({}).",
            cand.id,
            settings(spec, cand),
            cand.runs.len(),
            if cand.runs.len() == 1 { "" } else { "s" },
            short(cap / reference),
            if result.recommended.is_some() { "answer's cost in the search" } else { "reference's cost" },
            short(bound / reference)
        );
    }
    if !open.is_empty() {
        let listed = open.len().min(UNDECIDED_LISTED);
        let rounds = (listed * spec.search.seeds + spec.search.verify_seeds()) as f64;
        let needed = (10.0 * (spend(result) + PRICE_MARGIN * rounds * bound / reference)).ceil() / 10.0;
        text.push_str(&resume_line(spec, out_dir, needed, "with room to run them whole"));
    }
    text
}

/// The command that continues a tune from its stored runs with a larger spend limit.
fn resume_line(spec: &TuneSpec, out_dir: Option<&Path>, max_spend: f64, what: &str) -> String {
    format!(
        "`demsweep tune {}{} --resume --max-spend {}` continues from the stored runs, {what}.\n",
        spec.path.display(),
        out_dir.map_or(String::new(), |d| format!(" --out {}", d.display())),
        short(max_spend)
    )
}

/// Most undecided cheaper candidates the answer sheet lists.
const UNDECIDED_LISTED: usize = 2;
