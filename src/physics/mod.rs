//! The 2D discrete element model of the BMEDEM2D paper, as a library with no I/O.
//!
//! Units are SI throughout: metres, kilograms, seconds, newtons, joules, pascals, radians.
//! Disks are cylinders of thickness `h` lying in the x-y plane; gravity acts in that plane.
//!
//! Reading order for a newcomer:
//! [`config`] (what a scene is) → [`material`] (pair properties) → [`contact`] (force laws) →
//! [`neighbors`] (who touches whom) → [`forces`] (contact forces of a step) → [`integrator`] (time stepping) → [`simulation`] (the step loop) →
//! [`diagnostics`], [`stability`], [`time_step`], [`pile`] and [`record`] (what comes out), with
//! every per-run quantity's name and unit declared in [`quantity`].

pub mod config;
pub mod contact;
pub mod diagnostics;
pub mod forces;
pub mod integrator;
pub mod material;
mod monitor;
pub mod neighbors;
pub mod particles;
pub mod pile;
pub mod placement;
pub mod quantity;
pub mod record;
pub mod rng;
pub mod simulation;
pub mod stability;
pub mod time_step;
mod vector;
pub mod walls;

pub use config::SceneConfig;
pub use record::{RunRecord, RunStatus};
pub use simulation::{Control, Progress, Simulation};
