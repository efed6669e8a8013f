//! Where things live in a results file (a run group's attributes: see [`super::run_attrs`]).
//!
//! ```text
//! /                        root attributes: see `header`
//! /runs_00000/<identity>  one group per run, named by its identity (`crate::study::RunIdentity`; the
//!                          run id in files written before identities), in the batch group of the
//!                          commit that wrote it (batches `runs_00000`, `runs_00001`, … in commit
//!                          order); attributes: see `run_attrs`. `/summary`'s `identity` column is
//!                          the index from a run id to its group
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
//!
//! Each commit adds one new batch group under the root and changes no other group but the root:
//! hdf5-pure walks every object of the file when a commit rebuilds an existing group below the root
//! (to check it has one hard link), which made each commit cost grow with the file. Files written
//! before batches keep their runs in `/runs/b<index / 100>/<id>` ([`LEGACY_RUNS`]); readers read both.

use hdf5_pure::AttrValue;

use super::compound::Field;
use crate::physics::contact_network::ContactNetwork;
use crate::physics::quantity::{self, HISTORY_SERIES, SeriesValues};
use crate::physics::record::{DISK_FIELDS, History, Snapshot};

/// The prefix of a batch group's name: the run groups one commit wrote are in `/runs_<k>`, `k` the
/// commit's number (zero-padded to [`BATCH_DIGITS`] digits, more past 99 999).
pub const BATCH_PREFIX: &str = "runs_";
/// Digits of a batch group's number.
pub const BATCH_DIGITS: usize = 5;
/// The group holding the run buckets `b<index / 100>` in files written before batch groups.
pub const LEGACY_RUNS: &str = "runs";
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
/// Attribute of `/summary`: how many run groups the file held when `/summary` was written (runs
/// no longer planned included). A file holding more (a sweep killed before it finished) has its
/// summary assembled from the run groups.
pub const STORED_RUNS: &str = "stored_runs";
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

/// Name of the batch group of commit `k`.
pub fn batch_name(k: usize) -> String {
    format!("{BATCH_PREFIX}{k:0BATCH_DIGITS$}")
}

/// The commit number of a batch group's name; `None` for any other name.
pub fn batch_number(name: &str) -> Option<usize> {
    name.strip_prefix(BATCH_PREFIX).filter(|k| k.bytes().all(|b| b.is_ascii_digit())).and_then(|k| k.parse().ok())
}
