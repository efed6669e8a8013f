//! From a parsed study to a [`Plan`]: the base scene with each run's swept values set, every run
//! deserialized, validated and its placement tried, so that all problems surface before any run starts.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::de::DeserializeOwned;

use super::axes::{self, Axis, Sweep};
use super::csv_error::PlacementFileError;
use super::errors::{ErrorSink, StudyError, StudyErrors, did_you_mean, plain_types, suggest_nearest};
use super::file::{Document, KeyPath, StudyFile, dotted, leaves, set_path, set_paths, tree_with, tree_within};
use super::initial_csv::MissingRadius;
use super::{
    OutputOptions, ParamValue, Plan, PlannedRun, RunIdentity, initial_csv, lammps_file, name, reference, resources,
};
use crate::physics::SceneConfig;
use crate::physics::config::{PlacementConfig, PlacementKind};
use crate::physics::keys::implausible_values;
use crate::physics::number::exact;
use crate::physics::particles::{InitialContact, InitialDisk};
use crate::physics::placement;
use crate::physics::walls::BoxWalls;
use crate::physics::warning::WarningKind;

/// The tables of a study file (besides the strings `name` and `description`).
const TABLES: [&str; 4] = ["scene", "sweep", "output", "report"];

/// Checks the whole study and expands it into runs; every problem is reported at once.
pub(super) fn build(file: &StudyFile, doc: &Document) -> Result<Plan, StudyErrors> {
    let mut sink = ErrorSink::default();
    sink.extend(check_top_level(file, doc, ("a study", &TABLES)));
    let (base, scene_errors) = split_leaves::<SceneConfig>(file, doc, "scene");
    let refused: Vec<String> = scene_errors.iter().map(|e| e.key.clone()).collect();
    sink.extend(scene_errors);
    let (output, output_errors) = split_leaves::<OutputOptions>(file, doc, "output");
    sink.extend(output_errors);
    let (sweep, sweep_errors) = axes::parse(doc, file);
    sink.extend(sweep_errors);
    // An axis inside a refused value (a stage of a refused `[[scene.stages]]`) has nothing to set.
    let inside_refused = |axis: &Axis| {
        let key = format!("scene.{}", dotted(&axis.path));
        refused.iter().any(|r| key.strip_prefix(r.as_str()).is_some_and(|rest| rest.starts_with('.')))
    };
    let axis_errors: Vec<Vec<StudyError>> = sweep
        .axes
        .iter()
        .map(|axis| if inside_refused(axis) { Vec::new() } else { check_axis(file, &base, axis, sweep.replicates) })
        .collect();
    let faulty: Vec<bool> = axis_errors.iter().map(|e| !e.is_empty()).collect();
    sink.extend(axis_errors.into_iter().flatten());
    sink.extend(reference::check(file, doc, &sweep, &faulty));
    if !sink.is_empty() {
        // A refused value's key is checked with its default standing in: what that finds is not the user's.
        sink.extend(check_base_scene(file, doc, &base).into_iter().filter(|e| !refused.contains(&e.key)));
        return Err(sink.into_errors());
    }
    let mut planner = Planner::new(file, doc, &base, &sweep);
    let runs = planner.expand(&mut sink);
    let plan = Plan {
        study_path: file.path.clone(),
        study_text: file.text.clone(),
        name: study_name(doc, &file.path),
        fingerprint: fingerprint_with_inputs(&file.text, &runs),
        output: toml::Value::Table(output).try_into().unwrap_or_default(),
        runs,
        warnings: planner.warnings.into_errors().0,
    };
    sink.into_result(plan)
}

