//! Every per-run quantity, declared once: name, unit, description and how it is computed.
//!
//! The summary's columns (CSV and `/summary`), the run groups' attributes, their units (HDF5
//! attributes, the CSV files' metadata sidecars and the labels people read: [`unit()`], [`label`]), the
//! history tables, `compare --keep`, tune's `[keep]`, `summary --metric` and the column table of
//! docs/results.md all read these tables, and so do the metrics kept by default, the report's
//! per-point columns and `plot`'s charts (each entry's [`Role`]); nothing else lists the names. Adding a
//! pile metric is its computation in `pile.rs` (and its known-answer test) plus one entry in
//! [`PILE_METRICS`]; adding a final value one entry in [`FINAL_VALUES`]. The tables are read when a run's
//! record is turned into a row, never in the step loop.
//!
//! Units are SI symbols; an empty unit means dimensionless (a ratio, a fraction, a count).

use super::contact_record::PileContact;
use super::pile::{PILE_METRIC_COUNT, Pile, PileGeometry, PileMetrics};
use super::record::{DISK_FIELDS, History, RunRecord};
use super::stress::pile_stress;

/// One declared quantity; `value` says how it is computed (`()` where the runner measures it).
#[derive(Clone, Copy, Debug)]
pub struct Quantity<F> {
    /// Name in files and on the command line (snake_case).
    pub name: &'static str,
    /// SI unit symbol; empty when dimensionless.
    pub unit: &'static str,
    /// What it is, in one sentence.
    pub description: &'static str,
    /// Whether it is kept by default, its place in the report and whether it is charted.
    pub role: Role,
    /// How it is computed.
    pub value: F,
}

/// How a per-run quantity is presented beyond its column: `compare`'s and tune's default kept
/// metrics ([`kept_by_default`]), the report's per-point table and `plot`'s charts ([`charted`]) read it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Role {
    /// Relative tolerance it is kept within when no metric is named; `None`: not kept by default.
    pub keep: Option<f64>,
    /// Its column in the report's per-point table.
    pub report: Report,
    /// Whether its per-point values are charted against each swept axis.
    pub charted: bool,
}

impl Role {
    /// A column of the report, neither kept by default nor charted.
    pub const COLUMN: Role = Role { keep: None, report: Report::Column, charted: false };
    /// No column of the report, neither kept by default nor charted.
    pub const HIDDEN: Role = Role { report: Report::Hidden, ..Role::COLUMN };
}

/// A per-run quantity's column in the report's per-point table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Report {
    /// A column in the header group of the quantity declared before it.
    Column,
    /// A column that opens the header group `group`, checked on at first when `shown`.
    Opens { group: &'static str, shown: bool },
    /// No column (the energies, raw counts, a direction).
    Hidden,
}

/// A name, unit and description, without the computation.
pub type Declaration = Quantity<()>;

impl<F> Quantity<F> {
    /// The declaration alone.
    pub fn declaration(&self) -> Declaration {
        Quantity { name: self.name, unit: self.unit, description: self.description, role: self.role, value: () }
    }
}

/// How a pile metric is computed from a measured pile.
pub type PileValue = fn(&Pile) -> f64;
/// How a final value is computed from a run's record.
pub type RunValue = fn(&RunRecord) -> f64;

/// What each run reports about how it went, in summary order; the summary row keeps them as typed
/// fields (an optional settle time, integer step counts).
pub const OUTCOME: [Declaration; 6] = [
    SETTLE_TIME,
    Quantity { role: Role::HIDDEN, ..declared("steps", "", "Time steps taken.") },
    declared("particle_steps", "", "Time steps times disks: the run's cost, independent of the machine."),
    Quantity { role: Role::HIDDEN, ..declared("simulated_time", "s", "Simulated time reached.") },
    declared("wall_time", "s", "Wall-clock time of the simulation, measured by the runner."),
    declared("cpu_time", "s", "CPU time of the simulation's thread, measured by the runner; empty where not measured."),
];

