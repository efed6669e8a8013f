//! Exports of stored runs to other codes' formats, read from a results file. Every format is one
//! file of this module and one row of [`FORMATS`] (its `--format` name, what it writes, its writer);
//! `demsweep export --format` offers the table's names.
//!
//! Everything is written into a temporary sibling of the output folder, which is renamed to its
//! final name only once complete: a failed export leaves nothing under that name.

pub mod csv;
pub mod lammps;
pub mod vtk;

use std::path::{Path, PathBuf};

use crate::output::reader;
use crate::output::row::SummaryRow;
use crate::output::stored::{self, StoredRun};
use crate::physics::record::Snapshot;

/// One export format: a row of [`FORMATS`].
pub struct Format {
    /// Its `--format` name.
    pub name: &'static str,
    /// What it writes, in a line (the CLI's help).
    pub description: &'static str,
    /// Writes the states of one run into a folder.
    pub write_run: fn(&Path, &RunToExport, &[State]) -> Result<(), String>,
}

impl std::fmt::Debug for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Format({})", self.name)
    }
}

/// Every export format. A new one is a file of this module and a row here.
pub const FORMATS: &[&Format] = &[&vtk::FORMAT, &lammps::FORMAT, &csv::FORMAT];

/// The format called `name`.
pub fn format(name: &str) -> Option<&'static Format> {
    FORMATS.iter().copied().find(|f| f.name == name)
}

/// A run being exported: its summary row and its stored data.
pub struct RunToExport<'a> {
    /// The run's summary row (id, status, per-run quantities).
    pub row: &'a SummaryRow,
    /// The run's stored scene and states.
    pub run: &'a StoredRun,
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
}

/// One state to write: the run it belongs to, its name in file names and the snapshot.
pub struct State<'a> {
    /// The run's id.
    pub run: &'a str,
    /// `final`, or `frame_<k>` (zero-padded).
    pub label: String,
    /// The state.
    pub snapshot: &'a Snapshot,
}

/// Exports the requested runs; errors name the run, file or option at fault.
pub fn export(request: &ExportRequest) -> Result<ExportSummary, String> {
    let out = &request.out;
    if out.exists() && !request.force {
        return Err(format!("{}: already exists: pass --force to replace it, or choose another --out", out.display()));
    }
    let file = reader::open(&request.results).map_err(|e| e.to_string())?;
    let rows = reader::rows(&file, &request.results).map_err(|e| e.to_string())?;
    let chosen = choose_runs(&rows, &request.runs, &request.results)?;
    let partial = partial_folder(out);
    if partial.exists() {
        std::fs::remove_dir_all(&partial).map_err(|e| format!("{}: cannot remove: {e}", partial.display()))?;
    }
    std::fs::create_dir_all(&partial).map_err(|e| format!("{}: cannot create: {e}", partial.display()))?;
    let written = write_runs(request, &file, &chosen, &partial);
    if let Err(e) = written {
        let _ = std::fs::remove_dir_all(&partial);
        return Err(e);
    }
    if out.exists() {
        std::fs::remove_dir_all(out).map_err(|e| format!("{}: cannot replace: {e}", out.display()))?;
    }
    std::fs::rename(&partial, out)
        .map_err(|e| format!("{}: cannot rename to {}: {e}", partial.display(), out.display()))?;
    let (files, bytes) = folder_size(out)?;
    Ok(ExportSummary { runs: chosen.len(), files, bytes })
}

/// The rows to export: the named ones (each must exist), else every run that finished.
fn choose_runs<'a>(rows: &'a [SummaryRow], ids: &[String], results: &Path) -> Result<Vec<&'a SummaryRow>, String> {
    if ids.is_empty() {
        return Ok(rows.iter().filter(|r| r.is_finished()).collect());
    }
    ids.iter()
        .map(|id| {
            rows.iter().find(|r| &r.id == id).ok_or_else(|| {
                format!(
                    "{}: no run `{id}` (--run): see `demsweep summary {}` for the run ids",
                    results.display(),
                    results.display()
                )
            })
        })
        .collect()
}

/// Reads and writes each run into `folder`.
fn write_runs(
    request: &ExportRequest,
    file: &hdf5_pure::File,
    rows: &[&SummaryRow],
    folder: &Path,
) -> Result<(), String> {
    for row in rows {
        let run = stored::read_run(file, &request.results, row).map_err(|e| e.to_string())?;
        let states = states(request, row, &run)?;
        let written = (request.format.write_run)(folder, &RunToExport { row, run: &run }, &states);
        written.map_err(|e| format!("{}: run {}: {e}", folder.display(), row.id))?;
    }
    Ok(())
}

/// The states of a run to export: its frames (with `frames`) then its final state.
fn states<'a>(request: &ExportRequest, row: &'a SummaryRow, run: &'a StoredRun) -> Result<Vec<State<'a>>, String> {
    let results = request.results.display();
    let Some(final_state) = &run.final_state else {
        return Err(format!(
            "{results}: run {} has no stored final state (status {}; its study had output.final_states = false, or it \
             failed): leave it out of --run, or run it again with output.final_states = true",
            row.id, row.status
        ));
    };
    if request.frames && run.frames.is_empty() {
        return Err(format!(
            "{results}: run {} has no stored frames (--frames): run it again with output.frames = true and \
             run.frame_times or run.frame_interval set, or leave out --frames",
            row.id
        ));
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

/// The temporary sibling an export is written into: `<out>.partial`.
fn partial_folder(out: &Path) -> PathBuf {
    let mut name = out.file_name().map(|n| n.to_os_string()).unwrap_or_else(|| "export".into());
    name.push(".partial");
    out.with_file_name(name)
}

/// Files and bytes in a folder (not recursive: exports are flat).
fn folder_size(folder: &Path) -> Result<(usize, u64), String> {
    let entries = std::fs::read_dir(folder).map_err(|e| format!("{}: cannot list: {e}", folder.display()))?;
    let mut files = 0;
    let mut bytes = 0;
    for entry in entries.flatten() {
        files += 1;
        bytes += entry.metadata().map_or(0, |m| m.len());
    }
    Ok((files, bytes))
}

/// Creates `folder/name` and writes what `body` produces into it through a buffer.
pub(crate) fn write_file(
    folder: &Path,
    name: &str,
    body: impl FnOnce(&mut dyn std::io::Write) -> std::io::Result<()>,
) -> Result<(), String> {
    let path = folder.join(name);
    let fail = |e: std::io::Error| format!("{}: cannot write: {e}", path.display());
    let file = std::fs::File::create(&path).map_err(fail)?;
    let mut buffer = std::io::BufWriter::new(file);
    body(&mut buffer).and_then(|()| std::io::Write::flush(&mut buffer)).map_err(fail)
}
