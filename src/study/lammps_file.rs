//! LAMMPS placement files (`placement.kind = "lammps"`): the disks of a data file written for
//! `atom_style sphere` (as `demsweep export --format lammps` writes it, or LAMMPS's `write_data`) or
//! of the last snapshot of a `dump custom` file, so that a pile comes back from LAMMPS.
//!
//! Data file: the `Atoms` section (`id type diameter density x y z`, image flags allowed after
//! them) and, when present, `Velocities` (`id vx vy vz wx wy wz`: ω is `wz`). Dump file (its first
//! line `ITEM: TIMESTEP`): the columns `x`, `y` (or `xu`, `yu`; `xs`, `ys` scaled to the box),
//! `radius` or `diameter` (else `particles.radius`), and the optional `id`, `vx`, `vy`, `omegaz`.
//! A data file's first line is its title, whatever it says; a triclinic box is refused (the box is
//! rectangular).
//! Disks are taken in the order of their atom ids; `z` and the rest are not read (the disks lie in
//! the plane), and LAMMPS keeps no rotation angle of a sphere, so every angle starts at 0.

use std::collections::HashMap;
use std::path::Path;

use super::csv_error::PlacementFileError;
use super::initial_csv::{MissingRadius, Quoting};
use super::lammps_error::{LammpsError, LammpsProblem};
use crate::physics::config::PlacementKind;
use crate::physics::particles::InitialDisk;

/// Reads the disks of a placement file of `kind`: a LAMMPS data or dump file ([`read`]), else a
/// CSV ([`super::initial_csv::read`]); `missing`: what a disk without a radius in the file gets.
pub fn read_placement(
    kind: PlacementKind,
    path: &Path,
    missing: MissingRadius,
    folder: &Path,
) -> Result<Vec<InitialDisk>, PlacementFileError> {
    match kind {
        PlacementKind::Lammps => read(path, missing, folder),
        _ => super::initial_csv::read(path, missing, folder),
    }
}

/// Reads the disks of a LAMMPS data or dump file (a regular file of at most the size of a placement
/// CSV); errors name the file and line, and say what is wrong only when the file lies in the study's
/// `folder` (see [`Quoting`]).
pub fn read(
    path: &Path,
    missing: impl Into<MissingRadius>,
    folder: &Path,
) -> Result<Vec<InitialDisk>, PlacementFileError> {
    let text = super::initial_csv::read_text(path)?;
    parse(&text, missing).map_err(|error| PlacementFileError::Lammps {
        path: path.to_path_buf(),
        error: Box::new(error),
        quoted: Quoting::of(path, folder) == Quoting::Quoted,
    })
}

/// Parses a LAMMPS data file, or a dump file when its first line is `ITEM: TIMESTEP`; `missing`:
/// what a disk of a dump without radii gets.
pub fn parse(text: &str, missing: impl Into<MissingRadius>) -> Result<Vec<InitialDisk>, LammpsError> {
    let lines = numbered(text);
    let disks = if lines.first().is_some_and(|(_, l)| l.starts_with("ITEM:")) {
        dump(&lines, missing.into())?
    } else {
        atom_style_sphere(text)?;
        let after_title: Vec<(usize, &str)> = lines.into_iter().filter(|(number, _)| *number > 1).collect();
        data(&after_title)?
    };
    if disks.is_empty() {
        return Err(LammpsError::new(LammpsProblem::NoAtoms));
    }
    Ok(disks)
}

/// Refuses a data file whose `Atoms` section names an atom style other than `sphere` (the columns
/// differ); a section without a style is read as `sphere`. The first line is the title, whatever it says.
fn atom_style_sphere(text: &str) -> Result<(), LammpsError> {
    let style =
        text.lines().skip(1).find_map(|l| l.trim().strip_prefix("Atoms")).and_then(|rest| rest.split('#').nth(1));
    match style.map(str::trim) {
        Some(style) if !style.is_empty() && style != "sphere" => {
            Err(LammpsError::new(LammpsProblem::AtomStyle(style.to_string())))
        }
        _ => Ok(()),
    }
}

/// The lines that hold something (comments after `#` removed), trimmed, with their 1-based numbers.
fn numbered(text: &str) -> Vec<(usize, &str)> {
    text.lines()
        .enumerate()
        .map(|(k, line)| (k + 1, line.split('#').next().unwrap_or("").trim()))
        .filter(|(_, line)| !line.is_empty())
        .collect()
}

