//! Charts of a whole study: settle time against swept parameters.
//!
//! Runs that settled show their settle time, with the mean over the runs at each grid point and its
//! 95 % confidence interval (Student t) as error bars where there are two or more; runs that diverged are red crosses (lines) or red
//! crossed cells (heatmap); runs that did not settle or were interrupted are grey hollow circles
//! (lines) or grey cells (heatmap). A legend explains the marks that appear.

use std::ops::Range;

use plotters::coord::Shift;
use plotters::coord::ranged1d::{SegmentValue, SegmentedCoord};
use plotters::coord::types::RangedCoordi32;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::style::{self, DIVERGED, LABEL_SIZE, LINE_WIDTH, NOT_SETTLED};
use super::{Canvas, ChartOptions, DrawResult, Figure, PlotError, StudyPoint, render};
use crate::physics::RunStatus;
use crate::physics::quantity;
use crate::stats::{Describe, describe};

/// Draws settle time against the swept parameter `x_param`, one line per value of `series_param`
/// (one line in all without it), onto `canvas`. A line joins the mean settle time of the settled runs
/// at each x, with its 95 % interval as an error bar where two or more settled; every run is marked,
/// those without a settle time in a row above the data.
pub fn settle_time_lines<'c>(
    points: &[StudyPoint],
    x_param: &str,
    series_param: Option<&str>,
    options: &ChartOptions,
    canvas: impl Into<Canvas<'c>>,
) -> Result<(), PlotError> {
    let canvas = canvas.into();
    check_parameters(points, [Some(x_param), series_param].into_iter().flatten(), &canvas)?;
    render(&LinesFigure { points, x_param, series_param }, options, canvas)
}

/// Draws a heatmap of settle time over the grid of `x_param` × `y_param` values onto `canvas` and
/// returns its cells, one per grid point that has runs. A cell shows the mean settle time (and its
/// 95 % half-width, with two or more runs) when all its runs settled; otherwise it is marked
/// diverged if one of them diverged, not settled if not.
pub fn settle_time_heatmap<'c>(
    points: &[StudyPoint],
    x_param: &str,
    y_param: &str,
    options: &ChartOptions,
    canvas: impl Into<Canvas<'c>>,
) -> Result<Vec<HeatmapCell>, PlotError> {
    let canvas = canvas.into();
    check_parameters(points, [x_param, y_param], &canvas)?;
    render(&HeatmapFigure { grid: Grid::new(points, x_param, y_param), x_param, y_param }, options, canvas)
}

/// What a heatmap cell shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CellState {
    /// All runs settled; their mean settle time (s).
    Settled(f64),
    /// No run diverged, but some did not settle (or were interrupted).
    NotSettled,
    /// At least one run diverged.
    Diverged,
}

/// One cell of a heatmap: its grid point, state, run count and where it was drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct HeatmapCell {
    /// Value of the x parameter.
    pub x: f64,
    /// Value of the y parameter.
    pub y: f64,
    /// What the cell shows.
    pub state: CellState,
    /// Number of runs at this grid point (replicates).
    pub runs: usize,
    /// Half-width of the 95 % interval of the mean settle time (settled cells of two or more runs).
    pub half_width_95: Option<f64>,
    /// The filled rectangle in pixels: upper left and lower right corner (column, row).
    pub pixels: [(i32, i32); 2],
}

/// Checks that every point has every parameter in `names`.
fn check_parameters<'a>(
    points: &[StudyPoint],
    names: impl IntoIterator<Item = &'a str>,
    canvas: &Canvas<'_>,
) -> Result<(), PlotError> {
    for name in names {
        if let Some(index) = points.iter().position(|p| p.parameter(name).is_none()) {
            let reason = format!("run {index} has no swept parameter '{name}' to plot against");
            return Err(PlotError { path: canvas.label(), reason });
        }
    }
    Ok(())
}

/// The distinct values of `name` over `points`, sorted.
fn distinct_values<'a>(points: impl IntoIterator<Item = &'a StudyPoint>, name: &str) -> Vec<f64> {
    let mut values: Vec<f64> = points.into_iter().filter_map(|p| p.parameter(name)).collect();
    values.sort_by(f64::total_cmp);
    values.dedup();
    values
}

