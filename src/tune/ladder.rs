//! The ladder of standard settings tune tries first: the standard values of the levers it is given
//! (common practice: the time step at its largest valid value, local damping 0.2, a fifth of the
//! Rayleigh time), each only where its key is a lever, and the rungs of the time-step path
//! ([`stepped_down`]): the same setting with a smaller time step. A standard setting sets lever keys
//! only, so a tune never changes a key the user fixed.

use super::spec::{Lever, LeverRange, StandardSetting};
use crate::physics::SceneConfig;
use crate::study::ParamValue;

/// Yade's customary local (Cundall) damping coefficient, the ladder's damped rung.
pub const STANDARD_LOCAL_DAMPING: f64 = 0.2;

/// The fraction of the Rayleigh time of the ladder's Rayleigh rung (common practice, EDEM).
pub const STANDARD_RAYLEIGH_FRACTION: f64 = 0.2;

/// The keys that set a time step: an absolute step and the fractions of a time scale.
pub const TIME_STEP_KEYS: [&str; 3] =
    ["integrator.time_step", "integrator.contact_time_fraction", "integrator.rayleigh_fraction"];

/// +1 where raising the key makes each contact dissipate more (the contact damping β, a dissipation
/// time), -1 where lowering it does (a restitution), 0 otherwise: the direction in which a deposition
/// settles sooner, other things equal, while keeping its pile; `placement.lowered_by` +1 too (disks
/// lowered closer to the floor fall for less time). Numerical damping (local, viscous) also settles
/// sooner but loosens the pile as it grows: 0, its standard setting tries it.
pub fn dissipation(key: &str) -> f64 {
    let last = key.rsplit('.').next().unwrap_or(key);
    match last {
        "beta" | "dissipation_time" | "lowered_by" => 1.0,
        "restitution" => -1.0,
        _ => 0.0,
    }
}

/// The lever that sets the time step, when one does (the first written).
pub fn time_step_lever(levers: &[Lever]) -> Option<&Lever> {
    time_step_position(levers).map(|d| &levers[d])
}

/// The index of [`time_step_lever`] among `levers`.
pub fn time_step_position(levers: &[Lever]) -> Option<usize> {
    levers.iter().position(|l| TIME_STEP_KEYS.contains(&l.key.as_str()))
}

/// The ladder over `levers`: the time-step lever at its largest valid value (the top of the time-step
/// path, first when there is one; with list levers such as `integrator.scheme`, one top for each of
/// their values in `tops`, largest step first: see `crate::tune::validity::time_step_tops`), local
/// damping [`STANDARD_LOCAL_DAMPING`] (with the first top's time step), and
/// [`STANDARD_RAYLEIGH_FRACTION`] of the Rayleigh time; each standard value taken to the nearest
/// value of its lever's range, and a rung only where its levers are given.
pub fn standard_settings(
    reference: &SceneConfig,
    levers: &[Lever],
    tops: &[(Vec<(String, ParamValue)>, ParamValue)],
) -> Vec<StandardSetting> {
    let lever = |key: &str| levers.iter().find(|l| l.key == key);
    let mut ladder = time_step_rungs(reference, levers, tops);
    let top = ladder.first().map(|rung| rung.values.clone());
    if let Some(damping) = lever("damping.local").and_then(|l| nearest(l, STANDARD_LOCAL_DAMPING)) {
        let with_step = match &top {
            Some(values) => format!(" at that time step ({})", in_words(values)),
            None => String::new(),
        };
        ladder.push(StandardSetting {
            name: match damping == ParamValue::Float(STANDARD_LOCAL_DAMPING) {
                true => format!("local damping {damping} (Yade's default){with_step}"),
                false => format!(
                    "local damping {damping} (Yade's default {STANDARD_LOCAL_DAMPING}, within the range){with_step}"
                ),
            },
            values: top.iter().flatten().cloned().chain([("damping.local".to_string(), damping)]).collect(),
        });
    }
    let rayleigh = lever("integrator.rayleigh_fraction").and_then(|l| nearest(l, STANDARD_RAYLEIGH_FRACTION));
    let top_step = top.as_ref().and_then(|values| values.last().map(|(_, v)| v.clone()));
    if let Some(fraction) = rayleigh.filter(|f| top_step.as_ref() != Some(f)) {
        ladder.push(StandardSetting {
            name: format!("time step at {fraction} of the Rayleigh time"),
            values: vec![("integrator.rayleigh_fraction".to_string(), fraction)],
        });
    }
    ladder
}

