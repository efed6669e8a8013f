//! Placement files: initial disk states as CSV with a header line. Columns `x,y` (m) are required;
//! `r` (m), `vx,vy` (m/s), `omega` (rad/s) and `angle` (rad) are optional, in any order; `id` and
//! `contact_force` (written by `demsweep export --format csv`) are allowed and not read. Blank lines
//! and lines starting with `#` are skipped. A units line may follow the header (as in the CSV
//! files older versions of demsweep wrote: no cell a number); each of its cells is empty or the column's SI unit.
//!
//! Contact files (`placement.contacts`, written by the same export as `<run>_<state>_contacts.csv`):
//! the contact history of a restart, one row per contact, columns `first` (a disk: its row in the
//! placement file, from 0), `second` (a disk, or wall `−1 − k`: 0 floor, 1 left, 2 right, 3 lid),
//! `tangential_spring` (m) and `law_state` (the contact law's state; optional, 0 by default), in
//! any order, same rules (no rows: no contacts).

use std::path::Path;

use super::csv_error::{ColumnAt, CsvError, CsvProblem, PlacementFileError};
use super::file::ReadTextError;
use crate::physics::config::ParticlesConfig;
use crate::physics::contact_record::Partner;
use crate::physics::particles::{InitialContact, InitialDisk};

/// A column a file may have: its name and SI unit (empty when dimensionless).
type Column = (&'static str, &'static str);

/// The columns a placement file may have: the disk state, then the ones that are not read.
const COLUMNS: [Column; 9] = [
    ("x", "m"),
    ("y", "m"),
    ("r", "m"),
    ("vx", "m/s"),
    ("vy", "m/s"),
    ("omega", "rad/s"),
    ("angle", "rad"),
    ("id", ""),
    ("contact_force", "N"),
];
/// Of [`COLUMNS`], the required ones (x and y).
const REQUIRED: usize = 2;

/// The columns of a contact file, the first three required.
const CONTACT_COLUMNS: [Column; 4] = [("first", ""), ("second", ""), ("tangential_spring", "m"), ("law_state", "")];

/// Largest placement (or contact) file read (bytes): a million disks with every column take about 100 MB.
pub const MAX_PLACEMENT_BYTES: u64 = 256 << 20;

/// What a disk gets whose placement file gives no radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MissingRadius {
    /// This radius (m): `particles.radius`.
    Radius(f64),
    /// Nothing: the scene's radius key (its name) draws radii for generated placements only, so the
    /// file must give every disk's radius.
    Drawn(&'static str),
}

impl MissingRadius {
    /// What the disks of a placement file without radii get in a scene of `particles`.
    pub fn of(particles: &ParticlesConfig) -> Self {
        let drawn = [
            ("particles.radii", particles.radii.is_some()),
            ("particles.radius_max", particles.radius_max.is_some()),
            ("particles.size_distribution", particles.size_distribution.is_some()),
        ];
        drawn.into_iter().find(|(_, given)| *given).map_or(Self::Radius(particles.radius), |(key, _)| Self::Drawn(key))
    }
}

impl From<f64> for MissingRadius {
    /// Every disk without a radius gets `radius`.
    fn from(radius: f64) -> Self {
        Self::Radius(radius)
    }
}

/// Whether errors about a file's content may quote its text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quoting {
    /// The file is the user's own (in the study's folder): errors quote the cell at fault.
    Quoted,
    /// The file lies outside the study's folder (`/etc/shadow`, `/proc/self/environ`, or a link to
    /// them): errors name line and column only, so that no study can print another file's content.
    Withheld,
}

impl Quoting {
    /// [`Quoting::Quoted`] for a file that lies (links resolved) in `folder`, else withheld.
    pub fn of(path: &Path, folder: &Path) -> Self {
        let folder = if folder.as_os_str().is_empty() { Path::new(".") } else { folder };
        let inside = match (path.canonicalize(), folder.canonicalize()) {
            (Ok(path), Ok(folder)) => path.starts_with(folder),
            _ => false,
        };
        if inside { Self::Quoted } else { Self::Withheld }
    }

