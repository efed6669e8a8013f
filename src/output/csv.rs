//! RFC 4180 CSV: comma separated, CRLF line ends, fields quoted when they contain `"`, `,` or a line break.
//!
//! Every CSV file demsweep writes has one header line, the columns' bare names (the names the HDF5
//! files and the Python module use), then the values: `pandas.read_csv(path)` and a spreadsheet read
//! numbers as numbers. What each column is — its unit, datatype and meaning — is in a sidecar beside
//! the file, `<file>.csv-metadata.json`, in the W3C "CSV on the Web" metadata vocabulary (CSVW: the
//! file name a CSVW processor looks for first; columns' `titles`, `datatype`, `dc:description`, and
//! the unit as schema.org's `schema:unitText`, a property of CSVW's default context). The sidecar
//! also records the file's size and CRC-32 (`demsweep:content`), which bind the two: a file edited or
//! replaced since is no longer demsweep's ([`super::guard::made_by_demsweep`]).

use std::io::{self, Write};
use std::path::Path;

pub use super::guard::metadata_path;
use super::guard::{self, CONTENT_KEY, Content, Existing, GuardError, Refusal};
use super::table::{ColumnData, SummaryTable};
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

/// A column's values as CSVW names their XML Schema datatype.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Datatype {
    /// Whole numbers.
    Integer,
    /// Real numbers (`NaN`, `INF` included).
    Double,
    /// `true` or `false`.
    Boolean,
    /// Text.
    String,
}

impl Datatype {
    /// The CSVW name (`integer`, `double`, `boolean`, `string`).
    pub fn name(self) -> &'static str {
        match self {
            Datatype::Integer => "integer",
            Datatype::Double => "double",
            Datatype::Boolean => "boolean",
            Datatype::String => "string",
        }
    }

    /// The narrowest datatype every non-empty cell reads as (an empty cell is a missing value);
    /// text when every cell is empty.
    pub fn of_cells<'a>(cells: impl IntoIterator<Item = &'a str>) -> Datatype {
        let mut present = cells.into_iter().filter(|c| !c.is_empty()).peekable();
        if present.peek().is_none() {
            return Datatype::String;
        }
        let fits = |cell: &str, kind: Datatype| match kind {
            Datatype::Integer => cell.parse::<i64>().is_ok(),
            Datatype::Double => cell.parse::<f64>().is_ok(),
            Datatype::Boolean => cell == "true" || cell == "false",
            Datatype::String => true,
        };
        let mut candidates = vec![Datatype::Integer, Datatype::Double, Datatype::Boolean, Datatype::String];
        for cell in present {
            candidates.retain(|&kind| fits(cell, kind));
        }
        candidates[0]
    }

    /// The datatype of a table column.
    fn of_column(data: &ColumnData) -> Datatype {
        match data {
            ColumnData::Float(_) => Datatype::Double,
            ColumnData::Int(_) => Datatype::Integer,
            ColumnData::Bool(_) => Datatype::Boolean,
            ColumnData::Text(_) => Datatype::String,
        }
    }
}

/// What the sidecar says about a column.
#[derive(Clone, Debug, PartialEq)]
pub struct ColumnMeta {
    /// The bare name, as in the header line.
    pub name: String,
    /// SI unit symbol; empty when dimensionless or not a quantity.
    pub unit: String,
    /// Its values' datatype.
    pub datatype: Datatype,
    /// What it is; empty when nothing declares it.
    pub description: String,
}

impl ColumnMeta {
    /// A column named `name` whose unit and description are the ones demsweep declares for that name
    /// ([`quantity::unit`], [`quantity::description`]).
    pub fn declared(name: &str, datatype: Datatype) -> Self {
        let unit = quantity::unit(name).unwrap_or("").to_string();
        let description = quantity::description(name).unwrap_or("").to_string();
        ColumnMeta { name: name.to_string(), unit, datatype, description }
    }

    /// Declared columns named `names`, each one's datatype read from its cells in `rows`.
    pub fn declared_from_rows<N: AsRef<str>, S: AsRef<str>>(names: &[N], rows: &[Vec<S>]) -> Vec<Self> {
        let datatype = |k: usize| Datatype::of_cells(rows.iter().filter_map(|row| row.get(k)).map(AsRef::as_ref));
        names.iter().enumerate().map(|(k, name)| Self::declared(name.as_ref(), datatype(k))).collect()
    }
}

/// A CSVW column name: the bare name with every character a URI template variable name cannot hold
/// (other than letters, digits, `_` and inner `.`) percent-encoded.
fn csvw_name(name: &str) -> String {
    let mut encoded = String::new();
    for (k, c) in name.char_indices() {
        let inner_dot = c == '.' && k > 0 && k + 1 < name.len() && !name[k + 1..].starts_with('.');
        if c.is_ascii_alphanumeric() || (c == '_' && k > 0) || inner_dot {
            encoded.push(c);
        } else {
            let mut bytes = [0; 4];
            c.encode_utf8(&mut bytes).bytes().for_each(|b| encoded.push_str(&format!("%{b:02X}")));
        }
    }
    encoded
}

/// The CSVW metadata of the table in the file `url` (a name relative to the sidecar) whose columns
/// are `columns` and whose bytes have `content`: one header line, CRLF line ends, an empty cell a
/// missing value.
pub fn metadata(url: &str, columns: &[ColumnMeta], content: Content) -> serde_json::Value {
    let column = |c: &ColumnMeta| {
        let mut entry =
            serde_json::json!({"name": csvw_name(&c.name), "titles": c.name, "datatype": c.datatype.name()});
        if !c.unit.is_empty() {
            entry["schema:unitText"] = c.unit.clone().into();
        }
        if !c.description.is_empty() {
            entry["dc:description"] = c.description.clone().into();
        }
        entry
    };
    serde_json::json!({
        "@context": "http://www.w3.org/ns/csvw",
        "url": url,
        "dc:creator": "demsweep",
        CONTENT_KEY: content.to_json(),
        "dialect": {"header": true, "lineTerminators": ["\r\n", "\n"]},
        "tableSchema": {"columns": columns.iter().map(column).collect::<Vec<_>>()},
    })
}

