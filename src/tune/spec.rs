//! The types of a checked tune file: the levers and their ranges, the kept metrics, the search
//! settings and the [`TuneSpec`] that holds them with the reference scene (loading and checking are
//! in `file`).

use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;

use serde::Deserialize;

use crate::physics::SceneConfig;
use crate::physics::config::ConfigIssue;
use crate::physics::particles::InitialDisk;
use crate::physics::placement::{self, PlacementError};
use crate::study::file::{KeyPath, SetPathError, set_paths};
use crate::study::{OutputOptions, ParamValue};

/// Significant digits lever values are rounded to (clean values in the best study, and candidates
/// that differ by less are the same candidate).
pub(super) const DIGITS: i32 = 4;

/// Why a tune's scene with some lever values set is no scene.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneError {
    /// A lever's key cannot be set in the scene as written.
    Key(SetPathError),
    /// The scene does not read as one (a value of the wrong type, an unknown key).
    Read(toml::de::Error),
    /// Values the scene's checks refuse.
    Invalid(Vec<ConfigIssue>),
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Key(e) => write!(f, "{e}"),
            SceneError::Read(e) => write!(f, "{}", e.message()),
            SceneError::Invalid(issues) => {
                let issues: Vec<String> = issues.iter().map(|i| format!("{}: {}", i.key, i.reason)).collect();
                write!(f, "{}", issues.join("; "))
            }
        }
    }
}

impl std::error::Error for SceneError {}

/// The range of one lever.
#[derive(Clone, Debug, PartialEq)]
pub enum LeverRange {
    /// Evenly from a to b (integers when both ends are written as integers).
    Linear { low: f64, high: f64, integer: bool },
    /// Evenly in log scale from a to b (a, b > 0).
    Log { low: f64, high: f64, integer: bool },
    /// One of these values.
    List(Vec<ParamValue>),
}

/// A scene key tune may change.
#[derive(Clone, Debug, PartialEq)]
pub struct Lever {
    /// The dotted scene key, e.g. `material.restitution`.
    pub key: String,
    /// Its path into the scene.
    pub path: KeyPath,
    /// The values it may take.
    pub range: LeverRange,
}

impl Lever {
    /// A lever on the dotted scene key `key` (e.g. `material.restitution`) over `range`.
    pub fn new(key: &str, range: LeverRange) -> Self {
        Self { key: key.into(), path: key.split('.').map(String::from).collect(), range }
    }

    /// The value at normalized coordinate `u` in [0, 1] (log ranges are uniform in log scale).
    pub fn value(&self, u: f64) -> ParamValue {
        let u = u.clamp(0.0, 1.0);
        let number = |x: f64, integer: bool| {
            if integer { ParamValue::Int(x.round() as i64) } else { ParamValue::Float(round_significant(x, DIGITS)) }
        };
        match &self.range {
            LeverRange::Linear { low, high, integer } => number(low + (high - low) * u, *integer),
            LeverRange::Log { low, high, integer } => number(low * (high / low).powf(u), *integer),
            LeverRange::List(values) => {
                values[((u * values.len() as f64).floor() as usize).min(values.len() - 1)].clone()
            }
        }
    }

    /// The normalized coordinate of a value, when it lies in the range.
    pub fn coordinate(&self, value: &ParamValue) -> Option<f64> {
        let x = match value {
            ParamValue::Float(x) => Some(*x),
            ParamValue::Int(i) => Some(*i as f64),
            _ => None,
        };
        let inside = |u: f64| (-1e-9..=1.0 + 1e-9).contains(&u).then_some(u.clamp(0.0, 1.0));
        match &self.range {
            LeverRange::Linear { low, high, .. } => inside((x? - low) / (high - low)),
            LeverRange::Log { low, high, .. } => inside((x? / low).ln() / (high / low).ln()),
            LeverRange::List(values) => {
                let k = values.iter().position(|v| v == value)?;
                Some((k as f64 + 0.5) / values.len() as f64)
            }
        }
    }

    /// Whether the lever moves on a log scale.
    pub fn is_log(&self) -> bool {
        matches!(self.range, LeverRange::Log { .. })
    }

