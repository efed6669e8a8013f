//! The tune file: a reference `[scene]`, the `[levers]` tune may move, the pile metrics to `[keep]`
//! and the `[search]` settings; checked like a study (every problem at once, file:line:column: key).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::Deserialize;

use crate::physics::SceneConfig;
use crate::physics::config::PlacementKind;
use crate::physics::particles::InitialDisk;
use crate::physics::placement;
use crate::physics::quantity;
use crate::study::axes::{self, RangeEnds, Spacing};
use crate::study::errors::{ErrorSink, StudyError, StudyErrors};
use crate::study::file::{Document, KeyPath, MAX_STUDY_BYTES, StudyFile, quoted_key, read_text, set_path};
use crate::study::plan::{self, fingerprint, split_leaves};
use crate::study::{OutputOptions, ParamValue, initial_csv};

use super::validity::{self, StandardSetting};

/// Keys allowed at the top of a tune file.
/// The tables of a tune file (besides the strings `name` and `description`).
const TABLES: [&str; 5] = ["scene", "levers", "keep", "search", "output"];

/// Significant digits lever values are rounded to (clean values in the best study, and candidates
/// that differ by less are the same candidate).
const DIGITS: i32 = 4;

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
    fn extremes(&self) -> Vec<ParamValue> {
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
    pub fn scene(&self, values: &[(String, ParamValue)]) -> Result<SceneConfig, String> {
        self.edited_scene(values, &[])
    }

    /// The scene of a standard setting.
    pub fn standard_scene(&self, standard: &StandardSetting) -> Result<SceneConfig, String> {
        self.edited_scene(&standard.values, &standard.removed)
    }

    /// The base scene with the keys `removed` taken out, then `values` set.
    fn edited_scene(&self, values: &[(String, ParamValue)], removed: &[String]) -> Result<SceneConfig, String> {
        let tree = self.edited_tree(values, removed)?;
        let mut scene: SceneConfig = toml::Value::Table(tree).try_into().map_err(|e| e.message().to_string())?;
        if let Some(disks) = &self.initial {
            scene.particles.count = disks.len();
        }
        scene.validate().map_err(|issues| {
            issues.iter().map(|i| format!("{}: {}", i.key, i.reason)).collect::<Vec<_>>().join("; ")
        })?;
        Ok(scene)
    }

    /// The scene as written with `removed` taken out, then `values` set; a standard setting's when
    /// `standard` is given, else the levers at `point`.
    pub fn setting_tree(&self, point: &[f64], standard: Option<usize>) -> Result<toml::Table, String> {
        match standard {
            Some(k) => self.edited_tree(&self.standards[k].values, &self.standards[k].removed),
            None => self.edited_tree(&self.values(point), &[]),
        }
    }

    fn edited_tree(&self, values: &[(String, ParamValue)], removed: &[String]) -> Result<toml::Table, String> {
        let mut tree = self.base.clone();
        for key in removed {
            remove_path(&mut tree, key);
        }
        for (key, value) in values {
            let path: KeyPath = key.split('.').map(String::from).collect();
            set_path(&mut tree, &path, value.to_toml())?;
        }
        Ok(tree)
    }

    /// The lever values of normalized point `u`.
    pub fn values(&self, u: &[f64]) -> Vec<(String, ParamValue)> {
        self.levers.iter().zip(u).map(|(l, &x)| (l.key.clone(), l.value(x))).collect()
    }

    /// The reference scene's value of each lever that it sets (or whose default lies in the range),
    /// and its normalized coordinate when it lies in the range.
    pub fn reference_values(&self) -> Vec<(String, ParamValue, Option<f64>)> {
        let json = serde_json::to_value(&self.reference).unwrap_or_default();
        self.levers
            .iter()
            .filter_map(|lever| {
                let mut here = &json;
                for key in &lever.path {
                    here = here.get(key)?;
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

/// Removes a dotted key from a TOML tree (nothing when it is not there).
fn remove_path(tree: &mut toml::Table, key: &str) {
    match key.split_once('.') {
        Some((head, rest)) => {
            if let Some(toml::Value::Table(inner)) = tree.get_mut(head) {
                remove_path(inner, rest);
            }
        }
        None => {
            tree.remove(key);
        }
    }
}

/// Whether the file at `path` looks like a tune file (it has `[levers]`, `[keep]` or `[search]`).
pub fn is_tune_file(path: &Path) -> bool {
    let Ok(text) = read_text(path, MAX_STUDY_BYTES) else { return false };
    let Ok(table) = text.parse::<toml::Table>() else {
        return text.lines().any(|l| ["[levers", "[keep", "[search"].iter().any(|h| l.trim_start().starts_with(h)));
    };
    ["levers", "keep", "search"].iter().any(|k| table.contains_key(*k))
}

/// Reads and checks a tune file; every problem is reported at once.
pub fn load(path: &Path) -> Result<TuneSpec, StudyErrors> {
    let file = StudyFile::read(path)?;
    let doc = Document::parse(&file).map_err(StudyErrors::sorted)?;
    let mut sink = ErrorSink::default();
    sink.extend(check_top_level(&file, &doc));
    let (base, scene_errors) = split_leaves::<SceneConfig>(&file, &doc, "scene");
    sink.extend(scene_errors);
    let (output, output_errors) = split_leaves::<OutputOptions>(&file, &doc, "output");
    sink.extend(output_errors);
    let (search, search_errors) = split_leaves::<SearchOptions>(&file, &doc, "search");
    sink.extend(search_errors);
    let search: SearchOptions = toml::Value::Table(search).try_into().unwrap_or_default();
    sink.extend(check_search(&file, &doc, &search));
    let (levers, lever_errors) = parse_levers(&file, &doc);
    sink.extend(lever_errors);
    let (keep, keep_errors) = parse_keep(&file, &doc);
    sink.extend(keep_errors);
    let mut output_tree = toml::Table::new();
    output_tree.insert("histories".into(), toml::Value::Boolean(false));
    output_tree.insert("frames".into(), toml::Value::Boolean(false));
    output_tree.extend(output);
    let mut spec = TuneSpec {
        path: file.path.clone(),
        text: file.text.clone(),
        name: plan::study_name(&doc, path),
        fingerprint: fingerprint(&file.text),
        base,
        reference: SceneConfig::default(),
        initial: None,
        levers,
        keep,
        search,
        output: toml::Value::Table(output_tree).try_into().unwrap_or_default(),
        warnings: Vec::new(),
        standards: Vec::new(),
    };
    // The levers are checked against the valid part of the scene even when other keys are wrong, so
    // that every problem is reported at once.
    let scene_span = doc.span(&["scene".to_string()]);
    match spec.scene(&[]) {
        Ok(scene) => spec.reference = scene,
        Err(reason) => {
            sink.push(file.error(scene_span, "scene", reason));
            return Err(sink.into_errors());
        }
    }
    if let (PlacementKind::File, Some(name)) = (spec.reference.placement.kind, &spec.reference.placement.file) {
        let csv = file.path.parent().unwrap_or(Path::new("")).join(name);
        match initial_csv::read(&csv, spec.reference.particles.radius) {
            Ok(disks) => {
                spec.reference.particles.count = disks.len();
                spec.initial = Some(Arc::new(disks));
            }
            Err(reason) => sink.push(file.error(scene_span.clone(), "scene.placement.file", reason)),
        }
    } else if let Err(e) = placement::generate(&spec.reference) {
        sink.push(file.error(scene_span.clone(), format!("scene.{}", e.key), e.reason));
    }
    for lever in &spec.levers {
        let span = doc
            .span(&["levers".to_string(), lever.key.clone()])
            .or_else(|| doc.nearest_span(&lever_doc_path(&lever.path)));
        let extremes = lever.extremes();
        let failures: Vec<(ParamValue, String)> = extremes
            .iter()
            .filter_map(|value| {
                let problem = spec.scene(&[(lever.key.clone(), value.clone())]).and_then(|scene| {
                    let placed = ["domain", "particles", "placement"].contains(&lever.path[0].as_str());
                    if spec.initial.is_none() && placed {
                        placement::generate(&scene).map(|_| ()).map_err(|e| format!("{}: {}", e.key, e.reason))
                    } else {
                        Ok(())
                    }
                });
                problem.err().map(|reason| (value.clone(), reason))
            })
            .collect();
        let error = |reason: &str| file.error(span.clone(), lever_label(&lever.key), reason);
        if failures.len() == extremes.len() && failures.iter().all(|(_, r)| *r == failures[0].1) {
            sink.push(error(&failures[0].1));
        } else {
            failures.iter().for_each(|(value, reason)| sink.push(error(reason).with_value(value.to_string())));
        }
    }
    if sink.is_empty() {
        spec.warnings = validity::clip_levers(&mut spec);
        spec.standards = validity::standard_settings(&spec.reference);
    }
    sink.into_result(spec)
}

fn lever_doc_path(path: &[String]) -> KeyPath {
    std::iter::once("levers".to_string()).chain(path.iter().cloned()).collect()
}

fn lever_label(key: &str) -> String {
    format!("levers.{}", quoted_key(key))
}

fn check_top_level(file: &StudyFile, doc: &Document) -> Vec<StudyError> {
    let mut errors = plan::check_top_level(file, doc, ("a tune file", &TABLES));
    for section in ["levers", "keep"] {
        if !doc.root.contains_key(section) {
            errors.push(file.error(None, section, format!("a tune file needs a [{section}] table")));
        }
    }
    errors
}

fn check_search(file: &StudyFile, doc: &Document, s: &SearchOptions) -> Vec<StudyError> {
    let at = |key: &str| {
        let path = vec!["search".to_string(), key.to_string()];
        (doc.nearest_span(&path), format!("search.{key}"))
    };
    let mut errors = Vec::new();
    let mut check = |ok: bool, key: &str, reason: String| {
        if !ok {
            let (span, label) = at(key);
            errors.push(file.error(span, label, reason));
        }
    };
    check(s.seeds >= 2, "seeds", format!("must be at least 2 (a spread needs two runs), got {}", s.seeds));
    check(s.max_seeds >= s.seeds, "max_seeds", format!("must be at least seeds = {}, got {}", s.seeds, s.max_seeds));
    check(s.reference_seeds() >= 2, "reference_seeds", format!("must be at least 2, got {}", s.reference_seeds()));
    check(s.verify_seeds() >= 2, "verify_seeds", format!("must be at least 2, got {}", s.verify_seeds()));
    check(s.initial != Some(0), "initial", "must be at least 1".into());
    let least = s.reference_seeds() + 2 * s.seeds + 3 * s.verify_seeds();
    check(
        s.budget >= least,
        "budget",
        format!(
            "{} runs cannot hold the reference ({}), two candidates ({} each) and three verification rounds ({} each): \
             give at least {least}",
            s.budget,
            s.reference_seeds(),
            s.seeds,
            s.verify_seeds()
        ),
    );
    check(s.budget <= 100_000, "budget", format!("must be at most 100000 runs, got {}", s.budget));
    check(
        s.max_spend >= 1.0 && s.max_spend.is_finite(),
        "max_spend",
        format!("must be at least 1 reference deposition, got {}", s.max_spend),
    );
    errors
}

/// `[levers]`: `"key" = { linear = [a, b] }`, `{ log = [a, b] }` or a list, quoted or nested.
fn parse_levers(file: &StudyFile, doc: &Document) -> (Vec<Lever>, Vec<StudyError>) {
    let (mut levers, mut errors) = (Vec::new(), Vec::new());
    let Some(table) = doc.section("levers").and_then(|s| s.as_table()) else {
        return (levers, errors);
    };
    let mut found = Vec::new();
    collect(table, &mut vec!["levers".to_string()], &mut found);
    found.sort_by_key(|(doc_path, _)| doc.span(doc_path).map_or(0, |s| s.start));
    for (doc_path, value) in found {
        let path: KeyPath = doc_path[1..].iter().flat_map(|k| k.split('.')).map(String::from).collect();
        let key = path.join(".");
        let span = doc.span(&doc_path);
        let problem = |reason: String| file.error(span.clone(), lever_label(&key), reason);
        if levers.iter().any(|l: &Lever| l.key == key) {
            errors.push(problem("written twice".into()));
            continue;
        }
        if key == "placement.seed" {
            errors.push(problem("placement seeds are tune's replicates, not a lever".into()));
            continue;
        }
        match lever_range(value) {
            Ok(range) => levers.push(Lever { key, path, range }),
            Err(reason) => errors.push(problem(reason)),
        }
    }
    if levers.is_empty() && errors.is_empty() {
        errors.push(file.error(doc.span(&["levers".to_string()]), "levers", "lists no lever".to_string()));
    }
    (levers, errors)
}

fn collect<'a>(table: &'a toml::Table, prefix: &mut KeyPath, out: &mut Vec<(KeyPath, &'a toml::Value)>) {
    for (key, value) in table {
        prefix.push(key.clone());
        match value.as_table() {
            Some(inner) if !axes::is_range_spec(inner) => collect(inner, prefix, out),
            _ => out.push((prefix.clone(), value)),
        }
        prefix.pop();
    }
}

fn lever_range(value: &toml::Value) -> Result<LeverRange, String> {
    const SHAPE: &str = "a lever is { linear = [a, b] }, { log = [a, b] } or a list [v1, v2, ...]";
    match value {
        toml::Value::Array(items) if items.is_empty() => Err("a list lever needs at least one value".into()),
        toml::Value::Array(items) => {
            items.iter().map(axes::scalar).collect::<Result<Vec<_>, _>>().map(LeverRange::List)
        }
        toml::Value::Table(table) => {
            let RangeEnds { spacing, a: low, b: high, integer } = axes::range_ends(table, &[], SHAPE)?;
            if low >= high {
                return Err(format!("{}: the ends must increase, got [{low}, {high}]", spacing.key()));
            }
            Ok(match spacing {
                Spacing::Log => LeverRange::Log { low, high, integer },
                Spacing::Linear => LeverRange::Linear { low, high, integer },
            })
        }
        other => Err(format!("{SHAPE}; got a single {}", other.type_str())),
    }
}

/// Per-run quantities that are costs or settings, not results a `[keep]` entry may hold.
const NOT_KEPT: [&str; 5] = ["steps", "particle_steps", "simulated_time", "wall_time", "time_step"];

/// The per-run quantities a `[keep]` entry may name: the declared results, costs and settings left out.
pub fn keepable_metrics() -> Vec<String> {
    quantity::per_run().filter(|q| !NOT_KEPT.contains(&q.name)).map(|q| q.name.to_string()).collect()
}

/// `[keep]`: `metric = relative tolerance`, or `metric = { relative = r }` / `{ absolute = a }`.
fn parse_keep(file: &StudyFile, doc: &Document) -> (Vec<Keep>, Vec<StudyError>) {
    let (mut keep, mut errors) = (Vec::new(), Vec::new());
    let Some(table) = doc.section("keep").and_then(|s| s.as_table()) else {
        return (keep, errors);
    };
    let known = keepable_metrics();
    let mut entries: Vec<(&String, &toml::Value)> = table.iter().collect();
    entries.sort_by_key(|(k, _)| doc.span(&["keep".to_string(), (*k).clone()]).map_or(0, |s| s.start));
    for (metric, value) in entries {
        let span = doc.span(&["keep".to_string(), metric.clone()]);
        let label = format!("keep.{}", quoted_key(metric));
        if !known.contains(metric) {
            let reason = format!("unknown pile metric; one of {}", known.join(", "));
            errors.push(file.error(span, label, reason));
            continue;
        }
        let number = |v: &toml::Value| v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
        let parsed = match value {
            toml::Value::Table(t) if t.len() == 1 => match (t.get("relative"), t.get("absolute")) {
                (Some(v), None) => number(v).map(|x| (x, false)),
                (None, Some(v)) => number(v).map(|x| (x, true)),
                _ => None,
            },
            v => number(v).map(|x| (x, false)),
        };
        match parsed {
            Some((tolerance, absolute)) if tolerance > 0.0 && tolerance.is_finite() => {
                keep.push(Keep { metric: metric.clone(), tolerance, absolute })
            }
            Some((tolerance, _)) => {
                errors.push(file.error(span, label, format!("the tolerance must be > 0, got {tolerance}")))
            }
            None => errors.push(file.error(
                span,
                label,
                "expected a relative tolerance (e.g. 0.02), { relative = r } or { absolute = a }".to_string(),
            )),
        }
    }
    if keep.is_empty() && errors.is_empty() {
        errors.push(file.error(doc.span(&["keep".to_string()]), "keep", "lists no metric".to_string()));
    }
    (keep, errors)
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
