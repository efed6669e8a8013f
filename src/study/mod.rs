//! Study files: a base scene plus sweep axes, expanded into a plan (the list of runs).
//!
//! Data flows one way: study file → [`Plan`] → runner → simulation → records → writers.
//! (Contract types; `load` is implemented by the study planner.)

use std::path::PathBuf;
use std::sync::Arc;

use crate::physics::SceneConfig;
use crate::physics::particles::InitialDisk;

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

/// Which optional outputs a study asks for (what nobody asked for is not computed or written).
#[derive(Clone, Debug, PartialEq)]
pub struct OutputOptions {
    /// Write energy/UBF histories per run.
    pub histories: bool,
    /// Write the final state of every run.
    pub final_states: bool,
    /// Write recorded frames (the scene's `run.frame_times` / `run.frame_interval`).
    pub frames: bool,
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
    /// Relative cost estimate (particle-steps), for progress and shard balancing.
    pub estimated_cost: f64,
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
}
