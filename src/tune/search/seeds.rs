//! Seeds where they decide: which candidates are still in the running, the further seeds an
//! undecided one gets, and the cost caps of runs that can no longer win.

use super::run::Search;
use crate::tune::judge::{likely_different, runs_to_decide};
use crate::tune::model::{Candidate, Evaluator, Job, Role, State, TuneError};

/// An undecided candidate whose mean cost is below this share of the incumbent's would win by a
/// clear margin: past `max_seeds` it gets the seeds that decide it (sequential testing).
pub(super) const CLEAR_MARGIN: f64 = 0.9;

/// A candidate decided sequentially gets at most this many times `max_seeds` search seeds.
pub(super) const SEQUENTIAL_SEEDS: usize = 4;

impl<'a, E: Evaluator> Search<'a, E> {
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
        let running = self.result.candidates.iter().filter(|c| self.in_running(c));
        running.map(|c| self.result.assess(c).cost).collect()
    }

    /// Gives more seeds to undecided candidates that could still win, after more reference runs
    /// where the reference's own mean is in doubt ([`Self::doubtful_reference`]); false when there
    /// are none.
    pub(super) fn extra_seeds(&mut self, end: usize) -> Result<bool, TuneError> {
        if let Some(growth) = self.doubtful_reference()
            && self.grow(growth)?
        {
            return Ok(true);
        }
        let (_, incumbent_cost) = self.incumbent();
        let reference = self.result.reference_cost();
        let (mut chosen, mut runs, mut price) = (Vec::new(), 0, 0.0);
        for (k, cand) in self.result.candidates.iter().enumerate() {
            let a = self.result.assess(cand);
            let Some(more) = self.more_seeds(cand).filter(|_| a.cost < incumbent_cost) else { continue };
            let cost = more as f64 * a.cost / reference;
            let own = (a.n + more).max(self.config.verify_seeds) as f64 * a.cost / reference;
            let reserve = own.max(self.pending_reservation().unwrap_or(0.0));
            if self.result.runs + runs + more <= end && self.fits_price(runs + more, price + cost + reserve) {
                chosen.push((k, more));
                (runs, price) = (runs + more, price + cost);
            }
        }
        if chosen.is_empty() {
            return self.grow_reference();
        }
        self.run_more(&chosen)?;
        Ok(true)
    }

    /// The cost past which a further run of `cand` (which will then have `more` further runs)
    /// proves that it cannot beat the incumbent (the reference itself while there is none): with
    /// every other run costing nothing, its mean would still reach the incumbent's.
    ///
    /// A new candidate predicted dearer (see [`Candidate::relative_cost`]) than the cheapest one
    /// still in the running ([`Self::likely_cost`]: the incumbent, a valid undecided candidate or
    /// the reference) is expected to lose: its first run is stopped as soon as it alone costs that
    /// much, the point where the prediction is confirmed (a run that settles sooner than the
    /// reference's, e.g. with more damping, still ends below it and counts).
    ///
    /// First seeds that fit the spend limit only cut ([`Self::first_round`]) are cut there too.
    pub(super) fn cap(&self, cand: &Candidate, more: usize) -> Option<f64> {
        let spend = self.first_caps.get(&cand.id).copied().filter(|_| cand.runs.is_empty());
        let win = self.win_cap(cand, more);
        win.map_or(spend, |w| Some(spend.map_or(w, |s| s.min(w))))
    }

    fn win_cap(&self, cand: &Candidate, more: usize) -> Option<f64> {
        if cand.runs.is_empty() && self.predicted_dear(cand) {
            return self.config.cut_runs.then_some(self.likely_cost());
        }
        let incumbent = self.incumbent().1;
        let spent: f64 = cand.runs.iter().map(|o| o.cost).sum();
        self.config.cut_runs.then(|| (cand.runs.len() + more) as f64 * incumbent - spent).filter(|c| c.is_finite())
    }

    /// Runs `more` further search seeds of each candidate, as one batch; a new candidate predicted
    /// dearer than the cheapest one in the running ([`Self::predicted_dear`]) first runs one seed
    /// alone, and the rest only when that run ended below its cap and valid.
    pub(super) fn run_more(&mut self, chosen: &[(usize, usize)]) -> Result<(), TuneError> {
        let probe =
            |s: &Self, k: usize| s.result.candidates[k].runs.is_empty() && s.predicted_dear(&s.result.candidates[k]);
        let probes: Vec<(usize, usize)> =
            chosen.iter().filter(|&&(k, more)| more > 1 && probe(self, k)).map(|&(k, _)| (k, 1)).collect();
        if probes.is_empty() {
            return self.run_batch(chosen, None);
        }
        self.run_batch(&probes, None)?;
        let rest: Vec<(usize, usize)> = chosen
            .iter()
            .filter_map(|&(k, more)| match probes.iter().any(|&(p, _)| p == k) {
                true if self.result.candidates[k].runs.iter().any(|o| o.failure.is_some() || o.has_warning()) => None,
                true => Some((k, more - 1)),
                false => Some((k, more)),
            })
            .collect();
        self.run_batch(&rest, None)
    }

    /// Runs `more` further search seeds of each candidate, as one batch, cut at `cap` when given,
    /// else at [`Self::cap`].
    pub(super) fn run_batch(&mut self, chosen: &[(usize, usize)], cap: Option<Option<f64>>) -> Result<(), TuneError> {
        let mut jobs = Vec::new();
        for &(k, more) in chosen {
            let cand = &self.result.candidates[k];
            let cap = cap.unwrap_or_else(|| self.cap(cand, more));
            let first = cand.runs.len() as u64;
            jobs.extend((first..first + more as u64).map(|seed| Job {
                candidate: cand.id,
                point: cand.point.clone(),
                role: Role::Search,
                seed,
                standard: cand.standard,
                cap,
            }));
        }
        if jobs.is_empty() {
            return Ok(());
        }
        let outcomes = self.evaluate(&jobs)?;
        for (job, outcome) in jobs.iter().zip(outcomes) {
            self.result.candidates[job.candidate - 1].runs.push(outcome);
        }
        Ok(())
    }

    /// The mean cost of the cheapest candidate still in the running (feasible, or undecided with
    /// every run settled and valid), the reference's when none is cheaper: what the answer will
    /// likely cost.
    pub(super) fn likely_cost(&self) -> f64 {
        self.running_costs().into_iter().fold(self.result.reference_cost(), f64::min)
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