/// When a run settled: the study charts' quantity, and the first of the report's per-point columns.
pub const SETTLE_TIME: Declaration = Quantity {
    role: Role { report: Report::Opens { group: "settle time & cost", shown: true }, charted: true, ..Role::COLUMN },
    ..declared("settle_time", "s", "Start of the stretch over which the settle criterion held; empty if never.")
};

/// A declaration with [`Role::COLUMN`].
const fn declared(name: &'static str, unit: &'static str, description: &'static str) -> Declaration {
    Quantity { name, unit, description, role: Role::COLUMN, value: () }
}

/// A final value that is the last sample of the history series in the `History` field `$field`.
macro_rules! last_sample {
    ($field:ident, $name:literal, $unit:literal, $description:literal, $role:expr) => {
        Quantity {
            name: $name,
            unit: $unit,
            description: $description,
            role: $role,
            value: |r| RunRecord::last(&r.history.$field),
        }
    };
}

/// Final values of a run taken from its record (before the pile metrics in the summary).
pub const FINAL_VALUES: [Quantity<RunValue>; 13] = [
    Quantity {
        name: "time_step",
        unit: "s",
        description: "Time step used: given, or resolved from the scene's time scales.",
        role: Role { report: Report::Opens { group: "time step & final state", shown: false }, ..Role::COLUMN },
        value: |r| r.time_step,
    },
    Quantity {
        name: "final_kinetic",
        unit: "J",
        description: "Kinetic energy, translational plus rotational, at the last sample.",
        role: Role::HIDDEN,
        value: |r| RunRecord::last(&r.history.kinetic_translational) + RunRecord::last(&r.history.kinetic_rotational),
    },
    last_sample!(
        potential,
        "final_potential",
        "J",
        "Gravitational potential energy at the last sample (zero at the origin).",
        Role::HIDDEN
    ),
    last_sample!(
        elastic,
        "final_elastic",
        "J",
        "Elastic energy stored in the contacts at the last sample.",
        Role::HIDDEN
    ),
    last_sample!(
        dissipated,
        "final_dissipated",
        "J",
        "Energy removed by damping and friction, numerical damping included.",
        Role::HIDDEN
    ),
    last_sample!(
        numerical_damping_dissipated,
        "final_numerical_damping_dissipated",
        "J",
        "The part of final_dissipated removed by numerical damping.",
        Role::HIDDEN
    ),
    last_sample!(
        mechanical,
        "final_mechanical",
        "J",
        "Kinetic plus potential plus elastic energy at the last sample.",
        Role::HIDDEN
    ),
    last_sample!(unbalanced_force_ratio, "final_ubf", "", "Unbalanced force ratio at the last sample.", Role::COLUMN),
    Quantity {
        name: "energy_balance_error",
        unit: "",
        description: "Largest absolute error of the energy balance (mechanical + dissipated = initial) over the sampled steps, as a share of the energy available.",
        role: Role::COLUMN,
        value: |r| r.energy_balance_error,
    },
    Quantity {
        name: "largest_overlap_ratio",
        unit: "",
        description: "Largest overlap over the sampled steps, over the smaller radius of its pair.",
        role: Role::COLUMN,
        value: |r| r.largest_overlap_ratio,
    },
    Quantity {
        name: "physics_start_time",
        unit: "s",
        description: "When the scene's own physics began: 0 without stages, else when the last stage of its protocol ended; empty if the run ended first.",
        role: Role::COLUMN,
        value: |r| r.stage_ends.last().map_or(0.0, |end| end.time.unwrap_or(f64::NAN)),
    },
    Quantity {
        name: "poured_disks",
        unit: "",
        description: "Disks a pour inserted (placement.kind = \"pour\"); empty for other placements.",
        role: Role::COLUMN,
        value: |r| r.pour.map_or(f64::NAN, |pour| pour.inserted as f64),
    },
    Quantity {
        name: "refused_disks",
        unit: "",
        description: "Disks a pour refused, finding no free spot in its inlet; empty for other placements.",
        role: Role::COLUMN,
        value: |r| r.pour.map_or(f64::NAN, |pour| pour.refused as f64),
    },
];

