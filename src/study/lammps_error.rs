//! Why a LAMMPS data or dump file gives no disks: the line (and field) and the problem, typed; the
//! text is made by [`std::fmt::Display`], and without the file's content where it may not be quoted.

use std::fmt;

/// A problem with a LAMMPS file at a line (and field) when it has one.
#[derive(Clone, Debug, PartialEq)]
pub struct LammpsError {
    /// The line, from 1.
    pub line: Option<usize>,
    /// The field of the line, from 1.
    pub field: Option<usize>,
    /// What is wrong.
    pub problem: LammpsProblem,
}

/// What is wrong with a LAMMPS file.
#[derive(Clone, Debug, PartialEq)]
pub enum LammpsProblem {
    /// No atom at all.
    NoAtoms,
    /// A data file's `Atoms` section is for another atom style (its name).
    AtomStyle(String),
    /// A line with fewer fields than needed.
    FewFields {
        /// Fields on the line.
        found: usize,
        /// Fields needed.
        expected: usize,
    },
    /// A field that is no finite number (the field as written).
    NotANumber(String),
    /// An atom count that is no whole number ≥ 0.
    AtomCount(f64),
    /// A triclinic box (tilt factors `xy xz yz`): demsweep's box is rectangular.
    Triclinic,
    /// An atom id that is no whole number ≥ 1.
    AtomId(f64),
    /// A diameter or radius ≤ 0.
    NotPositive {
        /// `diameter` or `radius`.
        what: &'static str,
        /// The value.
        value: f64,
    },
    /// An atom id given twice.
    IdTwice {
        /// The id.
        id: u64,
        /// The line it was first given on.
        first: usize,
    },
    /// A data file without its `N atoms` line.
    NoAtomsLine,
    /// A data file without its `Atoms` section.
    NoAtomsSection,
    /// A section whose rows are not as many as the atoms.
    SectionRows {
        /// `Atoms` or `Velocities`.
        section: &'static str,
        /// Its rows.
        rows: usize,
        /// The atoms the header gives.
        atoms: usize,
    },
    /// A `Velocities` row for an atom the `Atoms` section does not have (its id).
    UnknownId(u64),
    /// A dump's last snapshot without an `ITEM:` line (its name).
    NoItem(&'static str),
    /// A dump that ends after an `ITEM:` line (its name).
    EndsAfter(&'static str),
    /// A dump without `ITEM: BOX BOUNDS`.
    NoBoxBounds,
    /// A dump's box bounds, needed to unscale a column (its name), cannot be read.
    Unscale {
        /// The scaled column.
        column: &'static str,
        /// Why the bounds cannot be read.
        cause: Box<LammpsError>,
    },
    /// A dump without a `radius` or `diameter` column in a scene whose radius key (its name) draws radii.
    NoRadii(&'static str),
    /// A dump without a position column.
    NoColumn {
        /// The plain column's name.
        plain: &'static str,
        /// The scaled column's name.
        scaled: &'static str,
    },
    /// A dump's snapshot whose rows are not as many as its atoms.
    SnapshotRows {
        /// Its rows.
        rows: usize,
        /// The atoms its header gives.
        atoms: usize,
    },
}

impl LammpsError {
    /// `problem`, not at a line.
    pub fn new(problem: LammpsProblem) -> Self {
        Self { line: None, field: None, problem }
    }

    /// `problem` at `line`.
    pub fn at(line: usize, problem: LammpsProblem) -> Self {
        Self { line: Some(line), field: None, problem }
    }

    /// Where the problem is (`line 13, field 6`), when it is at a line: all a file whose content may
    /// not be quoted shows.
    pub fn place(&self) -> Option<String> {
        match (self.line, self.field, &self.problem) {
            (Some(line), Some(field), _) => Some(format!("line {line}, field {field}")),
            (Some(line), None, _) => Some(format!("line {line}")),
            (None, _, LammpsProblem::Unscale { cause, .. }) => cause.place(),
            (None, ..) => None,
        }
    }
}

impl fmt::Display for LammpsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.line, &self.problem) {
            (Some(_), problem) => write!(f, "{}: {problem}", self.place().unwrap_or_default()),
            (None, problem) => write!(f, "{problem}"),
        }
    }
}

impl fmt::Display for LammpsProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LammpsProblem::NoAtoms => write!(f, "the file has no atoms"),
            LammpsProblem::AtomStyle(style) => write!(
                f,
                "the Atoms section is for atom_style {style}: placement.kind = \"lammps\" reads atom_style sphere"
            ),
            LammpsProblem::FewFields { found, expected } => write!(f, "{found} fields, expected at least {expected}"),
            LammpsProblem::NotANumber(field) => write!(f, "\"{field}\" is not a number"),
            LammpsProblem::AtomCount(value) => write!(f, "the atom count {value} is not a whole number ≥ 0"),
            LammpsProblem::Triclinic => write!(
                f,
                "a triclinic box (tilt factors xy xz yz): demsweep's box is rectangular, so the tilt would be lost; \
                 write the file from an orthogonal box"
            ),
            LammpsProblem::AtomId(value) => write!(f, "atom id {value} is not a whole number ≥ 1"),
            LammpsProblem::NotPositive { what, value } => write!(f, "the {what} must be > 0, got {value}"),
            LammpsProblem::IdTwice { id, first } => write!(f, "atom id {id} appears twice (first on line {first})"),
            LammpsProblem::NoAtomsLine => write!(f, "no `N atoms` line: not a LAMMPS data file"),
            LammpsProblem::NoAtomsSection => write!(f, "no `Atoms` section"),
            LammpsProblem::SectionRows { section: "Atoms", rows, atoms } => {
                write!(f, "the Atoms section has {rows} row(s), the header says {atoms} atoms")
            }
            LammpsProblem::SectionRows { section, rows, atoms } => {
                write!(f, "the {section} section has {rows} row(s), expected {atoms}")
            }
            LammpsProblem::UnknownId(id) => write!(f, "atom id {id} is not in the Atoms section"),
            LammpsProblem::NoItem(item) => write!(f, "no `ITEM: {item}` in the last snapshot"),
            LammpsProblem::EndsAfter(item) => write!(f, "the file ends after `ITEM: {item}`"),
            LammpsProblem::NoBoxBounds => write!(f, "no `ITEM: BOX BOUNDS`"),
            LammpsProblem::Unscale { column, cause } => write!(f, "{cause}: needed to unscale `{column}`"),
            LammpsProblem::NoRadii(key) => {
                write!(f, "no `radius` or `diameter` column, and {}", drawn_radii(key))
            }
            LammpsProblem::NoColumn { plain, scaled } => write!(f, "no `{plain}` column (nor `{scaled}`)"),
            LammpsProblem::SnapshotRows { rows, atoms } => {
                write!(f, "the snapshot has {rows} atoms, its header says {atoms}")
            }
        }
    }
}

impl std::error::Error for LammpsError {}

/// Why a placement file must give its disks' radii in a scene with the radius key `key`, and what to do.
pub(super) fn drawn_radii(key: &str) -> String {
    format!(
        "{key} draws radii for generated placements only: give every disk's radius in the file, or remove {key} \
         so that every disk gets particles.radius"
    )
}