/// The numbers of a line's first `count` fields; the error names the line and field.
fn numbers(number: usize, line: &str, count: usize) -> Result<Vec<f64>, LammpsError> {
    let fields: Vec<&str> = line.split_whitespace().collect();
    if fields.len() < count {
        return Err(LammpsError::at(number, LammpsProblem::FewFields { found: fields.len(), expected: count }));
    }
    fields[..count]
        .iter()
        .enumerate()
        .map(|(k, f)| {
            let value = f.parse::<f64>().ok().filter(|v| v.is_finite());
            let problem = || LammpsProblem::NotANumber(f.to_string());
            value.ok_or_else(|| LammpsError { field: Some(k + 1), ..LammpsError::at(number, problem()) })
        })
        .collect()
}

/// An atom id: a whole number ≥ 1.
fn atom_id(number: usize, value: f64) -> Result<u64, LammpsError> {
    if value >= 1.0 && value.fract() == 0.0 && value < 1e15 {
        Ok(value as u64)
    } else {
        Err(LammpsError::at(number, LammpsProblem::AtomId(value)))
    }
}

/// An atom count: a whole number ≥ 0; the error names the line.
fn atom_count(number: usize, value: f64) -> Result<usize, LammpsError> {
    if value >= 0.0 && value.fract() == 0.0 && value < 1e15 {
        Ok(value as usize)
    } else {
        Err(LammpsError::at(number, LammpsProblem::AtomCount(value)))
    }
}

/// A disk's radius from a diameter or radius column; the error names the line.
fn positive(number: usize, what: &'static str, value: f64) -> Result<f64, LammpsError> {
    if value > 0.0 { Ok(value) } else { Err(LammpsError::at(number, LammpsProblem::NotPositive { what, value })) }
}

/// An error naming the first atom id given twice among `atoms` (line, id, disk).
fn unique(atoms: &[(usize, u64, InitialDisk)]) -> Result<(), LammpsError> {
    let mut seen: HashMap<u64, usize> = HashMap::new();
    for (number, id, _) in atoms {
        if let Some(first) = seen.insert(*id, *number) {
            return Err(LammpsError::at(*number, LammpsProblem::IdTwice { id: *id, first }));
        }
    }
    Ok(())
}

/// The disks of `atoms` in the order of their ids (which [`unique`] has checked).
fn by_id(mut atoms: Vec<(usize, u64, InitialDisk)>) -> Vec<InitialDisk> {
    atoms.sort_by_key(|(_, id, _)| *id);
    atoms.into_iter().map(|(_, _, disk)| disk).collect()
}

/// Whether a data file line starts a section (a capitalised word and nothing numeric).
fn section_name(line: &str) -> Option<&str> {
    let first = line.split_whitespace().next()?;
    (first.chars().next()?.is_ascii_uppercase() && first.parse::<f64>().is_err()).then_some(line)
}

