//! Charts of a tune: cost against the largest |difference| / tolerance (the feasible region and the
//! recommendation marked), and cost along each lever.

use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::prelude::*;

use super::style::{self, DIVERGED, LABEL_SIZE, NOT_SETTLED};
use super::{Canvas, ChartOptions, DrawResult, Figure, PlotError, render};

/// One evaluated candidate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CostPoint {
    /// Largest |difference| / tolerance over the kept metrics (NaN when a run failed).
    pub worst: f64,
    /// Mean cost over the reference's.
    pub cost_ratio: f64,
    /// Equivalent on every metric with every run settled.
    pub feasible: bool,
    /// A run diverged, did not settle or failed.
    pub failed: bool,
}

/// The candidates along one lever.
#[derive(Clone, Debug, PartialEq)]
pub struct LeverSeries {
    /// The lever's key.
    pub name: String,
    /// Whether the lever moves on a log scale.
    pub log: bool,
    /// (lever value, cost ratio, feasible).
    pub points: Vec<(f64, f64, bool)>,
    /// The recommendation's value.
    pub best: Option<f64>,
    /// The reference's value (drawn at cost ratio 1).
    pub reference: Option<f64>,
}

/// Cost ratio against largest |difference|/tolerance; the feasible region (below 1) shaded.
pub fn cost_vs_difference_chart<'c>(
    points: &[CostPoint],
    recommended: Option<CostPoint>,
    options: &ChartOptions,
    canvas: impl Into<Canvas<'c>>,
) -> Result<(), PlotError> {
    render(&CostFigure { points, recommended }, options, canvas.into())
}

/// Cost ratio along each lever, one panel per lever.
pub fn cost_along_levers_chart(series: &[LeverSeries], options: &ChartOptions, path: &Path) -> Result<(), PlotError> {
    render(&LeverFigure { series }, options, path.into())
}

struct CostFigure<'a> {
    points: &'a [CostPoint],
    recommended: Option<CostPoint>,
}

fn feasible_colour() -> RGBColor {
    style::series_colour(2)
}

impl Figure for CostFigure<'_> {
    type Layout = ();

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, options: &ChartOptions) -> DrawResult<()>
    where
        DB::ErrorType: 'static,
    {
        let title = options.title("Tune: cost against the largest |difference| / tolerance");
        let finite_worst = self.points.iter().map(|p| p.worst).filter(|w| w.is_finite());
        let x_max = finite_worst.fold(1.5f64, f64::max).min(20.0) * 1.1;
        let failed_x = x_max * 0.97;
        let ratios = self.points.iter().map(|p| p.cost_ratio).chain([1.0]);
        let (_, hi) = style::finite_bounds(ratios).unwrap_or((0.5, 1.5));
        let y = 0.0..hi * 1.1;
        let mut chart = ChartBuilder::on(root)
            .caption(&title, style::title_text(root, &title, style::TITLE_SIZE))
            .margin(15)
            .x_label_area_size(55)
            .y_label_area_size(85)
            .build_cartesian_2d(0.0..x_max, y.clone())?;
        style::numbered_mesh(&mut chart.configure_mesh())
            .x_desc("largest |difference| / tolerance over the kept metrics (failed runs at the right edge)")
            .y_desc("cost / reference cost")
            .draw()?;
        let shade = feasible_colour().mix(0.12).filled();
        chart
            .draw_series([Rectangle::new([(0.0, y.start), (1.0, y.end)], shade)])?
            .label("feasible region (|difference| < tolerance)")
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 20, y + 5)], shade));
        chart.draw_series(LineSeries::new([(0.0, 1.0), (x_max, 1.0)], BLACK.stroke_width(1)))?;
        let at = |p: &CostPoint| (if p.worst.is_finite() { p.worst.min(x_max) } else { failed_x }, p.cost_ratio);
        let ok = feasible_colour().filled();
        chart
            .draw_series(self.points.iter().filter(|p| p.feasible).map(|p| Circle::new(at(p), 5, ok)))?
            .label("equivalent on every metric")
            .legend(move |(x, y)| Circle::new((x + 10, y), 5, ok));
        let other = NOT_SETTLED.filled();
        chart
            .draw_series(self.points.iter().filter(|p| !p.feasible && !p.failed).map(|p| Circle::new(at(p), 4, other)))?
            .label("different or undecided")
            .legend(move |(x, y)| Circle::new((x + 10, y), 4, other));
        let cross = DIVERGED.stroke_width(2);
        chart
            .draw_series(self.points.iter().filter(|p| p.failed).map(|p| Cross::new(at(p), 5, cross)))?
            .label("a run diverged or did not settle")
            .legend(move |(x, y)| Cross::new((x + 10, y), 5, cross));
        if let Some(best) = self.recommended {
            let star = BLACK.stroke_width(3);
            chart
                .draw_series([TriangleMarker::new(at(&best), 10, star)])?
                .label("recommendation (search runs)")
                .legend(move |(x, y)| TriangleMarker::new((x + 10, y), 7, star));
        }
        style::draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

