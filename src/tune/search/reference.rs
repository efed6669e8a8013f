//! The reference's runs: the first `reference_seeds`, and more where its own spread or a chance
//! draw keeps candidates undecided.

use super::context::{Context, Flow};
use super::standing::{CLEAR_MARGIN, SEQUENTIAL_SEEDS};
use crate::stats::{self, Decision};
use crate::tune::judge::{check_figures, decidability, reference_stands_apart, runs_to_decide_with};
use crate::tune::model::{Candidate, Evaluator, Job, Outcome, State, TuneError, describe_metric};

/// More reference runs and what they are priced with.
pub(super) struct Growth {
    /// Reference runs to add.
    pub(super) runs: usize,
    /// Runs in all that the price covers (against the run budget).
    pub(super) priced_runs: usize,
    /// Their price, in reference runs.
    pub(super) price: f64,
}

/// The step: the reference runs on `reference_seeds` seeds; a kept metric its spread cannot decide
/// ([`decidability`]) stops the search.
pub(super) fn step<E: Evaluator>(cx: &mut Context<'_, E>) -> Result<Flow, TuneError> {
    let c = cx.config;
    let jobs: Vec<Job> = (0..c.reference_seeds).map(|p| Job::reference(cx.replicate(p))).collect();
    cx.seen.insert(cx.evaluator.reference_identity());
    cx.add_reference(&jobs)?;
    cx.result.undecidable = decidability(&cx.result.reference, &cx.result.margins, c.max_seeds);
    Ok(if cx.result.undecidable.is_empty() { Flow::Next } else { Flow::Stop })
}

impl<E: Evaluator> Context<'_, E> {
    /// Runs reference `jobs` and adds them to the reference's runs; the margins and the reference's
    /// validity figures follow all its runs. A run that fails stops the tune.
    fn add_reference(&mut self, jobs: &[Job]) -> Result<(), TuneError> {
        let c = self.config;
        let outcomes = self.evaluate(jobs)?;
        if let Some((job, failure)) = jobs.iter().zip(&outcomes).find_map(|(j, o)| Some((j, o.failure.clone()?))) {
            return Err(TuneError::ReferenceFailed { seed: job.seed, failure });
        }
        let outcomes: Vec<Outcome> = self.result.reference.iter().cloned().chain(outcomes).collect();
        let mut margins = Vec::new();
        for (k, &(tolerance, absolute)) in c.tolerances.iter().enumerate() {
            let values: Vec<f64> = outcomes.iter().map(|o| o.metrics[k]).collect();
            let metric = || c.metrics.get(k).cloned().unwrap_or_else(|| format!("number {}", k + 1));
            let replicates: Vec<u64> = (0..).zip(&values).filter(|(_, v)| v.is_nan()).map(|(r, _)| r).collect();
            if !replicates.is_empty() {
                return Err(TuneError::UndefinedMetric { metric: metric(), replicates, runs: values.len() });
            }
            let mean = stats::describe(&values).mean;
            let margin = if absolute { tolerance } else { tolerance * mean.abs() };
            if !(margin > 0.0 && margin.is_finite()) {
                return Err(TuneError::NoMargin { metric: metric(), mean });
            }
            margins.push(margin);
        }
        self.result.reference_checks = check_figures(&outcomes, &[]);
        self.result.reference = outcomes;
        self.result.margins = margins;
        Ok(())
    }

    /// The cheapest way to decide undecided candidate `cand` when more of its own seeds alone
    /// cannot (the reference's spread is what keeps its interval wide): `g` more reference runs (a
    /// multiple of `seeds`, the reference at most doubled) and the candidate runs in all that then
    /// decide it (at most [`SEQUENTIAL_SEEDS`] times `max_seeds`), with the price of both
    /// and of verifying it on as many fresh seeds, in reference runs. None when no growth would.
    fn reference_growth(&self, cand: &Candidate) -> Option<(usize, usize, f64)> {
        let c = self.config;
        let result = &self.result;
        let n_r = result.reference.len();
        let cost = result.assess(cand).cost / result.reference_cost();
        let most = SEQUENTIAL_SEEDS * c.max_seeds;
        (1..)
            .map(|k| k * c.seeds)
            .take_while(|&g| n_r + g <= 2 * c.reference_seeds)
            .filter_map(|g| {
                let needed = runs_to_decide_with(&result.reference, &cand.runs, &result.margins, n_r + g)?;
                let more = needed.saturating_sub(cand.runs.len());
                (needed <= most).then(|| (g, needed, g as f64 + (more + needed.max(c.verify_seeds)) as f64 * cost))
            })
            .min_by(|a, b| a.2.total_cmp(&b.2))
    }

    /// Grows the reference when that is what decides the cheapest undecided candidate that would
    /// beat the incumbent by a clear margin ([`CLEAR_MARGIN`]) and its own seeds alone
    /// cannot ([`Self::reference_growth`]), within the spend limit; whether it did. (A reference
    /// whose own mean is in doubt is grown first, by [`Self::extra_seeds`].)
    pub(super) fn grow_reference(&mut self) -> Result<bool, TuneError> {
        let result = &self.result;
        let bound = (CLEAR_MARGIN * self.incumbent().1).min(result.reference_cost());
        let growth = result
            .candidates
            .iter()
            .map(|c| (result.assess(c), c))
            .filter(|(a, c)| a.state == State::Undecided && a.cost < bound && self.more_seeds(c).is_none())
            .filter(|(a, _)| a.n >= self.config.max_seeds)
            .min_by(|x, y| x.0.cost.total_cmp(&y.0.cost))
            .and_then(|(_, c)| self.reference_growth(c));
        match growth {
            Some((g, needed, price)) => self.grow(Growth { runs: g, priced_runs: g + 2 * needed, price }),
            None => Ok(false),
        }
    }

    /// Runs `growth`'s reference runs when its price, with a further verification round of the
    /// answer so far, fits the spend limit; then judges that answer again against the whole
    /// reference ([`Self::recheck_answer`]); whether it ran them. More reference runs move the
    /// margins and the mean the answer was verified against.
    pub(super) fn grow(&mut self, growth: Growth) -> Result<bool, TuneError> {
        let (runs, price) = self.answer_round();
        if !self.fits_price(growth.priced_runs + runs, growth.price + price) {
            return Ok(false);
        }
        let first = self.result.reference.len();
        let jobs: Vec<Job> = (first..first + growth.runs).map(|p| Job::reference(self.replicate(p))).collect();
        self.add_reference(&jobs)?;
        self.recheck_answer()?;
        Ok(true)
    }

    /// `seeds` more reference runs when the reference's own mean is in doubt: it stands apart
    /// ([`reference_stands_apart`]) from the candidates whose `seeds` or more search runs all
    /// settled, on a kept metric that leaves one cheaper than the reference undecided with its
    /// difference inside the margin (past it, the candidate is likely different whatever the
    /// reference's mean). Priced with a verification round of the cheapest candidate pending; the
    /// reference at most doubled.
    pub(super) fn doubtful_reference(&self) -> Option<Growth> {
        let c = self.config;
        let result = &self.result;
        if result.reference.len() + c.seeds > 2 * c.reference_seeds {
            return None;
        }
        let settled = |cand: &&Candidate| {
            cand.runs.len() >= c.seeds && cand.runs.iter().all(|o| o.failure.is_none() && !o.metrics.is_empty())
        };
        let ran: Vec<&Candidate> = result.candidates.iter().filter(settled).collect();
        let mut open = vec![false; result.margins.len()];
        for cand in &ran {
            let a = result.assess(cand);
            if a.state == State::Undecided && a.cost < result.reference_cost() {
                for (k, test) in a.tests.iter().enumerate() {
                    open[k] |= test.decision == Decision::Undecided && test.difference.abs() < result.margins[k];
                }
            }
        }
        let means: Vec<Vec<f64>> =
            ran.iter().map(|cand| (0..result.margins.len()).map(|k| column_mean(&cand.runs, k)).collect()).collect();
        if !reference_stands_apart(&result.reference, &means, &open) {
            return None;
        }
        let (verify, price) = self.pending_reservation().map_or((0, 0.0), |p| (c.verify_seeds, p));
        Some(Growth { runs: c.seeds, priced_runs: c.seeds + verify, price: c.seeds as f64 + price })
    }
}

