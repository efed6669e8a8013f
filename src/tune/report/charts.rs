//! The tune's charts' data (cost against the largest difference, cost along each lever) and the
//! report page's section.

use super::super::TuneSpec;
use super::super::model::{Candidate, SearchResult, State};
use super::tables::{candidate_records, lever_values};
use crate::physics::quantity;
use crate::plot::tune::{CostPoint, LeverSeries, cost_vs_difference_chart};
use crate::plot::{ChartOptions, PlotError};
use crate::report::TuneSection;
use crate::stats;
use crate::study::ParamValue;

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

/// One point per evaluated candidate: (largest |difference|/tolerance, cost ratio, feasible).
pub(super) fn cost_points(result: &SearchResult) -> (Vec<CostPoint>, Option<CostPoint>) {
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
pub(super) fn lever_series(spec: &TuneSpec, result: &SearchResult) -> Vec<LeverSeries> {
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
