//! Charts of one run: energies and unbalanced force ratio against time, the settled pile's stress
//! profile, and pile snapshots.

use std::ops::Range;
use std::path::PathBuf;

use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::style::{self, LINE_WIDTH};
use super::{Canvas, ChartOptions, DrawResult, Figure, Format, PlotError, render};
use crate::physics::quantity;
use crate::physics::record::{History, Snapshot};
use crate::physics::stress::{Stress, StressProfile};

/// Draws kinetic (translational + rotational), potential, elastic and total (kinetic + potential)
/// energy against time onto `canvas`, with the end of each stage of the run's protocol marked
/// (`stage_ends` as in [`UbfMarks`]). Samples that are not finite (a diverged run) break the lines.
pub fn energy_chart<'c>(
    history: &History,
    stage_ends: &[(String, f64)],
    options: &ChartOptions,
    canvas: impl Into<Canvas<'c>>,
) -> Result<(), PlotError> {
    render(&EnergyFigure { history, stage_ends }, options, canvas.into())
}

/// What the unbalanced force ratio chart marks besides the ratio.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UbfMarks<'a> {
    /// The settle threshold.
    pub threshold: f64,
    /// When the run settled (s), if it did.
    pub settle_time: Option<f64>,
    /// When each stage of the scene's protocol ended (s; NaN: the run ended first), by name.
    pub stage_ends: &'a [(String, f64)],
}

/// Draws the unbalanced force ratio against time on a log scale onto `canvas`, with the settle
/// threshold, the settle time (s) if the run settled, and the end of each stage of its protocol
/// marked. Samples without contacts (NaN) and zeros are left out.
pub fn ubf_chart<'c>(
    history: &History,
    marks: UbfMarks<'_>,
    options: &ChartOptions,
    canvas: impl Into<Canvas<'c>>,
) -> Result<(), PlotError> {
    render(&UbfFigure { history, marks }, options, canvas.into())
}

/// Draws the stress profile of a settled pile onto `canvas`: each height band's pressure and
/// deviatoric stress and the side walls' normal stress there (Pa) against the band's middle height
/// (m), a point per band. Bands whose values are not finite (a diverged run) break the lines.
pub fn stress_profile_chart<'c>(
    profile: &StressProfile,
    options: &ChartOptions,
    canvas: impl Into<Canvas<'c>>,
) -> Result<(), PlotError> {
    render(&StressProfileFigure { profile }, options, canvas.into())
}

/// Draws the disks of `snapshot` to scale inside the box `box_size` = (width, height) (m),
/// coloured on `scale`, with a colour bar, onto `canvas`. Returns where the box landed in pixels.
pub fn snapshot<'c>(
    snapshot: &Snapshot,
    box_size: (f64, f64),
    scale: &ColourScale,
    options: &ChartOptions,
    canvas: impl Into<Canvas<'c>>,
) -> Result<BoxFrame, PlotError> {
    render(&SnapshotFigure { snapshot, box_size, scale }, options, canvas.into())
}

/// How long each frame of a deposition animation shows (ms).
const ANIMATION_FRAME_MS: u16 = 500;

/// Draws `snapshots` (in time order, each on its colour scale) as an animated PNG (APNG: every
/// browser and most viewers play it; others show the first frame) onto a PNG file `canvas`, each
/// frame as [`snapshot`] draws it. An SVG canvas cannot animate: it gets the last snapshot.
pub fn animation<'c>(
    snapshots: &[(&Snapshot, ColourScale)],
    box_size: (f64, f64),
    options: &ChartOptions,
    canvas: impl Into<Canvas<'c>>,
) -> Result<(), PlotError> {
    let canvas = canvas.into();
    let Some(&(last, last_scale)) = snapshots.last() else {
        return Err(PlotError { path: PathBuf::from("(animation)"), reason: "no snapshots to animate".into() });
    };
    let path = match canvas {
        Canvas::File(path) if options.format == Format::Png => path.to_path_buf(),
        other => return snapshot(last, box_size, &last_scale, options, other).map(drop),
    };
    super::prepare_file(&path, options)?;
    let frames = snapshots
        .iter()
        .map(|(s, scale)| super::render_rgb(&SnapshotFigure { snapshot: s, box_size, scale }, options, &path))
        .map(|drawn| drawn.map(|(_, pixels)| pixels))
        .collect::<Result<Vec<_>, _>>()?;
    let bytes = super::encode_png(&frames, options, (&path, Some(ANIMATION_FRAME_MS)))?;
    super::write_image(&path, &bytes, options)
}