/// The pile metrics, measured once at the end of a run (see [`super::pile`] for the definitions;
/// only contacts that carry force count).
pub const PILE_METRICS: [Quantity<PileValue>; PILE_METRIC_COUNT] = [
    PILE_HEIGHT,
    Quantity {
        name: "surface_height",
        unit: "m",
        description: "Mean height of the pile's free surface over the box width (the top of the highest disk above each point).",
        role: Role::COLUMN,
        value: |pile| pile.surface_height(),
    },
    PACKING_FRACTION,
    PACKING_FRACTION_INTERIOR,
    Quantity {
        name: "coordination_number",
        unit: "",
        description: "2 C_dd / N over disk-disk contacts.",
        role: Role {
            keep: Some(0.03),
            report: Report::Opens { group: "contacts & forces", shown: false },
            charted: false,
        },
        value: |pile| pile.coordination_number(),
    },
    Quantity {
        name: "mechanical_coordination_number",
        unit: "",
        description: "2 C_dd / N after removing rattlers (fewer than 2 contacts) repeatedly.",
        role: Role { charted: true, ..Role::COLUMN },
        value: |pile| pile.mechanical_coordination_number(),
    },
    Quantity {
        name: "rattler_fraction",
        unit: "",
        description: "Share of disks that are rattlers.",
        role: Role::COLUMN,
        value: |pile| pile.rattler_fraction(),
    },
    Quantity {
        name: "floor_load_ratio",
        unit: "",
        description: "Floor normal forces over the disks' weight (below 1 when wall friction carries weight).",
        role: Role { keep: Some(0.02), charted: true, ..Role::COLUMN },
        value: |pile| pile.floor_load_ratio(),
    },
    Quantity {
        name: "floor_mean_contact_force",
        unit: "N",
        description: "Mean normal force of the floor's contacts.",
        role: Role::COLUMN,
        value: |pile| pile.floor_mean_contact_force(),
    },
    Quantity {
        name: "fabric_anisotropy",
        unit: "",
        description: "2 (λ1 − λ2) of the disk-disk contact-normal fabric tensor.",
        role: Role { keep: Some(0.25), ..Role::COLUMN },
        value: |pile| pile.fabric_anisotropy(),
    },
    Quantity {
        name: "fabric_direction",
        unit: "rad",
        description: "Major principal direction of the fabric tensor, from +x, in [0, π).",
        role: Role::HIDDEN,
        value: |pile| pile.fabric_direction(),
    },
    Quantity {
        name: "normal_force_width",
        unit: "",
        description: "Standard deviation over mean of the disk-disk normal forces (0 when uniformly loaded).",
        role: Role::COLUMN,
        value: |pile| pile.normal_force_width(),
    },
    Quantity {
        name: "sliding_fraction",
        unit: "",
        description: "Share of frictional contacts at the Coulomb limit.",
        role: Role::COLUMN,
        value: |pile| pile.sliding_fraction(),
    },
    Quantity {
        name: "mean_overlap_ratio",
        unit: "",
        description: "Mean overlap over the smaller radius.",
        role: Role { charted: true, ..Role::COLUMN },
        value: |pile| pile.mean_overlap_ratio(),
    },
    STRESS_PRESSURE,
    STRESS_DEVIATORIC,
    STRESS_XX,
    STRESS_YY,
    STRESS_XY,
];

/// The pile's height, kept with [`PACKING_FRACTION`] where a file predates the other metrics.
pub const PILE_HEIGHT: Quantity<PileValue> = Quantity {
    name: "pile_height",
    unit: "m",
    description: "Highest disk top.",
    role: Role { report: Report::Opens { group: "pile geometry", shown: true }, ..Role::COLUMN },
    value: |pile| pile.height(),
};

