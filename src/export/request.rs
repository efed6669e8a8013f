//! The table of export formats and an export request carried out: runs chosen, their states
//! written by the format into a temporary folder renamed once complete.

use std::path::{Path, PathBuf};

use super::{ExportError, Format, RunToExport, State, csv, lammps, vtk};

use crate::output::guard::{self, ReplacedFolder};
use crate::output::reader::{self, DamagedGroup};
use crate::output::row::SummaryRow;
use crate::output::stored::{self, StoredRun};

/// Every export format. A new one is a file of this module and a row here.
pub const FORMATS: &[&Format] = &[&vtk::FORMAT, &lammps::FORMAT, &csv::FORMAT];

/// The format called `name`.
pub fn format(name: &str) -> Option<&'static Format> {
    FORMATS.iter().copied().find(|f| f.name == name)
}

/// What to export.
#[derive(Clone, Debug)]
pub struct ExportRequest {
    /// The results file.
    pub results: PathBuf,
    /// The format (a row of [`FORMATS`]).
    pub format: &'static Format,
    /// Run ids to export; empty: every run with a stored final state.
    pub runs: Vec<String>,
    /// Also export each run's recorded frames.
    pub frames: bool,
    /// The output folder (created; must not exist unless `force`).
    pub out: PathBuf,
    /// Replace an existing output folder.
    pub force: bool,
}

/// What an export wrote.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ExportSummary {
    /// Runs exported.
    pub runs: usize,
    /// Files written.
    pub files: usize,
    /// Bytes written.
    pub bytes: u64,
    /// Run groups of the file that cannot be read (left out of an export of every run).
    pub damaged: Vec<DamagedGroup>,
}

/// Exports the requested runs; errors name the run, file or option at fault.
pub fn export(request: &ExportRequest) -> Result<ExportSummary, ExportError> {
    let out = &request.out;
    if exists_unforced(out, request.force) {
        return Err(guard::GuardError { path: out.clone(), refusal: guard::Refusal::Exists }.into());
    }
    let file = reader::open(&request.results)?;
    let (rows, damaged) = reader::scan(&file, &request.results)?;
    let mut names = Vec::new();
    for id in &request.runs {
        names.push(reader::listed_group(&file, &request.results, id)?.unwrap_or(id.clone()));
    }
    if let Some(d) = damaged.iter().find(|d| names.iter().any(|name| d.group.ends_with(&format!("/{name}")))) {
        let (group, reason) = (d.group.clone(), d.reason.to_string());
        return Err(ExportError::DamagedRun { results: request.results.clone(), group, reason });
    }
    let chosen = choose_runs(&rows, &request.runs, &request.results)?;
    let folder = ReplacedFolder::prepare(out, MARKER_KIND, &[&request.results], request.force)?;
    if let Err(e) = write_runs(request, &file, &chosen, folder.partial()) {
        folder.abandon();
        return Err(e);
    }
    folder.finish()?;
    let (files, bytes) = folder_size(out)?;
    Ok(ExportSummary { runs: chosen.len(), files, bytes, damaged })
}

/// The kind of the marker file in an export folder (`.demsweep-export`): `--force` replaces only such folders.
pub const MARKER_KIND: &str = "export";

/// Whether something is at `out` and `--force` was not given.
fn exists_unforced(out: &Path, force: bool) -> bool {
    !force && std::fs::symlink_metadata(out).is_ok()
}

/// The rows to export: the named ones (each must exist), else every run that finished.
fn choose_runs<'a>(rows: &'a [SummaryRow], ids: &[String], results: &Path) -> Result<Vec<&'a SummaryRow>, ExportError> {
    if ids.is_empty() {
        return Ok(rows.iter().filter(|r| r.is_finished()).collect());
    }
    ids.iter()
        .map(|id| {
            rows.iter()
                .find(|r| &r.id == id)
                .ok_or_else(|| ExportError::UnknownRun { results: results.to_path_buf(), id: id.clone() })
        })
        .collect()
}

/// Reads and writes each run into `folder`.
fn write_runs(
    request: &ExportRequest,
    file: &hdf5_pure::File,
    rows: &[&SummaryRow],
    folder: &Path,
) -> Result<(), ExportError> {
    for row in rows {
        let run = stored::read_run(file, &request.results, row)?;
        let states = states(request, row, &run)?;
        let written = (request.format.write_run)(folder, &RunToExport { row, run: &run }, &states);
        written.map_err(|source| ExportError::Write { folder: folder.to_path_buf(), id: row.id.clone(), source })?;
    }
    Ok(())
}

/// The states of a run to export: its frames (with `frames`) then its final state.
fn states<'a>(request: &ExportRequest, row: &'a SummaryRow, run: &'a StoredRun) -> Result<Vec<State<'a>>, ExportError> {
    let (results, id) = (request.results.clone(), row.id.clone());
    let Some(final_state) = &run.final_state else {
        return Err(ExportError::NoFinalState { results, id, status: row.status.to_string() });
    };
    if request.frames && run.frames.is_empty() {
        return Err(ExportError::NoFrames { results, id });
    }
    let frames = if request.frames { run.frames.as_slice() } else { &[] };
    let mut states: Vec<State> = frames
        .iter()
        .enumerate()
        .map(|(k, snapshot)| State {
            run: &row.id,
            label: format!("frame_{}", crate::output::layout::frame_name(k)),
            snapshot,
        })
        .collect();
    states.push(State { run: &row.id, label: "final".into(), snapshot: final_state });
    Ok(states)
}

/// Files and bytes in a folder (not recursive: exports are flat).
fn folder_size(folder: &Path) -> Result<(usize, u64), ExportError> {
    let entries = std::fs::read_dir(folder).map_err(|source| ExportError::Io { path: folder.to_path_buf(), source })?;
    let mut files = 0;
    let mut bytes = 0;
    let marker = guard::marker_name(MARKER_KIND);
    for entry in entries.flatten().filter(|e| e.file_name() != marker.as_str()) {
        files += 1;
        bytes += entry.metadata().map_or(0, |m| m.len());
    }
    Ok((files, bytes))
}
