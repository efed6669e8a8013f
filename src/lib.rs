//! demsweep: batch parameter sweeps of 2D DEM granular deposition (the BMEDEM2D model).
//!
//! Layers, each using only the ones below it (`tests/layering.rs` keeps this true):
//! - [`physics`]: the simulation library (no I/O): scene configuration ([`SceneConfig`]), the
//!   [`Simulation`] and its step loop, contact laws ([`physics::contact`]), diagnostics
//!   ([`physics::diagnostics`]), pile metrics ([`physics::pile`]) and the run record ([`RunRecord`]).
//! - [`study`]: study files → a [`study::Plan`] of runs (swept parameters, replicates, errors naming
//!   file, line and key).
//! - [`output`]: results files: one HDF5 file per study (or shard) and CSV tables next to it, written
//!   through [`output::ResultSink`]s and read back by [`output::reader`] and [`output::summary`].
//! - [`runner`] (running a plan in parallel, resume, shards and their merge), [`stats`] (statistics
//!   over replicates, no I/O) and [`slurm`] (batch scripts running a study as an array job).
//! - [`tune`] (searching for the cheapest settings that give the reference's answer), [`plot`] (PNG
//!   and SVG charts), [`report`] (one HTML page per results file), [`export`] (stored piles as
//!   ParaView, LAMMPS and placement files) and `bench` (the command's accuracy, stability and
//!   edge-case benchmarks, not a library interface).
//!
//! - [`workflow`]: a study run and a tune as the command does them, for every front end.
//!
//! Above them all, the `demsweep` command (`src/cli`) and the Python module (`python/`).
//!
//! A scene built in code and run (see `examples/library.rs`):
//!
//! ```no_run
//! use demsweep::physics::run_scene;
//! use demsweep::{Control, SceneConfig};
//!
//! let mut scene = SceneConfig::default();
//! scene.particles.count = 60;
//! scene.domain.width = 0.16;
//! let record = run_scene(&scene, None, &mut |_| Control::Continue).unwrap();
//! println!("{} at {:?} s, coordination {}", record.status, record.settle_time, record.pile["coordination_number"]);
//! ```
#![deny(unsafe_code)]

#[doc(hidden)]
pub mod bench;
pub mod export;
pub mod output;
pub mod physics;
pub mod plot;
pub mod report;
pub mod runner;
pub mod slurm;
pub mod stats;
pub mod study;
pub mod tune;
pub mod workflow;

pub use physics::{Control, RunRecord, RunStatus, SceneConfig, Simulation};
