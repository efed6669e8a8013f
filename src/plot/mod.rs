//! Pictures of runs and studies: energy and UBF histories, pile snapshots, settle-time charts.
//!
//! Every chart is drawn with plotters into a PNG or an SVG file ([`Format`]) of a fixed pixel size
//! ([`ChartOptions`]). Text uses the bundled DejaVu Sans font (`assets/fonts/`), so drawing needs no
//! system font libraries. Charts take in-memory data: [`crate::physics::record`] types for one run,
//! [`StudyPoint`]s for a study; [`results`] draws them all from a results file (`demsweep plot`).

use std::error::Error;
use std::fmt;
use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::output::guard::{self, Existing};
use crate::physics::RunStatus;
use style::DrawResult;

pub mod bench;
pub mod compare;
pub mod results;
pub mod run;
pub mod study;
mod style;
pub mod tune;

/// Image file format of a chart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Raster image (RGB PNG).
    Png,
    /// Vector image.
    Svg,
}

impl Format {
    /// File name extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Png => "png",
            Format::Svg => "svg",
        }
    }
}

/// Size, format and subject of a chart.
#[derive(Clone, Debug, PartialEq)]
pub struct ChartOptions {
    /// Image width (pixels).
    pub width: u32,
    /// Image height (pixels).
    pub height: u32,
    /// PNG or SVG.
    pub format: Format,
    /// What the chart is about (e.g. a run id and its parameters), appended to its title.
    pub subject: Option<String>,
    /// What an existing file at a chart's path may be, to be replaced (by default a chart demsweep
    /// drew: every chart file carries its mark, see [`crate::output::guard`]).
    pub existing: Existing,
}

impl Default for ChartOptions {
    fn default() -> Self {
        Self { width: 1000, height: 700, format: Format::Png, subject: None, existing: Existing::Ours { force: false } }
    }
}

impl ChartOptions {
    /// Smallest image size (pixels) the chart layouts fit in.
    pub const MIN_SIZE: (u32, u32) = (400, 300);

    /// The title of a chart showing `what`: `what`, then the subject if there is one.
    fn title(&self, what: &str) -> String {
        match &self.subject {
            Some(subject) => format!("{what} — {subject}"),
            None => what.to_string(),
        }
    }
}

/// A chart that could not be drawn or written, with the file it was meant for.
#[derive(Clone, Debug)]
pub struct PlotError {
    /// The image file.
    pub path: PathBuf,
    /// What went wrong.
    pub reason: String,
}

impl fmt::Display for PlotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.reason)
    }
}

impl Error for PlotError {}

/// One run of a study as the study charts see it.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyPoint {
    /// Swept parameters (dotted key path, value) of the run.
    pub parameters: Vec<(String, f64)>,
    /// How the run ended.
    pub status: RunStatus,
    /// When it settled (s), if it did.
    pub settle_time: Option<f64>,
}

impl StudyPoint {
    /// The value of the swept parameter `name`, if this run has it.
    pub fn parameter(&self, name: &str) -> Option<f64> {
        self.parameters.iter().find(|(key, _)| key == name).map(|(_, value)| *value)
    }

    /// The settle time of a run that settled; `None` for every other run.
    fn settled_time(&self) -> Option<f64> {
        self.settle_time.filter(|t| self.status == RunStatus::Settled && t.is_finite())
    }
}

impl From<guard::GuardError> for PlotError {
    fn from(e: guard::GuardError) -> Self {
        PlotError { reason: e.refusal_text(), path: e.path }
    }
}

/// A picture that can be drawn on any plotters backend.
trait Figure {
    /// What drawing reports back (e.g. where things landed, in pixels).
    type Layout;

    /// Draws the picture on `root`, a white area of the options' size.
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        options: &ChartOptions,
    ) -> DrawResult<Self::Layout>
    where
        DB::ErrorType: 'static;
}

/// Where a chart is drawn: an image file in the options' format, or an SVG document in memory
/// (for a page that embeds its charts). Chart functions take either (`&Path`, `&PathBuf`, `&mut String`).
pub enum Canvas<'a> {
    /// An image file (its folder is created if needed).
    File(&'a Path),
    /// An SVG document appended to this string, whatever the options' format.
    Svg(&'a mut String),
}

impl Canvas<'_> {
    /// What errors name: the file, or `(SVG in memory)`.
    fn label(&self) -> PathBuf {
        match self {
            Canvas::File(path) => path.to_path_buf(),
            Canvas::Svg(_) => PathBuf::from("(SVG in memory)"),
        }
    }
}

impl<'a> From<&'a Path> for Canvas<'a> {
    fn from(path: &'a Path) -> Self {
        Canvas::File(path)
    }
}