/// The disks of a data file (its lines after the title): its `Atoms` section for `atom_style
/// sphere`, with `Velocities`.
fn data(lines: &[(usize, &str)]) -> Result<Vec<InitialDisk>, LammpsError> {
    let header_count = |word: &str| {
        lines.iter().find(|(_, l)| l.split_whitespace().nth(1) == Some(word) && l.split_whitespace().count() == 2)
    };
    let Some(&(count_line, count_text)) = header_count("atoms") else {
        return Err(LammpsError::new(LammpsProblem::NoAtomsLine));
    };
    let count = atom_count(count_line, numbers(count_line, count_text, 1)?[0])?;
    if let Some(&(tilt_line, _)) = lines.iter().find(|(_, l)| l.ends_with("xy xz yz")) {
        return Err(LammpsError::at(tilt_line, LammpsProblem::Triclinic));
    }
    let section = |name: &str| {
        let start =
            lines.iter().position(|(_, l)| section_name(l).is_some_and(|s| s.split_whitespace().next() == Some(name)));
        start.map(|k| {
            let body = &lines[k + 1..];
            let end = body.iter().position(|(_, l)| section_name(l).is_some()).unwrap_or(body.len());
            (lines[k], &body[..end])
        })
    };
    let Some(((atoms_line, _), rows)) = section("Atoms") else {
        return Err(LammpsError::new(LammpsProblem::NoAtomsSection));
    };
    if rows.len() != count {
        let problem = LammpsProblem::SectionRows { section: "Atoms", rows: rows.len(), atoms: count };
        return Err(LammpsError::at(atoms_line, problem));
    }
    let mut atoms = Vec::with_capacity(count);
    for &(number, line) in rows {
        let row = numbers(number, line, 7)?; // id type diameter density x y z
        let r = positive(number, "diameter", row[2])? / 2.0;
        let disk = InitialDisk { x: row[4], y: row[5], r, vx: 0.0, vy: 0.0, omega: 0.0, angle: 0.0 };
        atoms.push((number, atom_id(number, row[0])?, disk));
    }
    unique(&atoms)?;
    if let Some(((velocities_line, _), rows)) = section("Velocities") {
        let index: HashMap<u64, usize> = atoms.iter().enumerate().map(|(k, (_, id, _))| (*id, k)).collect();
        if rows.len() != count {
            let problem = LammpsProblem::SectionRows { section: "Velocities", rows: rows.len(), atoms: count };
            return Err(LammpsError::at(velocities_line, problem));
        }
        for &(number, line) in rows {
            let row = numbers(number, line, 7)?; // id vx vy vz wx wy wz
            let id = atom_id(number, row[0])?;
            let k = *index.get(&id).ok_or_else(|| LammpsError::at(number, LammpsProblem::UnknownId(id)))?;
            let disk = &mut atoms[k].2;
            (disk.vx, disk.vy, disk.omega) = (row[1], row[2], row[6]);
        }
    }
    Ok(by_id(atoms))
}

/// A disk's coordinate from a dump's row.
type Coordinate = Box<dyn Fn(&[f64]) -> f64>;

