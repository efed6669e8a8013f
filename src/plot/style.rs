//! Shared look of the charts: font, sizes, colours, axis ranges and the colour bar.

use std::ops::Range;
use std::sync::Once;

use plotters::chart::MeshStyle;
use plotters::coord::Shift;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::prelude::*;
use plotters::style::register_font as register_plotters_font;

/// What drawing code returns: plotters' errors carry the backend's error type, boxed here.
pub(super) type DrawResult<T> = Result<T, Box<dyn std::error::Error>>;

/// Font family name every chart uses (registered from the bundled file).
pub(super) const FONT: &str = "sans-serif";
/// Title text size (pixels).
pub(super) const TITLE_SIZE: u32 = 26;
/// Axis description text size (pixels).
pub(super) const AXIS_DESC_SIZE: u32 = 20;
/// Smallest size a title shrinks to when it is too wide for its image (pixels).
const MIN_TITLE_SIZE: u32 = 12;
/// Room left on either side of a title (pixels).
const TITLE_PADDING: u32 = 10;
/// Tick label, legend and annotation text size (pixels).
pub(super) const LABEL_SIZE: u32 = 16;
/// Width of data lines (pixels).
pub(super) const LINE_WIDTH: u32 = 2;

/// Colour of runs that diverged.
pub(super) const DIVERGED: RGBColor = RGBColor(200, 20, 20);
/// Colour of runs that did not settle (or were interrupted).
pub(super) const NOT_SETTLED: RGBColor = RGBColor(140, 140, 140);
/// Colours of data series in order (the "tab10" set without its red, which marks divergence).
pub(super) const SERIES: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// DejaVu Sans (Bitstream Vera licence, see `assets/fonts/DejaVu-LICENSE.txt`).
static FONT_FILE: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Gives a chart's mesh the common look: numbers on both axes written short, the shared text
/// sizes, light grid lines.
pub(super) fn numbered_mesh<'a, 'b, 'm, X, Y, DB>(
    mesh: &'m mut MeshStyle<'a, 'b, X, Y, DB>,
) -> &'m mut MeshStyle<'a, 'b, X, Y, DB>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    DB: DrawingBackend,
{
    mesh.x_label_formatter(&axis_number)
        .y_label_formatter(&axis_number)
        .label_style(text(LABEL_SIZE))
        .axis_desc_style(text(AXIS_DESC_SIZE))
        .light_line_style(RGBColor(235, 235, 235))
}

fn axis_number(value: &f64) -> String {
    short_number(*value)
}

/// Registers the bundled font with plotters (once per process).
pub(super) fn register_font() {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        let registered = register_plotters_font(FONT, FontStyle::Normal, FONT_FILE).is_ok();
        assert!(registered, "the bundled font assets/fonts/DejaVuSans.ttf is not a valid TrueType font");
    });
}

/// Half-length of the caps of an error bar (pixels).
const ERROR_BAR_CAP: i32 = 5;

/// Draws vertical error bars `(x, low, high)` in `colour`: a line from low to high with short caps.
/// Bars with a non-finite end are left out.
pub(super) fn error_bars<DB, CT>(
    chart: &mut ChartContext<'_, DB, CT>,
    bars: impl IntoIterator<Item = (f64, f64, f64)>,
    colour: RGBColor,
) -> DrawResult<()>
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
    CT: CoordTranslate<From = (f64, f64)>,
{
    let line = colour.stroke_width(LINE_WIDTH);
    let cap = |at: (f64, f64)| EmptyElement::at(at) + PathElement::new([(-ERROR_BAR_CAP, 0), (ERROR_BAR_CAP, 0)], line);
    for (x, low, high) in bars.into_iter().filter(|(x, low, high)| x.is_finite() && low.is_finite() && high.is_finite())
    {
        chart.draw_series([PathElement::new([(x, low), (x, high)], line)])?;
        chart.draw_series([cap((x, low)), cap((x, high))])?;
    }
    Ok(())
}

