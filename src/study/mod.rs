//! Study files: a base scene plus sweep axes, expanded into a plan (the list of runs).
//!
//! Data flows one way: study file → [`Plan`] → runner → simulation → records → writers.
//! [`load`] reads a study file (format: docs/studies.md) and checks everything a run
//! could fail on at its start: every problem of the whole study is reported at once.

pub(crate) mod axes;
mod axis_error;
mod csv_error;
pub(crate) mod errors;
pub(crate) mod file;
pub mod identity;
pub mod initial_csv;
mod lammps_error;
pub mod lammps_file;
mod load;
pub mod name;
pub(crate) mod plan;
pub mod reference;
pub mod resources;
mod types;

pub use axes::{MAX_RUNS, Spacing};
pub use axis_error::AxisError;
pub use csv_error::{ColumnAt, CsvError, CsvProblem, PlacementFileError};
pub use errors::{Location, StudyError, StudyErrors, did_you_mean, nearest};
pub use file::{ReadTextError, SetPathError};
pub use identity::{IdentityChange, RunIdentity};
pub use lammps_error::{LammpsError, LammpsProblem};
pub use load::{SCENE_STUDY_NAME, Seeds, load, load_text, parse_table, scene_study};
pub use types::{OutputOptions, ParamValue, Plan, PlannedRun};
