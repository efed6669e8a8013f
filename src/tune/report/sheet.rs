//! The answer sheet: the recommendation (or why there is none) first, then what it was checked on.

use std::fmt::Write as _;
use std::path::Path;

use super::super::model::{Candidate, Outcome, RunFailure, SearchResult, State};
use super::super::{TuneSpec, seed_text};
use super::course::{
    cut_lines, end_line, metric_lines, path_line, reference_breaks, undecidable_text, undecided_lines,
};
use super::phrases::{failure_reason, resolved_time_step, settings, spend};
use super::recommendation::{
    against_standard, bound_line, check_lines, payback, pile_lines, rate_upper_bound, validity_line, wall_rate_lines,
};
use crate::physics::number::short;
use crate::stats;

/// The answer sheet: the recommendation (or why there is none) first, then what it was checked on.
/// `out_dir`: the `--out` folder the tune was given, which the `--resume` command it suggests names.
pub fn paragraph(spec: &TuneSpec, result: &SearchResult, out_dir: Option<&Path>) -> String {
    if !result.undecidable.is_empty() {
        return undecidable_text(spec, result);
    }
    let mut text = reference_breaks(result);
    let budget_line = budget_line(spec, result);
    match result.recommended {
        Some(k) => {
            let cand = &result.candidates[k];
            text.push_str(&recommendation_head(spec, result, cand, out_dir));
            text.push_str(&recommendation_cost(spec, result, cand));
            text.push_str(&recommendation_checks(spec, result, cand, &budget_line));
        }
        None => text.push_str(&no_recommendation(spec, result, &budget_line, out_dir)),
    }
    text.trim_end().to_string()
}

/// What the tune did: the time-step path, the settings evaluated and skipped, the runs by role, the
/// spend, the reference's seeds and those stepped over.
fn budget_line(spec: &TuneSpec, result: &SearchResult) -> String {
    let evaluated = result.candidates.iter().filter(|c| !c.runs.is_empty()).count();
    let skipped = result.candidates.iter().filter(|c| c.predicted_invalid.is_some()).count();
    let reference_seeds: Vec<u64> =
        (0..result.reference.len()).map(|p| result.replicates.get(p).copied().unwrap_or(p as u64)).collect();
    let mut text = format!(
        "{} The tune evaluated {evaluated} settings ({skipped} more were predicted to break a validity limit and \
         not run) in {} of a budget of {} runs, and spent {} reference depositions ({}; limit {}); the \
         reference ran on seeds {}.",
        path_line(spec, result),
        run_counts(result),
        result.budget,
        short(spend(result)),
        spec.search.objective.name(),
        short(spec.search.max_spend),
        seed_text(spec, &reference_seeds)
    );
    if !result.unplaceable.is_empty() {
        let seeds = if result.unplaceable.len() == 1 { "seed" } else { "seeds" };
        text.push_str(&format!(
            " No run was made on {seeds} {}: the reference's disks cannot be placed there (random placement near \
             its jamming limit), so they are no deposition of it.",
            seed_text(spec, &result.unplaceable)
        ));
    }
    text
}

/// The recommendation as resolved, whether a standard setting is the answer, and the cheaper
/// settings left undecided.
fn recommendation_head(spec: &TuneSpec, result: &SearchResult, cand: &Candidate, out_dir: Option<&Path>) -> String {
    let mut text = format!(
        "Recommendation for {}: {} (candidate {}), as resolved: {}.\n",
        spec.name,
        settings(spec, cand),
        cand.id,
        resolved_time_step(spec, cand)
    );
    let undecided = open_lines(spec, result, out_dir);
    if cand.standard.is_some() {
        let searched = result.candidates.iter().any(|c| c.standard.is_none() && !c.runs.is_empty());
        text.push_str(match (searched, undecided.is_empty()) {
            (true, true) => "The search found nothing cheaper than this standard setting: it is the answer.\n",
            (true, false) => {
                "The search left settings that may be cheaper undecided: this standard setting is the answer so \
                 far.\n"
            }
            (false, _) => "No search run was made: this standard setting is the answer.\n",
        });
    }
    text.push_str(&undecided);
    text
}

/// The recommendation's cost on the fresh verification seeds against the reference and the best
/// standard setting, its payback and, with wall time as the objective, the rates it was priced at.
fn recommendation_cost(spec: &TuneSpec, result: &SearchResult, cand: &Candidate) -> String {
    let costs: Vec<f64> = cand.verification.iter().map(|o| o.cost).collect();
    let ratio = stats::ratio_interval(&result.reference_costs(), &costs);
    let mut text = format!(
        "Cost ({}, on the fresh verification seeds): {} of the reference (95 % interval {}-{}), a speedup of {}x; \
         {}.\n",
        spec.search.objective.name(),
        short(ratio.ratio),
        short(ratio.low),
        short(ratio.high),
        short(1.0 / ratio.ratio),
        against_standard(spec, result, &costs)
    );
    let _ = writeln!(text, "{}", payback(result, ratio.ratio, spend(result)));
    text.push_str(&wall_rate_lines(result));
    text
}

