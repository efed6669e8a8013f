//! Charts of the benchmarks: work-precision (log-log lines) and stability maps (outcome per case).

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{self, DIVERGED, LABEL_SIZE, LINE_WIDTH};
use super::{Canvas, ChartOptions, DrawResult, Figure, PlotError, render};

/// One line of a log-log chart.
#[derive(Clone, Debug, PartialEq)]
pub struct LogLogSeries {
    /// Legend label.
    pub label: String,
    /// Points (x, y), both > 0; others are left out.
    pub points: Vec<(f64, f64)>,
}

/// Draws lines with markers on logarithmic x and y axes onto `canvas`.
pub fn log_log_chart<'c>(
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[LogLogSeries],
    options: &ChartOptions,
    canvas: impl Into<Canvas<'c>>,
) -> Result<(), PlotError> {
    render(&LogLogFigure { title, x_desc, y_desc, series }, options, canvas.into())
}

/// One panel of a stability map: cases at (x, y) that blew up or not, and a predicted boundary.
#[derive(Clone, Debug, PartialEq)]
pub struct MapPanel {
    /// Panel title.
    pub title: String,
    /// Cases: (x, y > 0, blew up).
    pub cases: Vec<(f64, f64, bool)>,
    /// The predicted boundary (x, y > 0), drawn as a line.
    pub predicted: Vec<(f64, f64)>,
}

/// Draws stability-map panels side by side in a grid of `columns` onto `canvas`: x linear with tick
/// labels `x_labels` at 0, 1, 2, …; y logarithmic.
pub fn stability_map_chart<'c>(
    panels: &[MapPanel],
    columns: usize,
    (x_desc, x_labels): (&str, &[String]),
    y_desc: &str,
    options: &ChartOptions,
    canvas: impl Into<Canvas<'c>>,
) -> Result<(), PlotError> {
    render(&MapFigure { panels, columns: columns.max(1), x_desc, x_labels, y_desc }, options, canvas.into())
}

/// A logarithmic axis range covering the positive values with a factor-of-1.5 margin.
fn log_range(values: impl IntoIterator<Item = f64>) -> std::ops::Range<f64> {
    match style::finite_bounds(values.into_iter().filter(|v| *v > 0.0)) {
        Some((lo, hi)) => style::log_span(lo / 1.5, hi * 1.5),
        None => 0.1..1.0,
    }
}

struct LogLogFigure<'a> {
    title: &'a str,
    x_desc: &'a str,
    y_desc: &'a str,
    series: &'a [LogLogSeries],
}

impl Figure for LogLogFigure<'_> {
    type Layout = ();

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, options: &ChartOptions) -> DrawResult<()>
    where
        DB::ErrorType: 'static,
    {
        let positive = |(x, y): &(f64, f64)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite();
        let all = || self.series.iter().flat_map(|s| s.points.iter().copied().filter(positive));
        let title = options.title(self.title);
        let mut chart = ChartBuilder::on(root)
            .caption(&title, style::title_text(root, &title, style::TITLE_SIZE))
            .margin(15)
            .x_label_area_size(55)
            .y_label_area_size(85)
            .build_cartesian_2d(log_range(all().map(|p| p.0)).log_scale(), log_range(all().map(|p| p.1)).log_scale())?;
        style::numbered_mesh(&mut chart.configure_mesh())
            .x_desc(self.x_desc)
            .y_desc(self.y_desc)
            .x_labels(6)
            .y_labels(8)
            .draw()?;
        for (index, series) in self.series.iter().enumerate() {
            let line_style = style::series_colour(index).stroke_width(LINE_WIDTH);
            let points: Vec<(f64, f64)> = series.points.iter().copied().filter(positive).collect();
            chart
                .draw_series(LineSeries::new(points, line_style).point_size(4))?
                .label(series.label.as_str())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], line_style));
        }
        style::draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

struct MapFigure<'a> {
    panels: &'a [MapPanel],
    columns: usize,
    x_desc: &'a str,
    x_labels: &'a [String],
    y_desc: &'a str,
}

impl Figure for MapFigure<'_> {
    type Layout = ();

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, options: &ChartOptions) -> DrawResult<()>
    where
        DB::ErrorType: 'static,
    {
        let area = style::titled(root, &options.title("Stability map"))?;
        let rows = self.panels.len().div_ceil(self.columns).max(1);
        let y_range = log_range(
            self.panels.iter().flat_map(|p| p.cases.iter().map(|c| c.1).chain(p.predicted.iter().map(|c| c.1))),
        );
        let x_range = -0.5..self.x_labels.len().max(1) as f64 - 0.5;
        for (panel, cell) in self.panels.iter().zip(area.split_evenly((rows, self.columns))) {
            let mut chart = ChartBuilder::on(&cell)
                .caption(&panel.title, style::text(LABEL_SIZE + 2))
                .margin(8)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d(x_range.clone(), y_range.clone().log_scale())?;
            let label = |v: &f64| {
                let index = v.round();
                let exact = (v - index).abs() < 1e-6 && index >= 0.0;
                exact.then(|| self.x_labels.get(index as usize).cloned()).flatten().unwrap_or_default()
            };
            chart
                .configure_mesh()
                .x_desc(self.x_desc)
                .y_desc(self.y_desc)
                .x_labels(self.x_labels.len() * 2 + 1)
                .x_label_formatter(&label)
                .y_label_formatter(&|v| style::short_number(*v))
                .label_style(style::text(LABEL_SIZE - 3))
                .axis_desc_style(style::text(LABEL_SIZE))
                .light_line_style(RGBColor(240, 240, 240))
                .draw()?;
            let stable = style::series_colour(0).filled();
            let cross = DIVERGED.stroke_width(2);
            chart.draw_series(panel.cases.iter().filter(|c| !c.2).map(|c| Circle::new((c.0, c.1), 3, stable)))?;
            chart.draw_series(panel.cases.iter().filter(|c| c.2).map(|c| Cross::new((c.0, c.1), 4, cross)))?;
            chart.draw_series(LineSeries::new(panel.predicted.iter().copied(), BLACK.stroke_width(LINE_WIDTH)))?;
        }
        Ok(())
    }
}
