//! Valid physics as a constraint before running: what a setting resolves to ([`identity`]), the
//! validity warnings its scene's own `limits` predict ([`predicted_warnings`]), and lever ranges
//! clipped where they reach past a limit ([`clip_levers`]).

use super::model::ScreenError;
use super::spec::{LeverRange, TuneSpec};
use crate::physics::particles::InitialDisk;
use crate::physics::stability::StabilityReport;
use crate::physics::warning::ValidityWarning;
use crate::physics::{SceneConfig, placement, predict_stability, scene_time_step};
use crate::study::ParamValue;

/// Bisection steps of a clipped range end (in the normalized coordinate: 2⁻²⁴ of the range).
const CLIP_STEPS: usize = 24;

/// What a scene resolves to: its JSON with the time step that actually runs in place of the fractions
/// that chose it (two settings with the same identity make the same runs).
pub fn identity(scene: &SceneConfig, disks: Option<&[InitialDisk]>) -> String {
    let mut resolved = scene.clone();
    resolved.integrator.time_step = Some(scene_time_step(scene, disks).dt);
    (resolved.integrator.contact_time_fraction, resolved.integrator.rayleigh_fraction) = (None, None);
    resolved.placement.seed = 0;
    serde_json::to_string(&resolved).unwrap_or_default()
}

/// The validity warnings predicted for a scene before running it (a capped time step, a time step
/// past the contact-time limit, an impact or static overlap past the Hertz validity ratio, a
/// damping rate too strong for the step), with the disks it starts from; or why it cannot start.
pub fn predicted_warnings(
    scene: &SceneConfig,
    initial: Option<&[InitialDisk]>,
) -> Result<Vec<ValidityWarning>, ScreenError> {
    predicted_report(scene, initial).map(|report| report.warnings)
}

/// The stability prediction of a scene from its initial disks (generated when `initial` is None).
pub fn predicted_report(scene: &SceneConfig, initial: Option<&[InitialDisk]>) -> Result<StabilityReport, ScreenError> {
    let disks = match initial {
        Some(disks) => disks.to_vec(),
        None => placement::generate(scene).map_err(|e| ScreenError::Placement(e.key.to_string(), e.reason))?,
    };
    Ok(predict_stability(scene, &disks))
}

/// Clips every continuous lever's range where, with the other keys at the reference's values, it
/// reaches past a validity limit (the end predicted invalid while the reference's value is valid):
/// the new end is the last valid value found by bisection. Returns a warning per clipped lever naming
/// the limit. A lever with no valid value found is left as it is (the screen rejects its points).
pub fn clip_levers(spec: &mut TuneSpec) -> Vec<String> {
    let mut warnings = Vec::new();
    for d in 0..spec.levers.len() {
        let lever = spec.levers[d].clone();
        let (low, high, integer, log) = match lever.range {
            LeverRange::Linear { low, high, integer } => (low, high, integer, false),
            LeverRange::Log { low, high, integer } => (low, high, integer, true),
            LeverRange::List(_) => continue,
        };
        if integer {
            continue;
        }
        // The limit a value breaks (its key), or "a placement" when it cannot start.
        let problem = |u: f64| -> Option<&'static str> {
            let scene = spec.scene(&[(lever.key.clone(), lever.value(u))]).ok()?;
            match predicted_warnings(&scene, spec.initial.as_deref().map(Vec::as_slice)) {
                Ok(w) => w.first().map(|w| w.kind.limit_key()),
                Err(_) => Some("a placement that fails"),
            }
        };
        let inside = spec.reference_values().into_iter().find(|(k, _, _)| *k == lever.key).and_then(|(_, _, c)| c);
        let (bad_low, bad_high) = (problem(0.0), problem(1.0));
        let clean = inside.filter(|&u| problem(u).is_none());
        if bad_low.is_some() && bad_high.is_some() && clean.is_none() {
            continue;
        }
        let mut ends = (0.0, 1.0);
        let mut named = Vec::new();
        for (end, bad) in [(0.0, bad_low), (1.0, bad_high)] {
            let Some(reason) = bad else { continue };
            let Some(mut good) = clean.or(if end == 0.0 { Some(1.0) } else { Some(0.0) }) else { continue };
            let mut wrong = end;
            for _ in 0..CLIP_STEPS {
                let mid = 0.5 * (good + wrong);
                if problem(mid).is_some() { wrong = mid } else { good = mid }
            }
            if end == 0.0 {
                ends.0 = good
            } else {
                ends.1 = good
            }
            named.push(reason);
        }
        if named.is_empty() {
            continue;
        }
        let number = |u: f64| match lever.value(u) {
            ParamValue::Float(x) => x,
            other => other.to_string().parse().unwrap_or(f64::NAN),
        };
        let (new_low, new_high) = (number(ends.0), number(ends.1));
        spec.levers[d].range = if log {
            LeverRange::Log { low: new_low, high: new_high, integer }
        } else {
            LeverRange::Linear { low: new_low, high: new_high, integer }
        };
        named.dedup();
        warnings.push(format!(
            "levers.\"{}\": the range [{low}, {high}] reaches past {} (predicted with the other keys at the \
             reference's values): clipped to [{new_low}, {new_high}]",
            lever.key,
            named.join(" and ")
        ));
    }
    warnings
}
