//! What a study expands to: its runs ([`PlannedRun`]) with their swept values ([`ParamValue`]) and
//! the outputs it asks for.

use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::errors::StudyError;
use crate::physics::SceneConfig;
use crate::physics::particles::{InitialContact, InitialDisk};

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
    /// A run of a (validated) scene, with its time step resolved and its cost estimated (the whole
    /// duration at the smallest step of its stages; no contact history: set `initial_contacts` for a
    /// restart).
    pub fn new(
        id: String,
        index: usize,
        parameters: Vec<(String, ParamValue)>,
        scene: SceneConfig,
        initial: Option<Arc<Vec<InitialDisk>>>,
    ) -> Self {
        let disks = initial.as_deref().map(Vec::as_slice);
        let time_step = crate::physics::scene_time_step(&scene, disks).dt;
        // An upper bound: the whole duration at the smallest step of the scene's stages.
        let stage_step = |stage| crate::physics::scene_time_step(&scene.in_stage(stage), disks).dt;
        let smallest = scene.stages.iter().map(stage_step).fold(time_step, f64::min);
        let estimated_cost = scene.particles.count as f64 * scene.total_steps(smallest) as f64;
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
