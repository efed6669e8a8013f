//! Grid points: the runs of a summary that differ only by placement seed, and their statistics
//! (the `/points` group and `<name>_points.csv`).

use std::collections::HashMap;
use std::path::Path;

use super::errors::UnknownMetric;
use super::{Describe, describe};
use crate::output::table::{Column, ColumnData, SummaryTable, short_float};
use crate::output::{OutputError, SummaryRow, Tables, reader};
use crate::physics::RunStatus;
use crate::physics::quantity;

/// The tables of a results file holding `rows`: the summary and its points table (what the runner
/// hands its sinks at the end of a sweep).
pub fn tables(rows: &[SummaryRow]) -> Tables {
    let summary = SummaryTable::from_rows(rows);
    let points = Points::new(&summary).table();
    Tables { summary, points }
}

/// The points table of a results file: `/points` when the file has it, else computed from the
/// summary (a file written before `/points` existed, or whose writer was killed).
pub fn read(path: &Path) -> Result<SummaryTable, OutputError> {
    let file = reader::open(path)?;
    match reader::points(&file, path)? {
        Some(points) => Ok(points),
        None => Ok(Points::new(&reader::summary(&file, path)?).table()),
    }
}

/// The swept parameter of replicate seeds: runs that differ only in it form one point.
pub const SEED: &str = "placement.seed";

/// Column name suffixes of each metric's statistics in the points table, in order.
const STATISTICS: [&str; 6] = ["n", "mean", "std", "ci95", "min", "max"];

/// The points of a summary table.
///
/// Coordinates are the swept parameter columns except [`SEED`]; metrics are the other numeric
/// columns (floats and integers) except `index` and the parameters. Metric values of runs that
/// failed with an error are left out; those runs still count in `n` and the status counts.
#[derive(Clone, Debug)]
pub struct Points<'a> {
    summary: &'a SummaryTable,
    coordinates: Vec<&'a Column>,
    metrics: Vec<&'a Column>,
    groups: Vec<Vec<usize>>,
}

impl<'a> Points<'a> {
    /// Groups the runs of `summary` into points, in order of their first run.
    pub fn new(summary: &'a SummaryTable) -> Self {
        let parameters = summary.parameters();
        let coordinates: Vec<&Column> = parameters.iter().filter(|c| c.name != SEED).collect();
        let metrics = summary
            .columns
            .iter()
            .filter(|c| c.data.is_numeric() && c.name != "index" && !parameters.iter().any(|p| p.name == c.name))
            .collect();
        let mut groups: Vec<Vec<usize>> = Vec::new();
        let mut index: HashMap<Vec<String>, usize> = HashMap::new();
        for row in 0..summary.len() {
            let key: Vec<String> = coordinates.iter().map(|c| c.data.text(row)).collect();
            let next = groups.len();
            let group = *index.entry(key).or_insert(next);
            if group == next {
                groups.push(Vec::new());
            }
            groups[group].push(row);
        }
        Self { summary, coordinates, metrics, groups }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.groups.len()
    }

    /// Whether there is no point (no run).
    pub fn is_empty(&self) -> bool {
        self.groups.is_empty()
    }