/// Unknown top-level keys, and tables or strings of the wrong type, of `what` (e.g. "a study")
/// whose tables are `tables`.
pub(crate) fn check_top_level(file: &StudyFile, doc: &Document, (what, tables): (&str, &[&str])) -> Vec<StudyError> {
    let mut errors = Vec::new();
    for (key, value) in &doc.root {
        let span = doc.span(std::slice::from_ref(key));
        let wrong = match key.as_str() {
            "name" | "description" if !value.is_str() => Some("must be a string".to_string()),
            k if tables.contains(&k) && !value.is_table() => Some("must be a table".to_string()),
            "name" | "description" => None,
            k if !tables.contains(&k) => {
                let known: Vec<String> = tables.iter().map(|t| format!("[{t}]")).collect();
                let list = || format!("{what} has name, description, {}", known.join(", "));
                let valid = ["name", "description"].into_iter().chain(tables.iter().copied());
                Some(format!("unknown key ({})", did_you_mean(k, valid).unwrap_or_else(list)))
            }
            _ => None,
        };
        if let Some(reason) = wrong {
            errors.push(file.error(span, dotted(std::slice::from_ref(key)), reason));
        }
    }
    errors.extend(check_study_name(file, doc));
    errors
}

/// An unsafe study name (the `name` key, or the file stem when there is none).
fn check_study_name(file: &StudyFile, doc: &Document) -> Option<StudyError> {
    let written = doc.section("name");
    if written.is_some_and(|n| !n.is_str()) {
        return None;
    }
    let reason = name::check_name(&study_name(doc, &file.path)).err()?;
    Some(match written {
        Some(_) => file.error(doc.span(&["name".to_string()]), "name", reason.to_string()),
        None => file.error(None, "name", format!("{reason}; the name comes from the file name: set `name = \"…\"`")),
    })
}

/// Deserializes every value of `[section]` on its own into `T`, so that each unknown key and
/// wrong type is reported (serde stops at the first). Returns the section without the bad values.
pub(crate) fn split_leaves<T: DeserializeOwned>(
    file: &StudyFile,
    doc: &Document,
    section: &str,
) -> (toml::Table, Vec<StudyError>) {
    let (mut valid, mut errors) = (toml::Table::new(), Vec::new());
    let Some(table) = doc.section(section).and_then(|s| s.as_table()) else {
        return (valid, errors);
    };
    for (path, value) in leaves(table) {
        match toml::Value::Table(tree_with(&path, value.clone())).try_into::<T>() {
            Ok(_) => set_path(&mut valid, &path, value.clone()).expect("leaves of a table do not collide"),
            Err(e) => {
                let reason = explain::<T>(&path, e.message(), value);
                let full: KeyPath = std::iter::once(section.to_string()).chain(path).collect();
                errors.push(file.error(doc.span(&full), dotted(&full), reason));
            }
        }
    }
    (valid, errors)
}

/// A deserializer's message about `value` at `path` of a `T` in the study's words: a value of
/// the wrong type for a choice lists the choices, Rust type names become what to write
/// ([`plain_types`]), an unknown key or choice names the valid one nearest to it ([`suggest_nearest`]).
fn explain<T: DeserializeOwned>(path: &[String], message: &str, value: &toml::Value) -> String {
    if message.contains("unit variant") {
        let probe = toml::Value::Table(tree_with(path, toml::Value::String("\u{1}".into())));
        let choices = probe.try_into::<T>().err().map(|e| e.message().to_string());
        if let Some((_, choices)) =
            choices.as_deref().filter(|m| m.contains("variant")).and_then(|m| m.split_once("expected "))
        {
            return format!("must be {choices} (a string in quotes)");
        }
    }
    suggest_nearest(&plain_types(message, value))
}

/// The impossible values of the base scene (without its sweep), for a study that cannot be expanded.
fn check_base_scene(file: &StudyFile, doc: &Document, base: &toml::Table) -> Vec<StudyError> {
    let no_sweep = Sweep::single();
    let mut planner = Planner::new(file, doc, base, &no_sweep);
    let errors = planner.plan_run(0, String::new()).err().unwrap_or_default();
    errors.into_iter().map(|e| StudyError { run: None, runs_affected: 0, ..e }).collect()
}