    /// `text` when it may be quoted.
    fn show(self, text: &str) -> Option<String> {
        match self {
            Self::Quoted => Some(text.to_string()),
            Self::Withheld => None,
        }
    }
}

/// Reads the disks of a placement CSV (a regular file of at most [`MAX_PLACEMENT_BYTES`], a leading
/// byte-order mark skipped); errors name the file, line and column, quoting the file only when it
/// lies in the study's `folder`.
pub fn read(
    path: &Path,
    missing: impl Into<MissingRadius>,
    folder: &Path,
) -> Result<Vec<InitialDisk>, PlacementFileError> {
    parse(&read_text(path)?, missing, Quoting::of(path, folder))
        .map_err(|error| PlacementFileError::Csv { path: path.to_path_buf(), error: Box::new(error) })
}

/// Reads the contact history of a contact CSV for a placement of `disks` disks in a box of `walls`
/// walls; errors as [`read`]'s.
pub fn read_contacts(
    path: &Path,
    disks: usize,
    walls: usize,
    folder: &Path,
) -> Result<Vec<InitialContact>, PlacementFileError> {
    parse_contacts(&read_text(path)?, disks, walls, Quoting::of(path, folder))
        .map_err(|error| PlacementFileError::Csv { path: path.to_path_buf(), error: Box::new(error) })
}

/// The text of a regular file (a FIFO, device or folder is refused before it is opened: reading one
/// would wait for a writer or never end).
pub(super) fn read_text(path: &Path) -> Result<String, PlacementFileError> {
    let cannot = |error| PlacementFileError::Read { path: path.to_path_buf(), error: std::sync::Arc::new(error) };
    let kind = std::fs::metadata(path).map_err(|e| cannot(ReadTextError::Io(e)))?.file_type();
    if !kind.is_file() {
        return Err(PlacementFileError::NotAFile { path: path.to_path_buf(), kind: file_kind(kind) });
    }
    super::file::read_text(path, MAX_PLACEMENT_BYTES).map_err(cannot)
}

/// What a file that is not a regular file is, in words.
fn file_kind(kind: std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    match kind {
        k if k.is_dir() => "a folder",
        k if k.is_fifo() => "a named pipe",
        k if k.is_socket() => "a socket",
        k if k.is_char_device() || k.is_block_device() => "a device",
        _ => "not a plain file",
    }
}

/// Parses placement CSV text; without an `r` column, the disks get the radius `missing` gives (or
/// none: an error). Errors name the line (1-based) and, for a bad value, the column number and name.
pub fn parse(text: &str, missing: impl Into<MissingRadius>, quoting: Quoting) -> Result<Vec<InitialDisk>, CsvError> {
    let rows = Table::parse(text, (&COLUMNS, REQUIRED), quoting)?;
    if rows.rows.is_empty() {
        return Err(CsvError { line: rows.header_line, column: None, problem: CsvProblem::NoDisks });
    }
    let mut defaults = [0.0; COLUMNS.len()];
    match missing.into() {
        MissingRadius::Radius(radius) => defaults[2] = radius,
        MissingRadius::Drawn(key) if !rows.header.contains(&2) => {
            return Err(CsvError { line: rows.header_line, column: None, problem: CsvProblem::NoRadii(key) });
        }
        MissingRadius::Drawn(_) => {}
    }
    let disks = rows.rows.iter().map(|&(line, ref values)| {
        let row = rows.values(values, &defaults);
        if row[2] <= 0.0 {
            return Err(CsvError { line, column: Some(rows.at(2)), problem: CsvProblem::Radius(row[2]) });
        }
        let [x, y, r, vx, vy, omega, angle, _id, _contact_force] = row;
        Ok(InitialDisk { x, y, r, vx, vy, omega, angle })
    });
    disks.collect()
}