/// What the disks of a snapshot are coloured by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourBy {
    /// Speed |v| (m/s).
    Speed,
    /// Sum of contact force magnitudes on the disk (N).
    ContactForce,
}

impl ColourBy {
    /// The coloured quantity of every disk of `snapshot`.
    pub fn values(self, snapshot: &Snapshot) -> Vec<f64> {
        match self {
            ColourBy::Speed => snapshot.vx.iter().zip(&snapshot.vy).map(|(vx, vy)| vx.hypot(*vy)).collect(),
            ColourBy::ContactForce => snapshot.contact_force.clone(),
        }
    }

    /// Colour bar label, with unit.
    fn label(self) -> String {
        match self {
            ColourBy::Speed => quantity::labelled("speed", "m/s"),
            ColourBy::ContactForce => quantity::label("contact_force"),
        }
    }
}

/// The colour scale of snapshots: `by`, from zero to `max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColourScale {
    /// The coloured quantity.
    pub by: ColourBy,
    /// Value at the top of the scale (values above are drawn in its colour).
    pub max: f64,
}

impl ColourScale {
    /// A scale from zero to the largest finite value in `snapshots`: frames of one run drawn with it
    /// share their colours.
    pub fn fitted<'a>(by: ColourBy, snapshots: impl IntoIterator<Item = &'a Snapshot>) -> Self {
        let max = snapshots.into_iter().flat_map(|s| by.values(s)).filter(|v| v.is_finite()).fold(0.0, f64::max);
        Self { by, max }
    }

    /// The value range of the scale (0..1 when there is nothing to scale).
    fn range(&self) -> Range<f64> {
        if self.max > 0.0 && self.max.is_finite() { 0.0..self.max } else { 0.0..1.0 }
    }
}

/// Where a snapshot's box landed in the image: the pixel of the box corner (0, 0) and the pixels
/// per metre along x (right) and y (up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxFrame {
    /// Pixel (column, row) of the point x = 0, y = 0.
    pub origin: (f64, f64),
    /// Pixels per metre along x and along y.
    pub pixels_per_metre: (f64, f64),
}

impl BoxFrame {
    /// The pixel (column, row) of the point (x, y) (m); rows grow downwards.
    pub fn to_pixel(&self, x: f64, y: f64) -> (f64, f64) {
        (self.origin.0 + x * self.pixels_per_metre.0, self.origin.1 - y * self.pixels_per_metre.1)
    }
}

/// A data line of a time chart: its label, colour and unbroken stretches of points.
struct Line {
    label: String,
    colour: RGBColor,
    segments: Vec<Vec<(f64, f64)>>,
}

impl Line {
    /// The points of `values` against `time` that are finite and that `keep` accepts, with lines
    /// breaking at the others.
    fn new(label: &str, colour: RGBColor, (time, values): (&[f64], &[f64]), keep: impl Fn(f64) -> bool) -> Self {
        let segments = style::segments(time, values, |t, v| t.is_finite() && v.is_finite() && keep(v));
        Self { label: label.to_string(), colour, segments }
    }

    /// Every drawn value.
    fn values(&self) -> impl Iterator<Item = f64> + '_ {
        self.segments.iter().flatten().map(|&(_, v)| v)
    }
}

/// Pixel sizes of the areas around a chart's plotting area.
const MARGIN: u32 = 15;
const X_LABEL_AREA: u32 = 55;
const Y_LABEL_AREA: u32 = 85;

/// A time chart with `y` as its vertical axis, with a caption (text, size), labelled axes and grid.
fn time_chart<'a, DB, Y>(
    root: &'a DrawingArea<DB, Shift>,
    (caption, caption_size): (&str, u32),
    time: Range<f64>,
    (y, y_desc): (Y, &str),
) -> DrawResult<ChartContext<'a, DB, Cartesian2d<RangedCoordf64, Y::CoordDescType>>>
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
    Y: AsRangedCoord<Value = f64>,
    Y::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut chart = ChartBuilder::on(root)
        .caption(caption, style::title_text(root, caption, caption_size))
        .margin(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(time, y)?;
    style::numbered_mesh(&mut chart.configure_mesh()).x_desc(quantity::label("t")).y_desc(y_desc).draw()?;
    Ok(chart)
}

