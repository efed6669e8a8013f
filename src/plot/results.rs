//! Plots of a results file (`demsweep plot`): the charts of the whole study, then those of
//! selected runs, drawn from what `demsweep run` stored.
//!
//! Study charts: settle time against the first swept numeric parameter, one line per value of the
//! second (if any), and a heatmap over the first two. Per run: energies, unbalanced force ratio,
//! the settled pile's stress profile, and a pile snapshot per recorded frame plus the final state.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use hdf5_pure::File;

use super::compare;
use super::run::{self, ColourBy, ColourScale};
use super::study;
use super::{Canvas, ChartOptions, Format, PlotError, StudyPoint};
use crate::output::guard::{self, Existing};
use crate::output::reader::{self, DamagedGroup};
use crate::output::stored::{self, StoredRun};
use crate::output::{OutputError, SummaryRow, SummaryTable};
use crate::physics::RunStatus;
use crate::physics::quantity::{self, SETTLE_TIME};
use crate::physics::record::Snapshot;
use crate::stats::points::Points;
use crate::study::ParamValue;

/// Per-run charts are drawn for at most this many runs unless runs are named or all are asked for.
pub const DEFAULT_RUN_LIMIT: usize = 20;

/// The swept parameter of replicate seeds: never a chart axis (the charts average over replicates).
const SEED: &str = "placement.seed";

/// What to plot and how.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotRequest {
    /// The results file (.h5).
    pub results: PathBuf,
    /// Folder for the images (`None`: `plots/` next to the results file).
    pub out_dir: Option<PathBuf>,
    /// Runs (ids) to draw per-run charts for; empty: see [`PlotRequest::all_runs`].
    pub run_ids: Vec<String>,
    /// With no `run_ids`: per-run charts for every run, instead of at most [`DEFAULT_RUN_LIMIT`]
    /// runs spread evenly over the study.
    pub all_runs: bool,
    /// Every chart is written in each of these formats.
    pub formats: Vec<Format>,
    /// What snapshot disks are coloured by: speed on one scale shared by a run's snapshots, contact
    /// force on a scale per snapshot.
    pub colour_by: ColourBy,
    /// Image size (pixels): width, height.
    pub size: (u32, u32),
    /// Replace any plain file at a chart's path (else only a chart demsweep drew).
    pub force: bool,
}

impl PlotRequest {
    /// The image folder: `out_dir`, or `plots/` next to the results file.
    pub fn image_dir(&self) -> PathBuf {
        self.out_dir.clone().unwrap_or_else(|| self.results.parent().unwrap_or(Path::new("")).join("plots"))
    }
}

