//! The summary as a table of typed columns, shared by `/summary`, the CSV file and the printed table.

use super::row::{CPU_TIME, OutcomeKind, OutcomeValue, SummaryRow};
use crate::physics::quantity::{self, FINAL_VALUE_COUNT, OUTCOME};
use crate::physics::record::RunStatus;
use crate::study::ParamValue;

pub use crate::physics::number::significant;

/// The values of one column. Equality treats NaN as equal to NaN (a missing value equals a missing value).
#[derive(Clone, Debug)]
pub enum ColumnData {
    /// Floats; NaN marks a missing value.
    Float(Vec<f64>),
    /// Integers.
    Int(Vec<i64>),
    /// Booleans (stored as 0/1 `u8` in HDF5).
    Bool(Vec<bool>),
    /// Text; empty marks a missing value.
    Text(Vec<String>),
}

/// A named column.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    /// Column name: a fixed name or a swept key path.
    pub name: String,
    /// Its values, one per row.
    pub data: ColumnData,
}

/// The summary: one row per run, sorted by run index.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct SummaryTable {
    /// Columns in display order.
    pub columns: Vec<Column>,
}

/// The column of each run's identity (the name of its group in its batch group).
pub const IDENTITY: &str = "identity";

/// Names of the columns that depend on the machine and the moment, not on the study.
pub const TIMING_COLUMNS: [&str; 2] = ["wall_time", "cpu_time"];

impl PartialEq for ColumnData {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (ColumnData::Float(a), ColumnData::Float(b)) => {
                a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x == y || (x.is_nan() && y.is_nan()))
            }
            (ColumnData::Int(a), ColumnData::Int(b)) => a == b,
            (ColumnData::Bool(a), ColumnData::Bool(b)) => a == b,
            (ColumnData::Text(a), ColumnData::Text(b)) => a == b,
            _ => false,
        }
    }
}

impl ColumnData {
    /// Number of values.
    pub fn len(&self) -> usize {
        match self {
            ColumnData::Float(v) => v.len(),
            ColumnData::Int(v) => v.len(),
            ColumnData::Bool(v) => v.len(),
            ColumnData::Text(v) => v.len(),
        }
    }

    /// Whether the column has no values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The bytes its values take (8 a number, 1 a boolean, a text's length).
    pub fn data_bytes(&self) -> usize {
        match self {
            ColumnData::Float(v) => 8 * v.len(),
            ColumnData::Int(v) => 8 * v.len(),
            ColumnData::Bool(v) => v.len(),
            ColumnData::Text(v) => v.iter().map(String::len).sum(),
        }
    }

    /// The value of row `i` as text: floats in shortest round-trip form, missing values (and rows
    /// past the column's end) empty.
    pub fn text(&self, i: usize) -> String {
        match self {
            // `+ 0.0` writes a negative zero as 0 (a zero energy or ratio is not negative).
            ColumnData::Float(v) => {
                v.get(i).filter(|x| !x.is_nan()).map_or(String::new(), |x| format!("{:?}", x + 0.0))
            }
            ColumnData::Int(v) => v.get(i).map_or(String::new(), i64::to_string),
            ColumnData::Bool(v) => v.get(i).map_or(String::new(), bool::to_string),
            ColumnData::Text(v) => v.get(i).cloned().unwrap_or_default(),
        }
    }
}

impl ColumnData {
    /// The value of row `i` as a number: floats and integers; `None` for booleans and text.
    pub fn number(&self, i: usize) -> Option<f64> {
        match self {
            ColumnData::Float(v) => Some(v[i]),
            ColumnData::Int(v) => Some(v[i] as f64),
            _ => None,
        }
    }

    /// Whether the column holds floats or integers.
    pub fn is_numeric(&self) -> bool {
        matches!(self, ColumnData::Float(_) | ColumnData::Int(_))
    }

