//! What the search's unit tests share: an evaluator that is never called, one that only screens,
//! one that makes runs by a rule, a one-lever configuration, a reference, and runs and candidates
//! made by hand.

use crate::tune::model::{Candidate, Evaluator, Job, Origin, Outcome, Screen, SearchConfig, SearchResult, TuneError};

/// An evaluator the code under test never calls.
pub(super) struct Unused;

impl Evaluator for Unused {
    fn screen(&mut self, _: &[f64], _: Option<usize>) -> Screen {
        unreachable!()
    }
    fn reference_identity(&mut self) -> String {
        unreachable!()
    }
    fn evaluate(&mut self, _: &[Job]) -> Result<Vec<Outcome>, TuneError> {
        unreachable!()
    }
    fn step_down(&mut self, _: usize, _: f64) -> Option<usize> {
        unreachable!()
    }
}

/// An evaluator that only screens, by `screen`; standard setting 0 sits at `standard_point`.
pub(super) struct Screening<F> {
    pub(super) screen: F,
    pub(super) standard_point: Option<Vec<f64>>,
}

impl<F: FnMut(&[f64]) -> Screen> Evaluator for Screening<F> {
    fn screen(&mut self, point: &[f64], _: Option<usize>) -> Screen {
        (self.screen)(point)
    }
    fn reference_identity(&mut self) -> String {
        "reference".into()
    }
    fn evaluate(&mut self, _: &[Job]) -> Result<Vec<Outcome>, TuneError> {
        unreachable!()
    }
    fn step_down(&mut self, _: usize, _: f64) -> Option<usize> {
        unreachable!()
    }
    fn standard_point(&mut self, standard: usize) -> Option<Vec<f64>> {
        self.standard_point.clone().filter(|_| standard == 0)
    }
}

/// An evaluator whose runs `run` makes, job by job; it screens nothing, and the reference's disks
/// cannot be placed on the seeds `unplaceable` holds.
pub(super) struct Running<F> {
    pub(super) run: F,
    pub(super) unplaceable: Vec<u64>,
}

impl<F: FnMut(&Job) -> Outcome> Evaluator for Running<F> {
    fn screen(&mut self, _: &[f64], _: Option<usize>) -> Screen {
        unreachable!()
    }
    fn reference_identity(&mut self) -> String {
        "reference".into()
    }
    fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, TuneError> {
        Ok(jobs.iter().map(&mut self.run).collect())
    }
    fn step_down(&mut self, _: usize, _: f64) -> Option<usize> {
        unreachable!()
    }
    fn placeable(&mut self, seed: u64) -> bool {
        !self.unplaceable.contains(&seed)
    }
}

/// One lever, one relative tolerance of 5 %, the default seeds and spend limit.
pub(super) fn config() -> SearchConfig {
    SearchConfig {
        dims: 1,
        levels: vec![None],
        tolerances: vec![(0.05, false)],
        metrics: vec!["a kept metric".into()],
        seeds: 3,
        max_seeds: 8,
        reference_seeds: 8,
        verify_seeds: 8,
        budget: 400,
        seed: 1,
        initial: None,
        dissipation: vec![0.0],
        home: vec![None],
        standards: 0,
        path: false,
        time_step: None,
        max_spend: 20.0,
        cut_runs: true,
    }
}

/// A reference's kept metric values: mean 1, spread 0.01.
pub(super) const REFERENCE: [f64; 8] = [0.99, 1.01, 0.985, 1.015, 1.0, 1.0, 0.995, 1.005];

/// Seats the reference of [`REFERENCE`]'s values, each run costing 100, and a margin of 0.05.
pub(super) fn seat_reference(result: &mut SearchResult) {
    result.reference = runs(100.0, &REFERENCE);
    result.margins = vec![0.05];
}

/// Settled runs of one kept metric, each costing `cost`.
pub(super) fn runs(cost: f64, values: &[f64]) -> Vec<Outcome> {
    values.iter().map(|&v| Outcome::settled(cost, vec![v])).collect()
}

/// A point of the lever space with `runs`, its time step the reference's.
pub(super) fn candidate(id: usize, runs: Vec<Outcome>) -> Candidate {
    Candidate {
        id,
        point: vec![0.1 * id as f64],
        standard: None,
        identity: id.to_string(),
        origin: Origin::Initial,
        predicted_invalid: None,
        runs,
        verification: Vec::new(),
        verify_seeds: Vec::new(),
        relative_cost: Some(1.0),
        stepped_from: None,
    }
}
