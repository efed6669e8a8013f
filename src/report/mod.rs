//! The morning-after report: one self-contained HTML page per results file (inline CSS, inline SVG
//! charts, a little inline JavaScript, no network request of any kind).
//!
//! Top to bottom: what was run; how the runs ended and their warnings grouped by kind; the
//! per-point table (columns under header groups with their units, sortable by any column,
//! filterable by status; [`crate::stats::points`]); the study charts (settle time with 95 %
//! intervals, heatmap) and the pile-metric charts; the tune, when the file holds one; a section per
//! charted run (energies, unbalanced force ratio, stress profile, final pile, and a player of its
//! frames when it has some), the runs `demsweep plot` chooses, each linked from its point's row.

mod html;
mod player;
mod table;

pub use table::{Cell, Table};

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

use crate::output::guard::{self, Existing};
use crate::output::reader::{self, DamagedGroup};
use crate::output::{FileHeader, OutputError, SummaryRow, SummaryTable};
use crate::physics::RunStatus;
use crate::physics::quantity;
use crate::physics::record::Snapshot;
use crate::physics::warning::{ValidityWarning, WarningKind};
use crate::plot::results::{self, ChartSink, DEFAULT_RUN_LIMIT, PlotRequest, SvgCharts};
use crate::plot::run::ColourBy;
use crate::plot::{Canvas, ChartOptions, Format, PlotError};
use crate::stats::compare::{self, Comparison};
use crate::stats::points::Points;
use crate::stats::{Decision, Describe};
use html::{escape, number};

/// Size of every chart on the page (pixels; the page scales them to its width).
const CHART_SIZE: (u32, u32) = (900, 560);

/// How the results were made: what the caller says, else what the file recorded of its last sweep.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReportContext {
    /// Worker threads the runs ran on.
    pub jobs: Option<usize>,
    /// Wall-clock time of the whole command (s).
    pub elapsed: Option<f64>,
}

/// The section a tune adds to the report of its results file: `demsweep tune` writes it next to the
/// results as `<name>_tune.json` ([`tune_section_path`]), and every report of that file shows it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TuneSection {
    /// The recommendation, one paragraph of plain text.
    pub recommendation: String,
    /// Cost against largest |difference| / tolerance, as an SVG document.
    pub chart_svg: String,
    /// Every evaluated setting, one row each (as in `<name>_candidates.csv`), under the columns' labels.
    pub candidates: Table,
}

pub use crate::output::report_path;

/// `<results folder>/<study name>_tune.json`: the tune's section of the report, when the file holds a tune.
pub fn tune_section_path(results: &Path, study_name: &str) -> PathBuf {
    results.with_file_name(format!("{study_name}_tune.json"))
}

/// Writes the tune's section next to its results file (see [`TuneSection`]), marked as demsweep's
/// (`"dc:creator": "demsweep"`), replacing a file there as `existing` allows.
pub fn write_tune_section(
    results: &Path,
    study_name: &str,
    section: &TuneSection,
    existing: Existing,
) -> Result<PathBuf, OutputError> {
    let path = tune_section_path(results, study_name);
    let mut json = serde_json::to_value(section).map_err(|e| OutputError::new(&path, e.to_string()))?;
    json["dc:creator"] = "demsweep".into();
    guard::write_with(&path, &[results], existing, |out| out.write_all(json.to_string().as_bytes()))
        .map_err(|e| OutputError::new(&path, e.refusal_text()))?;
    Ok(path)
}

/// The tune section next to a results file, if there is one: its path and the section, or why it
/// cannot be read (a note in its place).
fn read_tune_section(results: &Path, study_name: &str) -> Option<(PathBuf, serde_json::Result<TuneSection>)> {
    let path = tune_section_path(results, study_name);
    let text = std::fs::read_to_string(&path).ok()?;
    let section = serde_json::from_str(&text);
    Some((path, section))
}

