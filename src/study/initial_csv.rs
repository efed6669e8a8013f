//! Placement files: initial disk states as CSV with a header line. Columns `x,y` (m) are required;
//! `r` (m), `vx,vy` (m/s) and `omega` (rad/s) are optional, in any order; `id` and `contact_force`
//! (written by `demsweep export --format csv`) are allowed and not read. Blank lines and lines
//! starting with `#` are skipped.

use std::path::Path;

use crate::physics::particles::InitialDisk;

/// The columns a placement file may have: the disk state, then the ones that are not read.
const COLUMNS: [&str; 8] = ["x", "y", "r", "vx", "vy", "omega", "id", "contact_force"];

/// Largest placement file read (bytes): a million disks with every column take about 100 MB.
pub const MAX_PLACEMENT_BYTES: u64 = 256 << 20;

/// Reads the disks of a placement CSV (at most [`MAX_PLACEMENT_BYTES`], a leading byte-order mark
/// skipped); errors name the file, line and column.
pub fn read(path: &Path, default_radius: f64) -> Result<Vec<InitialDisk>, String> {
    let text = super::file::read_text(path, MAX_PLACEMENT_BYTES)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    parse(&text, default_radius).map_err(|e| format!("{}: {e}", path.display()))
}

/// Parses placement CSV text; disks without an `r` column get `default_radius`.
/// Errors name the line (1-based) and, for a bad value, the column number and name.
pub fn parse(text: &str, default_radius: f64) -> Result<Vec<InitialDisk>, String> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, line)| (i + 1, line.trim()))
        .filter(|(_, line)| !line.is_empty() && !line.starts_with('#'));
    let Some((header_line, header)) = lines.next() else {
        return Err("line 1: empty file: expected a header line like `x,y,r`".into());
    };
    let columns = header_columns(header).map_err(|e| format!("line {header_line}: {e}"))?;
    let disks =
        lines.map(|(number, line)| parse_row(line, &columns, default_radius).map_err(|e| format!("line {number}{e}")));
    let disks = disks.collect::<Result<Vec<_>, _>>()?;
    if disks.is_empty() {
        return Err(format!("line {header_line}: the file has a header but no disks"));
    }
    Ok(disks)
}

/// Index into [`COLUMNS`] of each header field.
fn header_columns(header: &str) -> Result<Vec<usize>, String> {
    let mut columns = Vec::new();
    for name in header.split(',').map(str::trim) {
        let Some(k) = COLUMNS.iter().position(|c| c.eq_ignore_ascii_case(name)) else {
            return Err(format!(
                "unknown column \"{name}\" (expected x, y and optionally r, vx, vy, omega, id, contact_force)"
            ));
        };
        if columns.contains(&k) {
            return Err(format!("column \"{name}\" appears twice"));
        }
        columns.push(k);
    }
    for required in [0, 1] {
        if !columns.contains(&required) {
            return Err(format!("the header has no \"{}\" column (x and y are required)", COLUMNS[required]));
        }
    }
    Ok(columns)
}

/// One disk from a data line; errors start with what follows the line number (", column ..." or ": ...").
fn parse_row(line: &str, columns: &[usize], default_radius: f64) -> Result<InitialDisk, String> {
    let fields: Vec<&str> = line.split(',').map(str::trim).collect();
    if fields.len() != columns.len() {
        return Err(format!(": has {} fields but the header has {}", fields.len(), columns.len()));
    }
    let mut values = [0.0, 0.0, default_radius, 0.0, 0.0, 0.0, 0.0, 0.0];
    for (position, (&column, field)) in columns.iter().zip(&fields).enumerate() {
        let at = || format!(", column {} ({})", position + 1, COLUMNS[column]);
        let value: f64 = field.parse().map_err(|_| format!("{}: \"{field}\" is not a number", at()))?;
        if !value.is_finite() {
            return Err(format!("{}: must be finite, got {field}", at()));
        }
        if column == 2 && value <= 0.0 {
            return Err(format!("{}: a radius must be > 0, got {field}", at()));
        }
        values[column] = value;
    }
    let [x, y, r, vx, vy, omega, _id, _contact_force] = values;
    Ok(InitialDisk { x, y, r, vx, vy, omega })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn optional_columns_in_any_order_and_default_radius() {
        let disks = parse("# initial state\ny, omega, x\n0.5,2,0.1\n\n0.25,0,0.3\n", 0.01).unwrap();
        assert_eq!(disks.len(), 2);
        assert_eq!(disks[0], InitialDisk { x: 0.1, y: 0.5, r: 0.01, vx: 0.0, vy: 0.0, omega: 2.0 });
        assert_eq!(disks[1].x, 0.3);
        let with_r = parse("x,y,r,vx,vy\n1,2,0.5,-1,3e-1\n", 0.01).unwrap();
        assert_eq!(with_r[0], InitialDisk { x: 1.0, y: 2.0, r: 0.5, vx: -1.0, vy: 0.3, omega: 0.0 });
    }

    #[test]
    fn reads_the_export_header_and_skips_id_and_contact_force() {
        let text = "# exported\nid,x,y,r,vx,vy,omega,contact_force\n7,1,2,0.5,-1,3,4,9.5\n";
        let disks = parse(text, 0.01).unwrap();
        assert_eq!(disks, vec![InitialDisk { x: 1.0, y: 2.0, r: 0.5, vx: -1.0, vy: 3.0, omega: 4.0 }]);
    }

    #[test]
    fn errors_name_line_and_column() {
        let err = parse("x,y,vx\n1,2,0\n1,2,abc\n", 0.01).unwrap_err();
        assert_eq!(err, "line 3, column 3 (vx): \"abc\" is not a number");
        let err = parse("x,y\n\n1,2,3\n", 0.01).unwrap_err();
        assert_eq!(err, "line 3: has 3 fields but the header has 2");
        let err = parse("x,y,r\n1,2,-0.1\n", 0.01).unwrap_err();
        assert_eq!(err, "line 2, column 3 (r): a radius must be > 0, got -0.1");
        let err = parse("x,y\n1,inf\n", 0.01).unwrap_err();
        assert_eq!(err, "line 2, column 2 (y): must be finite, got inf");
    }

    #[test]
    fn header_problems_and_empty_files() {
        assert_eq!(parse("x,radius\n", 0.01).unwrap_err().split(':').next(), Some("line 1"));
        assert!(parse("x,radius\n1,2\n", 0.01).unwrap_err().contains("unknown column \"radius\""));
        assert!(parse("x,r\n1,2\n", 0.01).unwrap_err().contains("no \"y\" column"));
        assert!(parse("x,y,x\n", 0.01).unwrap_err().contains("column \"x\" appears twice"));
        assert_eq!(parse("x,y\n", 0.01).unwrap_err(), "line 1: the file has a header but no disks");
        assert!(parse("\n# nothing\n", 0.01).unwrap_err().contains("empty file"));
    }
}