/// Draws the legend of `chart`'s labelled series at `position`, on a light box with a black border.
pub(super) fn draw_legend<'a, DB, CT>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> DrawResult<()>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
    CT: CoordTranslate,
{
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(text(LABEL_SIZE))
        .draw()?;
    Ok(())
}

/// The `index`-th series colour, cycling.
pub(super) fn series_colour(index: usize) -> RGBColor {
    SERIES[index % SERIES.len()]
}

/// The area below a title drawn at the top of `root`.
pub(super) fn titled<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
) -> DrawResult<DrawingArea<DB, Shift>>
where
    DB::ErrorType: 'static,
{
    Ok(root.margin(10, 0, 0, 0).titled(title, title_text(root, title, TITLE_SIZE))?)
}

/// Text of `size` for the title `title` across `area`, smaller where needed so that it fits the width.
pub(super) fn title_text<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    size: u32,
) -> TextStyle<'static> {
    let width = area.dim_in_pixel().0.saturating_sub(2 * TITLE_PADDING);
    let too_wide = |size: u32| area.estimate_text_size(title, &text(size)).is_ok_and(|(w, _)| w > width);
    let fitting = (MIN_TITLE_SIZE..=size).rev().find(|&s| !too_wide(s));
    text(fitting.unwrap_or(MIN_TITLE_SIZE.min(size)))
}

/// Text style of the given size in the chart font.
pub(super) fn text(size: u32) -> TextStyle<'static> {
    (FONT, size).into_font().into()
}

/// Smallest and largest finite value, or `None` when there is none.
pub(super) fn finite_bounds(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold(None, |acc, v| Some(acc.map_or((v, v), |(lo, hi): (f64, f64)| (lo.min(v), hi.max(v)))))
}

/// The smallest and largest value a logarithmic axis spans. Its key points are found by multiplying
/// by ten from the lower end to the upper: both must be finite and non-zero, with room to spare.
const LOG_AXIS_LIMITS: (f64, f64) = (1e-300, 1e300);

/// `lo..hi` made drawable as a logarithmic axis: within [`LOG_AXIS_LIMITS`] and increasing (a single
/// value gets a decade either side), whatever the values (zero, subnormal, infinite or NaN).
pub(super) fn log_span(lo: f64, hi: f64) -> Range<f64> {
    let (min, max) = LOG_AXIS_LIMITS;
    let limited = |v: f64| if v.is_nan() { 1.0 } else { v.clamp(min, max) };
    let (lo, hi) = (limited(lo.min(hi)), limited(hi.max(lo)));
    if lo < hi { lo..hi } else { lo / 10.0..hi * 10.0 }
}

/// An axis range covering `bounds` with `margin` (a fraction of the span) on both sides;
/// a single value gets a unit-sized range around it, no value the range 0..1.
pub(super) fn padded(bounds: Option<(f64, f64)>, margin: f64) -> Range<f64> {
    match bounds {
        None => 0.0..1.0,
        Some((lo, hi)) if hi > lo => {
            let pad = (hi - lo) * margin;
            lo - pad..hi + pad
        }
        Some((v, _)) => {
            let half = if v == 0.0 { 0.5 } else { v.abs() * 0.5 };
            v - half..v + half
        }
    }
}

/// Splits the points (x[i], y[i]) into runs of consecutive points that `keep` accepts:
/// a line drawn through each run breaks wherever a point was left out.
pub(super) fn segments(x: &[f64], y: &[f64], keep: impl Fn(f64, f64) -> bool) -> Vec<Vec<(f64, f64)>> {
    let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current = Vec::new();
    for (&xi, &yi) in x.iter().zip(y) {
        if keep(xi, yi) {
            current.push((xi, yi));
        } else if !current.is_empty() {
            runs.push(std::mem::take(&mut current));
        }
    }
    if !current.is_empty() {
        runs.push(current);
    }
    runs
}

