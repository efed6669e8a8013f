//! One run read back from a results file: its scene, histories, stress profile, final state and
//! frames.

use std::collections::HashMap;
use std::path::Path;

use hdf5_pure::{Dataset, File};

use super::layout::{
    CONTACT_FIELDS, FINAL, FINAL_CONTACTS, FRAME_CONTACT_TABLE, FRAME_CONTACTS, FRAME_INDEX, FRAME_TIME, FRAMES,
    STRESS_PROFILE,
};
use super::row::SummaryRow;
use super::table::ColumnData;
use super::{LayoutError, OutputError, OutputReason, compound, hdf5_error, reader};
use crate::physics::SceneConfig;
use crate::physics::contact_network::ContactNetwork;
use crate::physics::quantity::{HISTORY_SERIES, STRESS_XX, STRESS_XY, STRESS_YY};
use crate::physics::record::{DISK_FIELDS, History, Snapshot};
use crate::physics::stress::{Stress, StressProfile};

/// A run as stored: what was written for it (the parts the study's output options left out are
/// `None` or empty, as are all of them for a run that failed with an error).
#[derive(Clone, Debug)]
pub struct StoredRun {
    /// The complete scene (`scene.json` attribute).
    pub scene: SceneConfig,
    /// The sampled histories (`history`).
    pub history: Option<History>,
    /// The settled pile's stress per height band (`stress_profile`, stored with the histories).
    pub stress_profile: Option<StressProfile>,
    /// The state at the end of the run (`final`), with its contacts (`final_contacts`; empty in files
    /// written before contacts were stored).
    pub final_state: Option<Snapshot>,
    /// The recorded frames (the arrays of `frames`; `frames/00000`, … and `frame_contacts/<k>` in
    /// results format 2 and before), in order, with their contacts.
    pub frames: Vec<Snapshot>,
}

/// Reads the stored data of the run of `row` from `file` (at `path`); damaged data (a checksum that
/// does not match) is an error naming the run and the dataset.
pub fn read_run(file: &File, path: &Path, row: &SummaryRow) -> Result<StoredRun, OutputError> {
    let group_path = reader::find_group(file, path, row.group_name())?
        .ok_or_else(|| OutputError::at(path, OutputReason::NoGroup(row.id.clone())))?;
    let fail =
        |what: &str, reason: LayoutError| reader::damaged_data(path, &row.id, &format!("{group_path}/{what}"), reason);
    let group = file.group(&group_path).map_err(|e| hdf5_error(path, e))?;
    let attrs = group.attrs().map_err(|e| hdf5_error(path, e))?;
    let json = attrs
        .get("scene.json")
        .and_then(|a| a.as_str())
        .ok_or_else(|| fail("scene.json", LayoutError::inconsistent("missing")))?;
    let scene = serde_json::from_str(json).map_err(|e| fail("scene.json", LayoutError::inconsistent(e.to_string())))?;
    let datasets = group.datasets().map_err(|e| hdf5_error(path, e))?;
    let has = |name: &str| datasets.iter().any(|d| d == name);
    let history = has("history")
        .then(|| read_table(file, &format!("{group_path}/history"), path).and_then(|t| history(&t)))
        .transpose()
        .map_err(|e| fail("history", e))?;
    let stress_profile = has(STRESS_PROFILE)
        .then(|| read_table(file, &format!("{group_path}/{STRESS_PROFILE}"), path).and_then(|t| stress_profile(&t)))
        .transpose()
        .map_err(|e| fail(STRESS_PROFILE, e))?;
    let final_state = has(FINAL)
        .then(|| {
            let mut state = read_snapshot(file, &format!("{group_path}/{FINAL}"), path)?;
            if has(FINAL_CONTACTS) {
                state.contacts = read_contacts(file, &format!("{group_path}/{FINAL_CONTACTS}"), path)?;
                check_contacts(&state)?;
            }
            Ok(state)
        })
        .transpose()
        .map_err(|e| fail(FINAL, e))?;
    let frames = read_frames(file, &group_path, path).map_err(|e| fail("frames", e))?;
    Ok(StoredRun { scene, history, stress_profile, final_state, frames })
}