    /// The values of the rows `rows`, in that order.
    pub fn select(&self, rows: &[usize]) -> ColumnData {
        match self {
            ColumnData::Float(v) => ColumnData::Float(rows.iter().map(|&i| v[i]).collect()),
            ColumnData::Int(v) => ColumnData::Int(rows.iter().map(|&i| v[i]).collect()),
            ColumnData::Bool(v) => ColumnData::Bool(rows.iter().map(|&i| v[i]).collect()),
            ColumnData::Text(v) => ColumnData::Text(rows.iter().map(|&i| v[i].clone()).collect()),
        }
    }

    /// The value of row `i` as a swept parameter's value (see `parameter_data`); `None` where missing.
    pub fn param(&self, i: usize) -> Option<ParamValue> {
        match self {
            ColumnData::Float(v) if v[i].is_nan() => None,
            ColumnData::Float(v) => Some(ParamValue::Float(v[i])),
            ColumnData::Int(v) => Some(ParamValue::Int(v[i])),
            ColumnData::Bool(v) => Some(ParamValue::Bool(v[i])),
            ColumnData::Text(v) if v[i].is_empty() => None,
            ColumnData::Text(v) => Some(ParamValue::Text(v[i].clone())),
        }
    }

    /// The value of row `i` for reading on screen: floats to 6 significant digits, missing values `-`.
    pub fn display(&self, i: usize) -> String {
        match self {
            ColumnData::Float(v) if v[i].is_nan() => "-".to_string(),
            ColumnData::Float(v) => short_float(v[i]),
            _ => self.text(i),
        }
    }
}

/// A float to 6 significant digits: plain between 1e-3 and 1e6, scientific otherwise.
pub fn short_float(x: f64) -> String {
    significant(x, 6)
}

impl SummaryTable {
    /// Builds the table from rows (sorted here by run index).
    pub fn from_rows(rows: &[SummaryRow]) -> Self {
        let mut rows: Vec<&SummaryRow> = rows.iter().collect();
        rows.sort_by_key(|r| r.index);
        let floats = |f: &dyn Fn(&SummaryRow) -> f64| ColumnData::Float(rows.iter().map(|r| f(r)).collect());
        let texts = |f: &dyn Fn(&SummaryRow) -> String| ColumnData::Text(rows.iter().map(|r| f(r)).collect());
        let ints = |f: &dyn Fn(&SummaryRow) -> i64| ColumnData::Int(rows.iter().map(|r| f(r)).collect());
        let mut columns = vec![column("run_id", texts(&|r| r.id.clone())), column("index", ints(&|r| r.index as i64))];
        columns.extend(parameter_columns(&rows));
        columns.push(column("status", texts(&|r| r.status.as_str().to_string())));
        for (k, declared) in OUTCOME.iter().enumerate() {
            columns.push(column(declared.name, outcome_column(&rows, k)));
        }
        for (k, declared) in quantity::final_value_declarations().enumerate() {
            columns.push(column(declared.name, floats(&|r| r.final_values[k])));
        }
        columns.extend(stage_end_columns(&rows));
        columns.push(column("warnings", ints(&|r| r.warnings.len() as i64)));
        columns.push(column("message", texts(&|r| r.message.clone())));
        columns.push(column(IDENTITY, texts(&|r| r.identity.clone())));
        Self { columns }
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.columns.first().map_or(0, |c| c.data.len())
    }

    /// Whether the table has no rows.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The column with this name.
    pub fn column(&self, name: &str) -> Option<&Column> {
        self.columns.iter().find(|c| c.name == name)
    }

    /// The swept parameter columns of a summary: those between `index` and `status`.
    pub fn parameters(&self) -> &[Column] {
        let position = |name: &str| self.columns.iter().position(|c| c.name == name);
        match (position("index"), position("status")) {
            (Some(first), Some(end)) if first < end => &self.columns[first + 1..end],
            _ => &[],
        }
    }

