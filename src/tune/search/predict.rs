//! A setting's cost before it runs: its time step's cost times the settle time the runs so far
//! predict.

use super::context::Context;
use super::spend::FAR_TOO_DEAR;
use crate::stats::{self, fit};
use crate::tune::design;
use crate::tune::judge::predicted_breach;
use crate::tune::model::{Candidate, Evaluator, Screen};

impl<E: Evaluator> Context<'_, E> {
    /// A candidate's predicted cost in reference runs: its time step's
    /// ([`Candidate::relative_cost`]) times the settle time the settled runs so far predict at its
    /// point (the log-linear fit of measured cost over predicted, [`Self::settle_fit`]; without
    /// one, the mean settle time measured, else the reference's).
    pub(super) fn expected_cost(&self, k: usize) -> f64 {
        let cand = &self.result.candidates[k];
        let factors: Vec<f64> = self.settle_factors().into_iter().map(|(_, f)| f).collect();
        let mean = if factors.is_empty() { 1.0 } else { stats::describe(&factors).mean };
        let settle = match (self.settle_fit(), cand.standard) {
            (Some(b), None) => (b[0] + cand.point.iter().zip(&b[1..]).map(|(x, c)| x * c).sum::<f64>()).exp(),
            _ => mean,
        };
        cand.relative_cost.unwrap_or(1.0) * settle.clamp(0.05, 20.0)
    }

    /// The least any runnable setting may cost in reference runs: the cheapest time step of those
    /// proposed (the cheap corner's, once proposed) at the shortest settle time measured so far.
    pub(super) fn least_cost(&self) -> f64 {
        let runnable = self.result.candidates.iter().filter(|c| c.predicted_invalid.is_none());
        runnable.map(|c| self.optimistic_cost(c)).fold(self.optimistic_cost_at(1.0), f64::min)
    }

    /// The least a candidate may cost in reference runs: its time step's cost at the shortest
    /// settle time measured so far (relative to the reference's, at most 1).
    fn optimistic_cost(&self, cand: &Candidate) -> f64 {
        self.optimistic_cost_at(cand.relative_cost.unwrap_or(1.0))
    }

    /// [`Self::optimistic_cost`] of a setting whose time step costs `relative_cost`.
    fn optimistic_cost_at(&self, relative_cost: f64) -> f64 {
        let fastest = self.settle_factors().into_iter().map(|(_, f)| f).fold(1.0, f64::min);
        relative_cost * fastest
    }

    /// Per settled candidate (every run settled): its point and its mean cost over its time step's
    /// predicted cost, the settle time relative to the reference's.
    fn settle_factors(&self) -> Vec<(Vec<f64>, f64)> {
        let reference = self.result.reference_cost();
        self.result
            .candidates
            .iter()
            .filter(|c| !c.runs.is_empty() && c.runs.iter().all(|o| o.failure.is_none()))
            .map(|c| {
                let mean = c.runs.iter().map(|o| o.cost).sum::<f64>() / c.runs.len() as f64;
                (c.point.clone(), mean / (reference * c.relative_cost.unwrap_or(1.0)))
            })
            .collect()
    }

    /// The log-linear fit of the settle factors ([`Self::settle_factors`]) over the points of the
    /// lever space.
    pub(super) fn settle_fit(&self) -> Option<Vec<f64>> {
        let rows: Vec<(Vec<f64>, f64)> =
            self.settle_factors().into_iter().filter(|(p, _)| p.len() == self.config.dims).collect();
        fit::log_linear(&rows, self.config.dims)
    }

    /// Per lever: the log of the predicted cost at the top of its range over that at the bottom
    /// (the other levers at the centre), from the time steps the two settings resolve to; 0 where
    /// either cannot be predicted.
    pub(super) fn time_step_slopes(&mut self) -> Vec<f64> {
        let dims = self.config.dims;
        (0..dims)
            .map(|d| {
                let mut cost = |u: f64| {
                    let mut point = vec![0.5; dims];
                    point[d] = u;
                    self.evaluator.screen(&design::snap(&point, &self.config.levels), None).relative_cost
                };
                match (cost(0.0), cost(1.0)) {
                    (Some(low), Some(high)) if low > 0.0 && high > 0.0 => (high / low).ln(),
                    _ => 0.0,
                }
            })
            .collect()
    }

    /// Whether candidate `k` is predicted ([`Candidate::relative_cost`]) to cost more than
    /// [`FAR_TOO_DEAR`] times the cheapest candidate still in the running: it would have to settle
    /// in a third less time than the reference to win, so it is recorded and not run.
    pub(super) fn far_too_dear(&self, k: usize) -> bool {
        let reference = self.result.reference_cost();
        let cand = &self.result.candidates[k];
        cand.relative_cost.is_some() && self.optimistic_cost(cand) * reference > FAR_TOO_DEAR * self.likely_cost()
    }

    /// Whether `cand` is predicted dearer than the cheapest candidate still in the running, even at
    /// the shortest settle time measured so far.
    pub(super) fn predicted_dear(&self, cand: &Candidate) -> bool {
        let reference = self.result.reference_cost();
        self.config.cut_runs
            && cand.relative_cost.is_some()
            && self.optimistic_cost(cand) * reference > self.likely_cost()
    }

    /// Whether a screened setting starts and is predicted to break no limit beyond what the
    /// reference's own runs are held to.
    pub(super) fn predicted_valid(&self, screen: &Screen) -> bool {
        matches!(&screen.predicted, Ok(w) if predicted_breach(w, &self.result.reference_checks).is_none())
    }
}
