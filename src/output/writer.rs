//! Writes runs into a results file in place: each commit appends the staged run groups, in a new
//! batch group under the root (see [`layout`]), and repoints the superblock last (hdf5-pure's
//! crash-safe commit), so the file is valid after every commit.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use hdf5_pure::{AttrValue, DatasetBuilder, File, FileBuilder, StagedGroup};

use super::compound::{self, Field};
use super::copy::GroupCopy;
use super::header::FileHeader;
use super::layout::{self, POINTS, SUMMARY, SUMMARY_COLUMNS, SWEEP_JOBS, SWEEP_WALL_TIME};
use super::reader::{self, DamagedGroup};
use super::row::{DEMSWEEP_VERSION, SummaryRow};
use super::sink::{ResultSink, RunResult, Tables};
use super::table::{Column, ColumnData, SummaryTable};
use super::{LayoutError, OutputError, OutputReason, hdf5_error, run_attrs};
use crate::physics::SceneConfig;
use crate::physics::record::{DISK_FIELDS, RunRecord, Snapshot};
use crate::physics::stress::StressProfile;
use crate::study::OutputOptions;

/// A results file open for writing.
pub struct ResultsWriter {
    file: File,
    path: PathBuf,
    output: OutputOptions,
    /// The number of the next batch group, and the batch group being staged (if any).
    next_batch: usize,
    batch: Option<String>,
    /// Where the runs' groups are (committed and staged), by group name (see
    /// [`SummaryRow::group_name`]).
    groups: HashMap<String, String>,
    /// The demsweep version that made each run, by group name, for the runs not made by this one
    /// (empty where not recorded): most files hold none, so this costs nothing per run.
    made_by: HashMap<String, String>,
    /// The demsweep version that created the file (the header's).
    created_by: String,
    existing: Vec<SummaryRow>,
    damaged: Vec<DamagedGroup>,
    pending: usize,
    /// Whether this session changed no run (added, copied or deleted none): `/summary` and `/points`
    /// then stay unless they differ from the tables (rewriting them walks the whole file).
    unchanged: bool,
    sweep: Option<(usize, Instant)>,
}

impl ResultsWriter {
    /// Notes that a sweep on `jobs` worker threads started at `started`: [`Self::finish`] stores both
    /// (see [`layout::SWEEP_JOBS`]).
    pub fn note_sweep(&mut self, jobs: usize, started: Instant) {
        self.sweep = Some((jobs, started));
    }

    /// Creates a new file with the header (written under a temporary name and renamed, so a crash
    /// never leaves a half-written file at `path`).
    pub fn create(path: &Path, header: &FileHeader, output: OutputOptions) -> Result<Self, OutputError> {
        let mut builder = FileBuilder::new();
        for (name, value) in header.to_attrs() {
            builder.set_attr(name, value);
        }
        let partial = path.with_extension("h5.partial");
        super::guard::refuse_symlink(&partial)
            .map_err(|e| OutputError::at(&partial, OutputReason::Refused(e.refusal)))?;
        super::guard::refuse_symlink(path).map_err(|e| OutputError::at(path, OutputReason::Refused(e.refusal)))?;
        builder.write(&partial).map_err(|e| hdf5_error(&partial, e))?;
        std::fs::rename(&partial, path).map_err(|e| OutputError::io(path, e))?;
        Self::open(path, output).map(|(writer, _)| writer)
    }

    /// Opens an existing results file to add runs; returns its header too.
    pub fn open(path: &Path, output: OutputOptions) -> Result<(Self, FileHeader), OutputError> {
        let file = File::open_rw(path).map_err(|e| hdf5_error(path, e))?;
        let header = reader::header(&file, path)?;
        let runs = reader::committed_runs(&file, path)?;
        let root = file.root().groups().map_err(|e| hdf5_error(path, e))?;
        let next_batch = root.iter().filter_map(|name| layout::batch_number(name)).max().map_or(0, |k| k + 1);
        let made_by = runs
            .rows
            .iter()
            .filter(|r| r.made_by != DEMSWEEP_VERSION)
            .map(|r| (r.group_name().to_string(), r.made_by.clone()))
            .collect();
        let writer = Self {
            file,
            path: path.to_path_buf(),
            output,
            next_batch,
            batch: None,
            groups: runs.groups,
            made_by,
            created_by: header.demsweep_version.clone(),
            existing: runs.rows,
            damaged: runs.damaged,
            pending: 0,
            unchanged: true,
            sweep: None,
        };
        Ok((writer, header))
    }

