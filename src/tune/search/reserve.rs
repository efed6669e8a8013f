//! The spend kept in reserve: how many candidates the spend limit leaves room for, how a
//! candidate's first seeds fit with room to verify it, and what a pending verification may cost.

use super::context::Context;
use super::spend::{LEAST_SETTLE, PRICE_MARGIN};
use crate::tune::model::{Evaluator, State};

/// How a candidate's first seeds fit the run budget and the spend limit with room to verify it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum FirstRound {
    /// At the candidate's predicted cost.
    Whole,
    /// Only with each run cut at this cost (see [`Context::first_round`]).
    Cut(f64),
}

impl<E: Evaluator> Context<'_, E> {
    /// How many more candidates (at `seeds` runs each) the spend limit leaves room for, keeping a
    /// verification round of the candidate that would be verified. Runs are priced at the cheapest
    /// candidate still in the running, else at the least a runnable candidate may cost
    /// ([`Self::least_cost`]): a gate; each candidate is priced on its own when it runs
    /// ([`Self::evaluate_new`]).
    pub(super) fn affordable(&self) -> usize {
        let c = self.config;
        let reference = self.result.reference_cost();
        let running = self.running_costs().into_iter().reduce(f64::min);
        let unit = running.unwrap_or_else(|| self.least_cost() * reference);
        let count = |unit: f64| {
            let left = c.max_spend * reference - self.spent - c.verify_seeds as f64 * unit;
            if left > 0.0 { (left / (c.seeds as f64 * unit)).floor() as usize } else { 0 }
        };
        // First seeds are information: a round cut where it leaves room to verify it
        // ([`Self::first_round`]) is one more candidate.
        match count(unit) {
            0 if c.cut_runs => count(unit * LEAST_SETTLE).min(1),
            n => n,
        }
    }

    /// Whether candidate `k`'s first seeds fit the spend limit with room to verify it, and the cost
    /// cap of each of those runs (see [`Self::first_round`]).
    pub(super) fn fits_candidate(&self, k: usize) -> Option<FirstRound> {
        self.first_round(k, 0, 0.0, self.expected_cost(k))
    }

    /// How candidate `k`'s first seeds, after `runs` runs priced at `price` reference runs already
    /// chosen for the batch, fit the run budget and the spend limit with room to verify it: whole at
    /// its predicted cost `per_run` (reference runs); else cut, each run at the most it may cost for
    /// the round and its verification at that cost to fit, when that is at least its time step's cost
    /// times [`LEAST_SETTLE`] (a setting that settles sooner than that is rare): first seeds are
    /// information, and a candidate that settles soon enough is verified within the
    /// spend; None when neither fits.
    pub(super) fn first_round(&self, k: usize, runs: usize, price: f64, per_run: f64) -> Option<FirstRound> {
        let c = self.config;
        let runs = runs + c.seeds;
        let seeds = c.seeds as f64;
        if self.fits_price(runs, price + seeds * per_run + self.reservation(k)) {
            return Some(FirstRound::Whole);
        }
        let reference = self.result.reference_cost();
        let left = (c.max_spend * reference - self.spent) / (PRICE_MARGIN * reference) - price;
        let pending = self.pending_reservation().unwrap_or(0.0);
        let cap = (left / (seeds + c.verify_seeds as f64)).min((left - pending) / seeds);
        let floor = self.result.candidates[k].relative_cost.unwrap_or(1.0) * LEAST_SETTLE;
        let fits = c.cut_runs && cap >= floor && self.result.runs + runs <= c.budget;
        fits.then_some(FirstRound::Cut(cap * reference))
    }

    /// Records the cut of candidate `k`'s first seeds, where its first round is [`FirstRound::Cut`].
    pub(super) fn cut_first_seeds(&mut self, k: usize, round: FirstRound) {
        if let FirstRound::Cut(cap) = round {
            self.first_caps.insert(self.result.candidates[k].id, cap);
        }
    }

    /// What a verification round would cost (in reference runs) when candidate `k` may be the one
    /// verified: the dearer of its round and [`Self::pending_reservation`].
    fn reservation(&self, k: usize) -> f64 {
        let seeds = self.config.verify_seeds;
        let own = seeds as f64 * self.expected_cost(k);
        self.pending_reservation().map_or(own, |pending| own.max(pending))
    }

    /// What verifying a candidate in the running not yet verified may cost (in reference runs, on
    /// as many seeds as its search runs, at least `verify_seeds`): the dearer of the cheapest one's
    /// round (verified first) and the cheapest feasible one's (the answer when the cheaper ones
    /// fail).
    pub(super) fn pending_reservation(&self) -> Option<f64> {
        let rounds = [self.cheapest_pending(false, None), self.cheapest_pending(true, None)];
        rounds.into_iter().flatten().map(|(_, price)| price).reduce(f64::max)
    }

    /// The verification round (runs, price in reference runs: on as many seeds as its search runs,
    /// at least `verify_seeds`) of the cheapest candidate in the running not yet verified, other
    /// than `except`; with `feasible_only`, of the cheapest feasible one.
    pub(super) fn cheapest_pending(&self, feasible_only: bool, except: Option<usize>) -> Option<(usize, f64)> {
        let reference = self.result.reference_cost();
        let seeds = self.config.verify_seeds;
        self.result
            .candidates
            .iter()
            .enumerate()
            .filter(|&(j, c)| Some(j) != except && c.verification.is_empty() && self.in_running(c))
            .map(|(_, c)| (self.result.assess(c), c.runs.len().max(seeds)))
            .filter(|(a, _)| !feasible_only || a.state == State::Feasible)
            .min_by(|a, b| a.0.cost.total_cmp(&b.0.cost))
            .map(|(a, n)| (n, a.cost / reference * n as f64))
    }
}