/// What the recommendation was checked on: its pile metrics and checks against the reference's, the
/// levers on a range bound, the runs that did not settle, validity, the verification seeds and
/// `budget_line`.
fn recommendation_checks(spec: &TuneSpec, result: &SearchResult, cand: &Candidate, budget_line: &str) -> String {
    let mut text = String::from(
        "Pile metrics, recommendation minus reference with 90 % interval and in the reference's seed-to-seed \
         spread (σ):\n",
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
    text
}

/// Why there is no recommendation: the candidates that failed verification, the closest candidate,
/// why the search ended, `budget_line`, and the cheaper settings left undecided.
fn no_recommendation(spec: &TuneSpec, result: &SearchResult, budget_line: &str, out_dir: Option<&Path>) -> String {
    let mut text = format!("No acceptable setting was found for {}. ", spec.name);
    let failed_verification: Vec<&Candidate> =
        result.candidates.iter().filter(|c| !c.verification.is_empty()).collect();
    for cand in &failed_verification {
        text.push_str(&verification_failure(spec, result, cand));
    }
    text.push_str(&closest_line(spec, result, !failed_verification.is_empty()));
    text.push_str(&end_line(result.end, result.budget, spec.search.max_spend - spend(result)));
    text.push_str(budget_line);
    let undecided = open_lines(spec, result, out_dir);
    if !undecided.is_empty() {
        text.push('\n');
        text.push_str(&undecided);
    }
    text
}

/// Why a verified candidate is not the answer: it saved nothing on its fresh seeds, or failed there.
fn verification_failure(spec: &TuneSpec, result: &SearchResult, cand: &Candidate) -> String {
    let a = result.assess_verification(cand).expect("verified");
    if a.state == State::Feasible {
        return format!(
            "Candidate {} ({}) passed verification on seeds {} but cost {} of the reference there: it saves \
             nothing. ",
            cand.id,
            settings(spec, cand),
            seed_text(spec, &cand.verify_seeds),
            short(a.cost / stats::describe(&result.reference_costs()).mean),
        );
    }
    format!(
        "Candidate {} ({}) was equivalent during the search but failed verification on seeds {}: {}. ",
        cand.id,
        settings(spec, cand),
        seed_text(spec, &cand.verify_seeds),
        failure_reason(spec, result, &a)
    )
}

/// The closest candidate, its cost and why it failed; or that none ran clean (`other`: beside the
/// candidates that failed verification).
fn closest_line(spec: &TuneSpec, result: &SearchResult, other: bool) -> String {
    let Some(k) = result.closest() else {
        let other = if other { " other" } else { "" };
        return format!("No{other} candidate's runs all settled and passed the validity checks. ");
    };
    let cand = &result.candidates[k];
    let a = result.assess(cand);
    format!(
        "The closest candidate was {} ({}): cost {} of the reference; {}; metrics: {}. ",
        cand.id,
        settings(spec, cand),
        short(a.cost / stats::describe(&result.reference_costs()).mean),
        failure_reason(spec, result, &a),
        metric_lines(spec, result, &a)
    )
}

/// What a setting must cost less than to matter, and whose cost that is: the answer's in the search,
/// else the reference's.
fn answer_bound(result: &SearchResult) -> (f64, &'static str) {
    match result.recommended {
        Some(k) => (result.assess(&result.candidates[k]).cost, "the answer's"),
        None => (result.reference_cost(), "the reference's"),
    }
}

/// The settings cheaper than [`answer_bound`] left undecided, then those cut below it before they
/// settled (see [`undecided_lines`] and [`cut_lines`]).
fn open_lines(spec: &TuneSpec, result: &SearchResult, out_dir: Option<&Path>) -> String {
    let (bound, _) = answer_bound(result);
    undecided_lines(spec, result, bound, out_dir) + &cut_lines(spec, result, bound, out_dir)
}

/// Runs by role, in words that add up: `211 runs: 10 reference, 9 standard settings (2 cut once they
/// could no longer win), 180 search (12 cut …, 3 failed: did not settle), 12 verification`. A run cut
/// below the answer's cost in the search (the reference's without an answer) is not said to have
/// been unable to win.
pub fn run_counts(result: &SearchResult) -> String {
    let bound = answer_bound(result);
    let runs = |standard: bool| -> Vec<&Outcome> {
        let of = result.candidates.iter().filter(|c| c.standard.is_some() == standard);
        of.flat_map(|c| &c.runs).collect()
    };
    let (standard, search) = (runs(true), runs(false));
    let verify: usize = result.candidates.iter().map(|c| c.verification.len()).sum();
    let search_text = match search.len() {
        0 => "no search run was made".to_string(),
        n => format!("{n} search{}", ended(&search, bound)),
    };
    format!(
        "{} runs: {} reference, {} standard settings{}, {search_text}, {verify} verification",
        result.reference.len() + standard.len() + search.len() + verify,
        result.reference.len(),
        standard.len(),
        ended(&standard, bound)
    )
}

/// How many of `runs` were cut (at `bound`, whose cost it is, or above: once they could no longer
/// win; below it: before they settled) and how many failed, and why: ` (2 cut once they could no longer win; 3 failed: 2
/// did not settle, 1 diverged)`; empty when none.
fn ended(runs: &[&Outcome], (bound, whose): (f64, &str)) -> String {
    let cut = runs.iter().filter(|o| o.is_cut() && o.cost >= bound).count();
    let cut_below = runs.iter().filter(|o| o.is_cut() && o.cost < bound).count();
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
    if cut_below > 0 {
        parts.push(format!("{cut_below} cut below {whose} cost before they settled"));
    }
    if failed > 0 {
        let each: Vec<String> = why.iter().map(|(n, c)| format!("{c} {n}")).collect();
        parts.push(format!("{failed} failed: {}", each.join(", ")));
    }
    if parts.is_empty() { String::new() } else { format!(" ({})", parts.join("; ")) }
}