/// The index and name of the first of `options` among a dump's column `names`.
fn find_column(names: &[&str], options: &[&'static str]) -> Option<(usize, &'static str)> {
    options.iter().find_map(|o| names.iter().position(|n| n == o).map(|k| (k, *o)))
}

/// The disks of a dump file's last snapshot.
fn dump(lines: &[(usize, &str)], missing: MissingRadius) -> Result<Vec<InitialDisk>, LammpsError> {
    const COUNT: &str = "NUMBER OF ATOMS";
    let last = lines.iter().rposition(|(_, l)| l.starts_with("ITEM: TIMESTEP")).unwrap_or(0);
    let snapshot = &lines[last..];
    let item = |name: &'static str| {
        let at = snapshot.iter().position(|(_, l)| l.starts_with(&format!("ITEM: {name}")));
        at.ok_or(LammpsError::new(LammpsProblem::NoItem(name)))
    };
    let count_at = item(COUNT)?;
    let &(count_line, count_text) =
        snapshot.get(count_at + 1).ok_or(LammpsError::new(LammpsProblem::EndsAfter(COUNT)))?;
    let count = atom_count(count_line, numbers(count_line, count_text, 1)?[0])?;
    let bounds_at = item("BOX BOUNDS").ok();
    if let Some(&(tilt_line, _)) = bounds_at.map(|k| &snapshot[k]).filter(|(_, l)| l.contains(" xy ")) {
        return Err(LammpsError::at(tilt_line, LammpsProblem::Triclinic));
    }
    let bound = |axis: usize| -> Result<(f64, f64), LammpsError> {
        let bounds = bounds_at.and_then(|k| snapshot.get(k + 1 + axis));
        let &(number, line) = bounds.ok_or(LammpsError::new(LammpsProblem::NoBoxBounds))?;
        let ends = numbers(number, line, 2)?;
        Ok((ends[0], ends[1]))
    };
    let atoms_at = item("ATOMS")?;
    let (atoms_line, header) = snapshot[atoms_at];
    let names: Vec<&str> = header.trim_start_matches("ITEM: ATOMS").split_whitespace().collect();
    let column = |options: &[&'static str]| find_column(&names, options);
    let position =
        |axis: usize, plain: [&'static str; 2], scaled: [&'static str; 2]| -> Result<Coordinate, LammpsError> {
            if let Some((k, _)) = column(&plain) {
                return Ok(Box::new(move |row: &[f64]| row[k]));
            }
            let missing = LammpsProblem::NoColumn { plain: plain[0], scaled: scaled[0] };
            let (k, name) = column(&scaled).ok_or_else(|| LammpsError::at(atoms_line, missing))?;
            let unscale = |cause| LammpsError::new(LammpsProblem::Unscale { column: name, cause: Box::new(cause) });
            let (lo, hi) = bound(axis).map_err(unscale)?;
            Ok(Box::new(move |row: &[f64]| lo + row[k] * (hi - lo)))
        };
    let x = position(0, ["x", "xu"], ["xs", "xsu"])?;
    let y = position(1, ["y", "yu"], ["ys", "ysu"])?;
    let radius = column(&["radius", "diameter"]);
    let default_radius = match (radius, missing) {
        (None, MissingRadius::Drawn(key)) => return Err(LammpsError::at(atoms_line, LammpsProblem::NoRadii(key))),
        (_, MissingRadius::Radius(radius)) => radius,
        (Some(_), MissingRadius::Drawn(_)) => 0.0, // not read: every row gives its radius
    };
    let optional = |name: &'static str| column(&[name]).map(|(k, _)| k);
    let (id, vx, vy, omega) = (optional("id"), optional("vx"), optional("vy"), optional("omegaz"));
    let rows = &snapshot[atoms_at + 1..];
    if rows.len() != count {
        return Err(LammpsError::at(atoms_line, LammpsProblem::SnapshotRows { rows: rows.len(), atoms: count }));
    }
    let mut atoms = Vec::with_capacity(count);
    for (k, &(number, line)) in rows.iter().enumerate() {
        let row = numbers(number, line, names.len())?;
        let r = match radius {
            Some((c, "diameter")) => positive(number, "diameter", row[c])? / 2.0,
            Some((c, _)) => positive(number, "radius", row[c])?,
            None => default_radius,
        };
        let at = |c: Option<usize>| c.map_or(0.0, |c| row[c]);
        let disk = InitialDisk { x: x(&row), y: y(&row), r, vx: at(vx), vy: at(vy), omega: at(omega), angle: 0.0 };
        let atom = match id {
            Some(c) => atom_id(number, row[c])?,
            None => k as u64 + 1,
        };
        atoms.push((number, atom, disk));
    }
    unique(&atoms)?;
    Ok(by_id(atoms))
}

#[cfg(test)]
mod tests {
    use super::*;

    const DATA: &str = "LAMMPS data file from demsweep\n\n2 atoms\n1 atom types\n\n0 0.1 xlo xhi\n0 0.2 ylo yhi\n\
                        -0.01 0.01 zlo zhi\n\nAtoms # sphere\n\n2 1 0.004 2500 0.05 0.03 0 0 0 0\n\
                        1 1 0.01 2500 0.02 0.005 0\n\nVelocities\n\n1 0.5 -1 0 0 0 3\n2 0 0 0 0 0 -2\n";

    #[test]
    fn a_data_file_gives_its_atoms_in_id_order_with_velocities_and_spins() {
        let disks = parse(DATA, 1.0).unwrap();
        assert_eq!(disks.len(), 2);
        let first = InitialDisk { x: 0.02, y: 0.005, r: 0.005, vx: 0.5, vy: -1.0, omega: 3.0, angle: 0.0 };
        assert_eq!(disks[0], first);
        assert_eq!((disks[1].r, disks[1].omega), (0.002, -2.0));
    }

    #[test]
    fn a_dump_file_gives_its_last_snapshot() {
        let dump = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0 0.1\n0 0.2\n-1 1\n\
                    ITEM: ATOMS id x y radius\n1 0.01 0.02 0.003\n\
                    ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n0 0.1\n0 0.2\n-1 1\n\
                    ITEM: ATOMS id type xs ys z diameter vx vy omegaz\n2 1 0.5 0.5 0 0.004 1 2 3\n1 1 0.25 0.1 0 0.006 0 0 0\n";
        let disks = parse(dump, 1.0).unwrap();
        assert_eq!(disks.len(), 2);
        assert_eq!((disks[0].x, disks[0].y, disks[0].r), (0.025, 0.020000000000000004, 0.003));
        assert_eq!((disks[1].x, disks[1].vx, disks[1].vy, disks[1].omega), (0.05, 1.0, 2.0, 3.0));
        let no_radius = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: ATOMS x y\n0.01 0.02\n";
        assert_eq!(parse(no_radius, 0.004).unwrap()[0].r, 0.004, "particles.radius where the dump has none");
    }

    #[test]
    fn errors_name_the_line_and_what_is_wrong() {
        assert!(parse("title\n\n", 1.0).unwrap_err().to_string().contains("no `N atoms` line"));
        let short = DATA.replace("1 1 0.01 2500 0.02 0.005 0\n", "");
        assert!(
            parse(&short, 1.0)
                .unwrap_err()
                .to_string()
                .contains("the Atoms section has 1 row(s), the header says 2 atoms")
        );
        let bad = DATA.replace("0.02 0.005", "0.02 abc");
        assert_eq!(parse(&bad, 1.0).unwrap_err().to_string(), "line 13, field 6: \"abc\" is not a number");
        let atomic = DATA.replace("Atoms # sphere", "Atoms # atomic");
        assert!(parse(&atomic, 1.0).unwrap_err().to_string().contains("for atom_style atomic"));
        let twice = DATA.replace("2 1 0.004", "1 1 0.004");
        assert!(parse(&twice, 1.0).unwrap_err().to_string().contains("atom id 1 appears twice"));
        let flat = DATA.replace("0.01 2500", "0 2500");
        assert!(parse(&flat, 1.0).unwrap_err().to_string().contains("the diameter must be > 0, got 0"));
        let unscaled = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: ATOMS xs ys\n0.1 0.2\n";
        assert!(
            parse(unscaled, 1.0).unwrap_err().to_string().contains("no `ITEM: BOX BOUNDS`: needed to unscale `xs`")
        );
    }

    #[test]
    fn the_first_line_of_a_data_file_is_its_title_whatever_it_says() {
        let read = parse(DATA, 1.0).unwrap();
        for title in ["Atoms # atomic, by hand", "", "# from a script", "2 atoms"] {
            let titled = DATA.replacen("LAMMPS data file from demsweep", title, 1);
            assert_eq!(parse(&titled, 1.0).as_ref(), Ok(&read), "title {title:?}");
        }
    }

    #[test]
    fn a_fractional_atom_count_and_a_triclinic_box_are_refused_at_their_line() {
        let fractional = DATA.replace("2 atoms", "2.5 atoms");
        assert_eq!(
            parse(&fractional, 1.0).unwrap_err().to_string(),
            "line 3: the atom count 2.5 is not a whole number ≥ 0"
        );
        let tilted = DATA.replace("zlo zhi\n", "zlo zhi\n0.05 0 0 xy xz yz\n");
        assert!(parse(&tilted, 1.0).unwrap_err().to_string().starts_with("line 9: a triclinic box"));
        let dump = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS xy xz yz pp pp pp\n0 0.1 0.02\n\
                    0 0.2 0\n-1 1 0\nITEM: ATOMS x y\n0.01 0.02\n";
        assert!(parse(dump, 1.0).unwrap_err().to_string().starts_with("line 5: a triclinic box"));
        let half = dump
            .replace("BOX BOUNDS xy xz yz pp pp pp\n0 0.1 0.02", "BOX BOUNDS pp pp pp\n0 0.1")
            .replace("\n1\n", "\n1.5\n");
        assert_eq!(parse(&half, 1.0).unwrap_err().to_string(), "line 4: the atom count 1.5 is not a whole number ≥ 0");
    }

    #[test]
    fn where_a_problem_is_says_nothing_of_the_file_content() {
        let bad = DATA.replace("0.02 0.005", "0.02 abc");
        assert_eq!(parse(&bad, 1.0).unwrap_err().place().as_deref(), Some("line 13, field 6"));
        let atomic = DATA.replace("Atoms # sphere", "Atoms # atomic");
        assert_eq!(parse(&atomic, 1.0).unwrap_err().place(), None, "the style is the file's own text");
        let bounds = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0\n0 1\n-1 1\n\
                      ITEM: ATOMS xs ys\n0.1 0.2\n";
        assert_eq!(parse(bounds, 1.0).unwrap_err().place().as_deref(), Some("line 6"), "from the bounds' line");
    }
}