/// Writes the sidecar of the CSV file at `csv`, just written (see [`metadata_path`], [`metadata`]),
/// replacing a file there as `existing` allows.
pub fn write_metadata(csv: &Path, columns: &[ColumnMeta], existing: Existing) -> Result<(), GuardError> {
    let url = csv.file_name().unwrap_or_default().to_string_lossy();
    let bytes =
        std::fs::read(csv).map_err(|e| GuardError { path: csv.to_path_buf(), refusal: Refusal::Io(e.to_string()) })?;
    let mut text =
        serde_json::to_string_pretty(&metadata(&url, columns, Content::of(&bytes))).expect("JSON of strings");
    text.push('\n');
    guard::write_with(&metadata_path(csv), &[], existing, |out| out.write_all(text.as_bytes()))
}

/// Writes the CSV file `path` whole or not at all (`body` writes its lines), then its sidecar
/// ([`write_metadata`]), replacing files there as `existing` allows: both are checked first.
pub fn write_file(
    path: &Path,
    columns: &[ColumnMeta],
    existing: Existing,
    body: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), GuardError> {
    guard::check_replaceable(&metadata_path(path), &[], existing)?;
    guard::write_with(path, &[], existing, body)?;
    write_metadata(path, columns, existing)
}

/// The columns of `table`, declared (see [`ColumnMeta::declared`]) with their datatypes.
pub fn table_columns(table: &SummaryTable) -> Vec<ColumnMeta> {
    table.columns.iter().map(|c| ColumnMeta::declared(&c.name, Datatype::of_column(&c.data))).collect()
}

/// Writes the table: its names line, then its rows; missing values are empty cells.
pub fn write_table<W: Write>(out: &mut W, table: &SummaryTable) -> io::Result<()> {
    let names: Vec<&str> = table.columns.iter().map(|c| c.name.as_str()).collect();
    write_record(out, &names)?;
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
    fn the_datatype_is_the_narrowest_every_cell_reads_as() {
        assert_eq!(Datatype::of_cells(["1", "", "-3"]), Datatype::Integer);
        assert_eq!(Datatype::of_cells(["1", "2.5", "NaN"]), Datatype::Double);
        assert_eq!(Datatype::of_cells(["true", "false", ""]), Datatype::Boolean);
        assert_eq!(Datatype::of_cells(["r0000", "1"]), Datatype::String);
        assert_eq!(Datatype::of_cells(["", ""]), Datatype::String);
    }

    #[test]
    fn the_sidecar_names_each_column_its_unit_and_datatype() {
        let columns = vec![
            ColumnMeta::declared("run_id", Datatype::String),
            ColumnMeta::declared("material.youngs_modulus", Datatype::Double),
            ColumnMeta::declared("settle_time", Datatype::Double),
        ];
        let meta = metadata("s_summary.csv", &columns, Content::of(b"a\r\n"));
        assert_eq!(meta["@context"], "http://www.w3.org/ns/csvw");
        assert_eq!(meta["url"], "s_summary.csv");
        assert_eq!(
            meta[CONTENT_KEY],
            serde_json::json!({"bytes": 3, "crc32": format!("{:08x}", crc32fast::hash(b"a\r\n"))})
        );
        let listed = meta["tableSchema"]["columns"].as_array().unwrap();
        assert_eq!(listed[0]["titles"], "run_id");
        assert!(listed[0].get("schema:unitText").is_none(), "no unit for text: {}", listed[0]);
        assert_eq!(listed[1]["name"], "material.youngs_modulus");
        assert_eq!(listed[1]["schema:unitText"], "Pa");
        assert_eq!(
            (listed[2]["schema:unitText"].as_str(), listed[2]["datatype"].as_str()),
            (Some("s"), Some("double"))
        );
        assert!(listed[2]["dc:description"].as_str().is_some_and(|d| !d.is_empty()));
    }

    #[test]
    fn csvw_names_encode_what_a_uri_template_variable_cannot_hold() {
        assert_eq!(csvw_name("contact.linear.kn"), "contact.linear.kn");
        assert_eq!(csvw_name("wall time"), "wall%20time");
        assert_eq!(csvw_name("_x."), "%5Fx%2E");
    }

    #[test]
    fn a_csv_table_is_demsweeps_while_its_sidecar_records_its_content() {
        let dir = std::env::temp_dir().join(format!("demsweep-csv-bound-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let table = dir.join("t.csv");
        let columns = [ColumnMeta::declared("a", Datatype::Integer)];
        let ours = Existing::Ours { force: false };
        write_file(&table, &columns, ours, |out| out.write_all(b"a\r\n1\r\n")).unwrap();
        assert!(guard::made_by_demsweep(&table) && guard::made_by_demsweep(&metadata_path(&table)));
        write_file(&table, &columns, ours, |out| out.write_all(b"a\r\n2\r\n")).unwrap();
        assert!(guard::made_by_demsweep(&table), "its own table is replaced");
        std::fs::write(&table, "a\r\n3\r\n").unwrap();
        assert!(!guard::made_by_demsweep(&table), "a table edited since is the user's");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_sidecar_sits_beside_the_file() {
        assert_eq!(metadata_path(Path::new("out/s_points.csv")), Path::new("out/s_points.csv-metadata.json"));
    }
}