    /// The summary the points were built from.
    pub fn summary(&self) -> &'a SummaryTable {
        self.summary
    }

    /// The coordinate columns of the summary (swept parameters but the seed).
    pub fn coordinates(&self) -> &[&'a Column] {
        &self.coordinates
    }

    /// Names of the metric columns, in summary order.
    pub fn metric_names(&self) -> Vec<&'a str> {
        self.metrics.iter().map(|c| c.name.as_str()).collect()
    }

    /// Rows (in the summary) of the runs of `point`.
    pub fn rows(&self, point: usize) -> &[usize] {
        &self.groups[point]
    }

    /// The values of `metric` over the runs of `point` that did not fail with an error; empty when
    /// there is no such metric.
    pub fn values(&self, point: usize, metric: &str) -> Vec<f64> {
        let Some(column) = self.metrics.iter().find(|c| c.name == metric) else { return Vec::new() };
        let status = self.summary.column("status").map(|c| &c.data);
        let failed = |row: usize| matches!(status, Some(ColumnData::Text(s)) if s[row] == RunStatus::Error.as_str());
        self.groups[point].iter().filter(|&&row| !failed(row)).filter_map(|&row| column.data.number(row)).collect()
    }

    /// The value of coordinate `name` at `point` as text (as in the CSV).
    pub fn coordinate_text(&self, point: usize, name: &str) -> Option<String> {
        let column = self.coordinates.iter().find(|c| c.name == name)?;
        Some(column.data.text(self.groups[point][0]))
    }

    /// The numeric value of coordinate `name` at `point` (booleans as 0 and 1).
    pub fn coordinate(&self, point: usize, name: &str) -> Option<f64> {
        let column = self.coordinates.iter().find(|c| c.name == name)?;
        let row = self.groups[point][0];
        match &column.data {
            ColumnData::Bool(v) => Some(f64::from(u8::from(v[row]))),
            data => data.number(row),
        }
    }

    /// The point in words: `material.restitution=0.5, material.friction=0.6` (`all runs` without
    /// coordinates).
    pub fn label(&self, point: usize) -> String {
        let row = self.groups[point][0];
        let parts: Vec<String> = self.coordinates.iter().map(|c| format!("{}={}", c.name, c.data.text(row))).collect();
        if parts.is_empty() { "all runs".to_string() } else { parts.join(", ") }
    }

    /// The coordinate columns with one row per entry of `points` (the coordinates of that point).
    pub fn coordinate_columns(&self, points: &[usize]) -> Vec<Column> {
        let rows: Vec<usize> = points.iter().map(|&p| self.groups[p][0]).collect();
        self.coordinates.iter().map(|c| Column { name: c.name.clone(), data: c.data.select(&rows) }).collect()
    }

    /// Describes `metric` over the runs of `point` (see [`Points::values`]).
    pub fn describe(&self, point: usize, metric: &str) -> Describe {
        describe(&self.values(point, metric))
    }

    /// The points table: one row per point with its coordinates, `n`, the count of each status,
    /// `unsettled` (runs without a settle time), then `<metric>_n`, `_mean`, `_std`, `_ci95` (95 %
    /// half-width), `_min` and `_max` for every metric, and `runs` (the run ids, space separated).
    pub fn table(&self) -> SummaryTable {
        let mut columns = self.coordinate_columns(&(0..self.len()).collect::<Vec<_>>());
        let ints = |f: &dyn Fn(&[usize]) -> usize| ColumnData::Int(self.groups.iter().map(|g| f(g) as i64).collect());
        columns.push(column("n", ints(&|g| g.len())));
        let status = self.summary.column("status").map(|c| &c.data);
        for name in RunStatus::RECORDED.map(RunStatus::as_str) {
            let count = |g: &[usize]| {
                g.iter().filter(|&&r| matches!(status, Some(ColumnData::Text(s)) if s[r] == name)).count()
            };
            columns.push(column(name, ints(&count)));
        }
        let settle = self.summary.column(quantity::SETTLE_TIME.name).map(|c| &c.data);
        let unsettled =
            |g: &[usize]| g.iter().filter(|&&r| !settle.and_then(|d| d.number(r)).is_some_and(f64::is_finite)).count();
        columns.push(column("unsettled", ints(&unsettled)));
        for metric in self.metric_names() {
            let described: Vec<Describe> = (0..self.len()).map(|p| self.describe(p, metric)).collect();
            for statistic in STATISTICS {
                let name = format!("{metric}_{statistic}");
                let floats = |f: fn(&Describe) -> f64| ColumnData::Float(described.iter().map(f).collect());
                let data = match statistic {
                    "n" => ColumnData::Int(described.iter().map(|d| d.n as i64).collect()),
                    "mean" => floats(|d| d.mean),
                    "std" => floats(|d| d.std),
                    "ci95" => floats(|d| d.half_width_95),
                    "min" => floats(|d| d.min),
                    _ => floats(|d| d.max),
                };
                columns.push(Column { name, data });
            }
        }
        if let Some(ids) = self.summary.column("run_id") {
            let runs = self.groups.iter().map(|g| g.iter().map(|&r| ids.data.text(r)).collect::<Vec<_>>().join(" "));
            columns.push(column("runs", ColumnData::Text(runs.collect())));
        }
        SummaryTable { columns }
    }
}

fn column(name: &str, data: ColumnData) -> Column {
    Column { name: name.to_string(), data }
}