/// Writes the report of the results file `results` to `out` (default: [`report_path`]) from its
/// readable runs, whole or not at all, replacing a file there as `existing` allows; returns where it
/// went, the run groups that could not be read (left out) and the study charts that could not be
/// drawn (left out: warnings, as the summary they come from is whole). A run whose stored data
/// cannot be read is an error.
pub fn write_report(
    results: &Path,
    (out, existing): (Option<&Path>, Existing),
    context: &ReportContext,
) -> Result<(PathBuf, Vec<DamagedGroup>, Vec<PlotError>), OutputError> {
    let file = reader::open(results)?;
    let header = reader::header(&file, results)?;
    let (rows, damaged) = reader::scan(&file, results)?;
    let summary = SummaryTable::from_rows(&rows);
    let request = PlotRequest {
        results: results.to_path_buf(),
        out_dir: None,
        run_ids: Vec::new(),
        all_runs: false,
        formats: vec![Format::Svg],
        colour_by: ColourBy::Speed,
        size: CHART_SIZE,
        force: false,
    };
    let charted: Vec<&SummaryRow> =
        results::select_runs(&rows, &request).map_err(|e| OutputError::new(results, e.reason))?;
    let recorded = reader::sweep(&file);
    let context = ReportContext {
        jobs: context.jobs.or(recorded.map(|(jobs, _)| jobs)),
        elapsed: context.elapsed.or(recorded.map(|(_, wall)| wall)),
    };
    let mut page = html::Page::new(&header.study_name);
    let (mut failures, mut not_drawn) = (Vec::new(), Vec::new());
    // A tune's page shows its answer first, its warnings grouped by kind, and no study charts: a
    // tune's runs are not a grid, so averages over the levers mean nothing.
    let tune = read_tune_section(results, &header.study_name);
    page.push(&overview(&header, &rows, &context, tune.is_some()));
    match &tune {
        Some((_, Ok(tune))) => page.push(&tune_section(tune)),
        Some((path, Err(e))) => {
            let reason = format!("{}: {e}", path.display());
            page.push(&format!("<h2 id=\"tune\">Tune</h2><p class=\"note\">{}</p>", escape(&reason)));
        }
        None => {}
    }
    if !damaged.is_empty() {
        page.push(&format!("<p class=\"note\">{}</p>", escape(&reader::damage_text(&damaged))));
    }
    if tune.is_none() {
        page.push(&verdict(&summary, crate::study::reference::reference_spec(&header.study_text).as_deref()));
    }
    page.push(&outcomes(&rows, tune.is_some()));
    if tune.is_none() {
        let charted_ids: Vec<&str> = charted.iter().map(|r| r.id.as_str()).collect();
        page.push(&points_section(&summary, &charted_ids, &crate::output::points_csv_path(results)));
        let mut study = Svgs::new();
        results::study_charts(&mut study, &header.study_name, &rows);
        page.push(&charts_section(&study));
        let mut pile = Svgs::new();
        results::pile_metric_charts(&mut pile, &header.study_name, &rows);
        page.push(&pile_charts_section(&pile));
        not_drawn.extend(study.drawn.failures.into_iter().chain(pile.drawn.failures));
    }
    let mut runs = String::from("<h2 id=\"runs\">Runs</h2><div class=\"runs\">");
    if rows.len() > charted.len() {
        runs += &format!(
            "<p class=\"note\">{} of {} runs charted ({DEFAULT_RUN_LIMIT} at most, spread over the study; `demsweep plot --run ID` draws any other).</p>",
            charted.len(),
            rows.len()
        );
    }
    for row in &charted {
        let mut svgs = Svgs::new();
        results::run_charts(&mut svgs, (&file, results), row, (ColourBy::Speed, false));
        runs += &run_section(row, &svgs);
        failures.append(&mut svgs.drawn.failures);
    }
    runs += "</div>";
    page.push(&runs);
    let path = out.map_or_else(|| report_path(results), Path::to_path_buf);
    guard::write_with(&path, &[results], existing, |out| out.write_all(page.finish().as_bytes()))
        .map_err(|e| OutputError::new(&path, e.refusal_text()))?;
    match failures.is_empty() {
        true => Ok((path, damaged, not_drawn)),
        false => Err(unreadable(results, &path, &failures)),
    }
}

/// The error of a page written without the charts that `failures` name (a run's stored data that
/// fails its checksum, a chart that cannot be drawn): the page says so too.
fn unreadable(results: &Path, page: &Path, failures: &[PlotError]) -> OutputError {
    let named: Vec<String> = failures.iter().take(5).map(|f| f.reason.clone()).collect();
    let more = if failures.len() > 5 { format!(" and {} more", failures.len() - 5) } else { String::new() };
    OutputError::new(
        results,
        format!(
            "{} chart(s) or run(s) left out of the page {} ({}{more})",
            failures.len(),
            page.display(),
            named.join("; ")
        ),
    )
}

/// Charts drawn as SVG documents with what was noted on the way, and a run's frame player.
struct Svgs {
    drawn: SvgCharts,
    player: Option<String>,
}

impl Svgs {
    fn new() -> Self {
        Self { drawn: SvgCharts::new(CHART_SIZE), player: None }
    }
}