impl<'a> From<&'a PathBuf> for Canvas<'a> {
    fn from(path: &'a PathBuf) -> Self {
        Canvas::File(path)
    }
}

impl<'a> From<&'a mut String> for Canvas<'a> {
    fn from(svg: &'a mut String) -> Self {
        Canvas::Svg(svg)
    }
}

/// Draws `figure` onto `canvas` in the options' size (and format, for a file), creating the file's folder.
fn render<F: Figure>(figure: &F, options: &ChartOptions, canvas: Canvas<'_>) -> Result<F::Layout, PlotError> {
    let label = canvas.label();
    let fail = |reason: String| PlotError { path: label.clone(), reason };
    let (min_width, min_height) = ChartOptions::MIN_SIZE;
    if options.width < min_width || options.height < min_height {
        return Err(fail(format!(
            "image size {}x{} is below the smallest chart size {min_width}x{min_height} pixels",
            options.width, options.height
        )));
    }
    let path = match canvas {
        Canvas::Svg(svg) => {
            style::register_font();
            let root = SVGBackend::with_string(svg, (options.width, options.height)).into_drawing_area();
            return paint(figure, options, root).map_err(|e| fail(e.to_string()));
        }
        Canvas::File(path) => path,
    };
    prepare_file(path, options)?;
    let (layout, bytes) = match options.format {
        Format::Png => render_rgb(figure, options, path)
            .and_then(|(layout, pixels)| Ok((layout, encode_png(&[pixels], options, (path, None))?))),
        Format::Svg => {
            let mut svg = String::from(guard::SVG_MARK);
            style::register_font();
            let root = SVGBackend::with_string(&mut svg, (options.width, options.height)).into_drawing_area();
            let layout = paint(figure, options, root).map_err(|e| fail(e.to_string()))?;
            Ok((layout, svg.into_bytes()))
        }
    }?;
    write_image(path, &bytes, options)?;
    Ok(layout)
}

/// Creates the folder of the image file `path` and checks that the file may be written there.
fn prepare_file(path: &Path, options: &ChartOptions) -> Result<(), PlotError> {
    if let Some(folder) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(folder)
            .map_err(|e| PlotError { path: path.to_path_buf(), reason: format!("cannot create folder: {e}") })?;
    }
    Ok(guard::check_replaceable(path, &[], options.existing)?)
}

/// Writes an image file whole or not at all (see [`guard::write_with`]).
fn write_image(path: &Path, bytes: &[u8], options: &ChartOptions) -> Result<(), PlotError> {
    Ok(guard::write_with(path, &[], options.existing, |out| out.write_all(bytes))?)
}

/// Encodes RGB `frames` of the options' size as a PNG carrying demsweep's mark ([`guard::PNG_MARK`]):
/// an animated one showing each frame `frame_ms` milliseconds, when given. Errors name `path`.
fn encode_png(
    frames: &[Vec<u8>],
    options: &ChartOptions,
    (path, frame_ms): (&Path, Option<u16>),
) -> Result<Vec<u8>, PlotError> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, options.width, options.height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let (keyword, text) = guard::PNG_MARK;
    let mut encoded = encoder.add_text_chunk(keyword.into(), text.into());
    if let Some(ms) = frame_ms {
        encoded = encoded
            .and_then(|()| encoder.set_animated(frames.len() as u32, 0))
            .and_then(|()| encoder.set_frame_delay(ms, 1000));
    }
    encoded
        .and_then(|()| encoder.write_header())
        .and_then(|mut writer| {
            frames.iter().try_for_each(|pixels| writer.write_image_data(pixels)).and_then(|()| writer.finish())
        })
        .map_err(|e| PlotError { path: path.to_path_buf(), reason: format!("cannot encode the image: {e}") })?;
    Ok(bytes)
}

/// Draws `figure` in the options' size into 8-bit RGB pixels (rows top to bottom), e.g. for the
/// frames of an animation; returns what the drawing returned and the pixels.
fn render_rgb<F: Figure>(figure: &F, options: &ChartOptions, label: &Path) -> Result<(F::Layout, Vec<u8>), PlotError> {
    let mut pixels = vec![0u8; options.width as usize * options.height as usize * 3];
    style::register_font();
    let root = BitMapBackend::with_buffer(&mut pixels, (options.width, options.height)).into_drawing_area();
    let layout =
        paint(figure, options, root).map_err(|e| PlotError { path: label.to_path_buf(), reason: e.to_string() })?;
    Ok((layout, pixels))
}

/// Clears `root` to white, draws `figure` and writes the result.
fn paint<F: Figure, DB: DrawingBackend>(
    figure: &F,
    options: &ChartOptions,
    root: DrawingArea<DB, Shift>,
) -> DrawResult<F::Layout>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let layout = figure.draw(&root, options)?;
    root.present()?;
    Ok(layout)
}
