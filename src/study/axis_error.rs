//! Why a sweep axis, zip group, replicate count or tune lever range cannot be read: the values
//! involved, typed; [`std::fmt::Display`] makes the reason a study problem shows. The spacing of a
//! range is here, below the axes that read ranges, so that the errors can name it.

use std::fmt;

use crate::physics::number::exact;

/// How a range table spaces its values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Spacing {
    /// Evenly.
    Linear,
    /// Evenly in log scale (both ends > 0).
    Log,
}

impl Spacing {
    /// The key naming it in a range table.
    pub fn key(self) -> &'static str {
        match self {
            Spacing::Linear => "linear",
            Spacing::Log => "log",
        }
    }
}

/// What was written where a number of replicates belongs.
#[derive(Clone, Debug, PartialEq)]
pub enum Written {
    /// An integer out of range.
    Integer(i64),
    /// A value of another TOML type (its name).
    Other(&'static str),
}

/// Why an axis, zip group, replicate count or lever range cannot be read.
#[derive(Clone, Debug, PartialEq)]
pub enum AxisError {
    /// `replicates` is no integer from 1 to `max`.
    Replicates {
        /// What was written.
        written: Written,
        /// The most replicates (the most runs).
        max: usize,
    },
    /// A list axis without values.
    EmptyAxis,
    /// A list lever without values.
    EmptyLever,
    /// Neither a list nor a range table: what such a value looks like, and the TOML type found.
    Shape {
        /// What an axis or lever looks like.
        shape: &'static str,
        /// The TOML type written.
        found: &'static str,
    },
    /// A list value that is no number, boolean or string (its TOML type).
    NotScalar(&'static str),
    /// A range table's key that is not one of its keys.
    UnknownKey {
        /// The key.
        key: String,
        /// The valid key it most likely means.
        nearest: Option<String>,
        /// What a range table looks like.
        shape: &'static str,
    },
    /// A range table with both or neither of `linear` and `log`.
    OneSpacing {
        /// What a range table looks like.
        shape: &'static str,
    },
    /// A range's ends that are not two finite numbers.
    Ends {
        /// `linear` or `log`.
        spacing: Spacing,
        /// The ends as written; None when they are numbers, but not finite.
        written: Option<toml::Value>,
    },
    /// A log range with an end ≤ 0.
    LogEnds {
        /// The first end.
        a: f64,
        /// The second end.
        b: f64,
    },
    /// A lever range whose ends do not increase.
    Decreasing {
        /// `linear` or `log`.
        spacing: Spacing,
        /// The first end.
        low: f64,
        /// The second end.
        high: f64,
    },
    /// `steps` below 1.
    StepsBelowOne(i64),
    /// `steps` that is no integer.
    StepsNotInteger,
    /// A range without `steps`.
    NoSteps(Spacing),
    /// `steps = 1` with ends that differ.
    OneStep {
        /// The first end.
        a: f64,
        /// The second end.
        b: f64,
    },
    /// More steps than `max`.
    TooManySteps {
        /// The steps asked for.
        steps: usize,
        /// The most steps (the most runs).
        max: usize,
    },
    /// `zip` that is no list of names or of lists of names.
    ZipShape,
    /// A zip group's member that is no string.
    ZipName,
    /// A zip group's member that names no axis.
    ZipUnknown(String),
    /// An axis in two zip groups.
    ZipTwice(String),
    /// A zip group of fewer than two axes (their keys).
    ZipTooSmall(Vec<String>),
    /// An axis twice in one zip group (the group's keys).
    ZipRepeated(Vec<String>),
    /// Zipped axes of different lengths (each axis's key and length).
    ZipLengths(Vec<(String, usize)>),
    /// A sweep of more than `max` runs.
    TooManyRuns {
        /// The most runs one study may have.
        max: usize,
    },
}

/// "an array", "a table", ...
fn with_article(name: &str) -> String {
    let article = if name.starts_with(['a', 'e', 'i', 'o', 'u']) { "an" } else { "a" };
    format!("{article} {name}")
}

impl fmt::Display for AxisError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AxisError::Replicates { written: Written::Integer(k), max } => {
                write!(f, "must be an integer from 1 to {max}, got {k}")
            }
            AxisError::Replicates { written: Written::Other(found), max } => {
                write!(f, "must be an integer from 1 to {max}, got a {found}")
            }
            AxisError::EmptyAxis => write!(f, "an axis needs at least one value, got []"),
            AxisError::EmptyLever => write!(f, "a list lever needs at least one value"),
            AxisError::Shape { shape, found } => write!(f, "{shape}; got a single {found}"),
            AxisError::NotScalar(found) => {
                write!(f, "axis values must be numbers, booleans or strings, found {}", with_article(found))
            }
            AxisError::UnknownKey { key, nearest, shape } => match nearest {
                Some(meant) => write!(f, "unknown key \"{key}\" (did you mean `{meant}`? {shape})"),
                None => write!(f, "unknown key \"{key}\" ({shape})"),
            },
            AxisError::OneSpacing { shape } => write!(f, "exactly one of linear = [a, b] or log = [a, b] ({shape})"),
            AxisError::Ends { spacing, written: Some(value) } => {
                write!(f, "{}: expected two numbers [a, b], got {value}", spacing.key())
            }
            AxisError::Ends { spacing, written: None } => write!(f, "{}: ends must be finite", spacing.key()),
            AxisError::LogEnds { a, b } => write!(f, "log: the ends must be > 0, got [{}, {}]", exact(*a), exact(*b)),
            AxisError::Decreasing { spacing, low, high } => {
                write!(f, "{}: the ends must increase, got [{low}, {high}]", spacing.key())
            }
            AxisError::StepsBelowOne(n) => write!(f, "steps must be at least 1, got {n}"),
            AxisError::StepsNotInteger => write!(f, "steps must be an integer"),
            AxisError::NoSteps(spacing) => write!(f, "{} range needs steps = n (the number of values)", spacing.key()),
            AxisError::OneStep { a, b } => write!(f, "steps = 1 gives a single value, but the ends {a} and {b} differ"),
            AxisError::TooManySteps { steps, max } => write!(f, "steps must be at most {max}, got {steps}"),
            AxisError::ZipShape => write!(f, "zip is a list of axis names [\"a.b\", \"c.d\"] or a list of such lists"),
            AxisError::ZipName => write!(f, "zip groups list axis names (strings)"),
            AxisError::ZipUnknown(name) => write!(f, "\"{name}\" is not a sweep axis"),
            AxisError::ZipTwice(name) => write!(f, "\"{name}\" is in more than one zip group"),
            AxisError::ZipTooSmall(keys) => write!(f, "a zip group pairs at least two axes, got [{}]", keys.join(", ")),
            AxisError::ZipRepeated(keys) => write!(f, "an axis appears twice in the zip group [{}]", keys.join(", ")),
            AxisError::ZipLengths(lengths) => {
                let each: Vec<String> = lengths.iter().map(|(key, n)| format!("{key} has {n}")).collect();
                write!(f, "zipped axes must have equal lengths: {}", each.join(", "))
            }
            AxisError::TooManyRuns { max } => {
                write!(f, "the sweep expands to more than {max} runs; split it into several studies")
            }
        }
    }
}

impl std::error::Error for AxisError {}
