//! Valid physics as a constraint before running: what a setting resolves to ([`identity`]), the
//! validity warnings its scene's own `limits` predict ([`predicted_warnings`]), and lever ranges
//! clipped where they reach past a limit ([`clip_levers`]).

use super::ladder;
use super::model::{ScreenError, first_verification_seed};
use super::spec::{DIGITS, Lever, LeverRange, TuneSpec};
use crate::physics::particles::InitialDisk;
use crate::physics::stability::StabilityReport;
use crate::physics::warning::{ValidityWarning, WarningKind};
use crate::physics::{SceneConfig, placement, predict_stability, predict_stage_warnings, scene_time_step};
use crate::study::ParamValue;
use rayon::prelude::*;

/// Most combinations of list-lever values a range is judged under (see [`alternatives`]); past it, a
/// range is judged at the reference's values of the list levers alone.
const MAX_ALTERNATIVES: usize = 16;

/// Bisection steps of a clipped range end (in the normalized coordinate: 2⁻²⁴ of the range).
const CLIP_STEPS: usize = 24;

/// A range is bisected on this many placement seeds from the reference's on and as many from the
/// first verification seed on: the hardest impact differs from seed to seed.
const CLIP_SEEDS: u64 = 16;

/// A bisected end is confirmed on this many seeds from the reference's on and as many from the first
/// verification seed on (every seed a tune of the default budget runs); the seeds that break it (and
/// not the reference's value) join the bisection's and the end is bisected again.
const CONFIRM_SEEDS: u64 = 128;

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
/// damping rate too strong for the step), with the disks it starts from, then those its stages add
/// (see [`predict_stage_warnings`]); or why it cannot start.
pub fn predicted_warnings(
    scene: &SceneConfig,
    initial: Option<&[InitialDisk]>,
) -> Result<Vec<ValidityWarning>, ScreenError> {
    Ok(predicted_in_stages(scene, initial)?.into_iter().map(|(_, w)| w).collect())
}

/// [`predicted_warnings`], each with the index of the stage it is predicted in (None: the scene's own).
pub fn predicted_in_stages(
    scene: &SceneConfig,
    initial: Option<&[InitialDisk]>,
) -> Result<Vec<(Option<usize>, ValidityWarning)>, ScreenError> {
    let disks = disks_of(scene, initial)?;
    let own = predict_stability(scene, &disks).warnings;
    let stages = predict_stage_warnings(scene, &disks, &own);
    Ok(own.into_iter().map(|w| (None, w)).chain(stages.into_iter().map(|(k, w)| (Some(k), w))).collect())
}

/// The stability prediction of a scene from its initial disks (generated when `initial` is None).
pub fn predicted_report(scene: &SceneConfig, initial: Option<&[InitialDisk]>) -> Result<StabilityReport, ScreenError> {
    Ok(predict_stability(scene, &disks_of(scene, initial)?))
}

/// The disks a scene starts from: `initial`, or its placement generated.
pub(super) fn disks_of(scene: &SceneConfig, initial: Option<&[InitialDisk]>) -> Result<Vec<InitialDisk>, ScreenError> {
    match initial {
        Some(disks) => Ok(disks.to_vec()),
        None => placement::generate(scene).map_err(ScreenError::Placement),
    }
}

