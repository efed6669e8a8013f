//! Where things live in a results file (a run group's attributes and small tables: see
//! [`super::run_attrs`]). Results format 3 ([`super::run_attrs::RESULTS_FORMAT`]):
//!
//! ```text
//! /                        root attributes: see `header`
//! /runs_00000/<identity>  one group per run, named by its identity (`crate::study::RunIdentity`; the
//!                          run id in files written before identities), in the batch group of the
//!                          commit that wrote it (batches `runs_00000`, `runs_00001`, … in commit
//!                          order); attributes and the tables values, parameters, warnings: see
//!                          `run_attrs`
//!     history              compound table, one field per series, one row per sample (attr `units`)
//!     stress_profile       compound table, one row per height band of the settled pile (attr `units`)
//!     final                compound table, one field per disk property (`DISK_FIELDS`: x, y, vx,
//!                          vy, omega, angle, r, contact_force), one row per disk (attrs `time`, `units`)
//!     final_contacts       compound table, one field per contact property, one row per contact
//!                          (attrs `time`, `units`; see `CONTACT_FIELDS`), stored with `final`
//!     frames/time          the recorded frames' times (T), H5MD-like: one array per quantity over time
//!     frames/<field>       one (T, N) float64 array per disk property of `DISK_FIELDS` (attr `unit`)
//!     frames/contacts      compound table of every frame's contacts, frame after frame: field
//!                          `frame` (uint32, the row of `time`), then `CONTACT_FIELDS` (attr `units`)
//! /summary/<column>        one dataset per summary column (attribute `columns` on /summary, and
//!                          `jobs`, `wall_time` of the last sweep: see [`SWEEP_JOBS`]); the last two
//!                          columns, [`RUN_GROUP`] and [`RUN_MADE_BY`], are the file's own (not in
//!                          the summary table, the CSV or the printed summary)
//! ```
//!
//! Every dataset of a run is chunked with a Fletcher-32 checksum, so a damaged byte is an error,
//! not a value. Each commit adds one new batch group under the root and changes no other group but
//! the root: hdf5-pure walks every object of the file when a commit rebuilds an existing group below
//! the root (to check it has one hard link), which made each commit cost grow with the file. Files
//! written before batches keep their runs in `/runs/b<index / 100>/<id>` ([`LEGACY_RUNS`]); files of
//! results format 2 and before keep frames as `frames/<k>` and `frame_contacts/<k>` tables
//! ([`FRAME_DIGITS`]); readers read every layout.

use hdf5_pure::AttrValue;

use super::compound::Field;
use crate::physics::contact_network::ContactNetwork;
use crate::physics::quantity::{self, HISTORY_SERIES, SeriesValues};
use crate::physics::record::{DISK_FIELDS, History, Snapshot};
use crate::physics::stress::{Stress, StressProfile};

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
/// The attributes of a `/summary` or `/points` column dataset: `unit` of its values (a per-run
/// quantity, its statistic or a swept scene key; none for text columns such as `run_id`), and the
/// `description` of the per-run quantity it holds or whose statistic it holds.
pub fn column_attrs(column: &str) -> Vec<(&'static str, AttrValue)> {
    let unit = quantity::unit(column).map(|u| (UNIT, AttrValue::String(u.into())));
    let description = quantity::column_quantity(column).map(|q| (DESCRIPTION, AttrValue::String(q.description.into())));
    unit.into_iter().chain(description).collect()
}

/// Attribute of an array dataset (and of `/summary` and `/points` columns): the unit of its values
/// (empty when dimensionless).
pub const UNIT: &str = "unit";
/// Column of `/summary` (the file's own): the path of each run's group (`runs_00003/<identity>`),
/// so that `f[path]` reaches a run.
pub const RUN_GROUP: &str = "group";
/// Column of `/summary` (the file's own): the demsweep version that made each run (empty where
/// the run's group does not say: results formats before 3).
pub const RUN_MADE_BY: &str = "demsweep_version";
/// The frames' times in a run's `frames` group.
pub const FRAME_TIME: &str = "time";
/// The frames' contacts table in a run's `frames` group.
pub const FRAME_CONTACT_TABLE: &str = "contacts";
/// The field of [`FRAME_CONTACT_TABLE`] saying which frame a contact belongs to.
pub const FRAME_INDEX: &str = "frame";
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

