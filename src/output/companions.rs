//! The files written beside a results file: its summary and points CSV tables and its report page.

use std::path::{Path, PathBuf};

use super::guard::{self, Existing, Refusal};
use super::layout::{POINTS, SUMMARY};
use super::{OutputError, Tables, csv, reader, summary};

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
    summary::write_csv(&summary, &tables.summary, Existing::Any)?;
    summary::write_csv(&points, &tables.points, Existing::Any)?;
    Ok((summary, points))
}

/// Checks, before a results file is written, that the files written beside it (its CSV tables, their
/// sidecars and its report page) may be: no link or folder, and only files demsweep wrote unless
/// `force`. A CSV table is demsweep's also when its names line is that of the table the results file
/// stores (a table whose sidecar was lost: a command killed between the two, a full disk). Beside a
/// file being resumed (`resume`), a refusal says to move the file away, not to pass `--force` (which
/// would run the stored runs again).
pub fn check_companions(results: &Path, force: bool, resume: bool) -> Result<(), OutputError> {
    let check = |path: &Path| guard::check_replaceable(path, &[results], Existing::Ours { force });
    let table = |path: &Path, table: &str| match check(path) {
        Err(e) if e.refusal == Refusal::NotMadeByDemsweep && names_stored(results, path, table) => Ok(()),
        checked => checked,
    };
    let (summary, points) = (csv_path(results), points_csv_path(results));
    let checked = table(&summary, SUMMARY)
        .and_then(|()| check(&csv::metadata_path(&summary)))
        .and_then(|()| table(&points, POINTS))
        .and_then(|()| check(&csv::metadata_path(&points)))
        .and_then(|()| check(&report_path(results)));
    checked.map_err(|e| {
        let e = if resume { e.resuming() } else { e };
        OutputError::refused(&e.path.clone(), e)
    })
}

/// The files written beside a results file: its CSV tables, their sidecars and its report page.
fn companions(results: &Path) -> [PathBuf; 5] {
    let (summary, points) = (csv_path(results), points_csv_path(results));
    [csv::metadata_path(&summary), csv::metadata_path(&points), summary, points, report_path(results)]
}

/// Checks that `path`, a table another command writes from `results`, is none of the files written
/// beside it (`companions`) unless `force`: written there, that table would stand in for the
/// results file's own.
pub fn check_not_companion(results: &Path, path: &Path, force: bool) -> Result<(), OutputError> {
    if force || !companions(results).iter().any(|own| guard::same_file(path, own)) {
        return Ok(());
    }
    let error = guard::GuardError { path: path.to_path_buf(), refusal: Refusal::Companion(results.into()) };
    Err(OutputError::refused(path, error))
}

/// Whether the CSV table `csv` starts with the names line of the table `name` that `results` stores.
fn names_stored(results: &Path, csv: &Path, name: &str) -> bool {
    let Some(names) = reader::stored_names(results, name) else { return false };
    let mut line = Vec::new();
    csv::write_record(&mut line, &names).expect("writing to memory");
    let mut start = vec![0; line.len()];
    std::fs::File::open(csv).and_then(|mut f| std::io::Read::read_exact(&mut f, &mut start)).is_ok() && start == line
}