    /// The rows of a summary, each with its number of warnings (whose texts the table does not
    /// hold: the rows' `warnings` are empty); `None` when a column a row needs is missing or of
    /// another type (a file of an older layout).
    pub fn rows(&self) -> Option<Vec<(SummaryRow, usize)>> {
        let texts = |name: &str| match &self.column(name)?.data {
            ColumnData::Text(v) => Some(v),
            _ => None,
        };
        let ints = |name: &str| match &self.column(name)?.data {
            ColumnData::Int(v) => Some(v),
            _ => None,
        };
        let number = |name: &str, i: usize| self.column(name)?.data.number(i);
        let (ids, indices, statuses, messages, warnings) =
            (texts("run_id")?, ints("index")?, texts("status")?, texts("message")?, ints("warnings")?);
        (0..self.len())
            .map(|i| {
                let mut final_values = [f64::NAN; FINAL_VALUE_COUNT];
                for (slot, declared) in final_values.iter_mut().zip(quantity::final_value_declarations()) {
                    *slot = number(declared.name, i).unwrap_or(f64::NAN);
                }
                let parameters: Vec<_> =
                    self.parameters().iter().filter_map(|c| Some((c.name.clone(), c.data.param(i)?))).collect();
                let mut row = SummaryRow {
                    index: usize::try_from(indices[i]).ok()?,
                    status: RunStatus::parse(&statuses[i])?,
                    final_values,
                    stage_ends: self.stage_ends(i),
                    identity: texts(IDENTITY).map(|v| v[i].clone()).unwrap_or_default(),
                    made_by: String::new(),
                    ..SummaryRow::failed(0, &ids[i], &parameters, &messages[i])
                };
                row.read_outcome(|name, kind| match (self.column(name).map(|c| &c.data), kind) {
                    // Tables written before CPU time have none.
                    (None, _) if name == CPU_TIME => Ok(None),
                    (Some(ColumnData::Int(counts)), OutcomeKind::Int) => Ok(Some(OutcomeValue::Int(counts[i] as u64))),
                    (Some(data), OutcomeKind::Float) => data.number(i).map(|x| Some(OutcomeValue::Float(x))).ok_or(()),
                    _ => Err(()),
                })
                .ok()?;
                Some((row, usize::try_from(warnings[i]).ok()?))
            })
            .collect()
    }

    /// Row `i`'s stage end times, from the `stage_end_time.NAME` columns (NaN: the run ended first,
    /// or, in a table of several protocols, it has no such stage).
    fn stage_ends(&self, i: usize) -> Vec<(String, f64)> {
        let prefix = format!("{}.", quantity::STAGE_END_TIME.name);
        let stage = |c: &Column| Some((c.name.strip_prefix(&prefix)?.to_string(), c.data.number(i)?));
        self.columns.iter().filter_map(stage).collect()
    }

    /// The same table without the timing columns (for comparing runs made at different times):
    /// those named in [`TIMING_COLUMNS`] and their statistics (`wall_time_mean`, …).
    pub fn without_timing(&self) -> Self {
        let timing = |name: &str| {
            TIMING_COLUMNS
                .iter()
                .any(|t| name.strip_prefix(t).is_some_and(|rest| rest.is_empty() || rest.starts_with('_')))
        };
        let columns = self.columns.iter().filter(|c| !timing(&c.name)).cloned().collect();
        Self { columns }
    }
}

/// The column of outcome `k` of the rows: integers or floats, as every row's outcome `k` is.
fn outcome_column(rows: &[&SummaryRow], k: usize) -> ColumnData {
    let values = rows.iter().map(|r| r.outcome()[k]);
    match SummaryRow::failed(0, "", &[], "").outcome()[k] {
        OutcomeValue::Int(_) => ColumnData::Int(values.map(OutcomeValue::as_i64).collect()),
        OutcomeValue::Float(_) => ColumnData::Float(values.map(OutcomeValue::as_f64).collect()),
    }
}

fn column(name: &str, data: ColumnData) -> Column {
    Column { name: name.to_string(), data }
}

