//! Which candidates are still in the running, the incumbent, and the further seeds an undecided
//! one gets.

use super::context::Context;
use crate::tune::judge::{likely_different, runs_to_decide};
use crate::tune::model::{Candidate, Evaluator, State};

/// An undecided candidate whose mean cost is below this share of the incumbent's would win by a
/// clear margin: past `max_seeds` it gets the seeds that decide it (sequential testing).
pub(super) const CLEAR_MARGIN: f64 = 0.9;

/// A candidate decided sequentially gets at most this many times `max_seeds` search seeds.
pub(super) const SEQUENTIAL_SEEDS: usize = 4;

impl<E: Evaluator> Context<'_, E> {
    /// How many more search seeds candidate `cand` gets: an undecided one `seeds` at a time up to
    /// `max_seeds`; past that, one that would beat the incumbent by a clear margin
    /// ([`CLEAR_MARGIN`]) gets the seeds its runs so far say decide it ([`runs_to_decide`]), up to
    /// [`SEQUENTIAL_SEEDS`] times `max_seeds` and within the spend limit. None: it gets no more
    /// (decided, it cannot be, or more seeds would most likely decide it different,
    /// [`likely_different`]).
    pub(super) fn more_seeds(&self, cand: &Candidate) -> Option<usize> {
        let c = self.config;
        let a = self.result.assess(cand);
        if a.state != State::Undecided || a.n == 0 || likely_different(&a.tests, &self.result.margins) {
            return None;
        }
        if a.n < c.max_seeds {
            return Some(c.seeds.min(c.max_seeds - a.n));
        }
        if a.cost >= CLEAR_MARGIN * self.incumbent().1 {
            return None;
        }
        let needed = runs_to_decide(&self.result.reference, &cand.runs, &self.result.margins)?;
        let more = needed.saturating_sub(a.n).clamp(1, c.max_seeds);
        let price = more as f64 * a.cost / self.result.reference_cost();
        (needed <= SEQUENTIAL_SEEDS * c.max_seeds && self.fits_price(more, price)).then_some(more)
    }

    /// Whether a candidate is still in the running: feasible, or undecided with more seeds to come
    /// ([`Self::more_seeds`]); cheaper than the reference and not failed on fresh seeds.
    pub(super) fn in_running(&self, cand: &Candidate) -> bool {
        let failed = self.result.assess_verification(cand).is_some_and(|a| a.state != State::Feasible);
        let a = self.result.assess(cand);
        let open = match a.state {
            State::Feasible => true,
            State::Undecided => self.more_seeds(cand).is_some(),
            _ => false,
        };
        !failed && open && a.cost < self.result.reference_cost()
    }

    /// The mean costs of the candidates still in the running ([`Self::in_running`]).
    pub(super) fn running_costs(&self) -> Vec<f64> {
        self.running_costs_besides(None)
    }

    /// [`Self::running_costs`] of the candidates other than `skip`.
    fn running_costs_besides(&self, skip: Option<usize>) -> Vec<f64> {
        let running = self.result.candidates.iter().enumerate().filter(|&(j, c)| Some(j) != skip && self.in_running(c));
        running.map(|(_, c)| self.result.assess(c).cost).collect()
    }

    /// The mean cost of the cheapest candidate still in the running (feasible, or undecided with
    /// every run settled and valid), the reference's when none is cheaper: what the answer will
    /// likely cost.
    pub(super) fn likely_cost(&self) -> f64 {
        self.running_costs().into_iter().fold(self.result.reference_cost(), f64::min)
    }

    /// [`Self::likely_cost`] among the candidates other than `k`: the cost past which a further run
    /// of `k` could no longer win (its own mean is no bar to its own further seeds).
    pub(super) fn likely_cost_besides(&self, k: usize) -> f64 {
        self.running_costs_besides(Some(k)).into_iter().fold(self.result.reference_cost(), f64::min)
    }

    /// The cheapest feasible candidate, standard settings included, and its cost (infinite when
    /// there is none).
    pub(super) fn incumbent(&self) -> (Option<usize>, f64) {
        self.result.cheapest_feasible(|_| true)
    }

    /// Where the pattern search centres: the cheapest feasible point of the lever space, else the
    /// one closest to equivalence.
    pub(super) fn focus(&self) -> Option<usize> {
        self.result.cheapest_feasible(|c| c.standard.is_none()).0.or_else(|| self.result.closest_point())
    }
}
