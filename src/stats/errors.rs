//! Why a comparison or a points view cannot be made: the point, metric or tolerance asked for, and
//! what there is instead. The text is made by [`std::fmt::Display`].

use std::fmt;

use crate::physics::quantity;

/// A metric asked for that a table does not have.
#[derive(Clone, Debug, PartialEq)]
pub struct UnknownMetric {
    /// The metric asked for.
    pub metric: String,
    /// Whether it is a per-run quantity that the file was written before.
    pub predates: bool,
    /// The metric it most likely means, when one is near.
    pub nearest: Option<String>,
    /// The metrics there are.
    pub known: Vec<String>,
}

impl UnknownMetric {
    /// `metric`, missing from the metrics `known`.
    pub fn new(metric: &str, known: &[&str]) -> Self {
        Self {
            metric: metric.to_string(),
            predates: quantity::find(metric).is_some(),
            nearest: crate::study::nearest(metric, known.iter().copied()).map(String::from),
            known: known.iter().map(ToString::to_string).collect(),
        }
    }

    /// Why the metric is missing, in words.
    fn why(&self) -> &'static str {
        if self.predates {
            "this file was written before it existed"
        } else {
            "not a per-run quantity or numeric summary column"
        }
    }

    /// The metric meant, else the list of those there are (after `list`).
    fn hint(&self, list: &str) -> String {
        match &self.nearest {
            Some(meant) => format!("did you mean `{meant}`?"),
            None => format!("{list}: {}", self.known.join(", ")),
        }
    }
}

/// In a points table (`summary --by-point --metrics`).
impl fmt::Display for UnknownMetric {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "no metric `{}` in the points table ({}); {}", self.metric, self.why(), self.hint("the metrics are"))
    }
}

impl std::error::Error for UnknownMetric {}

/// Why `demsweep compare` cannot compare, or a tolerance cannot be read.
#[derive(Clone, Debug, PartialEq)]
pub enum CompareError {
    /// A tolerance not written `METRIC=TOL`.
    NotTolerance(String),
    /// A tolerance whose value is not a number.
    NotANumber {
        /// The value.
        value: String,
        /// The whole tolerance.
        text: String,
    },
    /// A tolerance that is not a positive finite number.
    NotPositive {
        /// Its metric.
        metric: String,
        /// Its value, as written.
        value: String,
    },
    /// A kept metric the file does not have.
    UnknownMetric(UnknownMetric),
    /// No metric kept by default is in the file (the numeric columns there are).
    NoDefaultMetrics(Vec<String>),
    /// A run id whose run belongs to no point.
    RunWithoutPoint(String),
    /// A part of the point's name that is neither a run id nor `KEY=VALUE`.
    NotKeyValue(String),
    /// No point named (the points there are, by label).
    NoReference(Vec<String>),
    /// No point has the values named (the points there are).
    NoMatch {
        /// The values named.
        spec: String,
        /// The points there are.
        points: Vec<String>,
    },
    /// Several points have the values named.
    Ambiguous {
        /// The values named.
        spec: String,
        /// The points that have them.
        matches: Vec<String>,
    },
    /// The placement seed named as a coordinate (a point holds every seed).
    SeedNamed(&'static str),
    /// A key that is not a swept parameter.
    NotSwept {
        /// The key.
        key: String,
        /// The parameter it most likely means.
        nearest: Option<String>,
        /// The swept parameters.
        swept: Vec<String>,
    },
}

impl fmt::Display for CompareError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let listing = |labels: &[String]| labels.iter().map(|label| format!("\n  {label}")).collect::<String>();
        match self {
            CompareError::NotTolerance(text) => {
                write!(f, "`{text}` is not METRIC=TOL (e.g. packing_fraction_interior=0.01)")
            }
            CompareError::NotANumber { value, text } => write!(f, "`{value}` is not a number (in `{text}`)"),
            CompareError::NotPositive { metric, value } => {
                write!(f, "the tolerance of `{metric}` must be a positive relative tolerance, got {value}")
            }
            CompareError::UnknownMetric(unknown) => {
                write!(f, "`{}`: {}; {}", unknown.metric, unknown.why(), unknown.hint("the metrics of this file are"))
            }
            CompareError::NoDefaultMetrics(available) => write!(
                f,
                "this file has none of the default metrics; name some with --keep METRIC=TOL: {}",
                available.join(", ")
            ),
            CompareError::RunWithoutPoint(run) => write!(f, "run {run} has no point"),
            CompareError::NotKeyValue(pair) => write!(
                f,
                "`{pair}` is neither a run id nor KEY=VALUE (e.g. material.restitution=0.5,material.friction=0.6)"
            ),
            CompareError::NoReference(points) => {
                write!(f, "no reference point given; the points are:{}", listing(points))
            }
            CompareError::NoMatch { spec, points } => {
                write!(f, "no point has {spec}; the points are:{}", listing(points))
            }
            CompareError::Ambiguous { spec, matches } => {
                write!(f, "{} points match {spec}; name more swept values:{}", matches.len(), listing(matches))
            }
            CompareError::SeedNamed(seed) => {
                write!(f, "{seed} is not a point coordinate: a point holds every seed (name a run id instead)")
            }
            CompareError::NotSwept { key, nearest: Some(meant), .. } => {
                write!(f, "`{key}` is not a swept parameter; did you mean `{meant}`?")
            }
            CompareError::NotSwept { key, nearest: None, swept } => {
                write!(f, "`{key}` is not a swept parameter; the swept parameters are: {}", swept.join(", "))
            }
        }
    }
}

impl std::error::Error for CompareError {}

impl From<UnknownMetric> for CompareError {
    fn from(unknown: UnknownMetric) -> Self {
        CompareError::UnknownMetric(unknown)
    }
}