/// The pile's packing fraction, kept with [`PILE_HEIGHT`] where a file predates the other metrics.
pub const PACKING_FRACTION: Quantity<PileValue> = Quantity {
    name: "packing_fraction",
    unit: "",
    description: "Disk area over the box width times the pile height.",
    role: Role::COLUMN,
    value: |pile| pile.packing_fraction(),
};

/// The packing fraction away from walls, floor and surface; undefined (NaN) where the pile is too
/// shallow or the box too narrow for its window ([`super::pile::predicted_interior_window`]).
pub const PACKING_FRACTION_INTERIOR: Quantity<PileValue> = Quantity {
    name: "packing_fraction_interior",
    unit: "",
    description: "Disk area fraction in a window 2 d_max from the walls, floor and surface.",
    role: Role { keep: Some(0.01), charted: true, ..Role::COLUMN },
    value: |pile| pile.interior_packing_fraction(),
};

/// The pile's mean normal stress, also the name of the stress profile's
/// column of it per height band.
pub const STRESS_PRESSURE: Quantity<PileValue> = Quantity {
    name: "stress_pressure",
    unit: "Pa",
    description: "Mean normal stress (σ_xx + σ_yy)/2 of the pile's Love–Weber stress, compression positive.",
    role: Role::COLUMN,
    value: |pile| pile_stress(pile).pressure(),
};

/// The pile's deviatoric stress, also the name of the stress profile's
/// column of it per height band.
pub const STRESS_DEVIATORIC: Quantity<PileValue> = Quantity {
    name: "stress_deviatoric",
    unit: "Pa",
    description: "Deviatoric stress √(((σ_xx − σ_yy)/2)² + σ_xy²) of the pile: the largest shear stress.",
    role: Role::COLUMN,
    value: |pile| pile_stress(pile).deviatoric(),
};

/// The pile's horizontal normal stress, also the name of the stress profile's
/// column of it per height band.
pub const STRESS_XX: Quantity<PileValue> = Quantity {
    name: "stress_xx",
    unit: "Pa",
    description: "Horizontal normal stress of the pile (Love–Weber over the area below its surface height).",
    role: Role::COLUMN,
    value: |pile| pile_stress(pile).xx,
};

/// The pile's vertical normal stress, also the name of the stress profile's
/// column of it per height band.
pub const STRESS_YY: Quantity<PileValue> = Quantity {
    name: "stress_yy",
    unit: "Pa",
    description: "Vertical normal stress of the pile (Love–Weber over the area below its surface height).",
    role: Role::COLUMN,
    value: |pile| pile_stress(pile).yy,
};

/// The pile's shear stress, also the name of the stress profile's
/// column of it per height band.
pub const STRESS_XY: Quantity<PileValue> = Quantity {
    name: "stress_xy",
    unit: "Pa",
    description: "Shear stress of the pile (Love–Weber, symmetrised).",
    role: Role::COLUMN,
    value: |pile| pile_stress(pile).xy,
};

impl PileMetrics {
    /// Measures a pile from its disks and contacts: every metric of [`PILE_METRICS`].
    pub fn measure(geometry: &PileGeometry, contacts: &[PileContact]) -> Self {
        let pile = Pile::new(geometry, contacts);
        Self { values: PILE_METRICS.map(|metric| (metric.value)(&pile)) }
    }

    /// The metric called `name`, `None` when there is no such metric.
    pub fn get(&self, name: &str) -> Option<f64> {
        PILE_METRICS.iter().position(|m| m.name == name).map(|k| self.values[k])
    }
}

impl std::ops::Index<&str> for PileMetrics {
    type Output = f64;

    /// The metric called `name`; panics naming it when there is no such metric.
    fn index(&self, name: &str) -> &f64 {
        let k = PILE_METRICS.iter().position(|m| m.name == name);
        &self.values[k.unwrap_or_else(|| panic!("no pile metric `{name}`"))]
    }
}

