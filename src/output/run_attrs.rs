//! A run group's description of its run: attributes (identity, how it ended, what made it, its scene)
//! and three small typed tables (per-run values, swept parameters, validity warnings).
//!
//! ```text
//! attributes   index (int64), id, status, message, identity (`crate::study::RunIdentity`, the
//!              group's name), demsweep_version (of the program that made the run),
//!              results_format (int64, [`RESULTS_FORMAT`]), scene.json (the complete scene)
//! values       compound, one row: each per-run quantity by name ([`OUTCOME`], then the final
//!              values and pile metrics), float64 (NaN when missing) or int64 (steps,
//!              particle_steps); attribute `units` (field order)
//! parameters   compound, one row: each swept key path, typed (float64, int64, uint8 0/1, text);
//!              attribute `units` (field order, the keys' SI units); absent when nothing is swept
//! stage_end_times  compound, one row: when each stage of the scene's protocol ended, float64 (s,
//!              NaN where the run ended first), by stage name in order; attribute `units`;
//!              absent for a scene without stages
//! warnings     compound, one row per validity warning: kind (text, e.g. `energy_balance`), value,
//!              limit, time, impact_speed, safe_time_step (NaN where the warning has none; see
//!              [`ValidityWarning`]); absent when the run has none
//! ```
//!
//! Eight attributes at most keep them in the group's object header: with more, hdf5-pure stores
//! them in a fractal heap, and a file holding such an object can never be proven free of object
//! references, so every commit walks the whole file to repoint references (a commit cost growing
//! with the file). The tables are chunked with a Fletcher-32 checksum, like every dataset of a run.
//! Older layouts: results format 2 (no `results_format` attribute) kept the row as JSON text in an
//! attribute `row`; format 1 had one attribute per value. [`row_from_group`] reads all three.

use std::collections::HashMap;

use hdf5_pure::{AttrValue, Group, StagedGroup};
use serde_json::Value;

use super::compound::{self, Field};
use super::layout_error::LayoutError;
use super::row::{CPU_TIME, DEMSWEEP_VERSION, OutcomeKind, OutcomeValue, PARTICLE_STEPS, SummaryRow};
use super::table::ColumnData;
use crate::physics::SceneConfig;
use crate::physics::quantity::{self, FINAL_VALUE_COUNT, OUTCOME};
use crate::physics::record::RunStatus;
use crate::physics::warning::{ValidityWarning, WarningKind};
use crate::study::ParamValue;

/// The layout of the run groups this program writes: 3 since per-run values are typed tables
/// (2: a JSON `row` attribute; 1: one attribute per value).
pub const RESULTS_FORMAT: i64 = 3;

const INDEX: &str = "index";
const ID: &str = "id";
const STATUS: &str = "status";
const MESSAGE: &str = "message";
const ROW: &str = "row";
const IDENTITY: &str = "identity";
/// Attribute of a run group: the demsweep version that made the run (absent before format 3).
pub const MADE_BY: &str = "demsweep_version";
/// Attribute of a run group: its results format ([`RESULTS_FORMAT`]; absent before format 3).
pub const FORMAT: &str = "results_format";
/// Attribute of a run group: its complete scene, as JSON.
pub const SCENE_JSON: &str = "scene.json";
const PARAMETERS: &str = "parameters";
const WARNINGS: &str = "warnings";
const STAGE_END_TIMES: &str = "stage_end_times";
/// The per-run values table of a run group.
pub const VALUES: &str = "values";
/// The fields of the warnings table after `kind`.
const WARNING_FIELDS: [&str; 5] = ["value", "limit", "time", "impact_speed", "safe_time_step"];

/// The attributes of a run group (see the module documentation).
pub fn run_attrs(row: &SummaryRow, scene: &SceneConfig) -> Vec<(&'static str, AttrValue)> {
    vec![
        (INDEX, AttrValue::I64(row.index as i64)),
        (ID, AttrValue::String(row.id.clone())),
        (STATUS, AttrValue::String(row.status.as_str().to_string())),
        (MESSAGE, AttrValue::String(row.message.clone())),
        (IDENTITY, AttrValue::String(row.identity.clone())),
        (MADE_BY, AttrValue::String(DEMSWEEP_VERSION.to_string())),
        (FORMAT, AttrValue::I64(RESULTS_FORMAT)),
        (SCENE_JSON, AttrValue::String(serde_json::to_string(scene).unwrap_or_default())),
    ]
}