/// What plotting reports as it goes.
#[derive(Debug)]
pub enum Event<'a> {
    /// An image file was written.
    Wrote(&'a Path),
    /// What was chosen or left out, in words.
    Note(&'a str),
    /// A chart that could not be drawn (or a run that could not be read); the others are still drawn.
    Failed(&'a PlotError),
}

/// What a plot produced.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PlotReport {
    /// Image files written.
    pub written: usize,
    /// Charts that could not be drawn and runs that could not be read.
    pub failed: usize,
    /// Runs that per-run charts were drawn for.
    pub runs_charted: usize,
    /// Runs in the file.
    pub runs_total: usize,
    /// Run groups that could not be read (left out).
    pub damaged: Vec<DamagedGroup>,
}

impl From<OutputError> for PlotError {
    fn from(e: OutputError) -> Self {
        PlotError { path: e.path, reason: e.reason.to_string() }
    }
}

/// Draws the study charts and the per-run charts of the requested runs of a results file, telling
/// `on_event` about every file written. Fails before drawing anything when the file cannot be read,
/// a requested run is not in it, the image size is too small or the image folder is `/`, a home
/// folder or above the working folder ([`guard::check_files_folder`]).
pub fn plot_results(request: &PlotRequest, on_event: &mut dyn FnMut(Event<'_>)) -> Result<PlotReport, PlotError> {
    let dir = request.image_dir();
    let (min_width, min_height) = ChartOptions::MIN_SIZE;
    if request.size.0 < min_width || request.size.1 < min_height {
        let reason =
            format!("image size {}x{} is below the smallest {min_width}x{min_height}", request.size.0, request.size.1);
        return Err(PlotError { path: dir, reason });
    }
    guard::check_files_folder(&dir)?;
    let path = &request.results;
    let file = reader::open(path)?;
    let study_name = reader::header(&file, path)?.study_name;
    let (rows, damaged) = reader::scan(&file, path)?;
    let selected = select_runs(&rows, request)?;
    let report = PlotReport { runs_charted: selected.len(), runs_total: rows.len(), damaged, ..Default::default() };
    let mut drawer = Drawer { request, dir, report, on_event };
    study_charts(&mut drawer, &study_name, &rows);
    pile_metric_charts(&mut drawer, &study_name, &rows);
    for row in selected {
        run_charts(&mut drawer, (&file, path), row, (request.colour_by, true));
    }
    Ok(drawer.report)
}

/// Where the charts of a results file go: image files (`demsweep plot`), or SVG documents (the report).
pub trait ChartSink {
    /// Draws the chart `name` (e.g. `r0007_energy`) about `subject` with `draw`, given the options
    /// and a canvas; returns what the drawing returned, `None` when it failed (reported by the sink).
    fn chart<T>(
        &mut self,
        name: &str,
        subject: &str,
        draw: impl Fn(&ChartOptions, Canvas<'_>) -> Result<T, PlotError>,
    ) -> Option<T>;
    /// What was chosen or left out, in words.
    fn note(&mut self, text: &str);
    /// A chart that could not be drawn, or a run that could not be read.
    fn fail(&mut self, error: &PlotError);
    /// The deposition of run `row` in a box of `box_size` (m): its frames (and its final state when
    /// taken after the last frame), named as its snapshot charts are; only for runs with frames. A
    /// sink that shows frames its own way (the report's player) takes them here; by default nothing.
    fn deposition(&mut self, _row: &SummaryRow, _box_size: (f64, f64), _pictures: &[(String, &Snapshot)]) {}
}

/// The runs to draw per-run charts for: the named ones (in the order named), else all runs or at
/// most [`DEFAULT_RUN_LIMIT`] spread evenly over the study (first and last included).
pub fn select_runs<'r>(rows: &'r [SummaryRow], request: &PlotRequest) -> Result<Vec<&'r SummaryRow>, PlotError> {
    if !request.run_ids.is_empty() {
        let mut selected: Vec<&SummaryRow> = Vec::new();
        for id in &request.run_ids {
            let row = rows.iter().find(|r| &r.id == id).ok_or_else(|| PlotError {
                path: request.results.clone(),
                reason: format!("no run `{id}` in this file (see `demsweep summary` for the run ids)"),
            })?;
            if !selected.iter().any(|r| r.id == row.id) {
                selected.push(row);
            }
        }
        return Ok(selected);
    }
    if request.all_runs {
        return Ok(rows.iter().collect());
    }
    Ok(spread(rows.len(), DEFAULT_RUN_LIMIT).into_iter().map(|i| &rows[i]).collect())
}

/// At most `limit` (two or more) indices of `0..len`, spread evenly with the first and the last
/// included; all of them when there are no more than `limit`.
pub fn spread(len: usize, limit: usize) -> Vec<usize> {
    if len <= limit {
        return (0..len).collect();
    }
    (0..limit).map(|i| i * (len - 1) / (limit - 1)).collect()
}

/// How a run ended, or `None` for a run that failed with an error (no record).
fn run_status(row: &SummaryRow) -> Option<RunStatus> {
    Some(row.status).filter(|s| *s != RunStatus::Error)
}

/// A run's id, swept parameters and status, for chart titles. Parameters go by their full key path
/// (`damping.local = 0.2`: the last part alone would not say which setting it is).
pub fn run_subject(row: &SummaryRow) -> String {
    subject_with(row, row.status.as_str())
}

/// The title subject of a snapshot at `time` (s): a frame taken before the run settled says when it
/// settles rather than calling the pile in it settled.
fn snapshot_subject(row: &SummaryRow, time: f64) -> String {
    match row.settle_time {
        Some(settle) if time < settle => {
            subject_with(row, &format!("settles at t = {} s", super::style::short_number(settle)))
        }
        _ => run_subject(row),
    }
}

fn subject_with(row: &SummaryRow, status: &str) -> String {
    let parameters: Vec<String> = row.parameters.iter().map(|(k, v)| format!("{k} = {v}")).collect();
    match parameters.is_empty() {
        true => format!("{} ({status})", row.id),
        false => format!("{}: {} ({status})", row.id, parameters.join(", ")),
    }
}

/// Charts drawn as SVG documents of one size, in order, with what was noted on the way (charts that
/// could not be drawn among the notes): the sink of a page that embeds its charts.
pub struct SvgCharts {
    /// Size of every chart (pixels): width, height.
    pub size: (u32, u32),
    /// Name and SVG document of each chart drawn.
    pub charts: Vec<(String, String)>,
    /// What was noted.
    pub notes: Vec<String>,
    /// The charts that could not be drawn and runs that could not be read (also among the notes).
    pub failures: Vec<PlotError>,
}

impl SvgCharts {
    /// No chart yet; charts of `size` (pixels).
    pub fn new(size: (u32, u32)) -> Self {
        Self { size, charts: Vec::new(), notes: Vec::new(), failures: Vec::new() }
    }
}

impl ChartSink for SvgCharts {
    fn chart<T>(
        &mut self,
        name: &str,
        subject: &str,
        draw: impl Fn(&ChartOptions, Canvas<'_>) -> Result<T, PlotError>,
    ) -> Option<T> {
        let (width, height) = self.size;
        let options = ChartOptions {
            width,
            height,
            format: Format::Svg,
            subject: Some(subject.to_string()),
            ..Default::default()
        };
        let mut svg = String::new();
        match draw(&options, Canvas::Svg(&mut svg)) {
            Ok(value) => {
                self.charts.push((name.to_string(), svg));
                Some(value)
            }
            Err(error) => {
                self.fail(&error);
                None
            }
        }
    }

    fn note(&mut self, text: &str) {
        self.notes.push(text.to_string());
    }

    fn fail(&mut self, error: &PlotError) {
        self.notes.push(format!("chart not drawn: {}", error.reason));
        self.failures.push(error.clone());
    }
}

/// Draws charts into the image folder and keeps count.
struct Drawer<'a> {
    request: &'a PlotRequest,
    dir: PathBuf,
    report: PlotReport,
    on_event: &'a mut dyn FnMut(Event<'_>),
}

