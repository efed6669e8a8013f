//! Study files: a base scene plus sweep axes, expanded into a plan (the list of runs).
//!
//! Data flows one way: study file → [`Plan`] → runner → simulation → records → writers.
//! [`load`] reads a study file (format: docs/studies.md) and checks everything a run
//! could fail on at its start: every problem of the whole study is reported at once.

pub(crate) mod axes;
pub(crate) mod errors;
pub(crate) mod file;
pub mod identity;
pub mod initial_csv;
pub mod lammps_file;
pub mod name;
pub(crate) mod plan;
pub mod reference;
pub mod resources;

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::{Deserialize, Serialize};

pub use axes::MAX_RUNS;
pub use errors::{Location, StudyError, StudyErrors, did_you_mean, nearest, warning_kind};
pub use identity::{IdentityChange, RunIdentity};

use crate::physics::SceneConfig;
use crate::physics::particles::{InitialContact, InitialDisk};

/// Reads, checks and expands a study file into its plan.
pub fn load(path: &Path) -> Result<Plan, StudyErrors> {
    expand(&file::StudyFile::read(path)?)
}

/// Checks and expands a study given as text, as [`load`] does a file holding it; `path` names it in
/// errors (and relative placement files are found from its folder).
pub fn load_text(path: &Path, text: String) -> Result<Plan, StudyErrors> {
    expand(&file::StudyFile::new(path, text))
}

fn expand(study: &file::StudyFile) -> Result<Plan, StudyErrors> {
    let doc = file::Document::parse(study).map_err(StudyErrors::sorted)?;
    plan::build(study, &doc)
}

/// Which placement seeds a single scene runs with (see [`scene_study`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Seeds {
    /// One run, with the scene's own `placement.seed`.
    Scene,
    /// `n` runs, seeds `placement.seed`, `placement.seed + 1`, … (a study's `replicates = n`).
    Replicates(usize),
    /// One run per seed (a study's `"placement.seed" = [...]`).
    List(Vec<i64>),
}

/// The name of the study [`scene_study`] writes.
pub const SCENE_STUDY_NAME: &str = "scene";

/// The text of a study that runs one scene (`scene`: the keys of a study's `[scene]`) with `seeds`:
/// `check`, `run` and [`load_text`] of it report and run exactly what a study file holding it would.
pub fn scene_study(scene: toml::Table, seeds: &Seeds) -> String {
    let mut study = toml::Table::new();
    study.insert("name".into(), toml::Value::String(SCENE_STUDY_NAME.into()));
    study.insert("scene".into(), toml::Value::Table(scene));
    let sweep = match seeds {
        Seeds::Scene => None,
        Seeds::Replicates(n) => Some(("replicates", toml::Value::Integer(*n as i64))),
        Seeds::List(seeds) => {
            Some(("placement.seed", toml::Value::Array(seeds.iter().map(|&s| toml::Value::Integer(s)).collect())))
        }
    };
    if let Some((key, value)) = sweep {
        study.insert("sweep".into(), toml::Value::Table(toml::Table::from_iter([(key.to_string(), value)])));
    }
    toml::to_string(&study).expect("a table of TOML values serializes")
}

/// The TOML text `text` (named `path` in errors) as a table; its syntax errors located as in a study.
pub fn parse_table(path: &Path, text: String) -> Result<toml::Table, StudyErrors> {
    let doc = file::Document::parse(&file::StudyFile::new(path, text)).map_err(StudyErrors::sorted)?;
    Ok(doc.root)
}

/// One swept parameter's value, typed as in the study file.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamValue {
    /// A float (most axes).
    Float(f64),
    /// An integer (e.g. a seed or a count).
    Int(i64),
    /// A boolean.
    Bool(bool),
    /// A string (e.g. an integrator name).
    Text(String),
}

impl ParamValue {
    /// The value as TOML.
    pub fn to_toml(&self) -> toml::Value {
        match self {
            Self::Float(v) => toml::Value::Float(*v),
            Self::Int(v) => toml::Value::Integer(*v),
            Self::Bool(v) => toml::Value::Boolean(*v),
            Self::Text(v) => toml::Value::String(v.clone()),
        }
    }
}

/// Floats print shortest-exact (`0.7`, `1e9`, `2.5e-5`), text quoted as in TOML.
impl fmt::Display for ParamValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Float(v) if *v != 0.0 && !(1e-3..1e6).contains(&v.abs()) => write!(f, "{v:e}"),
            Self::Float(v) => write!(f, "{v:?}"),
            Self::Int(v) => write!(f, "{v}"),
            Self::Bool(v) => write!(f, "{v}"),
            Self::Text(v) => write!(f, "{}", toml::Value::String(v.clone())),
        }
    }
}

/// Which optional outputs a study asks for (what nobody asked for is not computed or written).
/// Written as the study's `[output]` table; everything defaults to `true`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OutputOptions {
    /// Write energy/UBF histories per run.
    pub histories: bool,
    /// Write the final state of every run.
    pub final_states: bool,
    /// Write recorded frames (the scene's `run.frame_times` / `run.frame_interval`).
    pub frames: bool,
}

impl Default for OutputOptions {
    fn default() -> Self {
        Self { histories: true, final_states: true, frames: true }
    }
}

