//! The attributes of a run group: its summary row, identity and scene, in at most eight attributes.
//!
//! ```text
//! index, id, status, message   the run's identity and how it ended (int64, strings)
//! row                          JSON: {"parameters": [[key path, value], …] in axis order,
//!                              "warnings": [{kind, value, limit, time, …}, …] (typed: see
//!                              [`ValidityWarning`]), then each per-run quantity by name
//!                              (settle_time, steps, …, pile metrics); a missing value is null,
//!                              an infinite one "inf" / "-inf"}
//! identity                     what the run's results depend on (`crate::study::RunIdentity`), the
//!                              group's name; absent in files written before identities
//! scene.json                   the complete scene
//! ```
//!
//! Eight attributes at most keep them in the group's object header: with more, hdf5-pure stores
//! them in a fractal heap, and a file holding such an object can never be proven free of object
//! references, so every commit walks the whole file to repoint references (a commit cost growing
//! with the file). Files written before this layout have one attribute per value; [`row_from_attrs`]
//! reads both.

use std::collections::HashMap;

use hdf5_pure::AttrValue;
use serde_json::{Map, Value, json};

use super::row::{OutcomeValue, SummaryRow};
use crate::physics::SceneConfig;
use crate::physics::quantity::{self, FINAL_VALUE_COUNT, OUTCOME};
use crate::physics::record::RunStatus;
use crate::study::ParamValue;

const INDEX: &str = "index";
const ID: &str = "id";
const STATUS: &str = "status";
const MESSAGE: &str = "message";
const ROW: &str = "row";
const IDENTITY: &str = "identity";
const SCENE_JSON: &str = "scene.json";
const PARAMETERS: &str = "parameters";
const WARNINGS: &str = "warnings";

/// The attributes of a run group (see the module documentation).
pub fn run_attrs(row: &SummaryRow, scene: &SceneConfig) -> Vec<(&'static str, AttrValue)> {
    vec![
        (INDEX, AttrValue::I64(row.index as i64)),
        (ID, AttrValue::String(row.id.clone())),
        (STATUS, AttrValue::String(row.status.as_str().to_string())),
        (MESSAGE, AttrValue::String(row.message.clone())),
        (ROW, AttrValue::String(row_json(row).to_string())),
        (IDENTITY, AttrValue::String(row.identity.clone())),
        (SCENE_JSON, AttrValue::String(serde_json::to_string(scene).unwrap_or_default())),
    ]
}

/// The `row` attribute: parameters, warnings and per-run quantities.
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

