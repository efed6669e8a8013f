//! Charts of `demsweep compare --plot`: each kept metric against the first swept parameter (point
//! means with 95 % intervals, the reference's tolerance band shaded), and each point's cost ratio
//! against its largest deviation from the reference (acceptable points marked).

use std::ops::Range;
use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{self, LINE_WIDTH, NOT_SETTLED};
use super::{Canvas, ChartOptions, DrawResult, Figure, PlotError, render};
use crate::stats::Ratio;
use crate::stats::compare::Comparison;
use crate::stats::points::Points;

/// Fill of the reference's tolerance band.
const BAND: RGBColor = RGBColor(200, 230, 200);
/// Colour of acceptable points.
const ACCEPTABLE: RGBColor = RGBColor(44, 160, 44);
/// Points labelled by name on the cost chart at most (more would hide each other).
const MAX_LABELS: usize = 20;

/// One point of a metric chart.
#[derive(Clone, Debug, PartialEq)]
pub struct MetricPoint {
    /// Value of the chart's x parameter.
    pub x: f64,
    /// Value of the series parameter, if the chart has one.
    pub series: Option<f64>,
    /// Mean of the metric over the point's runs.
    pub mean: f64,
    /// Half-width of its 95 % interval (NaN with fewer than 2 runs).
    pub half_width_95: f64,
    /// Whether this is the reference point.
    pub reference: bool,
}

/// Draws `metric` against `x_param` (a line per value of `series_param`), every point with its 95 %
/// interval, and the reference's tolerance band `band` shaded, onto `canvas`.
pub fn metric_chart<'c>(
    metric: &str,
    points: &[MetricPoint],
    (x_param, series_param): (&str, Option<&str>),
    band: Range<f64>,
    options: &ChartOptions,
    canvas: impl Into<Canvas<'c>>,
) -> Result<(), PlotError> {
    render(&MetricFigure { metric, points, x_param, series_param, band }, options, canvas.into())
}

/// One point of the cost chart.
#[derive(Clone, Debug, PartialEq)]
pub struct CostPoint {
    /// Short name (its swept values).
    pub label: String,
    /// Largest |difference| / margin over the kept metrics.
    pub deviation: f64,
    /// Cost relative to the reference, with its 95 % interval.
    pub cost: Ratio,
    /// Whether every kept metric is equivalent.
    pub acceptable: bool,
}

/// Draws each point's cost ratio (with its 95 % interval) against its deviation, acceptable points
/// filled green, the reference at (0, 1), onto `canvas`; `cost` names the cost measure.
pub fn cost_chart<'c>(
    points: &[CostPoint],
    cost: &str,
    options: &ChartOptions,
    canvas: impl Into<Canvas<'c>>,
) -> Result<(), PlotError> {
    render(&CostFigure { points, cost }, options, canvas.into())
}

