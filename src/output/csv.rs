//! RFC 4180 CSV: comma separated, CRLF line ends, fields quoted when they contain `"`, `,` or a line break.
//!
//! Every CSV file demsweep writes starts with two header lines: the columns' names (the names the
//! HDF5 files and the Python module use), then their SI units (an empty cell for a dimensionless or
//! text column); the values follow. `pandas.read_csv(path, skiprows=[1])` reads the names alone,
//! `header=[0, 1]` both lines.

use std::io::{self, Write};

use super::table::SummaryTable;
use crate::physics::quantity;

/// Quotes a field when RFC 4180 requires it.
pub fn field(text: &str) -> String {
    if text.contains(['"', ',', '\n', '\r']) { format!("\"{}\"", text.replace('"', "\"\"")) } else { text.to_string() }
}

/// Writes one record (a line) of fields.
pub fn write_record<W: Write + ?Sized, S: AsRef<str>>(out: &mut W, fields: &[S]) -> io::Result<()> {
    let line: Vec<String> = fields.iter().map(|f| field(f.as_ref())).collect();
    write!(out, "{}\r\n", line.join(","))
}

/// Writes the two header lines: `names`, then `units` (one per name, empty where none).
pub fn write_header<W: Write + ?Sized, N: AsRef<str>, U: AsRef<str>>(
    out: &mut W,
    names: &[N],
    units: &[U],
) -> io::Result<()> {
    write_record(out, names)?;
    write_record(out, units)
}

/// Writes the header lines of columns named `names`, each with its [`quantity::unit`].
pub fn write_named_header<W: Write, N: AsRef<str>>(out: &mut W, names: &[N]) -> io::Result<()> {
    let units: Vec<&str> = names.iter().map(|n| quantity::unit(n.as_ref()).unwrap_or("")).collect();
    write_header(out, names, &units)
}

/// Writes the table: its header lines (see [`write_named_header`]), then its rows; missing values are empty cells.
pub fn write_table<W: Write>(out: &mut W, table: &SummaryTable) -> io::Result<()> {
    let names: Vec<&str> = table.columns.iter().map(|c| c.name.as_str()).collect();
    write_named_header(out, &names)?;
    for i in 0..table.len() {
        let cells: Vec<String> = table.columns.iter().map(|c| c.data.text(i)).collect();
        write_record(out, &cells)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_header_is_the_names_then_their_units() {
        let mut out = Vec::new();
        write_named_header(&mut out, &["run_id", "material.youngs_modulus", "settle_time", "packing_fraction"])
            .unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(text, "run_id,material.youngs_modulus,settle_time,packing_fraction\r\n,Pa,s,\r\n");
    }
}