    /// The ends (or every value) of the range, for checking.
    pub(super) fn extremes(&self) -> Vec<ParamValue> {
        match &self.range {
            LeverRange::List(values) => values.clone(),
            _ => vec![self.value(0.0), self.value(1.0)],
        }
    }
}

/// `x` rounded to `digits` significant digits.
pub fn round_significant(x: f64, digits: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(digits - 1 - x.abs().log10().floor() as i32);
    let rounded = (x * scale).round() / scale;
    // Through text, so that the value prints short (0.3, not 0.30000000000000004).
    format!("{rounded:.*e}", (digits - 1) as usize).parse().unwrap_or(rounded)
}

/// A pile metric that must stay equivalent to the reference's.
#[derive(Clone, Debug, PartialEq)]
pub struct Keep {
    /// Summary column, e.g. `packing_fraction`.
    pub metric: String,
    /// Tolerance: relative to the reference mean, or absolute.
    pub tolerance: f64,
    /// Whether `tolerance` is absolute (in the metric's unit) rather than relative.
    pub absolute: bool,
}

impl Keep {
    /// The absolute equivalence margin for a reference mean.
    pub fn margin(&self, reference_mean: f64) -> f64 {
        if self.absolute { self.tolerance } else { self.tolerance * reference_mean.abs() }
    }
}

/// What the search minimizes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Objective {
    /// Mean particle-steps (disks × time steps) per run: deterministic, machine independent.
    #[default]
    ParticleSteps,
    /// Mean wall time per run (noisy, machine dependent).
    WallTime,
}

impl Objective {
    /// The name as written in a tune file.
    pub fn name(self) -> &'static str {
        match self {
            Objective::ParticleSteps => "particle_steps",
            Objective::WallTime => "wall_time",
        }
    }
}

/// The `[search]` table.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SearchOptions {
    /// What to minimize.
    pub objective: Objective,
    /// Placement seeds each candidate starts with (at least 2).
    pub seeds: usize,
    /// Most seeds one candidate gets while its equivalence is undecided.
    pub max_seeds: usize,
    /// Seeds of the reference (default: twice `seeds`, at least 6).
    pub reference_seeds: Option<usize>,
    /// Fresh seeds a recommendation is verified on (default: `max_seeds`).
    pub verify_seeds: Option<usize>,
    /// Runs at most, reference and verification included.
    pub budget: usize,
    /// Seed of the search's random choices.
    pub seed: u64,
    /// Points of the initial design (default: 2 × levers + 2, at least 6, and at most what half the
    /// search budget runs).
    pub initial: Option<usize>,
    /// Most the whole tune may spend, in reference depositions (mean particle-steps of a reference
    /// run): the search stops proposing when its next round and the verification would pass it.
    pub max_spend: f64,
}

impl Default for SearchOptions {
    fn default() -> Self {
        Self {
            objective: Objective::ParticleSteps,
            seeds: 3,
            max_seeds: 8,
            reference_seeds: None,
            verify_seeds: None,
            budget: 150,
            seed: 1,
            initial: None,
            max_spend: 20.0,
        }
    }
}

impl SearchOptions {
    /// Seeds of the reference.
    pub fn reference_seeds(&self) -> usize {
        self.reference_seeds.unwrap_or((2 * self.seeds).max(6))
    }

    /// Fresh seeds of one verification.
    pub fn verify_seeds(&self) -> usize {
        self.verify_seeds.unwrap_or(self.max_seeds)
    }
}

/// A standard setting: the reference scene with a few of the levers set to standard values.
#[derive(Clone, Debug, PartialEq)]
pub struct StandardSetting {
    /// In words, e.g. `time step at its largest valid value (integrator.contact_time_fraction = 0.1)`.
    pub name: String,
    /// Lever keys set (dotted scene keys).
    pub values: Vec<(String, ParamValue)>,
}

