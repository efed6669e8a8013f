//! Whether runs fit the run budget and the spend limit.

use super::context::Context;
use crate::tune::model::{Evaluator, SearchConfig};

/// A batch is priced this much above its predicted cost against the spend limit: settle times
/// spread.
pub const PRICE_MARGIN: f64 = 1.1;

/// Verification rounds the run budget keeps back from the search's candidates (see
/// `Context::search_end`).
pub const KEPT_ROUNDS: usize = 3;

/// A point of the lever space predicted (from its time step) to cost more than this times the
/// cheapest candidate still in the running is not run: levers that shorten settling (damping, fill
/// height) rarely take a third off the reference's settle time.
pub(super) const FAR_TOO_DEAR: f64 = 1.5;

/// The shortest settle time, as a share of the reference's, that a candidate's first seeds are cut
/// at to fit the spend limit (see `Context::first_round`): damping levers on an undamped
/// reference settle piles in about half its time. With such seeds run one at a time, a setting
/// that settles no sooner costs one cut run.
pub(super) const LEAST_SETTLE: f64 = 0.5;

impl<E: Evaluator> Context<'_, E> {
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

    /// The run count the search's candidates stop at: the budget less [`KEPT_ROUNDS`] verification
    /// rounds.
    pub(super) fn search_end(&self) -> usize {
        self.config.budget.saturating_sub(KEPT_ROUNDS * self.config.verify_seeds)
    }
}

/// What the spend limit buys before any run (see [`spend_plan`]), in reference depositions.
#[derive(Clone, Debug, PartialEq)]
pub struct SpendPlan {
    /// The reference's own runs.
    pub reference: f64,
    /// What the spend limit leaves after them.
    pub left: f64,
    /// Candidates whose first seeds that pays for at the reference's cost per run, with a
    /// verification round in reserve (priced [`PRICE_MARGIN`] above).
    pub candidates: usize,
    /// Without one: the cost per run, over the reference's, at which the first candidate's seeds are
    /// cut so that its verification still fits, when a candidate settling that soon is plausible
    /// (`LEAST_SETTLE`).
    pub cut_at: Option<f64>,
    /// The `max_spend` that pays for one candidate at the reference's cost.
    pub max_spend: f64,
    /// The most `reference_seeds` (not below the default's least) that leave room for one
    /// candidate at the reference's cost; None when even that many do not.
    pub reference_seeds: Option<usize>,
}

/// What `config`'s spend limit buys before any run: the reference's `reference_seeds` runs, then
/// candidates at the reference's cost per run, each `seeds` runs, the first with a verification
/// round of `verify_seeds` in reserve, as the search prices them.
pub fn spend_plan(config: &SearchConfig) -> SpendPlan {
    let reference = config.reference_seeds as f64;
    let left = (config.max_spend - reference).max(0.0);
    let (seeds, verify) = (config.seeds as f64, config.verify_seeds as f64);
    let first = PRICE_MARGIN * (seeds + verify);
    let candidates = if left >= first { 1 + ((left - first) / (PRICE_MARGIN * seeds)).floor() as usize } else { 0 };
    let cap = left / first;
    let least = (2 * config.seeds).max(6) as f64;
    SpendPlan {
        reference,
        left,
        candidates,
        cut_at: (candidates == 0 && config.cut_runs && cap >= LEAST_SETTLE).then_some(cap),
        max_spend: reference + first,
        reference_seeds: ((config.max_spend - first).floor() >= least).then_some((config.max_spend - first) as usize),
    }
}