/// One column per protocol stage (first-appearance order): its end time, NaN where a run has no such stage.
fn stage_end_columns(rows: &[&SummaryRow]) -> Vec<Column> {
    let mut names: Vec<&str> = Vec::new();
    for (name, _) in rows.iter().flat_map(|r| &r.stage_ends) {
        if !names.contains(&name.as_str()) {
            names.push(name);
        }
    }
    let time = |r: &SummaryRow, name: &str| r.stage_ends.iter().find(|(n, _)| n == name).map_or(f64::NAN, |(_, t)| *t);
    let end_times = |name: &str| ColumnData::Float(rows.iter().map(|r| time(r, name)).collect());
    names.iter().map(|name| column(&quantity::stage_end_column(name), end_times(name))).collect()
}

/// One column per swept key path (first-appearance order), typed by its values.
fn parameter_columns(rows: &[&SummaryRow]) -> Vec<Column> {
    let mut keys: Vec<&str> = Vec::new();
    for row in rows {
        for (key, _) in &row.parameters {
            if !keys.contains(&key.as_str()) {
                keys.push(key);
            }
        }
    }
    keys.iter()
        .map(|key| {
            let values: Vec<Option<&ParamValue>> =
                rows.iter().map(|r| r.parameters.iter().find(|(k, _)| k == key).map(|(_, v)| v)).collect();
            column(key, parameter_data(&values))
        })
        .collect()
}

/// Typed values of one parameter: its own type when every row has the same one, floats when all are
/// numbers (NaN where missing), text otherwise.
fn parameter_data(values: &[Option<&ParamValue>]) -> ColumnData {
    let all = |f: fn(&ParamValue) -> bool| values.iter().all(|v| v.is_some_and(f));
    if all(|v| matches!(v, ParamValue::Int(_))) {
        ColumnData::Int(values.iter().map(|v| if let Some(ParamValue::Int(i)) = v { *i } else { 0 }).collect())
    } else if all(|v| matches!(v, ParamValue::Bool(_))) {
        ColumnData::Bool(values.iter().map(|v| matches!(v, Some(ParamValue::Bool(true)))).collect())
    } else if values.iter().all(|v| matches!(v, None | Some(ParamValue::Int(_) | ParamValue::Float(_)))) {
        ColumnData::Float(values.iter().map(|v| v.map_or(f64::NAN, numeric)).collect())
    } else {
        ColumnData::Text(values.iter().map(|v| v.map(param_text).unwrap_or_default()).collect())
    }
}

fn numeric(v: &ParamValue) -> f64 {
    match v {
        ParamValue::Float(x) => *x,
        ParamValue::Int(i) => *i as f64,
        _ => f64::NAN,
    }
}

/// A parameter value as text (floats in shortest round-trip form).
pub fn param_text(v: &ParamValue) -> String {
    match v {
        ParamValue::Float(x) => format!("{x:?}"),
        ParamValue::Int(i) => i.to_string(),
        ParamValue::Bool(b) => b.to_string(),
        ParamValue::Text(s) => s.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_show_six_significant_digits() {
        let column = ColumnData::Float(vec![0.39639599999999997, 1234.56789, 2.5e-7, 0.0, f64::NAN, 3.0, 1.5e9]);
        let shown: Vec<String> = (0..7).map(|i| column.display(i)).collect();
        assert_eq!(shown, ["0.396396", "1234.57", "2.50000e-7", "0", "-", "3", "1.50000e9"]);
        assert_eq!(column.text(0), "0.39639599999999997", "the CSV keeps every digit");
        assert_eq!(column.text(4), "", "a missing value is an empty CSV cell");
    }

    #[test]
    fn a_negative_zero_is_written_as_zero() {
        let column = ColumnData::Float(vec![-0.0, -1e-300]);
        assert_eq!((column.text(0), column.text(1)), ("0.0".to_string(), "-1e-300".to_string()));
    }

    #[test]
    fn a_negative_zero_shows_as_zero() {
        assert_eq!(short_float(-0.0), "0");
        assert_eq!(significant(-0.0, 3), "0");
        assert_eq!(short_float(-2e-9), "-2.00000e-9", "a small negative value keeps its sign");
    }
}
