//! Every point against a reference point (`demsweep compare`): equivalence of each kept metric
//! within a relative tolerance, and cost ratios.

use std::str::FromStr;

use super::errors::{CompareError, UnknownMetric};
use super::points::{Points, SEED, plus_minus};
use super::{Decision, Describe, Equivalence, Ratio, equivalence, ratio_interval};
use crate::output::table::{Column, ColumnData, SummaryTable, short_float};
use crate::physics::quantity::{self, PACKING_FRACTION, PILE_HEIGHT};

/// Kept by default when a file has none of [`quantity::kept_by_default`] (files written before the
/// pile metrics).
pub const FALLBACK_KEEP: [(&str, f64); 2] = [(PACKING_FRACTION.name, 0.01), (PILE_HEIGHT.name, 0.01)];

/// Cost columns, the first one present is used: particle-steps, else time steps.
const COST_COLUMNS: [&str; 2] = ["particle_steps", "steps"];

/// Wall-clock time column.
const WALL_TIME: &str = "wall_time";

/// The measured times: the columns that differ between runs of one scene.
const MEASURED_TIMES: [&str; 2] = [WALL_TIME, "cpu_time"];

/// A metric to keep within a relative tolerance: `METRIC=TOL` on the command line.
#[derive(Clone, Debug, PartialEq)]
pub struct Tolerance {
    /// Summary column name.
    pub metric: String,
    /// Relative tolerance (> 0): the margin is `relative × |mean(reference)|`.
    pub relative: f64,
}

impl FromStr for Tolerance {
    type Err = CompareError;

    fn from_str(text: &str) -> Result<Self, CompareError> {
        let (metric, value) = text.split_once('=').ok_or_else(|| CompareError::NotTolerance(text.to_string()))?;
        let relative: f64 = value
            .trim()
            .parse()
            .map_err(|_| CompareError::NotANumber { value: value.to_string(), text: text.to_string() })?;
        if !(relative > 0.0 && relative.is_finite()) {
            return Err(CompareError::NotPositive { metric: metric.to_string(), value: value.to_string() });
        }
        Ok(Self { metric: metric.trim().to_string(), relative })
    }
}

/// A kept metric with its margin at the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Kept {
    /// The metric and its relative tolerance.
    pub tolerance: Tolerance,
    /// Absolute margin: relative tolerance × |mean at the reference|.
    pub margin: f64,
    /// The metric at the reference point.
    pub reference: Describe,
}

/// One point against the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct PointComparison {
    /// The point (index into [`Points`]).
    pub point: usize,
    /// Its number of runs.
    pub n: usize,
    /// The point's mean of each kept metric, in the order of [`Comparison::kept`].
    pub means: Vec<f64>,
    /// The equivalence test of each kept metric, same order.
    pub tests: Vec<Equivalence>,
    /// Cost (particle-steps or steps) relative to the reference, 95 % interval.
    pub cost: Ratio,
    /// Wall time relative to the reference, 95 % interval.
    pub wall_time: Ratio,
}

impl PointComparison {
    /// Whether every kept metric is equivalent.
    pub fn acceptable(&self) -> bool {
        self.tests.iter().all(|t| t.decision == Decision::Equivalent)
    }

    /// The largest |difference| / margin over the kept metrics (below 1: every mean within tolerance).
    pub fn deviation(&self, kept: &[Kept]) -> f64 {
        self.tests.iter().zip(kept).map(|(t, k)| t.difference.abs() / k.margin).fold(f64::NAN, f64::max)
    }
}

/// Every other point against the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// The reference point.
    pub reference: usize,
    /// The metrics kept, with their margins.
    pub kept: Vec<Kept>,
    /// The cost column used (`particle_steps` or `steps`).
    pub cost_column: String,
    /// What was chosen for the user, in words (e.g. the fallback metrics).
    pub notes: Vec<String>,
    /// One entry per point but the reference, in point order.
    pub points: Vec<PointComparison>,
}

