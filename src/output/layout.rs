//! Where things live in a results file, and how a run's summary row maps to run-group attributes.
//!
//! ```text
//! /                        root attributes: see `header`
//! /runs/b0000/r0007        one group per run (bucket `b<index / 100>`); attributes: summary row + scene
//!     history              compound table, one field per series, one row per sample
//!     final                compound table, one field per disk property (`DISK_FIELDS`: x, y, vx,
//!                          vy, omega, angle, r, contact_force), one row per disk (attrs `time`, `units`)
//!     final_contacts       compound table, one field per contact property, one row per contact
//!                          (attr `time`; see `CONTACT_FIELDS`), stored with `final`
//!     frames/<k>           the state table of recorded frame k (attribute `time`); k zero-padded to
//!                          `FRAME_DIGITS` digits (`00000`, `00001`, …), so names sort in time order
//!     frame_contacts/<k>   the contact table of frame k, stored with `frames`
//! /summary/<column>        one dataset per summary column (attribute `columns` on /summary, and
//!                          `jobs`, `wall_time` of the last sweep: see [`SWEEP_JOBS`])
//! ```

use std::collections::HashMap;

use hdf5_pure::AttrValue;

use super::compound::Field;
use super::row::{OutcomeValue, SummaryRow};
use crate::physics::SceneConfig;
use crate::physics::contact_network::ContactNetwork;
use crate::physics::material::{Elastic, Materials, restitution_from_beta};
use crate::physics::quantity::{self, FINAL_VALUE_COUNT, HISTORY_SERIES, OUTCOME, SeriesValues};
use crate::physics::record::{DISK_FIELDS, History, RunStatus, Snapshot};
use crate::study::ParamValue;

/// Runs per bucket group under `/runs`.
pub const BUCKET_SIZE: usize = 100;
/// The group holding the run buckets.
pub const RUNS: &str = "runs";
/// The group holding the summary columns.
pub const SUMMARY: &str = "summary";
/// The group holding the per-point statistics (one dataset per column, like `/summary`).
pub const POINTS: &str = "points";
/// Attribute of `/summary` and `/points` listing the column names in order.
pub const SUMMARY_COLUMNS: &str = "columns";
/// Attributes of `/summary` saying how the last sweep into the file ran: its worker threads and
/// its wall time (s) from start to finish.
pub const SWEEP_JOBS: &str = "jobs";
/// See [`SWEEP_JOBS`].
pub const SWEEP_WALL_TIME: &str = "wall_time";
/// The attributes of a `/summary` or `/points` column dataset: `unit` and `description` of the
/// per-run quantity it holds (or whose statistic it holds); none for other columns.
pub fn column_attrs(column: &str) -> Vec<(&'static str, AttrValue)> {
    quantity::column_quantity(column).map_or_else(Vec::new, |q| {
        vec![(UNIT, AttrValue::String(q.unit.into())), (DESCRIPTION, AttrValue::String(q.description.into()))]
    })
}

const UNIT: &str = "unit";
const DESCRIPTION: &str = "description";

/// The history table: one field per series of [`HISTORY_SERIES`], in its order.
pub fn history_table(h: &History) -> [(&'static str, Field<'_>); HISTORY_SERIES.len()] {
    HISTORY_SERIES.map(|series| {
        let field = match (series.quantity.value)(h) {
            SeriesValues::Real(v) => Field::F64(v),
            SeriesValues::Count(v) => Field::U32(v),
        };
        (series.quantity.name, field)
    })
}

/// Attribute of the `history` and state tables listing the unit of each field, in field order (empty
/// when dimensionless); each `/summary` dataset has attributes `unit` and `description`.
pub const UNITS: &str = "units";

/// The units of the history table's fields, in order.
pub fn history_units() -> AttrValue {
    AttrValue::StringArray(HISTORY_SERIES.iter().map(|s| s.quantity.unit.to_string()).collect())
}

/// The units of the state tables' fields ([`DISK_FIELDS`]), in order (attribute [`UNITS`]).
pub fn state_units() -> AttrValue {
    AttrValue::StringArray(DISK_FIELDS.iter().map(|f| f.unit.to_string()).collect())
}

/// The state table of a snapshot: one field per disk property of [`DISK_FIELDS`], in its order.
pub fn state_table(s: &Snapshot) -> [(&'static str, Field<'_>); DISK_FIELDS.len()] {
    DISK_FIELDS.map(|field| (field.name, Field::F64((field.values)(s))))
}

