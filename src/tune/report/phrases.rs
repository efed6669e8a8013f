//! The figures and phrases the answer sheet and the candidates table share: a candidate's settings
//! and time step, the tune's spend and why a setting is not acceptable.

use std::fmt::Write as _;

use super::super::model::{Assessment, Candidate, Rejection, SearchResult, State};
use super::super::{TuneSpec, candidate_scene, validity};
use crate::physics::SceneConfig;
use crate::physics::number::short;
use crate::stats;

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
pub(super) fn resolved_time_step(spec: &TuneSpec, candidate: &Candidate) -> String {
    let Ok(scene) = candidate_scene(spec, candidate) else { return String::new() };
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
    let text = match validity::predicted_report(scene, disks).map(|r| r.dt_over_contact_time) {
        Ok(f) if !fraction_given => format!("time step {} s ({} of the contact time)", short(dt), short(f)),
        _ => format!("time step {} s", short(dt)),
    };
    (dt, text)
}

/// The whole cost of the tune in mean reference runs.
pub fn spend(result: &SearchResult) -> f64 {
    let reference = stats::describe(&result.reference_costs()).mean;
    let runs =
        result.reference.iter().chain(result.candidates.iter().flat_map(|c| c.runs.iter().chain(&c.verification)));
    runs.map(|o| o.cost).sum::<f64>() / reference
}

pub(super) fn decision_name(d: stats::Decision) -> &'static str {
    match d {
        stats::Decision::Equivalent => "equivalent",
        stats::Decision::Different => "different",
        stats::Decision::Undecided => "undecided",
    }
}

/// The kept metric furthest from equivalence (|difference| over its margin) among those not
/// equivalent, with its test.
pub(super) fn worst_test<'a>(result: &SearchResult, a: &'a Assessment) -> Option<(usize, &'a stats::Equivalence)> {
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