/// Parses contact CSV text for `disks` disks and `walls` walls; errors name the line and column.
pub fn parse_contacts(
    text: &str,
    disks: usize,
    walls: usize,
    quoting: Quoting,
) -> Result<Vec<InitialContact>, CsvError> {
    let rows = Table::parse(text, (&CONTACT_COLUMNS, 3), quoting)?;
    let contacts = rows.rows.iter().map(|&(line, ref values)| {
        let [first, second, tangential_spring, law_state] = rows.values(values, &[0.0; 4]);
        let at = |column: usize, problem| CsvError { line, column: Some(rows.at(column)), problem };
        let disk = body(first, disks, walls).and_then(|body| match body {
            Partner::Disk(i) => Ok(i),
            Partner::Wall(_) => Err(CsvProblem::FirstIsWall(first)),
        });
        let disk = disk.map_err(|why| at(0, why))?;
        let partner = body(second, disks, walls).map_err(|why| at(1, why))?;
        if partner == Partner::Disk(disk) {
            return Err(at(1, CsvProblem::SelfContact(disk)));
        }
        Ok(InitialContact { disk, partner, tangential_spring, law_state })
    });
    contacts.collect()
}

/// The body a contact file's index names: disk `value ≥ 0` of `disks`, or wall `−1 − value` of `walls`.
fn body(value: f64, disks: usize, walls: usize) -> Result<Partner, CsvProblem> {
    if value.fract() != 0.0 || value.abs() >= 1e15 {
        return Err(CsvProblem::NotWhole(value));
    }
    let index = value as i64;
    if index >= 0 {
        let disk = usize::try_from(index).ok().filter(|&i| i < disks);
        disk.map(Partner::Disk).ok_or(CsvProblem::NoSuchDisk { index, disks })
    } else {
        let wall = usize::try_from(-1 - index).ok().filter(|&w| w < walls);
        wall.map(Partner::Wall).ok_or(CsvProblem::NoSuchWall { index, walls })
    }
}

/// A problem in a column of a line, or in the line as a whole; the caller knows the line.
type Misplaced = (Option<ColumnAt>, CsvProblem);

/// The data rows of a CSV text with a header naming some of `columns` (the first `required` of
/// them required), each row's values in header order with its line number.
struct Table<'a> {
    columns: &'a [Column],
    /// Index into `columns` of each header field.
    header: Vec<usize>,
    /// The header's line number.
    header_line: usize,
    rows: Vec<(usize, Vec<f64>)>,
    quoting: Quoting,
}