/// The time-step lever at its largest valid value: once at the clipped range's top, or once for each
/// combination of list-lever values in `tops` (their own largest valid step, largest first); the time
/// step's key is last in each rung's values.
fn time_step_rungs(
    reference: &SceneConfig,
    levers: &[Lever],
    tops: &[(Vec<(String, ParamValue)>, ParamValue)],
) -> Vec<StandardSetting> {
    let Some(l) = time_step_lever(levers) else { return Vec::new() };
    let limit = match l.key.as_str() {
        "integrator.contact_time_fraction" => reference.limits.contact_time_fraction,
        _ => f64::INFINITY,
    };
    let capped = |value: &ParamValue| match value {
        ParamValue::Float(x) => at_most(l, x.min(limit)),
        _ => None,
    };
    let rungs: Vec<Vec<(String, ParamValue)>> = match tops {
        [] => at_most(l, limit).map(|value| vec![(l.key.clone(), value)]).into_iter().collect(),
        _ => tops
            .iter()
            .filter_map(|(combination, top)| {
                let value = capped(top)?;
                Some(combination.iter().cloned().chain([(l.key.clone(), value)]).collect())
            })
            .collect(),
    };
    rungs
        .into_iter()
        .map(|values| StandardSetting {
            name: format!("time step at its largest valid value ({})", in_words(&values)),
            values,
        })
        .collect()
}

/// `key = value, key = value`: a rung's values in words.
fn in_words(values: &[(String, ParamValue)]) -> String {
    values.iter().map(|(key, value)| format!("{key} = {value}")).collect::<Vec<_>>().join(", ")
}

/// The numeric values of a list lever.
fn listed(values: &[ParamValue]) -> impl Iterator<Item = (f64, &ParamValue)> {
    values.iter().filter_map(|v| match v {
        ParamValue::Float(x) => Some((*x, v)),
        ParamValue::Int(i) => Some((*i as f64, v)),
        _ => None,
    })
}

/// The largest value of the lever's range at most `x`, when there is one.
fn at_most(lever: &Lever, x: f64) -> Option<ParamValue> {
    match &lever.range {
        LeverRange::List(values) => {
            listed(values).filter(|(v, _)| *v <= x).max_by(|a, b| a.0.total_cmp(&b.0)).map(|(_, v)| v.clone())
        }
        LeverRange::Linear { low, .. } | LeverRange::Log { low, .. } if x < *low => None,
        _ => nearest(lever, x),
    }
}

/// The value of the lever's range nearest `x`.
fn nearest(lever: &Lever, x: f64) -> Option<ParamValue> {
    match &lever.range {
        LeverRange::List(values) => {
            listed(values).min_by(|a, b| (a.0 - x).abs().total_cmp(&(b.0 - x).abs())).map(|(_, v)| v.clone())
        }
        LeverRange::Linear { low, high, .. } | LeverRange::Log { low, high, .. } => {
            let clamped = ParamValue::Float(x.clamp(*low, *high));
            Some(lever.value(lever.coordinate(&clamped)?))
        }
    }
}

/// Standard setting `setting` with the key that sets its time step multiplied by `factor` and rounded
/// down to two significant digits; None when no key sets it (or the product rounds to zero).
pub fn stepped_down(setting: &StandardSetting, factor: f64) -> Option<StandardSetting> {
    let position = setting.values.iter().position(|(key, _)| TIME_STEP_KEYS.contains(&key.as_str()))?;
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
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stepped_down_rung_rounds_its_fraction_down() {
        let levers = [Lever::new(
            "integrator.contact_time_fraction",
            LeverRange::Linear { low: 0.01, high: 0.2, integer: false },
        )];
        let ladder = standard_settings(&SceneConfig::default(), &levers, &[]);
        assert_eq!(ladder[0].values, vec![(levers[0].key.clone(), ParamValue::Float(0.1))], "at the limit");
        let stepped = stepped_down(&ladder[0], 0.8 / 1.08).unwrap();
        assert_eq!(stepped.values[0].1, ParamValue::Float(0.074));
        assert!(stepped_down(&StandardSetting { values: Vec::new(), ..ladder[0].clone() }, 0.5).is_none());
    }

    #[test]
    fn the_ladder_sets_only_the_levers_it_is_given() {
        let scene = SceneConfig::default();
        let damping = Lever::new("damping.local", LeverRange::Linear { low: 0.0, high: 0.1, integer: false });
        let restitution =
            Lever::new("material.restitution", LeverRange::Linear { low: 0.1, high: 0.9, integer: false });
        let ladder = standard_settings(&scene, &[restitution.clone(), damping.clone()], &[]);
        assert_eq!(ladder.len(), 1, "{ladder:?}");
        assert_eq!(
            ladder[0].values,
            vec![("damping.local".to_string(), ParamValue::Float(0.1))],
            "clamped to the range"
        );
        assert!(standard_settings(&scene, &[restitution], &[]).is_empty());
        let step = Lever::new(
            "integrator.time_step",
            LeverRange::List(vec![ParamValue::Float(1e-6), ParamValue::Float(4e-6)]),
        );
        let ladder = standard_settings(&scene, &[step, damping], &[]);
        let keys: Vec<Vec<&str>> = ladder.iter().map(|s| s.values.iter().map(|(k, _)| k.as_str()).collect()).collect();
        assert_eq!(keys, vec![vec!["integrator.time_step"], vec!["integrator.time_step", "damping.local"]]);
        assert_eq!(ladder[0].values[0].1, ParamValue::Float(4e-6), "the largest listed step");
    }
}
