//! The search's state, its start and its order of work ([`search`]), and the batch that every run
//! goes through.

use crate::physics::rng::Rng;
use crate::tune::design::PRIMES;
use crate::tune::judge::decidability;
use crate::tune::model::{
    Evaluator, Job, Origin, Outcome, PathEnd, SearchConfig, SearchEnd, SearchResult, TuneError, first_verification_seed,
};
use std::collections::{HashMap, HashSet};

/// Runs the search.
pub fn search<E: Evaluator>(config: &SearchConfig, evaluator: &mut E) -> Result<SearchResult, TuneError> {
    Search::new(config, evaluator).run()
}

pub(super) struct Search<'a, E> {
    pub(super) config: &'a SearchConfig,
    pub(super) evaluator: &'a mut E,
    pub(super) result: SearchResult,
    pub(super) seen: HashSet<String>,
    pub(super) shift: Vec<f64>,
    pub(super) halton_index: u64,
    /// Cost of every run so far.
    pub(super) spent: f64,
    /// The next fresh seed of a verification.
    pub(super) next_seed: u64,
    /// The most the spend may reach while the time-step path runs (cost units).
    pub(super) path_limit: f64,
    /// The cheap corner once proposed: its candidate, if it was a new runnable one.
    pub(super) corner: Option<Option<usize>>,
    /// The cost of the cheap corner's time step
    /// ([`Candidate::relative_cost`](crate::tune::model::Candidate::relative_cost)), as the
    /// time-step path starts.
    pub(super) corner_cost: Option<f64>,
    /// Per candidate id: the cost cap of its first seeds where they fit the spend limit only cut
    /// ([`Search::first_round`]).
    pub(super) first_caps: HashMap<usize, f64>,
}

/// More reference runs and what they are priced with.
pub(super) struct Growth {
    /// Reference runs to add.
    pub(super) runs: usize,
    /// Runs in all that the price covers (against the run budget).
    pub(super) priced_runs: usize,
    /// Their price, in reference runs.
    pub(super) price: f64,
}

/// What the time-step path does next.
pub(super) enum PathStep {
    /// Run (or judge) the rung at this factor of the first rung's time step, stepped down from that
    /// candidate when it cures one.
    Rung(f64, Option<usize>),
    /// Verify this rung (candidate index).
    Verify(usize),
    /// It is over.
    End(PathEnd),
}

impl<'a, E: Evaluator> Search<'a, E> {
    pub(super) fn new(config: &'a SearchConfig, evaluator: &'a mut E) -> Self {
        // The search's only randomness: the Halton sequence's random shift.
        let mut rng = Rng::new(config.seed ^ 0x7475_6e65);
        let shift = (0..config.dims).map(|_| rng.unit()).collect();
        let result = SearchResult {
            reference: Vec::new(),
            margins: Vec::new(),
            reference_checks: Vec::new(),
            candidates: Vec::new(),
            recommended: None,
            runs: 0,
            budget: config.budget,
            undecidable: Vec::new(),
            path: (Vec::new(), PathEnd::NotRun),
            end: SearchEnd::NotSearched,
            wall_rates: Vec::new(),
        };
        let next_seed = first_verification_seed(config.budget, config.reference_seeds);
        Self {
            config,
            evaluator,
            result,
            seen: HashSet::new(),
            shift,
            halton_index: 1,
            spent: 0.0,
            next_seed,
            path_limit: f64::INFINITY,
            corner: None,
            corner_cost: None,
            first_caps: HashMap::new(),
        }
    }

    pub(super) fn run(mut self) -> Result<SearchResult, TuneError> {
        let c = self.config;
        assert!(c.dims <= PRIMES.len(), "at most {} levers", PRIMES.len());
        self.reference()?;
        self.result.undecidable = decidability(&self.result.reference, &self.result.margins, c.max_seeds);
        if !self.result.undecidable.is_empty() {
            return Ok(self.result);
        }
        self.path()?;
        self.explore_ladder()?;
        let search_end = c.budget.saturating_sub(3 * c.verify_seeds);
        let room = (search_end.saturating_sub(self.result.runs)) / (2 * c.seeds);
        let initial = c.initial.unwrap_or((2 * c.dims + 2).max(6)).min(room).min(self.affordable());
        self.result.end = if initial > 0 {
            let mut fresh = self.explore(initial.max(2), Origin::Initial);
            // The corner, when the standard settings' turn left no room to run it.
            fresh.extend(self.cheap_corner().filter(|&k| self.result.candidates[k].runs.is_empty()));
            self.evaluate_new(&fresh, search_end)?;
            self.pattern_search(search_end)?
        } else {
            self.stopped(search_end)
        };
        self.verify(|_| true)?;
        Ok(self.result)
    }

    /// Runs a batch, counting its runs and cost.
    pub(super) fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, TuneError> {
        let outcomes = self.evaluator.evaluate(jobs)?;
        self.result.runs += jobs.len();
        self.spent += outcomes.iter().map(|o| o.cost).sum::<f64>();
        Ok(outcomes)
    }
}