/// A value of the one-row tables.
enum Cell {
    Float(f64),
    Int(i64),
    Bool(bool),
    Text(String),
}

impl Cell {
    fn field(&self) -> Field<'_> {
        match self {
            Cell::Float(x) => Field::F64(std::slice::from_ref(x)),
            Cell::Int(i) => Field::I64(std::slice::from_ref(i)),
            Cell::Bool(b) => Field::Bool(std::slice::from_ref(b)),
            Cell::Text(t) => Field::Text(std::slice::from_ref(t)),
        }
    }
}

/// Stages the tables `values`, `parameters` and `warnings` of a run's row in its group `g`.
pub fn stage_tables(g: &mut StagedGroup<'_>, row: &SummaryRow) {
    let outcome = OUTCOME.iter().zip(row.outcome()).map(|(q, v)| match v {
        OutcomeValue::Float(x) => (q.name, Cell::Float(x)),
        OutcomeValue::Int(i) => (q.name, Cell::Int(i as i64)),
    });
    let finals = quantity::final_value_declarations().zip(row.final_values).map(|(q, x)| (q.name, Cell::Float(x)));
    let values: Vec<(&str, Cell)> = outcome.chain(finals).collect();
    g.create_dataset(VALUES, |b| {
        compound::stage(b, &values.iter().map(|(n, c)| (*n, c.field())).collect::<Vec<_>>());
        b.set_attr(super::layout::UNITS, values_units());
    });
    let parameters: Vec<(&str, Cell)> = row
        .parameters
        .iter()
        .map(|(key, value)| {
            let cell = match value {
                ParamValue::Float(x) => Cell::Float(*x),
                ParamValue::Int(i) => Cell::Int(*i),
                ParamValue::Bool(b) => Cell::Bool(*b),
                ParamValue::Text(t) => Cell::Text(t.clone()),
            };
            (key.as_str(), cell)
        })
        .collect();
    if !parameters.is_empty() {
        g.create_dataset(PARAMETERS, |b| {
            compound::stage(b, &parameters.iter().map(|(n, c)| (*n, c.field())).collect::<Vec<_>>());
            let units = parameters.iter().map(|(key, _)| quantity::unit(key).unwrap_or_default().to_string());
            b.set_attr(super::layout::UNITS, AttrValue::StringArray(units.collect()));
        });
    }
    if !row.stage_ends.is_empty() {
        let ends: Vec<(&str, Cell)> = row.stage_ends.iter().map(|(name, t)| (name.as_str(), Cell::Float(*t))).collect();
        g.create_dataset(STAGE_END_TIMES, |b| {
            compound::stage(b, &ends.iter().map(|(n, c)| (*n, c.field())).collect::<Vec<_>>());
            let unit = quantity::STAGE_END_TIME.unit.to_string();
            b.set_attr(super::layout::UNITS, AttrValue::StringArray(vec![unit; ends.len()]));
        });
    }
    if !row.warnings.is_empty() {
        let kinds: Vec<String> = row.warnings.iter().map(|w| kind_name(w.kind)).collect();
        let nan = |x: Option<f64>| x.unwrap_or(f64::NAN);
        let columns: [Vec<f64>; 5] = [
            row.warnings.iter().map(|w| w.value).collect(),
            row.warnings.iter().map(|w| w.limit).collect(),
            row.warnings.iter().map(|w| nan(w.time)).collect(),
            row.warnings.iter().map(|w| nan(w.impact_speed)).collect(),
            row.warnings.iter().map(|w| nan(w.safe_time_step)).collect(),
        ];
        let mut fields = vec![("kind", Field::Text(&kinds))];
        fields.extend(WARNING_FIELDS.iter().zip(&columns).map(|(name, v)| (*name, Field::F64(v))));
        g.create_dataset(WARNINGS, |b| compound::stage(b, &fields));
    }
}

/// The units of the `values` table's fields, in order.
fn values_units() -> AttrValue {
    let units = OUTCOME.iter().map(|q| q.unit).chain(quantity::final_value_declarations().map(|q| q.unit));
    AttrValue::StringArray(units.map(str::to_string).collect())
}

/// A warning kind's name in files (`energy_balance`).
fn kind_name(kind: WarningKind) -> String {
    serde_json::to_value(kind).ok().and_then(|v| v.as_str().map(str::to_string)).unwrap_or_default()
}