/// A number written short: up to four significant digits, exponent form when very large or small.
pub(super) fn short_number(value: f64) -> String {
    let magnitude = value.abs();
    if value == 0.0 || !value.is_finite() {
        format!("{value}")
    } else if !(1e-3..1e5).contains(&magnitude) {
        let text = format!("{value:.2e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        format!("{}e{exponent}", trim_zeros(mantissa))
    } else {
        let decimals = (3 - magnitude.log10().floor() as i32).max(0) as usize;
        trim_zeros(&format!("{value:.decimals$}")).to_string()
    }
}

/// A decimal number without trailing zeros after its point (and without a trailing point).
fn trim_zeros(text: &str) -> &str {
    if text.contains('.') { text.trim_end_matches('0').trim_end_matches('.') } else { text }
}

/// Viridis colour of `value` on the scale `range` (values outside are clamped). The fraction along
/// the scale is computed in f64: a scale up to 1e200 (a diverged run's speeds) overflows f32.
pub(super) fn viridis(value: f64, range: &Range<f64>) -> RGBColor {
    let fraction = (value - range.start) / (range.end - range.start);
    let fraction = if fraction.is_finite() { fraction.clamp(0.0, 1.0) } else { 0.0 };
    ViridisRGB.get_color_normalized(fraction as f32, 0.0, 1.0)
}

/// Number of colour steps drawn in a colour bar.
const COLOUR_BAR_STEPS: usize = 128;
/// Width of the colour bar itself (pixels).
const COLOUR_BAR_WIDTH: u32 = 28;
/// Gap between the chart and the colour bar (pixels).
const COLOUR_BAR_GAP: u32 = 10;
/// Width of the colour bar's tick labels and description (pixels).
const COLOUR_BAR_LABELS: u32 = 95;

/// Draws a vertical viridis colour bar for `range` at the left of `area`, with tick labels and `label`
/// on its right. `top` and `bottom` are the pixel margins that line it up with the chart beside it.
pub(super) fn colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    range: Range<f64>,
    label: &str,
    (top, bottom): (u32, u32),
) -> DrawResult<()>
where
    DB::ErrorType: 'static,
{
    let mut bar = ChartBuilder::on(area)
        .margin_top(top)
        .margin_bottom(bottom)
        .margin_left(COLOUR_BAR_GAP)
        .margin_right(area.dim_in_pixel().0.saturating_sub(COLOUR_BAR_GAP + COLOUR_BAR_WIDTH + COLOUR_BAR_LABELS))
        .right_y_label_area_size(COLOUR_BAR_LABELS)
        .build_cartesian_2d(0.0..1.0, range.clone())?;
    bar.configure_mesh()
        .disable_x_axis()
        .disable_mesh()
        .y_desc(label)
        .y_labels(8)
        .set_all_tick_mark_size(6)
        .y_label_formatter(&|v| short_number(*v))
        .label_style(text(LABEL_SIZE))
        .axis_desc_style(text(AXIS_DESC_SIZE))
        .draw()?;
    let step = (range.end - range.start) / COLOUR_BAR_STEPS as f64;
    bar.draw_series((0..COLOUR_BAR_STEPS).map(|i| {
        let lo = range.start + step * i as f64;
        Rectangle::new([(0.0, lo), (1.0, lo + step)], viridis(lo + step / 2.0, &range).filled())
    }))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_takes_scales_beyond_f32_and_values_that_are_not_finite() {
        let huge = 0.0..1e200;
        assert_eq!(viridis(1e200, &huge), viridis(1.0, &(0.0..1.0)), "the top of the scale");
        assert_eq!(viridis(0.0, &huge), viridis(0.0, &(0.0..1.0)), "the bottom of the scale");
        assert_eq!(viridis(f64::NAN, &huge), viridis(0.0, &huge));
        assert_eq!(viridis(f64::INFINITY, &(0.0..f64::INFINITY)), viridis(0.0, &huge));
        assert_eq!(viridis(2e300, &huge), viridis(1e200, &huge), "clamped");
    }
}
