//! One run read back from a results file: its scene, histories, final state and frames.

use std::collections::HashMap;
use std::path::Path;

use hdf5_pure::{Dataset, File};

use super::layout::{self, STATE_FIELDS};
use super::row::SummaryRow;
use super::table::ColumnData;
use super::{OutputError, compound, hdf5_error};
use crate::physics::SceneConfig;
use crate::physics::quantity::HISTORY_SERIES;
use crate::physics::record::{History, Snapshot};

/// A run as stored: what was written for it (the parts the study's output options left out are
/// `None` or empty, as are all of them for a run that failed with an error).
#[derive(Clone, Debug)]
pub struct StoredRun {
    /// The complete scene (`scene.json` attribute).
    pub scene: SceneConfig,
    /// The sampled histories (`history`).
    pub history: Option<History>,
    /// The state at the end of the run (`final`).
    pub final_state: Option<Snapshot>,
    /// The recorded frames (`frames/0`, `frames/1`, …), in order.
    pub frames: Vec<Snapshot>,
}

/// Reads the stored data of the run of `row` from `file` (at `path`).
pub fn read_run(file: &File, path: &Path, row: &SummaryRow) -> Result<StoredRun, OutputError> {
    let group_path = layout::run_path(row.index, &row.id);
    let fail = |what: &str, reason: String| OutputError::new(path, format!("/{group_path}/{what}: {reason}"));
    let group = file.group(&group_path).map_err(|e| hdf5_error(path, e))?;
    let attrs = group.attrs().map_err(|e| hdf5_error(path, e))?;
    let json = attrs.get("scene.json").and_then(|a| a.as_str()).ok_or_else(|| fail("scene.json", "missing".into()))?;
    let scene = serde_json::from_str(json).map_err(|e| fail("scene.json", e.to_string()))?;
    let datasets = group.datasets().map_err(|e| hdf5_error(path, e))?;
    let has = |name: &str| datasets.iter().any(|d| d == name);
    let history = has("history")
        .then(|| read_table(file, &group_path, "history", path).and_then(|t| history(&t)))
        .transpose()
        .map_err(|e| fail("history", e))?;
    let final_state = has("final")
        .then(|| read_snapshot(file, &format!("{group_path}/final"), path))
        .transpose()
        .map_err(|e| fail("final", e))?;
    let frames = read_frames(file, &group_path, path).map_err(|e| fail("frames", e))?;
    Ok(StoredRun { scene, history, final_state, frames })
}

/// The frames of a run group, ordered by their number.
fn read_frames(file: &File, group_path: &str, path: &Path) -> Result<Vec<Snapshot>, String> {
    let group = file.group(group_path).map_err(|e| e.to_string())?;
    if !group.groups().map_err(|e| e.to_string())?.iter().any(|g| g == "frames") {
        return Ok(Vec::new());
    }
    let frames_path = format!("{group_path}/frames");
    let names = file.group(&frames_path).and_then(|g| g.datasets()).map_err(|e| e.to_string())?;
    let mut numbered: Vec<(usize, String)> =
        names.into_iter().filter_map(|name| Some((name.parse().ok()?, name))).collect();
    numbered.sort();
    numbered.iter().map(|(_, name)| read_snapshot(file, &format!("{frames_path}/{name}"), path)).collect()
}

/// A compound table of a run group as named columns.
fn read_table(file: &File, group_path: &str, name: &str, path: &Path) -> Result<HashMap<String, ColumnData>, String> {
    let dataset = file.dataset(&format!("{group_path}/{name}")).map_err(|e| hdf5_error(path, e).message)?;
    Ok(compound::decode(&dataset)?.into_iter().collect())
}

/// A state table (final or frame) with its `time` attribute.
fn read_snapshot(file: &File, dataset_path: &str, path: &Path) -> Result<Snapshot, String> {
    let dataset: Dataset = file.dataset(dataset_path).map_err(|e| hdf5_error(path, e).message)?;
    let time = dataset.attrs().map_err(|e| e.to_string())?.get("time").and_then(|a| a.as_f64());
    let time = time.ok_or("no `time` attribute")?;
    let table: HashMap<String, ColumnData> = compound::decode(&dataset)?.into_iter().collect();
    let [x, y, vx, vy, omega, r, contact_force] = STATE_FIELDS.map(|name| floats(&table, name));
    Ok(Snapshot {
        time,
        x: x?,
        y: y?,
        vx: vx?,
        vy: vy?,
        omega: omega?,
        r: r?,
        contact_force: contact_force?,
        ..Default::default()
    })
}

/// The history series of [`HISTORY_SERIES`] from the columns of a `history` table (a series the
/// file predates takes its declared value at every sample).
fn history(table: &HashMap<String, ColumnData>) -> Result<History, String> {
    let samples = floats(table, HISTORY_SERIES[0].quantity.name)?.len();
    let mut history = History::default();
    for series in &HISTORY_SERIES {
        let values = match series.when_absent {
            Some(value) if !table.contains_key(series.quantity.name) => vec![value; samples],
            _ => floats(table, series.quantity.name)?,
        };
        (series.store)(&mut history, values);
    }
    Ok(history)
}

/// Column `name` of a table as floats (integer columns converted).
fn floats(table: &HashMap<String, ColumnData>, name: &str) -> Result<Vec<f64>, String> {
    match table.get(name) {
        Some(ColumnData::Float(v)) => Ok(v.clone()),
        Some(ColumnData::Int(v)) => Ok(v.iter().map(|&i| i as f64).collect()),
        Some(_) => Err(format!("field `{name}` is not numeric")),
        None => Err(format!("no field `{name}`")),
    }
}