/// Clips every continuous lever's range where, with the other continuous keys at the reference's
/// values, it reaches past a validity limit under every value of the list levers (an
/// `integrator.scheme` lever: a time step past one scheme's stable step stays in the range while
/// another scheme is stable there), on any placement seed the tune's runs use (the end predicted
/// invalid while the reference's value is valid): the new end is the last valid value found by
/// bisection on twice `CLIP_SEEDS` placements, confirmed on twice `CONFIRM_SEEDS`. Returns a
/// warning per clipped lever naming the limit, and the time-step tops of the clipped ranges
/// (`time_step_tops`, judged on the same placements). A lever with no valid value found is left as
/// it is (the screen rejects its points, each at its own list-lever values).
pub fn clip_levers(spec: &mut TuneSpec) -> (Vec<String>, Vec<StepTop>) {
    let mut placements = Placements::new(spec);
    // Each lever's reference coordinate depends on its own range only, read before it is clipped.
    let home = spec.reference_coordinates();
    let mut warnings = Vec::new();
    for (d, inside) in home.into_iter().enumerate() {
        let lever = spec.levers[d].clone();
        let (low, high, log) = match lever.range {
            LeverRange::Linear { low, high, integer: false } => (low, high, false),
            LeverRange::Log { low, high, integer: false } => (low, high, true),
            _ => continue,
        };
        let alternatives = alternatives(spec, &lever);
        let Some((ends, named)) = clipped_ends(spec, &lever, inside, &alternatives, &mut placements) else { continue };
        // The ends as found, rounded inwards so that the clipped range stays within the limit.
        let raw = |u: f64| if log { low * (high / low).powf(u) } else { low + (high - low) * u };
        let (new_low, new_high) = (round_inward(raw(ends.0), true), round_inward(raw(ends.1), false));
        spec.levers[d].range = if log {
            LeverRange::Log { low: new_low, high: new_high, integer: false }
        } else {
            LeverRange::Linear { low: new_low, high: new_high, integer: false }
        };
        let over = match spec.initial {
            Some(_) => "the placement file's disks".to_string(),
            None => format!("{} placement seeds, the search's and the verification's", placements.screened()),
        };
        let others = match alternatives.len() {
            1 => "the other keys at the reference's values",
            _ => "the other keys at the reference's values, under every value of the list levers",
        };
        warnings.push(format!(
            "levers.\"{}\": the range [{low}, {high}] reaches past {} (predicted on {over}, with {others}): \
             clipped to [{new_low}, {new_high}]",
            lever.key,
            named.join(" and "),
        ));
    }
    let tops = time_step_tops(spec, &mut placements);
    (warnings, tops)
}

/// The time-step lever's largest valid value with the list-lever values it holds for (see
/// `time_step_tops`).
pub type StepTop = (Vec<(String, ParamValue)>, ParamValue);

/// The values of the list levers (other than `lever`) that leave the disks where they are, each
/// combination of them (e.g. each `integrator.scheme`): a value of `lever` is past a limit only when
/// it is past one under every combination. One empty combination (the reference's values) when there
/// are none, or more than [`MAX_ALTERNATIVES`].
fn alternatives(spec: &TuneSpec, lever: &Lever) -> Vec<Vec<(String, ParamValue)>> {
    let mut combinations = vec![Vec::new()];
    for other in spec.levers.iter().filter(|l| l.key != lever.key && !moves_disks(&l.key)) {
        let LeverRange::List(values) = &other.range else { continue };
        combinations = combinations
            .iter()
            .flat_map(|c| values.iter().map(move |v| [c.as_slice(), &[(other.key.clone(), v.clone())]].concat()))
            .collect();
        if combinations.len() > MAX_ALTERNATIVES {
            return vec![Vec::new()];
        }
    }
    combinations
}

/// Whether a key changes where the disks start (a lever of the placement, the particles or the box).
fn moves_disks(key: &str) -> bool {
    ["particles.", "domain.", "placement."].iter().any(|p| key.starts_with(p))
}

/// The time-step lever's largest valid value under each combination of the list levers' values
/// (see [`alternatives`]), largest first: each scheme's own top of the time-step ladder. Empty when
/// there is no time-step lever or no list lever to combine it with (the clipped range's top is then
/// the only one).
fn time_step_tops(spec: &TuneSpec, placements: &mut Placements) -> Vec<StepTop> {
    let Some(lever) = ladder::time_step_lever(&spec.levers) else { return Vec::new() };
    let combinations = alternatives(spec, lever);
    if combinations.len() < 2 {
        return Vec::new();
    }
    let inside = spec.reference_coordinates()[spec.levers.iter().position(|l| l.key == lever.key).unwrap_or(0)];
    let mut tops: Vec<(Vec<(String, ParamValue)>, f64)> = combinations
        .into_iter()
        .filter_map(|combination| {
            let alone = [combination.clone()];
            let top = match clipped_ends(spec, lever, inside, &alone, placements) {
                Some(((_, high), _)) => high,
                None if breach(spec, lever, 1.0, &placements.bisected, &alone).is_some() => return None,
                None => 1.0,
            };
            Some((combination, top))
        })
        .collect();
    tops.sort_by(|a, b| b.1.total_cmp(&a.1));
    tops.into_iter().map(|(combination, u)| (combination, lever.value(u))).collect()
}