/// Draws `lines` on `chart`, each with a legend entry.
fn draw_lines<DB, CT>(chart: &mut ChartContext<'_, DB, CT>, lines: &[Line]) -> DrawResult<()>
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
    CT: CoordTranslate<From = (f64, f64)>,
{
    for line in lines {
        let style = line.colour.stroke_width(LINE_WIDTH);
        for (index, segment) in line.segments.iter().enumerate() {
            let drawn = chart.draw_series(LineSeries::new(segment.iter().copied(), style))?;
            if index == 0 {
                drawn.label(line.label.as_str()).legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], style));
            }
        }
    }
    Ok(())
}

/// Draws the end of each stage that ended (`stage_ends` by name, NaN: the run ended first) on
/// `chart` as a dotted vertical line across `span`, with a legend entry where `labelled`.
fn draw_stage_ends<DB, CT>(
    chart: &mut ChartContext<'_, DB, CT>,
    stage_ends: &[(String, f64)],
    span: Range<f64>,
    labelled: bool,
) -> DrawResult<()>
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
    CT: CoordTranslate<From = (f64, f64)>,
{
    for (k, (name, t)) in stage_ends.iter().filter(|(_, t)| t.is_finite()).enumerate() {
        let stage_style = style::series_colour(3 + k).stroke_width(LINE_WIDTH);
        let drawn = chart.draw_series(DashedLineSeries::new([(*t, span.start), (*t, span.end)], 3, 4, stage_style))?;
        if labelled {
            drawn
                .label(format!("stage {name} ends at {} s", style::short_number(*t)))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], stage_style));
        }
    }
    Ok(())
}

/// The time axis range of `history`.
fn time_range(history: &History) -> Range<f64> {
    style::padded(style::finite_bounds(history.time.iter().copied()), 0.0)
}

/// Energies against time: all four on a linear scale above, kinetic and elastic on a log scale
/// below; stage ends marked on both, named in the upper one's legend.
struct EnergyFigure<'a> {
    history: &'a History,
    stage_ends: &'a [(String, f64)],
}

/// Share of the energy chart's height given to the linear panel.
const ENERGY_PANEL_SHARE: f64 = 0.6;
/// The log panel spans at most this many decades below its largest value.
const LOG_PANEL_DECADES: f64 = 8.0;

impl Figure for EnergyFigure<'_> {
    type Layout = ();

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, options: &ChartOptions) -> DrawResult<()>
    where
        DB::ErrorType: 'static,
    {
        let h = self.history;
        let kinetic: Vec<f64> = h.kinetic_translational.iter().zip(&h.kinetic_rotational).map(|(t, r)| t + r).collect();
        let (kinetic, elastic) = ((h.time.as_slice(), kinetic.as_slice()), (h.time.as_slice(), h.elastic.as_slice()));
        let any = |_| true;
        let lines = [
            Line::new("kinetic", style::series_colour(0), kinetic, any),
            Line::new("potential", style::series_colour(1), (&h.time, &h.potential), any),
            Line::new("elastic", style::series_colour(2), elastic, any),
            Line::new("total (kinetic + potential)", BLACK, (&h.time, &h.total), any),
        ];
        let time = time_range(h);
        let (upper, lower) = root.split_vertically(f64::from(options.height) * ENERGY_PANEL_SHARE);
        let energy = style::padded(style::finite_bounds(lines.iter().flat_map(Line::values)), 0.05);
        let title = options.title("Energies");
        let energy_label = quantity::labelled("energy", "J");
        let mut chart = time_chart(&upper, (&title, style::TITLE_SIZE), time.clone(), (energy.clone(), &energy_label))?;
        draw_lines(&mut chart, &lines)?;
        draw_stage_ends(&mut chart, self.stage_ends, energy, true)?;
        style::draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        let positive = style::finite_bounds(lines[0].values().chain(lines[2].values()).filter(|v| *v > 0.0));
        let (lo, hi) = positive.unwrap_or((1e-3, 1.0));
        let (lo, hi) = (lo.max(hi * 10f64.powf(-LOG_PANEL_DECADES)) / 2.0, hi * 2.0);
        let detail = [
            Line::new("kinetic", style::series_colour(0), kinetic, |v| v >= lo),
            Line::new("elastic", style::series_colour(2), elastic, |v| v >= lo),
        ];
        let caption = ("kinetic and elastic energy, log scale", style::AXIS_DESC_SIZE);
        let mut chart = time_chart(&lower, caption, time, (style::log_span(lo, hi).log_scale(), &energy_label))?;
        draw_lines(&mut chart, &detail)?;
        draw_stage_ends(&mut chart, self.stage_ends, lo..hi, false)?;
        style::draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

/// Stress against height, one line per stress of [`stress_profile_chart`].
struct StressProfileFigure<'a> {
    profile: &'a StressProfile,
}

