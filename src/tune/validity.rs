//! Valid physics as a constraint: what a setting resolves to and whether the scene's own `limits`
//! predict it invalid ([`screen`]), lever ranges clipped where they reach past a limit
//! ([`clip_levers`]), and the ladder of standard settings tune tries before searching
//! ([`standard_settings`]), and a rung stepped down when its runs break a limit that a smaller time
//! step cures ([`stepped_down`], [`time_step_excess`]).

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

/// The keys of the fractions of a time scale that set a time step.
const TIME_STEP_FRACTIONS: [&str; 2] = ["integrator.contact_time_fraction", "integrator.rayleigh_fraction"];

/// Standard setting `setting` with the fraction of the time scale that sets its time step multiplied
/// by `factor` and rounded down to two significant digits; None when no fraction sets it (or the
/// product rounds to zero).
pub fn stepped_down(setting: &StandardSetting, factor: f64) -> Option<StandardSetting> {
    let position = setting.values.iter().position(|(key, _)| TIME_STEP_FRACTIONS.contains(&key.as_str()))?;
    let ParamValue::Float(fraction) = setting.values[position].1 else { return None };
    let scaled = fraction * factor;
    let scale = 10f64.powi(1 - scaled.log10().floor() as i32);
    let stepped: f64 = format!("{:.6e}", (scaled * scale).floor() / scale).parse().ok()?;
    if !(stepped > 0.0 && stepped < fraction) {
        return None;
    }
    let mut values = setting.values.clone();
    values[position].1 = ParamValue::Float(stepped);
    Some(StandardSetting {
        name: format!(
            "{}, stepped down to {stepped} (x {factor:.3}: its runs broke a validity limit that a smaller step cures)",
            setting.name
        ),
        values,
        removed: setting.removed.clone(),
    })
}

/// How far past their limits the measured values of a run's warnings went, when every warning is
/// one a smaller time step cures: the largest of the energy-balance error over
/// `limits.energy_balance_tolerance` and the overlap over `limits.overlap_warning_ratio`, read from
/// the warnings' texts. None when there is no warning, or one of another kind.
pub fn time_step_excess(warnings: &[String]) -> Option<f64> {
    warnings.iter().map(|w| warning_excess(w)).reduce(|a, b| Some(a?.max(b?)))?
}

/// The measured value over its limit of one energy-balance or overlap warning.
fn warning_excess(warning: &str) -> Option<f64> {
    let number_after = |marker: &str| -> Option<f64> {
        let rest = &warning[warning.find(marker)? + marker.len()..];
        let end = rest.find(|c: char| !(c.is_ascii_digit() || "+-.eE".contains(c))).unwrap_or(rest.len());
        rest[..end].parse().ok()
    };
    if warning.contains("limits.energy_balance_tolerance") {
        let (imbalance, available) = (number_after("is off by ")?, number_after("% of the ")?);
        let tolerance = number_after("limits.energy_balance_tolerance = ")?;
        Some(imbalance / available / tolerance)
    } else if warning.contains("limits.overlap_warning_ratio") && warning.contains("largest overlap") {
        Some(number_after("largest overlap ")? / number_after("Hertz validity limit ")?)
    } else {
        None
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn excess_is_read_from_energy_and_overlap_warnings_only() {
        let energy = "energy balance (mechanical + dissipated = initial) is off by 2.1600e-1 J at t = 0.5000 s, 1.08 % \
                      of the 2.0000e1 J available: the integration is inaccurate (time step too large for the contact \
                      stiffness or damping; limit limits.energy_balance_tolerance = 0.01)";
        let overlap = "largest overlap 0.150 radii at t = 0.1000 s is beyond the Hertz validity limit 0.1 \
                       (limits.overlap_warning_ratio)";
        let excess = time_step_excess(&[energy.to_string()]).unwrap();
        assert!((excess - 1.08).abs() < 1e-12, "{excess}");
        assert!((time_step_excess(&[energy.into(), overlap.into()]).unwrap() - 1.5).abs() < 1e-12);
        assert_eq!(time_step_excess(&[energy.into(), "time step capped by the damping rate".into()]), None);
        assert_eq!(time_step_excess(&[]), None);
    }

    #[test]
    fn a_stepped_down_rung_rounds_its_fraction_down() {
        let ladder = standard_settings(&SceneConfig::default());
        let stepped = stepped_down(&ladder[0], 0.8 / 1.08).unwrap();
        assert_eq!(stepped.values[0].1, ParamValue::Float(0.074));
        assert_eq!(stepped.removed, ladder[0].removed);
        assert!(stepped_down(&StandardSetting { values: Vec::new(), ..ladder[0].clone() }, 0.5).is_none());
    }
}