/// Draws `compare_<metric>` for every kept metric and `compare_cost` into `dir` as PNG; returns the
/// files written. The x axis is the first swept numeric parameter with two or more values (the point
/// number without one), the series the second.
pub fn draw_all(
    points: &Points,
    comparison: &Comparison,
    dir: &Path,
    options: &ChartOptions,
) -> Result<Vec<PathBuf>, PlotError> {
    let axes: Vec<&str> = points
        .coordinates()
        .iter()
        .map(|c| c.name.as_str())
        .filter(|name| {
            let values: Option<Vec<f64>> = (0..points.len()).map(|p| points.coordinate(p, name)).collect();
            values.is_some_and(|mut values| {
                values.sort_by(f64::total_cmp);
                values.dedup();
                values.len() >= 2
            })
        })
        .take(2)
        .collect();
    let x_param = axes.first().copied().unwrap_or("point");
    let series_param = axes.get(1).copied();
    let x_of = |p: usize| axes.first().map_or(p as f64, |name| points.coordinate(p, name).unwrap_or(f64::NAN));
    let options =
        ChartOptions { subject: Some(format!("reference {}", points.label(comparison.reference))), ..options.clone() };
    let mut written = Vec::new();
    for kept in &comparison.kept {
        let metric = kept.tolerance.metric.as_str();
        let chart_points: Vec<MetricPoint> = (0..points.len())
            .map(|p| {
                let described = points.describe(p, metric);
                MetricPoint {
                    x: x_of(p),
                    series: series_param.and_then(|name| points.coordinate(p, name)),
                    mean: described.mean,
                    half_width_95: described.half_width_95,
                    reference: p == comparison.reference,
                }
            })
            .collect();
        let centre = kept.reference.mean;
        let path = dir.join(format!("compare_{metric}.png"));
        let band = centre - kept.margin..centre + kept.margin;
        metric_chart(metric, &chart_points, (x_param, series_param), band, &options, &path)?;
        written.push(path);
    }
    let cost_points: Vec<CostPoint> = comparison
        .points
        .iter()
        .map(|p| CostPoint {
            label: points.coordinate_columns(&[p.point]).iter().map(|c| c.data.text(0)).collect::<Vec<_>>().join(", "),
            deviation: p.deviation(&comparison.kept),
            cost: p.cost,
            acceptable: p.acceptable(),
        })
        .collect();
    let path = dir.join("compare_cost.png");
    cost_chart(&cost_points, &comparison.cost_column, &options, &path)?;
    written.push(path);
    Ok(written)
}

/// A kept metric against the first swept parameter.
struct MetricFigure<'a> {
    metric: &'a str,
    points: &'a [MetricPoint],
    x_param: &'a str,
    series_param: Option<&'a str>,
    band: Range<f64>,
}

impl Figure for MetricFigure<'_> {
    type Layout = ();

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, options: &ChartOptions) -> DrawResult<()>
    where
        DB::ErrorType: 'static,
    {
        let x_range = style::padded(style::finite_bounds(self.points.iter().map(|p| p.x)), 0.05);
        let spread = |p: &MetricPoint| p.half_width_95.max(0.0);
        let ys = self
            .points
            .iter()
            .flat_map(|p| [p.mean - spread(p), p.mean + spread(p)])
            .chain([self.band.start, self.band.end]);
        let y_range = style::padded(style::finite_bounds(ys), 0.08);
        let title = options.title(self.metric);
        let mut chart = ChartBuilder::on(root)
            .caption(&title, style::title_text(root, &title, style::TITLE_SIZE))
            .margin(15)
            .x_label_area_size(55)
            .y_label_area_size(95)
            .build_cartesian_2d(x_range.clone(), y_range)?;
        style::numbered_mesh(&mut chart.configure_mesh())
            .x_desc(self.x_param)
            .y_desc(format!("{} (mean ± 95%)", self.metric))
            .draw()?;
        let band = [(x_range.start, self.band.start), (x_range.end, self.band.end)];
        chart
            .draw_series([Rectangle::new(band, BAND.filled())])?
            .label("reference ± tolerance")
            .legend(|(x, y)| Rectangle::new([(x, y - 6), (x + 24, y + 6)], BAND.filled()));
        let centre = (self.band.start + self.band.end) / 2.0;
        let centre_line = [(x_range.start, centre), (x_range.end, centre)];
        chart.draw_series(DashedLineSeries::new(centre_line, 6, 4, ACCEPTABLE.stroke_width(1)))?;
        let mut series: Vec<Option<f64>> = self.points.iter().map(|p| p.series).collect();
        series.sort_by(|a, b| a.unwrap_or(f64::NAN).total_cmp(&b.unwrap_or(f64::NAN)));
        series.dedup();
        for (index, value) in series.iter().enumerate() {
            let colour = style::series_colour(index);
            let mut line: Vec<&MetricPoint> = self.points.iter().filter(|p| p.series == *value).collect();
            line.sort_by(|a, b| a.x.total_cmp(&b.x));
            let line_style = colour.stroke_width(LINE_WIDTH);
            let label = match (self.series_param, value) {
                (Some(name), Some(v)) => format!("{name} = {}", style::short_number(*v)),
                _ => self.metric.to_string(),
            };
            let means = line.iter().filter(|p| p.mean.is_finite()).map(|p| (p.x, p.mean));
            chart
                .draw_series(LineSeries::new(means, line_style).point_size(4))?
                .label(label)
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], line_style));
            style::error_bars(
                &mut chart,
                line.iter().map(|p| (p.x, p.mean - p.half_width_95, p.mean + p.half_width_95)),
                colour,
            )?;
        }
        if let Some(reference) = self.points.iter().find(|p| p.reference) {
            let ring = BLACK.stroke_width(2);
            chart
                .draw_series([Circle::new((reference.x, reference.mean), 9, ring)])?
                .label("reference")
                .legend(move |(x, y)| Circle::new((x + 12, y), 7, ring));
        }
        style::draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