/// An axis whose key cannot be set in the scene, whose values the scene rejects by type, or that
/// clashes with `replicates`.
fn check_axis(file: &StudyFile, base: &toml::Table, axis: &Axis, replicates: usize) -> Vec<StudyError> {
    let at = || file.error(Some(axis.span.clone()), axis.label(), "");
    let with = |reason: String| StudyError { reason, ..at() };
    if let Err(reason) = set_path(&mut base.clone(), &axis.path, axis.values[0].to_toml()) {
        return vec![with(format!("cannot sweep this key: scene.{reason}"))];
    }
    if replicates > 1 && axis.key() == "placement.seed" {
        return vec![with("replicates derive placement.seed; sweep either the seed or replicates, not both".into())];
    }
    let failures: Vec<(&ParamValue, String)> = axis
        .values
        .iter()
        .filter_map(|v| {
            let tree = toml::Value::Table(tree_within(base, &axis.path, v.to_toml()));
            let reason = |e: toml::de::Error| explain::<SceneConfig>(&axis.path, e.message(), &v.to_toml());
            tree.try_into::<SceneConfig>().err().map(|e| (v, reason(e)))
        })
        .collect();
    if failures.len() == axis.values.len() && failures.iter().all(|(_, m)| *m == failures[0].1) {
        return vec![with(failures[0].1.clone())];
    }
    failures.into_iter().map(|(v, reason)| with(reason).with_value(v.to_string())).collect()
}

/// The study's `name`, else the file stem.
pub(crate) fn study_name(doc: &Document, path: &Path) -> String {
    match doc.section("name").and_then(|n| n.as_str()) {
        Some(name) => name.to_string(),
        None => path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default(),
    }
}

/// FNV-1a 64 of the study text and the demsweep version, as 16 hex digits.
pub(crate) fn fingerprint(text: &str) -> String {
    let bytes = text.bytes().chain(std::iter::once(0)).chain(env!("CARGO_PKG_VERSION").bytes());
    format!("{:016x}", super::identity::fnv(bytes))
}

/// The fingerprint of a study text whose runs are `runs`: of its text, the demsweep version and
/// the content of its input files, so that shards or a resume whose placement file changed differ.
fn fingerprint_with_inputs(text: &str, runs: &[PlannedRun]) -> String {
    let mut inputs: Vec<u64> = RunIdentity::all(runs).iter().map(|identity| identity.inputs).collect();
    inputs.sort_unstable();
    inputs.dedup();
    let digests: String = inputs.iter().map(|d| format!("{d:016x}")).collect();
    fingerprint(&format!("{text}\0{digests}"))
}

/// Run ids `r0000`, `r0001`, ... zero-padded to the plan's size (at least 4 digits).
pub(crate) fn run_id(index: usize, runs: usize) -> String {
    let width = runs.saturating_sub(1).to_string().len().max(4);
    format!("r{index:0width$}")
}

/// Disks read from a placement file, or why they could not be read.
type InitialStates = Result<Arc<Vec<InitialDisk>>, PlacementFileError>;

/// A restart's contact history, shared by the runs that use its file.
type InitialContacts = Arc<Vec<InitialContact>>;

/// Disks a generated placement gives, or its problem (key, reason).
type Placed = Result<Arc<Vec<InitialDisk>>, (String, String)>;

