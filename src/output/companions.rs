//! The files written beside a results file: its summary and points CSV tables and its report page.

use std::path::{Path, PathBuf};

use super::{OutputError, Tables, guard, summary};

/// The summary CSV path next to a results file: `<stem>_summary.csv`.
pub fn csv_path(results: &Path) -> PathBuf {
    sibling(results, "summary")
}

/// The per-point CSV path next to a results file: `<stem>_points.csv`.
pub fn points_csv_path(results: &Path) -> PathBuf {
    sibling(results, "points")
}

/// The report page path next to a results file: `<stem>_report.html` (`<study name>_report.html`
/// for a study's results, `<study name>.shard-K-of-N_report.html` for a shard's, so that shards never
/// share a page).
pub fn report_path(results: &Path) -> PathBuf {
    let stem = results.file_stem().unwrap_or_default().to_string_lossy();
    results.with_file_name(format!("{stem}_report.html"))
}

/// `<stem>_<what>.csv` next to a results file.
fn sibling(results: &Path, what: &str) -> PathBuf {
    let stem = results.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    results.with_file_name(format!("{stem}_{what}.csv"))
}

/// Writes the summary and points CSV files next to a results file (each whole or not at all, see
/// [`guard::write_with`]); returns their paths. Whoever writes the results file checks them first
/// ([`check_companions`]).
pub fn write_csv_files(results: &Path, tables: &Tables) -> Result<(PathBuf, PathBuf), OutputError> {
    let (summary, points) = (csv_path(results), points_csv_path(results));
    summary::write_csv(&summary, &tables.summary, guard::Existing::Any)?;
    summary::write_csv(&points, &tables.points, guard::Existing::Any)?;
    Ok((summary, points))
}

/// Checks, before a results file is written, that the files written beside it (its CSV files and
/// report page) may be: no link, and only files demsweep wrote unless `force`.
pub fn check_companions(results: &Path, force: bool) -> Result<(), OutputError> {
    for path in [csv_path(results), points_csv_path(results), report_path(results)] {
        guard::check_replaceable(&path, &[results], guard::Existing::Ours { force })
            .map_err(|e| OutputError::refused(&path, e))?;
    }
    Ok(())
}
