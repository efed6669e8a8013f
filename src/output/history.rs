//! One run's histories, or its stress profile, as CSV (for `demsweep history`): on a stream, or as a
//! CSV file with its metadata sidecar (each column's unit and datatype).

use std::io::Write;
use std::path::Path;

use super::csv::{ColumnMeta, Datatype};
use super::guard::Existing;
use super::{OutputError, OutputReason, compound, csv, layout, reader};

/// A table of one run that `demsweep history` writes as CSV.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunTable {
    /// The sampled histories (`history`): one column per series, one line per sample.
    History,
    /// The settled pile's stress profile (`stress_profile`, see `layout::stress_profile_columns`):
    /// one line per height band.
    StressProfile,
}

impl RunTable {
    /// The table's dataset in the run's group.
    fn dataset(self) -> &'static str {
        match self {
            RunTable::History => "history",
            RunTable::StressProfile => layout::STRESS_PROFILE,
        }
    }

    /// Why run `run_id` has no such table to write.
    fn missing(self, run_id: &str) -> OutputReason {
        match self {
            RunTable::History => OutputReason::NoHistories(run_id.to_string()),
            RunTable::StressProfile => OutputReason::NoStressProfile(run_id.to_string()),
        }
    }
}

/// Writes the histories of run `run_id` of a results file as CSV: one column per series (the fields
/// of the run's `history` table, headed by their bare names; the units are the results file's), one
/// line per sample.
pub fn to_csv<W: Write>(path: &Path, run_id: &str, out: &mut W) -> Result<(), OutputError> {
    table_to_csv(path, run_id, RunTable::History, out)
}

/// Writes the stress profile of run `run_id` (its `stress_profile` table: one line per height band,
/// see `layout::stress_profile_columns`) as CSV, as [`to_csv`] writes the histories.
pub fn stress_profile_to_csv<W: Write>(path: &Path, run_id: &str, out: &mut W) -> Result<(), OutputError> {
    table_to_csv(path, run_id, RunTable::StressProfile, out)
}

/// Writes the table `table` of run `run_id` as the CSV file `csv`, whole or not at all, with its
/// metadata sidecar (each column's unit, as the results file stores it, datatype and meaning where
/// demsweep declares one); files there are replaced as `existing` allows.
pub fn write_csv_file(
    path: &Path,
    run_id: &str,
    table: RunTable,
    (csv, existing): (&Path, Existing),
) -> Result<(), OutputError> {
    let read = read_table(path, run_id, table)?;
    let columns: Vec<ColumnMeta> = (read.names.iter().enumerate())
        .map(|(k, name)| {
            let declared = ColumnMeta::declared(name, Datatype::of_cells(read.rows.iter().map(|row| row[k].as_str())));
            match &read.units {
                Some(units) => ColumnMeta { unit: units[k].clone(), ..declared },
                None => declared,
            }
        })
        .collect();
    csv::write_file(csv, &columns, existing, |out| write_rows(out, &read))
        .map_err(|e| OutputError::refused(&e.path.clone(), e))
}

/// Writes the table `table` of run `run_id` as CSV, headed by its field names.
fn table_to_csv<W: Write>(path: &Path, run_id: &str, table: RunTable, out: &mut W) -> Result<(), OutputError> {
    let read = read_table(path, run_id, table)?;
    write_rows(out, &read).map_err(|e| OutputError::io(Path::new("<output>"), e))
}

/// A run's table as CSV cells: its field names, their units as the file stores them (`None` when it
/// stores none: those demsweep declares for the names are used) and one row of cells per line.
struct CsvTable {
    names: Vec<String>,
    units: Option<Vec<String>>,
    rows: Vec<Vec<String>>,
}

/// Reads the table `table` of run `run_id` as cells.
fn read_table(path: &Path, run_id: &str, table: RunTable) -> Result<CsvTable, OutputError> {
    let file = reader::open(path)?;
    let run = reader::find_run(&file, path, run_id)?;
    let name = format!("{run}/{}", table.dataset());
    let dataset = file.dataset(&name).map_err(|_| OutputError::at(path, table.missing(run_id)))?;
    let columns = compound::decode(&dataset, compound::read_limit(path))
        .map_err(|e| reader::damaged_data(path, run_id, &name, e))?;
    let stored =
        dataset.attrs().ok().and_then(|a| a.get(layout::UNITS).and_then(|u| u.as_strings()).map(<[String]>::to_vec));
    let units = stored.filter(|u| u.len() == columns.len());
    let rows = (0..columns.first().map_or(0, |(_, c)| c.len()))
        .map(|i| columns.iter().map(|(_, c)| c.text(i)).collect())
        .collect();
    Ok(CsvTable { names: columns.into_iter().map(|(n, _)| n).collect(), units, rows })
}

/// Writes a table's names line, then its rows.
fn write_rows(out: &mut (impl Write + ?Sized), table: &CsvTable) -> std::io::Result<()> {
    csv::write_record(out, &table.names)?;
    table.rows.iter().try_for_each(|row| csv::write_record(out, row))
}
