//! One run's histories as CSV (for `demsweep history`).

use std::io::Write;
use std::path::Path;

use super::layout::HISTORY_SERIES;
use super::reader;
use super::table::ColumnData;
use super::{OutputError, csv, hdf5_error};

/// Writes the histories of run `run_id` of a results file as CSV: one column per series
/// (in the order of [`HISTORY_SERIES`]), one line per sample.
pub fn to_csv<W: Write>(path: &Path, run_id: &str, out: &mut W) -> Result<(), OutputError> {
    let file = reader::open(path)?;
    let run = reader::find_run(&file, path, run_id)?;
    let group = file.group(&format!("{run}/history")).map_err(|_| {
        OutputError::new(path, format!("run `{run_id}` has no histories (the study's output.histories is off)"))
    })?;
    let columns = HISTORY_SERIES
        .iter()
        .map(|name| {
            let dataset = group.dataset(name).map_err(|e| hdf5_error(path, e))?;
            let data = if *name == "contacts" {
                let counts = dataset.read_u32().map_err(|e| hdf5_error(path, e))?;
                ColumnData::Int(counts.into_iter().map(i64::from).collect())
            } else {
                ColumnData::Float(dataset.read_f64().map_err(|e| hdf5_error(path, e))?)
            };
            Ok(data)
        })
        .collect::<Result<Vec<_>, OutputError>>()?;
    let write_err = |e| OutputError::io(Path::new("<stdout>"), e);
    csv::write_record(out, &HISTORY_SERIES).map_err(write_err)?;
    for i in 0..columns.first().map_or(0, ColumnData::len) {
        let cells: Vec<String> = columns.iter().map(|c| c.text(i)).collect();
        csv::write_record(out, &cells).map_err(write_err)?;
    }
    Ok(())
}
