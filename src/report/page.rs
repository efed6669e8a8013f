//! The page as a whole: what it is built from (a results file, and the tables of its runs), its
//! sections in order, and the page written beside the results.

use std::path::{Path, PathBuf};

use hdf5_pure::File;

use super::html::{self, escape};
use super::sections::{charts_section, outcomes, overview, pile_charts_section, points_section, run_section};
use super::tune::{read_tune_section, tune_section};
use super::verdict::verdict;
use super::{CHART_SIZE, Svgs, report_path};
use crate::output::guard::{self, Existing};
use crate::output::reader::{self, DamagedGroup};
use crate::output::{FileHeader, OutputError, SummaryRow, Tables};
use crate::plot::Format;
use crate::plot::PlotError;
use crate::plot::results::{self, DEFAULT_RUN_LIMIT, PlotRequest};
use crate::plot::run::ColourBy;
use crate::stats::points;

/// How the results were made: what the caller says, else what the file recorded of its last sweep.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReportContext {
    /// Worker threads the runs ran on.
    pub jobs: Option<usize>,
    /// Wall-clock time of the whole command (s).
    pub elapsed: Option<f64>,
}

/// A page written: where it went, the run groups left out of it (unreadable) and the study charts
/// that could not be drawn; or why there is none.
pub type Written = Result<(PathBuf, Vec<DamagedGroup>, Vec<PlotError>), OutputError>;

/// What a page is built from besides the tables of its runs: the results file, its header, the rows
/// of its readable runs and the run groups that cannot be read, and what it recorded of its last
/// sweep.
struct Source<'a> {
    results: &'a Path,
    file: File,
    header: FileHeader,
    rows: Vec<SummaryRow>,
    damaged: Vec<DamagedGroup>,
    recorded: Option<(usize, f64)>,
}

impl<'a> Source<'a> {
    /// Reads the results file `results`.
    fn read(results: &'a Path) -> Result<Self, OutputError> {
        let file = reader::open(results)?;
        let header = reader::header(&file, results)?;
        let (rows, damaged) = reader::scan(&file, results)?;
        let recorded = reader::sweep(&file);
        Ok(Self { results, file, header, rows, damaged, recorded })
    }
}

/// Writes the report of the results file `results` to `out` (default: [`report_path`]) from its
/// readable runs, whole or not at all, replacing a file there as `existing` allows; returns where it
/// went, the run groups that could not be read (left out) and the study charts that could not be
/// drawn (left out: warnings, as the summary they come from is whole). A run whose stored data
/// cannot be read is an error.
pub fn write_report(results: &Path, out: (Option<&Path>, Existing), context: &ReportContext) -> Written {
    let source = Source::read(results)?;
    let tables = points::tables(&source.rows);
    write_page(&source, &tables, out, context)
}

/// [`write_report`] of a sweep's results file with the tables its runner computed (its summary and
/// per-point statistics) in place of those of the file's runs. A file that holds runs the sweep left
/// out of its tables (stored runs the study no longer plans) has the page of all its runs.
pub fn write_report_of(
    results: &Path,
    tables: &Tables,
    out: (Option<&Path>, Existing),
    context: &ReportContext,
) -> Written {
    let source = Source::read(results)?;
    match source.rows.len() == tables.summary.len() {
        true => write_page(&source, tables, out, context),
        false => write_page(&source, &points::tables(&source.rows), out, context),
    }
}

/// The page of `source` with the statistics of `tables`, written as [`write_report`] says.
fn write_page(
    source: &Source,
    tables: &Tables,
    (out, existing): (Option<&Path>, Existing),
    context: &ReportContext,
) -> Written {
    let results = source.results;
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
        results::select_runs(&source.rows, &request).map_err(|e| OutputError::new(results, e.reason))?;
    let context = ReportContext {
        jobs: context.jobs.or(source.recorded.map(|(jobs, _)| jobs)),
        elapsed: context.elapsed.or(source.recorded.map(|(_, wall)| wall)),
    };
    let mut page = html::Page::new(&source.header.study_name);
    let not_drawn = push_results(&mut page, source, tables, (&charted, &context));
    let failures = push_runs(&mut page, source, &charted);
    let path = out.map_or_else(|| report_path(results), Path::to_path_buf);
    guard::write_with(&path, &[results], existing, |out| out.write_all(page.finish().as_bytes()))
        .map_err(|e| OutputError::new(&path, e.refusal_text()))?;
    match failures.is_empty() {
        true => Ok((path, source.damaged.clone(), not_drawn)),
        false => Err(unreadable(results, &path, &failures)),
    }
}

/// Pushes the page's sections above the runs' (what was run, the tune, the answer, how the runs
/// ended, the grid points and the study charts); returns the study charts not drawn.
fn push_results(
    page: &mut html::Page,
    source: &Source,
    tables: &Tables,
    (charted, context): (&[&SummaryRow], &ReportContext),
) -> Vec<PlotError> {
    let (header, rows) = (&source.header, &source.rows);
    // A tune's page shows its answer first, its warnings grouped by kind, and no study charts: a
    // tune's runs are not a grid, so averages over the levers mean nothing.
    let tune = read_tune_section(source.results, &header.study_name);
    page.push(&overview(header, rows, context, tune.is_some()));
    match &tune {
        Some((_, Ok(tune))) => page.push(&tune_section(tune)),
        Some((path, Err(e))) => {
            let reason = format!("{}: {e}", path.display());
            page.push(&format!("<h2 id=\"tune\">Tune</h2><p class=\"note\">{}</p>", escape(&reason)));
        }
        None => {}
    }
    if !source.damaged.is_empty() {
        page.push(&format!("<p class=\"note\">{}</p>", escape(&reader::damage_text(&source.damaged))));
    }
    if tune.is_some() {
        page.push(&outcomes(rows, true));
        return Vec::new();
    }
    page.push(&verdict(&tables.summary, crate::study::reference::reference_spec(&header.study_text).as_deref()));
    page.push(&outcomes(rows, false));
    let charted_ids: Vec<&str> = charted.iter().map(|r| r.id.as_str()).collect();
    page.push(&points_section(tables, &charted_ids, &crate::output::points_csv_path(source.results)));
    let mut study = Svgs::new();
    results::study_charts(&mut study, &header.study_name, rows);
    page.push(&charts_section(&study));
    let mut pile = Svgs::new();
    results::pile_metric_charts(&mut pile, &header.study_name, rows);
    page.push(&pile_charts_section(&pile));
    study.drawn.failures.into_iter().chain(pile.drawn.failures).collect()
}

/// Pushes the section of each charted run; returns the charts and runs that could not be drawn.
fn push_runs(page: &mut html::Page, source: &Source, charted: &[&SummaryRow]) -> Vec<PlotError> {
    let mut failures = Vec::new();
    let mut runs = String::from("<h2 id=\"runs\">Runs</h2><div class=\"runs\">");
    if source.rows.len() > charted.len() {
        runs += &format!(
            "<p class=\"note\">{} of {} runs charted ({DEFAULT_RUN_LIMIT} at most, spread over the study; `demsweep plot --run ID` draws any other).</p>",
            charted.len(),
            source.rows.len()
        );
    }
    for row in charted {
        let mut svgs = Svgs::new();
        results::run_charts(&mut svgs, (&source.file, source.results), row, (ColourBy::Speed, false));
        runs += &run_section(row, &svgs);
        failures.append(&mut svgs.drawn.failures);
    }
    runs += "</div>";
    page.push(&runs);
    failures
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