/// The frames of a run group, in time order, with their contacts where stored: from the arrays over
/// time of results format 3, or the numbered tables of the formats before.
fn read_frames(file: &File, group_path: &str, path: &Path) -> Result<Vec<Snapshot>, LayoutError> {
    let group = file.group(group_path)?;
    if !group.groups()?.iter().any(|g| g == FRAMES) {
        return Ok(Vec::new());
    }
    let frames = file.group(&format!("{group_path}/{FRAMES}"))?;
    if !frames.datasets()?.iter().any(|d| d == FRAME_TIME) {
        return read_numbered_frames(file, group_path, path);
    }
    let array = |name: &str| -> Result<(Vec<u64>, Vec<f64>), LayoutError> {
        let within = |e: LayoutError| e.within(name);
        let dataset = frames.dataset(name).map_err(|e| within(e.into()))?;
        let shape = dataset.shape().map_err(|e| within(e.into()))?;
        let declared = shape.iter().try_fold(8u64, |bytes, &n| bytes.checked_mul(n));
        if declared.is_none_or(|bytes| bytes > compound::read_limit(path)) {
            return Err(within(LayoutError::too_large(format!("{shape:?} values"))));
        }
        Ok((shape, dataset.read_f64().map_err(|e| within(e.into()))?))
    };
    let (_, times) = array(FRAME_TIME)?;
    let mut snapshots: Vec<Snapshot> = times.iter().map(|&time| Snapshot { time, ..Default::default() }).collect();
    for field in &DISK_FIELDS {
        let (shape, values) = array(field.name)?;
        let [count, disks] = shape[..] else {
            return Err(LayoutError::inconsistent("not a (time, disk) array").within(field.name));
        };
        if count as usize != times.len() || values.len() as u64 != count * disks {
            let found = format!("{shape:?} values for {} frames", times.len());
            return Err(LayoutError::inconsistent(found).within(field.name));
        }
        for (snapshot, row) in snapshots.iter_mut().zip(values.chunks_exact(disks.max(1) as usize)) {
            *(field.values_mut)(snapshot) = row.to_vec();
        }
    }
    let table = read_table(file, &format!("{group_path}/{FRAMES}/{FRAME_CONTACT_TABLE}"), path)?;
    split_contacts(table, &mut snapshots)?;
    Ok(snapshots)
}

/// Gives each frame its contacts from the table of every frame's contacts (see
/// [`FRAME_CONTACT_TABLE`]), checked against the frame's disks.
fn split_contacts(mut table: HashMap<String, ColumnData>, frames: &mut [Snapshot]) -> Result<(), LayoutError> {
    let Some(ColumnData::Int(frame_of)) = table.remove(FRAME_INDEX) else {
        return Err(LayoutError::missing(format!("integer field `{FRAME_INDEX}`")).within(FRAME_CONTACT_TABLE));
    };
    if frame_of.windows(2).any(|w| w[0] > w[1]) {
        let unordered = LayoutError::inconsistent("the contacts are not frame after frame");
        return Err(unordered.within(FRAME_CONTACT_TABLE));
    }
    let all = contacts(table)?;
    for (k, frame) in frames.iter_mut().enumerate() {
        let k = k as i64;
        frame.contacts = slice(&all, frame_of.partition_point(|&f| f < k)..frame_of.partition_point(|&f| f <= k));
        check_contacts(frame)?;
    }
    Ok(())
}

/// The contacts `rows` of a network.
fn slice(c: &ContactNetwork, rows: std::ops::Range<usize>) -> ContactNetwork {
    let f = |v: &Vec<f64>| v[rows.clone()].to_vec();
    ContactNetwork {
        first: c.first[rows.clone()].to_vec(),
        second: c.second[rows.clone()].to_vec(),
        normal_x: f(&c.normal_x),
        normal_y: f(&c.normal_y),
        normal_force: f(&c.normal_force),
        tangential_force: f(&c.tangential_force),
        overlap: f(&c.overlap),
        point_x: f(&c.point_x),
        point_y: f(&c.point_y),
        sliding: c.sliding[rows.clone()].to_vec(),
        tangential_spring: f(&c.tangential_spring),
        law_state: f(&c.law_state),
    }
}