/// One lever's panel on `cell`: cost ratio against the lever on the x axis `x` (linear or log),
/// points filled `ok` when feasible, `other` when not, the recommendation as a vertical line and the
/// reference as a cross at cost ratio 1.
fn lever_panel<DB, X>(
    cell: &DrawingArea<DB, Shift>,
    series: &LeverSeries,
    x: X,
    y: std::ops::Range<f64>,
    (ok, other): (ShapeStyle, ShapeStyle),
) -> DrawResult<()>
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
    X: AsRangedCoord<Value = f64>,
    X::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut chart = ChartBuilder::on(cell)
        .caption(&series.name, style::text(LABEL_SIZE + 2))
        .margin(8)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(x, y.clone())?;
    chart
        .configure_mesh()
        .x_labels(if series.log { 4 } else { 5 })
        .x_label_formatter(&|v| style::short_number(*v))
        .y_label_formatter(&|v| style::short_number(*v))
        .label_style(style::text(LABEL_SIZE - 3))
        .draw()?;
    chart.draw_series(series.points.iter().map(|p| Circle::new((p.0, p.1), 4, if p.2 { ok } else { other })))?;
    if let Some(b) = series.best {
        chart.draw_series(LineSeries::new([(b, y.start), (b, y.end)], BLACK.stroke_width(2)))?;
    }
    if let Some(r) = series.reference {
        chart.draw_series([Cross::new((r, 1.0), 7, BLACK.stroke_width(3))])?;
    }
    Ok(())
}

struct LeverFigure<'a> {
    series: &'a [LeverSeries],
}

impl Figure for LeverFigure<'_> {
    type Layout = ();

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, options: &ChartOptions) -> DrawResult<()>
    where
        DB::ErrorType: 'static,
    {
        let title = "Tune: cost along each lever (green: equivalent; cross: the reference; line: the answer)";
        let area = style::titled(root, &options.title(title))?;
        let columns = self.series.len().clamp(1, 3);
        let rows = self.series.len().div_ceil(columns).max(1);
        let ratios = self.series.iter().flat_map(|s| s.points.iter().map(|p| p.1)).chain([1.0]);
        let (_, hi) = style::finite_bounds(ratios).unwrap_or((0.5, 1.5));
        let y = 0.0..hi * 1.1;
        for (series, cell) in self.series.iter().zip(area.split_evenly((rows, columns))) {
            let xs = series.points.iter().map(|p| p.0).chain(series.best).chain(series.reference);
            let (xlo, xhi) = style::finite_bounds(xs).unwrap_or((0.0, 1.0));
            let ok = feasible_colour().filled();
            let other = NOT_SETTLED.filled();
            if series.log && xlo > 0.0 {
                lever_panel(&cell, series, style::log_span(xlo / 1.2, xhi * 1.2).log_scale(), y.clone(), (ok, other))?;
            } else {
                let pad = ((xhi - xlo) * 0.05).max(1e-12);
                lever_panel(&cell, series, (xlo - pad)..(xhi + pad), y.clone(), (ok, other))?;
            }
        }
        Ok(())
    }
}