impl ChartSink for Drawer<'_> {
    fn note(&mut self, text: &str) {
        (self.on_event)(Event::Note(text));
    }

    fn fail(&mut self, error: &PlotError) {
        self.report.failed += 1;
        (self.on_event)(Event::Failed(error));
    }

    /// Draws the chart into `<name>.<extension>` in every requested format; returns what the last
    /// successful drawing returned.
    fn chart<T>(
        &mut self,
        name: &str,
        subject: &str,
        draw: impl Fn(&ChartOptions, Canvas<'_>) -> Result<T, PlotError>,
    ) -> Option<T> {
        let mut drawn = None;
        for &format in &self.request.formats {
            let (width, height) = self.request.size;
            let existing = Existing::Ours { force: self.request.force };
            let options = ChartOptions { width, height, format, subject: Some(subject.to_string()), existing };
            let path = self.dir.join(format!("{name}.{}", format.extension()));
            match draw(&options, Canvas::File(&path)) {
                Ok(value) => {
                    self.report.written += 1;
                    (self.on_event)(Event::Wrote(&path));
                    drawn = Some(value);
                }
                Err(error) => self.fail(&error),
            }
        }
        drawn
    }
}

/// The study charts of `rows`: settle-time lines, and a heatmap when two parameters span a grid.
pub fn study_charts(sink: &mut impl ChartSink, study_name: &str, rows: &[SummaryRow]) {
    let axes = StudyAxes::choose(rows);
    for note in &axes.notes {
        sink.note(note);
    }
    let points: Vec<StudyPoint> = rows.iter().filter_map(study_point).collect();
    if points.len() < rows.len() {
        let failed = rows.len() - points.len();
        sink.note(&format!("{failed} run(s) failed with an error: left out of the study charts"));
    }
    let Some(x) = axes.x.as_deref() else {
        return sink.note("no swept numeric parameter with two or more values: no study charts");
    };
    let series = axes.series.as_deref();
    sink.chart(SETTLE_TIME.name, study_name, |o, c| study::settle_time_lines(&points, x, series, o, c));
    let Some(y) = series else { return };
    let cells = sink.chart("settle_time_heatmap", study_name, |o, c| study::settle_time_heatmap(&points, x, y, o, c));
    if let Some(cells) = cells {
        sink.note(&format!("settle time heatmap: {} cells over {x} x {y}", cells.len()));
    }
}