/// Cost ratio against deviation.
struct CostFigure<'a> {
    points: &'a [CostPoint],
    cost: &'a str,
}

impl Figure for CostFigure<'_> {
    type Layout = ();

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, options: &ChartOptions) -> DrawResult<()>
    where
        DB::ErrorType: 'static,
    {
        let shown: Vec<&CostPoint> =
            self.points.iter().filter(|p| p.deviation.is_finite() && p.cost.ratio.is_finite()).collect();
        let far = shown.iter().map(|p| p.deviation).fold(1.2, f64::max);
        let ys = shown.iter().flat_map(|p| [p.cost.ratio, p.cost.low, p.cost.high]).chain([1.0]);
        let y_range = style::padded(style::finite_bounds(ys), 0.08);
        let title = options.title("Cost against deviation");
        let mut chart = ChartBuilder::on(root)
            .caption(&title, style::title_text(root, &title, style::TITLE_SIZE))
            .margin(15)
            .x_label_area_size(55)
            .y_label_area_size(85)
            .build_cartesian_2d(-0.05 * far..far * 1.1, y_range.clone())?;
        style::numbered_mesh(&mut chart.configure_mesh())
            .x_desc("largest |difference| / margin over the kept metrics")
            .y_desc(format!("{} ratio to the reference (95%)", self.cost))
            .draw()?;
        let limit = [(1.0, y_range.start), (1.0, y_range.end)];
        chart
            .draw_series(DashedLineSeries::new(limit, 6, 4, NOT_SETTLED.stroke_width(2)))?
            .label("tolerance (means)")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 24, y)], NOT_SETTLED.stroke_width(2)));
        let bars = shown.iter().map(|p| (p.deviation, p.cost.low, p.cost.high));
        style::error_bars(&mut chart, bars, NOT_SETTLED)?;
        let (good, other): (Vec<&CostPoint>, Vec<&CostPoint>) = shown.iter().partition(|p| p.acceptable);
        let filled = ACCEPTABLE.filled();
        chart
            .draw_series(good.iter().map(|p| Circle::new((p.deviation, p.cost.ratio), 6, filled)))?
            .label("acceptable (every kept metric equivalent)")
            .legend(move |(x, y)| Circle::new((x + 12, y), 6, filled));
        let hollow = style::series_colour(1).stroke_width(2);
        chart
            .draw_series(other.iter().map(|p| Circle::new((p.deviation, p.cost.ratio), 6, hollow)))?
            .label("not shown equivalent")
            .legend(move |(x, y)| Circle::new((x + 12, y), 6, hollow));
        let star = BLACK.stroke_width(3);
        chart
            .draw_series([Cross::new((0.0, 1.0), 7, star)])?
            .label("reference")
            .legend(move |(x, y)| Cross::new((x + 12, y), 6, star));
        if shown.len() <= MAX_LABELS {
            let text = style::text(style::LABEL_SIZE - 4);
            chart.draw_series(shown.iter().map(|p| {
                EmptyElement::at((p.deviation, p.cost.ratio)) + Text::new(p.label.clone(), (9, -14), text.clone())
            }))?;
        }
        style::draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}
