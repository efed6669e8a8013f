//! How a sweep ended, in the terms of its exit status: whether a script or a Slurm job may go on.

use crate::output::SummaryTable;
use crate::output::table::ColumnData;
use crate::physics::RunStatus;

/// Exit status of a sweep some of whose runs diverged, failed with an error or are missing while
/// the others are recorded.
pub const EXIT_PARTIAL: i32 = 4;

/// How many runs a sweep was to make and how the recorded ones ended.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RunCounts {
    /// Runs the sweep was to make (the plan, or a shard of it).
    pub selected: usize,
    /// Of those, runs in the results file.
    pub recorded: usize,
    /// Recorded runs that diverged.
    pub diverged: usize,
    /// Recorded runs that failed with an error.
    pub errored: usize,
}

impl RunCounts {
    /// The counts of `selected` runs whose recorded ones ended with `statuses` (as in a summary).
    pub fn of<'a>(selected: usize, statuses: impl IntoIterator<Item = &'a str>) -> Self {
        let mut counts = Self { selected, ..Self::default() };
        for status in statuses {
            counts.recorded += 1;
            if status == RunStatus::Diverged.as_str() {
                counts.diverged += 1;
            } else if status == RunStatus::Error.as_str() {
                counts.errored += 1;
            }
        }
        counts
    }

    /// The counts of `selected` runs whose recorded ones are the rows of `summary`.
    pub fn of_summary(selected: usize, summary: &SummaryTable) -> Self {
        let statuses = match summary.column("status").map(|c| &c.data) {
            Some(ColumnData::Text(statuses)) => statuses.as_slice(),
            _ => &[],
        };
        Self::of(selected, statuses.iter().map(String::as_str))
    }

    /// Selected runs not in the file.
    pub fn missing(&self) -> usize {
        self.selected.saturating_sub(self.recorded)
    }

    /// Selected runs that give no result: diverged, failed with an error or missing.
    pub fn failed(&self) -> usize {
        self.diverged + self.errored + self.missing()
    }
}

/// How a sweep (a run, a shard, a merge) ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SweepOutcome {
    /// Every selected run is recorded, settled or not; none diverged or failed.
    Complete,
    /// Some runs diverged, failed with an error or are missing; the others are recorded.
    Partial,
    /// No run gives a result: every one diverged, failed with an error or is missing.
    Failed,
    /// Stopped by Ctrl-C, SIGTERM or SIGHUP (finished runs are kept).
    Interrupted,
}

impl SweepOutcome {
    /// The outcome of a sweep with `counts`, stopped by a signal or not.
    pub fn of(counts: &RunCounts, interrupted: bool) -> Self {
        match counts.failed() {
            _ if interrupted => Self::Interrupted,
            0 => Self::Complete,
            failed if failed >= counts.selected => Self::Failed,
            _ => Self::Partial,
        }
    }

    /// The process exit status: 0 complete, 4 partial, 1 failed, 130 interrupted.
    pub fn exit_code(self) -> i32 {
        match self {
            Self::Complete => 0,
            Self::Partial => EXIT_PARTIAL,
            Self::Failed => 1,
            Self::Interrupted => super::interrupt::EXIT_INTERRUPTED,
        }
    }
}

impl std::fmt::Display for RunCounts {
    /// `3 of 48 runs failed (2 diverged, 1 with an error)`, the missing runs counted as such.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let parts: Vec<String> =
            [(self.diverged, "diverged"), (self.errored, "with an error"), (self.missing(), "missing")]
                .into_iter()
                .filter(|(n, _)| *n > 0)
                .map(|(n, what)| format!("{n} {what}"))
                .collect();
        write!(f, "{} of {} runs failed ({})", self.failed(), self.selected, parts.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outcome(selected: usize, statuses: &[&str]) -> SweepOutcome {
        SweepOutcome::of(&RunCounts::of(selected, statuses.iter().copied()), false)
    }

    #[test]
    fn a_sweep_is_complete_partial_or_failed_by_its_runs() {
        assert_eq!(outcome(2, &["settled", "not_settled"]), SweepOutcome::Complete);
        assert_eq!(outcome(0, &[]), SweepOutcome::Complete);
        assert_eq!(outcome(2, &["settled", "diverged"]), SweepOutcome::Partial);
        assert_eq!(outcome(2, &["settled"]), SweepOutcome::Partial);
        assert_eq!(outcome(2, &["diverged", "error"]), SweepOutcome::Failed);
        assert_eq!(outcome(2, &["diverged"]), SweepOutcome::Failed);
        assert_eq!(SweepOutcome::of(&RunCounts::of(2, ["settled"]), true), SweepOutcome::Interrupted);
        let counts = RunCounts::of(48, ["diverged", "diverged", "error", "settled"]);
        assert_eq!(counts.to_string(), "47 of 48 runs failed (2 diverged, 1 with an error, 44 missing)");
    }
}
