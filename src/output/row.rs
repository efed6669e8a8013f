//! One summary row per run: what the writer stores on each run group and what `/summary` and the
//! CSV summary are built from.

use crate::physics::quantity::{self, FINAL_VALUE_COUNT, OUTCOME};
use crate::physics::record::{RunRecord, RunStatus};
use crate::physics::warning::ValidityWarning;
use crate::study::ParamValue;

/// The version of this program, recorded on each run it makes.
pub const DEMSWEEP_VERSION: &str = env!("CARGO_PKG_VERSION");

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
    pub warnings: Vec<ValidityWarning>,
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
    /// CPU time of the simulation's thread (s); NaN where not measured.
    pub cpu_time: f64,
    /// Final values (NaN for failed runs), in the order of [`quantity::final_value_declarations`].
    pub final_values: [f64; FINAL_VALUE_COUNT],
    /// When each stage of the scene's protocol ended (s; NaN where the run ended first), in order.
    pub stage_ends: Vec<(String, f64)>,
    /// The run's identity (`crate::study::RunIdentity`: what its results depend on); empty for runs of
    /// files written before identities.
    pub identity: String,
    /// The demsweep version that made the run (a run group's `demsweep_version`); empty where the
    /// file does not say (results formats before 3: the file header's version is the best guess).
    pub made_by: String,
}

/// The outcome quantities files written before them lack (their readers read them as missing).
pub(crate) const CPU_TIME: &str = "cpu_time";
pub(crate) const PARTICLE_STEPS: &str = "particle_steps";

/// A value of one of a row's [`OUTCOME`] fields.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OutcomeValue {
    /// A float; NaN when missing.
    Float(f64),
    /// A count.
    Int(u64),
}

/// How a row keeps one of its [`OUTCOME`] fields.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutcomeKind {
    /// A float.
    Float,
    /// A count.
    Int,
}

impl OutcomeValue {
    /// Whether it is a float or a count.
    pub fn kind(self) -> OutcomeKind {
        match self {
            OutcomeValue::Float(_) => OutcomeKind::Float,
            OutcomeValue::Int(_) => OutcomeKind::Int,
        }
    }

    /// As a count (floats truncated, NaN and negatives to 0).
    pub fn as_u64(self) -> u64 {
        match self {
            OutcomeValue::Float(x) => x as u64,
            OutcomeValue::Int(i) => i,
        }
    }

    /// As a float.
    pub fn as_f64(self) -> f64 {
        match self {
            OutcomeValue::Float(x) => x,
            OutcomeValue::Int(i) => i as f64,
        }
    }

    /// As an integer (floats truncated).
    pub fn as_i64(self) -> i64 {
        match self {
            OutcomeValue::Float(x) => x as i64,
            OutcomeValue::Int(i) => i as i64,
        }
    }
}

impl SummaryRow {
    /// The row's values of [`OUTCOME`], in order (a missing settle or CPU time is NaN).
    pub fn outcome(&self) -> [OutcomeValue; OUTCOME.len()] {
        use OutcomeValue::{Float, Int};
        let settle = self.settle_time.unwrap_or(f64::NAN);
        [
            Float(settle),
            Int(self.steps),
            Int(self.particle_steps),
            Float(self.simulated_time),
            Float(self.wall_time),
            Float(self.cpu_time),
        ]
    }

    /// Sets the row's [`OUTCOME`] fields (the inverse of [`Self::outcome`]), each from what `read`
    /// gives for its name and kind: `None` where the source lacks it (a missing value: NaN, no
    /// settle time, or a count of 0). The one decoder of a run's outcome, whatever holds it (a run
    /// group's `values` table, its `row` attribute, older files' attributes, a summary table).
    pub fn read_outcome<E>(
        &mut self,
        mut read: impl FnMut(&'static str, OutcomeKind) -> Result<Option<OutcomeValue>, E>,
    ) -> Result<(), E> {
        let mut values = self.outcome();
        for (slot, declared) in values.iter_mut().zip(&OUTCOME) {
            let missing = match slot.kind() {
                OutcomeKind::Float => OutcomeValue::Float(f64::NAN),
                OutcomeKind::Int => OutcomeValue::Int(0),
            };
            *slot = read(declared.name, slot.kind())?.unwrap_or(missing);
        }
        let [settle, steps, particle_steps, simulated, wall, cpu] = values;
        self.settle_time = Some(settle.as_f64()).filter(|x| !x.is_nan());
        (self.steps, self.particle_steps) = (steps.as_u64(), particle_steps.as_u64());
        (self.simulated_time, self.wall_time, self.cpu_time) = (simulated.as_f64(), wall.as_f64(), cpu.as_f64());
        Ok(())
    }

    /// The row of a finished run.
    pub fn finished(index: usize, id: &str, parameters: &[(String, ParamValue)], record: &RunRecord) -> Self {
        Self {
            index,
            id: id.to_string(),
            parameters: parameters.to_vec(),
            status: record.status,
            message: record.message.clone().unwrap_or_default(),
            warnings: record.warnings.clone(),
            settle_time: record.settle_time,
            steps: record.steps,
            particle_steps: record.particle_steps(),
            simulated_time: record.simulated_time,
            wall_time: 0.0,
            cpu_time: f64::NAN,
            final_values: quantity::final_values(record),
            stage_ends: record.stage_ends.iter().map(|e| (e.name.clone(), e.time.unwrap_or(f64::NAN))).collect(),
            identity: String::new(),
            made_by: DEMSWEEP_VERSION.to_string(),
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
            cpu_time: f64::NAN,
            final_values: [f64::NAN; FINAL_VALUE_COUNT],
            stage_ends: Vec::new(),
            identity: String::new(),
            made_by: DEMSWEEP_VERSION.to_string(),
        }
    }

    /// The name of the run's group in a results file: its identity, or its id in files written
    /// before identities.
    pub fn group_name(&self) -> &str {
        if self.identity.is_empty() { &self.id } else { &self.identity }
    }

    /// The final value or pile metric `name` (see `quantity`), if there is one of that name.
    pub fn final_value(&self, name: &str) -> Option<f64> {
        quantity::final_value_declarations().position(|q| q.name == name).map(|k| self.final_values[k])
    }

    /// Whether the run finished (settled, not settled or diverged), as opposed to failing.
    pub fn is_finished(&self) -> bool {
        self.status != RunStatus::Error
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_outcome_read_back_is_the_outcome_written() {
        let mut row = SummaryRow::failed(3, "r3", &[], "m");
        (row.settle_time, row.steps, row.particle_steps) = (Some(0.25), 7, 70);
        (row.simulated_time, row.wall_time, row.cpu_time) = (1.5, 2.5, 3.5);
        let written = row.outcome();
        let names: Vec<&str> = OUTCOME.iter().map(|q| q.name).collect();
        let mut read = SummaryRow::failed(3, "r3", &[], "m");
        read.read_outcome(|name, _| Ok::<_, ()>(Some(written[names.iter().position(|n| *n == name).unwrap()])))
            .unwrap();
        assert_eq!(format!("{read:?}"), format!("{row:?}"));
        read.read_outcome(|_, _| Ok::<_, ()>(None)).unwrap();
        assert_eq!((read.settle_time, read.steps, read.wall_time.is_nan()), (None, 0, true), "missing");
        assert!([CPU_TIME, PARTICLE_STEPS].iter().all(|name| names.contains(name)), "declared names");
    }
}
