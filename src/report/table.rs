//! Tables of typed cells: numbers stay numbers from the code that makes them to the page and the
//! CSV file that show them, so that nothing reads a number back from its text.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::output::csv::Datatype;
use crate::study::ParamValue;

/// One cell: a whole number, a real number, a yes/no, text, or nothing.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Cell {
    /// A count or an id.
    Whole(i64),
    /// A measured or computed value.
    Number(f64),
    /// Yes or no.
    Flag(bool),
    /// Words.
    Text(String),
    /// No value.
    Empty,
}

impl Cell {
    /// The number `x`, or no value when it is not finite (JSON holds no NaN or infinity).
    pub fn number(x: f64) -> Self {
        if x.is_finite() { Cell::Number(x) } else { Cell::Empty }
    }

    /// The text `text`.
    pub fn text(text: impl Into<String>) -> Self {
        Cell::Text(text.into())
    }

    /// A swept or set value as a cell of its own type.
    pub fn of_param(value: &ParamValue) -> Self {
        match value {
            ParamValue::Float(x) => Cell::number(*x),
            ParamValue::Int(i) => Cell::Whole(*i),
            ParamValue::Bool(b) => Cell::Flag(*b),
            ParamValue::Text(s) => Cell::Text(s.clone()),
        }
    }

    /// The CSVW datatype of this cell; None for no value.
    fn datatype(&self) -> Option<Datatype> {
        match self {
            Cell::Whole(_) => Some(Datatype::Integer),
            Cell::Number(_) => Some(Datatype::Double),
            Cell::Flag(_) => Some(Datatype::Boolean),
            Cell::Text(_) => Some(Datatype::String),
            Cell::Empty => None,
        }
    }
}

/// As in a CSV file: a real number in the shortest text that reads back as the same number.
impl fmt::Display for Cell {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Cell::Whole(n) => write!(f, "{n}"),
            Cell::Number(x) => write!(f, "{x:?}"),
            Cell::Flag(b) => write!(f, "{b}"),
            Cell::Text(text) => f.write_str(text),
            Cell::Empty => Ok(()),
        }
    }
}

/// Named columns and rows of cells.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Table {
    /// The column names.
    pub columns: Vec<String>,
    /// The rows, each one cell per column.
    pub rows: Vec<Vec<Cell>>,
}

impl Table {
    /// The narrowest CSVW datatype of column `k`'s cells: whole numbers among real ones make it real;
    /// any other mixture, or no value at all, text.
    pub fn datatype(&self, k: usize) -> Datatype {
        let mut types = self.rows.iter().filter_map(|row| row.get(k)?.datatype());
        let Some(first) = types.next() else { return Datatype::String };
        types.fold(first, |a, b| match (a, b) {
            _ if a == b => a,
            (Datatype::Integer | Datatype::Double, Datatype::Integer | Datatype::Double) => Datatype::Double,
            _ => Datatype::String,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_keep_their_type_through_json_and_give_their_column_a_datatype() {
        let table = Table {
            columns: vec!["n".into(), "ratio".into(), "recommended".into(), "reason".into()],
            rows: vec![
                vec![Cell::Whole(3), Cell::Whole(1), Cell::Flag(true), Cell::text("0.5")],
                vec![Cell::Whole(4), Cell::number(0.25), Cell::Flag(false), Cell::Empty],
                vec![Cell::Empty, Cell::number(f64::NAN), Cell::Empty, Cell::text("too soft")],
            ],
        };
        let back: Table = serde_json::from_str(&serde_json::to_string(&table).unwrap()).unwrap();
        assert_eq!(back, table, "a whole number, a real one, a flag, text that looks like a number");
        let types: Vec<Datatype> = (0..5).map(|k| table.datatype(k)).collect();
        assert_eq!(types, [Datatype::Integer, Datatype::Double, Datatype::Boolean, Datatype::String, Datatype::String]);
        let text: Vec<String> = table.rows[1].iter().map(ToString::to_string).collect();
        assert_eq!(text, ["4", "0.25", "false", ""]);
        assert_eq!(Cell::number(1.0).to_string(), "1.0", "a real number reads as one");
    }
}