/// Expands runs, caching what several runs share (placement files, placement outcomes).
struct Planner<'a> {
    file: &'a StudyFile,
    doc: &'a Document,
    base: &'a toml::Table,
    sweep: &'a Sweep,
    study_dir: PathBuf,
    /// Placement files read so far, by path, kind and what a disk without a radius gets (the
    /// radius's bits, or the key that draws radii).
    initial_files: HashMap<(PathBuf, PlacementKind, Result<u64, &'static str>), InitialStates>,
    /// Contact files read so far, by path and the disks and walls they were checked against.
    contact_files: HashMap<(PathBuf, usize, usize), Result<InitialContacts, PlacementFileError>>,
    /// Placements that failed, by the scene sections they depend on: (key, reason).
    failed_placements: HashMap<String, (String, String)>,
    /// The first seed's problem of each setup whose placement failed, by the sections without the
    /// seed: later seeds that fail too report it, so that it is one problem with a count of runs.
    first_failures: HashMap<String, (String, String)>,
    /// The last placement that succeeded: its setup and disks.
    last_placement: Option<(String, Arc<Vec<InitialDisk>>)>,
    /// Warnings so far, one per kind and place.
    warnings: ErrorSink,
}

/// One run while it is being planned: its swept values, for locating problems.
struct RunPoint<'a> {
    id: String,
    chosen: Vec<&'a ParamValue>,
    replicates: bool,
}

impl<'a> Planner<'a> {
    fn new(file: &'a StudyFile, doc: &'a Document, base: &'a toml::Table, sweep: &'a Sweep) -> Self {
        let study_dir = file.path.parent().map(Path::to_path_buf).unwrap_or_default();
        let (initial_files, failed_placements, warnings) = (HashMap::new(), HashMap::new(), ErrorSink::by_kind());
        let (contact_files, first_failures) = (HashMap::new(), HashMap::new());
        let last_placement = None;
        Self {
            file,
            doc,
            base,
            sweep,
            study_dir,
            initial_files,
            contact_files,
            failed_placements,
            first_failures,
            last_placement,
            warnings,
        }
    }

    fn expand(&mut self, sink: &mut ErrorSink) -> Vec<PlannedRun> {
        let count = self.sweep.run_count();
        let mut runs = Vec::with_capacity(count);
        for index in 0..count {
            match self.plan_run(index, run_id(index, count)) {
                Ok(run) => runs.push(run),
                Err(errors) => sink.extend(errors),
            }
        }
        runs
    }

    fn plan_run(&mut self, index: usize, id: String) -> Result<PlannedRun, Vec<StudyError>> {
        let sweep = self.sweep;
        let (chosen, replicate) = sweep.point(index);
        let chosen: Vec<&ParamValue> = sweep.axes.iter().zip(&chosen).map(|(a, &k)| &a.values[k]).collect();
        let point = RunPoint { id, chosen, replicates: sweep.replicates > 1 };
        let mut scene = self.scene(&point)?;
        let mut parameters: Vec<(String, ParamValue)> =
            sweep.axes.iter().zip(&point.chosen).map(|(a, v)| (a.key(), (*v).clone())).collect();
        if point.replicates {
            let seed = scene.placement.seed.checked_add(replicate as u64).and_then(|s| i64::try_from(s).ok());
            let seed =
                seed.ok_or_else(|| vec![self.problem(&point, "placement.seed", "seed + replicate overflows".into())])?;
            scene.placement.seed = seed as u64;
            parameters.push(("placement.seed".into(), ParamValue::Int(seed)));
        }
        let initial = self.initial_states(&point, &mut scene)?;
        self.check_scene(&point, &scene, initial.as_ref())?;
        self.warn_copies(&point, &scene);
        if let Some((key, reason)) = scene.stages_past_the_run() {
            self.warnings.push(self.problem(&point, &key, reason));
        }
        let initial_contacts = self.initial_contacts(&point, &scene)?;
        let mut run = PlannedRun::new(point.id, index, parameters, scene, initial);
        run.initial_contacts = initial_contacts;
        Ok(run)
    }