/// The placements a clipped end is judged on: those it is bisected on (growing by the seeds that
/// break an end found) and those it is confirmed on, generated once for every lever.
struct Placements {
    /// Those an end is bisected on: the first [`CLIP_SEEDS`] of the search's seeds and of the
    /// verification's (the placement file's disks alone when there is one), and the seeds that broke
    /// an end found.
    bisected: Vec<Vec<InitialDisk>>,
    /// The further seeds an end is confirmed on.
    confirm_seeds: Vec<u64>,
    /// Their placements, once generated.
    confirm: Option<Vec<Vec<InitialDisk>>>,
    /// How many of the bisection's seeds the disks could be placed on.
    placed: usize,
}

impl Placements {
    fn new(spec: &TuneSpec) -> Self {
        let first = first_verification_seed(spec.search.budget, spec.search.reference_seeds());
        let seeds = |count: u64| (0..count).chain((0..count).map(move |s| s + first));
        let bisected_seeds: Vec<u64> = seeds(CLIP_SEEDS).collect();
        let mut confirm_seeds: Vec<u64> = seeds(CONFIRM_SEEDS).filter(|s| !bisected_seeds.contains(s)).collect();
        confirm_seeds.sort_unstable();
        confirm_seeds.dedup();
        let bisected = match spec.initial.as_deref() {
            Some(disks) => vec![disks.clone()],
            None => bisected_seeds.iter().filter_map(|&s| placement_at(spec, s)).collect(),
        };
        let placed = bisected.len();
        Self { bisected, confirm_seeds, confirm: None, placed }
    }

    /// Distinct placements screened (the seed ranges overlap where the run budget is below
    /// CONFIRM_SEEDS): a seed the disks cannot be placed on is no deposition, and not counted.
    fn screened(&self) -> usize {
        self.placed + self.confirm.as_ref().map_or(0, Vec::len)
    }

    /// The confirmation placements (in seed order) on which `lever` at coordinate `u` breaks a limit
    /// that it does not break at `good`: a seed on which the good end breaks the limit too cannot move
    /// the end (bisecting towards `good` would find `good` again, forever). They are generated, in
    /// parallel, on first use.
    fn breaking(
        &mut self,
        spec: &TuneSpec,
        lever: &Lever,
        (u, good): (f64, f64),
        alternatives: &[Vec<(String, ParamValue)>],
    ) -> Vec<Vec<InitialDisk>> {
        let seeds = &self.confirm_seeds;
        let confirm =
            self.confirm.get_or_insert_with(|| seeds.par_iter().filter_map(|&s| placement_at(spec, s)).collect());
        let breaks = |x: f64, disks: &Vec<InitialDisk>| {
            breach(spec, lever, x, std::slice::from_ref(disks), alternatives).is_some()
        };
        confirm.par_iter().filter(|disks| breaks(u, disks) && !breaks(good, disks)).cloned().collect()
    }
}

/// A lever's clipped ends in the normalized coordinate and the limits they stop at, or None when
/// neither end breaks one (or no valid value is found). `inside`: the reference's coordinate, when
/// within the range. A lever that moves the disks is judged on its own placement; any other on every
/// seed's, and a seed past the bisection's that breaks an end found joins them, the end bisected again.
fn clipped_ends(
    spec: &TuneSpec,
    lever: &Lever,
    inside: Option<f64>,
    alternatives: &[Vec<(String, ParamValue)>],
    placements: &mut Placements,
) -> Option<((f64, f64), Vec<&'static str>)> {
    let own_placement = moves_disks(&lever.key);
    let confirmed = !own_placement && spec.initial.is_none();
    let problem = |u: f64, disks: &[Vec<InitialDisk>]| {
        breach(spec, lever, u, if own_placement { &[] } else { disks }, alternatives)
    };
    let (bad_low, bad_high) = (problem(0.0, &placements.bisected), problem(1.0, &placements.bisected));
    let clean = inside.filter(|&u| problem(u, &placements.bisected).is_none());
    if bad_low.is_some() && bad_high.is_some() && clean.is_none() {
        return None;
    }
    let mut ends = (0.0, 1.0);
    let mut named = Vec::new();
    for (end, bad) in [(0.0, bad_low), (1.0, bad_high)] {
        let Some(reason) = bad else { continue };
        let good = clean.unwrap_or(1.0 - end);
        let mut found = bisect(|u| problem(u, &placements.bisected).is_some(), good, end, CLIP_STEPS);
        // The seeds past the bisection's that break the end found (and not the good end) join them,
        // all at once, and the end is bisected again on all of them.
        loop {
            let breaking =
                if confirmed { placements.breaking(spec, lever, (found, good), alternatives) } else { Vec::new() };
            if breaking.is_empty() {
                break;
            }
            placements.bisected.extend(breaking);
            found = bisect(|u| problem(u, &placements.bisected).is_some(), good, found, CLIP_STEPS);
        }
        if end == 0.0 {
            ends.0 = found
        } else {
            ends.1 = found
        }
        named.push(reason);
    }
    named.dedup();
    (!named.is_empty()).then_some((ends, named))
}