/// Reads a summary row back from a run group (any results format); the error names what is missing
/// or damaged. `limit` bounds what a table may declare (see `compound::read_limit`).
pub fn row_from_group(group: &Group, limit: u64) -> Result<SummaryRow, LayoutError> {
    let attrs = group.attrs()?;
    let mut row = row_header(&attrs)?;
    if attrs.contains_key(FORMAT) {
        let table = |name: &str| -> Result<Option<HashMap<String, ColumnData>>, LayoutError> {
            if !group.datasets()?.iter().any(|d| d == name) {
                return Ok(None);
            }
            let decoded = group.dataset(name).map_err(LayoutError::from).and_then(|d| compound::decode(&d, limit));
            Ok(Some(decoded.map_err(|e| e.within(format!("`{name}`")))?.into_iter().collect()))
        };
        let values = table(VALUES)?.ok_or(LayoutError::missing(format!("`{VALUES}` table")))?;
        fill_values(&mut row, &values).map_err(|e| e.within(format!("`{VALUES}`")))?;
        row.parameters = match group.dataset(PARAMETERS) {
            Ok(dataset) => {
                let columns = compound::decode(&dataset, limit).map_err(|e| e.within(format!("`{PARAMETERS}`")))?;
                columns.into_iter().filter_map(|(key, column)| Some((key, column.param(0)?))).collect()
            }
            Err(_) => Vec::new(),
        };
        row.stage_ends = match group.dataset(STAGE_END_TIMES) {
            Ok(dataset) => {
                let columns =
                    compound::decode(&dataset, limit).map_err(|e| e.within(format!("`{STAGE_END_TIMES}`")))?;
                columns.into_iter().map(|(name, column)| (name, first_number(&column))).collect()
            }
            Err(_) => Vec::new(),
        };
        row.warnings = table(WARNINGS)?.map_or(Ok(Vec::new()), |t| warnings(&t))?;
        return Ok(row);
    }
    match attrs.get(ROW) {
        Some(json) => {
            let json = json.as_str().ok_or(LayoutError::not_a(format!("`{ROW}`"), "text"))?;
            let value: Value = serde_json::from_str(json)
                .map_err(|e| LayoutError::inconsistent(format!("`{ROW}` is not JSON: {e}")))?;
            fill_from_json(&mut row, &value).map_err(|e| e.within(format!("`{ROW}`")))?;
        }
        None => legacy::fill_from_attrs(&mut row, &attrs)?,
    }
    Ok(row)
}

/// A one-row table column's number; NaN when it has none.
fn first_number(column: &ColumnData) -> f64 {
    if column.is_empty() { f64::NAN } else { column.number(0).unwrap_or(f64::NAN) }
}

/// The row's index, id, status, message and identity from a run group's attributes.
fn row_header(attrs: &HashMap<String, AttrValue>) -> Result<SummaryRow, LayoutError> {
    let get = |name: &str| attrs.get(name).ok_or(LayoutError::missing(format!("`{name}` attribute")));
    let text = |name: &str| {
        get(name).and_then(|v| v.as_str().map(str::to_string).ok_or(LayoutError::not_a(format!("`{name}`"), "text")))
    };
    let index = get(INDEX).and_then(|v| v.as_i64().ok_or(LayoutError::not_a(format!("`{INDEX}`"), "an integer")))?;
    let index = index as usize;
    let status = text(STATUS)?;
    let status = RunStatus::parse(&status)
        .ok_or_else(|| LayoutError::inconsistent(format!("`{STATUS}` is `{status}`, not a run status")))?;
    let mut row = SummaryRow::failed(index, &text(ID)?, &[], &text(MESSAGE)?);
    row.status = status;
    row.identity = attrs.get(IDENTITY).and_then(AttrValue::as_str).unwrap_or_default().to_string();
    row.made_by = attrs.get(MADE_BY).and_then(AttrValue::as_str).unwrap_or_default().to_string();
    Ok(row)
}

/// The quantities of a row from its `values` table (a quantity the file predates reads as missing).
fn fill_values(row: &mut SummaryRow, values: &HashMap<String, ColumnData>) -> Result<(), LayoutError> {
    let number = |name: &str| -> Result<f64, LayoutError> {
        match values.get(name) {
            None => Ok(f64::NAN),
            Some(column) if column.len() == 1 => {
                column.number(0).ok_or(LayoutError::not_a(format!("`{name}`"), "a number"))
            }
            Some(_) => Err(LayoutError::inconsistent(format!("`{name}` does not hold one value"))),
        }
    };
    row.read_outcome(|name, _| number(name).map(|x| Some(OutcomeValue::Float(x))))?;
    for (slot, declared) in row.final_values.iter_mut().zip(quantity::final_value_declarations()) {
        *slot = number(declared.name)?;
    }
    Ok(())
}