impl Figure for StressProfileFigure<'_> {
    type Layout = ();

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, options: &ChartOptions) -> DrawResult<()>
    where
        DB::ErrorType: 'static,
    {
        let p = self.profile;
        let middle: Vec<f64> = p.bottom.iter().zip(&p.top).map(|(b, t)| 0.5 * (b + t)).collect();
        let pressure: Vec<f64> = p.stress.iter().map(Stress::pressure).collect();
        let deviatoric: Vec<f64> = p.stress.iter().map(Stress::deviatoric).collect();
        let stresses = [
            ("pressure (σxx + σyy)/2", &pressure),
            ("deviatoric stress", &deviatoric),
            ("side walls' normal stress", &p.wall_normal),
        ];
        let lines: Vec<Line> = (stresses.iter().enumerate())
            .map(|(k, (label, values))| Line::new(label, style::series_colour(k), (values, &middle), |_| true))
            .collect();
        let all = stresses.iter().flat_map(|(_, values)| values.iter().copied());
        let stress = style::padded(style::finite_bounds(all.chain([0.0])), 0.05);
        let top = p.top.iter().copied().filter(|h| h.is_finite()).fold(0.0, f64::max);
        let height = 0.0..if top > 0.0 { top } else { 1.0 };
        let title = options.title("Stress profile of the settled pile");
        let mut chart = ChartBuilder::on(root)
            .caption(&title, style::title_text(root, &title, style::TITLE_SIZE))
            .margin(MARGIN)
            .x_label_area_size(X_LABEL_AREA)
            .y_label_area_size(Y_LABEL_AREA)
            .build_cartesian_2d(stress, height)?;
        let (x_desc, y_desc) = (quantity::labelled("stress", "Pa"), quantity::labelled("height", "m"));
        style::numbered_mesh(&mut chart.configure_mesh()).x_desc(x_desc).y_desc(y_desc).draw()?;
        draw_lines(&mut chart, &lines)?;
        for line in &lines {
            let points = line.segments.iter().flatten().map(|&point| Circle::new(point, 3, line.colour.filled()));
            chart.draw_series(points)?;
        }
        style::draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

/// Unbalanced force ratio against time, log scale.
struct UbfFigure<'a> {
    history: &'a History,
    marks: UbfMarks<'a>,
}

impl Figure for UbfFigure<'_> {
    type Layout = ();

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, options: &ChartOptions) -> DrawResult<()>
    where
        DB::ErrorType: 'static,
    {
        let h = self.history;
        let ubf =
            Line::new("unbalanced force ratio", style::series_colour(0), (&h.time, &h.unbalanced_force_ratio), |v| {
                v > 0.0
            });
        let positive = ubf.values().chain([self.marks.threshold]).filter(|v| *v > 0.0);
        let (lo, hi) = style::finite_bounds(positive).unwrap_or((1e-3, 1.0));
        // At least two decades, so that the log axis has labelled ticks.
        let lo = lo.min(hi / 100.0);
        let axis = style::log_span(lo / 3.0, hi * 3.0);
        let time = time_range(h);
        let title = options.title("Unbalanced force ratio");
        let caption = (title.as_str(), style::TITLE_SIZE);
        let mut chart = time_chart(
            root,
            caption,
            time.clone(),
            (axis.clone().log_scale(), &quantity::label("unbalanced_force_ratio")),
        )?;
        draw_lines(&mut chart, std::slice::from_ref(&ubf))?;
        self.draw_markers(&mut chart, time, axis)?;
        // Early times (no or few contacts) and low ratios: the lower left is usually empty.
        style::draw_legend(&mut chart, SeriesLabelPosition::LowerLeft)
    }
}