/// The points that have parameter `name` (not NaN), grouped by its value, in ascending order of the
/// values (one sort: linear in the points but for it).
fn group_by_value<'a>(points: impl IntoIterator<Item = &'a StudyPoint>, name: &str) -> Vec<(f64, Vec<&'a StudyPoint>)> {
    let mut valued: Vec<(f64, &StudyPoint)> =
        points.into_iter().filter_map(|p| Some((p.parameter(name).filter(|v| !v.is_nan())?, p))).collect();
    valued.sort_by(|a, b| a.0.total_cmp(&b.0));
    valued.chunk_by(|a, b| a.0 == b.0).map(|group| (group[0].0, group.iter().map(|&(_, p)| p).collect())).collect()
}

/// The settle times of the settled runs among `runs` described (mean, 95 % half-width, …).
fn settle_times<'a>(runs: impl IntoIterator<Item = &'a StudyPoint>) -> Describe {
    describe(&runs.into_iter().filter_map(StudyPoint::settled_time).collect::<Vec<_>>())
}

/// Shift along x between the no-settle-time marks of neighbouring series, as a fraction of the x range.
const UNSETTLED_SHIFT: f64 = 0.012;

/// Settle time against one parameter, a line per value of another.
struct LinesFigure<'a> {
    points: &'a [StudyPoint],
    x_param: &'a str,
    series_param: Option<&'a str>,
}

impl LinesFigure<'_> {
    /// The runs of each series: (legend label, runs), in order of the series parameter.
    fn series(&self) -> Vec<(String, Vec<&StudyPoint>)> {
        let Some(name) = self.series_param else {
            return vec![("settle time".to_string(), self.points.iter().collect())];
        };
        group_by_value(self.points, name)
            .into_iter()
            .map(|(value, runs)| (format!("{name} = {}", style::short_number(value)), runs))
            .collect()
    }

    /// The line of one series: the settle times of its settled runs at each x where some settled.
    fn mean_line(&self, runs: &[&StudyPoint]) -> Vec<(f64, Describe)> {
        group_by_value(runs.iter().copied(), self.x_param)
            .into_iter()
            .map(|(x, at_x)| (x, settle_times(at_x)))
            .filter(|(_, times)| times.n > 0)
            .collect()
    }
}

impl Figure for LinesFigure<'_> {
    type Layout = ();

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, options: &ChartOptions) -> DrawResult<()>
    where
        DB::ErrorType: 'static,
    {
        let x = |p: &StudyPoint| p.parameter(self.x_param).unwrap_or(f64::NAN);
        let x_range = style::padded(style::finite_bounds(self.points.iter().map(x)), 0.05);
        let lines: Vec<(String, Vec<(f64, Describe)>)> =
            self.series().into_iter().map(|(label, runs)| (label, self.mean_line(&runs))).collect();
        let upper = |d: &Describe| d.mean + d.half_width_95.max(0.0);
        let longest = self
            .points
            .iter()
            .filter_map(StudyPoint::settled_time)
            .chain(lines.iter().flat_map(|(_, line)| line.iter().map(|(_, d)| upper(d))))
            .fold(0.0, f64::max);
        let top = if longest > 0.0 { longest } else { 1.0 };
        // Runs without a settle time sit on a row above the data.
        let unsettled_row = top * 1.12;
        let title = options.title("Settle time");
        let mut chart = ChartBuilder::on(root)
            .caption(&title, style::title_text(root, &title, style::TITLE_SIZE))
            .margin(15)
            .x_label_area_size(55)
            .y_label_area_size(85)
            .build_cartesian_2d(x_range.clone(), 0.0..top * 1.2)?;
        style::numbered_mesh(&mut chart.configure_mesh())
            .x_desc(self.x_param)
            .y_desc(quantity::label(quantity::SETTLE_TIME.name))
            .draw()?;
        let row = [(x_range.start, unsettled_row), (x_range.end, unsettled_row)];
        chart.draw_series(DashedLineSeries::new(row, 4, 6, NOT_SETTLED.stroke_width(1)))?;
        for (index, ((label, line), (_, runs))) in lines.iter().zip(self.series()).enumerate() {
            let colour = style::series_colour(index);
            let line_style = colour.stroke_width(LINE_WIDTH);
            chart
                .draw_series(LineSeries::new(line.iter().map(|(x, d)| (*x, d.mean)), line_style).point_size(4))?
                .label(label.as_str())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], line_style));
            let bars = line.iter().map(|(x, d)| (*x, d.mean - d.half_width_95, d.mean + d.half_width_95));
            style::error_bars(&mut chart, bars, colour)?;
            let settled = runs.iter().filter_map(|p| Some((x(p), p.settled_time()?)));
            chart.draw_series(settled.map(|at| Circle::new(at, 3, colour.mix(0.5).filled())))?;
        }
        self.draw_unsettled(&mut chart, unsettled_row, &x_range)?;
        style::draw_legend(&mut chart, SeriesLabelPosition::LowerRight)
    }
}

