//! Benchmarks of accuracy against cost, numerical stability and edge cases, as library functions.
//!
//! Each submodule exposes one function that takes a small options struct (so tests can run tiny
//! versions), returns its rows and writes CSV and Markdown into a given directory:
//! - [`accuracy`]: work-precision of both integrators over time steps `t_c/5 … t_c/400`;
//! - [`stability_map`]: where runs blow up or never come to rest over time step × stiffness × damping,
//!   restarts included, against the prediction;
//! - [`stable_step`]: the largest step of each integrator at which depositions settle, straight through
//!   and restarted, by damping ratio;
//! - [`stress`]: edge-case scenes, each ending with a clear status and message;
//! - [`skipping`]: time saved by stopping at settle, sparse diagnostics and frictionless shortcuts;
//! - [`tune`]: `demsweep tune` against a brute-force ladder over its levers on fresh seeds
//!   ([`tune_ladder`]).

mod error;

pub use error::{BenchError, create_folder};

pub mod accuracy;
pub mod skipping;
pub mod stability_map;
pub mod stable_step;
pub mod stress;
pub mod tune;
pub mod tune_ladder;

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use crate::output::csv;
use crate::physics::config::{IntegratorKind, SceneConfig};
use crate::physics::particles::InitialDisk;
use crate::physics::quantity;
use crate::physics::simulation::Control;
use crate::physics::{RunRecord, placement, run_scene};

/// The engine's reference deposition (docs/reference_scene.md) at `count` disks, the box widened
/// with them so that the pile is as deep as the reference's: E 1e9 Pa, e 0.5, μ 0.5, dt 1e-5 s,
/// `duration` s to the end. At 300 disks with [`reference_disks`], the reference scene.
pub fn reference_deposition(count: usize, duration: f64) -> SceneConfig {
    let mut s = SceneConfig::default();
    s.material.restitution = Some(0.5);
    s.material.friction = 0.5;
    s.integrator.time_step = Some(1e-5);
    s.particles.count = count;
    s.domain.width = 0.4 * count as f64 / 300.0;
    s.run.duration = duration;
    s.run.stop_at_settle = false;
    s
}

/// The reference scene's 300 initial disks (`tests/data/deposition_300.csv`).
pub fn reference_disks() -> Vec<InitialDisk> {
    let text = include_str!("../../tests/data/deposition_300.csv");
    let number = |x: &str| x.parse::<f64>().expect("tests/data/deposition_300.csv holds numbers");
    let disk = |v: Vec<f64>| InitialDisk { x: v[0], y: v[1], r: v[2], ..Default::default() };
    text.lines().skip(1).map(|line| disk(line.split(',').map(number).collect())).collect()
}

/// Where benchmarks write by default: a folder git ignores, so that running one changes no tracked file.
pub const LATEST_DIR: &str = "results/bench_latest";
/// The committed figures the docs quote; written only when asked (`demsweep bench KIND --update-results`).
pub const COMMITTED_DIR: &str = "results/bench";

/// Both integrators, the paper's first.
pub const SCHEMES: [IntegratorKind; 2] = [IntegratorKind::AdamsBashforthMoulton, IntegratorKind::VelocityVerlet];

/// One row of a CSV table.
pub trait CsvRow {
    /// Column names and SI units (empty where a column has none).
    const COLUMNS: &'static [(&'static str, &'static str)];
    /// The row's values, in [`Self::COLUMNS`] order.
    fn values(&self) -> Vec<String>;

    /// The columns' labels, for Markdown tables ([`quantity::labelled`]).
    fn labels() -> Vec<String> {
        Self::COLUMNS.iter().map(|(name, unit)| quantity::labelled(name, unit)).collect()
    }
}

/// Writes rows as CSV (RFC 4180, the names line of `csv`) with its metadata sidecar (each column's
/// unit and datatype).
pub fn write_csv<R: CsvRow>(path: &Path, rows: &[R]) -> Result<(), BenchError> {
    let mut text = Vec::new();
    let names: Vec<&str> = R::COLUMNS.iter().map(|(name, _)| *name).collect();
    let values: Vec<Vec<String>> = rows.iter().map(CsvRow::values).collect();
    csv::write_record(&mut text, &names).expect("writing to memory");
    values.iter().for_each(|row| csv::write_record(&mut text, row).expect("writing to memory"));
    write_file(path, &String::from_utf8_lossy(&text))?;
    let mut columns = csv::ColumnMeta::declared_from_rows(&names, &values);
    columns.iter_mut().zip(R::COLUMNS).for_each(|(column, (_, unit))| column.unit = unit.to_string());
    Ok(csv::write_metadata(path, &columns, crate::output::guard::Existing::Any)?)
}

/// Writes a text file, creating its folder; the error names the path.
pub fn write_file(path: &Path, text: &str) -> Result<(), BenchError> {
    if let Some(dir) = path.parent() {
        create_folder(dir)?;
    }
    Ok(crate::output::guard::write(path, text.as_bytes(), &[])?)
}

/// Snake-case name of a scheme, as in scene files.
pub fn scheme_name(kind: IntegratorKind) -> &'static str {
    match kind {
        IntegratorKind::AdamsBashforthMoulton => "adams_bashforth_moulton",
        IntegratorKind::VelocityVerlet => "velocity_verlet",
    }
}

/// Runs `f` and returns its result with the wall-clock seconds it took.
pub fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let start = Instant::now();
    let value = f();
    (value, start.elapsed().as_secs_f64())
}

/// Runs a scene to its end (no observer), with its initial disks.
pub fn run(scene: &SceneConfig, disks: &[InitialDisk]) -> Result<RunRecord, BenchError> {
    Ok(run_scene(scene, Some(disks.to_vec()), &mut |_| Control::Continue)?)
}

/// The initial disks a scene's random or lattice placement generates.
pub fn placed_disks(scene: &SceneConfig) -> Result<Vec<InitialDisk>, BenchError> {
    Ok(placement::generate(scene)?)
}

/// Ratios `t_c / dt` spaced geometrically (`per_doubling` values per factor 2) from `coarsest` to
/// `finest`, both included, coarsest first.
pub fn ratio_grid(coarsest: f64, finest: f64, per_doubling: u32) -> Vec<f64> {
    let steps = ((finest / coarsest).log2() * per_doubling as f64 + 1e-9).floor().max(0.0) as i32;
    let mut grid: Vec<f64> = (0..=steps).map(|k| coarsest * 2f64.powf(k as f64 / per_doubling as f64)).collect();
    if grid.last().is_some_and(|last| *last < finest * 0.999) {
        grid.push(finest);
    }
    grid
}

/// A Markdown table from a header and rows of cells.
pub fn markdown_table<S: AsRef<str>>(header: &[S], rows: &[Vec<String>]) -> String {
    let header: Vec<&str> = header.iter().map(AsRef::as_ref).collect();
    let mut text = format!("| {} |\n|{}\n", header.join(" | "), "---|".repeat(header.len()));
    for row in rows {
        let _ = writeln!(text, "| {} |", row.join(" | "));
    }
    text
}

/// Relative difference `|a − b| / |b|`.
pub fn relative_error(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}
