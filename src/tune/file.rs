//! The tune file: a reference `[scene]`, the `[levers]` tune may move, the pile metrics to `[keep]`
//! and the `[search]` settings; checked like a study (every problem at once, file:line:column: key).

use std::ops::Range;
use std::path::Path;
use std::sync::Arc;

use crate::physics::SceneConfig;
use crate::physics::number::exact;
use crate::physics::placement;
use crate::physics::quantity;
use crate::physics::warning::ValidityWarning;
use crate::study::axes::{self, RangeEnds, Spacing};
use crate::study::errors::{ErrorSink, StudyError, StudyErrors, did_you_mean};
use crate::study::file::{Document, KeyPath, MAX_STUDY_BYTES, StudyFile, quoted_key, read_text};
use crate::study::initial_csv::MissingRadius;
use crate::study::plan::{self, fingerprint, split_leaves};
use crate::study::{AxisError, OutputOptions, ParamValue, lammps_file};

use super::ladder;
use super::measurable;
use super::search::KEPT_ROUNDS;
use super::spec::{Keep, Lever, LeverRange, SearchOptions, TuneSpec};
use super::validity;

/// The tables of a tune file (besides the strings `name` and `description`).
const TABLES: [&str; 5] = ["scene", "levers", "keep", "search", "output"];

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
    let mut spec = parse_spec(&file, &doc, &mut sink);
    // The levers are checked against the valid part of the scene even when other keys are wrong, so
    // that every problem is reported at once.
    let scene_span = doc.span(&["scene".to_string()]);
    match spec.scene(&[]) {
        Ok(scene) => spec.reference = scene,
        Err(reason) => {
            sink.push(file.error(scene_span, "scene", reason.to_string()));
            return Err(sink.into_errors());
        }
    }
    check_reference_placement(&file, scene_span, &mut spec, &mut sink);
    for lever in &spec.levers {
        check_lever_extremes(&file, &doc, &spec, lever, &mut sink);
    }
    if sink.is_empty() {
        let (warnings, tops) = validity::clip_levers(&mut spec);
        spec.warnings = warnings;
        spec.warnings.extend(measurable::kept_metric_warnings(&spec));
        spec.standards = ladder::standard_settings(&spec.reference, &spec.levers, &tops);
    }
    sink.into_result(spec)
}