impl LinesFigure<'_> {
    /// Marks every run without a settle time on the row `y`, with legend entries for the kinds present.
    /// Marks of different series are shifted apart a little along x so that they do not hide each other.
    fn draw_unsettled<DB, CT>(
        &self,
        chart: &mut ChartContext<'_, DB, CT>,
        y: f64,
        x_range: &Range<f64>,
    ) -> DrawResult<()>
    where
        DB: DrawingBackend,
        DB::ErrorType: 'static,
        CT: CoordTranslate<From = (f64, f64)>,
    {
        let series_values = self.series_param.map(|name| distinct_values(self.points, name)).unwrap_or_default();
        let shift = |p: &StudyPoint| {
            let value = self.series_param.and_then(|name| p.parameter(name));
            let index = series_values.iter().position(|v| Some(*v) == value).unwrap_or(0);
            let centred = index as f64 - (series_values.len().max(1) - 1) as f64 / 2.0;
            centred * UNSETTLED_SHIFT * (x_range.end - x_range.start)
        };
        let unsettled = || self.points.iter().filter(|p| p.settled_time().is_none());
        let at = |p: &StudyPoint| (p.parameter(self.x_param).unwrap_or(f64::NAN) + shift(p), y);
        let diverged: Vec<(f64, f64)> = unsettled().filter(|p| p.status == RunStatus::Diverged).map(at).collect();
        let other: Vec<(f64, f64)> = unsettled().filter(|p| p.status != RunStatus::Diverged).map(at).collect();
        let cross = DIVERGED.stroke_width(3);
        let hollow = NOT_SETTLED.stroke_width(2);
        if !diverged.is_empty() {
            chart
                .draw_series(diverged.into_iter().map(|at| Cross::new(at, 7, cross)))?
                .label("diverged (top row)")
                .legend(move |(x, y)| Cross::new((x + 12, y), 6, cross));
        }
        if !other.is_empty() {
            chart
                .draw_series(other.into_iter().map(|at| Circle::new(at, 6, hollow)))?
                .label("not settled / interrupted (top row)")
                .legend(move |(x, y)| Circle::new((x + 12, y), 6, hollow));
        }
        Ok(())
    }
}

/// Runs arranged on the grid of two parameters' distinct values.
struct Grid {
    xs: Vec<f64>,
    ys: Vec<f64>,
    /// (x index, y index, state, run count, 95 % half-width of a settled cell) of every grid point
    /// that has runs.
    cells: Vec<(usize, usize, CellState, usize, Option<f64>)>,
}

impl Grid {
    /// Groups `points` by their (x, y) parameter values.
    fn new(points: &[StudyPoint], x_param: &str, y_param: &str) -> Self {
        let xs = distinct_values(points, x_param);
        let ys = distinct_values(points, y_param);
        let mut cells = Vec::new();
        for (i, (_, column)) in group_by_value(points, x_param).into_iter().enumerate() {
            for (y, runs) in group_by_value(column, y_param) {
                let j = ys.partition_point(|&v| v < y);
                let state = cell_state(&runs);
                let half_width = settle_times(runs.iter().copied()).half_width_95;
                let half_width =
                    (matches!(state, CellState::Settled(_)) && half_width.is_finite()).then_some(half_width);
                cells.push((i, j, state, runs.len(), half_width));
            }
        }
        Self { xs, ys, cells }
    }