    /// Whether the file's runs carry identities (files written before them are matched to a study
    /// by its fingerprint and run index).
    pub fn has_identities(&self) -> bool {
        self.existing.iter().all(|row| !row.identity.is_empty())
    }

    /// The results file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The demsweep version that made the stored run of `row`: recorded on the run (results format
    /// 3), else the version that created the file (the best guess for older formats).
    pub fn made_by<'a>(&'a self, row: &'a SummaryRow) -> &'a str {
        if row.made_by.is_empty() { &self.created_by } else { &row.made_by }
    }

    /// Rows of the runs the file held when it was opened (sorted by index), which the writer
    /// hands over: it keeps no rows (the runner, above it, keeps those of the sweep's statistics).
    pub fn take_existing(&mut self) -> Vec<SummaryRow> {
        std::mem::take(&mut self.existing)
    }

    /// Deletes the committed runs that failed with an error (in one commit), so that they can run
    /// again; returns how many there were.
    pub fn forget_failed(&mut self) -> Result<usize, OutputError> {
        let (failed, kept): (Vec<SummaryRow>, Vec<SummaryRow>) =
            std::mem::take(&mut self.existing).into_iter().partition(|row| !row.is_finished());
        self.existing = kept;
        for row in &failed {
            if let Some(group) = self.groups.remove(row.group_name()) {
                self.delete_run(&group)?;
            }
        }
        if !failed.is_empty() {
            self.unchanged = false;
            self.file.commit().map_err(|e| hdf5_error(&self.path, e))?;
        }
        Ok(failed.len())
    }

    /// Deletes the committed run groups called `names` (in one commit), e.g. runs that lack an output
    /// now asked for, so that they run again.
    pub fn forget(&mut self, names: &[String]) -> Result<(), OutputError> {
        for name in names {
            if let Some(group) = self.groups.remove(name) {
                self.delete_run(&group)?;
            }
        }
        if !names.is_empty() {
            self.unchanged = false;
            self.file.commit().map_err(|e| hdf5_error(&self.path, e))?;
        }
        Ok(())
    }

    /// Deletes the run groups that cannot be read (in one commit), so that their runs run again;
    /// returns them. A batch holding a damaged run group cannot be rebuilt without it (hdf5-pure
    /// must read every header to rebuild a group), so its readable runs are copied to a new batch and
    /// the damaged batch deleted whole; a batch whose index is damaged loses all its runs.
    pub fn forget_damaged(&mut self) -> Result<Vec<DamagedGroup>, OutputError> {
        let damaged = std::mem::take(&mut self.damaged);
        let mut batches: Vec<&str> =
            damaged.iter().map(|d| d.group.trim_start_matches('/').split('/').next().unwrap_or_default()).collect();
        batches.sort_unstable();
        batches.dedup();
        for batch in batches {
            let prefix = format!("{batch}/");
            let kept: Vec<String> =
                self.groups.keys().filter(|id| self.groups[*id].starts_with(&prefix)).cloned().collect();
            for id in kept {
                let to = format!("{}/{id}", self.stage_batch()?);
                self.file.copy(&self.groups[&id], &to).map_err(|e| hdf5_error(&self.path, e))?;
                self.groups.insert(id, to);
            }
            self.file.root().delete(batch).map_err(|e| hdf5_error(&self.path, e))?;
        }
        if !damaged.is_empty() {
            self.unchanged = false;
            self.file.commit().map_err(|e| hdf5_error(&self.path, e))?;
            self.end_batch();
        }
        Ok(damaged)
    }

    /// Stages the deletion of the run group at `group` (its path from the root).
    fn delete_run(&self, group: &str) -> Result<(), OutputError> {
        let (parent, name) = group.rsplit_once('/').unwrap_or(("", group));
        self.file.group(parent).and_then(|g| g.delete(name)).map_err(|e| hdf5_error(&self.path, e))
    }

    /// Whether the file holds a run group called `name` with every output `output` asks for
    /// (frames only when `frames` says the run records some).
    pub fn holds(&self, name: &str, output: &OutputOptions, frames: bool) -> bool {
        let Some(group) = self.groups.get(name).and_then(|path| self.file.group(path).ok()) else { return false };
        let (Ok(datasets), Ok(groups)) = (group.datasets(), group.groups()) else { return false };
        let has = |list: &[String], name: &str| list.iter().any(|n| n == name);
        (!output.histories || has(&datasets, "history"))
            && (!output.final_states || has(&datasets, layout::FINAL))
            && (!(output.frames && frames) || has(&groups, layout::FRAMES))
    }