/// The mean of kept metric `k` over `runs`.
fn column_mean(runs: &[Outcome], k: usize) -> f64 {
    describe_metric(runs, k).mean
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tune::model::Role;
    use crate::tune::search::testing::{REFERENCE, Running, candidate, config, runs, seat_reference};

    /// An answer's eight fresh runs at 0.965, equivalent to the reference's (mean 1, margin 0.05).
    const ANSWER: [f64; 8] = [0.96, 0.97, 0.965, 0.962, 0.968, 0.964, 0.966, 0.965];

    /// Grows the reference by three runs at 1.04 (which leaves the answer at 0.965 undecided)
    /// around an answer (candidate 0, cost 40) and a dearer verified candidate 1 (cost 60, fresh
    /// runs on the reference's mean), with `spent` already spent; further fresh runs of the
    /// answer measure `again`. Whether it grew, the answer after, and the answer's fresh runs.
    fn grow_around_an_answer(spent: f64, again: f64) -> (bool, Option<usize>, usize) {
        let config = config();
        let run = |job: &Job| match job.role {
            Role::Reference => Outcome::settled(100.0, vec![1.04]),
            _ => Outcome::settled(40.0, vec![again]),
        };
        let mut evaluator = Running { run, unplaceable: Vec::new() };
        let mut cx = Context::new(&config, &mut evaluator);
        seat_reference(&mut cx.result);
        let mut answer = candidate(1, runs(40.0, &ANSWER[..3]));
        answer.verification = runs(40.0, &ANSWER);
        let mut dearer = candidate(2, runs(60.0, &REFERENCE[..3]));
        dearer.verification = runs(60.0, &REFERENCE);
        cx.result.candidates = vec![answer, dearer];
        assert_eq!(cx.result.assess_runs(&cx.result.candidates[0].verification).state, State::Feasible);
        cx.result.recommended = Some(0);
        cx.spent = spent;
        let grew = cx.grow(Growth { runs: 3, priced_runs: 3, price: 3.0 }).unwrap();
        (grew, cx.result.recommended, cx.result.candidates[0].verification.len())
    }

    #[test]
    fn an_answer_the_grown_reference_leaves_undecided_is_verified_again_and_kept_when_it_passes() {
        // Eight more fresh runs on the grown reference's mean decide it equivalent.
        assert_eq!(grow_around_an_answer(0.0, 1.01), (true, Some(0), 16));
    }

    #[test]
    fn an_answer_that_fails_against_the_grown_reference_gives_way_to_the_next_verified_candidate() {
        assert_eq!(grow_around_an_answer(0.0, 0.9), (true, Some(1), 16));
    }

    #[test]
    fn the_reference_grows_only_with_room_to_verify_the_answer_again() {
        // 600 left of 2000: three reference runs (330 with the price margin) fit, but not with a
        // further round of the answer (8 at 40: 682 in all).
        assert_eq!(grow_around_an_answer(1400.0, 1.01), (false, Some(0), 8));
        assert_eq!(grow_around_an_answer(1000.0, 1.01), (true, Some(0), 16));
    }
}
