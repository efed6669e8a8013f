//! Batches of search runs: a candidate's further seeds, cut where they can no longer win.

use super::context::Context;
use super::spend::FAR_TOO_DEAR;
use crate::stats;
use crate::tune::model::{Candidate, Evaluator, Job, Role, TuneError};

impl<E: Evaluator> Context<'_, E> {
    /// Runs candidate `k`'s first seeds when they fit the spend limit with room to verify it (cut
    /// where only that fits, [`Self::first_round`]); whether they ran.
    pub(super) fn run_first(&mut self, k: usize) -> Result<bool, TuneError> {
        let Some(round) = self.fits_candidate(k) else { return Ok(false) };
        self.cut_first_seeds(k, round);
        self.run_more(&[(k, self.config.seeds)])?;
        Ok(true)
    }

    /// The cost past which a further run of `cand` (which will then have `more` further runs)
    /// proves that it cannot beat the incumbent (the reference itself while there is none): with
    /// every other run costing nothing, its mean would still reach the incumbent's.
    ///
    /// A new candidate predicted dearer (see [`Candidate::relative_cost`]) than the cheapest one
    /// still in the running ([`Self::likely_cost`]: the incumbent, a valid undecided candidate or
    /// the reference) is expected to lose: its first run is stopped as soon as it alone costs that
    /// much and twice a run's seed-to-seed spread more ([`Self::probe_cap`]), the point where the
    /// prediction is confirmed (a run that settles sooner than the reference's, e.g. with more
    /// damping, still ends below it and counts).
    ///
    /// First seeds that fit the spend limit only cut ([`Self::first_round`]) are cut there too, all
    /// `seeds` of them.
    pub(super) fn cap(&self, cand: &Candidate, more: usize) -> Option<f64> {
        let spend = self.first_caps.get(&cand.id).copied().filter(|_| cand.runs.len() < self.config.seeds);
        let win = self.win_cap(cand, more);
        win.map_or(spend, |w| Some(spend.map_or(w, |s| s.min(w))))
    }

    fn win_cap(&self, cand: &Candidate, more: usize) -> Option<f64> {
        if cand.runs.is_empty() && self.predicted_dear(cand) {
            return self.config.cut_runs.then(|| self.probe_cap());
        }
        let incumbent = self.incumbent().1;
        let spent: f64 = cand.runs.iter().map(|o| o.cost).sum();
        self.config.cut_runs.then(|| (cand.runs.len() + more) as f64 * incumbent - spent).filter(|c| c.is_finite())
    }

    /// The cost at which a single run shows its setting dearer than the cheapest one still in the
    /// running ([`Self::likely_cost`]): that cost plus twice a run's seed-to-seed spread (the
    /// reference runs' coefficient of variation), at most [`FAR_TOO_DEAR`] times it. A run of a
    /// setting as cheap passes it about once in 40; at the mean itself, a setting 10 % cheaper
    /// would be cut on one run in four.
    fn probe_cap(&self) -> f64 {
        let costs = stats::describe(&self.result.reference_costs());
        let spread = if costs.std.is_finite() { costs.std / costs.mean } else { 0.0 };
        self.likely_cost() * (1.0 + 2.0 * spread).min(FAR_TOO_DEAR)
    }

    /// Runs `more` further search seeds of each candidate, as one batch; a new candidate predicted
    /// dearer than the cheapest one in the running ([`Self::predicted_dear`]), or whose first seeds
    /// fit the spend limit only cut, first runs one seed alone, and the rest only when that run
    /// ended below its cap and valid: a cut run tells the others' fate at a third of the spend.
    pub(super) fn run_more(&mut self, chosen: &[(usize, usize)]) -> Result<(), TuneError> {
        let probe = |s: &Self, k: usize| {
            let cand = &s.result.candidates[k];
            cand.runs.is_empty() && (s.predicted_dear(cand) || s.first_caps.contains_key(&cand.id))
        };
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
            let first = self.result.candidates[k].runs.len();
            let seeds: Vec<u64> = (first..first + more).map(|p| self.replicate(p)).collect();
            let cand = &self.result.candidates[k];
            let cap = cap.unwrap_or_else(|| self.cap(cand, more));
            jobs.extend(seeds.into_iter().map(|seed| Job {
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tune::search::testing::{Unused, config, runs};

    /// The probe cap with the reference's runs costing `costs` and no candidate yet.
    fn probe_cap(costs: &[f64]) -> f64 {
        let config = config();
        let mut evaluator = Unused;
        let mut cx = Context::new(&config, &mut evaluator);
        cx.result.reference = costs.iter().flat_map(|&c| runs(c, &[1.0])).collect();
        cx.result.margins = vec![0.05];
        cx.probe_cap()
    }

    #[test]
    fn a_probe_is_cut_twice_a_runs_spread_past_the_cheapest_cost_and_at_most_half_again() {
        // Mean 100, standard deviation 7.07: a run of a setting as cheap ends below 114.1.
        let cap = probe_cap(&[90.0, 110.0, 95.0, 105.0, 100.0, 100.0]);
        assert!((cap - (100.0 + 2.0 * 50f64.sqrt())).abs() < 1e-9, "{cap}");
        assert_eq!(probe_cap(&[100.0; 6]), 100.0, "no spread: the cost itself");
        assert_eq!(probe_cap(&[40.0, 160.0, 100.0]), 150.0, "a wide spread: at most 1.5 times");
    }
}
