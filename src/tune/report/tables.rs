//! The tables of settings: the candidates that ran (`<name>_candidates.csv`, the report's table) and
//! those that did not (`<name>_skipped.csv`).

use super::super::TuneSpec;
use super::super::model::{Candidate, Outcome, SearchResult, State, describe_metric};
use super::phrases::{decision_name, failure_reason, settings};
use crate::report::{Cell, Table};
use crate::stats;
use crate::study::ParamValue;

/// The candidates table (`<name>_candidates.csv`): the reference, then every setting that ran with
/// its levers, n, cost (the objective's mean, and its ratio to the reference's), metric means,
/// decisions and verification (the settings not run are in [`skipped_records`]).
pub fn candidate_records(spec: &TuneSpec, result: &SearchResult) -> Table {
    let reference = stats::describe(&result.reference_costs()).mean;
    let mut rows = vec![reference_row(spec, result, reference)];
    for (index, cand) in result.candidates.iter().enumerate().filter(|(_, c)| !c.runs.is_empty()) {
        rows.push(candidate_row(spec, result, cand, reference, result.recommended == Some(index)));
    }
    Table { columns: candidate_columns(spec), rows }
}

/// The candidates table's columns: candidate, origin, the levers, n, cost, each kept metric's mean,
/// difference and decision, then the decision, its reason, verification and recommendation.
fn candidate_columns(spec: &TuneSpec) -> Vec<String> {
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
    columns
}

/// The mean of kept metric `k` over `runs`.
fn mean_of(runs: &[Outcome], k: usize) -> f64 {
    describe_metric(runs, k).mean
}

/// A count as a cell.
fn count(n: usize) -> Cell {
    Cell::Whole(n as i64)
}

/// The reference's row (candidate 0): its lever values, runs, mean cost `reference` and metric means.
fn reference_row(spec: &TuneSpec, result: &SearchResult, reference: f64) -> Vec<Cell> {
    let mut row = vec![Cell::Whole(0), Cell::text("reference")];
    let values = spec.reference_values();
    row.extend(
        spec.levers
            .iter()
            .map(|l| values.iter().find(|(k, _, _)| *k == l.key).map_or(Cell::Empty, |(_, v, _)| Cell::of_param(v))),
    );
    row.extend([count(result.reference.len()), Cell::number(reference), Cell::Number(1.0)]);
    for k in 0..spec.keep.len() {
        row.extend([Cell::number(mean_of(&result.reference, k)), Cell::Number(0.0), Cell::Empty]);
    }
    row.extend([Cell::Number(0.0), Cell::text("reference")]);
    row.extend(std::iter::repeat_n(Cell::Empty, 5));
    row
}

/// The row of a candidate that ran, its cost as a ratio to the reference's mean cost `reference`;
/// `recommended`: whether it is the recommendation.
fn candidate_row(
    spec: &TuneSpec,
    result: &SearchResult,
    cand: &Candidate,
    reference: f64,
    recommended: bool,
) -> Vec<Cell> {
    let a = result.assess(cand);
    let mut row = vec![count(cand.id), Cell::text(cand.origin.name())];
    row.extend(lever_values(spec, cand).iter().map(|v| v.as_ref().map_or(Cell::Empty, Cell::of_param)));
    row.extend([count(a.n), Cell::number(a.cost), Cell::number(a.cost / reference)]);
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
        Some(v) => row.extend([count(v.n), Cell::number(v.cost / reference), Cell::text(v.state.name())]),
        None => row.extend([Cell::Empty, Cell::Empty, Cell::Empty]),
    }
    row.push(Cell::Flag(recommended));
    row
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

/// Each lever's value in a candidate's runs (see [`TuneSpec::lever_values`]).
pub(super) fn lever_values(spec: &TuneSpec, cand: &Candidate) -> Vec<Option<ParamValue>> {
    spec.lever_values(&spec.setting_values(&cand.point, cand.standard))
}
