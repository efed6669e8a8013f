//! What every step of the search shares: the configuration, the evaluator that runs batches, the
//! candidate table (the result so far) and the spend and fresh seeds drawn on; and the shape of a
//! step.

use crate::tune::model::{
    Evaluator, Job, Outcome, PathEnd, SearchConfig, SearchEnd, SearchResult, TuneError, first_verification_seed,
};
use std::collections::{HashMap, HashSet};

/// One step of the search's order of work: it reads and adds to the context, and says whether the
/// search goes on.
pub(super) type Step<E> = fn(&mut Context<'_, E>) -> Result<Flow, TuneError>;

/// Whether the search goes on after a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Flow {
    Next,
    Stop,
}

/// The search's shared state.
pub(super) struct Context<'a, E> {
    pub(super) config: &'a SearchConfig,
    pub(super) evaluator: &'a mut E,
    /// The candidate table, the reference's runs and the answer so far.
    pub(super) result: SearchResult,
    /// The identities of the settings proposed so far (the reference's included).
    pub(super) seen: HashSet<String>,
    /// Cost of every run so far.
    pub(super) spent: f64,
    /// The next fresh seed of a verification.
    pub(super) next_seed: u64,
    /// Per candidate id: the cost cap of its first seeds where they fit the spend limit only cut
    /// ([`Context::first_round`]).
    pub(super) first_caps: HashMap<usize, f64>,
    /// The cheap corner's candidate, once proposed, if it was a new runnable one.
    pub(super) corner: Option<usize>,
}

impl<'a, E: Evaluator> Context<'a, E> {
    pub(super) fn new(config: &'a SearchConfig, evaluator: &'a mut E) -> Self {
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
            replicates: Vec::new(),
            unplaceable: Vec::new(),
        };
        Self {
            config,
            evaluator,
            result,
            seen: HashSet::new(),
            spent: 0.0,
            next_seed: first_verification_seed(config.budget, config.reference_seeds),
            first_caps: HashMap::new(),
            corner: None,
        }
    }

    /// Runs a batch, counting its runs and cost.
    pub(super) fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, TuneError> {
        let outcomes = self.evaluator.evaluate(jobs)?;
        self.result.runs += jobs.len();
        self.spent += outcomes.iter().map(|o| o.cost).sum::<f64>();
        Ok(outcomes)
    }
}
