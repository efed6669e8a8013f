//! One run's histories, or its stress profile, as CSV (for `demsweep history`).

use std::io::Write;
use std::path::Path;

use super::{OutputError, OutputReason, compound, csv, layout, reader};

/// Writes the histories of run `run_id` of a results file as CSV: one column per series (the fields
/// of the run's `history` table, headed by their bare names; the units are the results file's), one
/// line per sample.
pub fn to_csv<W: Write>(path: &Path, run_id: &str, out: &mut W) -> Result<(), OutputError> {
    table_to_csv(path, run_id, "history", out)
}

/// Writes the stress profile of run `run_id` (its `stress_profile` table: one line per height band,
/// see `layout::stress_profile_columns`) as CSV, as [`to_csv`] writes the histories.
pub fn stress_profile_to_csv<W: Write>(path: &Path, run_id: &str, out: &mut W) -> Result<(), OutputError> {
    table_to_csv(path, run_id, layout::STRESS_PROFILE, out)
}

/// Writes the table `table` of run `run_id` as CSV, headed by its field names.
fn table_to_csv<W: Write>(path: &Path, run_id: &str, table: &str, out: &mut W) -> Result<(), OutputError> {
    let file = reader::open(path)?;
    let run = reader::find_run(&file, path, run_id)?;
    let missing = || match table {
        "history" => OutputReason::NoHistories(run_id.to_string()),
        _ => OutputReason::NoStressProfile(run_id.to_string()),
    };
    let dataset = file.dataset(&format!("{run}/{table}")).map_err(|_| OutputError::at(path, missing()))?;
    let columns = compound::decode(&dataset, compound::read_limit(path))
        .map_err(|e| reader::damaged_data(path, run_id, &format!("{run}/{table}"), e))?;
    let write_err = |e| OutputError::io(Path::new("<output>"), e);
    let names: Vec<&str> = columns.iter().map(|(n, _)| n.as_str()).collect();
    csv::write_record(out, &names).map_err(write_err)?;
    for i in 0..columns.first().map_or(0, |(_, c)| c.len()) {
        let cells: Vec<String> = columns.iter().map(|(_, c)| c.text(i)).collect();
        csv::write_record(out, &cells).map_err(write_err)?;
    }
    Ok(())
}
