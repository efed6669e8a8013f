//! Reads results files back: header, run rows, the summary table, one run's history.

use std::cell::Cell;
use std::collections::HashMap;
use std::path::Path;

use hdf5_pure::{AttrValue, DType, Dataset, File};

use super::error::OutputReason;
use super::header::FileHeader;
use super::layout::{self, LEGACY_RUNS, POINTS, STORED_RUNS, SUMMARY, SUMMARY_COLUMNS, SWEEP_JOBS, SWEEP_WALL_TIME};
use super::layout_error::LayoutError;
use super::row::SummaryRow;
use super::table::{Column, ColumnData, SummaryTable};
use super::{OutputError, hdf5_error, run_attrs};

pub use super::error::{DamagedGroup, damage_text};

/// The results file `path` names: the file itself, or the one results file (`*.h5`, not a temporary
/// `*.partial` or `*.merging.h5`) in the folder `path`; an error naming the folder when it holds none
/// or several (listed).
pub fn locate(path: &Path) -> Result<std::path::PathBuf, OutputError> {
    if !path.is_dir() {
        return Ok(path.to_path_buf());
    }
    let entries = std::fs::read_dir(path).map_err(|e| OutputError::io(path, e))?;
    let mut found: Vec<std::path::PathBuf> = entries
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "h5"))
        .filter(|p| !p.to_string_lossy().ends_with(".merging.h5"))
        .collect();
    found.sort();
    match found.len() {
        1 => Ok(found.remove(0)),
        0 => Err(OutputError::at(path, OutputReason::NoResultsFile)),
        _ => {
            let names: Vec<String> =
                found.iter().filter_map(|p| p.file_name()).map(|n| n.to_string_lossy().into_owned()).collect();
            Err(OutputError::at(path, OutputReason::SeveralResultsFiles(names)))
        }
    }
}

/// Opens a results file for reading (streaming: only what is read is loaded).
pub fn open(path: &Path) -> Result<File, OutputError> {
    if !path.is_file() {
        return Err(OutputError::at(path, OutputReason::NoSuchFile));
    }
    File::open_streaming(path).map_err(|e| match path.extension().and_then(|e| e.to_str()) {
        Some(ext) if !ext.eq_ignore_ascii_case("h5") => {
            OutputError::at(path, OutputReason::NotHdf5 { extension: ext.to_string(), error: e.to_string() })
        }
        _ => hdf5_error(path, e),
    })
}

/// The file's root attributes.
pub fn header(file: &File, path: &Path) -> Result<FileHeader, OutputError> {
    let attrs = file.root().attrs().map_err(|e| hdf5_error(path, e))?;
    FileHeader::from_attrs(&attrs).map_err(|reason| OutputError::at(path, OutputReason::NotResults(reason)))
}

/// How the last sweep into the file ran: worker threads and wall time (s), when it was recorded
/// (`/summary` attributes, see [`SWEEP_JOBS`]).
pub fn sweep(file: &File) -> Option<(usize, f64)> {
    let attrs = file.group(SUMMARY).and_then(|g| g.attrs()).ok()?;
    let jobs = attrs.get(SWEEP_JOBS)?.as_i64()?;
    let wall_time = attrs.get(SWEEP_WALL_TIME)?.as_f64()?;
    Some((jobs as usize, wall_time))
}

/// The committed runs of a results file.
#[derive(Clone, Debug, Default)]
pub struct CommittedRuns {
    /// The rows of the readable runs, sorted by run index.
    pub rows: Vec<SummaryRow>,
    /// Where each readable run's group is: group name (see [`SummaryRow::group_name`]) → group path
    /// (without a leading `/`).
    pub groups: HashMap<String, String>,
    /// The run groups (or batch groups) that cannot be read.
    pub damaged: Vec<DamagedGroup>,
}

thread_local! {
    /// Run groups whose rows this thread has read (attributes and tables): each costs a read of a run
    /// group, which readers do only for runs `/summary` does not describe (and for the warnings
    /// of runs that have warnings). Tests count them to check that reading a finished file does not.
    static ATTRIBUTE_SETS_READ: Cell<usize> = const { Cell::new(0) };
}

/// How many run groups' attribute sets this thread has read (see [`committed_runs`]).
pub fn attribute_sets_read() -> usize {
    ATTRIBUTE_SETS_READ.get()
}