/// The warnings of a `warnings` table.
fn warnings(table: &HashMap<String, ColumnData>) -> Result<Vec<ValidityWarning>, LayoutError> {
    let within = |e: LayoutError| e.within(format!("`{WARNINGS}`"));
    let Some(ColumnData::Text(kinds)) = table.get("kind") else {
        return Err(within(LayoutError::missing("text field `kind`")));
    };
    let column = |name: &str| match table.get(name) {
        Some(ColumnData::Float(v)) if v.len() == kinds.len() => Ok(v),
        _ => Err(within(LayoutError::missing(format!("float field `{name}` of {} rows", kinds.len())))),
    };
    let [value, limit, time, impact_speed, safe_time_step] = WARNING_FIELDS.map(column);
    let (value, limit, time, impact_speed, safe_time_step) = (value?, limit?, time?, impact_speed?, safe_time_step?);
    let some = |x: f64| (!x.is_nan()).then_some(x);
    kinds
        .iter()
        .enumerate()
        .map(|(i, kind)| {
            let kind: WarningKind = serde_json::from_value(Value::String(kind.clone()))
                .map_err(|_| within(LayoutError::not_a(format!("`{kind}`"), "a warning kind")))?;
            Ok(ValidityWarning {
                time: some(time[i]),
                impact_speed: some(impact_speed[i]),
                safe_time_step: some(safe_time_step[i]),
                ..ValidityWarning::new(kind, value[i], limit[i])
            })
        })
        .collect()
}

/// A float of a format-2 `row`: a number, null when missing (NaN), `"inf"` / `"-inf"` when infinite.
fn json_float(value: &Value) -> Option<f64> {
    match value {
        Value::Null => Some(f64::NAN),
        Value::String(text) => text.parse().ok().filter(|x: &f64| x.is_infinite()),
        other => other.as_f64(),
    }
}

fn json_param(value: &Value) -> Option<ParamValue> {
    match value {
        Value::Bool(b) => Some(ParamValue::Bool(*b)),
        Value::Number(n) if n.is_i64() => n.as_i64().map(ParamValue::Int),
        Value::String(s) => Some(ParamValue::Text(s.clone())),
        other => json_float(other).map(ParamValue::Float),
    }
}

/// The parameters, warnings and quantities of a row from its `row` attribute (a quantity the file
/// predates reads as missing).
fn fill_from_json(row: &mut SummaryRow, value: &Value) -> Result<(), LayoutError> {
    let get = |name: &str| value.get(name).ok_or(LayoutError::missing(format!("`{name}`")));
    let not_a = |name: &str, expected| LayoutError::not_a(format!("`{name}`"), expected);
    let float = |name: &str| get(name).and_then(|v| json_float(v).ok_or(not_a(name, "a number")));
    let int = |name: &str| get(name).and_then(|v| v.as_u64().ok_or(not_a(name, "a whole number")));
    let pairs = get(PARAMETERS)?.as_array().ok_or(not_a(PARAMETERS, "a list"))?;
    row.parameters = pairs
        .iter()
        .map(|pair| match pair.as_array().map(Vec::as_slice) {
            Some([Value::String(key), value]) => {
                json_param(value).map(|v| (key.clone(), v)).ok_or(not_a(key, "a supported value"))
            }
            _ => Err(LayoutError::not_a("a parameter", "a [key, value] pair")),
        })
        .collect::<Result<_, _>>()?;
    let warnings = get(WARNINGS)?.as_array().ok_or(not_a(WARNINGS, "a list"))?;
    // Files written before warnings were typed hold texts: those are not read back (the count in
    // `/summary` stays).
    row.warnings = warnings.iter().filter_map(|w| serde_json::from_value(w.clone()).ok()).collect();
    row.read_outcome(|name, kind| match (value.get(name), kind) {
        // Files written before CPU time have none.
        (None, _) if name == CPU_TIME => Ok(None),
        (_, OutcomeKind::Float) => float(name).map(|x| Some(OutcomeValue::Float(x))),
        (_, OutcomeKind::Int) => int(name).map(|i| Some(OutcomeValue::Int(i))),
    })?;
    let mut final_values = [f64::NAN; FINAL_VALUE_COUNT];
    for (slot, declared) in final_values.iter_mut().zip(quantity::final_value_declarations()) {
        if value.get(declared.name).is_some() {
            *slot = float(declared.name)?;
        }
    }
    row.final_values = final_values;
    Ok(())
}