    /// The base scene with this run's swept values set.
    fn scene(&self, point: &RunPoint) -> Result<SceneConfig, Vec<StudyError>> {
        let mut tree = self.base.clone();
        let values = self.sweep.axes.iter().zip(&point.chosen).map(|(axis, value)| (&axis.path[..], value.to_toml()));
        set_paths(&mut tree, values).expect("axes were checked against the base scene");
        toml::Value::Table(tree).try_into::<SceneConfig>().map_err(|e| {
            let span = self.doc.span(&["scene".to_string()]);
            vec![self.file.error(span, "scene", e.message()).in_run(&point.id)]
        })
    }

    /// A run's problem with scene key `key`: located at the axis that sets it, else in `[scene]`.
    fn problem(&self, point: &RunPoint, key: &str, reason: String) -> StudyError {
        let plain = key.split('[').next().unwrap_or(key);
        let path: KeyPath = plain.split('.').map(String::from).collect();
        let swept = self.sweep.axes.iter().zip(&point.chosen).find(|(a, _)| a.path == path);
        let error = match swept {
            Some((axis, value)) => {
                self.file.error(Some(axis.span.clone()), axis.label(), reason).with_value(value.to_string())
            }
            None if point.replicates && plain == "placement.seed" => {
                self.file.error(self.sweep.replicates_span.clone(), "sweep.replicates", reason)
            }
            None => {
                let full: KeyPath = std::iter::once("scene".to_string()).chain(path).collect();
                self.file.error(self.doc.nearest_span(&full), format!("scene.{key}"), reason)
            }
        };
        error.in_run(&point.id)
    }

    /// File placement: the disks read from `placement.file` (relative to the study's folder);
    /// sets `particles.count` to their number. The file gives the radii, else `particles.radius`
    /// does; a radius key that draws radii is refused with a file without them, and warned of with a
    /// file with them (it draws none).
    fn initial_states(
        &mut self,
        point: &RunPoint,
        scene: &mut SceneConfig,
    ) -> Result<Option<Arc<Vec<InitialDisk>>>, Vec<StudyError>> {
        let (true, Some(name)) = (scene.placement.kind.reads_file(), &scene.placement.file) else {
            return Ok(None);
        };
        let path = self.study_dir.join(name);
        let (kind, missing) = (scene.placement.kind, MissingRadius::of(&scene.particles));
        let radius_key = match missing {
            MissingRadius::Radius(radius) => Ok(radius.to_bits()),
            MissingRadius::Drawn(key) => Err(key),
        };
        let disks = self
            .initial_files
            .entry((path.clone(), kind, radius_key))
            .or_insert_with(|| lammps_file::read_placement(kind, &path, missing, &self.study_dir).map(Arc::new))
            .clone()
            .map_err(|reason| vec![self.problem(point, "placement.file", reason.to_string())])?;
        if let MissingRadius::Drawn(key) = missing {
            let reason = format!(
                "draws no radius: {} gives every disk's own (a placement file keeps its radii); remove {key}",
                path.display()
            );
            let warning = self.problem(point, key, reason);
            self.warnings.push(warning);
        }
        scene.particles.count = disks.len();
        Ok(Some(disks))
    }

    /// A restart's contact history: the contacts read from `placement.contacts` (relative to the
    /// study's folder), checked against the placement file's disks and the box's walls.
    fn initial_contacts(
        &mut self,
        point: &RunPoint,
        scene: &SceneConfig,
    ) -> Result<Option<InitialContacts>, Vec<StudyError>> {
        let Some(name) = &scene.placement.contacts else {
            return Ok(None);
        };
        let path = self.study_dir.join(name);
        let (disks, walls) = (scene.particles.count, BoxWalls::new(&scene.domain).walls.len());
        let contacts = self
            .contact_files
            .entry((path.clone(), disks, walls))
            .or_insert_with(|| initial_csv::read_contacts(&path, disks, walls, &self.study_dir).map(Arc::new))
            .clone()
            .map_err(|reason| vec![self.problem(point, "placement.contacts", reason.to_string())])?;
        Ok(Some(contacts))
    }