    /// Replaces the file's header (the study it now holds), in one commit.
    pub fn set_header(&mut self, header: &FileHeader) -> Result<(), OutputError> {
        let root = self.file.root();
        for (name, value) in header.to_attrs() {
            root.set_attr(name, value).map_err(|e| hdf5_error(&self.path, e))?;
        }
        self.unchanged = false;
        self.file.commit().map_err(|e| hdf5_error(&self.path, e))
    }

    /// Number of runs staged and not yet committed.
    pub fn pending(&self) -> usize {
        self.pending
    }

    /// Stages one run (its group, attributes and the outputs the study asks for).
    pub fn stage(&mut self, run: &RunResult) -> Result<(), OutputError> {
        let group = format!("{}/{}", self.stage_batch()?, run.row.group_name());
        self.groups.insert(run.row.group_name().to_string(), group.clone());
        self.made_by.remove(run.row.group_name());
        let root = self.file.root();
        let attrs = run_attrs::run_attrs(&run.row, &run.scene);
        let output = &self.output;
        root.create_group_with(&group, |g| {
            for (name, value) in attrs {
                g.set_attr(name, value);
            }
            run_attrs::stage_tables(g, &run.row);
            if let Some(record) = &run.record {
                stage_record(g, record, output);
                if output.histories {
                    stage_stress_profile(g, record, &run.scene);
                }
            }
        })
        .map_err(|e| hdf5_error(&self.path, e))?;
        self.pending += 1;
        self.unchanged = false;
        Ok(())
    }

    /// Stages a copy of the committed run group `group` of another results file under the name
    /// `name` (for merging), read from `source` run by run (open it streaming: only this run is
    /// held), made by demsweep `made_by` (empty: not recorded); returns the bytes of dataset data
    /// staged.
    pub fn stage_copy(
        &mut self,
        source: (&File, &Path),
        group: &str,
        (name, made_by): (&str, &str),
    ) -> Result<usize, OutputError> {
        let (source, source_path) = source;
        let copy = source.group(group).map_err(LayoutError::from).and_then(|group| GroupCopy::read(&group)).map_err(
            |reason| OutputError::at(source_path, OutputReason::BadCopy { group: group.to_string(), reason }),
        )?;
        let bytes = copy.data_bytes();
        let path = format!("{}/{name}", self.stage_batch()?);
        self.file.root().create_group_with(&path, |g| copy.stage(g)).map_err(|e| hdf5_error(&self.path, e))?;
        self.groups.insert(name.to_string(), path);
        if made_by != DEMSWEEP_VERSION {
            self.made_by.insert(name.to_string(), made_by.to_string());
        }
        self.pending += 1;
        self.unchanged = false;
        Ok(bytes)
    }

    /// The batch group of the commit being staged: a new group under the root, staged with its
    /// first run.
    fn stage_batch(&mut self) -> Result<String, OutputError> {
        if let Some(batch) = &self.batch {
            return Ok(batch.clone());
        }
        let batch = layout::batch_name(self.next_batch);
        self.file.root().create_group(&batch).map_err(|e| hdf5_error(&self.path, e))?;
        self.batch = Some(batch.clone());
        Ok(batch)
    }

    /// Commits the staged runs.
    pub fn commit(&mut self) -> Result<(), OutputError> {
        if self.pending == 0 {
            return Ok(());
        }
        self.file.commit().map_err(|e| hdf5_error(&self.path, e))?;
        self.pending = 0;
        self.end_batch();
        Ok(())
    }

    /// After a commit: the next run staged starts a new batch.
    fn end_batch(&mut self) {
        if self.batch.take().is_some() {
            self.next_batch += 1;
        }
    }