/// Files written before the `row` attribute: one attribute per value.
mod legacy {
    use super::*;

    /// The parameters (listed in `parameters`, each under its key path) and quantities of a
    /// row from one attribute each (a final value the file predates reads as missing).
    pub(super) fn fill_from_attrs(row: &mut SummaryRow, attrs: &HashMap<String, AttrValue>) -> Result<(), LayoutError> {
        let get = |name: &str| attrs.get(name).ok_or(LayoutError::missing(format!("`{name}` attribute")));
        let not_a = |name: &str, expected| LayoutError::not_a(format!("`{name}`"), expected);
        let float = |name: &str| get(name).and_then(|v| v.as_f64().ok_or(not_a(name, "a float")));
        let int = |name: &str| get(name).and_then(|v| v.as_i64().ok_or(not_a(name, "an integer")));
        let keys = attrs.get(PARAMETERS).and_then(AttrValue::as_strings).unwrap_or(&[]);
        row.parameters = keys
            .iter()
            .map(|k| get(k).and_then(|v| attr_param(v).ok_or(not_a(k, "of a supported type"))).map(|v| (k.clone(), v)))
            .collect::<Result<Vec<_>, _>>()?;
        for (slot, declared) in row.final_values.iter_mut().zip(quantity::final_value_declarations()) {
            if attrs.contains_key(declared.name) {
                *slot = float(declared.name)?;
            }
        }
        // Files written before CPU time or particle steps have none: the latter are the steps times
        // the disks.
        row.read_outcome(|name, kind| match (attrs.get(name), kind) {
            (None, _) if name == CPU_TIME || name == PARTICLE_STEPS => Ok(None),
            (_, OutcomeKind::Float) => float(name).map(|x| Some(OutcomeValue::Float(x))),
            (_, OutcomeKind::Int) => int(name).map(|i| Some(OutcomeValue::Int(i as u64))),
        })?;
        if !attrs.contains_key(PARTICLE_STEPS) {
            row.particle_steps = row.steps * attrs.get("scene.count").and_then(AttrValue::as_i64).unwrap_or(0) as u64;
        }
        Ok(())
    }