    /// The colour scale range: the settle times of settled cells, widened by the largest 95 %
    /// half-width on each side, so that cells whose intervals overlap do not look far apart.
    fn settle_range(&self) -> Range<f64> {
        let widest = self.cells.iter().filter_map(|c| c.4).fold(0.0, f64::max);
        let times = self.cells.iter().filter_map(|(_, _, state, _, _)| match state {
            CellState::Settled(t) => Some(*t),
            _ => None,
        });
        let ends = times.flat_map(|t| [(t - widest).max(0.0), t + widest]);
        match style::finite_bounds(ends) {
            Some((lo, hi)) if hi > lo => lo..hi,
            bounds => style::padded(bounds, 0.0),
        }
    }
}

/// The state of a grid point from its runs.
fn cell_state(runs: &[&StudyPoint]) -> CellState {
    if runs.iter().any(|p| p.status == RunStatus::Diverged) {
        CellState::Diverged
    } else if runs.iter().all(|p| p.settled_time().is_some()) {
        CellState::Settled(settle_times(runs.iter().copied()).mean)
    } else {
        CellState::NotSettled
    }
}

/// Settle time over a two-parameter grid.
struct HeatmapFigure<'a> {
    grid: Grid,
    x_param: &'a str,
    y_param: &'a str,
}

/// Width of the area right of the heatmap: colour bar and legend (pixels).
const SIDE_AREA: u32 = 190;
/// Height of the legend under the colour bar (pixels).
const LEGEND_AREA: u32 = 90;
/// Pixel sizes around the heatmap's plotting area.
const MARGIN: u32 = 15;
const X_LABEL_AREA: u32 = 55;
/// Smallest cell (pixels) that gets its settle time written in it.
const CELL_TEXT_MIN: (i32, i32) = (60, 26);

impl Figure for HeatmapFigure<'_> {
    type Layout = Vec<HeatmapCell>;

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        options: &ChartOptions,
    ) -> DrawResult<Vec<HeatmapCell>>
    where
        DB::ErrorType: 'static,
    {
        let body = style::titled(root, &options.title("Settle time"))?;
        let (body_width, _) = body.dim_in_pixel();
        let (left, right) = body.split_horizontally(body_width.saturating_sub(SIDE_AREA));
        // A segmented range 0..=n has n + 1 segments, one per grid value.
        let last = |values: &[f64]| (values.len() as i32 - 1).max(0);
        let (nx, ny) = (last(&self.grid.xs), last(&self.grid.ys));
        let mut chart = ChartBuilder::on(&left)
            .margin(MARGIN)
            .x_label_area_size(X_LABEL_AREA)
            .y_label_area_size(85)
            .build_cartesian_2d((0..nx).into_segmented(), (0..ny).into_segmented())?;
        let label = |values: &[f64], v: &SegmentValue<i32>| match v {
            SegmentValue::CenterOf(i) => values.get(*i as usize).map(|v| style::short_number(*v)).unwrap_or_default(),
            _ => String::new(),
        };
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(self.x_param)
            .y_desc(self.y_param)
            .x_labels(self.grid.xs.len())
            .y_labels(self.grid.ys.len())
            .x_label_formatter(&|v| label(&self.grid.xs, v))
            .y_label_formatter(&|v| label(&self.grid.ys, v))
            .label_style(style::text(LABEL_SIZE))
            .axis_desc_style(style::text(style::AXIS_DESC_SIZE))
            .draw()?;
        let range = self.grid.settle_range();
        let cells = self.draw_cells(&mut chart, root, &range)?;
        let bar_bottom = MARGIN + X_LABEL_AREA + LEGEND_AREA;
        style::colour_bar(&right, range, &quantity::label(quantity::SETTLE_TIME.name), (MARGIN, bar_bottom))?;
        let legend_top = right.dim_in_pixel().1.saturating_sub(LEGEND_AREA + X_LABEL_AREA);
        self.draw_legend(&right.shrink((20, legend_top), (170, LEGEND_AREA)))?;
        Ok(cells)
    }
}