/// Lines a pile-metric chart draws at most (one colour each): more values of the colour axis are
/// thinned to this many, spread over them.
pub const MAX_METRIC_LINES: usize = 8;

/// Values of the x axis a pile-metric chart draws at most: more are thinned to this many, spread
/// over them (an 800-pixel chart cannot part more, and 160 000 markers with their intervals would be
/// tens of megabytes of SVG).
pub const MAX_METRIC_X_VALUES: usize = 200;

/// The pile-metric charts of `rows`: each of [`quantity::charted`] per grid point (mean and 95 %
/// interval over its runs, the `/points` statistics) against each chart axis, a line per value of
/// the other axis of a two-parameter grid (at most [`MAX_METRIC_LINES`]); named `<metric>_vs_<axis>`. Settle time against the first axis is
/// the settle-time chart's, and is not drawn again.
pub fn pile_metric_charts(sink: &mut impl ChartSink, study_name: &str, rows: &[SummaryRow]) {
    let axes = StudyAxes::choose(rows);
    let Some(x) = axes.x.as_deref() else { return };
    // The points of the two axes: further swept parameters are averaged over, as on the
    // settle-time chart (else a line would zigzag through their values at each x).
    let on_axes: Vec<SummaryRow> =
        rows.iter().map(|r| with_parameters(r, &[Some(x), axes.series.as_deref()])).collect();
    let summary = SummaryTable::from_rows(&on_axes);
    let points = Points::new(&summary);
    let along = [(x, axes.series.as_deref())].into_iter().chain(axes.series.as_deref().map(|y| (y, Some(x))));
    let mut lines = HashSet::new(); // (axis, value of the other axis drawn as a line) of each chart
    let mut shown = HashSet::new(); // (axis, value along it drawn) of each chart
    for (axis, colour) in along.clone() {
        if let Some(colour) = colour {
            let what = format!("lines for {{kept}} of the {{all}} values of {colour}");
            lines.extend(thinned(sink, rows, (axis, colour), MAX_METRIC_LINES, &what));
        }
        shown.extend(thinned(sink, rows, (axis, axis), MAX_METRIC_X_VALUES, "{kept} of its {all} values"));
    }
    for (axis, colour) in along {
        for metric in quantity::charted().filter(|m| points.metric_names().contains(m)) {
            if metric == SETTLE_TIME.name && axis == x {
                continue;
            }
            let unit = quantity::unit(metric).unwrap_or("");
            let mut estimates = compare::metric_points(&points, metric, (Some(axis), colour), None);
            estimates.retain(|e| {
                e.series.is_none_or(|v| lines.contains(&(axis, v.to_bits()))) && shown.contains(&(axis, e.x.to_bits()))
            });
            sink.chart(&format!("{metric}_vs_{axis}"), study_name, |o, c| {
                compare::metric_chart((metric, unit), &estimates, (axis, colour), None, o, c)
            });
        }
    }
}

/// `row` with only the parameters `kept`.
fn with_parameters(row: &SummaryRow, kept: &[Option<&str>]) -> SummaryRow {
    let mut row = row.clone();
    row.parameters.retain(|(key, _)| kept.contains(&Some(key.as_str())));
    row
}

