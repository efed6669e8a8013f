//! The tune's files: the candidates and skipped tables as CSV, `<name>_best.toml`,
//! `<name>_scene_change.toml`, `<name>_recommendation.txt` and the charts.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::super::TuneSpec;
use super::super::model::{Candidate, SearchResult};
use super::charts::{cost_points, lever_series};
use super::phrases::settings;
use super::tables::{candidate_records, skipped_records};
use crate::output::guard::Existing;
use crate::output::{csv, guard};
use crate::plot::tune::{cost_along_levers_chart, cost_vs_difference_chart};
use crate::plot::{ChartOptions, Format, PlotError};
use crate::report::Table;

/// Why a tune's files could not be written.
#[derive(Debug)]
pub enum WriteError {
    /// The output folder could not be made.
    CreateDir {
        /// The folder.
        dir: PathBuf,
        /// Why.
        error: std::io::Error,
    },
    /// A file was refused or could not be written.
    File(guard::GuardError),
    /// The report section's chart could not be drawn.
    Chart(PlotError),
}

impl std::fmt::Display for WriteError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            WriteError::CreateDir { dir, error } => write!(f, "{}: {error}", dir.display()),
            WriteError::File(e) => write!(f, "{e}"),
            WriteError::Chart(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for WriteError {}

impl From<guard::GuardError> for WriteError {
    fn from(error: guard::GuardError) -> Self {
        WriteError::File(error)
    }
}

/// Files a tune wrote.
#[derive(Clone, Debug, Default)]
pub struct Written {
    /// Every file, in the order written.
    pub files: Vec<PathBuf>,
    /// Charts that could not be drawn.
    pub chart_errors: Vec<PlotError>,
}

/// The files [`write_all`] writes into `dir` (the charts aside): `<name>_candidates.csv`,
/// `<name>_skipped.csv` (each with its sidecar), `<name>_best.toml`, `<name>_scene_change.toml`
/// and `<name>_recommendation.txt`.
pub fn files(spec: &TuneSpec, dir: &Path) -> [PathBuf; 5] {
    ["candidates.csv", "skipped.csv", "best.toml", "scene_change.toml", "recommendation.txt"]
        .map(|what| dir.join(format!("{}_{what}", spec.name)))
}

/// Writes `<name>_candidates.csv`, `<name>_best.toml` (when there is a recommendation), the charts and
/// `<name>_recommendation.txt` into `dir` ([`files`]), replacing files there as `existing` allows (the
/// text files stamped as demsweep's: [`guard::stamp`]).
pub fn write_all(
    spec: &TuneSpec,
    result: &SearchResult,
    dir: &Path,
    text: &str,
    existing: Existing,
) -> Result<Written, WriteError> {
    let mut written = Written::default();
    std::fs::create_dir_all(dir).map_err(|error| WriteError::CreateDir { dir: dir.to_path_buf(), error })?;
    let [csv, skipped, best, change, note] = files(spec, dir);
    write_records(&candidate_records(spec, result), &csv, existing)?;
    write_records(&skipped_records(spec, result), &skipped, existing)?;
    written.files.extend([csv, skipped]);
    let mut write = |path: PathBuf, text: &str| -> Result<(), WriteError> {
        guard::write_with(&path, &[], existing, |out| out.write_all(guard::stamp(text).as_bytes()))?;
        written.files.push(path);
        Ok(())
    };
    if let Some(k) = result.recommended {
        write(best, &best_study(spec, result, k))?;
        write(change, &scene_change(spec, &result.candidates[k]))?;
    }
    write(note, &format!("{text}\n"))?;
    let plots = dir.join("plots");
    let options = ChartOptions { format: Format::Png, subject: Some(spec.name.clone()), ..Default::default() };
    let (points, recommended) = cost_points(result);
    let chart = plots.join(format!("{}_cost_vs_difference.png", spec.name));
    match cost_vs_difference_chart(&points, recommended, &options, &chart) {
        Ok(()) => written.files.push(chart),
        Err(e) => written.chart_errors.push(e),
    }
    let series = lever_series(spec, result);
    let chart = plots.join(format!("{}_cost_along_levers.png", spec.name));
    match cost_along_levers_chart(&series, &options, &chart) {
        Ok(()) => written.files.push(chart),
        Err(e) => written.chart_errors.push(e),
    }
    Ok(written)
}

/// Writes a table as CSV (the column names, then the rows), whole or not at all
/// ([`guard::write_with`]), and its metadata sidecar (units, datatypes from the cells' types).
fn write_records(table: &Table, path: &Path, existing: Existing) -> Result<(), guard::GuardError> {
    let columns: Vec<csv::ColumnMeta> =
        table.columns.iter().enumerate().map(|(k, name)| csv::ColumnMeta::declared(name, table.datatype(k))).collect();
    csv::write_file(path, &columns, existing, |out| {
        csv::write_record(&mut *out, &table.columns)?;
        table.rows.iter().try_for_each(|row| {
            let fields: Vec<String> = row.iter().map(ToString::to_string).collect();
            csv::write_record(&mut *out, &fields)
        })
    })
}

/// The sweep over verification seeds `seeds`: replicates from the first where they follow on, else
/// their list (a seed the reference's disks cannot be placed on was stepped over).
fn seed_sweep(spec: &TuneSpec, seeds: &[u64]) -> toml::Table {
    let mut sweep = toml::Table::new();
    if seeds.windows(2).all(|w| w[1] == w[0] + 1) {
        sweep.insert("replicates".into(), toml::Value::Integer(seeds.len().max(1) as i64));
    } else {
        let base = spec.reference.placement.seed;
        let list = seeds.iter().map(|s| toml::Value::Integer(base.wrapping_add(*s) as i64)).collect();
        sweep.insert("placement.seed".into(), toml::Value::Array(list));
    }
    sweep
}

/// A runnable study of the recommended scene: the reference scene with the lever values set, run on
/// the verification seeds.
pub fn best_study(spec: &TuneSpec, result: &SearchResult, k: usize) -> String {
    let cand = &result.candidates[k];
    let mut scene = spec.setting_tree(&cand.point, cand.standard).unwrap_or_else(|_| spec.base.clone());
    let first_seed = spec.reference.placement.seed.wrapping_add(cand.verify_seeds.first().copied().unwrap_or(0));
    let _ = crate::study::file::set_path(
        &mut scene,
        &["placement".to_string(), "seed".to_string()],
        toml::Value::Integer(first_seed as i64),
    );
    let mut doc = toml::Table::new();
    doc.insert("name".into(), toml::Value::String(format!("{}_best", spec.name)));
    doc.insert(
        "description".into(),
        toml::Value::String(format!(
            "the recommendation of `demsweep tune {}`: {}",
            spec.path.display(),
            settings(spec, cand)
        )),
    );
    doc.insert("scene".into(), toml::Value::Table(scene));
    doc.insert("sweep".into(), toml::Value::Table(seed_sweep(spec, &cand.verify_seeds)));
    let header = format!(
        "# Written by `demsweep tune {}`: the reference scene with the recommended levers\n# ({}), \
         on its verification seeds. Run it with: demsweep run {}_best.toml\n",
        spec.path.display(),
        spec.levers.iter().map(|l| l.key.as_str()).collect::<Vec<_>>().join(", "),
        spec.name
    );
    format!("{header}{}", toml::to_string(&doc).unwrap_or_default())
}

/// The recommendation as a change to the tune file: the `[scene]` keys to set, levers only.
pub fn scene_change(spec: &TuneSpec, cand: &Candidate) -> String {
    let values = spec.setting_values(&cand.point, cand.standard);
    let mut text = format!(
        "# The recommendation of `demsweep tune {}` as a change to its [scene] table: set these keys\n",
        spec.path.display()
    );
    text.push_str("[scene]\n");
    for (key, value) in values.iter().filter(|(key, _)| in_stage(key).is_none()) {
        let _ = writeln!(text, "{} = {}", key, value.to_toml());
    }
    // A stage's keys belong in its own [[scene.stages]] table, which a [scene] table cannot name.
    let mut stages: Vec<&str> = values.iter().filter_map(|(key, _)| Some(in_stage(key)?.0)).collect();
    stages.dedup();
    for stage in stages {
        let _ = writeln!(text, "# and in the stage named {stage:?} (its [[scene.stages]] table):");
        for (key, value) in &values {
            if let Some((_, inner)) = in_stage(key).filter(|(name, _)| *name == stage) {
                let _ = writeln!(text, "#   {} = {}", inner, value.to_toml());
            }
        }
    }
    text
}

/// The stage and the key within it of a stage's key (`stages.NAME.KEY`).
fn in_stage(key: &str) -> Option<(&str, &str)> {
    key.strip_prefix("stages.")?.split_once('.')
}