impl ChartSink for Svgs {
    fn chart<T>(
        &mut self,
        name: &str,
        subject: &str,
        draw: impl Fn(&ChartOptions, Canvas<'_>) -> Result<T, PlotError>,
    ) -> Option<T> {
        self.drawn.chart(name, subject, draw)
    }

    fn note(&mut self, text: &str) {
        self.drawn.note(text);
    }

    fn fail(&mut self, error: &PlotError) {
        self.drawn.fail(error);
    }

    fn deposition(&mut self, row: &SummaryRow, box_size: (f64, f64), pictures: &[(String, &Snapshot)]) {
        self.player = Some(player::player(row, box_size, pictures));
    }
}

/// What was run: study, fingerprint, version, dates, wall time, cores, and the study file itself.
fn overview(header: &FileHeader, rows: &[SummaryRow], context: &ReportContext, tune: bool) -> String {
    let description = toml::from_str::<toml::Table>(&header.study_text)
        .ok()
        .and_then(|t| t.get("description").and_then(|d| d.as_str().map(str::to_string)));
    let run_seconds: f64 = rows.iter().map(|r| r.wall_time).sum();
    let measured: Vec<f64> = rows.iter().map(|r| r.cpu_time).filter(|t| t.is_finite()).collect();
    let cpu = match measured.len() {
        0 => "no CPU time measured".to_string(),
        n if n == rows.len() => format!("{} s CPU time", number(measured.iter().sum())),
        n => format!("{} s CPU time over the {n} runs that measured it", number(measured.iter().sum())),
    };
    let mut facts = vec![
        ("study", escape(&header.study_name)),
        ("fingerprint", format!("<code>{}</code>", escape(&header.fingerprint))),
        ("demsweep", escape(&header.demsweep_version)),
        ("results file created", escape(&header.created)),
        ("report written", escape(&crate::output::header::utc_now())),
        (
            "runs",
            match tune {
                true => format!("{} (a tune decides its runs as it goes: see below how they add up)", rows.len()),
                false => format!("{} of {} planned", rows.len(), header.planned_runs),
            },
        ),
        ("computing time", format!("{} s wall time summed over all runs; {cpu}", number(run_seconds))),
    ];
    if let Some(elapsed) = context.elapsed {
        facts.push(("wall time", format!("{} s (the last sweep into the file)", number(elapsed))));
    }
    if let Some(jobs) = context.jobs {
        facts.push(("cores", format!("{jobs} worker threads")));
    }
    let facts: String = facts.iter().map(|(k, v)| format!("<dt>{k}</dt><dd>{v}</dd>")).collect();
    format!(
        "<h1>{}</h1><p class=\"lead\">{}</p><dl class=\"facts\">{facts}</dl><details><summary>study file</summary><pre>{}</pre></details>",
        escape(&header.study_name),
        escape(description.as_deref().unwrap_or("")),
        escape(&header.study_text)
    )
}

/// Grid points the answer at the top of the page lists at most.
const VERDICT_POINTS: usize = 5;

/// The answer first: the grid points that settle fastest (mean settle time over their settled runs
/// with its 95 % interval, and their cost), and whether each can be told apart from the fastest
/// (its interval above the fastest's) or not (the intervals overlap: more seeds would decide); then,
/// when the study names a reference point (`spec`), which points are equivalent to it.
fn verdict(summary: &SummaryTable, spec: Option<&str>) -> String {
    let points = Points::new(summary);
    let answer = first_answer(&points, spec);
    let reference = spec.map_or(String::new(), |spec| reference_section(&points, spec));
    let mut settled: Vec<(usize, Describe)> = (0..points.len())
        .map(|p| (p, points.describe(p, quantity::SETTLE_TIME.name)))
        .filter(|(_, d)| d.n > 0 && d.mean.is_finite())
        .collect();
    if settled.is_empty() {
        return format!(
            "<h2 id=\"verdict\">The answer</h2>{answer}<p class=\"verdict\">No grid point has a settled run: nothing \
             settles in this sweep (see how the runs ended below).</p>{reference}"
        );
    }
    settled.sort_by(|a, b| a.1.mean.total_cmp(&b.1.mean));
    let fastest = &settled[0].1;
    let fastest_top = fastest.mean + fastest.half_width_95.max(0.0);
    let rows: String = settled
        .iter()
        .take(VERDICT_POINTS)
        .enumerate()
        .map(|(rank, (point, d))| {
            let runs = points.rows(*point).len();
            let cost = points.describe(*point, "particle_steps");
            let judged = match rank {
                0 => "the fastest".to_string(),
                _ if !d.half_width_95.is_finite() || !fastest.half_width_95.is_finite() => {
                    "one settled run: no interval to compare".to_string()
                }
                _ if d.mean - d.half_width_95 > fastest_top => "slower than the fastest (the intervals are apart)".into(),
                _ => "not told apart from the fastest (the intervals overlap)".into(),
            };
            format!(
                "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{} of {runs}</td><td class=\"num\">{}</td><td>{judged}</td></tr>",
                escape(&points.label(*point)),
                escape(&crate::stats::points::plus_minus(Some(d.mean), Some(d.half_width_95))),
                d.n,
                number(cost.mean),
            )
        })
        .collect();
    let undecided = settled.iter().skip(1).filter(|(_, d)| d.mean - d.half_width_95 <= fastest_top).count();
    let summary_line = match undecided {
        0 => "The fastest grid point settles sooner than every other: its 95 % interval lies below theirs.".to_string(),
        n => format!(
            "{n} other grid point(s) cannot be told apart from the fastest at these seeds: their 95 % intervals \
             overlap; more replicates would decide."
        ),
    };
    format!(
        "<h2 id=\"verdict\">The answer</h2>{answer}<p class=\"verdict\">Fastest-settling grid points (mean settle time \
         over the settled runs, ± the 95 % confidence half-width). {summary_line}</p>\
         <table class=\"verdict\"><thead><tr><th>grid point</th><th>{}</th><th>settled runs</th>\
         <th>{}</th><th></th></tr></thead><tbody>{rows}</tbody></table>{reference}",
        escape(&quantity::label(quantity::SETTLE_TIME.name)),
        escape(&quantity::label("particle_steps_mean")),
    )
}

/// The study's question answered in one paragraph (`<p id="answer">`). With a reference point
/// (`spec`): the cheapest grid point faster than the reference (by the cost ratio) that makes an
/// equivalent pile, or, when none of the faster points does, the nearest miss and the metric that
/// moved most. Without one: the cheapest point, and that its pile was not compared.
fn first_answer(points: &Points, spec: Option<&str>) -> String {
    let text = match spec.map(|spec| ReferenceVerdict::new(points, spec)) {
        Some(Ok(verdict)) => reference_answer(points, &verdict),
        Some(Err(_)) | None => cheapest_answer(points, spec.is_some()),
    };
    format!("<p class=\"verdict answer\" id=\"answer\">{text}</p>")
}

/// The answer against the reference point (see [`first_answer`]).
fn reference_answer(points: &Points, verdict: &ReferenceVerdict) -> String {
    let comparison = &verdict.comparison;
    let reference = escape(&points.label(comparison.reference));
    let cost = &comparison.cost_column;
    let faster: Vec<usize> = (0..comparison.points.len()).filter(|&i| comparison.points[i].cost.ratio < 1.0).collect();
    let costs = |p: &compare::PointComparison| {
        let ratios = format!(
            "{} of the reference's {cost} and {} of its wall time",
            compare::ratio(&p.cost),
            compare::ratio(&p.wall_time)
        );
        (ratios, if ratios_disagree(p) { vec![points.label(p.point)] } else { Vec::new() })
    };
    if let Some(&best) = verdict.equivalent.iter().find(|i| faster.contains(i)) {
        let point = &comparison.points[best];
        let (ratios, disagreeing) = costs(point);
        return format!(
            "<b>{}</b> is the fastest grid point that makes the same pile as the reference ({reference}): every kept \
             metric is equivalent, at {ratios}.{}",
            escape(&points.label(point.point)),
            disagreement(&disagreeing, cost)
        );
    }
    let deviation = |i: &usize| comparison.points[*i].deviation(&comparison.kept);
    let Some(&miss) = faster.iter().min_by(|a, b| deviation(a).total_cmp(&deviation(b))) else {
        return format!(
            "No grid point is faster than the reference ({reference}) by {cost}: keep the reference's settings."
        );
    };
    let point = &comparison.points[miss];
    let moved = (0..comparison.kept.len())
        .max_by(|&a, &b| {
            let share = |k: usize| point.tests[k].difference.abs() / comparison.kept[k].margin;
            share(a).total_cmp(&share(b))
        })
        .map_or(String::new(), |k| {
            let (kept, test) = (&comparison.kept[k], &point.tests[k]);
            let decision = match test.decision {
                Decision::Different => "different",
                _ => "not shown equivalent (more seeds would decide)",
            };
            format!(
                ": its {} moved by {} from the reference's {} (the margin is ± {}), {decision}",
                escape(&kept.tolerance.metric),
                number(test.difference),
                number(kept.reference.mean),
                number(kept.margin)
            )
        });
    let (ratios, disagreeing) = costs(point);
    format!(
        "None of the {} faster grid points makes the same pile as the reference ({reference}). The nearest miss is \
         <b>{}</b>, at {ratios}{moved}.{}",
        faster.len(),
        escape(&points.label(point.point)),
        disagreement(&disagreeing, cost)
    )
}

/// The answer without a comparable reference: the point with settled runs of the lowest mean
/// cost, and that its pile was not compared (`named`: the study names a reference that could not be compared).
fn cheapest_answer(points: &Points, named: bool) -> String {
    let cost = if points.metric_names().contains(&"particle_steps") { "particle_steps" } else { "steps" };
    let cheapest = (0..points.len())
        .filter(|&p| points.describe(p, quantity::SETTLE_TIME.name).n > 0)
        .map(|p| (p, points.describe(p, cost)))
        .filter(|(_, d)| d.mean.is_finite())
        .min_by(|a, b| a.1.mean.total_cmp(&b.1.mean));
    let why = if named {
        "the study's reference point could not be compared (see below)"
    } else {
        "the study names no reference point (<code>[report] reference</code>, docs/studies.md)"
    };
    let Some((point, d)) = cheapest else {
        return format!("No grid point has a settled run, so none is the fastest; the pile was not compared: {why}.");
    };
    format!(
        "<b>{}</b> is the fastest grid point: {} {cost} per run (mean ± 95 % half-width). The pile was not compared: \
         {why}, so whether it makes the same pile as your usual settings is not known.",
        escape(&points.label(point)),
        escape(&crate::stats::points::plus_minus(Some(d.mean), Some(d.half_width_95))),
    )
}

/// Which ratio to trust, for the points (`labels`) whose cost and wall-time ratios disagree; empty
/// when there are none.
fn disagreement(labels: &[String], cost: &str) -> String {
    if labels.is_empty() {
        return String::new();
    }
    format!(
        " <span class=\"note\">For {}, the {cost} and wall-time ratios disagree (their 95 % intervals do not \
         overlap): trust the {cost} ratio. It counts the work done (disks × time steps), the same on any machine; \
         wall time also counts whatever else the machine was running, which on a shared or busy machine moves it by \
         more than the difference. Wall time is worth a second look only where the work per step differs (another \
         contact law, many more contacts), measured on an idle machine.</span>",
        escape(&labels.join(", "))
    )
}

/// Whether a point's cost and wall-time ratios disagree: their 95 % intervals do not overlap.
fn ratios_disagree(point: &compare::PointComparison) -> bool {
    let (c, w) = (&point.cost, &point.wall_time);
    c.high < w.low || w.high < c.low
}

/// The points compared with the study's reference point (`demsweep compare`, default tolerances),
/// sorted by their decision over every kept metric (TOST at 90 %).
#[derive(Debug)]
struct ReferenceVerdict {
    /// Every other point against the reference.
    comparison: Comparison,
    /// Indices into `comparison.points`, each list cheapest first: equivalent on every kept metric.
    equivalent: Vec<usize>,
    /// Different on at least one kept metric.
    different: Vec<usize>,
    /// Neither: more seeds would decide.
    undecided: Vec<usize>,
}

impl ReferenceVerdict {
    fn new(points: &Points, spec: &str) -> Result<Self, crate::stats::CompareError> {
        let comparison = compare::compare(points, spec, &[])?;
        let (mut equivalent, mut different, mut undecided) = (Vec::new(), Vec::new(), Vec::new());
        for (i, point) in comparison.points.iter().enumerate() {
            match () {
                _ if point.acceptable() => equivalent.push(i),
                _ if point.tests.iter().any(|t| t.decision == Decision::Different) => different.push(i),
                _ => undecided.push(i),
            }
        }
        let cheapest_first = |list: &mut Vec<usize>| {
            list.sort_by(|&a, &b| comparison.points[a].cost.ratio.total_cmp(&comparison.points[b].cost.ratio))
        };
        [&mut equivalent, &mut different, &mut undecided].into_iter().for_each(cheapest_first);
        Ok(Self { comparison, equivalent, different, undecided })
    }
}

/// The answer about the study's reference point: which points make the same pile, at what cost.
fn reference_section(points: &Points, spec: &str) -> String {
    let verdict = match ReferenceVerdict::new(points, spec) {
        Ok(verdict) => verdict,
        Err(reason) => {
            return format!(
                "<h3 id=\"reference\">Against the reference point</h3><p class=\"note\">The study's reference ({}) \
                 cannot be compared: {}</p>",
                escape(spec),
                escape(&reason.to_string())
            );
        }
    };
    let comparison = &verdict.comparison;
    let kept: Vec<String> = comparison
        .kept
        .iter()
        .map(|k| format!("{} within {} %", k.tolerance.metric, number(100.0 * k.tolerance.relative)))
        .collect();
    // Long names and intervals wrap (at underscores, before the interval) so the table fits the page.
    let wrapped = |text: &str| escape(text).replace('_', "_<wbr>").replacen(" [", "<br>[", 1);
    let metric_headers: String =
        comparison.kept.iter().map(|k| format!("<th>{}</th>", wrapped(&k.tolerance.metric))).collect();
    let cost = &comparison.cost_column;
    let cost_header = wrapped(cost);
    let row = |i: &usize, judged: &str| {
        let point = &comparison.points[*i];
        let decisions: String = point.tests.iter().map(|t| format!("<td>{}</td>", t.decision.as_str())).collect();
        format!(
            "<tr><td>{}</td>{decisions}<td class=\"num\">{}</td><td class=\"num\">{}</td><td>{judged}</td></tr>",
            escape(&points.label(point.point)),
            wrapped(&compare::ratio(&point.cost)),
            wrapped(&compare::ratio(&point.wall_time)),
        )
    };
    let rows: String =
        [(&verdict.equivalent, "equivalent"), (&verdict.undecided, "undecided"), (&verdict.different, "different")]
            .iter()
            .flat_map(|(list, judged)| list.iter().map(move |i| row(i, judged)))
            .collect();
    let notes: String = comparison.notes.iter().map(|n| format!(" {}.", escape(n))).collect();
    let disagreeing: Vec<String> =
        comparison.points.iter().filter(|p| ratios_disagree(p)).map(|p| points.label(p.point)).collect();
    let disagreeing = match disagreement(&disagreeing, cost) {
        note if note.is_empty() => note,
        note => format!("<p class=\"note\" id=\"ratios-disagree\">{}</p>", note.trim_start()),
    };
    format!(
        "<h3 id=\"reference\">Against the reference point</h3><p class=\"verdict\" id=\"reference-verdict\">Reference: \
         {}. {} of {} other grid points make an equivalent pile (TOST, 90 % intervals of the difference inside \
         the margins: {}); {} differ, {} are undecided (more seeds would decide).{notes} Cost: {cost} and wall time \
         relative to the reference, with 95 % intervals.</p><table class=\"verdict\" id=\"reference-table\"><thead><tr>\
         <th>grid point</th>{metric_headers}<th>{cost_header} ratio</th><th>wall time ratio</th><th>pile</th></tr></thead>\
         <tbody>{rows}</tbody></table>{disagreeing}",
        escape(&points.label(comparison.reference)),
        verdict.equivalent.len(),
        comparison.points.len(),
        escape(&kept.join(", ")),
        verdict.different.len(),
        verdict.undecided.len(),
    )
}

/// How the runs ended (counts by status), their failure messages grouped, and their warnings by
/// kind: how many runs have one and the worst (largest over its limit); in a tune's report the
/// kind's name and key with the worst value, else the worst warning in full (what it means, its cure).
fn outcomes(rows: &[SummaryRow], tune: bool) -> String {
    let mut statuses: BTreeMap<&str, usize> = BTreeMap::new();
    let mut worst: BTreeMap<WarningKind, (&ValidityWarning, &str)> = BTreeMap::new();
    let mut runs: BTreeMap<WarningKind, usize> = BTreeMap::new();
    let mut messages: BTreeMap<(&str, &str), usize> = BTreeMap::new();
    for row in rows {
        *statuses.entry(row.status.as_str()).or_default() += 1;
        for warning in &row.warnings {
            let entry = worst.entry(warning.kind).or_insert((warning, &row.id));
            if warning.excess() > entry.0.excess() {
                *entry = (warning, &row.id);
            }
        }
        let mut kinds: Vec<WarningKind> = row.warnings.iter().map(|w| w.kind).collect();
        kinds.sort_unstable();
        kinds.dedup();
        kinds.into_iter().for_each(|k| *runs.entry(k).or_default() += 1);
        if !row.message.is_empty() {
            *messages.entry((row.status.as_str(), &row.message)).or_default() += 1;
        }
    }
    let badges: String =
        statuses.iter().map(|(s, n)| format!("<span class=\"{}\">{n} {}</span>", escape(s), escape(s))).collect();
    let mut out = format!("<h2 id=\"outcomes\">How the runs ended</h2><p class=\"badges\">{badges}</p>");
    let grouped = |title: &str, entries: Vec<(String, usize)>| {
        let mut sorted = entries;
        sorted.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let rows: String =
            sorted.iter().map(|(m, n)| format!("<tr><td class=\"num\">{n}</td><td>{}</td></tr>", escape(m))).collect();
        format!(
            "<h3>{title}</h3><table><thead><tr><th>runs</th><th>message</th></tr></thead><tbody>{rows}</tbody></table>"
        )
    };
    if !messages.is_empty() {
        let entries = messages.into_iter().map(|((s, m), n)| (format!("{s}: {m}"), n)).collect();
        out += &grouped("Why runs failed or diverged", entries);
    }
    if worst.is_empty() {
        out += "<p class=\"note\">No run has a warning.</p>";
        return out;
    }
    let entries = worst
        .into_iter()
        .map(|(kind, (warning, id))| {
            let text = if tune {
                let (value, limit) = (warning.value, warning.limit);
                format!("{} ({}): worst {value:.4} against {limit} (run {id})", kind.name(), kind.limit_key())
            } else {
                format!("{} (worst: run {id}): {warning}", kind.name())
            };
            (text, runs.get(&kind).copied().unwrap_or(0))
        })
        .collect();
    out + &grouped("Warnings", entries)
}

/// The per-point table: rows built in the browser from embedded JSON; a note names the points CSV
/// when the grid has more points than the table holds.
fn points_section(summary: &SummaryTable, charted: &[&str], points_csv: &Path) -> String {
    let points = Points::new(summary);
    let table = html::PointsTable::new(&points, charted);
    let left_out = match table.shown() {
        (shown, total) if shown < total => format!(
            "<p class=\"note\" id=\"points-left-out\">{shown} of {total} grid points shown ({} at most, spread evenly over the grid); every point is in {} and in `demsweep summary --by-point`.</p>",
            html::MAX_POINT_ROWS,
            escape(&points_csv.file_name().unwrap_or_default().to_string_lossy())
        ),
        _ => String::new(),
    };
    let statuses: String =
        RunStatus::RECORDED.iter().map(|s| format!("<option value=\"{s}\">with {s} runs</option>")).collect();
    format!(
        "<h2 id=\"grid-points\">Grid points</h2><p class=\"note\">One row per grid point (the runs that differ only by placement seed): mean ± 95 % confidence half-width over its runs, in the unit of its column's header (hover over a header for what it is). Click a column header to sort; click again to reverse. Tick a header group under \"columns\" to show its columns.</p>{left_out}\
         <div class=\"controls\"><label>show <select id=\"status-filter\"><option value=\"\">all points</option>{statuses}</select></label>\
         <span id=\"column-groups\" title=\"Show or hide a header group's columns.\">columns:</span></div>\
         <div class=\"scroll\"><table id=\"points\">{}<tbody></tbody></table></div>\
         <script type=\"application/json\" id=\"points-data\">{}</script>",
        table.header(),
        table.json()
    )
}

/// The study charts, each as inline SVG.
fn charts_section(svgs: &Svgs) -> String {
    let mut out = String::from("<h2 id=\"charts\">Settle time</h2>");
    for (_, svg) in &svgs.drawn.charts {
        out += &format!("<div class=\"chart\">{svg}</div>");
    }
    for note in &svgs.drawn.notes {
        out += &format!("<p class=\"note\">{}</p>", escape(note));
    }
    out
}

/// The pile-metric charts (per-point means with 95 % intervals against each swept axis), two abreast.
fn pile_charts_section(svgs: &Svgs) -> String {
    if svgs.drawn.charts.is_empty() {
        return String::new();
    }
    let charts: String = svgs.drawn.charts.iter().map(|(_, svg)| format!("<div class=\"chart\">{svg}</div>")).collect();
    format!(
        "<h2 id=\"pile-metrics\">Pile metrics</h2><p class=\"note\">Mean over the runs at each value of the two chart axes (replicates and further swept parameters) with its 95 % interval, against each of them; each series is shifted a little along x so that intervals at one value stay apart.</p><div class=\"grid2\">{charts}</div>"
    )
}

/// The tune's answer (its lines: indented ones, the pile metrics, as a list with those beyond 2σ
/// marked), chart and candidate table.
fn tune_section(tune: &TuneSection) -> String {
    let mut answer = String::new();
    let mut list = String::new();
    for line in tune.recommendation.lines() {
        match line.strip_prefix("  ") {
            Some(item) => {
                let class = if item.contains("beyond 2σ") { " class=\"flag\"" } else { "" };
                list += &format!("<li{class}>{}</li>", escape(item));
            }
            None => {
                if !list.is_empty() {
                    answer += &format!("<ul class=\"metrics\">{}</ul>", std::mem::take(&mut list));
                }
                answer += &format!("<p class=\"recommendation\">{}</p>", escape(line));
            }
        }
    }
    if !list.is_empty() {
        answer += &format!("<ul class=\"metrics\">{list}</ul>");
    }
    format!(
        "<h2 id=\"tune\">Tune: the answer</h2>{answer}<div class=\"chart\">{}</div><h3>Candidates</h3><div class=\"scroll\">{}</div>",
        tune.chart_svg,
        html::static_table(&tune.candidates)
    )
}

/// A charted run: its energies, unbalanced force ratio, stress profile and pile, and its deposition's
/// player.
fn run_section(row: &SummaryRow, svgs: &Svgs) -> String {
    let charts: String = svgs.drawn.charts.iter().map(|(_, svg)| format!("<div class=\"chart\">{svg}</div>")).collect();
    let notes: String = svgs.drawn.notes.iter().map(|n| format!("<p class=\"note\">{}</p>", escape(n))).collect();
    let mut settle = row.settle_time.map_or("not settled".to_string(), |t| format!("settled at {} s", number(t)));
    if let Some(t) = row.final_value("physics_start_time").filter(|t| *t > 0.0) {
        settle = format!("its protocol's stages ended at {} s; {settle}", number(t));
    }
    format!(
        "<section id=\"run-{id}\"><h3>{}</h3><p class=\"note\">{settle}; {} steps; {} s of computing; {} warnings</p><div class=\"grid2\">{charts}{}</div>{notes}</section>",
        escape(&results::run_subject(row)),
        row.steps,
        number(row.wall_time),
        row.warnings.len(),
        svgs.player.as_deref().unwrap_or(""),
        id = escape(&row.id),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::table::{Column, ColumnData};

    /// Six runs at each friction 0.2, 0.4, 0.6: the packing fraction of 0.4 within 0.1 % of 0.2's
    /// at half the particle-steps, that of 0.6 10 % higher.
    fn summary() -> SummaryTable {
        summary_of(&[(0.2, 0.80, 2e6, 1.0), (0.4, 0.8004, 1e6, 1.0), (0.6, 0.88, 2e6, 1.0)])
    }

    /// Six runs at each (friction, packing fraction, particle-steps, wall seconds per 1e7 particle-steps).
    fn summary_of(grid: &[(f64, f64, f64, f64)]) -> SummaryTable {
        let (mut friction, mut packing, mut cost, mut wall) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (point, (mu, level, steps, speed)) in grid.iter().enumerate() {
            for seed in 0..6 {
                let noise = [-2.0, 1.0, 0.5, -0.5, 1.5, -0.5][(seed + point) % 6] * 1e-4;
                friction.push(*mu);
                packing.push(level + noise);
                cost.push(steps * (1.0 + noise));
                wall.push(steps * (1.0 + noise) * 1e-7 * speed);
            }
        }
        let n = friction.len();
        let column = |name: &str, data| Column { name: name.to_string(), data };
        SummaryTable {
            columns: vec![
                column("index", ColumnData::Int((0..n as i64).collect())),
                column("material.friction", ColumnData::Float(friction)),
                column("status", ColumnData::Text(vec!["settled".into(); n])),
                column("settle_time", ColumnData::Float(vec![0.5; n])),
                column("packing_fraction_interior", ColumnData::Float(packing)),
                column("particle_steps", ColumnData::Float(cost.clone())),
                column("wall_time", ColumnData::Float(wall)),
            ],
        }
    }

    #[test]
    fn the_reference_verdict_sorts_points_by_their_tost_decision() {
        let summary = summary();
        let points = Points::new(&summary);
        let verdict = ReferenceVerdict::new(&points, "friction=0.2").unwrap();
        let label = |i: &usize| points.label(verdict.comparison.points[*i].point);
        assert_eq!(points.label(verdict.comparison.reference), "material.friction=0.2");
        assert_eq!(verdict.equivalent.iter().map(label).collect::<Vec<_>>(), ["material.friction=0.4"]);
        assert_eq!(verdict.different.iter().map(label).collect::<Vec<_>>(), ["material.friction=0.6"]);
        assert!(verdict.undecided.is_empty());
        let cost = &verdict.comparison.points[verdict.equivalent[0]].cost;
        assert!((cost.ratio - 0.5).abs() < 1e-3 && cost.low < 0.5 && cost.high > 0.5, "{cost:?}");
        let html = super::verdict(&summary, Some("friction=0.2"));
        assert!(html.contains("1 of 2 other grid points make an equivalent pile"), "{html}");
        assert!(ReferenceVerdict::new(&points, "friction=0.3").unwrap_err().to_string().contains("no point has"));
    }

    #[test]
    fn warnings_are_grouped_by_kind_with_the_worst_of_each() {
        let overlap = |value| ValidityWarning::new(WarningKind::Overlap, value, 0.1);
        let energy = ValidityWarning::new(WarningKind::EnergyBalance, 0.05, 0.01);
        let mut rows: Vec<SummaryRow> = (0..3).map(|i| SummaryRow::failed(i, &format!("r{i}"), &[], "")).collect();
        rows[0].warnings = vec![overlap(0.12), overlap(0.13)];
        rows[1].warnings = vec![overlap(0.31), energy];
        let page = outcomes(&rows, false);
        let worst = escape(&overlap(0.31).to_string());
        let group = format!("<td class=\"num\">2</td><td>measured overlap (worst: run r1): {worst}</td>");
        assert!(page.contains(&group), "one row for both runs' overlaps, the worst in full: {page}");
        assert!(page.contains("<td class=\"num\">1</td><td>energy-balance error (worst: run r1): "), "{page}");
        let tune = outcomes(&rows, true);
        let short = "measured overlap (limits.overlap_warning_ratio): worst 0.3100 against 0.1 (run r1)";
        assert!(tune.contains(short), "{tune}");
        assert!(outcomes(&rows[2..], false).contains("No run has a warning."));
    }

    /// The text of the page's first answer.
    fn answer(summary: &SummaryTable, spec: Option<&str>) -> String {
        let html = super::verdict(summary, spec);
        let start = html.find("<p class=\"verdict answer\" id=\"answer\">").expect("the answer paragraph");
        html[start..].split("</p>").next().unwrap().to_string()
    }

    #[test]
    fn the_answer_is_the_fastest_point_that_makes_the_same_pile() {
        let text = answer(&summary(), Some("friction=0.2"));
        assert!(
            text.contains("<b>material.friction=0.4</b> is the fastest grid point that makes the same pile"),
            "{text}"
        );
        let rounded = "0.500000 [0.499919, 0.500081] of the reference's particle_steps"; // half-width 8.1e-5
        assert!(
            text.contains(rounded) && !text.contains("disagree"),
            "the cost ratio, rounded to its interval: {text}"
        );
        let html = super::verdict(&summary(), Some("friction=0.2"));
        assert!(html.find("id=\"answer\"").unwrap() < html.find("Fastest-settling").unwrap_or(usize::MAX), "first");
    }

    #[test]
    fn without_an_equivalent_faster_point_the_answer_names_the_nearest_miss_and_what_moved() {
        // 0.4 and 0.6 are faster than 0.2; both piles differ, 0.4's less.
        let grid = [(0.2, 0.80, 2e6, 1.0), (0.4, 0.84, 1e6, 1.0), (0.6, 0.90, 1.5e6, 1.0)];
        let text = answer(&summary_of(&grid), Some("friction=0.2"));
        assert!(
            text.starts_with("<p class=\"verdict answer\" id=\"answer\">None of the 2 faster grid points"),
            "{text}"
        );
        assert!(text.contains("The nearest miss is <b>material.friction=0.4</b>"), "{text}");
        assert!(text.contains("its packing_fraction_interior moved by 0.04"), "{text}");
        let slower = [(0.2, 0.80, 1e6, 1.0), (0.4, 0.80, 2e6, 1.0)];
        assert!(
            answer(&summary_of(&slower), Some("friction=0.2")).contains("No grid point is faster than the reference")
        );
    }

    #[test]
    fn without_a_reference_the_answer_is_the_fastest_point_and_says_the_pile_was_not_compared() {
        let text = answer(&summary(), None);
        assert!(text.contains("<b>material.friction=0.4</b> is the fastest grid point"), "{text}");
        assert!(text.contains("The pile was not compared: the study names no reference point"), "{text}");
        let mut unsettled = summary();
        unsettled.columns.retain(|c| c.name != "settle_time");
        assert!(answer(&unsettled, None).contains("No grid point has a settled run, so none is the fastest"));
    }

    #[test]
    fn where_wall_time_and_particle_steps_disagree_the_page_says_which_to_trust() {
        // 0.4 takes half the particle-steps but, on a busy machine, three times the wall time per step.
        let grid = [(0.2, 0.80, 2e6, 1.0), (0.4, 0.8004, 1e6, 3.0), (0.6, 0.88, 2e6, 1.0)];
        let html = super::verdict(&summary_of(&grid), Some("friction=0.2"));
        let text = answer(&summary_of(&grid), Some("friction=0.2"));
        assert!(text.contains("the particle_steps and wall-time ratios disagree"), "{text}");
        assert!(text.contains("trust the particle_steps ratio"), "{text}");
        assert!(html.contains("id=\"ratios-disagree\""), "beside the table too");
        assert!(!super::verdict(&summary(), Some("friction=0.2")).contains("disagree"), "agreeing ratios: no note");
    }
}
