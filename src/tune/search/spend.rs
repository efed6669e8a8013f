//! Whether runs fit the run budget and the spend limit, with a verification round kept in reserve.

use super::run::Search;
use crate::tune::model::{Evaluator, State};

/// A batch is priced this much above its predicted cost against the spend limit: settle times
/// spread.
pub(super) const PRICE_MARGIN: f64 = 1.1;

impl<'a, E: Evaluator> Search<'a, E> {
    /// Whether `runs` more runs predicted at `relative_cost` of a reference run each fit the run
    /// budget and the spend limit.
    pub(super) fn fits(&self, runs: usize, relative_cost: Option<f64>) -> bool {
        self.fits_price(runs, runs as f64 * relative_cost.unwrap_or(1.0))
    }

    /// Whether `runs` more runs costing `price` reference runs in all fit the run budget and the
    /// spend limit (priced [`PRICE_MARGIN`] above).
    pub(super) fn fits_price(&self, runs: usize, price: f64) -> bool {
        let reference = self.result.reference_cost();
        let price = PRICE_MARGIN * price * reference;
        self.result.runs + runs <= self.config.budget && self.spent + price <= self.config.max_spend * reference
    }

    /// [`Self::fits_price`], and within the time-step path's share of the spend while none of its
    /// rungs is valid and equivalent in the search: a path whose rungs fail ends early and leaves
    /// the rest to the other levers.
    pub(super) fn fits_path(&self, runs: usize, price: f64) -> bool {
        let reference = self.result.reference_cost();
        let result = &self.result;
        let found = result.path.0.iter().any(|&k| result.assess(&result.candidates[k]).state == State::Feasible);
        let within = found || self.spent + PRICE_MARGIN * price * reference <= self.path_limit;
        self.fits_price(runs, price) && within
    }

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
        let left = c.max_spend * reference - self.spent - c.verify_seeds as f64 * unit;
        if left > 0.0 { (left / (c.seeds as f64 * unit)).floor() as usize } else { 0 }
    }

    /// Whether candidate `k`'s first seeds fit the spend limit with room to verify it.
    pub(super) fn fits_candidate(&self, k: usize) -> bool {
        let seeds = self.config.seeds;
        self.fits_price(seeds, seeds as f64 * self.expected_cost(k) + self.reservation(k))
    }

    /// What a verification round would cost (in reference runs) when candidate `k` may be the one
    /// verified: the dearer of its round and [`Self::pending_reservation`].
    pub(super) fn reservation(&self, k: usize) -> f64 {
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