/// Every committed run: its row and its group, and the groups that cannot be read. The rows come
/// from `/summary` for the runs it describes (reading the warning texts of runs with warnings from
/// their group), from the run group's attributes for the others (a file whose writer was killed
/// before writing `/summary`), so that reading a finished file costs a header per run (listing a
/// batch opens each run group's header, which finds damaged ones), not an attribute set.
pub fn committed_runs(file: &File, path: &Path) -> Result<CommittedRuns, OutputError> {
    let mut described = summary_rows(file, path)?;
    let (located, mut damaged) = run_groups(file, path, &described)?;
    let mut runs = CommittedRuns::default();
    let limit = super::compound::read_limit(path);
    for (name, group) in located {
        let row = match described.remove(&name) {
            Some((row, warnings)) => with_warnings(file, &group, row, (warnings, limit)),
            None => group_row(file, &group, limit),
        };
        match row.and_then(|row| checked_id(row, &name)) {
            Ok(row) => {
                runs.rows.push(row);
                runs.groups.insert(name, group);
            }
            Err(reason) => damaged.push(DamagedGroup { group: format!("/{group}"), reason }),
        }
    }
    runs.rows.sort_by_key(|r| r.index);
    runs.damaged = damaged;
    Ok(runs)
}

/// The row if its run id is its group's name and can name files (plots and exports are named by
/// it): not empty, `.` or `..`, without `/`, `\\` or control characters.
fn checked_id(row: SummaryRow, group_name: &str) -> Result<SummaryRow, LayoutError> {
    if row.group_name() != group_name {
        let named = if row.identity.is_empty() { "run id" } else { "identity" };
        return Err(LayoutError::inconsistent(format!(
            "its {named} `{}` is not its group's name `{group_name}`",
            row.group_name().escape_debug()
        )));
    }
    let unsafe_name =
        matches!(row.id.as_str(), "" | "." | "..") || row.id.chars().any(|c| c == '/' || c == '\\' || c.is_control());
    if unsafe_name {
        return Err(LayoutError::inconsistent(format!("its run id `{}` cannot name a file", row.id.escape_debug())));
    }
    Ok(row)
}

/// The rows of every readable committed run (sorted by run index) and the run groups that cannot
/// be read (see [`committed_runs`]).
pub fn scan(file: &File, path: &Path) -> Result<(Vec<SummaryRow>, Vec<DamagedGroup>), OutputError> {
    let runs = committed_runs(file, path)?;
    Ok((runs.rows, runs.damaged))
}

/// The run groups of a file, by id (without a leading `/`), in storage order, from the names in the
/// batch groups (and the buckets of files written before batches). Listing a batch opens each of its
/// run groups' headers, so a damaged run group fails its batch's listing: the runs `described` by
/// `/summary` are then looked up in that batch one by one, and a batch none of them is found in is
/// damaged as a whole.
fn run_groups(
    file: &File,
    path: &Path,
    described: &HashMap<String, (SummaryRow, usize)>,
) -> Result<(Vec<RunGroup>, Vec<DamagedGroup>), OutputError> {
    let (mut located, mut damaged) = (Vec::new(), Vec::new());
    for parent in containers(file).map_err(|e| hdf5_error(path, e))? {
        match file.group(&parent).and_then(|g| g.groups()) {
            Ok(names) => located.extend(names.into_iter().map(|id| (id.clone(), format!("{parent}/{id}")))),
            Err(e) => {
                let (found, unreadable) = look_up(file, &parent, described.keys());
                if found.is_empty() && unreadable.is_empty() {
                    damaged.push(DamagedGroup { group: format!("/{parent}"), reason: e.into() });
                }
                located.extend(found);
                damaged.extend(unreadable);
            }
        }
    }
    Ok((located, damaged))
}

/// A run group's name and path.
type RunGroup = (String, String);

/// The runs of `ids` in the group `parent`, each opened and its attributes read: those found, and
/// those whose group is there but cannot be read.
fn look_up<'a>(file: &File, parent: &str, ids: impl Iterator<Item = &'a String>) -> (Vec<RunGroup>, Vec<DamagedGroup>) {
    let (mut found, mut unreadable) = (Vec::new(), Vec::new());
    for id in ids {
        let group = format!("{parent}/{id}");
        match file.group(&group) {
            Err(hdf5_pure::Error::Format(hdf5_pure::FormatError::PathNotFound(_))) => {}
            opened => match opened.and_then(|g| g.attrs()).map_err(LayoutError::from) {
                Ok(_) => found.push((id.clone(), group)),
                Err(reason) => unreadable.push(DamagedGroup { group: format!("/{group}"), reason }),
            },
        }
    }
    (found, unreadable)
}