    /// Validation, then (for valid scenes) whether the state fits in memory and the disks in the box:
    /// placement is tried once per distinct domain/particles/placement, and file disks must not overlap
    /// each other or the walls beyond `limits.max_overlap_ratio`. Warnings (overlaps beyond
    /// `limits.overlap_warning_ratio`, sampling, the predicted validity of the run) are collected.
    fn check_scene(
        &mut self,
        point: &RunPoint,
        scene: &SceneConfig,
        initial: Option<&Arc<Vec<InitialDisk>>>,
    ) -> Result<(), Vec<StudyError>> {
        if let Err(issues) = scene.validate() {
            // A length written in mm is often why a box is too small: the hint of a value that looks
            // written in another unit goes with the errors.
            let hints = implausible_values(scene).into_iter();
            let hints = hints.filter(|h| !h.suggestions.is_empty() && issues.iter().all(|i| i.key != h.key));
            let hints: Vec<StudyError> = hints.map(|h| self.problem(point, &h.key, h.to_string())).collect();
            let errors = issues.into_iter().map(|i| self.problem(point, &i.key, i.reason));
            return Err(errors.chain(hints).collect());
        }
        if let Some((key, reason)) = resources::stage_table_problem(scene).or_else(|| resources::memory_problem(scene))
        {
            return Err(vec![self.problem(point, key, reason)]);
        }
        for (key, reason) in sampling_warnings(scene) {
            let warning = self.problem(point, key, reason);
            self.warnings.push(warning);
        }
        for implausible in implausible_values(scene) {
            let warning = self.problem(point, &implausible.key, implausible.to_string());
            self.warnings.push(warning);
        }
        let disks = match initial {
            Some(disks) => {
                let overlaps = placement::Overlaps::find(scene, disks);
                if let Some(reason) = overlaps.warning() {
                    let warning = self.problem(point, "placement.file", reason);
                    self.warnings.push(warning);
                }
                if let Some(reason) = overlaps.error() {
                    return Err(vec![self.problem(point, "placement.file", reason)]);
                }
                disks.clone()
            }
            None => self.try_placement(scene).map_err(|(key, reason)| vec![self.problem(point, &key, reason)])?,
        };
        let own = crate::physics::predict_stability(scene, &disks).warnings;
        let stages = crate::physics::predict_stage_warnings(scene, &disks, &own);
        for (stage, predicted) in
            own.into_iter().map(|w| (None, w)).chain(stages.into_iter().map(|(k, w)| (Some(k), w)))
        {
            let (key, value) = scene.key_at_fault(predicted.kind, stage);
            let during = stage.map(|k| format!(" in stage \"{}\"", scene.stages[k].name)).unwrap_or_default();
            let reason = format!("predicted{during}: {predicted}{}", contacts_named(scene, predicted.kind));
            let mut warning = self.problem(point, &key, reason).of_rule(predicted.kind);
            warning.value = warning.value.or_else(|| Some(exact(value)));
            self.warnings.push(warning);
        }
        Ok(())
    }

    /// Seeds that replicate nothing: the study's seeds (replicates or a `placement.seed` axis) run
    /// identical copies of a scene whose disks do not depend on the seed.
    fn warn_copies(&mut self, point: &RunPoint, scene: &SceneConfig) {
        let seed_axis = self.sweep.axes.iter().find(|axis| axis.key() == "placement.seed");
        let seeds = seed_axis.map_or(self.sweep.replicates, |axis| axis.values.len());
        if seeds < 2 || placement::draws_from_seed(scene) {
            return;
        }
        let kind = serde_json::to_string(&scene.placement.kind).unwrap_or_default();
        let reason = format!(
            "placement.kind = {kind} places the same disks whatever placement.seed: the study's {seeds} seeds run \
             identical copies, whose spread is 0 (95 % intervals of ±0, comparisons on zero variance); use \
             random or dropped placement or drawn radii, or drop the seeds"
        );
        let warning = self.problem(point, "placement.kind", reason);
        self.warnings.push(warning);
    }