/// Contact fields: the fields of the `final_contacts` and `frame_contacts/<k>` tables (see
/// [`ContactNetwork`]): `first` disk index (`u32`), `second` disk index or wall `−1 − k` (`i64`; 0 floor,
/// 1 left, 2 right, 3 lid), unit normal from first to second, normal force (N, repulsive positive),
/// tangential force on `first` along `(−n_y, n_x)` (N), overlap (m), contact point (m), `sliding`
/// (`u8`: 1 when the tangential force sits on the Coulomb limit), and the contact's history: the
/// tangential spring (m) and the law's state (a number; the hysteretic law's largest overlap, m).
pub const CONTACT_FIELDS: [&str; 12] = [
    "first",
    "second",
    "normal_x",
    "normal_y",
    "normal_force",
    "tangential_force",
    "overlap",
    "point_x",
    "point_y",
    "sliding",
    "tangential_spring",
    "law_state",
];

/// The contact table of a network: one field per contact property, in the order of [`CONTACT_FIELDS`].
pub fn contact_table(c: &ContactNetwork) -> [(&'static str, Field<'_>); CONTACT_FIELDS.len()] {
    [
        ("first", Field::U32(&c.first)),
        ("second", Field::I64(&c.second)),
        ("normal_x", Field::F64(&c.normal_x)),
        ("normal_y", Field::F64(&c.normal_y)),
        ("normal_force", Field::F64(&c.normal_force)),
        ("tangential_force", Field::F64(&c.tangential_force)),
        ("overlap", Field::F64(&c.overlap)),
        ("point_x", Field::F64(&c.point_x)),
        ("point_y", Field::F64(&c.point_y)),
        ("sliding", Field::Bool(&c.sliding)),
        ("tangential_spring", Field::F64(&c.tangential_spring)),
        ("law_state", Field::F64(&c.law_state)),
    ]
}

/// The final state's table in a run group.
pub const FINAL: &str = "final";
/// The final state's contact table in a run group.
pub const FINAL_CONTACTS: &str = "final_contacts";
/// The group of frame state tables in a run group.
pub const FRAMES: &str = "frames";
/// The group of frame contact tables in a run group.
pub const FRAME_CONTACTS: &str = "frame_contacts";
/// Digits of a frame's name (zero-padded, so that names sort in time order).
pub const FRAME_DIGITS: usize = 5;

/// Name of frame `k` in [`FRAMES`] and [`FRAME_CONTACTS`].
pub fn frame_name(k: usize) -> String {
    format!("{k:0FRAME_DIGITS$}")
}

const INDEX: &str = "index";
const ID: &str = "id";
const PARAMETERS: &str = "parameters";
const STATUS: &str = "status";
const MESSAGE: &str = "message";
const WARNINGS: &str = "warnings";
const WARNING_COUNT: &str = "warning_count";

/// Name of the bucket group of a run.
pub fn bucket_name(index: usize) -> String {
    format!("b{:04}", index / BUCKET_SIZE)
}

/// Path of a run's group (without a leading `/`).
pub fn run_path(index: usize, id: &str) -> String {
    format!("{RUNS}/{}/{id}", bucket_name(index))
}

/// The attributes of a run group: its summary row (swept parameters under their key paths, listed in
/// `parameters`) and key scene values (`scene.*`).
pub fn run_attrs(row: &SummaryRow, scene: &SceneConfig) -> Vec<(String, AttrValue)> {
    let mut attrs: Vec<(String, AttrValue)> = vec![
        (INDEX.into(), AttrValue::I64(row.index as i64)),
        (ID.into(), AttrValue::String(row.id.clone())),
        (STATUS.into(), AttrValue::String(row.status.as_str().to_string())),
        (MESSAGE.into(), AttrValue::String(row.message.clone())),
        (WARNING_COUNT.into(), AttrValue::I64(row.warnings.len() as i64)),
    ];
    attrs.extend(OUTCOME.iter().zip(row.outcome()).map(|(q, v)| (q.name.into(), outcome_attr(v))));
    if !row.warnings.is_empty() {
        attrs.push((WARNINGS.into(), AttrValue::StringArray(row.warnings.clone())));
    }
    if !row.parameters.is_empty() {
        let keys = row.parameters.iter().map(|(k, _)| k.clone()).collect();
        attrs.push((PARAMETERS.into(), AttrValue::StringArray(keys)));
    }
    attrs.extend(row.parameters.iter().map(|(k, v)| (k.clone(), param_attr(v))));
    let finals = quantity::final_value_declarations().zip(row.final_values);
    attrs.extend(finals.map(|(q, v)| (q.name.to_string(), AttrValue::F64(v))));
    attrs.extend(scene_values(scene).into_iter().map(|(k, v)| (format!("scene.{k}"), v)));
    attrs
}