    /// Commits what is staged, rewrites `/summary` and `/points` from `tables`, and closes the file
    /// (as a sink's [`ResultSink::finish`] does); nothing is written through it afterwards.
    pub fn close(&mut self, tables: &Tables) -> Result<(), OutputError> {
        self.commit()?;
        let err = |e| hdf5_error(&self.path, e);
        let stored = AttrValue::I64(self.groups.len() as i64);
        let sweep: Vec<(&str, AttrValue)> = std::iter::once((layout::STORED_RUNS, stored))
            .chain(self.sweep.iter().flat_map(|(jobs, started)| {
                [
                    (SWEEP_JOBS, AttrValue::I64(*jobs as i64)),
                    (SWEEP_WALL_TIME, AttrValue::F64(started.elapsed().as_secs_f64())),
                ]
            }))
            .collect();
        let stored = |name| reader::stored_table(&self.file, &self.path, name);
        let kept = self.unchanged
            && stored(SUMMARY)?.as_ref() == Some(&tables.summary)
            && stored(POINTS)?.as_ref() == Some(&tables.points);
        if !kept {
            // Separate commits, so that the staged copy of one is gone before the other is staged; the
            // old `/points` goes first (until the new one is complete, readers compute points from
            // `/summary`).
            if self.file.root().groups().map_err(err)?.iter().any(|g| g == POINTS) {
                self.file.root().delete(POINTS).map_err(err)?;
            }
            let index = self.run_index(&tables.summary);
            write_columns(&self.file, SUMMARY, (&tables.summary, &index), &sweep).map_err(err)?;
            drop(index);
            write_columns(&self.file, POINTS, (&tables.points, &[]), &[]).map_err(err)?;
        }
        self.file.clone().close().map_err(err)
    }
}

impl ResultsWriter {
    /// `/summary`'s datasets beside its columns, one value per row of `summary`: the path of the
    /// run's group ([`layout::RUN_GROUP`]) and the version that made it ([`layout::RUN_MADE_BY`]).
    fn run_index(&self, summary: &SummaryTable) -> Vec<Column> {
        let column = |name: &str| summary.column(name).map(|c| &c.data);
        let (ids, identities) = (column("run_id"), column(super::table::IDENTITY));
        let names: Vec<String> = (0..summary.len())
            .map(|i| {
                let identity = identities.map(|c| c.text(i)).unwrap_or_default();
                if identity.is_empty() { ids.map(|c| c.text(i)).unwrap_or_default() } else { identity }
            })
            .collect();
        let paths = names.iter().map(|n| self.groups.get(n).cloned().unwrap_or_default());
        let made_by = names.iter().map(|n| self.made_by.get(n).map_or(DEMSWEEP_VERSION, String::as_str).to_string());
        vec![
            Column { name: layout::RUN_GROUP.into(), data: ColumnData::Text(paths.collect()) },
            Column { name: layout::RUN_MADE_BY.into(), data: ColumnData::Text(made_by.collect()) },
        ]
    }
}

/// The results file as a sink: runs become run groups (committed in place), the tables `/summary`
/// and `/points`.
impl ResultSink for ResultsWriter {
    type Error = OutputError;

    fn accept(&mut self, run: &RunResult) -> Result<(), OutputError> {
        self.stage(run)
    }

    fn commit(&mut self) -> Result<(), OutputError> {
        ResultsWriter::commit(self)
    }

    fn finish(&mut self, tables: &Tables) -> Result<(), OutputError> {
        self.close(tables)
    }
}

/// Data (bytes) of a table's columns staged per commit by [`write_columns`].
const TABLE_BYTES_PER_COMMIT: usize = 100 << 20;

/// Replaces the group `name` (`/summary`, `/points`) with one dataset per column of `table` and then
/// of `beside` (the file's own columns, which readers leave out of the table), listed in order by its
/// attribute `columns`, and the attributes `attrs`. Each dataset is chunked with a checksum.
///
/// Written in commits of at most [`TABLE_BYTES_PER_COMMIT`] of data: a sweep with one grid point per
/// run has a points table of 170 MB at 100 000 runs, which staged whole would be held twice. The first
/// commit replaces the group, each later one adds to it (rebuilding a group below the root walks the
/// whole file, about 2 s at 100 000 runs, once per part at the end of a sweep), and the last adds
/// `columns` and `attrs`: a group without `columns` reads as absent (see
/// [`reader::stored_table`]), so a file killed between them reads as one without the table.
fn write_columns(
    file: &File,
    name: &str,
    columns: (&SummaryTable, &[Column]),
    attrs: &[(&str, AttrValue)],
) -> Result<(), hdf5_pure::Error> {
    write_columns_in_parts(file, name, columns, attrs, TABLE_BYTES_PER_COMMIT)
}