/// A checked tune file.
#[derive(Clone, Debug)]
pub struct TuneSpec {
    /// Path of the tune file.
    pub path: PathBuf,
    /// Its text, verbatim.
    pub text: String,
    /// Name (the file stem unless the file sets one).
    pub name: String,
    /// Hash of the text and the demsweep version.
    pub fingerprint: String,
    /// The reference scene as written (`[scene]`).
    pub base: toml::Table,
    /// The reference scene.
    pub reference: SceneConfig,
    /// Initial disks of a file placement, shared by every run.
    pub initial: Option<Arc<Vec<InitialDisk>>>,
    /// The levers, in written order.
    pub levers: Vec<Lever>,
    /// The kept metrics, in written order.
    pub keep: Vec<Keep>,
    /// Search settings.
    pub search: SearchOptions,
    /// Optional outputs of every run (histories and frames default to off).
    pub output: OutputOptions,
    /// What loading changed and the user should know (lever ranges clipped at a validity limit).
    pub warnings: Vec<String>,
    /// The standard settings evaluated before the search.
    pub standards: Vec<StandardSetting>,
}

impl TuneSpec {
    /// The scene with `values` set on the base scene.
    pub fn scene(&self, values: &[(String, ParamValue)]) -> Result<SceneConfig, SceneError> {
        let tree = self.edited_tree(values).map_err(SceneError::Key)?;
        let mut scene: SceneConfig = toml::Value::Table(tree).try_into().map_err(SceneError::Read)?;
        if let Some(disks) = &self.initial {
            scene.particles.count = disks.len();
        }
        scene.validate().map_err(SceneError::Invalid)?;
        Ok(scene)
    }

    /// The reference scene with its placement seed moved by `offset` (a tune's seed number).
    pub fn reference_at(&self, offset: u64) -> SceneConfig {
        let mut scene = self.reference.clone();
        scene.placement.seed = self.reference.placement.seed.wrapping_add(offset);
        scene
    }

    /// Why the reference's disks cannot be placed on seed number `seed` (a random placement near its
    /// jamming limit fits on some seeds and not on others); None where they can or come from a file.
    pub fn placement_failure(&self, seed: u64) -> Option<PlacementError> {
        let scene = self.reference_at(seed);
        if scene.placement.kind.reads_file() { None } else { placement::generate(&scene).err() }
    }

    /// The scene of a standard setting.
    pub fn standard_scene(&self, standard: &StandardSetting) -> Result<SceneConfig, SceneError> {
        self.scene(&standard.values)
    }

    /// The scene as written with lever values set: a standard setting's when `standard` is given,
    /// else those at `point`.
    pub fn setting_tree(&self, point: &[f64], standard: Option<usize>) -> Result<toml::Table, SetPathError> {
        self.edited_tree(&self.setting_values(point, standard))
    }

    /// The lever values a setting sets: a standard setting's, or those at `point`.
    pub fn setting_values(&self, point: &[f64], standard: Option<usize>) -> Vec<(String, ParamValue)> {
        match standard {
            Some(k) => self.standards[k].values.clone(),
            None => self.values(point),
        }
    }

    /// Each lever's value in the runs of a setting that sets `set`: the value it sets, else the
    /// reference's (a standard setting sets only some levers); None where the reference has none.
    pub fn lever_values(&self, set: &[(String, ParamValue)]) -> Vec<Option<ParamValue>> {
        let reference = self.reference_values();
        let value = |key: &str| {
            let given = set.iter().find(|(k, _)| k == key).map(|(_, v)| v.clone());
            given.or_else(|| reference.iter().find(|(k, _, _)| k == key).map(|(_, v, _)| v.clone()))
        };
        self.levers.iter().map(|l| value(&l.key)).collect()
    }

    /// The normalized point of a setting that sets `set` (see [`Self::lever_values`]); None where a
    /// lever has no value or one outside its range.
    pub fn lever_point(&self, set: &[(String, ParamValue)]) -> Option<Vec<f64>> {
        let values = self.lever_values(set);
        self.levers.iter().zip(values).map(|(lever, value)| lever.coordinate(&value?)).collect()
    }