/// Key scene values of a run, resolved as the simulation uses them (e.g. ν = 0.3 when not given).
pub fn scene_values(scene: &SceneConfig) -> Vec<(&'static str, AttrValue)> {
    let m = Materials::from_scene(scene);
    let nu = Elastic::new(scene.material.youngs_modulus, scene.material.poisson_ratio, scene.material.shear_modulus)
        .poisson_ratio;
    vec![
        ("youngs_modulus", AttrValue::F64(scene.material.youngs_modulus)),
        ("poisson_ratio", AttrValue::F64(nu)),
        ("beta", AttrValue::F64(m.particle.beta)),
        ("restitution", AttrValue::F64(restitution_from_beta(m.particle.beta))),
        ("friction", AttrValue::F64(m.particle.friction)),
        ("rolling_friction", AttrValue::F64(m.particle.rolling_friction)),
        ("density", AttrValue::F64(scene.material.density)),
        ("time_step", AttrValue::F64(scene.integrator.time_step.unwrap_or(f64::NAN))),
        ("integrator", serde_name(&scene.integrator.scheme)),
        ("contact_law", serde_name(&scene.contact.law)),
        ("count", AttrValue::I64(scene.particles.count as i64)),
        ("radius", AttrValue::F64(scene.particles.radius)),
        ("seed", AttrValue::I64(scene.placement.seed as i64)),
        ("duration", AttrValue::F64(scene.run.duration)),
        ("width", AttrValue::F64(scene.domain.width)),
        ("json", AttrValue::String(serde_json::to_string(scene).unwrap_or_default())),
    ]
}

fn outcome_attr(value: OutcomeValue) -> AttrValue {
    match value {
        OutcomeValue::Float(x) => AttrValue::F64(x),
        OutcomeValue::Int(i) => AttrValue::I64(i as i64),
    }
}

/// A serde unit enum's name as written in scene files (e.g. `adams_bashforth_moulton`).
fn serde_name<T: serde::Serialize>(value: &T) -> AttrValue {
    let name = serde_json::to_value(value).ok().and_then(|v| v.as_str().map(str::to_string));
    AttrValue::String(name.unwrap_or_default())
}

/// A parameter value as an attribute: floats `f64`, integers `i64`, booleans `u8`, text strings.
pub fn param_attr(v: &ParamValue) -> AttrValue {
    match v {
        ParamValue::Float(x) => AttrValue::F64(*x),
        ParamValue::Int(i) => AttrValue::I64(*i),
        ParamValue::Bool(b) => AttrValue::U8(u8::from(*b)),
        ParamValue::Text(s) => AttrValue::String(s.clone()),
    }
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

/// Reads a summary row back from a run group's attributes; the error names what is missing.
pub fn row_from_attrs(attrs: &HashMap<String, AttrValue>) -> Result<SummaryRow, String> {
    let get = |name: &str| attrs.get(name).ok_or(format!("no `{name}` attribute"));
    let float = |name: &str| get(name).and_then(|v| v.as_f64().ok_or(format!("`{name}` is not a float")));
    let int = |name: &str| get(name).and_then(|v| v.as_i64().ok_or(format!("`{name}` is not an integer")));
    let text =
        |name: &str| get(name).and_then(|v| v.as_str().map(str::to_string).ok_or(format!("`{name}` is not text")));
    let keys = attrs.get(PARAMETERS).and_then(AttrValue::as_strings).unwrap_or(&[]);
    let parameters = keys
        .iter()
        .map(|k| {
            get(k).and_then(|v| attr_param(v).ok_or(format!("`{k}` has an unsupported type"))).map(|v| (k.clone(), v))
        })
        .collect::<Result<Vec<_>, _>>()?;
    // Files written before a final value existed lack its attribute: it reads as missing (NaN).
    let mut final_values = [f64::NAN; FINAL_VALUE_COUNT];
    for (slot, declared) in final_values.iter_mut().zip(quantity::final_value_declarations()) {
        if attrs.contains_key(declared.name) {
            *slot = float(declared.name)?;
        }
    }
    let [settle_time, steps, particle_steps, simulated_time, wall_time] = OUTCOME.map(|q| q.name);
    let steps = int(steps)? as u64;
    let particle_steps = match attrs.get(particle_steps) {
        Some(_) => int(particle_steps)? as u64,
        None => steps * attrs.get("scene.count").and_then(AttrValue::as_i64).unwrap_or(0) as u64,
    };
    let settle = float(settle_time)?;
    let status = text(STATUS)?;
    let status = RunStatus::parse(&status).ok_or(format!("`{STATUS}` is `{status}`, not a run status"))?;
    Ok(SummaryRow {
        index: int(INDEX)? as usize,
        id: text(ID)?,
        parameters,
        status,
        message: text(MESSAGE)?,
        warnings: attrs.get(WARNINGS).and_then(AttrValue::as_strings).map(<[String]>::to_vec).unwrap_or_default(),
        settle_time: (!settle.is_nan()).then_some(settle),
        steps,
        particle_steps,
        simulated_time: float(simulated_time)?,
        wall_time: float(wall_time)?,
        final_values,
    })
}