/// [`write_columns`] in commits of at most `bytes_per_commit` of data.
fn write_columns_in_parts(
    file: &File,
    name: &str,
    (table, beside): (&SummaryTable, &[Column]),
    attrs: &[(&str, AttrValue)],
    bytes_per_commit: usize,
) -> Result<(), hdf5_pure::Error> {
    let root = file.root();
    if root.groups()?.iter().any(|g| g == name) {
        root.delete(name)?;
    }
    let columns: Vec<&Column> = table.columns.iter().chain(beside).collect();
    let parts = parts(&columns, bytes_per_commit);
    let mut failure = None;
    for (k, part) in parts.iter().enumerate() {
        let last = k + 1 == parts.len();
        let mut described: Vec<(&str, AttrValue)> = Vec::new();
        if last {
            let names = columns.iter().map(|c| c.name.clone()).collect();
            described.push((SUMMARY_COLUMNS, AttrValue::StringArray(names)));
            described.extend(attrs.iter().cloned());
        }
        if k == 0 {
            root.create_group_with(name, |g| {
                for (key, value) in described {
                    g.set_attr(key, value);
                }
                for column in *part {
                    g.create_dataset(&column.name, |b| stage_column(b, column, &mut failure));
                }
            })?;
        } else {
            let group = file.group(name)?;
            for column in *part {
                group.create_dataset(&column.name, |b| stage_column(b, column, &mut failure))?;
            }
            for (key, value) in described {
                group.set_attr(key, value)?;
            }
        }
        if let Some(e) = failure.take() {
            return Err(e.into());
        }
        file.commit()?;
    }
    Ok(())
}