/// The reference's placement with its seed moved by `offset`; None when it cannot be placed.
fn placement_at(spec: &TuneSpec, offset: u64) -> Option<Vec<InitialDisk>> {
    placement::generate(&spec.reference_at(offset)).ok()
}

/// The limit (its key) that lever coordinate `u` breaks on any of `placements` (on the scene's own
/// placement when there are none) under every combination of list-lever values in `alternatives`,
/// or "a placement that fails" when it cannot start; the first combination's limit is named.
fn breach(
    spec: &TuneSpec,
    lever: &Lever,
    u: f64,
    placements: &[Vec<InitialDisk>],
    alternatives: &[Vec<(String, ParamValue)>],
) -> Option<&'static str> {
    let mut reasons = alternatives.iter().map(|combination| {
        let values: Vec<(String, ParamValue)> =
            combination.iter().cloned().chain([(lever.key.clone(), lever.value(u))]).collect();
        breach_at(spec, &values, placements)
    });
    let first = reasons.next().flatten()?;
    reasons.all(|r| r.is_some()).then_some(first)
}

/// The limit that the reference with `values` breaks on any of `placements` (see [`breach`]).
fn breach_at(
    spec: &TuneSpec,
    values: &[(String, ParamValue)],
    placements: &[Vec<InitialDisk>],
) -> Option<&'static str> {
    let scene = spec.scene(values).ok()?;
    let named = |warnings: Result<Vec<ValidityWarning>, ScreenError>| match warnings {
        Ok(w) => w.first().map(|w| match w.kind {
            WarningKind::IntegratorStability => "the stable step of integrator.scheme at this damping",
            kind => kind.limit_key(),
        }),
        Err(_) => Some("a placement that fails"),
    };
    if placements.is_empty() {
        return named(predicted_warnings(&scene, spec.initial.as_deref().map(Vec::as_slice)));
    }
    placements.iter().find_map(|disks| named(predicted_warnings(&scene, Some(disks))))
}

/// The last coordinate between `good` (not broken) and `wrong` that `broken` accepts as not broken,
/// by `steps` bisection steps (`wrong` itself is never tried).
pub(crate) fn bisect(mut broken: impl FnMut(f64) -> bool, mut good: f64, mut wrong: f64, steps: usize) -> f64 {
    for _ in 0..steps {
        let mid = 0.5 * (good + wrong);
        if broken(mid) { wrong = mid } else { good = mid }
    }
    good
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
    fn only_the_seeds_the_disks_can_be_placed_on_count_as_screened() {
        // Near its jamming limit, random placement fits 30 disks in this box on most seeds, not all.
        let text = include_str!("../../tests/data/tiny_tune.toml")
            .replace("domain.height = 0.15", "domain.height = 0.052\nplacement.seed = 20");
        let spec = crate::tune::file::load_text("screened", &text);
        let first = first_verification_seed(spec.search.budget, spec.search.reference_seeds());
        let placeable = |seeds: &[u64]| seeds.iter().filter(|&&s| placement_at(&spec, s).is_some()).count();
        let bisected: Vec<u64> = (0..CLIP_SEEDS).chain(first..first + CLIP_SEEDS).collect();
        let mut placements = Placements::new(&spec);
        assert!(placeable(&bisected) < bisected.len(), "some seeds of the box cannot be placed on");
        assert_eq!(placements.screened(), placeable(&bisected));
        let lever = spec.levers[0].clone();
        placements.breaking(&spec, &lever, (0.5, 0.5), &alternatives(&spec, &lever));
        let confirmed: Vec<u64> = placements.confirm_seeds.clone();
        assert!(!confirmed.iter().any(|s| bisected.contains(s)));
        assert_eq!(placements.screened(), placeable(&bisected) + placeable(&confirmed));
    }

    #[test]
    fn a_clipped_end_rounds_inwards() {
        assert_eq!(round_inward(0.100_09, false), 0.1);
        assert_eq!(round_inward(0.010_001, true), 0.010_01);
        assert_eq!(round_inward(2.7e9 + 1e-3, true), 2.7e9);
    }
}
