//! One summary row per run: what the writer stores on each run group and what `/summary` and the
//! CSV summary are built from.

use crate::physics::pile::PILE_METRIC_NAMES;
use crate::physics::record::{RunRecord, RunStatus};
use crate::study::ParamValue;

/// One run's summary: identity, swept parameters, outcome and final values.
#[derive(Clone, Debug, PartialEq)]
pub struct SummaryRow {
    /// Position in the plan (0-based).
    pub index: usize,
    /// Stable run id (e.g. `r0007`).
    pub id: String,
    /// Swept key paths and values, in axis order.
    pub parameters: Vec<(String, ParamValue)>,
    /// How the run ended: one of [`RunStatus::RECORDED`].
    pub status: RunStatus,
    /// Why the run diverged or failed; empty otherwise.
    pub message: String,
    /// Validity warnings.
    pub warnings: Vec<String>,
    /// Settle time (s), `None` when the run did not settle.
    pub settle_time: Option<f64>,
    /// Time steps taken.
    pub steps: u64,
    /// Time steps times disks: the run's cost, independent of the machine.
    pub particle_steps: u64,
    /// Simulated time reached (s).
    pub simulated_time: f64,
    /// Wall-clock time of the simulation (s).
    pub wall_time: f64,
    /// Final values (NaN for failed runs), in the order of [`FINAL_VALUE_NAMES`].
    pub final_values: [f64; FINAL_VALUE_NAMES.len()],
}

/// Names of the final values of a row (columns of the summary, attributes of a run group): the
/// time step, energies, the unbalanced force ratio and the pile metrics of [`PILE_METRIC_NAMES`].
pub const FINAL_VALUE_NAMES: [&str; 19] = [
    "time_step",
    "final_kinetic",
    "final_potential",
    "final_elastic",
    "final_dissipated",
    "final_numerical_damping_dissipated",
    "final_mechanical",
    "final_ubf",
    "pile_height",
    "packing_fraction",
    PILE_METRIC_NAMES[0],
    PILE_METRIC_NAMES[1],
    PILE_METRIC_NAMES[2],
    PILE_METRIC_NAMES[3],
    PILE_METRIC_NAMES[4],
    PILE_METRIC_NAMES[5],
    PILE_METRIC_NAMES[6],
    PILE_METRIC_NAMES[7],
    PILE_METRIC_NAMES[8],
];

/// Final values of a record, in the order of [`FINAL_VALUE_NAMES`]; `width` is the box width (m).
pub fn final_values(record: &RunRecord, width: f64) -> [f64; FINAL_VALUE_NAMES.len()] {
    let h = &record.history;
    let last = RunRecord::last;
    let head = [
        record.time_step,
        last(&h.kinetic_translational) + last(&h.kinetic_rotational),
        last(&h.potential),
        last(&h.elastic),
        last(&h.dissipated),
        last(&h.numerical_damping_dissipated),
        last(&h.mechanical),
        last(&h.unbalanced_force_ratio),
        record.pile_height(),
        record.packing_fraction(width),
    ];
    let mut values = [f64::NAN; FINAL_VALUE_NAMES.len()];
    let pile = record.pile.values();
    values[..head.len()].copy_from_slice(&head);
    values[head.len()..].copy_from_slice(&pile);
    values
}

impl SummaryRow {
    /// The row of a finished run.
    pub fn finished(
        index: usize,
        id: &str,
        parameters: &[(String, ParamValue)],
        record: &RunRecord,
        width: f64,
    ) -> Self {
        Self {
            index,
            id: id.to_string(),
            parameters: parameters.to_vec(),
            status: record.status,
            message: record.message.clone().unwrap_or_default(),
            warnings: record.warnings.clone(),
            settle_time: record.settle_time,
            steps: record.steps,
            particle_steps: record.steps * record.final_state.x.len() as u64,
            simulated_time: record.simulated_time,
            wall_time: 0.0,
            final_values: final_values(record, width),
        }
    }

    /// The row of a run that failed without a record.
    pub fn failed(index: usize, id: &str, parameters: &[(String, ParamValue)], message: &str) -> Self {
        Self {
            index,
            id: id.to_string(),
            parameters: parameters.to_vec(),
            status: RunStatus::Error,
            message: message.to_string(),
            warnings: Vec::new(),
            settle_time: None,
            steps: 0,
            particle_steps: 0,
            simulated_time: 0.0,
            wall_time: 0.0,
            final_values: [f64::NAN; FINAL_VALUE_NAMES.len()],
        }
    }

    /// Whether the run finished (settled, not settled or diverged), as opposed to failing.
    pub fn is_finished(&self) -> bool {
        self.status != RunStatus::Error
    }
}