/// Compares every point with the reference named by `reference` (see [`find_point`]) on the
/// metrics `keep` (the defaults when empty, see [`quantity::kept_by_default`]). Fails on an unknown or ambiguous
/// point and on a requested metric that is not a numeric column, naming the valid ones.
pub fn compare(points: &Points, reference: &str, keep: &[Tolerance]) -> Result<Comparison, CompareError> {
    let reference = find_point(points, reference)?;
    let (tolerances, mut notes) = choose_metrics(points, keep)?;
    let kept: Vec<Kept> = tolerances
        .into_iter()
        .map(|tolerance| {
            let described = points.describe(reference, &tolerance.metric);
            Kept { margin: tolerance.relative * described.mean.abs(), reference: described, tolerance }
        })
        .collect();
    let available = points.metric_names();
    let cost_column = COST_COLUMNS.iter().find(|c| available.contains(c)).copied().unwrap_or(COST_COLUMNS[1]);
    if points.rows(reference).len() < 2 {
        notes.push("the reference has fewer than 2 runs: every decision is undecided (add replicates)".into());
    }
    notes.extend(copies_note(points));
    let ratio =
        |point: usize, column: &str| ratio_interval(&points.values(reference, column), &points.values(point, column));
    let compared = (0..points.len())
        .filter(|&p| p != reference)
        .map(|point| {
            let values = |k: &Kept| points.values(point, &k.tolerance.metric);
            PointComparison {
                point,
                n: points.rows(point).len(),
                means: kept.iter().map(|k| super::describe(&values(k)).mean).collect(),
                tests: kept
                    .iter()
                    .map(|k| equivalence(&points.values(reference, &k.tolerance.metric), &values(k), k.margin))
                    .collect(),
                cost: ratio(point, cost_column),
                wall_time: ratio(point, WALL_TIME),
            }
        })
        .collect();
    Ok(Comparison { reference, kept, cost_column: cost_column.to_string(), notes, points: compared })
}

/// A note naming the points whose runs are copies of one run: two or more that agree exactly in
/// every column but the measured times (their seeds replicated nothing: a placement that does not
/// draw from `placement.seed`), so that their decisions rest on zero variance, not on evidence.
fn copies_note(points: &Points) -> Option<String> {
    let metrics: Vec<&str> = points.metric_names().into_iter().filter(|m| !MEASURED_TIMES.contains(m)).collect();
    let copies = |p: usize| {
        let columns: Vec<Vec<f64>> =
            metrics.iter().map(|m| points.values(p, m).into_iter().filter(|v| v.is_finite()).collect()).collect();
        columns.iter().any(|c| c.len() >= 2) && columns.iter().all(|c| c.iter().all(|v| *v == c[0]))
    };
    let labels: Vec<String> = (0..points.len()).filter(|&p| copies(p)).map(|p| points.label(p)).collect();
    (!labels.is_empty()).then(|| {
        format!(
            "the runs of {} are copies of one run (equal in every column but the times: their seeds replicated \
             nothing, as a placement that does not draw from placement.seed does): their spread of 0 makes \
             decisions on zero variance, not on evidence",
            labels.join("; ")
        )
    })
}

/// The metrics to keep: `keep` checked against the numeric columns, or the defaults present.
fn choose_metrics(points: &Points, keep: &[Tolerance]) -> Result<(Vec<Tolerance>, Vec<String>), CompareError> {
    let available = points.metric_names();
    if let Some(unknown) = keep.iter().find(|t| !available.contains(&t.metric.as_str())) {
        return Err(UnknownMetric::new(&unknown.metric, &available).into());
    }
    if !keep.is_empty() {
        return Ok((keep.to_vec(), Vec::new()));
    }
    // A column without a single finite value is a metric the file predates (read back as NaN).
    let measured = |m: &str| (0..points.len()).any(|p| points.values(p, m).iter().any(|v| v.is_finite()));
    let present = |set: &[(&str, f64)]| -> Vec<Tolerance> {
        set.iter()
            .filter(|(m, _)| available.contains(m) && measured(m))
            .map(|(m, r)| Tolerance { metric: m.to_string(), relative: *r })
            .collect()
    };
    let default: Vec<(&str, f64)> = quantity::kept_by_default().collect();
    let chosen = present(&default);
    if !chosen.is_empty() {
        return Ok((chosen, Vec::new()));
    }
    let fallback = present(&FALLBACK_KEEP);
    if fallback.is_empty() {
        return Err(CompareError::NoDefaultMetrics(available.iter().map(ToString::to_string).collect()));
    }
    let names: Vec<&str> = default.iter().map(|(m, _)| *m).collect();
    let used: Vec<&str> = fallback.iter().map(|t| t.metric.as_str()).collect();
    let note = format!(
        "this file has none of the pile metrics {} (written before they existed): keeping {} instead",
        names.join(", "),
        used.join(", ")
    );
    Ok((fallback, vec![note]))
}