/// The values of parameter `of` kept on the pile-metric charts against `axis`: at most `limit`,
/// spread over them, as `(axis, value bits)`; a note says `what` (`{kept}` and `{all}` filled in)
/// when values were left out.
fn thinned<'a>(
    sink: &mut impl ChartSink,
    rows: &[SummaryRow],
    (axis, of): (&'a str, &str),
    limit: usize,
    what: &str,
) -> Vec<(&'a str, u64)> {
    let values = distinct_values(rows, of);
    let kept = spread(values.len(), limit);
    if kept.len() < values.len() {
        let what = what.replace("{kept}", &kept.len().to_string()).replace("{all}", &values.len().to_string());
        sink.note(&format!("pile-metric charts against {axis}: {what}, spread over them"));
    }
    kept.into_iter().map(|k| (axis, values[k].to_bits())).collect()
}

/// The charts of one run of the results `file` (at `path`): energies and UBF (when histories are
/// stored) and its snapshots (the final state, and with `frames` every recorded frame), disks
/// coloured `by`.
pub fn run_charts(
    sink: &mut impl ChartSink,
    (file, path): (&File, &Path),
    row: &SummaryRow,
    (by, frames): (ColourBy, bool),
) {
    if run_status(row).is_none() {
        return sink.note(&format!("{}: {} ({}): nothing to plot", row.id, row.status, row.message));
    }
    let stored = match stored::read_run(file, path, row) {
        Ok(stored) => stored,
        Err(error) => return sink.fail(&error.into()),
    };
    let subject = run_subject(row);
    match &stored.history {
        Some(history) => {
            let stage_ends = &row.stage_ends;
            sink.chart(&format!("{}_energy", row.id), &subject, |o, c| run::energy_chart(history, stage_ends, o, c));
            let marks = run::UbfMarks {
                threshold: stored.scene.settle.ubf_threshold,
                settle_time: row.settle_time,
                stage_ends: &row.stage_ends,
            };
            sink.chart(&format!("{}_ubf", row.id), &subject, |o, c| run::ubf_chart(history, marks, o, c));
        }
        None => sink.note(&format!("{}: no histories stored: no energy or UBF chart", row.id)),
    }
    if let Some(profile) = stored.stress_profile.as_ref().filter(|p| !p.bottom.is_empty()) {
        sink.chart(&format!("{}_stress_profile", row.id), &subject, |o, c| run::stress_profile_chart(profile, o, c));
    }
    snapshots(sink, row, &stored, (by, frames));
    if !stored.frames.is_empty() {
        sink.deposition(row, (stored.scene.domain.width, stored.scene.domain.height), &snapshot_names(&stored));
    }
}

/// A snapshot per stored frame and of the final state (unless the last frame shows it).
fn snapshots(sink: &mut impl ChartSink, row: &SummaryRow, stored: &StoredRun, (by, frames): (ColourBy, bool)) {
    let pictures = match frames {
        true => snapshot_names(stored),
        false => stored.final_state.iter().map(|s| ("final".to_string(), s)).collect(),
    };
    if pictures.is_empty() {
        return sink.note(&format!("{}: no frames or final state stored: no snapshots", row.id));
    }
    let box_size = (stored.scene.domain.width, stored.scene.domain.height);
    let shared = ColourScale::fitted(by, pictures.iter().map(|(_, s)| *s));
    let scaled: Vec<(&Snapshot, ColourScale)> = pictures
        .iter()
        .map(|(_, snapshot)| match by {
            ColourBy::Speed => (*snapshot, shared),
            ColourBy::ContactForce => (*snapshot, ColourScale::fitted(by, [*snapshot])),
        })
        .collect();
    for ((name, _), (snapshot, scale)) in pictures.iter().zip(&scaled) {
        let name = format!("{}_{name}", row.id);
        let subject = snapshot_subject(row, snapshot.time);
        sink.chart(&name, &subject, |o, c| run::snapshot(snapshot, box_size, scale, o, c));
    }
    if scaled.len() > 1 {
        let subject = run_subject(row);
        sink.chart(&format!("{}_deposition", row.id), &subject, |o, c| run::animation(&scaled, box_size, o, c));
    }
}

