//! Why a placement or contact CSV gives no disks or contacts: the line, the column and the problem,
//! typed; [`std::fmt::Display`] makes the text, quoting the file's content only where it may. And
//! why a placement file of either kind (CSV or LAMMPS) cannot be read, naming it.

use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;

use super::file::ReadTextError;
use super::lammps_error::{LammpsError, drawn_radii};

/// A column of a CSV line: its position (from 1) and, when the header has named it, its name.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColumnAt {
    /// Position on the line, from 1.
    pub position: usize,
    /// The column's name, when known.
    pub name: Option<&'static str>,
}

/// A problem with a placement or contact CSV, at a line (and column).
#[derive(Clone, Debug, PartialEq)]
pub struct CsvError {
    /// The line, from 1.
    pub line: usize,
    /// The column, when the problem is in one.
    pub column: Option<ColumnAt>,
    /// What is wrong.
    pub problem: CsvProblem,
}

/// What is wrong with a CSV line. Text from the file (`given`) is None where it may not be quoted.
#[derive(Clone, Debug, PartialEq)]
pub enum CsvProblem {
    /// No header line (an example of one).
    EmptyFile(String),
    /// A header field that names no column.
    UnknownColumn {
        /// The field, when it may be quoted.
        given: Option<String>,
        /// The column it most likely means.
        nearest: Option<&'static str>,
        /// The file's columns (name and unit), the required ones first.
        columns: &'static [(&'static str, &'static str)],
        /// How many of them are required.
        required: usize,
    },
    /// A column named twice.
    Twice {
        /// The field, when it may be quoted.
        given: Option<String>,
        /// Where it is first (from 1).
        first: usize,
    },
    /// A required column missing from the header.
    Missing {
        /// The column.
        column: &'static str,
        /// The required columns (name and unit).
        required: &'static [(&'static str, &'static str)],
    },
    /// A units line with a number of fields other than the header's.
    UnitsFields {
        /// Fields on the units line.
        found: usize,
        /// Fields of the header.
        header: usize,
    },
    /// A unit other than the column's SI unit.
    Unit {
        /// The unit given, when it may be quoted.
        given: Option<String>,
        /// The SI unit (empty: dimensionless).
        si: &'static str,
    },
    /// A data line with a number of fields other than the header's.
    Fields {
        /// Fields on the line.
        found: usize,
        /// Fields of the header.
        header: usize,
    },
    /// A value that is no number (the value, when it may be quoted).
    NotANumber(Option<String>),
    /// A value that is no finite number (as written: `inf`, `NaN`, `1e999`).
    NotFinite(String),
    /// A header and no disk.
    NoDisks,
    /// A radius ≤ 0.
    Radius(f64),
    /// A header without the `r` column in a scene whose radius key (its name) draws radii.
    NoRadii(&'static str),
    /// A body index that is no whole number.
    NotWhole(f64),
    /// A disk index past the placement's disks.
    NoSuchDisk {
        /// The index.
        index: i64,
        /// The placement's disks.
        disks: usize,
    },
    /// A wall index past the box's walls.
    NoSuchWall {
        /// The index (−1 the floor).
        index: i64,
        /// The box's walls.
        walls: usize,
    },
    /// A wall as a contact's first body (its index).
    FirstIsWall(f64),
    /// A disk in contact with itself (its index).
    SelfContact(usize),
}

/// The columns' names, listed.
fn names(columns: &[(&str, &str)]) -> String {
    columns.iter().map(|c| c.0).collect::<Vec<_>>().join(", ")
}

/// `"text"` when it may be quoted, else `withheld`.
fn shown(given: &Option<String>, withheld: &str) -> String {
    given.as_ref().map_or(withheld.to_string(), |text| format!("\"{text}\""))
}

impl fmt::Display for CsvError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}", self.line)?;
        match self.column {
            Some(ColumnAt { position, name: Some(name) }) => write!(f, ", column {position} ({name})")?,
            Some(ColumnAt { position, name: None }) => write!(f, ", column {position}")?,
            None => {}
        }
        write!(f, ": {}", self.problem)
    }
}