/// The frames of results format 2 and before: one state table per frame (`frames/<k>`), ordered by
/// number, with its contact table (`frame_contacts/<k>`) where stored.
fn read_numbered_frames(file: &File, group_path: &str, path: &Path) -> Result<Vec<Snapshot>, LayoutError> {
    let mut frames: Vec<Snapshot> = numbered_datasets(file, group_path, FRAMES)?
        .iter()
        .map(|name| read_snapshot(file, &format!("{group_path}/{FRAMES}/{name}"), path))
        .collect::<Result<_, _>>()?;
    let contacts = numbered_datasets(file, group_path, FRAME_CONTACTS)?;
    for (frame, name) in frames.iter_mut().zip(&contacts) {
        frame.contacts = read_contacts(file, &format!("{group_path}/{FRAME_CONTACTS}/{name}"), path)?;
        check_contacts(frame)?;
    }
    Ok(frames)
}

/// The datasets of the subgroup `name` of a run group named by numbers, in numeric order (none when
/// there is no such subgroup).
fn numbered_datasets(file: &File, group_path: &str, name: &str) -> Result<Vec<String>, LayoutError> {
    let group = file.group(group_path)?;
    if !group.groups()?.iter().any(|g| g == name) {
        return Ok(Vec::new());
    }
    let names = file.group(&format!("{group_path}/{name}")).and_then(|g| g.datasets())?;
    let mut numbered: Vec<(usize, String)> =
        names.into_iter().filter_map(|name| Some((name.parse().ok()?, name))).collect();
    numbered.sort();
    Ok(numbered.into_iter().map(|(_, name)| name).collect())
}

/// A contact table (see [`CONTACT_FIELDS`]) as a network.
fn read_contacts(file: &File, dataset_path: &str, path: &Path) -> Result<ContactNetwork, LayoutError> {
    contacts(read_table(file, dataset_path, path)?)
}

/// The contact fields of a table (see [`CONTACT_FIELDS`]) as a network.
fn contacts(mut table: HashMap<String, ColumnData>) -> Result<ContactNetwork, LayoutError> {
    let contacts = table.get(CONTACT_FIELDS[0]).map_or(0, ColumnData::len);
    // The history fields are newer than the rest: a file without them has no history (zeros).
    for name in ["tangential_spring", "law_state"] {
        table.entry(name.to_string()).or_insert_with(|| ColumnData::Float(vec![0.0; contacts]));
    }
    let mut take = |name: &str| table.remove(name).ok_or(LayoutError::missing(format!("field `{name}`")));
    let [
        first,
        second,
        normal_x,
        normal_y,
        normal_force,
        tangential_force,
        overlap,
        point_x,
        point_y,
        sliding,
        tangential_spring,
        law_state,
    ] = CONTACT_FIELDS.map(&mut take);
    let ints = |c: Result<ColumnData, LayoutError>| match c? {
        ColumnData::Int(v) => Ok(v),
        _ => Err(LayoutError::not_a("an index field", "an integer")),
    };
    let floats = |c: Result<ColumnData, LayoutError>| match c? {
        ColumnData::Float(v) => Ok(v),
        _ => Err(LayoutError::not_a("a force or geometry field", "a float")),
    };
    let ColumnData::Bool(sliding) = sliding? else { return Err(LayoutError::not_a("field `sliding`", "0/1")) };
    Ok(ContactNetwork {
        first: ints(first)?.into_iter().map(|i| u32::try_from(i).unwrap_or(u32::MAX)).collect(),
        second: ints(second)?,
        normal_x: floats(normal_x)?,
        normal_y: floats(normal_y)?,
        normal_force: floats(normal_force)?,
        tangential_force: floats(tangential_force)?,
        overlap: floats(overlap)?,
        point_x: floats(point_x)?,
        point_y: floats(point_y)?,
        sliding,
        tangential_spring: floats(tangential_spring)?,
        law_state: floats(law_state)?,
    })
}

