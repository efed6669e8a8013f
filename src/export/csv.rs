//! Placement CSV: one row per disk, `id,x,y,r,vx,vy,omega,angle,contact_force` (SI units), the
//! columns `placement.kind = "file"` reads (it skips `id` and `contact_force`, which are there for the
//! reader); beside it the contacts' history, one row per contact,
//! `first,second,tangential_spring,law_state`, which `placement.contacts` reads. Both files are CSV
//! as demsweep writes every CSV (RFC 4180; the names line, then the values: `pandas.read_csv(path)`),
//! each with its CSVW metadata sidecar (each column's unit, datatype and meaning); what the state is —
//! the run, the time — is in a JSON file beside them.

use std::io::Write;
use std::path::Path;

use super::{Format, RunToExport, State, WriteError};
use crate::output::csv;
use crate::output::guard::Existing;

/// The format's row of [`super::FORMATS`].
pub const FORMAT: Format = Format {
    name: "csv",
    description: "placement CSV that placement.kind = \"file\" reads back (velocities, spins, contacts' history), \
                  with a JSON file of units beside it",
    write_run,
};

/// A column of an exported CSV: name, unit (empty when dimensionless), meaning.
type Column = (&'static str, &'static str, &'static str);

/// The disks' file's columns.
pub const DISK_COLUMNS: [Column; 9] = [
    ("id", "", "disk index, from 0 (the row order)"),
    ("x", "m", "centre x"),
    ("y", "m", "centre y"),
    ("r", "m", "radius"),
    ("vx", "m/s", "velocity x"),
    ("vy", "m/s", "velocity y"),
    ("omega", "rad/s", "angular velocity, counter-clockwise"),
    ("angle", "rad", "rotation angle, counter-clockwise"),
    ("contact_force", "N", "sum of the magnitudes of the contact forces on the disk"),
];

/// The contacts' file's columns.
pub const CONTACT_COLUMNS: [Column; 4] = [
    ("first", "", "a disk, by its id"),
    ("second", "", "a disk by its id, or a wall: -1 floor, -2 left, -3 right, -4 lid"),
    ("tangential_spring", "m", "the tangential spring's elongation"),
    ("law_state", "", "the contact law's state (hysteretic_linear: the largest overlap, m; 0 for other laws)"),
];

/// Writes the names line of `columns`.
fn header(out: &mut dyn Write, columns: &[Column]) -> std::io::Result<()> {
    let names: Vec<&str> = columns.iter().map(|c| c.0).collect();
    csv::write_record(out, &names)
}

/// Writes the CSVW sidecar of the file `name` in `folder` whose columns are `columns` (the disk ids
/// and the contacts' ends are integers, the rest reals).
fn write_metadata(folder: &Path, name: &str, columns: &[Column]) -> Result<(), WriteError> {
    let integer = ["id", "first", "second"];
    let meta: Vec<csv::ColumnMeta> = columns
        .iter()
        .map(|(name, unit, description)| csv::ColumnMeta {
            name: name.to_string(),
            unit: unit.to_string(),
            datatype: if integer.contains(name) { csv::Datatype::Integer } else { csv::Datatype::Double },
            description: description.to_string(),
        })
        .collect();
    csv::write_metadata(&folder.join(name), &meta, Existing::Any).map_err(WriteError::Create)
}

/// Writes each state's `<run>_<label>.csv` (the disks), `<run>_<label>_contacts.csv` and
/// `<run>_<label>.json` (what they hold) into `folder`.
fn write_run(folder: &Path, _: &RunToExport, states: &[State]) -> Result<(), WriteError> {
    states.iter().try_for_each(|state| write_state(folder, state))
}

fn write_state(folder: &Path, state: &State) -> Result<(), WriteError> {
    let s = state.snapshot;
    let stem = format!("{}_{}", state.run, state.label);
    super::write_file(folder, &format!("{stem}.csv"), |out: &mut dyn Write| {
        header(out, &DISK_COLUMNS)?;
        for i in 0..s.x.len() {
            let (x, y, r, vx, vy) = (s.x[i], s.y[i], s.r[i], s.vx[i], s.vy[i]);
            write!(out, "{i},{x},{y},{r},{vx},{vy},{},{},{}\r\n", s.omega[i], s.angle[i], s.contact_force[i])?;
        }
        Ok(())
    })?;
    write_metadata(folder, &format!("{stem}.csv"), &DISK_COLUMNS)?;
    let c = &s.contacts;
    super::write_file(folder, &format!("{stem}_contacts.csv"), |out: &mut dyn Write| {
        header(out, &CONTACT_COLUMNS)?;
        for k in 0..c.len() {
            write!(out, "{},{},{},{}\r\n", c.first[k], c.second[k], c.tangential_spring[k], c.law_state[k])?;
        }
        Ok(())
    })?;
    write_metadata(folder, &format!("{stem}_contacts.csv"), &CONTACT_COLUMNS)?;
    let table = |file: String, rows: usize, columns: &[Column]| {
        let columns: Vec<_> = columns
            .iter()
            .map(
                |(name, unit, description)| serde_json::json!({"name": name, "unit": unit, "description": description}),
            )
            .collect();
        serde_json::json!({"file": file, "rows": rows, "columns": columns})
    };
    let sidecar = serde_json::json!({
        "written_by": "demsweep export --format csv",
        "run": state.run,
        "state": state.label,
        "time": s.time,
        "time_unit": "s",
        "disks": table(format!("{stem}.csv"), s.x.len(), &DISK_COLUMNS),
        "contacts": table(format!("{stem}_contacts.csv"), c.len(), &CONTACT_COLUMNS),
    });
    super::write_file(folder, &format!("{stem}.json"), |out: &mut dyn Write| {
        serde_json::to_writer_pretty(&mut *out, &sidecar).map_err(std::io::Error::other)?;
        writeln!(out)
    })
}