/// Attribute of the `history`, `values`, `parameters`, state and contact tables listing the unit of
/// each field, in field order (empty when dimensionless); `/summary` and `/points` columns have a
/// `unit` of their own instead (see [`column_attrs`]).
pub const UNITS: &str = "units";

/// The units of the history table's fields, in order.
pub fn history_units() -> AttrValue {
    AttrValue::StringArray(HISTORY_SERIES.iter().map(|s| s.quantity.unit.to_string()).collect())
}

/// The run's stress profile table (written with the histories).
pub const STRESS_PROFILE: &str = "stress_profile";

/// The stress profile table's fields with their units, in order: band edges (m), the band's stress
/// components, pressure and deviatoric stress, the side walls' normal and shear stress (Pa).
pub fn stress_profile_columns(p: &StressProfile) -> [(&'static str, &'static str, Vec<f64>); 9] {
    let stress = |f: fn(&Stress) -> f64| p.stress.iter().map(f).collect();
    [
        ("bottom", "m", p.bottom.clone()),
        ("top", "m", p.top.clone()),
        (quantity::STRESS_XX.name, "Pa", stress(|s| s.xx)),
        (quantity::STRESS_YY.name, "Pa", stress(|s| s.yy)),
        (quantity::STRESS_XY.name, "Pa", stress(|s| s.xy)),
        (quantity::STRESS_PRESSURE.name, "Pa", stress(Stress::pressure)),
        (quantity::STRESS_DEVIATORIC.name, "Pa", stress(Stress::deviatoric)),
        ("wall_normal_stress", "Pa", p.wall_normal.clone()),
        ("wall_shear_stress", "Pa", p.wall_shear.clone()),
    ]
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

/// The units of [`CONTACT_FIELDS`], in order (empty: an index, a flag or dimensionless; `law_state`
/// is the hysteretic law's largest overlap, 0 for the other laws).
pub const CONTACT_UNITS: [&str; CONTACT_FIELDS.len()] = ["", "", "", "", "N", "N", "m", "m", "m", "", "m", "m"];

/// The units of a contact table's fields, `leading` empty ones first (attribute [`UNITS`]).
pub fn contact_units(leading: usize) -> AttrValue {
    let units = std::iter::repeat_n("", leading).chain(CONTACT_UNITS);
    AttrValue::StringArray(units.map(str::to_string).collect())
}

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
/// The group of frame contact tables in a run group of results format 2 and before.
pub const FRAME_CONTACTS: &str = "frame_contacts";

/// Digits of a frame's number in names (zero-padded, so that names sort in time order): exported
/// and plotted frames, and the frame tables of results format 2 and before.
pub const FRAME_DIGITS: usize = 5;

/// Name of frame `k` (see [`FRAME_DIGITS`]).
pub fn frame_name(k: usize) -> String {
    format!("{k:0FRAME_DIGITS$}")
}

/// The contacts of every frame, frame after frame, and the frame of each (see [`FRAME_CONTACT_TABLE`]).
pub fn frame_contacts(frames: &[Snapshot]) -> (Vec<u32>, ContactNetwork) {
    let mut all = ContactNetwork::default();
    let mut frame = Vec::new();
    for (k, s) in frames.iter().enumerate() {
        let c = &s.contacts;
        frame.extend(std::iter::repeat_n(k as u32, c.first.len()));
        all.first.extend(&c.first);
        all.second.extend(&c.second);
        for (to, from) in [
            (&mut all.normal_x, &c.normal_x),
            (&mut all.normal_y, &c.normal_y),
            (&mut all.normal_force, &c.normal_force),
            (&mut all.tangential_force, &c.tangential_force),
            (&mut all.overlap, &c.overlap),
            (&mut all.point_x, &c.point_x),
            (&mut all.point_y, &c.point_y),
            (&mut all.tangential_spring, &c.tangential_spring),
            (&mut all.law_state, &c.law_state),
        ] {
            to.extend(from);
        }
        all.sliding.extend(&c.sliding);
    }
    (frame, all)
}

/// Name of the batch group of commit `k`.
pub fn batch_name(k: usize) -> String {
    format!("{BATCH_PREFIX}{k:0BATCH_DIGITS$}")
}

/// The commit number of a batch group's name; `None` for any other name.
pub fn batch_number(name: &str) -> Option<usize> {
    name.strip_prefix(BATCH_PREFIX).filter(|k| k.bytes().all(|b| b.is_ascii_digit())).and_then(|k| k.parse().ok())
}