impl fmt::Display for CsvProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CsvProblem::EmptyFile(example) => write!(f, "empty file: expected a header line like `{example}`"),
            CsvProblem::UnknownColumn { given, nearest: Some(meant), .. } => {
                write!(f, "unknown column {} (did you mean `{meant}`?)", shown(given, "name"))
            }
            CsvProblem::UnknownColumn { given, nearest: None, columns, required } => {
                let (must, may) = columns.split_at(*required);
                write!(
                    f,
                    "unknown column {} (expected {} and optionally {})",
                    shown(given, "name"),
                    names(must),
                    names(may)
                )
            }
            CsvProblem::Twice { given, first } => {
                write!(f, "column {} appears twice (first at column {first})", shown(given, "name"))
            }
            CsvProblem::Missing { column, required } => {
                write!(f, "the header has no \"{column}\" column ({} are required)", names(required))
            }
            CsvProblem::UnitsFields { found, header } => {
                write!(f, "the units line has {found} fields but the header has {header}")
            }
            CsvProblem::Unit { given, si } => {
                let si = if si.is_empty() { "dimensionless" } else { si };
                write!(f, "unit {}: values are read in SI ({si})", shown(given, "given"))
            }
            CsvProblem::Fields { found, header } => write!(f, "has {found} fields but the header has {header}"),
            CsvProblem::NotANumber(given) => write!(f, "{} is not a number", shown(given, "the value")),
            CsvProblem::NotFinite(field) => write!(f, "must be finite, got {field}"),
            CsvProblem::NoDisks => write!(f, "the file has a header but no disks"),
            CsvProblem::Radius(r) => write!(f, "a radius must be > 0, got {r}"),
            CsvProblem::NoRadii(key) => write!(f, "the header has no \"r\" column, and {}", drawn_radii(key)),
            CsvProblem::NotWhole(value) => write!(f, "{value} is not a whole number"),
            CsvProblem::NoSuchDisk { index, disks } => write!(
                f,
                "disk {index} is out of range: the placement file has {disks} disks (0 to {})",
                *disks as i64 - 1
            ),
            CsvProblem::NoSuchWall { index, walls } => {
                write!(f, "wall {index} does not exist: the box has {walls} walls (-1 floor to {})", -(*walls as i64))
            }
            CsvProblem::FirstIsWall(index) => {
                write!(f, "{index} is a wall: the first body is a disk (a wall goes in `second`)")
            }
            CsvProblem::SelfContact(disk) => write!(f, "a disk ({disk}) cannot touch itself"),
        }
    }
}

impl std::error::Error for CsvError {}

/// Why a placement or contact file (CSV or LAMMPS) gives no disks or contacts, naming the file.
#[derive(Clone, Debug)]
pub enum PlacementFileError {
    /// It is not a regular file (what it is: a folder, a named pipe …).
    NotAFile {
        /// The file.
        path: PathBuf,
        /// What it is.
        kind: &'static str,
    },
    /// It cannot be read.
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        error: Arc<ReadTextError>,
    },
    /// A CSV problem.
    Csv {
        /// The file.
        path: PathBuf,
        /// What and where.
        error: Box<CsvError>,
    },
    /// A LAMMPS file problem.
    Lammps {
        /// The file.
        path: PathBuf,
        /// What and where.
        error: Box<LammpsError>,
        /// Whether the file's content may be quoted (it lies in the study's folder).
        quoted: bool,
    },
}

impl fmt::Display for PlacementFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PlacementFileError::NotAFile { path, kind } => {
                write!(f, "{}: cannot read: not a regular file ({kind})", path.display())
            }
            PlacementFileError::Read { path, error } => write!(f, "{}: cannot read: {error}", path.display()),
            PlacementFileError::Csv { path, error } => write!(f, "{}: {error}", path.display()),
            PlacementFileError::Lammps { path, error, quoted: true } => write!(f, "{}: {error}", path.display()),
            PlacementFileError::Lammps { path, error, quoted: false } => write!(
                f,
                "{}: {}not a LAMMPS data or dump file demsweep reads (the file lies outside the study's folder, so \
                 its content is not quoted)",
                path.display(),
                error.place().map(|place| format!("{place}: ")).unwrap_or_default()
            ),
        }
    }
}

impl std::error::Error for PlacementFileError {}