/// Number of final values of a run: [`FINAL_VALUES`] then [`PILE_METRICS`].
pub const FINAL_VALUE_COUNT: usize = FINAL_VALUES.len() + PILE_METRICS.len();

/// The final values' declarations, in the order of [`final_values`].
pub fn final_value_declarations() -> impl Iterator<Item = Declaration> {
    FINAL_VALUES.iter().map(Quantity::declaration).chain(PILE_METRICS.iter().map(Quantity::declaration))
}

/// The final values of a record: [`FINAL_VALUES`] computed, then its pile metrics.
pub fn final_values(record: &RunRecord) -> [f64; FINAL_VALUE_COUNT] {
    let mut values = [f64::NAN; FINAL_VALUE_COUNT];
    for (slot, quantity) in values.iter_mut().zip(&FINAL_VALUES) {
        *slot = (quantity.value)(record);
    }
    values[FINAL_VALUES.len()..].copy_from_slice(record.pile.values());
    values
}

/// Every per-run quantity in summary order: [`OUTCOME`], then the final values.
pub fn per_run() -> impl Iterator<Item = Declaration> {
    OUTCOME.into_iter().chain(final_value_declarations())
}

/// The metrics kept by default, with their relative tolerances (see [`Role::keep`]), in summary order.
pub fn kept_by_default() -> impl Iterator<Item = (&'static str, f64)> {
    per_run().filter_map(|q| q.role.keep.map(|relative| (q.name, relative)))
}

/// The quantities charted per point against each swept axis (see [`Role::charted`]): the final
/// values a deposition is run for, then the outcomes (settle time).
pub fn charted() -> impl Iterator<Item = &'static str> {
    final_value_declarations().chain(OUTCOME).filter(|q| q.role.charted).map(|q| q.name)
}

/// The per-run quantity called `name`; a column `stage_end_time.NAME` is [`STAGE_END_TIME`].
pub fn find(name: &str) -> Option<Declaration> {
    let stage = || name.strip_prefix(STAGE_END_TIME.name).filter(|rest| rest.starts_with('.')).map(|_| STAGE_END_TIME);
    per_run().find(|q| q.name == name).or_else(stage)
}

/// When a stage of a scene's protocol ended: one column per stage, `stage_end_time.NAME`.
pub const STAGE_END_TIME: Declaration =
    declared("stage_end_time", "s", "When the protocol stage the column names ended; empty if the run ended first.");

/// The column of the end time of the stage called `stage`.
pub fn stage_end_column(stage: &str) -> String {
    format!("{}.{stage}", STAGE_END_TIME.name)
}

/// The statistics a column may hold of a per-run quantity, in its unit, by suffix: over runs
/// (`_mean`, `_std`, `_ci95`, `_min`, `_max`) or between two settings' means (`_difference`, in tune's
/// candidates table).
const STATISTIC_SUFFIXES: [&str; 6] = ["_mean", "_std", "_ci95", "_min", "_max", "_difference"];

/// The per-run quantity a column holds, directly or as a statistic of it (see
/// `STATISTIC_SUFFIXES`); `None` for other columns.
pub fn column_quantity(column: &str) -> Option<Declaration> {
    let statistic = |suffix: &&str| column.strip_suffix(suffix);
    find(column).or_else(|| STATISTIC_SUFFIXES.iter().find_map(statistic).and_then(find))
}

/// The SI unit of a named column wherever demsweep stores or reads it (`""`: dimensionless): a
/// per-run quantity or a statistic of one (`settle_time_ci95`), a history series, a disk field of a
/// state, or a scene key (a swept column such as `material.youngs_modulus`); `None` for anything
/// else (text, run ids, counts of runs). Every CSV file's metadata sidecar and every [`label`] read it.
pub fn unit(name: &str) -> Option<&'static str> {
    let series = || HISTORY_SERIES.iter().find(|s| s.quantity.name == name).map(|s| s.quantity.unit);
    let disk_field = || DISK_FIELDS.iter().find(|f| f.name == name).map(|f| f.unit);
    let key = || super::keys::scene_keys().into_iter().find(|k| k.path == name).map(|k| k.unit);
    column_quantity(name).map(|q| q.unit).or_else(series).or_else(disk_field).or_else(key)
}

