//! Valid physics as a constraint before running: what a setting resolves to ([`identity`]), the
//! validity warnings its scene's own `limits` predict ([`predicted_warnings`]), and lever ranges
//! clipped where they reach past a limit ([`clip_levers`]).

use super::model::{ScreenError, first_verification_seed};
use super::spec::{DIGITS, LeverRange, TuneSpec};
use crate::physics::particles::InitialDisk;
use crate::physics::stability::StabilityReport;
use crate::physics::warning::{ValidityWarning, WarningKind};
use crate::physics::{SceneConfig, placement, predict_stability, scene_time_step};

/// Bisection steps of a clipped range end (in the normalized coordinate: 2⁻²⁴ of the range).
const CLIP_STEPS: usize = 24;

/// A range is clipped where any of this many placement seeds from the reference's on, or as many from
/// the first verification seed on (the seeds the tune's runs use), predicts a breach: the hardest
/// impact differs from seed to seed.
const CLIP_SEEDS: u64 = 16;

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
        None => placement::generate(scene).map_err(ScreenError::Placement)?,
    };
    Ok(predict_stability(scene, &disks))
}

/// Clips every continuous lever's range where, with the other keys at the reference's values, it
/// reaches past a validity limit on any of twice [`CLIP_SEEDS`] placements (the end predicted invalid
/// while the reference's value is valid): the new end is the last valid value found by bisection.
/// Returns a warning per clipped lever naming the limit. A lever with no valid value found is left as it is
/// (the screen rejects its points).
pub fn clip_levers(spec: &mut TuneSpec) -> Vec<String> {
    let mut warnings = Vec::new();
    let placements: Vec<Vec<InitialDisk>> = match spec.initial.as_deref() {
        Some(disks) => vec![disks.clone()],
        None => (0..CLIP_SEEDS)
            .chain(
                (0..CLIP_SEEDS).map(|s| s + first_verification_seed(spec.search.budget, spec.search.reference_seeds())),
            )
            .filter_map(|s| {
                let mut scene = spec.reference.clone();
                scene.placement.seed = scene.placement.seed.wrapping_add(s);
                placement::generate(&scene).ok()
            })
            .collect(),
    };
    // Each lever's reference coordinate depends on its own range only, read before it is clipped.
    let home = spec.reference_coordinates();
    for (d, inside) in home.into_iter().enumerate() {
        let lever = spec.levers[d].clone();
        let (low, high, integer, log) = match lever.range {
            LeverRange::Linear { low, high, integer } => (low, high, integer, false),
            LeverRange::Log { low, high, integer } => (low, high, integer, true),
            LeverRange::List(_) => continue,
        };
        if integer {
            continue;
        }
        // A lever that moves the disks is judged on its own placement; any other on every seed's.
        let own_placement = ["particles.", "domain.", "placement."].iter().any(|p| lever.key.starts_with(p));
        let named = |warnings: Vec<ValidityWarning>| {
            warnings.first().map(|w| match w.kind {
                WarningKind::IntegratorStability => "the stable step of integrator.scheme at this damping",
                kind => kind.limit_key(),
            })
        };
        // The limit a value breaks (its key), or "a placement" when it cannot start.
        let problem = |u: f64| -> Option<&'static str> {
            let scene = spec.scene(&[(lever.key.clone(), lever.value(u))]).ok()?;
            if own_placement || placements.is_empty() {
                return match predicted_warnings(&scene, spec.initial.as_deref().map(Vec::as_slice)) {
                    Ok(w) => named(w),
                    Err(_) => Some("a placement that fails"),
                };
            }
            placements.iter().find_map(|disks| match predicted_warnings(&scene, Some(disks)) {
                Ok(w) => named(w),
                Err(_) => Some("a placement that fails"),
            })
        };
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
        // The ends as found, rounded inwards so that the clipped range stays within the limit.
        let raw = |u: f64| if log { low * (high / low).powf(u) } else { low + (high - low) * u };
        let (new_low, new_high) = (round_inward(raw(ends.0), true), round_inward(raw(ends.1), false));
        spec.levers[d].range = if log {
            LeverRange::Log { low: new_low, high: new_high, integer }
        } else {
            LeverRange::Linear { low: new_low, high: new_high, integer }
        };
        named.dedup();
        let over = match spec.initial {
            Some(_) => "the placement file's disks".to_string(),
            None => format!("{} placement seeds, the search's and the verification's", placements.len()),
        };
        warnings.push(format!(
            "levers.\"{}\": the range [{low}, {high}] reaches past {} (predicted on {over}, with the other \
             keys at the reference's values): clipped to [{new_low}, {new_high}]",
            lever.key,
            named.join(" and "),
        ));
    }
    warnings
}

/// `x` rounded to the lever digits, up (`up`) or down: a clipped range's end moved inwards.
fn round_inward(x: f64, up: bool) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(DIGITS - 1 - x.abs().log10().floor() as i32);
    let scaled = x * scale;
    // A value a hair past a round number (from the bisection's arithmetic) stays on it.
    let nearest = scaled.round();
    let rounded = if (scaled - nearest).abs() < 1e-9 {
        nearest
    } else if up {
        scaled.ceil()
    } else {
        scaled.floor()
    };
    format!("{:.*e}", (DIGITS - 1) as usize, rounded / scale).parse().unwrap_or(rounded / scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_clipped_end_rounds_inwards() {
        assert_eq!(round_inward(0.100_09, false), 0.1);
        assert_eq!(round_inward(0.010_001, true), 0.010_01);
        assert_eq!(round_inward(2.7e9 + 1e-3, true), 2.7e9);
    }
}