/// A float back from [`float_json`]; `None` for anything else.
fn json_float(value: &Value) -> Option<f64> {
    match value {
        Value::Null => Some(f64::NAN),
        Value::String(text) => text.parse().ok().filter(|x: &f64| x.is_infinite()),
        other => other.as_f64(),
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

fn json_param(value: &Value) -> Option<ParamValue> {
    match value {
        Value::Bool(b) => Some(ParamValue::Bool(*b)),
        Value::Number(n) if n.is_i64() => n.as_i64().map(ParamValue::Int),
        Value::String(s) => Some(ParamValue::Text(s.clone())),
        other => json_float(other).map(ParamValue::Float),
    }
}

/// Reads a summary row back from a run group's attributes (either layout); the error names what is
/// missing.
pub fn row_from_attrs(attrs: &HashMap<String, AttrValue>) -> Result<SummaryRow, String> {
    let get = |name: &str| attrs.get(name).ok_or(format!("no `{name}` attribute"));
    let text =
        |name: &str| get(name).and_then(|v| v.as_str().map(str::to_string).ok_or(format!("`{name}` is not text")));
    let index = get(INDEX).and_then(|v| v.as_i64().ok_or(format!("`{INDEX}` is not an integer")))? as usize;
    let status = text(STATUS)?;
    let status = RunStatus::parse(&status).ok_or(format!("`{STATUS}` is `{status}`, not a run status"))?;
    let mut row = SummaryRow::failed(index, &text(ID)?, &[], &text(MESSAGE)?);
    row.status = status;
    row.identity = attrs.get(IDENTITY).and_then(AttrValue::as_str).unwrap_or_default().to_string();
    match attrs.get(ROW) {
        Some(json) => {
            let json = json.as_str().ok_or(format!("`{ROW}` is not text"))?;
            let value: Value = serde_json::from_str(json).map_err(|e| format!("`{ROW}` is not JSON: {e}"))?;
            fill_from_json(&mut row, &value).map_err(|what| format!("`{ROW}`: {what}"))?;
        }
        None => legacy::fill_from_attrs(&mut row, attrs)?,
    }
    Ok(row)
}

/// The parameters, warnings and quantities of a row from its `row` attribute (a quantity the file
/// predates reads as missing).
fn fill_from_json(row: &mut SummaryRow, value: &Value) -> Result<(), String> {
    let get = |name: &str| value.get(name).ok_or(format!("no `{name}`"));
    let float = |name: &str| get(name).and_then(|v| json_float(v).ok_or(format!("`{name}` is not a number")));
    let int = |name: &str| get(name).and_then(|v| v.as_u64().ok_or(format!("`{name}` is not a whole number")));
    let pairs = get(PARAMETERS)?.as_array().ok_or("`parameters` is not a list")?;
    row.parameters = pairs
        .iter()
        .map(|pair| match pair.as_array().map(Vec::as_slice) {
            Some([Value::String(key), value]) => {
                json_param(value).map(|v| (key.clone(), v)).ok_or(format!("`{key}` has an unsupported value"))
            }
            _ => Err("a parameter is not a [key, value] pair".to_string()),
        })
        .collect::<Result<_, _>>()?;
    let warnings = get(WARNINGS)?.as_array().ok_or("`warnings` is not a list")?;
    // Files written before warnings were typed hold texts: those are not read back (the count in
    // `/summary` stays).
    row.warnings = warnings.iter().filter_map(|w| serde_json::from_value(w.clone()).ok()).collect();
    let [settle_time, steps, particle_steps, simulated_time, wall_time, cpu_time] = OUTCOME.map(|q| q.name);
    let settle = float(settle_time)?;
    row.settle_time = (!settle.is_nan()).then_some(settle);
    (row.steps, row.particle_steps) = (int(steps)?, int(particle_steps)?);
    (row.simulated_time, row.wall_time) = (float(simulated_time)?, float(wall_time)?);
    // Files written before CPU time have none.
    row.cpu_time = if value.get(cpu_time).is_some() { float(cpu_time)? } else { f64::NAN };
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
    pub(super) fn fill_from_attrs(row: &mut SummaryRow, attrs: &HashMap<String, AttrValue>) -> Result<(), String> {
        let get = |name: &str| attrs.get(name).ok_or(format!("no `{name}` attribute"));
        let float = |name: &str| get(name).and_then(|v| v.as_f64().ok_or(format!("`{name}` is not a float")));
        let int = |name: &str| get(name).and_then(|v| v.as_i64().ok_or(format!("`{name}` is not an integer")));
        let keys = attrs.get(PARAMETERS).and_then(AttrValue::as_strings).unwrap_or(&[]);
        row.parameters = keys
            .iter()
            .map(|k| {
                get(k)
                    .and_then(|v| attr_param(v).ok_or(format!("`{k}` has an unsupported type")))
                    .map(|v| (k.clone(), v))
            })
            .collect::<Result<Vec<_>, _>>()?;
        for (slot, declared) in row.final_values.iter_mut().zip(quantity::final_value_declarations()) {
            if attrs.contains_key(declared.name) {
                *slot = float(declared.name)?;
            }
        }
        let [settle_time, steps, particle_steps, simulated_time, wall_time, cpu_time] = OUTCOME.map(|q| q.name);
        row.steps = int(steps)? as u64;
        row.particle_steps = match attrs.get(particle_steps) {
            Some(_) => int(particle_steps)? as u64,
            None => row.steps * attrs.get("scene.count").and_then(AttrValue::as_i64).unwrap_or(0) as u64,
        };
        let settle = float(settle_time)?;
        row.settle_time = (!settle.is_nan()).then_some(settle);
        row.simulated_time = float(simulated_time)?;
        row.wall_time = float(wall_time)?;
        row.cpu_time = if attrs.contains_key(cpu_time) { float(cpu_time)? } else { f64::NAN };
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
    use super::*;
    use crate::physics::warning::{ValidityWarning, WarningKind};

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
        row
    }

    #[test]
    fn a_row_reads_back_bit_for_bit_from_at_most_eight_attributes() {
        let row = row();
        let attrs = run_attrs(&row, &SceneConfig::default());
        assert!(attrs.len() <= 8, "{} attributes: more go to a fractal heap", attrs.len());
        let attrs: HashMap<String, AttrValue> = attrs.into_iter().map(|(k, v)| (k.to_string(), v)).collect();
        let back = row_from_attrs(&attrs).unwrap();
        assert_eq!(back.parameters, row.parameters);
        assert_eq!(back.final_values.map(f64::to_bits), row.final_values.map(f64::to_bits), "NaN and ±inf too");
        let without_finals = |r: SummaryRow| SummaryRow { final_values: [0.0; FINAL_VALUE_COUNT], ..r };
        assert_eq!(without_finals(back), without_finals(row));
    }

    #[test]
    fn a_damaged_row_attribute_is_named() {
        let mut attrs: HashMap<String, AttrValue> =
            run_attrs(&row(), &SceneConfig::default()).into_iter().map(|(k, v)| (k.to_string(), v)).collect();
        attrs.insert(ROW.into(), AttrValue::String("{\"parameters\": []".into()));
        assert!(row_from_attrs(&attrs).unwrap_err().starts_with("`row` is not JSON"));
    }
}
