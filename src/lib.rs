//! demsweep: batch parameter sweeps of 2D DEM granular deposition (the BMEDEM2D model).
//!
//! Layers, each depending only on the ones above it in this list:
//! - [`physics`]: the simulation library (no I/O): particles, contacts, integrators, walls, diagnostics.
//! - study / runner / output / CLI: study files → plan → parallel runs → HDF5 and CSV.
//! - [`slurm`]: batch scripts running a study as a Slurm array job (one shard per task) plus a merge job.
//! - [`stats`]: statistics over replicates (per-point descriptions, equivalence tests), no I/O.
//! - [`plot`]: PNG and SVG pictures of runs and studies, drawn from in-memory records or a results file.
//! - [`report`]: one self-contained HTML page per results file, built from the results, statistics and charts.
#![deny(unsafe_code)]

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