    fn edited_tree(&self, values: &[(String, ParamValue)]) -> Result<toml::Table, SetPathError> {
        let mut tree = self.base.clone();
        let paths: Vec<KeyPath> = values.iter().map(|(key, _)| key.split('.').map(String::from).collect()).collect();
        set_paths(&mut tree, paths.iter().map(|p| &p[..]).zip(values.iter().map(|(_, v)| v.to_toml())))?;
        Ok(tree)
    }

    /// The lever values of normalized point `u`; a `placement.lowered_by` lever reads 0 where the
    /// `placement.kind` lever picks a kind that cannot be lowered (dropped, file), so that the two
    /// levers combine into a valid scene.
    pub fn values(&self, u: &[f64]) -> Vec<(String, ParamValue)> {
        let mut values: Vec<(String, ParamValue)> =
            self.levers.iter().zip(u).map(|(l, &x)| (l.key.clone(), l.value(x))).collect();
        let unlowerable = values.iter().any(|(key, value)| {
            key == "placement.kind" && !matches!(value, ParamValue::Text(kind) if kind == "random" || kind == "lattice")
        });
        let lowered = values.iter_mut().find(|(key, _)| key == "placement.lowered_by").filter(|_| unlowerable);
        if let Some((_, lowered)) = lowered {
            *lowered = match lowered {
                ParamValue::Int(_) => ParamValue::Int(0),
                _ => ParamValue::Float(0.0),
            };
        }
        values
    }

    /// Per lever, in order: the normalized coordinate of the reference's value, when the reference
    /// sets it ([`Self::reference_values`]) and it lies in the range.
    pub fn reference_coordinates(&self) -> Vec<Option<f64>> {
        let values = self.reference_values();
        let coordinate = |key: &str| values.iter().find(|(k, _, _)| k == key).and_then(|(_, _, c)| *c);
        self.levers.iter().map(|l| coordinate(&l.key)).collect()
    }

    /// The reference scene's value of each lever that it sets (or whose default lies in the range; a
    /// stage's key in the stage of that name), and its normalized coordinate when it lies in the range.
    pub fn reference_values(&self) -> Vec<(String, ParamValue, Option<f64>)> {
        let json = serde_json::to_value(&self.reference).unwrap_or_default();
        self.levers
            .iter()
            .filter_map(|lever| {
                let mut here = &json;
                for key in &lever.path {
                    here = match here {
                        // A stage (`stages.NAME.KEY`) is found by its name.
                        serde_json::Value::Array(items) => items.iter().find(|item| item["name"] == key.as_str())?,
                        _ => here.get(key)?,
                    };
                }
                let value = match here {
                    serde_json::Value::Number(n) if n.is_i64() => ParamValue::Int(n.as_i64()?),
                    serde_json::Value::Number(n) => ParamValue::Float(n.as_f64()?),
                    serde_json::Value::Bool(b) => ParamValue::Bool(*b),
                    serde_json::Value::String(s) => ParamValue::Text(s.clone()),
                    _ => return None,
                };
                let coordinate = lever.coordinate(&value);
                Some((lever.key.clone(), value, coordinate))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lever_values_round_and_cover_the_range() {
        let lin = Lever {
            key: "a".into(),
            path: vec!["a".into()],
            range: LeverRange::Linear { low: 0.1, high: 0.9, integer: false },
        };
        assert_eq!(lin.value(0.0), ParamValue::Float(0.1));
        assert_eq!(lin.value(1.0), ParamValue::Float(0.9));
        assert_eq!(lin.value(0.25), ParamValue::Float(0.3));
        let log = Lever { range: LeverRange::Log { low: 1e7, high: 1e9, integer: false }, ..lin.clone() };
        assert_eq!(log.value(0.5), ParamValue::Float(1e8));
        assert!((log.coordinate(&ParamValue::Float(1e8)).unwrap() - 0.5).abs() < 1e-12);
        let list = Lever { range: LeverRange::List(vec![ParamValue::Int(1), ParamValue::Int(2)]), ..lin };
        assert_eq!(list.value(0.49), ParamValue::Int(1));
        assert_eq!(list.value(1.0), ParamValue::Int(2));
        assert_eq!(round_significant(0.123456, 4), 0.1235);
    }
}