/// The point named by `spec`: a run id (the point of that run), or swept values
/// `key=value,key=value` (a key may be shortened to its last part, e.g. `restitution=0.5`) that
/// match exactly one point. Numbers match within a relative 1e-9.
pub fn find_point(points: &Points, spec: &str) -> Result<usize, CompareError> {
    let labels = |list: &mut dyn Iterator<Item = usize>| list.map(|p| points.label(p)).collect::<Vec<_>>();
    if let Some(ids) = points.summary().column("run_id")
        && let Some(row) = (0..ids.data.len()).find(|&i| ids.data.text(i) == spec.trim())
    {
        let point = (0..points.len()).find(|&p| points.rows(p).contains(&row));
        return point.ok_or_else(|| CompareError::RunWithoutPoint(spec.to_string()));
    }
    let mut wanted = Vec::new();
    for pair in spec.split(',').filter(|p| !p.trim().is_empty()) {
        let (key, value) = pair.split_once('=').ok_or_else(|| CompareError::NotKeyValue(pair.to_string()))?;
        wanted.push((coordinate_name(points, key.trim())?, value.trim()));
    }
    if wanted.is_empty() {
        return Err(CompareError::NoReference(labels(&mut (0..points.len()))));
    }
    let matches: Vec<usize> = (0..points.len())
        .filter(|&p| wanted.iter().all(|(key, value)| coordinate_matches(points, p, key, value)))
        .collect();
    match matches[..] {
        [point] => Ok(point),
        [] => Err(CompareError::NoMatch { spec: spec.to_string(), points: labels(&mut (0..points.len())) }),
        _ => Err(CompareError::Ambiguous { spec: spec.to_string(), matches: labels(&mut matches.into_iter()) }),
    }
}

/// The coordinate named `key`: its full key path or a unique last part of it.
fn coordinate_name(points: &Points, key: &str) -> Result<String, CompareError> {
    let names: Vec<&str> = points.coordinates().iter().map(|c| c.name.as_str()).collect();
    if key == SEED {
        return Err(CompareError::SeedNamed(SEED));
    }
    if names.contains(&key) {
        return Ok(key.to_string());
    }
    let suffix = format!(".{key}");
    match names.iter().filter(|n| n.ends_with(&suffix)).collect::<Vec<_>>()[..] {
        [name] => Ok(name.to_string()),
        _ => Err(CompareError::NotSwept {
            key: key.to_string(),
            nearest: crate::study::nearest(key, names.iter().copied()).map(String::from),
            swept: names.iter().map(ToString::to_string).collect(),
        }),
    }
}

/// Whether coordinate `key` of `point` has the value written `value`.
fn coordinate_matches(points: &Points, point: usize, key: &str, value: &str) -> bool {
    let number = match value {
        "true" => Some(1.0),
        "false" => Some(0.0),
        _ => value.parse::<f64>().ok(),
    };
    match (points.coordinate(point, key), number) {
        (Some(have), Some(want)) => (have - want).abs() <= 1e-9 * have.abs().max(want.abs()),
        _ => points.coordinate_text(point, key).as_deref() == Some(value),
    }
}

impl Comparison {
    /// The comparison as a table for spreadsheets: one row per point and kept metric, with the
    /// point's coordinates, `n`, the metric, its tolerance and margin, the reference and point
    /// means, the difference with its 90 % interval, the decision and seeds needed, the cost and
    /// wall-time ratios with their 95 % intervals, and whether the point is acceptable.
    pub fn table(&self, points: &Points) -> SummaryTable {
        let rows = self.pairs();
        let floats = |f: &dyn Fn(&PointComparison, usize) -> f64| {
            ColumnData::Float(rows.iter().map(|&(p, k)| f(p, k)).collect())
        };
        let texts = |f: &dyn Fn(&PointComparison, usize) -> String| {
            ColumnData::Text(rows.iter().map(|&(p, k)| f(p, k)).collect())
        };
        let mut columns = points.coordinate_columns(&rows.iter().map(|(p, _)| p.point).collect::<Vec<_>>());
        let cost = &self.cost_column;
        let named = [
            ("n", ColumnData::Int(rows.iter().map(|(p, _)| p.n as i64).collect())),
            ("metric", texts(&|_, k| self.kept[k].tolerance.metric.clone())),
            ("tolerance", floats(&|_, k| self.kept[k].tolerance.relative)),
            ("margin", floats(&|_, k| self.kept[k].margin)),
            ("reference_mean", floats(&|_, k| self.kept[k].reference.mean)),
            ("mean", floats(&|p, k| p.means[k])),
            ("difference", floats(&|p, k| p.tests[k].difference)),
            ("difference_low_90", floats(&|p, k| p.tests[k].low)),
            ("difference_high_90", floats(&|p, k| p.tests[k].high)),
            ("decision", texts(&|p, k| p.tests[k].decision.as_str().to_string())),
            ("seeds_needed", texts(&|p, k| p.tests[k].seeds_needed.map_or(String::new(), |n| n.to_string()))),
            (&format!("{cost}_ratio"), floats(&|p, _| p.cost.ratio)),
            (&format!("{cost}_ratio_low_95"), floats(&|p, _| p.cost.low)),
            (&format!("{cost}_ratio_high_95"), floats(&|p, _| p.cost.high)),
            ("wall_time_ratio", floats(&|p, _| p.wall_time.ratio)),
            ("wall_time_ratio_low_95", floats(&|p, _| p.wall_time.low)),
            ("wall_time_ratio_high_95", floats(&|p, _| p.wall_time.high)),
            ("acceptable", ColumnData::Bool(rows.iter().map(|(p, _)| p.acceptable()).collect())),
        ];
        columns.extend(named.into_iter().map(|(name, data)| Column { name: name.to_string(), data }));
        SummaryTable { columns }
    }

