//! The 2D discrete element model of the BMEDEM2D paper, as a library with no I/O.
//!
//! Units are SI throughout: metres, kilograms, seconds, newtons, joules, pascals, radians.
//! Disks are cylinders of thickness `h` lying in the x-y plane; gravity acts in that plane.
//!
//! Reading order for a newcomer:
//! [`config`] (what a scene is) → [`material`] (pair properties) → [`contact`] (force laws) →
//! `neighbors` (who touches whom) → `forces` (contact forces of a step, in blocks) →
//! `contact_list` (the same, one contact at a time) → `integrator` (time stepping), [`memory_order`]
//! (where disks live in memory), `energy`
//! (work and dissipation bookkeeping), `rolling` (rolling resistance) → [`simulation`] (the step
//! loop) → [`diagnostics`], [`stability`], [`time_step`], [`pile`] and [`record`] (what comes out),
//! with every per-run quantity's name, unit and computation declared once in [`quantity`].
//! [`run_scene`], [`scene_time_step`] and [`predict_stability`] do their work with whichever law
//! the scene names, through the contact models table's one dispatch ([`contact::table`]).

pub mod config;
pub mod contact;
mod contact_list;
pub mod contact_network;
pub mod contact_record;
mod contact_sums;
pub mod diagnostics;
mod dispatch;
mod energy;
mod forces;
mod integrator;
pub mod key_spec;
pub mod keys;
pub mod material;
pub mod memory_order;
mod monitor;
mod neighbors;
pub mod number;
pub mod parallel;
pub mod particles;
pub mod pile;
pub mod placement;
pub mod pour;
pub mod quantity;
pub mod record;
pub mod rng;
mod rolling;
pub mod run_state;
mod scheme;
pub mod simulation;
pub mod size_distribution;
pub mod stability;
pub mod stage;
pub mod stress;
pub mod time_step;
pub mod vector;
pub mod walls;
pub mod warning;

/// The version of the physics: bumped by every change that changes a run's results, so that runs
/// stored by another version are not reused as if this one had made them (see `study::identity`).
/// What each version changed is in the history of this line (git).
pub const PHYSICS_VERSION: u32 = 3;

pub use config::SceneConfig;
pub use contact::{ContactConfig, ContactLaw, ContactLawKind};
pub use dispatch::{
    RunError, predict_stability, predict_stage_warnings, run_scene, run_scene_on, run_scene_resumable,
    run_scene_with_history, scene_time_step,
};
pub use neighbors::CellGrid;
pub use parallel::Threads;
pub use record::{RunRecord, RunStatus};
pub use simulation::{Control, Progress, Simulation};