/// The groups holding run groups: the batch groups in commit order, then the buckets of a file
/// written before batches.
fn containers(file: &File) -> Result<Vec<String>, hdf5_pure::Error> {
    let root = file.root().groups()?;
    let mut batches: Vec<(usize, String)> =
        root.iter().filter_map(|name| Some((layout::batch_number(name)?, name.clone()))).collect();
    batches.sort();
    let mut parents: Vec<String> = batches.into_iter().map(|(_, name)| name).collect();
    if root.iter().any(|g| g == LEGACY_RUNS) {
        parents.extend(file.group(LEGACY_RUNS)?.groups()?.into_iter().map(|b| format!("{LEGACY_RUNS}/{b}")));
    }
    Ok(parents)
}

/// The rows `/summary` describes, by group name, with their warning counts (and the version that
/// made each, where `/summary` records it); none when the file has no `/summary` or one that does
/// not describe runs completely (an older layout).
fn summary_rows(file: &File, path: &Path) -> Result<HashMap<String, (SummaryRow, usize)>, OutputError> {
    let Some(table) = stored_table(file, path, SUMMARY)? else { return Ok(HashMap::new()) };
    let mut rows = table.rows().unwrap_or_default();
    let made_by = file.dataset(&format!("{SUMMARY}/{}", layout::RUN_MADE_BY)).and_then(|d| d.read_string());
    if let Some(made_by) = made_by.ok().filter(|v| v.len() == rows.len()) {
        for ((row, _), version) in rows.iter_mut().zip(made_by) {
            row.made_by = version;
        }
    }
    Ok(rows.into_iter().map(|(row, warnings)| (row.group_name().to_string(), (row, warnings))).collect())
}

/// A row `/summary` describes; a run with warnings gets them from its group (tables read at most
/// `limit` bytes).
fn with_warnings(
    file: &File,
    group: &str,
    mut row: SummaryRow,
    (warnings, limit): (usize, u64),
) -> Result<SummaryRow, LayoutError> {
    if warnings > 0 {
        row.warnings = group_row(file, group, limit)?.warnings;
    }
    Ok(row)
}

/// A run's row read from its group (counted: see [`attribute_sets_read`]).
fn group_row(file: &File, group: &str, limit: u64) -> Result<SummaryRow, LayoutError> {
    let opened = file.group(group)?;
    ATTRIBUTE_SETS_READ.set(ATTRIBUTE_SETS_READ.get() + 1);
    run_attrs::row_from_group(&opened, limit)
}

/// The rows of every committed run, sorted by run index; an error naming the damaged run groups if
/// some cannot be read (see [`scan`]).
pub fn rows(file: &File, path: &Path) -> Result<Vec<SummaryRow>, OutputError> {
    let (rows, damaged) = scan(file, path)?;
    if damaged.is_empty() { Ok(rows) } else { Err(OutputError::at(path, OutputReason::Damaged(damaged))) }
}

/// The summary and the damaged run groups: `/summary` when every run group reads and it was written
/// after the last run was stored (see [`layout::STORED_RUNS`]), else the summary of the readable runs.
pub fn checked_summary(file: &File, path: &Path) -> Result<(SummaryTable, Vec<DamagedGroup>), OutputError> {
    let (rows, damaged) = scan(file, path)?;
    let stored_runs = file.group(SUMMARY).and_then(|g| g.attrs()).ok().and_then(|a| a.get(STORED_RUNS)?.as_i64());
    match stored_table(file, path, SUMMARY)? {
        Some(table) if damaged.is_empty() && stored_runs.map_or(table.len(), |n| n as usize) == rows.len() => {
            Ok((table, damaged))
        }
        _ => Ok((SummaryTable::from_rows(&rows), damaged)),
    }
}

/// The summary: `/summary` when the file has it, else assembled from the run groups (a file whose
/// writer was killed before finishing).
pub fn summary(file: &File, path: &Path) -> Result<SummaryTable, OutputError> {
    match stored_table(file, path, SUMMARY)? {
        Some(table) => Ok(table),
        None => Ok(SummaryTable::from_rows(&rows(file, path)?)),
    }
}

/// The per-point statistics stored in `/points`; `None` for a file written before `/points` existed,
/// or whose writer was killed (`crate::stats::points::read` computes them then).
pub fn points(file: &File, path: &Path) -> Result<Option<SummaryTable>, OutputError> {
    stored_table(file, path, POINTS)
}