/// A tune file's `text` loaded from a file of its own (`name`, in the temporary folder), for tests.
#[cfg(test)]
pub(crate) fn load_text(name: &str, text: &str) -> TuneSpec {
    let path = std::env::temp_dir().join(format!("demsweep-{name}-{}.toml", std::process::id()));
    std::fs::write(&path, text).unwrap();
    let spec = load(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    spec
}

/// The first of the reference's replicates whose placement fails, with why: the tune could not
/// start (a random placement near its jamming limit fits on some seeds and not on others).
fn reference_placement_failure(spec: &TuneSpec) -> Option<(u64, placement::PlacementError)> {
    (0..spec.search.reference_seeds() as u64)
        .find_map(|replicate| spec.placement_failure(replicate).map(|e| (replicate, e)))
}

/// The tune file's tables as a spec (its reference scene, initial disks, warnings and standard
/// settings not yet made), their problems into `sink`.
fn parse_spec(file: &StudyFile, doc: &Document, sink: &mut ErrorSink) -> TuneSpec {
    sink.extend(check_top_level(file, doc));
    let (base, scene_errors) = split_leaves::<SceneConfig>(file, doc, "scene");
    sink.extend(scene_errors);
    let (output, output_errors) = split_leaves::<OutputOptions>(file, doc, "output");
    sink.extend(output_errors);
    let (search, search_errors) = split_leaves::<SearchOptions>(file, doc, "search");
    sink.extend(search_errors);
    let search: SearchOptions = toml::Value::Table(search).try_into().unwrap_or_default();
    sink.extend(check_search(file, doc, &search));
    let (levers, lever_errors) = parse_levers(file, doc);
    sink.extend(lever_errors);
    let (keep, keep_errors) = parse_keep(file, doc);
    sink.extend(keep_errors);
    let mut output_tree = toml::Table::new();
    output_tree.insert("histories".into(), toml::Value::Boolean(false));
    output_tree.insert("frames".into(), toml::Value::Boolean(false));
    output_tree.extend(output);
    TuneSpec {
        path: file.path.clone(),
        text: file.text.clone(),
        name: plan::study_name(doc, &file.path),
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
    }
}

/// Places the reference scene's disks: reads its placement file into `spec.initial` (and the disk
/// count), else generates the placement to check it; a failure into `sink` at `scene_span`.
fn check_reference_placement(
    file: &StudyFile,
    scene_span: Option<Range<usize>>,
    spec: &mut TuneSpec,
    sink: &mut ErrorSink,
) {
    let reference = &spec.reference;
    if let (true, Some(name)) = (reference.placement.kind.reads_file(), &reference.placement.file) {
        let folder = file.path.parent().unwrap_or(Path::new(""));
        let missing = MissingRadius::of(&reference.particles);
        match lammps_file::read_placement(reference.placement.kind, &folder.join(name), missing, folder) {
            Ok(disks) => {
                spec.reference.particles.count = disks.len();
                spec.initial = Some(Arc::new(disks));
            }
            Err(reason) => sink.push(file.error(scene_span, "scene.placement.file", reason.to_string())),
        }
    } else if let Some((replicate, e)) = reference_placement_failure(spec) {
        let on = if replicate == 0 {
            String::new()
        } else {
            let seed = spec.reference_at(replicate).placement.seed;
            format!(" (on the reference's replicate {replicate}, placement.seed = {seed})")
        };
        sink.push(file.error(scene_span, format!("scene.{}", e.key), format!("{}{on}", e.reason)));
    }
}

/// Checks the scene at each extreme of `lever` (and its placement, where the lever moves the box, the
/// disks or the placement and they are generated): one error when every extreme fails the same
/// way, else one per failing value.
fn check_lever_extremes(file: &StudyFile, doc: &Document, spec: &TuneSpec, lever: &Lever, sink: &mut ErrorSink) {
    let span =
        doc.span(&["levers".to_string(), lever.key.clone()]).or_else(|| doc.nearest_span(&lever_doc_path(&lever.path)));
    let extremes = lever.extremes();
    let failures: Vec<(ParamValue, String)> = extremes
        .iter()
        .filter_map(|value| {
            let scene = spec.scene(&[(lever.key.clone(), value.clone())]).map_err(|e| e.to_string());
            let problem = scene.and_then(|scene| {
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

/// The reference scene's predicted validity warnings, each at the key at fault as a study's are
/// (`FILE:LINE:COLUMN: scene.KEY: value V: predicted: ...`, a stage's key where a stage breaks the rule).
pub fn reference_warnings(spec: &TuneSpec) -> Vec<String> {
    let file = StudyFile::new(&spec.path, spec.text.clone());
    let doc = Document::parse(&file).ok();
    let span = |key: &str| {
        let path: KeyPath = std::iter::once("scene").chain(key.split('.')).map(String::from).collect();
        doc.as_ref().and_then(|doc| doc.nearest_span(&path))
    };
    let scene = &spec.reference;
    let predicted = match validity::predicted_in_stages(scene, spec.initial.as_deref().map(Vec::as_slice)) {
        Ok(predicted) => predicted,
        Err(reason) => return vec![file.error(span(""), "scene", format!("the reference: {reason}")).to_string()],
    };
    let warning = |(stage, w): (Option<usize>, ValidityWarning)| {
        let (key, value) = scene.key_at_fault(w.kind, stage);
        let during = stage.map(|k| format!(" in stage \"{}\"", scene.stages[k].name)).unwrap_or_default();
        let reason = format!(
            "predicted{during}: {w}. The reference itself breaks {}: tune holds every candidate to no worse than \
             the reference on it",
            w.kind.limit_key()
        );
        file.error(span(&key), format!("scene.{key}"), reason).with_value(exact(value)).to_string()
    };
    predicted.into_iter().map(warning).collect()
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
    let least = s.reference_seeds() + 2 * s.seeds + KEPT_ROUNDS * s.verify_seeds();
    check(
        s.budget >= least,
        "budget",
        format!(
            "{} runs cannot hold the reference ({}), two candidates ({} each) and {KEPT_ROUNDS} verification rounds ({} each): \
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
            Err(reason) => errors.push(problem(reason.to_string())),
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

fn lever_range(value: &toml::Value) -> Result<LeverRange, AxisError> {
    const SHAPE: &str = "a lever is { linear = [a, b] }, { log = [a, b] } or a list [v1, v2, ...]";
    match value {
        toml::Value::Array(items) if items.is_empty() => Err(AxisError::EmptyLever),
        toml::Value::Array(items) => {
            items.iter().map(axes::scalar).collect::<Result<Vec<_>, _>>().map(LeverRange::List)
        }
        toml::Value::Table(table) => {
            let RangeEnds { spacing, a: low, b: high, integer } = axes::range_ends(table, &[], SHAPE)?;
            if low >= high {
                return Err(AxisError::Decreasing { spacing, low, high });
            }
            Ok(match spacing {
                Spacing::Log => LeverRange::Log { low, high, integer },
                Spacing::Linear => LeverRange::Linear { low, high, integer },
            })
        }
        other => Err(AxisError::Shape { shape: SHAPE, found: other.type_str() }),
    }
}

/// Per-run quantities that are costs or settings, not results a `[keep]` entry may hold.
const NOT_KEPT: [&str; 6] = ["steps", "particle_steps", "simulated_time", "wall_time", "cpu_time", "time_step"];

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
            let list = || format!("one of {}", known.join(", "));
            let reason = format!(
                "unknown pile metric; {}",
                did_you_mean(metric, known.iter().map(String::as_str)).unwrap_or_else(list)
            );
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
                errors.push(file.error(span, label, format!("the tolerance must be > 0, got {}", exact(tolerance))))
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