/// The metrics of a points table: the names `m` with a column `m_mean`, in order.
pub fn table_metrics(points: &SummaryTable) -> Vec<&str> {
    points.columns.iter().filter_map(|c| c.name.strip_suffix("_mean")).collect()
}

/// A points table for reading on screen: coordinates, `n`, the status counts, and `mean ± half-width`
/// (95 %) of each metric in `metrics`. Fails naming an unknown metric and listing the known ones.
pub fn view(points: &SummaryTable, metrics: &[&str]) -> Result<SummaryTable, UnknownMetric> {
    let known = table_metrics(points);
    if let Some(unknown) = metrics.iter().find(|m| !known.contains(m)) {
        return Err(UnknownMetric::new(unknown, &known));
    }
    let end = points.columns.iter().position(|c| c.name == "n").map_or(0, |n| n + 1 + RunStatus::RECORDED.len());
    let mut columns: Vec<Column> = points.columns[..end.min(points.columns.len())].to_vec();
    for metric in metrics {
        let (Some(mean), Some(half)) =
            (points.column(&format!("{metric}_mean")), points.column(&format!("{metric}_ci95")))
        else {
            continue;
        };
        let cells = (0..points.len()).map(|i| plus_minus(mean.data.number(i), half.data.number(i))).collect();
        columns.push(Column { name: format!("{} ±95%", quantity::label(metric)), data: ColumnData::Text(cells) });
    }
    Ok(SummaryTable { columns })
}

/// `mean ± half` rounded to its interval (see [`rounded`]); `mean` alone to 6 significant digits
/// without a half-width or with a zero one (every run the same: a count of 2 in each is `2`), `-`
/// without a mean.
pub fn plus_minus(mean: Option<f64>, half: Option<f64>) -> String {
    match (mean.filter(|m| m.is_finite()), half.filter(|h| h.is_finite() && *h != 0.0)) {
        (None, _) => "-".to_string(),
        (Some(m), None) => short_float(m),
        (Some(m), Some(h)) => {
            let (scale, digit) = rounded(m.abs().max(h), h);
            let at = |x: f64| at_digit(x / 10f64.powi(scale), digit);
            let text = format!("{} ± {}", at(m), at(h));
            if scale == 0 { text } else { format!("({text})e{scale}") }
        }
    }
}

/// How values with an interval of half-width `half` are written, the largest of them of size
/// `size`: the power of ten they are shown in (0 within [1e-3, 1e6)) and, in it, the power of ten of
/// the last digit shown: the half-width's second significant digit (`0.368243 ± 0.0478264` is
/// `0.368 ± 0.048`); a zero or unknown half-width keeps 6 significant digits of `size`.
pub fn rounded(size: f64, half: f64) -> (i32, i32) {
    let scale = if size == 0.0 || (1e-3..1e6).contains(&size) { 0 } else { size.log10().floor() as i32 };
    let step = if half.is_finite() && half > 0.0 { half } else { size * 1e-4 };
    (scale, (step / 10f64.powi(scale)).log10().floor() as i32 - 1)
}

/// `x` rounded to the digit of power of ten `digit` (`12345.6` at 1 is `12350`, `0.36824` at −3 `0.368`).
pub fn at_digit(x: f64, digit: i32) -> String {
    let step = 10f64.powi(digit);
    let decimals = (-digit).max(0) as usize;
    format!("{:.decimals$}", (x / step).round() * step + 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intervals_are_rounded_to_two_significant_digits_of_the_half_width() {
        assert_eq!(plus_minus(Some(0.368243), Some(0.0478264)), "0.368 ± 0.048");
        assert_eq!(plus_minus(Some(12345.6), Some(234.5)), "12350 ± 230");
        assert_eq!(plus_minus(Some(2.0), Some(0.0)), "2", "a count without spread");
        assert_eq!(plus_minus(Some(2.5), Some(0.0)), "2.5");
        assert_eq!(plus_minus(Some(3.2047e-5), Some(1.13e-6)), "(3.20 ± 0.11)e-5");
        assert_eq!(plus_minus(Some(-0.0001), Some(0.05)), "0.000 ± 0.050", "no negative zero");
        assert_eq!(plus_minus(Some(0.5), None), "0.5");
        assert_eq!(plus_minus(None, Some(0.1)), "-");
    }
}
