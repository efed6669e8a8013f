//! The ladder of standard settings tune tries (common practice: the time step at the contact-time
//! limit, the same with local damping, a fraction of the Rayleigh time) and the rungs of the time-step
//! path ([`stepped_down`]): the same setting with a smaller fraction of its time scale.

use crate::physics::SceneConfig;
use crate::study::ParamValue;

/// Yade's customary local (Cundall) damping coefficient, the ladder's damped rung.
pub const STANDARD_LOCAL_DAMPING: f64 = 0.2;

/// The fraction of the Rayleigh time of the ladder's Rayleigh rung (common practice, EDEM).
pub const STANDARD_RAYLEIGH_FRACTION: f64 = 0.2;

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
        name: format!("{}, with {} lowered to {stepped}", setting.name, setting.values[position].0),
        values,
        removed: setting.removed.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stepped_down_rung_rounds_its_fraction_down() {
        let ladder = standard_settings(&SceneConfig::default());
        let stepped = stepped_down(&ladder[0], 0.8 / 1.08).unwrap();
        assert_eq!(stepped.values[0].1, ParamValue::Float(0.074));
        assert_eq!(stepped.removed, ladder[0].removed);
        assert!(stepped_down(&StandardSetting { values: Vec::new(), ..ladder[0].clone() }, 0.5).is_none());
    }
}
