//! Charts of `demsweep compare --plot`: each kept metric against the first swept parameter (point
//! means with 95 % intervals, the reference's tolerance band shaded), and each point's cost ratio
//! against its largest deviation from the reference (acceptable points marked).

use std::ops::Range;
use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::style::{self, LINE_WIDTH, NOT_SETTLED};
use super::{Canvas, ChartOptions, DrawResult, Figure, PlotError, render};
use crate::physics::quantity;
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

/// Where a point of a metric chart was drawn (pixels): its marker's centre and the rows of its 95 %
/// interval's ends (`None` without an interval).
#[derive(Clone, Debug, PartialEq)]
pub struct DrawnPoint {
    /// The marker's centre (column, row).
    pub marker: (i32, i32),
    /// Rows of the interval's lower and upper end.
    pub interval: Option<(i32, i32)>,
}

/// Draws `metric` (with its unit, `""` when dimensionless) against `x_param` (a line per value of
/// `series_param`, each series shifted a little along x so that intervals at one x stay apart),
/// every point with its 95 % interval, and the reference's tolerance band `band` shaded when given,
/// onto `canvas`; returns where each point of `points` was drawn (`None`: no finite mean).
pub fn metric_chart<'c>(
    (metric, unit): (&str, &str),
    points: &[MetricPoint],
    (x_param, series_param): (&str, Option<&str>),
    band: Option<Range<f64>>,
    options: &ChartOptions,
    canvas: impl Into<Canvas<'c>>,
) -> Result<Vec<Option<DrawnPoint>>, PlotError> {
    render(&MetricFigure { metric, unit, points, x_param, series_param, band }, options, canvas.into())
}