/// One run of a study.
#[derive(Clone, Debug)]
pub struct PlannedRun {
    /// Stable id: the same study gives the same ids (e.g. `r0007`), usable as an HDF5 group name.
    pub id: String,
    /// Position in the plan (0-based).
    pub index: usize,
    /// The swept key paths and their values for this run, in axis order (replicate seed included).
    pub parameters: Vec<(String, ParamValue)>,
    /// The complete scene of this run.
    pub scene: SceneConfig,
    /// Initial states read from the placement file, shared by runs that use the same file.
    pub initial: Option<Arc<Vec<InitialDisk>>>,
    /// The contact history read from `placement.contacts` (a restart), shared like `initial`.
    pub initial_contacts: Option<Arc<Vec<InitialContact>>>,
    /// The time step the run will use (s): given, or resolved from the scene (see
    /// [`crate::physics::time_step`]).
    pub time_step: f64,
    /// Relative cost estimate (particle-steps at most: runs stop when settled), for progress and
    /// shard balancing.
    pub estimated_cost: f64,
}

impl PlannedRun {
    /// A run of a (validated) scene, with its time step resolved and its cost estimated (and no
    /// contact history: set `initial_contacts` for a restart).
    pub fn new(
        id: String,
        index: usize,
        parameters: Vec<(String, ParamValue)>,
        scene: SceneConfig,
        initial: Option<Arc<Vec<InitialDisk>>>,
    ) -> Self {
        let time_step = crate::physics::scene_time_step(&scene, initial.as_deref().map(Vec::as_slice)).dt;
        let estimated_cost = scene.particles.count as f64 * scene.total_steps(time_step) as f64;
        Self { id, index, parameters, scene, initial, initial_contacts: None, time_step, estimated_cost }
    }
}

/// A validated, expanded study.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Path of the study file.
    pub study_path: PathBuf,
    /// The study file's text, verbatim.
    pub study_text: String,
    /// Study name (the file stem unless the study sets one).
    pub name: String,
    /// Hash of the study text and the demsweep version: identifies results of this study.
    pub fingerprint: String,
    /// Optional outputs.
    pub output: OutputOptions,
    /// The runs, in a stable order.
    pub runs: Vec<PlannedRun>,
    /// What will not stop the study but deserves a look (validity predicted before running, sampling
    /// that cannot sample, initial overlaps), located like errors; warnings of one kind shared by
    /// several runs are listed once, with the first run and how many runs have one.
    pub warnings: Vec<StudyError>,
}

impl Plan {
    /// Sum of the runs' cost estimates (particle-steps).
    pub fn total_cost(&self) -> f64 {
        self.runs.iter().map(|r| r.estimated_cost).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(text: &str) -> toml::Table {
        parse_table(Path::new("<scene>"), text.to_string()).unwrap()
    }

    #[test]
    fn a_scene_study_runs_its_seeds_and_reports_problems_as_a_study_file_would() {
        let text = scene_study(scene("particles.count = 12\n[placement]\nseed = 7\n"), &Seeds::List(vec![3, 9]));
        let plan = load_text(Path::new("<scene>"), text).unwrap();
        let seeds: Vec<u64> = plan.runs.iter().map(|r| r.scene.placement.seed).collect();
        assert_eq!((plan.name.as_str(), seeds), (SCENE_STUDY_NAME, vec![3, 9]));
        let text = scene_study(scene("[placement]\nseed = 7\n"), &Seeds::Replicates(3));
        let seeds: Vec<u64> =
            load_text(Path::new("s"), text).unwrap().runs.iter().map(|r| r.scene.placement.seed).collect();
        assert_eq!(seeds, [7, 8, 9]);
        assert_eq!(load_text(Path::new("s"), scene_study(scene(""), &Seeds::Scene)).unwrap().runs.len(), 1);

        let text = scene_study(scene("material.frction = 0.5\n"), &Seeds::Scene);
        let errors = load_text(Path::new("<scene>"), text.clone()).unwrap_err();
        assert_eq!(errors.0.len(), 1);
        assert_eq!(errors.0[0].key, "scene.material.frction");
        assert_eq!(errors.0[0].file, Path::new("<scene>"));
        let dir = std::env::temp_dir().join(format!("demsweep-scene-study-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("scene.toml");
        std::fs::write(&file, &text).unwrap();
        let from_file = load(&file).unwrap_err();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(from_file.0[0].reason, errors.0[0].reason);
        assert_eq!(from_file.0[0].location, errors.0[0].location);
    }

    #[test]
    fn toml_syntax_errors_of_a_scene_are_located_in_its_text() {
        let errors = parse_table(Path::new("<scene>"), "a = 1\nb = = 2\n".into()).unwrap_err();
        assert_eq!(errors.0[0].location.map(|l| l.line), Some(2));
        assert!(errors.to_string().starts_with("<scene>:2:"), "{errors}");
    }

    #[test]
    fn param_values_display_as_written() {
        let shown: Vec<String> = [
            ParamValue::Float(0.7),
            ParamValue::Float(1e9),
            ParamValue::Float(2.5e-5),
            ParamValue::Float(0.0),
            ParamValue::Float(150.0),
            ParamValue::Int(12),
            ParamValue::Text("linear".into()),
        ]
        .iter()
        .map(|v| v.to_string())
        .collect();
        assert_eq!(shown, ["0.7", "1e9", "2.5e-5", "0.0", "150.0", "12", "\"linear\""]);
    }
}