/// The snapshots of a run with their file name parts: `frame_<k>` for each frame, `final` for the
/// final state unless the last frame was taken at the same step.
fn snapshot_names(stored: &StoredRun) -> Vec<(String, &Snapshot)> {
    let mut pictures: Vec<(String, &Snapshot)> = stored
        .frames
        .iter()
        .enumerate()
        .map(|(k, frame)| (format!("frame_{}", crate::output::layout::frame_name(k)), frame))
        .collect();
    if let Some(last) = &stored.final_state {
        let half_step = 0.5 * stored.scene.integrator.fixed_time_step().unwrap_or(1e-12);
        if !stored.frames.last().is_some_and(|frame| (frame.time - last.time).abs() < half_step) {
            pictures.push(("final".to_string(), last));
        }
    }
    pictures
}

/// A run as the study charts see it: its numeric swept parameters (booleans as 0 and 1); `None` for
/// a run that failed with an error.
fn study_point(row: &SummaryRow) -> Option<StudyPoint> {
    let parameters = row.parameters.iter().filter_map(|(key, value)| Some((key.clone(), numeric(value)?))).collect();
    Some(StudyPoint { parameters, status: run_status(row)?, settle_time: row.settle_time })
}

/// A parameter value as a number, if it is one.
fn numeric(value: &ParamValue) -> Option<f64> {
    match value {
        ParamValue::Float(v) => Some(*v),
        ParamValue::Int(v) => Some(*v as f64),
        ParamValue::Bool(v) => Some(f64::from(u8::from(*v))),
        ParamValue::Text(_) => None,
    }
}

/// The swept parameters the study charts are drawn against, and why others are not.
#[derive(Debug, Default, PartialEq)]
struct StudyAxes {
    /// Horizontal axis of the lines and the heatmap.
    x: Option<String>,
    /// One line per value of it; the vertical axis of the heatmap.
    series: Option<String>,
    /// What was left out, in words.
    notes: Vec<String>,
}

impl StudyAxes {
    /// The first two swept numeric parameters with two or more values that vary independently (a
    /// parameter zipped with the first is no second axis); text parameters and replicate seeds are
    /// averaged over, as are further parameters.
    fn choose(rows: &[SummaryRow]) -> Self {
        let mut axes = Self::default();
        let keys = rows.first().map(|r| r.parameters.iter().map(|(k, v)| (k.as_str(), v))).into_iter().flatten();
        let mut averaged = Vec::new();
        for (key, value) in keys {
            let values = distinct_values(rows, key);
            if numeric(value).is_none() {
                axes.notes.push(format!("text parameter {key} is not a chart axis: study charts average over it"));
            } else if key == SEED {
                averaged.push(key);
            } else if values.len() < 2 {
                continue;
            } else if axes.x.is_none() {
                axes.x = Some(key.to_string());
            } else if axes.series.is_none() && !determined_by(rows, axes.x.as_deref().unwrap_or_default(), key) {
                axes.series = Some(key.to_string());
            } else {
                averaged.push(key);
            }
        }
        if !averaged.is_empty() {
            axes.notes.push(format!("study charts average over {}", averaged.join(", ")));
        }
        axes
    }
}

/// The distinct numeric values of parameter `key` over `rows`, sorted.
fn distinct_values(rows: &[SummaryRow], key: &str) -> Vec<f64> {
    let mut values: Vec<f64> = rows.iter().filter_map(|r| parameter(r, key)).collect();
    values.sort_by(f64::total_cmp);
    values.dedup();
    values
}

/// The numeric value of parameter `key` of a run.
fn parameter(row: &SummaryRow, key: &str) -> Option<f64> {
    row.parameters.iter().find(|(k, _)| k == key).and_then(|(_, v)| numeric(v))
}

