//! RFC 4180 CSV: comma separated, CRLF line ends, fields quoted when they contain `"`, `,` or a line break.

use std::io::{self, Write};

use super::table::SummaryTable;
use crate::physics::quantity;

/// Quotes a field when RFC 4180 requires it.
pub fn field(text: &str) -> String {
    if text.contains(['"', ',', '\n', '\r']) { format!("\"{}\"", text.replace('"', "\"\"")) } else { text.to_string() }
}

/// Writes one record (a line) of fields.
pub fn write_record<W: Write, S: AsRef<str>>(out: &mut W, fields: &[S]) -> io::Result<()> {
    let line: Vec<String> = fields.iter().map(|f| field(f.as_ref())).collect();
    write!(out, "{}\r\n", line.join(","))
}

/// Writes the table with a header line (names with their units, see [`quantity::with_unit`]);
/// missing values are empty cells.
pub fn write_table<W: Write>(out: &mut W, table: &SummaryTable) -> io::Result<()> {
    let header: Vec<String> = table.columns.iter().map(|c| quantity::with_unit(&c.name)).collect();
    write_record(out, &header)?;
    for i in 0..table.len() {
        let cells: Vec<String> = table.columns.iter().map(|c| c.data.text(i)).collect();
        write_record(out, &cells)?;
    }
    Ok(())
}