impl HeatmapFigure<'_> {
    /// Draws one filled rectangle per grid point with runs, plus its mark or value; returns the cells.
    fn draw_cells<DB>(
        &self,
        chart: &mut ChartContext<'_, DB, Cartesian2d<SegmentedCoord<RangedCoordi32>, SegmentedCoord<RangedCoordi32>>>,
        root: &DrawingArea<DB, Shift>,
        range: &Range<f64>,
    ) -> DrawResult<Vec<HeatmapCell>>
    where
        DB: DrawingBackend,
        DB::ErrorType: 'static,
    {
        let mut cells = Vec::with_capacity(self.grid.cells.len());
        for &(i, j, state, runs, half_width_95) in &self.grid.cells {
            let (i, j) = (i as i32, j as i32);
            let upper_left = chart.backend_coord(&(SegmentValue::Exact(i), SegmentValue::Exact(j + 1)));
            let lower_right = chart.backend_coord(&(SegmentValue::Exact(i + 1), SegmentValue::Exact(j)));
            // One pixel of white between neighbouring cells.
            let pixels = [(upper_left.0 + 1, upper_left.1 + 1), (lower_right.0 - 1, lower_right.1 - 1)];
            root.draw(&Rectangle::new(pixels, cell_fill(state, range).filled()))?;
            draw_cell_mark(root, state, half_width_95, pixels, range)?;
            let (x, y) = (self.grid.xs[i as usize], self.grid.ys[j as usize]);
            cells.push(HeatmapCell { x, y, state, runs, half_width_95, pixels });
        }
        Ok(cells)
    }

    /// Swatches explaining the diverged and not settled cells, in `area`.
    fn draw_legend<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> DrawResult<()>
    where
        DB::ErrorType: 'static,
    {
        let entries = [(CellState::Diverged, "diverged"), (CellState::NotSettled, "not settled")];
        for (row, (state, label)) in entries.into_iter().enumerate() {
            let top = 10 + 36 * row as i32;
            let swatch = [(0, top), (28, top + 26)];
            area.draw(&Rectangle::new(swatch, cell_fill(state, &(0.0..1.0)).filled()))?;
            draw_cell_mark(area, state, None, swatch, &(0.0..1.0))?;
            area.draw(&Text::new(
                label,
                (38, top + 13),
                style::text(LABEL_SIZE).pos(Pos::new(HPos::Left, VPos::Center)),
            ))?;
        }
        Ok(())
    }
}

/// Fill colour of a cell: viridis settle time, light red when diverged, grey when not settled.
fn cell_fill(state: CellState, range: &Range<f64>) -> RGBColor {
    match state {
        CellState::Settled(t) => style::viridis(t, range),
        CellState::NotSettled => RGBColor(200, 200, 200),
        CellState::Diverged => RGBColor(250, 200, 200),
    }
}

/// What a cell shows on top of its fill: a red X when diverged, its settle time (and below it the
/// 95 % half-width, when known and there is room) when there is room.
fn draw_cell_mark<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    state: CellState,
    half_width_95: Option<f64>,
    [(x0, y0), (x1, y1)]: [(i32, i32); 2],
    range: &Range<f64>,
) -> DrawResult<()>
where
    DB::ErrorType: 'static,
{
    match state {
        CellState::Diverged => {
            let style = DIVERGED.stroke_width(3);
            area.draw(&PathElement::new([(x0 + 3, y0 + 3), (x1 - 3, y1 - 3)], style))?;
            area.draw(&PathElement::new([(x0 + 3, y1 - 3), (x1 - 3, y0 + 3)], style))?;
        }
        CellState::Settled(t) if x1 - x0 >= CELL_TEXT_MIN.0 && y1 - y0 >= CELL_TEXT_MIN.1 => {
            let light_cell = (t - range.start) / (range.end - range.start) > 0.6;
            let colour = if light_cell { BLACK } else { WHITE };
            let text = style::text(LABEL_SIZE).color(&colour).pos(Pos::new(HPos::Center, VPos::Center));
            let centre = ((x0 + x1) / 2, (y0 + y1) / 2);
            match half_width_95.filter(|_| y1 - y0 >= 2 * CELL_TEXT_MIN.1) {
                Some(half) => {
                    let line = LABEL_SIZE as i32 / 2 + 2;
                    area.draw(&Text::new(style::short_number(t), (centre.0, centre.1 - line), text.clone()))?;
                    let spread = format!("± {}", style::short_number(half));
                    area.draw(&Text::new(spread, (centre.0, centre.1 + line), text))?;
                }
                None => area.draw(&Text::new(style::short_number(t), centre, text))?,
            }
        }
        _ => {}
    }
    Ok(())
}
