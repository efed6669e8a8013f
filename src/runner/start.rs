//! What a sweep starts from: the runs it selects, those already stored and those to make.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::checkpoints::Checkpointing;
use super::notes::RunNote;
use super::{RunOptions, results_path, reuse, shard};
use crate::output::SummaryRow;
use crate::output::lock::ResultsLock;
use crate::study::{Plan, RunIdentity};

/// The runs of a sweep: those it selects (the plan, or a shard), those already stored (their rows),
/// those to make, and what the results file, when there is one, needs while they run (its lock, the
/// checkpoints beside it). Made by [`super::open_results`], or by [`Start::fresh`] for a sweep into
/// sinks alone.
pub struct Start {
    /// The results file (where it goes when no sink writes it).
    pub(super) results: PathBuf,
    /// The results file's lock, held until the sweep ends.
    pub(super) lock: Option<ResultsLock>,
    /// When the sweep started.
    pub(super) started: Instant,
    /// The plan indices of the selected runs.
    pub(super) selected: Vec<usize>,
    /// The identity of every planned run, by plan index.
    pub(super) identities: Vec<String>,
    /// Rows of the selected runs already stored.
    pub(super) stored: Vec<SummaryRow>,
    /// Plan indices of the runs to make, one per identity.
    pub(super) todo: Vec<usize>,
    /// Planned runs that share the identity of a run to make, by identity.
    pub(super) aliases: HashMap<String, Vec<SummaryRow>>,
    /// What was found in the results file and done about it.
    pub(super) notes: Vec<RunNote>,
    /// The checkpoints of the runs, beside the results file.
    pub(super) checkpointing: Option<Checkpointing>,
}

impl Start {
    /// The selected runs of `plan` (the shard of `options`), none stored: a sweep whose sinks are
    /// all the caller's, with no results file, lock or checkpoints.
    pub fn fresh(plan: &Plan, options: &RunOptions) -> Self {
        let started = Instant::now();
        let selected = selected(plan, options);
        let identities = identities(plan);
        let (mut todo, mut aliases) = (Vec::new(), HashMap::<String, Vec<SummaryRow>>::new());
        let mut making = HashSet::new();
        for &i in &selected {
            let identity = identities[i].as_str();
            match making.insert(identity) {
                true => todo.push(i),
                false => aliases.entry(identity.to_string()).or_default().push(reuse::alias(&plan.runs[i], identity)),
            }
        }
        Self {
            results: results_path(plan, options),
            lock: None,
            started,
            selected,
            identities,
            stored: Vec::new(),
            todo,
            aliases,
            notes: Vec::new(),
            checkpointing: None,
        }
    }

    /// The results file.
    pub fn results(&self) -> &Path {
        &self.results
    }
}

/// The plan indices of the runs a sweep of `plan` with `options` selects: all, or its shard's.
pub(super) fn selected(plan: &Plan, options: &RunOptions) -> Vec<usize> {
    match options.shard {
        Some(spec) => shard::select(plan, spec),
        None => (0..plan.runs.len()).collect(),
    }
}

/// The identity of every run of `plan`, as text, by plan index.
pub(super) fn identities(plan: &Plan) -> Vec<String> {
    RunIdentity::all(&plan.runs).iter().map(ToString::to_string).collect()
}