    fn attr_param(v: &AttrValue) -> Option<ParamValue> {
        match v {
            AttrValue::U8(b) => Some(ParamValue::Bool(*b != 0)),
            AttrValue::F64(x) => Some(ParamValue::Float(*x)),
            other => {
                other.as_i64().map(ParamValue::Int).or_else(|| other.as_str().map(|s| ParamValue::Text(s.to_string())))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use serde_json::{Map, json};

    use super::*;

    fn row() -> SummaryRow {
        let parameters = [
            ("material.friction".to_string(), ParamValue::Float(0.1 + 0.2)),
            ("particles.count".to_string(), ParamValue::Int(300)),
            ("contact.allow_tension".to_string(), ParamValue::Bool(true)),
            ("label".to_string(), ParamValue::Text("case \"1\", μ".into())),
        ];
        let mut row = SummaryRow::failed(7, "r0007", &parameters, "");
        row.status = RunStatus::Diverged;
        row.warnings = vec![
            ValidityWarning::new(WarningKind::ImpactOverlap, 0.2, 0.1),
            ValidityWarning { time: Some(0.25), ..ValidityWarning::new(WarningKind::EnergyBalance, 0.02, 0.01) },
        ];
        (row.settle_time, row.steps, row.particle_steps) = (Some(1.0 / 3.0), 12, 3600);
        (row.simulated_time, row.wall_time, row.cpu_time) = (0.25, 1e-300, 0.125);
        row.final_values[0] = f64::INFINITY;
        row.final_values[1] = -f64::INFINITY;
        row.final_values[2] = 5e-324;
        row.identity = "0123456789abcdef-0000000000000007-p1".into();
        row
    }

    /// Writes a file with one group `run` staged by `stage`, and reads its row back.
    fn written(name: &str, stage: impl FnOnce(&mut StagedGroup<'_>)) -> Result<SummaryRow, LayoutError> {
        let path = std::env::temp_dir().join(format!("demsweep-run-attrs-{name}-{}.h5", std::process::id()));
        hdf5_pure::FileBuilder::new().write(&path).unwrap();
        let file = hdf5_pure::File::open_rw(&path).unwrap();
        file.root().create_group_with("run", stage).unwrap();
        file.commit().unwrap();
        file.close().unwrap();
        let file = hdf5_pure::File::open(&path).unwrap();
        let row = row_from_group(&file.group("run").unwrap(), compound::read_limit(&path));
        std::fs::remove_file(&path).unwrap();
        row
    }

    fn set_attrs(g: &mut StagedGroup<'_>, attrs: Vec<(&'static str, AttrValue)>) {
        for (name, value) in attrs {
            g.set_attr(name, value);
        }
    }

    fn without_finals(r: SummaryRow) -> SummaryRow {
        SummaryRow { final_values: [0.0; FINAL_VALUE_COUNT], ..r }
    }

    #[test]
    fn a_row_reads_back_bit_for_bit_from_eight_attributes_and_typed_tables() {
        let row = row();
        let attrs = run_attrs(&row, &SceneConfig::default());
        assert!(attrs.len() <= 8, "{} attributes: more go to a fractal heap", attrs.len());
        let back = written("typed", |g| {
            set_attrs(g, attrs);
            stage_tables(g, &row);
        })
        .unwrap();
        assert_eq!(back.parameters, row.parameters);
        assert_eq!(back.final_values.map(f64::to_bits), row.final_values.map(f64::to_bits), "NaN and ±inf too");
        assert_eq!(back.made_by, DEMSWEEP_VERSION);
        assert_eq!(without_finals(back), without_finals(row));
    }

    /// The `row` attribute of results format 2.
    fn row_json(row: &SummaryRow) -> Value {
        let mut map = Map::new();
        let parameters = row.parameters.iter().map(|(k, v)| json!([k, param_json(v)])).collect();
        map.insert(PARAMETERS.into(), Value::Array(parameters));
        map.insert(WARNINGS.into(), json!(row.warnings));
        for (q, value) in OUTCOME.iter().zip(row.outcome()) {
            let value = match value {
                OutcomeValue::Float(x) => float_json(x),
                OutcomeValue::Int(i) => json!(i),
            };
            map.insert(q.name.into(), value);
        }
        for (q, value) in quantity::final_value_declarations().zip(row.final_values) {
            map.insert(q.name.into(), float_json(value));
        }
        Value::Object(map)
    }

    /// A float in JSON: a number, null when missing (NaN), `"inf"` / `"-inf"` when infinite.
    fn float_json(x: f64) -> Value {
        match x {
            x if x.is_finite() => json!(x),
            x if x.is_nan() => Value::Null,
            x if x > 0.0 => json!("inf"),
            _ => json!("-inf"),
        }
    }

    fn param_json(v: &ParamValue) -> Value {
        match v {
            ParamValue::Float(x) => float_json(*x),
            ParamValue::Int(i) => json!(i),
            ParamValue::Bool(b) => json!(b),
            ParamValue::Text(s) => json!(s),
        }
    }

    /// The attributes of a run group of results format 2.
    fn format2_attrs(row: &SummaryRow, json: String) -> Vec<(&'static str, AttrValue)> {
        vec![
            (INDEX, AttrValue::I64(row.index as i64)),
            (ID, AttrValue::String(row.id.clone())),
            (STATUS, AttrValue::String(row.status.as_str().to_string())),
            (MESSAGE, AttrValue::String(row.message.clone())),
            (ROW, AttrValue::String(json)),
            (IDENTITY, AttrValue::String(row.identity.clone())),
        ]
    }

    #[test]
    fn a_row_of_results_format_2_reads_back() {
        let row = row();
        let attrs = format2_attrs(&row, row_json(&row).to_string());
        let back = written("format2", |g| set_attrs(g, attrs)).unwrap();
        assert_eq!(back.final_values.map(f64::to_bits), row.final_values.map(f64::to_bits));
        assert_eq!(back.made_by, "", "format 2 does not say which version made the run");
        assert_eq!(without_finals(back), without_finals(SummaryRow { made_by: String::new(), ..row }));
    }

    #[test]
    fn a_damaged_row_attribute_is_named() {
        let attrs = format2_attrs(&row(), "{\"parameters\": []".into());
        let refused = written("damaged", |g| set_attrs(g, attrs)).unwrap_err().to_string();
        assert!(refused.starts_with("`row` is not JSON"), "{refused}");
    }
}