/// The columns in consecutive parts of at most `bytes` of data each (a larger column alone); one
/// empty part for no columns.
fn parts<'a>(columns: &'a [&'a Column], bytes: usize) -> Vec<&'a [&'a Column]> {
    let mut parts = Vec::new();
    let (mut start, mut size) = (0, 0);
    for (k, column) in columns.iter().enumerate() {
        let data = column.data.data_bytes();
        if k > start && size + data > bytes {
            parts.push(&columns[start..k]);
            (start, size) = (k, 0);
        }
        size += data;
    }
    parts.push(&columns[start..]);
    parts
}

/// Stages a column's dataset with its `unit` and `description` (a failure to encode it in `failure`).
fn stage_column(b: &mut DatasetBuilder, column: &Column, failure: &mut Option<hdf5_pure::FormatError>) {
    if let Err(e) = column_data(b, &column.data) {
        *failure = Some(e);
    }
    for (key, value) in layout::column_attrs(&column.name) {
        b.set_attr(key, value);
    }
}

fn column_data(b: &mut DatasetBuilder, data: &ColumnData) -> Result<(), hdf5_pure::FormatError> {
    match data {
        ColumnData::Float(v) => drop(b.with_f64_data(v)),
        ColumnData::Int(v) => drop(b.with_i64_data(v)),
        ColumnData::Bool(v) => drop(b.with_u8_data(&v.iter().map(|&x| u8::from(x)).collect::<Vec<_>>())),
        ColumnData::Text(v) => drop(b.with_strings(&v.iter().map(String::as_str).collect::<Vec<_>>())?),
    }
    compound::checksummed(b, &[data.len() as u64]);
    Ok(())
}

fn stage_record(g: &mut StagedGroup<'_>, record: &RunRecord, output: &OutputOptions) {
    if output.histories {
        g.create_dataset("history", |b| {
            compound::stage(b, &layout::history_table(&record.history));
            b.set_attr(layout::UNITS, layout::history_units());
        });
    }
    if output.final_states {
        stage_snapshot(g, layout::FINAL, &record.final_state);
        stage_contacts(g, layout::FINAL_CONTACTS, &record.final_state);
    }
    if output.frames && !record.frames.is_empty() {
        g.create_group_with(layout::FRAMES, |g| stage_frames(g, &record.frames));
    }
}

/// The stress profile of the run's final state (see [`layout::STRESS_PROFILE`]).
fn stage_stress_profile(g: &mut StagedGroup<'_>, record: &RunRecord, scene: &SceneConfig) {
    let profile = StressProfile::of_state(&record.final_state, scene.domain.width, scene.particles.thickness);
    let columns = layout::stress_profile_columns(&profile);
    let fields: Vec<(&str, Field<'_>)> = columns.iter().map(|(name, _, v)| (*name, Field::F64(v))).collect();
    let units = columns.iter().map(|(_, unit, _)| unit.to_string()).collect();
    g.create_dataset(layout::STRESS_PROFILE, |b| {
        compound::stage(b, &fields);
        b.set_attr(layout::UNITS, AttrValue::StringArray(units));
    });
}

/// The frames as arrays over time: `time` (T), one (T, N) array per disk property, and the contacts
/// of every frame in one table (see [`layout`]).
fn stage_frames(g: &mut StagedGroup<'_>, frames: &[Snapshot]) {
    let times: Vec<f64> = frames.iter().map(|s| s.time).collect();
    g.create_dataset(layout::FRAME_TIME, |b| {
        b.with_f64_data(&times);
        compound::checksummed(b, &[times.len() as u64]);
        b.set_attr(layout::UNIT, AttrValue::String("s".into()));
    });
    let disks = frames[0].x.len() as u64;
    for field in &DISK_FIELDS {
        let values: Vec<f64> = frames.iter().flat_map(|s| (field.values)(s).iter().copied()).collect();
        g.create_dataset(field.name, |b| {
            b.with_f64_data(&values).with_shape(&[frames.len() as u64, disks]);
            compound::checksummed(b, &[frames.len() as u64, disks]);
            b.set_attr(layout::UNIT, AttrValue::String(field.unit.into()));
        });
    }
    let (frame, contacts) = layout::frame_contacts(frames);
    g.create_dataset(layout::FRAME_CONTACT_TABLE, |b| {
        let mut fields = vec![(layout::FRAME_INDEX, Field::U32(&frame))];
        fields.extend(layout::contact_table(&contacts));
        compound::stage(b, &fields);
        b.set_attr(layout::UNITS, layout::contact_units(1));
    });
}

/// A snapshot as a state table with attributes `time` and `units`.
fn stage_snapshot(g: &mut StagedGroup<'_>, name: &str, s: &Snapshot) {
    g.create_dataset(name, |b| {
        compound::stage(b, &layout::state_table(s));
        b.set_attr("time", hdf5_pure::AttrValue::F64(s.time));
        b.set_attr(layout::UNITS, layout::state_units());
    });
}

/// A snapshot's contact network as a contact table with attributes `time` and `units`.
fn stage_contacts(g: &mut StagedGroup<'_>, name: &str, s: &Snapshot) {
    g.create_dataset(name, |b| {
        compound::stage(b, &layout::contact_table(&s.contacts));
        b.set_attr("time", hdf5_pure::AttrValue::F64(s.time));
        b.set_attr(layout::UNITS, layout::contact_units(0));
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn column(name: &str, values: usize) -> Column {
        Column { name: name.into(), data: ColumnData::Float((0..values).map(|i| i as f64).collect()) }
    }

    #[test]
    fn columns_split_into_parts_of_at_most_so_many_bytes_a_larger_one_alone() {
        let (a, b, c, d) = (column("a", 3), column("b", 3), column("c", 10), column("d", 1));
        let columns = [&a, &b, &c, &d];
        let names = |parts: Vec<&[&Column]>| -> Vec<Vec<String>> {
            parts.iter().map(|p| p.iter().map(|c| c.name.clone()).collect()).collect()
        };
        assert_eq!(names(parts(&columns, 48)), [vec!["a", "b"], vec!["c"], vec!["d"]]);
        assert_eq!(names(parts(&columns, 1000)), [vec!["a", "b", "c", "d"]]);
        assert_eq!(names(parts(&[], 48)), [Vec::<String>::new()]);
    }

    #[test]
    fn a_table_written_in_several_commits_reads_back_whole_and_not_before_its_last() {
        let path = std::env::temp_dir().join(format!("demsweep-parts-{}.h5", std::process::id()));
        FileBuilder::new().write(&path).unwrap();
        let table = SummaryTable { columns: vec![column("a", 5), column("b", 5), column("c", 5)] };
        let file = File::open_rw(&path).unwrap();
        let attrs = [(SWEEP_JOBS, AttrValue::I64(2))];
        write_columns_in_parts(&file, POINTS, (&table, &[]), &attrs, 40).unwrap();
        file.close().unwrap();
        let file = File::open(&path).unwrap();
        assert_eq!(reader::stored_table(&file, &path, POINTS).unwrap(), Some(table.clone()));
        assert_eq!(file.group(POINTS).unwrap().attrs().unwrap()[SWEEP_JOBS].as_i64(), Some(2));
        drop(file);
        // Cut short after its first part (a kill): no `columns` yet, so the table reads as absent.
        let file = File::open_rw(&path).unwrap();
        write_columns_in_parts(&file, POINTS, (&SummaryTable { columns: vec![column("a", 5)] }, &[]), &[], 40).unwrap();
        file.group(POINTS).unwrap().remove_attr(SUMMARY_COLUMNS).unwrap();
        file.commit().unwrap();
        file.close().unwrap();
        let file = File::open(&path).unwrap();
        assert_eq!(reader::stored_table(&file, &path, POINTS).unwrap(), None);
        std::fs::remove_file(&path).unwrap();
    }
}
