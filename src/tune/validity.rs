//! Valid physics as a constraint: what a setting resolves to and whether the scene's own `limits`
//! predict it invalid ([`screen`]), lever ranges clipped where they reach past a limit
//! ([`clip_levers`]), and the ladder of standard settings tune tries before searching
//! ([`standard_settings`]).

use super::file::{LeverRange, TuneSpec};
use crate::physics::particles::InitialDisk;
use crate::physics::stability::StabilityReport;
use crate::physics::{SceneConfig, placement, predict_stability, scene_time_step};
use crate::study::ParamValue;

/// Yade's customary local (Cundall) damping coefficient, the ladder's damped rung.
pub const STANDARD_LOCAL_DAMPING: f64 = 0.2;

/// The fraction of the Rayleigh time of the ladder's Rayleigh rung (common practice, EDEM).
pub const STANDARD_RAYLEIGH_FRACTION: f64 = 0.2;

/// Bisection steps of a clipped range end (in the normalized coordinate: 2⁻²⁴ of the range).
const CLIP_STEPS: usize = 24;

/// A standard setting: the reference scene with a few keys set and others removed.
#[derive(Clone, Debug, PartialEq)]
pub struct StandardSetting {
    /// In words, e.g. `time step at the contact-time limit`.
    pub name: String,
    /// Keys set (dotted scene keys).
    pub values: Vec<(String, ParamValue)>,
    /// Keys removed first (a time-step choice that would take precedence).
    pub removed: Vec<String>,
}

/// The ladder: the time step at the largest valid contact-time fraction (`limits.contact_time_fraction`
/// of the reference), the same with local damping 0.2, and 20 % of the Rayleigh time.
pub fn standard_settings(reference: &SceneConfig) -> Vec<StandardSetting> {
    let fraction = reference.limits.contact_time_fraction;
    let contact = ("integrator.contact_time_fraction".to_string(), ParamValue::Float(fraction));
    let not_contact = vec!["integrator.time_step".to_string(), "integrator.rayleigh_fraction".to_string()];
    vec![
        StandardSetting {
            name: format!("time step at the contact-time limit ({fraction} of the contact time)"),
            values: vec![contact.clone()],
            removed: not_contact.clone(),
        },
        StandardSetting {
            name: format!(
                "time step at the contact-time limit with local damping {STANDARD_LOCAL_DAMPING} (Yade's default)"
            ),
            values: vec![contact, ("damping.local".to_string(), ParamValue::Float(STANDARD_LOCAL_DAMPING))],
            removed: not_contact,
        },
        StandardSetting {
            name: format!("time step at {} % of the Rayleigh time", 100.0 * STANDARD_RAYLEIGH_FRACTION),
            values: vec![("integrator.rayleigh_fraction".to_string(), ParamValue::Float(STANDARD_RAYLEIGH_FRACTION))],
            removed: vec!["integrator.time_step".to_string(), "integrator.contact_time_fraction".to_string()],
        },
    ]
}

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
pub fn predicted_warnings(scene: &SceneConfig, initial: Option<&[InitialDisk]>) -> Result<Vec<String>, String> {
    predicted_report(scene, initial).map(|report| report.warnings)
}

/// The stability prediction of a scene from its initial disks (generated when `initial` is None).
pub fn predicted_report(scene: &SceneConfig, initial: Option<&[InitialDisk]>) -> Result<StabilityReport, String> {
    let disks = match initial {
        Some(disks) => disks.to_vec(),
        None => placement::generate(scene).map_err(|e| format!("placement fails: {}: {}", e.key, e.reason))?,
    };
    Ok(predict_stability(scene, &disks))
}

/// The `limits.*` key a physics warning names (its first), for naming the limit a range reaches past.
pub fn limit_named(warning: &str) -> &str {
    let Some(start) = warning.find("limits.") else { return "a validity limit" };
    let rest = &warning[start..];
    let end = rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '.')).unwrap_or(rest.len());
    rest[..end].trim_end_matches('.')
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
        let problem = |u: f64| -> Option<String> {
            let scene = spec.scene(&[(lever.key.clone(), lever.value(u))]).ok()?;
            match predicted_warnings(&scene, spec.initial.as_deref().map(Vec::as_slice)) {
                Ok(w) => w.into_iter().next(),
                Err(reason) => Some(reason),
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
            named.push(limit_named(&reason).to_string());
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
