//! The summary of a results file: read it, print it aligned, export it as CSV.

use std::io::Write;
use std::path::Path;

use super::guard::Existing;
use super::table::SummaryTable;
use super::{OutputError, csv, reader};
use crate::physics::quantity;

/// Reads the summary of a results file (see [`reader::summary`]).
pub fn read(path: &Path) -> Result<SummaryTable, OutputError> {
    let file = reader::open(path)?;
    reader::summary(&file, path)
}

/// Writes a table (the summary or the points) as a CSV file (the names line, RFC 4180 quoting,
/// missing values empty), whole or not at all, and its metadata sidecar (units, datatypes:
/// `csv::write_file`); existing files are replaced as `existing` allows.
pub fn write_csv(path: &Path, table: &SummaryTable, existing: Existing) -> Result<(), OutputError> {
    csv::write_file(path, &csv::table_columns(table), existing, |mut out| csv::write_table(&mut out, table))
        .map_err(|e| OutputError::refused(&e.path.clone(), e))
}

/// Writes the summary as an aligned text table (headed by labels, [`quantity::label`], columns separated by two spaces, floats to 6
/// significant digits; the CSV has them exactly).
pub fn print_aligned<W: Write>(out: &mut W, table: &SummaryTable) -> std::io::Result<()> {
    let cells: Vec<Vec<String>> = table
        .columns
        .iter()
        .map(|c| std::iter::once(quantity::label(&c.name)).chain((0..table.len()).map(|i| c.data.display(i))).collect())
        .collect();
    let widths: Vec<usize> = cells.iter().map(|col| col.iter().map(|s| s.chars().count()).max().unwrap_or(0)).collect();
    for line in 0..=table.len() {
        let fields: Vec<String> = cells.iter().zip(&widths).map(|(col, w)| format!("{:<w$}", col[line])).collect();
        writeln!(out, "{}", fields.join("  ").trim_end())?;
    }
    Ok(())
}