/// The points of `metric` over a grid: x is the value of `x_param` (the point number without one),
/// the series the value of `series_param`; mean and 95 % half-width over each point's runs (the
/// `/points` statistics); `reference` marks one point.
pub fn metric_points(
    points: &Points,
    metric: &str,
    (x_param, series_param): (Option<&str>, Option<&str>),
    reference: Option<usize>,
) -> Vec<MetricPoint> {
    (0..points.len())
        .map(|p| {
            let described = points.describe(p, metric);
            MetricPoint {
                x: x_param.map_or(p as f64, |name| points.coordinate(p, name).unwrap_or(f64::NAN)),
                series: series_param.and_then(|name| points.coordinate(p, name)),
                mean: described.mean,
                half_width_95: described.half_width_95,
                reference: Some(p) == reference,
            }
        })
        .collect()
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
/// number without one), the series the second. Refused when `dir` is `/`, a home folder or above the
/// working folder ([`crate::output::guard::check_files_folder`]).
pub fn draw_all(
    points: &Points,
    comparison: &Comparison,
    dir: &Path,
    options: &ChartOptions,
) -> Result<Vec<PathBuf>, PlotError> {
    crate::output::guard::check_files_folder(dir)?;
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
    let series_param = axes.get(1).copied();
    let options =
        ChartOptions { subject: Some(format!("reference {}", points.label(comparison.reference))), ..options.clone() };
    let mut written = Vec::new();
    for kept in &comparison.kept {
        let metric = kept.tolerance.metric.as_str();
        let chart_points =
            metric_points(points, metric, (axes.first().copied(), series_param), Some(comparison.reference));
        let centre = kept.reference.mean;
        let path = dir.join(format!("compare_{metric}.png"));
        let band = Some(centre - kept.margin..centre + kept.margin);
        let unit = quantity::unit(metric).unwrap_or("");
        let x_param = axes.first().copied().unwrap_or("point");
        metric_chart((metric, unit), &chart_points, (x_param, series_param), band, &options, &path)?;
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

/// Shift along x between neighbouring series of a metric chart, as a fraction of the x range.
const SERIES_SHIFT: f64 = 0.012;

/// A metric against a swept parameter.
struct MetricFigure<'a> {
    metric: &'a str,
    unit: &'a str,
    points: &'a [MetricPoint],
    x_param: &'a str,
    series_param: Option<&'a str>,
    band: Option<Range<f64>>,
}

impl MetricFigure<'_> {
    /// The distinct series values, in order (`None` alone without a series parameter).
    fn series(&self) -> Vec<Option<f64>> {
        let mut series: Vec<Option<f64>> = self.points.iter().map(|p| p.series).collect();
        series.sort_by(|a, b| a.unwrap_or(f64::NAN).total_cmp(&b.unwrap_or(f64::NAN)));
        series.dedup();
        series
    }

    /// The metric with its unit, for the title and the axis.
    fn quantity(&self) -> String {
        quantity::labelled(self.metric, self.unit)
    }
}

impl Figure for MetricFigure<'_> {
    type Layout = Vec<Option<DrawnPoint>>;

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        options: &ChartOptions,
    ) -> DrawResult<Vec<Option<DrawnPoint>>>
    where
        DB::ErrorType: 'static,
    {
        let x_range = style::padded(style::finite_bounds(self.points.iter().map(|p| p.x)), 0.05);
        let spread = |p: &MetricPoint| p.half_width_95.max(0.0);
        let band_ends = self.band.iter().flat_map(|band| [band.start, band.end]);
        let ys = self.points.iter().flat_map(|p| [p.mean - spread(p), p.mean + spread(p)]).chain(band_ends);
        let y_range = style::padded(style::finite_bounds(ys), 0.08);
        let title = options.title(&self.quantity());
        let mut chart = ChartBuilder::on(root)
            .caption(&title, style::title_text(root, &title, style::TITLE_SIZE))
            .margin(15)
            .x_label_area_size(55)
            .y_label_area_size(95)
            .build_cartesian_2d(x_range.clone(), y_range)?;
        style::numbered_mesh(&mut chart.configure_mesh())
            .x_desc(self.x_param)
            .y_desc(format!("{} (mean ± 95%)", self.quantity()))
            .draw()?;
        if let Some(band) = &self.band {
            let corners = [(x_range.start, band.start), (x_range.end, band.end)];
            chart
                .draw_series([Rectangle::new(corners, BAND.filled())])?
                .label("reference ± tolerance")
                .legend(|(x, y)| Rectangle::new([(x, y - 6), (x + 24, y + 6)], BAND.filled()));
            let centre = (band.start + band.end) / 2.0;
            let centre_line = [(x_range.start, centre), (x_range.end, centre)];
            chart.draw_series(DashedLineSeries::new(centre_line, 6, 4, ACCEPTABLE.stroke_width(1)))?;
        }
        let series = self.series();
        let mut drawn = vec![None; self.points.len()];
        let mut reference = None;
        for (index, value) in series.iter().enumerate() {
            let colour = style::series_colour(index);
            let centred = index as f64 - (series.len() - 1) as f64 / 2.0;
            let shift = centred * SERIES_SHIFT * (x_range.end - x_range.start);
            let mut line: Vec<usize> = (0..self.points.len()).filter(|&k| self.points[k].series == *value).collect();
            line.sort_by(|&a, &b| self.points[a].x.total_cmp(&self.points[b].x));
            let line_style = colour.stroke_width(LINE_WIDTH);
            let label = match (self.series_param, value) {
                (Some(name), Some(v)) => format!("{name} = {}", style::short_number(*v)),
                _ => self.metric.to_string(),
            };
            let at = |k: &usize| (self.points[*k].x + shift, self.points[*k].mean);
            let means: Vec<(f64, f64)> = line.iter().map(at).filter(|(x, y)| x.is_finite() && y.is_finite()).collect();
            chart
                .draw_series(LineSeries::new(means, line_style).point_size(4))?
                .label(label)
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], line_style));
            let bar = |k: &usize| {
                let p = &self.points[*k];
                (p.x + shift, p.mean - p.half_width_95, p.mean + p.half_width_95)
            };
            style::error_bars(&mut chart, line.iter().map(bar), colour)?;
            for k in line {
                drawn[k] = drawn_point(&chart, at(&k), bar(&k));
                reference = reference.or(self.points[k].reference.then(|| at(&k)));
            }
        }
        if let Some(reference) = reference {
            let ring = BLACK.stroke_width(2);
            chart
                .draw_series([Circle::new(reference, 9, ring)])?
                .label("reference")
                .legend(move |(x, y)| Circle::new((x + 12, y), 7, ring));
        }
        style::draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        Ok(drawn)
    }
}

/// Where a point at `(x, mean)` with the interval `(x, low, high)` lands on `chart` (`None`
/// without a finite mean; no interval unless both ends are finite).
fn drawn_point<DB: DrawingBackend>(
    chart: &ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    (x, mean): (f64, f64),
    (_, low, high): (f64, f64, f64),
) -> Option<DrawnPoint> {
    (x.is_finite() && mean.is_finite()).then(|| DrawnPoint {
        marker: chart.backend_coord(&(x, mean)),
        interval: (low.is_finite() && high.is_finite())
            .then(|| (chart.backend_coord(&(x, low)).1, chart.backend_coord(&(x, high)).1)),
    })
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
