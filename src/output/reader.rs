//! Reads results files back: header, run rows, the summary table, one run's history.

use std::path::Path;

use hdf5_pure::{DType, Dataset, File};

use super::header::FileHeader;
use super::layout::{self, POINTS, RUNS, SUMMARY, SUMMARY_COLUMNS, SWEEP_JOBS, SWEEP_WALL_TIME};
use super::row::SummaryRow;
use super::table::{Column, ColumnData, SummaryTable};
use super::{OutputError, hdf5_error};

/// Opens a results file for reading (streaming: only what is read is loaded).
pub fn open(path: &Path) -> Result<File, OutputError> {
    if !path.is_file() {
        return Err(OutputError::new(path, "no such results file"));
    }
    File::open_streaming(path).map_err(|e| hdf5_error(path, e))
}

/// The file's root attributes.
pub fn header(file: &File, path: &Path) -> Result<FileHeader, OutputError> {
    let attrs = file.root().attrs().map_err(|e| hdf5_error(path, e))?;
    FileHeader::from_attrs(&attrs)
        .map_err(|reason| OutputError::new(path, format!("not a demsweep results file: {reason}")))
}

/// How the last sweep into the file ran: worker threads and wall time (s), when it was recorded
/// (`/summary` attributes, see [`SWEEP_JOBS`]).
pub fn sweep(file: &File) -> Option<(usize, f64)> {
    let attrs = file.group(SUMMARY).and_then(|g| g.attrs()).ok()?;
    let jobs = attrs.get(SWEEP_JOBS)?.as_i64()?;
    let wall_time = attrs.get(SWEEP_WALL_TIME)?.as_f64()?;
    Some((jobs as usize, wall_time))
}

/// A run group that cannot be read (overwritten bytes, a failed disk): its path and the reason.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DamagedGroup {
    /// The group, e.g. `/runs/b0000/r0012` (a whole bucket, `/runs/b0003`, when its index is damaged).
    pub group: String,
    /// What could not be read.
    pub reason: String,
}

/// The rows of every readable committed run (sorted by run index) and the run groups that cannot
/// be read.
pub fn scan(file: &File, path: &Path) -> Result<(Vec<SummaryRow>, Vec<DamagedGroup>), OutputError> {
    let (mut rows, mut damaged) = (Vec::new(), Vec::new());
    let buckets = file.group(RUNS).and_then(|g| g.iter_groups()).map_err(|e| hdf5_error(path, e))?;
    for (bucket, group) in buckets {
        let runs = match group.iter_groups() {
            Ok(runs) => runs,
            Err(e) => {
                damaged.push(DamagedGroup { group: format!("/{RUNS}/{bucket}"), reason: e.to_string() });
                continue;
            }
        };
        for (name, run) in runs {
            let row = run.attrs().map_err(|e| e.to_string()).and_then(|attrs| layout::row_from_attrs(&attrs));
            match row {
                Ok(row) => rows.push(row),
                Err(reason) => damaged.push(DamagedGroup { group: format!("/{RUNS}/{bucket}/{name}"), reason }),
            }
        }
    }
    rows.sort_by_key(|r| r.index);
    Ok((rows, damaged))
}

/// The rows of every committed run, sorted by run index; an error naming the damaged run groups if
/// some cannot be read (see [`scan`]).
pub fn rows(file: &File, path: &Path) -> Result<Vec<SummaryRow>, OutputError> {
    let (rows, damaged) = scan(file, path)?;
    if damaged.is_empty() { Ok(rows) } else { Err(OutputError::new(path, damage_text(&damaged))) }
}

/// What is wrong with a file whose `damaged` run groups cannot be read, and what to do.
pub fn damage_text(damaged: &[DamagedGroup]) -> String {
    let named: Vec<String> = damaged.iter().take(10).map(|d| format!("{} ({})", d.group, d.reason)).collect();
    let more = if damaged.len() > 10 { format!(" and {} more", damaged.len() - 10) } else { String::new() };
    format!(
        "damaged: {} run group(s) cannot be read: {}{more}; `demsweep run STUDY --resume` on this file runs them again",
        damaged.len(),
        named.join(", ")
    )
}

/// The summary and the damaged run groups: `/summary` when every run group reads (see [`summary`]),
/// else the summary of the readable runs.
pub fn checked_summary(file: &File, path: &Path) -> Result<(SummaryTable, Vec<DamagedGroup>), OutputError> {
    let (rows, damaged) = scan(file, path)?;
    if damaged.is_empty() {
        return Ok((summary(file, path)?, damaged));
    }
    Ok((SummaryTable::from_rows(&rows), damaged))
}

/// The summary: `/summary` when the file has it, else assembled from the run groups (a file whose
/// writer was killed before finishing).
pub fn summary(file: &File, path: &Path) -> Result<SummaryTable, OutputError> {
    match columns(file, path, SUMMARY)? {
        Some(table) => Ok(table),
        None => Ok(SummaryTable::from_rows(&rows(file, path)?)),
    }
}

/// The per-point statistics stored in `/points`; `None` for a file written before `/points` existed,
/// or whose writer was killed (`crate::stats::points::read` computes them then).
pub fn points(file: &File, path: &Path) -> Result<Option<SummaryTable>, OutputError> {
    columns(file, path, POINTS)
}

/// The table stored as one dataset per column in the group `name`, if the file has that group.
fn columns(file: &File, path: &Path, name: &str) -> Result<Option<SummaryTable>, OutputError> {
    let err = |e| hdf5_error(path, e);
    if !file.root().groups().map_err(err)?.iter().any(|g| g == name) {
        return Ok(None);
    }
    let group = file.group(name).map_err(err)?;
    let attrs = group.attrs().map_err(err)?;
    let names = attrs.get(SUMMARY_COLUMNS).and_then(|a| a.as_strings()).unwrap_or(&[]);
    let columns = names
        .iter()
        .map(|name| {
            let dataset = group.dataset(name).map_err(err)?;
            let data = column_data(&dataset).map_err(err)?;
            Ok(Column { name: name.clone(), data })
        })
        .collect::<Result<_, OutputError>>()?;
    Ok(Some(SummaryTable { columns }))
}

fn column_data(dataset: &Dataset) -> Result<ColumnData, hdf5_pure::Error> {
    Ok(match dataset.dtype()? {
        DType::I64 => ColumnData::Int(dataset.read_i64()?),
        DType::U8 => ColumnData::Bool(dataset.read_u8()?.into_iter().map(|b| b != 0).collect()),
        DType::String => ColumnData::Text(dataset.read_string()?),
        _ => ColumnData::Float(dataset.read_f64()?),
    })
}

/// Path of the group of the run with this id (searched in every bucket).
pub fn find_run(file: &File, path: &Path, run_id: &str) -> Result<String, OutputError> {
    let err = |e| hdf5_error(path, e);
    for (bucket, group) in file.group(RUNS).and_then(|g| g.iter_groups()).map_err(err)? {
        if group.groups().map_err(err)?.iter().any(|g| g == run_id) {
            return Ok(format!("{RUNS}/{bucket}/{run_id}"));
        }
    }
    Err(OutputError::new(path, format!("no run `{run_id}` in this file (see `demsweep summary` for the run ids)")))
}