/// The table stored as one dataset per column in the group `name` (`/summary`, `/points`), if the
/// file has that group.
pub fn stored_table(file: &File, path: &Path, name: &str) -> Result<Option<SummaryTable>, OutputError> {
    let err = |e| hdf5_error(path, e);
    if !file.root().groups().map_err(err)?.iter().any(|g| g == name) {
        return Ok(None);
    }
    let group = file.group(name).map_err(err)?;
    let attrs = group.attrs().map_err(err)?;
    // No `columns`: a table whose writing was cut short (see `writer::write_columns`).
    let Some(names) = table_names(&attrs) else { return Ok(None) };
    let columns = names
        .iter()
        .map(|name| {
            let dataset = group.dataset(name).map_err(err)?;
            Ok(column_data(&dataset).ok().map(|data| Column { name: name.clone(), data }))
        })
        .collect::<Result<Option<Vec<Column>>, OutputError>>()?;
    // A column that does not read (its checksum fails) or columns of different lengths (a damaged
    // or crafted file): the table is not used, as if the file had none (`/summary` is then rebuilt
    // from the run groups, `/points` from the summary).
    let Some(columns) = columns else { return Ok(None) };
    let rows = columns.first().map_or(0, |c| c.data.len());
    Ok(columns.iter().all(|c| c.data.len() == rows).then_some(SummaryTable { columns }))
}

/// The names of the columns of the table stored in the group `name` of the results file `path`
/// (`/summary`, `/points`), its data unread; `None` when the file has no complete such table.
pub fn stored_names(path: &Path, name: &str) -> Option<Vec<String>> {
    let file = open(path).ok()?;
    table_names(&file.group(name).ok()?.attrs().ok()?)
}

/// The table's column names from its group's attributes (its `columns` less the file's own).
fn table_names(attrs: &HashMap<String, AttrValue>) -> Option<Vec<String>> {
    let names = attrs.get(SUMMARY_COLUMNS)?.as_strings()?;
    Some(
        names
            .iter()
            .filter(|name| ![layout::RUN_GROUP, layout::RUN_MADE_BY].contains(&name.as_str()))
            .cloned()
            .collect(),
    )
}

fn column_data(dataset: &Dataset) -> Result<ColumnData, hdf5_pure::Error> {
    Ok(match dataset.dtype()? {
        DType::I64 => ColumnData::Int(dataset.read_i64()?),
        DType::U8 => ColumnData::Bool(dataset.read_u8()?.into_iter().map(|b| b != 0).collect()),
        DType::String => ColumnData::Text(dataset.read_string()?),
        _ => ColumnData::Float(dataset.read_f64()?),
    })
}

/// Path of the group of the run with this id (without a leading `/`): its group name from
/// `/summary` (or from the run groups when `/summary` does not list it), looked up in each batch (and
/// bucket): a lookup per batch, not a read of every run's name.
pub fn find_run(file: &File, path: &Path, run_id: &str) -> Result<String, OutputError> {
    let missing = || OutputError::at(path, OutputReason::NoRun(run_id.to_string()));
    let name = match listed_group(file, path, run_id)? {
        Some(name) => name,
        None => scan(file, path)?.0.into_iter().find(|r| r.id == run_id).ok_or_else(missing)?.group_name().to_string(),
    };
    find_group(file, path, &name)?.ok_or_else(missing)
}

/// The name of the group of run `run_id` as `/summary` lists it (its identity, or its id in files
/// written before identities); `None` when `/summary` does not list the run.
pub fn listed_group(file: &File, path: &Path, run_id: &str) -> Result<Option<String>, OutputError> {
    Ok(stored_table(file, path, SUMMARY)?.and_then(|table| {
        let ids = table.column("run_id")?;
        let row = (0..table.len()).find(|&i| ids.data.text(i) == run_id)?;
        let identity = table.column(super::table::IDENTITY).map(|c| c.data.text(row)).unwrap_or_default();
        Some(if identity.is_empty() { run_id.to_string() } else { identity })
    }))
}

/// Path of the run group called `name` (see [`SummaryRow::group_name`]), looked up in each batch
/// (and bucket), newest first; `None` when no batch holds it.
pub fn find_group(file: &File, path: &Path, name: &str) -> Result<Option<String>, OutputError> {
    let parents = containers(file).map_err(|e| hdf5_error(path, e))?;
    Ok(parents.iter().rev().map(|parent| format!("{parent}/{name}")).find(|group| file.group(group).is_ok()))
}

/// The error of a dataset of run `run_id` (`dataset`: its path) that cannot be read, e.g. one whose
/// Fletcher-32 checksum does not match its bytes (damaged data is an error, never a value).
pub fn damaged_data(path: &Path, run_id: &str, dataset: &str, reason: LayoutError) -> OutputError {
    OutputError::at(path, OutputReason::BadData { run: run_id.to_string(), dataset: dataset.to_string(), reason })
}