impl<'a> Table<'a> {
    /// Reads the header and the rows (every value a finite number).
    fn parse(text: &str, (columns, required): (&'static [Column], usize), quoting: Quoting) -> Result<Self, CsvError> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, line)| (i + 1, line.trim()))
            .filter(|(_, line)| !line.is_empty() && !line.starts_with('#'))
            .peekable();
        let Some((header_line, header)) = lines.next() else {
            let example = names(&columns[..required]).join(",");
            return Err(CsvError { line: 1, column: None, problem: CsvProblem::EmptyFile(example) });
        };
        let at = |line: usize| move |(column, problem): Misplaced| CsvError { line, column, problem };
        let header = header_columns(header, (columns, required), quoting).map_err(at(header_line))?;
        let mut table = Self { columns, header, header_line, rows: Vec::new(), quoting };
        if let Some((number, line)) = lines.next_if(|(_, line)| is_units_line(line)) {
            table.check_units(line).map_err(at(number))?;
        }
        for (number, line) in lines {
            let values = table.parse_row(line).map_err(at(number))?;
            table.rows.push((number, values));
        }
        Ok(table)
    }

    /// Each cell of a units line is empty or its column's SI unit; errors as [`Self::parse_row`]'s.
    fn check_units(&self, line: &str) -> Result<(), Misplaced> {
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        if cells.len() != self.header.len() {
            return Err((None, CsvProblem::UnitsFields { found: cells.len(), header: self.header.len() }));
        }
        let wrong =
            cells.iter().zip(&self.header).position(|(cell, &c)| !cell.is_empty() && *cell != self.columns[c].1);
        match wrong {
            None => Ok(()),
            Some(position) => {
                let si = self.columns[self.header[position]].1;
                Err((
                    Some(self.at_position(position)),
                    CsvProblem::Unit { given: self.quoting.show(cells[position]), si },
                ))
            }
        }
    }

    /// One data line's values.
    fn parse_row(&self, line: &str) -> Result<Vec<f64>, Misplaced> {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != self.header.len() {
            return Err((None, CsvProblem::Fields { found: fields.len(), header: self.header.len() }));
        }
        let values = fields.iter().enumerate().map(|(position, field)| {
            let at = Some(self.at_position(position));
            let value: f64 = field.parse().map_err(|_| (at, CsvProblem::NotANumber(self.quoting.show(field))))?;
            if !value.is_finite() {
                return Err((at, CsvProblem::NotFinite(field.to_string())));
            }
            Ok(value)
        });
        values.collect()
    }

    /// A row's values in the order of `columns`, `defaults` where the header lacks a column.
    fn values<const N: usize>(&self, row: &[f64], defaults: &[f64; N]) -> [f64; N] {
        let mut values = *defaults;
        for (&column, &value) in self.header.iter().zip(row) {
            values[column] = value;
        }
        values
    }

    /// Column `column` of `columns` where the header places it.
    fn at(&self, column: usize) -> ColumnAt {
        let position = self.header.iter().position(|&c| c == column).unwrap_or(column);
        ColumnAt { position: position + 1, name: Some(self.columns[column].0) }
    }

    /// The column at `position` (from 0) of a line.
    fn at_position(&self, position: usize) -> ColumnAt {
        ColumnAt { position: position + 1, name: Some(self.columns[self.header[position]].0) }
    }
}

/// Index into `columns` of each header field; the first `required` columns must be there.
fn header_columns(
    header: &str,
    (columns, required): (&'static [Column], usize),
    quoting: Quoting,
) -> Result<Vec<usize>, Misplaced> {
    let mut found = Vec::new();
    for (position, name) in header.split(',').map(str::trim).enumerate() {
        let at = Some(ColumnAt { position: position + 1, name: None });
        let Some(k) = columns.iter().position(|c| c.0.eq_ignore_ascii_case(name)) else {
            let problem = CsvProblem::UnknownColumn {
                given: quoting.show(name),
                nearest: super::errors::nearest(name, names(columns)),
                columns,
                required,
            };
            return Err((at, problem));
        };
        if let Some(first) = found.iter().position(|&f| f == k) {
            return Err((at, CsvProblem::Twice { given: quoting.show(name), first: first + 1 }));
        }
        found.push(k);
    }
    if let Some(missing) = columns[..required].iter().enumerate().find(|(k, _)| !found.contains(k)) {
        return Err((None, CsvProblem::Missing { column: missing.1.0, required: &columns[..required] }));
    }
    Ok(found)
}

/// The columns' names.
fn names(columns: &[Column]) -> Vec<&'static str> {
    columns.iter().map(|c| c.0).collect()
}

/// Whether a line after the header is a units line: none of its cells a number.
fn is_units_line(line: &str) -> bool {
    line.split(',').all(|cell| cell.trim().parse::<f64>().is_err())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn optional_columns_in_any_order_and_default_radius() {
        let disks = parse("# initial state\ny, omega, x\n0.5,2,0.1\n\n0.25,0,0.3\n", 0.01, Quoting::Quoted).unwrap();
        assert_eq!(disks.len(), 2);
        assert_eq!(disks[0], InitialDisk { x: 0.1, y: 0.5, r: 0.01, omega: 2.0, ..Default::default() });
        assert_eq!(disks[1].x, 0.3);
        let with_r = parse("x,y,r,vx,vy\n1,2,0.5,-1,3e-1\n", 0.01, Quoting::Quoted).unwrap();
        assert_eq!(with_r[0], InitialDisk { x: 1.0, y: 2.0, r: 0.5, vx: -1.0, vy: 0.3, ..Default::default() });
    }

    #[test]
    fn reads_the_export_header_and_skips_id_and_contact_force() {
        let text = "# exported\nid,x,y,r,vx,vy,omega,angle,contact_force\n7,1,2,0.5,-1,3,4,-6.5,9.5\n";
        let disks = parse(text, 0.01, Quoting::Quoted).unwrap();
        assert_eq!(disks, vec![InitialDisk { x: 1.0, y: 2.0, r: 0.5, vx: -1.0, vy: 3.0, omega: 4.0, angle: -6.5 }]);
    }

    #[test]
    fn a_units_line_under_the_header_is_checked_and_skipped() {
        let text =
            "id,x,y,r,vx,vy,omega,angle,contact_force\r\n,m,m,m,m/s,m/s,rad/s,rad,N\r\n7,1,2,0.5,-1,3,4,-6.5,9.5\r\n";
        let disks = parse(text, 0.01, Quoting::Quoted).unwrap();
        assert_eq!(disks, vec![InitialDisk { x: 1.0, y: 2.0, r: 0.5, vx: -1.0, vy: 3.0, omega: 4.0, angle: -6.5 }]);
        assert_eq!(parse("x,y\n,\n1,2\n", 0.01, Quoting::Quoted).unwrap().len(), 1, "empty unit cells are allowed");
        assert_eq!(
            parse("x,y,r\nmm,m,\n1,2,3\n", 0.01, Quoting::Quoted).unwrap_err().to_string(),
            "line 2, column 1 (x): unit \"mm\": values are read in SI (m)"
        );
        assert_eq!(
            parse("x,y\nm,m,m\n1,2\n", 0.01, Quoting::Quoted).unwrap_err().to_string(),
            "line 2: the units line has 3 fields but the header has 2"
        );
        let contacts =
            parse_contacts("first,second,tangential_spring\n,,m\n0,1,5e-8\n", 2, 3, Quoting::Quoted).unwrap();
        assert_eq!(contacts.len(), 1);
        assert_eq!(
            parse_contacts("first,second,tangential_spring\n,,N\n0,1,5e-8\n", 2, 3, Quoting::Quoted)
                .unwrap_err()
                .to_string(),
            "line 2, column 3 (tangential_spring): unit \"N\": values are read in SI (m)"
        );
        assert_eq!(
            parse("x,y\n1,abc\n", 0.01, Quoting::Quoted).unwrap_err().to_string(),
            "line 2, column 2 (y): \"abc\" is not a number",
            "a data line with a number"
        );
    }

    #[test]
    fn contact_rows_name_both_bodies_and_their_history() {
        let text = "# exported\nfirst,second,tangential_spring,law_state\n0,2,1e-7,3e-5\n1,-1,-2e-7,0\n2,-4,0,0\n";
        let contacts = parse_contacts(text, 3, 4, Quoting::Quoted).unwrap();
        let contact = |disk, partner, tangential_spring, law_state| InitialContact {
            disk,
            partner,
            tangential_spring,
            law_state,
        };
        assert_eq!(
            contacts,
            [
                contact(0, Partner::Disk(2), 1e-7, 3e-5),
                contact(1, Partner::Wall(0), -2e-7, 0.0),
                contact(2, Partner::Wall(3), 0.0, 0.0)
            ]
        );
        let without_law_state =
            parse_contacts("second,first,tangential_spring\n1,0,5e-8\n", 2, 3, Quoting::Quoted).unwrap();
        assert_eq!(without_law_state, [contact(0, Partner::Disk(1), 5e-8, 0.0)]);
    }

    #[test]
    fn contact_errors_name_line_column_and_range() {
        let header = "first,second,tangential_spring\n";
        let err = |rows: &str, disks| {
            parse_contacts(&format!("{header}{rows}"), disks, 3, Quoting::Quoted).unwrap_err().to_string()
        };
        assert_eq!(
            err("0,1,0\n0,30,0\n", 30),
            "line 3, column 2 (second): disk 30 is out of range: the placement file has 30 disks (0 to 29)"
        );
        assert_eq!(
            err("-1,1,0\n", 30),
            "line 2, column 1 (first): -1 is a wall: the first body is a disk (a wall goes in `second`)"
        );
        assert_eq!(
            err("0,-4,0\n", 30),
            "line 2, column 2 (second): wall -4 does not exist: the box has 3 walls (-1 floor to -3)"
        );
        assert_eq!(err("0,1.5,0\n", 30), "line 2, column 2 (second): 1.5 is not a whole number");
        assert_eq!(err("2,2,0\n", 30), "line 2, column 2 (second): a disk (2) cannot touch itself");
        assert!(
            parse_contacts("first,second\n0,1\n", 2, 3, Quoting::Quoted)
                .unwrap_err()
                .to_string()
                .contains("no \"tangential_spring\" column")
        );
        assert_eq!(parse_contacts(header, 2, 3, Quoting::Quoted), Ok(vec![]), "a pile without contacts has no history");
    }

    #[test]
    fn errors_name_line_and_column() {
        let err = parse("x,y,vx\n1,2,0\n1,2,abc\n", 0.01, Quoting::Quoted).unwrap_err().to_string();
        assert_eq!(err, "line 3, column 3 (vx): \"abc\" is not a number");
        let err = parse("x,y\n\n1,2,3\n", 0.01, Quoting::Quoted).unwrap_err().to_string();
        assert_eq!(err, "line 3: has 3 fields but the header has 2");
        let err = parse("x,y,r\n1,2,-0.1\n", 0.01, Quoting::Quoted).unwrap_err().to_string();
        assert_eq!(err, "line 2, column 3 (r): a radius must be > 0, got -0.1");
        let err = parse("x,y\n1,inf\n", 0.01, Quoting::Quoted).unwrap_err().to_string();
        assert_eq!(err, "line 2, column 2 (y): must be finite, got inf");
    }

    #[test]
    fn header_problems_and_empty_files() {
        let unknown = parse("x,radius\n", 0.01, Quoting::Quoted).unwrap_err();
        assert_eq!((unknown.line, unknown.column), (1, Some(ColumnAt { position: 2, name: None })));
        assert!(
            parse("x,radius\n1,2\n", 0.01, Quoting::Quoted)
                .unwrap_err()
                .to_string()
                .contains("unknown column \"radius\"")
        );
        assert!(parse("x,r\n1,2\n", 0.01, Quoting::Quoted).unwrap_err().to_string().contains("no \"y\" column"));
        assert!(
            parse("x,y,x\n", 0.01, Quoting::Quoted).unwrap_err().to_string().contains("column \"x\" appears twice")
        );
        assert_eq!(
            parse("x,y\n", 0.01, Quoting::Quoted).unwrap_err().to_string(),
            "line 1: the file has a header but no disks"
        );
        assert!(parse("\n# nothing\n", 0.01, Quoting::Quoted).unwrap_err().to_string().contains("empty file"));
    }

    #[test]
    fn a_withheld_file_is_never_quoted() {
        let withheld = |text: &str| parse(text, 0.01, Quoting::Withheld).unwrap_err().to_string();
        assert_eq!(
            withheld("x,secret\n"),
            "line 1, column 2: unknown column name (expected x, y and optionally r, vx, vy, omega, angle, id, contact_force)"
        );
        assert_eq!(withheld("x,y,x\n"), "line 1, column 3: column name appears twice (first at column 1)");
        assert_eq!(withheld("x,y\nm,secret\n1,2\n"), "line 2, column 2 (y): unit given: values are read in SI (m)");
        assert_eq!(withheld("x,y\n1,2\n3,secret\n"), "line 3, column 2 (y): the value is not a number");
        let contacts = parse_contacts("first,secret\n", 2, 3, Quoting::Withheld).unwrap_err().to_string();
        assert!(contacts.starts_with("line 1, column 2: unknown column name"), "{contacts}");
    }
}