/// Whether the value of `key` follows from the value of `by` in every run (as for zipped axes).
fn determined_by(rows: &[SummaryRow], by: &str, key: &str) -> bool {
    let bits = |row: &SummaryRow, name: &str| parameter(row, name).map(f64::to_bits);
    let mut seen = std::collections::HashMap::new();
    rows.iter().all(|row| *seen.entry(bits(row, by)).or_insert(bits(row, key)) == bits(row, key))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(index: usize, parameters: &[(&str, ParamValue)]) -> SummaryRow {
        let parameters: Vec<(String, ParamValue)> =
            parameters.iter().map(|(k, v)| (k.to_string(), v.clone())).collect();
        let mut row = SummaryRow::failed(index, &format!("r{index:04}"), &parameters, "");
        row.status = RunStatus::Settled;
        row
    }

    #[test]
    fn titles_keep_full_key_paths_and_frames_before_settling_say_so() {
        let mut settled =
            row(0, &[("damping.local", ParamValue::Float(0.2)), ("material.friction", ParamValue::Float(0.5))]);
        settled.settle_time = Some(0.42);
        assert_eq!(run_subject(&settled), "r0000: damping.local = 0.2, material.friction = 0.5 (settled)");
        let before = snapshot_subject(&settled, 0.15);
        assert_eq!(before, "r0000: damping.local = 0.2, material.friction = 0.5 (settles at t = 0.42 s)");
        assert_eq!(snapshot_subject(&settled, 0.42), run_subject(&settled), "the settled pile is called settled");
    }

    #[test]
    fn axes_skip_text_seeds_single_values_and_zipped_parameters() {
        use ParamValue::{Float, Int, Text};
        let mut rows = Vec::new();
        for (i, (e, mu)) in [(0.1, 0.2), (0.1, 0.6), (0.5, 0.2), (0.5, 0.6)].into_iter().enumerate() {
            rows.push(row(
                i,
                &[
                    ("integrator.scheme", Text("verlet".into())),
                    ("material.restitution", Float(e)),
                    ("material.rolling_friction", Float(e * 2.0)),
                    ("material.density", Float(2500.0)),
                    ("material.friction", Float(mu)),
                    ("placement.seed", Int(i as i64)),
                ],
            ));
        }
        let axes = StudyAxes::choose(&rows);
        assert_eq!(axes.x.as_deref(), Some("material.restitution"));
        assert_eq!(axes.series.as_deref(), Some("material.friction"));
        assert_eq!(axes.notes.len(), 2, "{:?}", axes.notes);
        assert!(axes.notes[0].contains("integrator.scheme"));
        assert!(axes.notes[1].ends_with("material.rolling_friction, placement.seed"), "{:?}", axes.notes);
    }

    #[test]
    fn pile_metric_charts_draw_at_most_eight_lines_spread_over_the_other_axis() {
        use ParamValue::Float;
        let metric = quantity::final_value_declarations().position(|q| q.name == "floor_load_ratio").unwrap();
        let mut rows = Vec::new();
        for e in [0.1, 0.5, 0.9] {
            for k in 0..12 {
                let mut run =
                    row(rows.len(), &[("material.restitution", Float(e)), ("material.friction", Float(k.into()))]);
                run.final_values[metric] = e + f64::from(k);
                rows.push(run);
            }
        }
        let mut sink = SvgCharts::new((1000, 700));
        pile_metric_charts(&mut sink, "study", &rows);
        let chart = |name: &str| &sink.charts.iter().find(|(n, _)| n == name).unwrap().1;
        // A marker per drawn point: 8 of the 12 frictions (the first and last kept) at 3 restitutions.
        let markers = |svg: &str| svg.matches("r=\"4\"").count();
        assert_eq!(markers(chart("floor_load_ratio_vs_material.restitution")), 8 * 3);
        assert_eq!(markers(chart("floor_load_ratio_vs_material.friction")), 12 * 3);
        assert!(chart("floor_load_ratio_vs_material.restitution").contains("material.friction = 11"));
        let note = "pile-metric charts against material.restitution: lines for 8 of the 12 values of material.friction";
        assert!(sink.notes.iter().any(|n| n.starts_with(note)), "{:?}", sink.notes);
    }

    #[test]
    fn pile_metric_charts_average_over_a_third_axis() {
        use ParamValue::Float;
        let metric = quantity::final_value_declarations().position(|q| q.name == "floor_load_ratio").unwrap();
        let mut rows = Vec::new();
        for (e, mu, rolling) in three_axis_grid() {
            let parameters = [
                ("material.restitution", Float(e)),
                ("material.friction", Float(mu)),
                ("material.rolling_friction", Float(rolling)),
            ];
            let mut run = row(rows.len(), &parameters);
            run.final_values[metric] = e + mu + rolling;
            rows.push(run);
        }
        let mut sink = SvgCharts::new((1000, 700));
        pile_metric_charts(&mut sink, "study", &rows);
        let chart = |name: &str| &sink.charts.iter().find(|(n, _)| n == name).unwrap().1;
        // One marker per (restitution, friction): the three rolling frictions are averaged over.
        let markers = |svg: &str| svg.matches("r=\"4\"").count();
        assert_eq!(markers(chart("floor_load_ratio_vs_material.restitution")), 2 * 2);
        assert_eq!(markers(chart("floor_load_ratio_vs_material.friction")), 2 * 2);
    }

    /// Two restitutions x two frictions x three rolling frictions.
    fn three_axis_grid() -> Vec<(f64, f64, f64)> {
        let mut grid = Vec::new();
        for e in [0.1, 0.9] {
            for mu in [0.2, 0.6] {
                grid.extend([0.0, 0.1, 0.2].map(|rolling| (e, mu, rolling)));
            }
        }
        grid
    }

    #[test]
    fn pile_metric_charts_draw_at_most_their_x_value_limit_spread_over_the_axis() {
        use ParamValue::Float;
        let metric = quantity::final_value_declarations().position(|q| q.name == "floor_load_ratio").unwrap();
        let values = MAX_METRIC_X_VALUES + 101;
        let rows: Vec<SummaryRow> = (0..values)
            .map(|k| {
                let mut run = row(k, &[("material.friction", Float(k as f64))]);
                run.final_values[metric] = k as f64;
                run
            })
            .collect();
        let mut sink = SvgCharts::new((1000, 700));
        pile_metric_charts(&mut sink, "study", &rows);
        let svg = &sink.charts.iter().find(|(n, _)| n == "floor_load_ratio_vs_material.friction").unwrap().1;
        assert_eq!(svg.matches("r=\"4\"").count(), MAX_METRIC_X_VALUES, "one marker per kept value");
        let note =
            format!("pile-metric charts against material.friction: {MAX_METRIC_X_VALUES} of its {values} values");
        assert!(sink.notes.iter().any(|n| n.starts_with(&note)), "{:?}", sink.notes);
    }

    #[test]
    fn default_selection_spreads_the_run_limit_over_a_large_study() {
        let rows: Vec<SummaryRow> = (0..1000).map(|i| row(i, &[])).collect();
        let request = PlotRequest {
            results: PathBuf::from("study.h5"),
            out_dir: None,
            run_ids: Vec::new(),
            all_runs: false,
            formats: vec![Format::Png],
            colour_by: ColourBy::Speed,
            size: (1000, 700),
            force: false,
        };
        let selected = select_runs(&rows, &request).unwrap();
        assert_eq!(selected.len(), DEFAULT_RUN_LIMIT);
        assert_eq!((selected[0].index, selected[DEFAULT_RUN_LIMIT - 1].index), (0, 999));
        assert!(selected.windows(2).all(|w| w[1].index > w[0].index));
        let all = select_runs(&rows, &PlotRequest { all_runs: true, ..request.clone() }).unwrap();
        assert_eq!(all.len(), 1000);
        let named = PlotRequest { run_ids: vec!["r0007".into(), "r0003".into(), "r0007".into()], ..request.clone() };
        let ids: Vec<&str> = select_runs(&rows, &named).unwrap().iter().map(|r| r.id.as_str()).collect();
        assert_eq!(ids, ["r0007", "r0003"]);
        let unknown = PlotRequest { run_ids: vec!["r5000".into()], ..request };
        assert!(select_runs(&rows, &unknown).unwrap_err().reason.contains("no run `r5000`"));
        assert_eq!(PlotRequest { results: "results/s/s.h5".into(), ..named }.image_dir(), Path::new("results/s/plots"));
    }
}