/// Walls a contact's `second` may name (`−1 − k`): floor, left, right, lid.
const WALLS: i64 = 4;

/// Refuses contacts whose bodies are not disks of the state (or walls): a damaged or crafted table.
fn check_contacts(state: &Snapshot) -> Result<(), LayoutError> {
    let disks = state.x.len();
    let c = &state.contacts;
    let bad_first = c.first.iter().position(|&i| i as usize >= disks);
    let bad_second = c.second.iter().position(|&j| j < -WALLS || usize::try_from(j).is_ok_and(|j| j >= disks));
    match bad_first.or(bad_second) {
        Some(k) => Err(LayoutError::inconsistent(format!(
            "contact {k} joins body {} and body {}, but the state has {disks} disks (and walls -1 to -{WALLS})",
            c.first[k], c.second[k]
        ))),
        None => Ok(()),
    }
}

/// A compound table (its path in the file) as named columns.
fn read_table(file: &File, dataset_path: &str, path: &Path) -> Result<HashMap<String, ColumnData>, LayoutError> {
    let dataset = file.dataset(dataset_path)?;
    Ok(compound::decode(&dataset, compound::read_limit(path))?.into_iter().collect())
}

/// A state table (final or frame) with its `time` attribute.
fn read_snapshot(file: &File, dataset_path: &str, path: &Path) -> Result<Snapshot, LayoutError> {
    let dataset: Dataset = file.dataset(dataset_path)?;
    let time = dataset.attrs()?.get("time").and_then(|a| a.as_f64());
    let time = time.ok_or(LayoutError::missing("`time` attribute"))?;
    let table: HashMap<String, ColumnData> =
        compound::decode(&dataset, compound::read_limit(path))?.into_iter().collect();
    let mut snapshot = Snapshot { time, ..Default::default() };
    let disks = table.get(DISK_FIELDS[0].name).map_or(0, ColumnData::len);
    for field in &DISK_FIELDS {
        *(field.values_mut)(&mut snapshot) = match field.when_absent {
            Some(value) if !table.contains_key(field.name) => vec![value; disks],
            _ => floats(&table, field.name)?,
        };
    }
    Ok(snapshot)
}

/// The history series of [`HISTORY_SERIES`] from the columns of a `history` table (a series the
/// file predates takes its declared value at every sample).
fn history(table: &HashMap<String, ColumnData>) -> Result<History, LayoutError> {
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

/// The stress profile from the columns of a `stress_profile` table (see
/// [`super::layout::stress_profile_columns`]; pressure and deviatoric stress follow from the
/// components), every column one value per band.
fn stress_profile(table: &HashMap<String, ColumnData>) -> Result<StressProfile, LayoutError> {
    let bottom = floats(table, "bottom")?;
    let [top, xx, yy, xy, wall_normal, wall_shear] =
        ["top", STRESS_XX.name, STRESS_YY.name, STRESS_XY.name, "wall_normal_stress", "wall_shear_stress"].map(
            |name| {
                let column = floats(table, name)?;
                match column.len() == bottom.len() {
                    true => Ok(column),
                    false => {
                        Err(LayoutError::inconsistent(format!("{} values for {} bands", column.len(), bottom.len()))
                            .within(name))
                    }
                }
            },
        );
    let (xx, yy, xy) = (xx?, yy?, xy?);
    let stress = (0..bottom.len()).map(|k| Stress { xx: xx[k], yy: yy[k], xy: xy[k] }).collect();
    Ok(StressProfile { bottom, top: top?, stress, wall_normal: wall_normal?, wall_shear: wall_shear? })
}

/// Column `name` of a table as floats (integer columns converted).
fn floats(table: &HashMap<String, ColumnData>, name: &str) -> Result<Vec<f64>, LayoutError> {
    match table.get(name) {
        Some(ColumnData::Float(v)) => Ok(v.clone()),
        Some(ColumnData::Int(v)) => Ok(v.iter().map(|&i| i as f64).collect()),
        Some(_) => Err(LayoutError::not_a(format!("field `{name}`"), "numeric")),
        None => Err(LayoutError::missing(format!("field `{name}`"))),
    }
}
