//! Which planned runs a results file already holds, matched by identity (so that an edited study
//! continues in the same file), which must run, and which stored runs the study no longer plans.

use std::collections::{BTreeMap, HashMap, HashSet};

use super::notes::RunNote;
use crate::output::row::DEMSWEEP_VERSION;
use crate::output::{OutputError, OutputReason, ResultsWriter, SummaryRow};
use crate::study::{IdentityChange, Plan, PlannedRun, RunIdentity};

/// What a resumed (or new) results file gives a sweep.
pub(super) struct Reuse {
    /// Rows of the stored runs the plan reuses, under the plan's index, id and parameters.
    pub rows: Vec<SummaryRow>,
    /// Plan indices of the runs to make, one per identity.
    pub todo: Vec<usize>,
    /// Planned runs that share the identity of a run to make, by identity (see `writer_thread`).
    pub aliases: HashMap<String, Vec<SummaryRow>>,
    /// Stored runs the study no longer plans: kept in the file, left out of the summary.
    pub unplanned: Vec<SummaryRow>,
    /// Stored runs that lacked an output the study now asks for (they run again).
    pub lacking: usize,
    /// For planned runs to make whose swept values match a stored run of another identity: what
    /// changed, with how many runs.
    pub changed: BTreeMap<Vec<IdentityChange>, usize>,
    /// Reused runs made by another demsweep version (reused only when accepted): (run id, version).
    pub other_versions: Vec<(String, String)>,
}

impl Reuse {
    /// Matches the `stored` runs of `writer`'s file to the `selected` runs of `plan` (whose
    /// identities are `identities`). Stored runs without identities (files written before them,
    /// of the same study) are matched by index. Stored runs lacking an output the plan asks for
    /// are deleted from the file, to run again. A stored run made by another demsweep version is
    /// reused only when `accept_version` says so; else the sweep is refused before anything
    /// changes, naming the run and both versions (see [`version_refusal`]).
    pub fn new(
        plan: &Plan,
        identities: &[String],
        (selected, accept_version): (&[usize], bool),
        stored: Vec<SummaryRow>,
        writer: &mut ResultsWriter,
    ) -> Result<Self, OutputError> {
        let mut reuse = Reuse {
            rows: Vec::new(),
            todo: Vec::new(),
            aliases: HashMap::new(),
            unplanned: Vec::new(),
            lacking: 0,
            changed: BTreeMap::new(),
            other_versions: Vec::new(),
        };
        let (legacy, stored): (Vec<SummaryRow>, Vec<SummaryRow>) =
            stored.into_iter().partition(|row| row.identity.is_empty());
        let legacy_done: HashSet<usize> = legacy.iter().map(|r| r.index).collect();
        reuse.rows.extend(legacy);
        let planned: HashSet<&str> = identities.iter().map(String::as_str).collect();
        let (mut by_identity, unplanned): (HashMap<String, SummaryRow>, Vec<SummaryRow>) = {
            let (kept, gone): (Vec<SummaryRow>, Vec<SummaryRow>) =
                stored.into_iter().partition(|row| planned.contains(row.identity.as_str()));
            (kept.into_iter().map(|row| (row.identity.clone(), row)).collect(), gone)
        };
        let mut making: HashSet<&str> = HashSet::new();
        let mut lacking = Vec::new();
        for &i in selected.iter().filter(|i| !legacy_done.contains(i)) {
            let (run, identity) = (&plan.runs[i], identities[i].as_str());
            let frames = !run.scene.run.frame_times.is_empty() || run.scene.run.frame_interval.is_some();
            let as_planned = |row: &SummaryRow| as_planned(run, identity, row);
            if let Some(row) = by_identity.get(identity) {
                if writer.holds(identity, &plan.output, frames) {
                    let made_by = writer.made_by(row);
                    if made_by != DEMSWEEP_VERSION {
                        reuse.other_versions.push((run.id.clone(), made_by.to_string()));
                    }
                    reuse.rows.push(as_planned(row));
                    continue;
                }
                lacking.push(by_identity.remove(identity).expect("present").group_name().to_string());
            }
            if !making.insert(identity) {
                reuse.aliases.entry(identity.to_string()).or_default().push(alias(run, identity));
                continue;
            }
            reuse.todo.push(i);
            if let Some(old) = unplanned.iter().find(|row| row.parameters == run.parameters) {
                let (Ok(was), Ok(now)) = (old.identity.parse::<RunIdentity>(), identity.parse::<RunIdentity>()) else {
                    continue;
                };
                *reuse.changed.entry(was.changes(&now)).or_default() += 1;
            }
        }
        if let (Some(refusal), false) = (version_refusal(&reuse.other_versions), accept_version) {
            return Err(OutputError::at(writer.path(), refusal));
        }
        reuse.lacking = lacking.len();
        writer.forget(&lacking)?;
        reuse.unplanned = unplanned;
        Ok(reuse)
    }

    /// What a user should know about the file's stored runs; `dropped`: whether the unplanned
    /// ones were deleted.
    pub fn notes(&self, dropped: bool) -> Vec<RunNote> {
        let mut notes = Vec::new();
        if let Some(first) = self.other_versions.first() {
            notes.push(RunNote::OtherVersions { runs: self.other_versions.len(), first: first.clone() });
        }
        for (changed, &runs) in &self.changed {
            notes.push(RunNote::IdentityChanged { runs, changed: changed.clone() });
        }
        if self.lacking > 0 {
            notes.push(RunNote::LackingOutput { runs: self.lacking });
        }
        if !self.unplanned.is_empty() {
            let ids = self.unplanned.iter().map(|r| r.id.clone()).collect();
            notes.push(RunNote::Unplanned { ids, deleted: dropped });
        }
        notes
    }
}

/// `row` as the row of the planned `run` (identity `identity`): its index, id and parameters.
fn as_planned(run: &PlannedRun, identity: &str, row: &SummaryRow) -> SummaryRow {
    SummaryRow {
        index: run.index,
        id: run.id.clone(),
        parameters: run.parameters.clone(),
        identity: identity.to_string(),
        ..row.clone()
    }
}

/// The alias of `run` (identity `identity`): a planned run that shares the identity of a run the
/// sweep makes, and gets its row (see `writer_thread`).
pub(super) fn alias(run: &PlannedRun, identity: &str) -> SummaryRow {
    as_planned(run, identity, &SummaryRow::failed(0, "", &[], ""))
}

/// The refusal of reusing runs made by other demsweep versions (`(run id, version)`), naming the
/// first run and both versions; `None` when there are none. A version that kept the physics version
/// computes the same results unless a change outside the physics (placement, measures) altered
/// them, which only the user can judge: so it is refused with the two ways on, not rerun silently
/// (which could cost days of sweeps) nor reused silently.
pub(super) fn version_refusal(other_versions: &[(String, String)]) -> Option<OutputReason> {
    let (id, version) = other_versions.first()?;
    Some(OutputReason::OtherVersions { run: id.clone(), version: version.clone(), count: other_versions.len() })
}
