//! What is wrong with data a results file holds, found while reading it back: where it is and what.

use std::fmt;

/// What is wrong with data a results file holds (a run group, a table, a header): where it is and
/// what.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LayoutError {
    /// Where, outermost first (a table, then a field): each shown before the problem, with `: `.
    pub within: Vec<String>,
    /// What is wrong there.
    pub problem: LayoutProblem,
}

/// The kinds of [`LayoutError`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LayoutProblem {
    /// Something is not there (shown as `no WHAT`, e.g. ``no `steps` attribute``).
    Missing(String),
    /// A value of another type than the layout's.
    NotA {
        /// The value (e.g. `` `steps` ``).
        what: String,
        /// What it should be (e.g. `an integer`).
        expected: &'static str,
    },
    /// A declared size no file of this size could hold: what is declared (e.g. `[100] rows of 16 bytes`).
    TooLarge(String),
    /// The HDF5 library cannot read it.
    Hdf5(String),
    /// Values that do not fit together, in words.
    Inconsistent(String),
}

impl LayoutError {
    fn of(problem: LayoutProblem) -> Self {
        Self { within: Vec::new(), problem }
    }

    /// `what` is missing.
    pub fn missing(what: impl Into<String>) -> Self {
        Self::of(LayoutProblem::Missing(what.into()))
    }

    /// `what` is not `expected`.
    pub fn not_a(what: impl Into<String>, expected: &'static str) -> Self {
        Self::of(LayoutProblem::NotA { what: what.into(), expected })
    }

    /// `declared` is more than the file could hold.
    pub fn too_large(declared: impl Into<String>) -> Self {
        Self::of(LayoutProblem::TooLarge(declared.into()))
    }

    /// Values that do not fit together.
    pub fn inconsistent(text: impl Into<String>) -> Self {
        Self::of(LayoutProblem::Inconsistent(text.into()))
    }

    /// The same problem, found within `place`.
    pub fn within(mut self, place: impl Into<String>) -> Self {
        self.within.insert(0, place.into());
        self
    }
}

impl From<hdf5_pure::Error> for LayoutError {
    fn from(error: hdf5_pure::Error) -> Self {
        Self::of(LayoutProblem::Hdf5(error.to_string()))
    }
}

impl fmt::Display for LayoutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for place in &self.within {
            write!(f, "{place}: ")?;
        }
        match &self.problem {
            LayoutProblem::Missing(what) => write!(f, "no {what}"),
            LayoutProblem::NotA { what, expected } => write!(f, "{what} is not {expected}"),
            LayoutProblem::TooLarge(declared) => write!(f, "declares {declared}, more than its file could hold"),
            LayoutProblem::Hdf5(text) | LayoutProblem::Inconsistent(text) => write!(f, "{text}"),
        }
    }
}

impl std::error::Error for LayoutError {}