impl UbfFigure<'_> {
    /// The threshold (dashed horizontal line), the settle time (vertical line, or a note that there
    /// is none) and the end of each stage of a protocol (dotted vertical lines).
    fn draw_markers<DB, CT>(
        &self,
        chart: &mut ChartContext<'_, DB, CT>,
        time: Range<f64>,
        ubf: Range<f64>,
    ) -> DrawResult<()>
    where
        DB: DrawingBackend,
        DB::ErrorType: 'static,
        CT: CoordTranslate<From = (f64, f64)>,
    {
        let threshold_style = BLACK.stroke_width(LINE_WIDTH);
        let threshold = [(time.start, self.marks.threshold), (time.end, self.marks.threshold)];
        chart
            .draw_series(DashedLineSeries::new(threshold, 10, 6, threshold_style))?
            .label(format!("settle threshold {}", style::short_number(self.marks.threshold)))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], threshold_style));
        draw_stage_ends(chart, self.marks.stage_ends, ubf.clone(), true)?;
        let settle_style = style::series_colour(2).stroke_width(LINE_WIDTH + 1);
        match self.marks.settle_time {
            Some(t) => {
                chart
                    .draw_series(LineSeries::new([(t, ubf.start), (t, ubf.end)], settle_style))?
                    .label(format!("settle time {} s", style::short_number(t)))
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], settle_style));
            }
            None => {
                let note = Text::new("no settle time", (10, 10), style::text(style::AXIS_DESC_SIZE));
                chart.draw_series([EmptyElement::at((time.start, ubf.end)) + note])?;
            }
        }
        Ok(())
    }
}

/// Disks to scale in their box.
struct SnapshotFigure<'a> {
    snapshot: &'a Snapshot,
    box_size: (f64, f64),
    scale: &'a ColourScale,
}

/// Width of the colour bar area (pixels).
const COLOUR_BAR_AREA: u32 = 140;

impl SnapshotFigure<'_> {
    /// The x and y ranges drawn: the box (up to the highest disk top if that is higher) and a small margin.
    fn ranges(&self) -> (Range<f64>, Range<f64>) {
        let s = self.snapshot;
        let (width, height) = self.box_size;
        let top = s.y.iter().zip(&s.r).map(|(y, r)| y + r).filter(|v| v.is_finite()).fold(height, f64::max);
        let pad = 0.02 * width.max(top);
        (-pad..width + pad, -pad..top + pad)
    }
}

impl Figure for SnapshotFigure<'_> {
    type Layout = BoxFrame;

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, options: &ChartOptions) -> DrawResult<BoxFrame>
    where
        DB::ErrorType: 'static,
    {
        let title = options.title(&format!("Pile at t = {} s", style::short_number(self.snapshot.time)));
        let body = style::titled(root, &title)?;
        let (body_width, body_height) = body.dim_in_pixel();
        let (x_range, y_range) = self.ranges();
        // Fit the box so that a metre spans the same number of pixels along x and y, then centre
        // the chart and its colour bar in the spare room.
        let available_w = f64::from(body_width.saturating_sub(COLOUR_BAR_AREA + Y_LABEL_AREA + 2 * MARGIN));
        let available_h = f64::from(body_height.saturating_sub(X_LABEL_AREA + 2 * MARGIN));
        let span = (x_range.end - x_range.start, y_range.end - y_range.start);
        let pixels_per_metre = (available_w / span.0).min(available_h / span.1);
        let spare_w = (available_w - span.0 * pixels_per_metre) as u32;
        let spare_h = (available_h - span.1 * pixels_per_metre) as u32;
        let group = body.margin(spare_h / 2, spare_h - spare_h / 2, spare_w / 2, spare_w - spare_w / 2);
        let (area, bar_area) = group.split_horizontally(group.dim_in_pixel().0.saturating_sub(COLOUR_BAR_AREA));
        let mut chart = ChartBuilder::on(&area)
            .margin(MARGIN)
            .x_label_area_size(X_LABEL_AREA)
            .y_label_area_size(Y_LABEL_AREA)
            .build_cartesian_2d(x_range, y_range)?;
        style::numbered_mesh(&mut chart.configure_mesh())
            .disable_mesh()
            .x_desc(quantity::label("x"))
            .y_desc(quantity::label("y"))
            .x_labels(6)
            .y_labels(8)
            .draw()?;
        let (width, height) = self.box_size;
        chart.draw_series([PathElement::new(
            [(0.0, height), (0.0, 0.0), (width, 0.0), (width, height)],
            BLACK.stroke_width(3),
        )])?;
        let frame = box_frame(&chart, self.box_size);
        chart.draw_series(self.disks(frame.pixels_per_metre.0))?;
        chart.draw_series(self.force_chains(frame.pixels_per_metre.0))?;
        style::colour_bar(&bar_area, self.scale.range(), &self.scale.by.label(), (MARGIN, MARGIN + X_LABEL_AREA))?;
        Ok(frame)
    }
}