    /// The disks of a generated placement, or its problem (key, reason). A failure is remembered per
    /// setup, and reported in the words of the setup's first failing seed; the disks only for the
    /// last setup (consecutive runs often share it; keeping every setup's disks could fill the memory).
    fn try_placement(&mut self, scene: &SceneConfig) -> Placed {
        let setup = placement_setup(scene);
        if let Some((last, disks)) = &self.last_placement
            && *last == setup
        {
            return Ok(disks.clone());
        }
        if let Some(problem) = self.failed_placements.get(&setup) {
            return Err(problem.clone());
        }
        let outcome = match placement::generate(scene) {
            Ok(disks) if disks.is_empty() => {
                Err(("particles.count".to_string(), "a scene needs at least one disk, got 0".to_string()))
            }
            Ok(disks) => Ok(Arc::new(disks)),
            Err(e) => Err((e.key, e.reason)),
        };
        match outcome {
            Ok(disks) => {
                self.last_placement = Some((setup, disks.clone()));
                Ok(disks)
            }
            Err(problem) => {
                let any_seed =
                    SceneConfig { placement: PlacementConfig { seed: 0, ..scene.placement.clone() }, ..scene.clone() };
                let first = self.first_failures.entry(placement_setup(&any_seed)).or_insert(problem).clone();
                self.failed_placements.insert(setup, first.clone());
                Err(first)
            }
        }
    }
}

/// The scene sections a generated placement depends on, as one string.
fn placement_setup(scene: &SceneConfig) -> String {
    serde_json::to_string(&(&scene.domain, &scene.particles, &scene.placement)).unwrap_or_default()
}

/// Sampling that cannot sample: an interval longer than the run, frames past its end (key, reason).
fn sampling_warnings(scene: &SceneConfig) -> Vec<(&'static str, String)> {
    let run = &scene.run;
    let mut warnings = Vec::new();
    if run.sample_interval > run.duration {
        warnings.push((
            "run.sample_interval",
            format!(
                "{} s is longer than run.duration ({} s): the run is sampled only at its start and end, so its \
                 histories, settle detection and divergence checks see two samples; use an interval below the duration",
                run.sample_interval, run.duration
            ),
        ));
    }
    if let Some(interval) = run.frame_interval.filter(|i| *i > run.duration) {
        warnings.push((
            "run.frame_interval",
            format!("{interval} s is longer than run.duration ({} s): no periodic frame is recorded", run.duration),
        ));
    }
    let late: Vec<String> = run.frame_times.iter().filter(|t| **t > run.duration).map(|t| format!("{t} s")).collect();
    if !late.is_empty() {
        warnings.push((
            "run.frame_times",
            format!("{} past run.duration ({} s): never recorded", late.join(", "), run.duration),
        ));
    }
    warnings
}

/// For a predicted overlap, the contacts that are too soft: " (hertz_mindlin, E = 2.000e4 Pa)".
fn contacts_named(scene: &SceneConfig, kind: WarningKind) -> String {
    if !matches!(kind, WarningKind::ImpactOverlap | WarningKind::StaticOverlap) {
        return String::new();
    }
    format!(" ({}, E = {:.3e} Pa)", scene.contact.law_name(), scene.material.youngs_modulus)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_ids_are_padded_to_the_plan_size() {
        assert_eq!(run_id(7, 12), "r0007");
        assert_eq!(run_id(0, 10_000), "r0000");
        assert_eq!(run_id(12_345, 100_001), "r012345");
    }

    #[test]
    fn fingerprint_depends_on_the_text() {
        assert_eq!(fingerprint("a = 1"), fingerprint("a = 1"));
        assert_ne!(fingerprint("a = 1"), fingerprint("a = 2"));
        assert_eq!(fingerprint("").len(), 16);
    }
}