    /// Every (point, kept metric index) pair, point by point.
    fn pairs(&self) -> Vec<(&PointComparison, usize)> {
        self.points.iter().flat_map(|p| (0..self.kept.len()).map(move |k| (p, k))).collect()
    }

    /// The tables printed by `demsweep compare`: the decisions (one row per point and metric) and
    /// the costs (one row per point), all text.
    pub fn printed(&self, points: &Points) -> (SummaryTable, SummaryTable) {
        let text = |name: &str, cells: Vec<String>| Column { name: name.to_string(), data: ColumnData::Text(cells) };
        let pairs = self.pairs();
        let cells = |f: &dyn Fn(&PointComparison, usize) -> String| pairs.iter().map(|&(p, k)| f(p, k)).collect();
        let mut decisions = points.coordinate_columns(&pairs.iter().map(|(p, _)| p.point).collect::<Vec<_>>());
        decisions.extend([
            text("n", cells(&|p, _| p.n.to_string())),
            text("metric", cells(&|_, k| self.kept[k].tolerance.metric.clone())),
            text("mean", cells(&|p, k| plus_minus(Some(p.means[k]), None))),
            text("difference", cells(&|p, k| signed(p.tests[k].difference))),
            text("90% interval", cells(&|p, k| interval(p.tests[k].low, p.tests[k].high, signed))),
            text("margin", cells(&|_, k| format!("±{}", short_float(self.kept[k].margin)))),
            text("decision", cells(&|p, k| p.tests[k].decision.as_str().to_string())),
            text("seeds", cells(&|p, k| p.tests[k].seeds_needed.map_or(String::new(), |n| n.to_string()))),
        ]);
        let per_point = |f: &dyn Fn(&PointComparison) -> String| self.points.iter().map(f).collect();
        let mut costs = points.coordinate_columns(&self.points.iter().map(|p| p.point).collect::<Vec<_>>());
        costs.extend([
            text("n", per_point(&|p| p.n.to_string())),
            text(&format!("{} ratio [95%]", self.cost_column), per_point(&|p| ratio(&p.cost))),
            text("wall time ratio [95%]", per_point(&|p| ratio(&p.wall_time))),
            text("max |diff|/margin", per_point(&|p| plus_minus(Some(p.deviation(&self.kept)), None))),
            text("acceptable", per_point(&|p| if p.acceptable() { "yes" } else { "no" }.to_string())),
        ]);
        (SummaryTable { columns: decisions }, SummaryTable { columns: costs })
    }
}

/// A number with its sign: `+0.0012`, `-0.031`.
fn signed(x: f64) -> String {
    let text = short_float(x);
    if x > 0.0 { format!("+{text}") } else { text }
}

/// `[low, high]`, or `-` when the interval is unknown.
fn interval(low: f64, high: f64, show: impl Fn(f64) -> String) -> String {
    if low.is_finite() && high.is_finite() { format!("[{}, {}]", show(low), show(high)) } else { "-".to_string() }
}

/// `1.16 [0.98, 1.35]`: the ratio and its 95 % interval, rounded to two significant digits of the
/// interval's half-width ([`super::points::rounded`]).
pub fn ratio(r: &Ratio) -> String {
    if !(r.low.is_finite() && r.high.is_finite()) {
        return plus_minus(Some(r.ratio), None);
    }
    let (_, digit) = super::points::rounded(1.0, (r.high - r.low) / 2.0);
    let at = |x: f64| super::points::at_digit(x, digit);
    format!("{} {}", at(r.ratio), interval(r.low, r.high, at))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratios_are_rounded_to_their_interval() {
        assert_eq!(ratio(&Ratio { ratio: 1.16, low: 0.9834, high: 1.3467 }), "1.16 [0.98, 1.35]");
        assert_eq!(ratio(&Ratio { ratio: 0.85123, low: 0.8411, high: 0.8613 }), "0.851 [0.841, 0.861]");
        assert_eq!(ratio(&Ratio { ratio: 0.85123, low: f64::NAN, high: f64::NAN }), "0.85123");
    }

    #[test]
    fn cost_columns_are_declared_quantities() {
        assert!(COST_COLUMNS.iter().chain([&WALL_TIME]).all(|c| quantity::find(c).is_some()));
    }
}