impl SnapshotFigure<'_> {
    /// One filled circle per disk with a finite position; radius rounded down to whole pixels so that
    /// touching disks stay apart. Disks without a finite colour value are grey.
    fn disks(&self, pixels_per_metre: f64) -> Vec<Circle<(f64, f64), f64>> {
        let s = self.snapshot;
        let range = self.scale.range();
        let values = self.scale.by.values(s);
        (0..s.x.len())
            .filter(|&i| s.x[i].is_finite() && s.y[i].is_finite() && s.r[i].is_finite())
            .map(|i| {
                let value = values.get(i).copied().unwrap_or(f64::NAN);
                let colour = if value.is_finite() { style::viridis(value, &range) } else { style::NOT_SETTLED };
                Circle::new((s.x[i], s.y[i]), (s.r[i] * pixels_per_metre).max(1.0), colour.filled())
            })
            .collect()
    }
}

/// Widest force-chain line, as a fraction of the smallest disk's drawn diameter.
const CHAIN_WIDTH: f64 = 0.6;
/// Colour of the force-chain lines (dark red: apart from the black walls and the viridis disks).
pub const CHAIN_COLOUR: RGBColor = RGBColor(160, 0, 0);

impl SnapshotFigure<'_> {
    /// The force chains: one [`CHAIN_COLOUR`] line per contact carrying compression, between the centres (to the
    /// contact point for a wall), its width proportional to the normal force (the widest, the largest
    /// force, [`CHAIN_WIDTH`] of the smallest disk's diameter; lines under a pixel are left out).
    fn force_chains(&self, pixels_per_metre: f64) -> Vec<PathElement<(f64, f64)>> {
        let s = self.snapshot;
        let c = &s.contacts;
        let largest = c.normal_force.iter().copied().filter(|f| f.is_finite()).fold(0.0, f64::max);
        let smallest_radius = s.r.iter().copied().filter(|r| r.is_finite()).fold(f64::INFINITY, f64::min);
        let widest = CHAIN_WIDTH * 2.0 * smallest_radius * pixels_per_metre;
        if largest <= 0.0 || !widest.is_finite() {
            return Vec::new();
        }
        (0..c.len())
            .filter_map(|k| {
                let width = (widest * c.normal_force[k] / largest).round();
                let i = c.first[k] as usize;
                let far = match usize::try_from(c.second[k]) {
                    Ok(j) => (s.x[j], s.y[j]),
                    Err(_) => (c.point_x[k], c.point_y[k]),
                };
                (width >= 1.0)
                    .then(|| PathElement::new([(s.x[i], s.y[i]), far], CHAIN_COLOUR.stroke_width(width as u32)))
            })
            .collect()
    }
}

/// The pixel frame of the box from where its corners landed on `chart`.
fn box_frame<DB: DrawingBackend>(
    chart: &ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    (width, height): (f64, f64),
) -> BoxFrame {
    let origin = chart.backend_coord(&(0.0, 0.0));
    let corner = chart.backend_coord(&(width, height));
    BoxFrame {
        origin: (f64::from(origin.0), f64::from(origin.1)),
        pixels_per_metre: (f64::from(corner.0 - origin.0) / width, f64::from(origin.1 - corner.1) / height),
    }
}