/// What a column named after a per-run quantity or a history series holds, in one sentence; `None`
/// for anything else (a statistic of a quantity included).
pub fn description(name: &str) -> Option<&'static str> {
    let series = || HISTORY_SERIES.iter().find(|s| s.quantity.name == name).map(|s| s.quantity.description);
    find(name).map(|q| q.description).or_else(series)
}

/// The one way a name is shown with its unit to people (plot axes, report and terminal table
/// headers): `name (unit)`, the name alone when the unit is empty. Files hold the bare name.
pub fn labelled(name: &str, unit: &str) -> String {
    if unit.is_empty() { name.to_string() } else { format!("{name} ({unit})") }
}

/// A column's label: [`labelled`] with its [`unit()`].
pub fn label(name: &str) -> String {
    labelled(name, unit(name).unwrap_or(""))
}

/// The values of a history series.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SeriesValues<'a> {
    /// Real numbers.
    Real(&'a [f64]),
    /// Counts.
    Count(&'a [u32]),
}

/// A history series: one value per sample, a field of the `history` table.
#[derive(Clone, Copy, Debug)]
pub struct Series {
    /// What it is, and its values in a [`History`].
    pub quantity: Quantity<fn(&History) -> SeriesValues<'_>>,
    /// Stores values read back from a file.
    pub store: fn(&mut History, Vec<f64>),
    /// The value of every sample when a file predates the series; `None` when it is required.
    pub when_absent: Option<f64>,
}

impl Series {
    /// Bytes one sample of the series takes (8 for a real, 4 for a count), in memory and in files.
    pub fn bytes_per_sample(&self) -> u64 {
        match (self.quantity.value)(&History::default()) {
            SeriesValues::Real(_) => 8,
            SeriesValues::Count(_) => 4,
        }
    }
}

/// Bytes one history sample takes: every series of [`HISTORY_SERIES`].
pub fn history_bytes_per_sample() -> u64 {
    HISTORY_SERIES.iter().map(Series::bytes_per_sample).sum()
}

/// A series of real numbers stored in the `History` field `$field`, required in files.
macro_rules! real_series {
    ($field:ident, $name:literal, $unit:literal, $description:literal) => {
        Series {
            quantity: Quantity {
                name: $name,
                unit: $unit,
                description: $description,
                role: Role::COLUMN,
                value: |h| SeriesValues::Real(&h.$field),
            },
            store: |h, v| h.$field = v,
            when_absent: None,
        }
    };
}

/// The history series, in the order of the `history` table's fields.
pub const HISTORY_SERIES: [Series; 12] = [
    real_series!(time, "t", "s", "Simulated time."),
    real_series!(kinetic_translational, "kinetic_translational", "J", "Translational kinetic energy Σ ½ m v²."),
    real_series!(kinetic_rotational, "kinetic_rotational", "J", "Rotational kinetic energy Σ ½ I ω²."),
    real_series!(potential, "potential", "J", "Gravitational potential energy −Σ m g·x."),
    real_series!(elastic, "elastic", "J", "Elastic energy stored in the contacts."),
    real_series!(
        dissipated,
        "dissipated",
        "J",
        "Energy removed by damping and friction so far, numerical damping included."
    ),
    // Files written before numerical damping existed: nothing was dissipated by it.
    Series {
        when_absent: Some(0.0),
        ..real_series!(
            numerical_damping_dissipated,
            "numerical_damping_dissipated",
            "J",
            "The part of dissipated removed by numerical damping."
        )
    },
    real_series!(total, "total", "J", "The paper's total energy: kinetic plus potential."),
    real_series!(mechanical, "mechanical", "J", "Kinetic plus potential plus elastic energy."),
    real_series!(
        unbalanced_force_ratio,
        "unbalanced_force_ratio",
        "",
        "Mean net force over mean contact force (gravity included); NaN without contacts."
    ),
    Series {
        quantity: Quantity {
            name: "contacts",
            unit: "",
            description: "Number of contacts, disk-disk and disk-wall.",
            role: Role::COLUMN,
            value: |h| SeriesValues::Count(&h.contacts),
        },
        store: |h, v| h.contacts = v.into_iter().map(|c| c as u32).collect(),
        when_absent: None,
    },
    real_series!(max_overlap_ratio, "max_overlap_ratio", "", "Largest overlap over the smaller radius of its pair."),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_snake_case() {
        let names: Vec<&str> =
            per_run().map(|q| q.name).chain(HISTORY_SERIES.iter().map(|s| s.quantity.name)).collect();
        for name in &names {
            assert!(name.chars().all(|c| c.is_ascii_lowercase() || c == '_'), "{name}");
        }
        let per_run: Vec<&str> = per_run().map(|q| q.name).collect();
        let mut sorted = per_run.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), per_run.len(), "a per-run name declared twice: {per_run:?}");
    }

    #[test]
    fn every_history_field_is_a_declared_series() {
        // The serialised field names of a history, `time` stored as `t`.
        let fields = serde_json::to_value(History::default()).unwrap();
        let mut fields: Vec<String> = fields.as_object().unwrap().keys().map(|k| k.replace("time", "t")).collect();
        let mut declared: Vec<String> = HISTORY_SERIES.iter().map(|s| s.quantity.name.to_string()).collect();
        fields.sort();
        declared.sort();
        assert_eq!(fields, declared);
    }

    #[test]
    fn series_store_what_they_read() {
        let mut history = History::default();
        for (k, series) in HISTORY_SERIES.iter().enumerate() {
            (series.store)(&mut history, vec![k as f64, 2.0 * k as f64]);
        }
        for (k, series) in HISTORY_SERIES.iter().enumerate() {
            let expected = [k as f64, 2.0 * k as f64];
            match (series.quantity.value)(&history) {
                SeriesValues::Real(v) => assert_eq!(v, expected, "{}", series.quantity.name),
                SeriesValues::Count(v) => assert_eq!(v, [k as u32, 2 * k as u32], "{}", series.quantity.name),
            }
        }
    }

    #[test]
    fn every_stored_name_has_one_unit() {
        assert_eq!(label("settle_time"), "settle_time (s)");
        assert_eq!(label("pile_height_ci95"), "pile_height_ci95 (m)");
        assert_eq!(label("floor_mean_contact_force_mean"), "floor_mean_contact_force_mean (N)");
        assert_eq!(label("wall_time_std"), "wall_time_std (s)");
        assert_eq!(unit("packing_fraction_difference"), Some(""));
        assert_eq!(unit("settle_time_n"), None, "a count of values is not a quantity");
        assert_eq!(label("coordination_number_mean"), "coordination_number_mean", "dimensionless");
        assert_eq!(unit("coordination_number_mean"), Some(""));
        assert_eq!(unit("material.youngs_modulus"), Some("Pa"), "a swept scene key");
        assert_eq!(unit("material.friction"), Some(""));
        assert_eq!(label("t"), "t (s)");
        assert_eq!(label("contacts"), "contacts");
        assert_eq!((unit("vx"), unit("contact_force")), (Some("m/s"), Some("N")), "disk fields");
        assert_eq!((unit("run_id"), unit("status")), (None, None));
        assert_eq!(labelled("run_time", "s"), "run_time (s)");
    }

    #[test]
    fn a_name_means_one_quantity_across_the_tables() {
        let mut names: Vec<&str> = per_run()
            .map(|q| q.name)
            .chain(HISTORY_SERIES.iter().map(|s| s.quantity.name))
            .chain(DISK_FIELDS.iter().map(|f| f.name))
            .collect();
        let count = names.len();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), count, "a name declared in two tables would have two units");
    }
}
