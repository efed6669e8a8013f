//! Verification on fresh seeds, judged on those runs alone, and the answer: the cheapest verified
//! candidate that saves something.

use super::context::{Context, Flow};
use super::standing::CLEAR_MARGIN;
use crate::stats;
use crate::tune::judge::runs_to_decide;
use crate::tune::model::{Candidate, Evaluator, Job, Role, State, TuneError, describe_metric};
use std::collections::HashSet;

/// Most verification rounds of one candidate.
const VERIFY_ROUNDS: usize = 4;

/// After the search, a candidate is verified only when its search cost is below this share of the
/// answer's verified cost: search costs, the cheapest of many on a few seeds, come out dearer on
/// fresh seeds, and a round measures a cost to several percent, so a candidate nearer than this
/// saves nothing a round can show, spends the round and, the last round being the one that fits
/// least, may take the spend past its limit (results/bench/tune.md).
const LEAST_SAVING: f64 = 0.95;

/// How far a verification step goes.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Until {
    /// Until one candidate passes and becomes the answer.
    Answer,
    /// As [`Until::Answer`], among the candidates cheaper than the answer so far by a clear margin
    /// ([`CLEAR_MARGIN`]).
    ClearlyCheaper,
    /// Until the spend ends or no candidate cheaper than the answer by [`LEAST_SAVING`] is left: the
    /// answer is the cheapest verified candidate, and the spend a search leaves over pays for the
    /// cheaper ones.
    Spent,
}

impl Until {
    /// The share of the answer's verified cost below which a candidate's search cost must lie to be
    /// verified in this step.
    pub(super) fn share(self) -> f64 {
        match self {
            Until::Answer => 1.0,
            Until::ClearlyCheaper => CLEAR_MARGIN,
            Until::Spent => LEAST_SAVING,
        }
    }
}

/// The step before the exploration, where a standard setting is feasible: among what has run (the
/// standard settings and the cheap corner), the candidate whose verification most likely saves most
/// verified, when cheaper than the answer so far. A feasible corner cheaper than the standard
/// settings is the likelier answer, and verifying a dearer standard setting first may leave no
/// spend to verify it. Without a feasible standard setting, the design's first seeds run first.
pub(super) fn before_search<E: Evaluator>(cx: &mut Context<'_, E>) -> Result<Flow, TuneError> {
    if cx.result.best_standard().is_some() {
        cx.verify(|_| true, Until::Answer)?;
    }
    Ok(Flow::Next)
}

/// The last step: the candidates cheaper than the answer so far verified, while the spend lasts.
pub(super) fn all<E: Evaluator>(cx: &mut Context<'_, E>) -> Result<Flow, TuneError> {
    cx.verify(|_| true, Until::Spent)?;
    Ok(Flow::Next)
}

impl<E: Evaluator> Context<'_, E> {
    /// The chance that a feasible candidate passes a verification round: per kept metric, that the
    /// difference its fresh runs show, plus the 90 % interval half-width expected of them against
    /// the reference, stays inside 0.9 of the margin (the search's winners look better than they
    /// are: the 0.9 allows for that); the product over the metrics. The fresh runs' mean is
    /// predicted from the search runs': around their mean, with their spread over both counts
    /// (Student's t on the search runs' degrees of freedom).
    fn pass_chance(&self, cand: &Candidate) -> f64 {
        let n_v = self.config.verify_seeds.max(cand.runs.len()) as f64;
        let reference = &self.result.reference;
        (0..self.result.margins.len())
            .map(|k| {
                let (r, c) = (describe_metric(reference, k), describe_metric(&cand.runs, k));
                let se = (c.std * c.std / n_v + r.std * r.std / r.n as f64).sqrt();
                let half = if se > 0.0 { stats::student_t_quantile(0.95, n_v + r.n as f64 - 2.0) * se } else { 0.0 };
                let room = 0.9 * self.result.margins[k] - half;
                let difference = c.mean - r.mean;
                let spread = c.std * (1.0 / n_v + 1.0 / c.n as f64).sqrt();
                let df = c.n.saturating_sub(1) as f64;
                let cdf = |x: f64| stats::student_t_cdf(x / spread, df);
                if room > 0.0 && spread > 0.0 {
                    cdf(room - difference) - cdf(-room - difference)
                } else {
                    f64::from(difference.abs() < room)
                }
            })
            .product()
    }

    /// Verifies feasible candidates among those `keep` accepts (and cheaper than the
    /// recommendation so far), in the order of [`Self::next_to_verify`], on fresh seeds until one
    /// passes (it becomes the recommendation) or the budget ends; with [`Until::Spent`], the
    /// verification goes on among those cheaper than it, past a round the budget leaves no room
    /// for. After a failure, only candidates that stood further inside the tolerances during the
    /// search (largest |difference|/tolerance below 0.9 of the failed one's) are tried: the
    /// failure says the edge of the acceptable region is nearer than the search runs showed.
    pub(super) fn verify(&mut self, keep: impl Fn(&Candidate) -> bool, until: Until) -> Result<(), TuneError> {
        let mut tried = HashSet::new();
        let mut limit = f64::INFINITY;
        loop {
            let bound = until.share() * self.answer_cost();
            let cheaper = |c: &Candidate| keep(c) && self.result.assess(c).cost < bound;
            let Some(k) = self.next_to_verify(&tried, limit, cheaper) else { return Ok(()) };
            tried.insert(k);
            let passed = self.verify_candidate(k)?;
            let answered = passed == Some(true) && self.accept(k);
            match passed {
                Some(true) if answered && until != Until::Spent => return Ok(()),
                Some(false) => {
                    let cand = &self.result.candidates[k];
                    if self.result.assess_verification(cand).is_some_and(|a| a.state != State::Undecided) {
                        limit = 0.9 * self.result.assess(cand).worst;
                    }
                }
                // With [`Until::Spent`], a cheaper round may still fit.
                None if until != Until::Spent => return Ok(()),
                _ => {}
            }
        }
    }

    /// The answer so far judged again on its fresh runs, after the reference has grown: its
    /// margins and mean moved, and an answer is one its fresh runs show equivalent to the whole
    /// reference. Where they now leave it undecided, it gets further rounds on fresh seeds as
    /// [`Self::verify_candidate`] gives them; one that fails, or that the spend leaves undecided,
    /// is withdrawn (the sheet then names it as failed on fresh seeds, with what would decide it),
    /// and the answer is the cheapest other verified candidate whose fresh runs still pass.
    pub(super) fn recheck_answer(&mut self) -> Result<(), TuneError> {
        let Some(k) = self.result.recommended else { return Ok(()) };
        let state = self.result.assess_runs(&self.result.candidates[k].verification).state;
        if state == State::Feasible {
            return Ok(());
        }
        self.result.recommended = None;
        if state == State::Undecided && self.verify_candidate(k)? == Some(true) && self.accept(k) {
            return Ok(());
        }
        self.result.recommended = self.cheapest_passing();
        Ok(())
    }

    /// A verification round of the answer so far, should it need one more: its runs and price in
    /// reference runs (none without an answer).
    pub(super) fn answer_round(&self) -> (usize, f64) {
        let Some(k) = self.result.recommended else { return (0, 0.0) };
        let size = self.config.verify_seeds.max(self.result.candidates[k].runs.len());
        (size, size as f64 * self.answer_cost() / self.result.reference_cost())
    }

    /// The cheapest candidate whose fresh runs pass against the whole reference and cost less than
    /// it.
    fn cheapest_passing(&self) -> Option<usize> {
        let result = &self.result;
        let verified = |(j, c): (usize, &Candidate)| {
            let a = result.assess_verification(c)?;
            (a.state == State::Feasible && a.cost < result.reference_cost()).then_some((j, a.cost))
        };
        result.candidates.iter().enumerate().filter_map(verified).min_by(|a, b| a.1.total_cmp(&b.1)).map(|(j, _)| j)
    }

    /// The verified cost of the answer so far (infinite without one).
    pub(super) fn answer_cost(&self) -> f64 {
        let verified = |k: usize| self.result.assess_runs(&self.result.candidates[k].verification).cost;
        self.result.recommended.map_or(f64::INFINITY, verified)
    }

    /// Makes candidate `k`, which passed its verification, the answer when its verified cost is
    /// below the answer so far's and the reference's: the answer is the cheapest verified
    /// candidate, and one that saves nothing on its fresh seeds is none. Whether it did.
    pub(super) fn accept(&mut self, k: usize) -> bool {
        let verified = self.result.assess_runs(&self.result.candidates[k].verification).cost;
        let cheaper = verified < self.answer_cost().min(self.result.reference_cost());
        if cheaper {
            self.result.recommended = Some(k);
        }
        cheaper
    }

    /// The next candidate to verify: feasible in the search, cheaper than the reference, not tried,
    /// standing inside `limit`; the one whose verification most likely saves most: its chance of
    /// passing ([`Self::pass_chance`]) times what it saves on the answer so far (else the
    /// reference), the cheaper first on a tie. A slightly dearer candidate decided on more seeds,
    /// or further inside the tolerances, goes before a cheaper one a round would likely leave
    /// undecided: the spend often pays for one verification.
    fn next_to_verify(&self, tried: &HashSet<usize>, limit: f64, keep: impl Fn(&Candidate) -> bool) -> Option<usize> {
        let result = &self.result;
        let bound = self.answer_cost().min(result.reference_cost());
        result
            .candidates
            .iter()
            .enumerate()
            .filter(|(k, cand)| !tried.contains(k) && cand.verification.is_empty() && keep(cand))
            .filter_map(|(k, cand)| {
                let a = result.assess(cand);
                let cheaper = result.cheapest_feasible(|c| c.id == cand.id).0.is_some();
                let open = cheaper && a.state == State::Feasible && a.worst < limit;
                open.then(|| (k, a.cost, self.pass_chance(cand) * (bound - a.cost).max(0.0)))
            })
            .min_by(|a, b| b.2.total_cmp(&a.2).then(a.1.total_cmp(&b.1)).then(a.0.cmp(&b.0)))
            .map(|(k, _, _)| k)
    }

    /// Runs candidate `k` on fresh seeds, `verify_seeds` at a time: once more when undecided, and
    /// again (up to [`VERIFY_ROUNDS`]) while the runs so far say two more rounds would decide it
    /// ([`runs_to_decide`]). Some(true) when it passes, Some(false) when it fails, None when the
    /// budget or the spend limit leaves no room.
    pub(super) fn verify_candidate(&mut self, k: usize) -> Result<Option<bool>, TuneError> {
        let c = self.config;
        // A candidate the search decided on more seeds than a round has is verified on as many.
        let size = c.verify_seeds.max(self.result.candidates[k].runs.len());
        for round in 0..VERIFY_ROUNDS {
            let cost = self.result.assess(&self.result.candidates[k]).cost / self.result.reference_cost();
            // A further round leaves room for the next candidate's first round, should this one fail.
            let fallback = if round == 0 { None } else { self.cheapest_pending(true, Some(k)) };
            let (more, fallback) = fallback.unwrap_or((0, 0.0));
            if !self.fits_price(size + more, size as f64 * cost + fallback) {
                return Ok(None);
            }
            let seeds: Vec<u64> = (0..size).map(|_| self.fresh_seed()).collect();
            let cand = &self.result.candidates[k];
            let jobs: Vec<Job> = seeds
                .iter()
                .map(|&seed| Job {
                    candidate: cand.id,
                    point: cand.point.clone(),
                    role: Role::Verify,
                    seed,
                    standard: cand.standard,
                    cap: None,
                })
                .collect();
            let outcomes = self.evaluate(&jobs)?;
            let cand = &mut self.result.candidates[k];
            cand.verification.extend(outcomes);
            cand.verify_seeds.extend(seeds);
            let result = &self.result;
            let runs = &result.candidates[k].verification;
            let soon =
                || runs_to_decide(&result.reference, runs, &result.margins).is_some_and(|n| n <= runs.len() + 2 * size);
            match result.assess_runs(runs).state {
                State::Feasible => return Ok(Some(true)),
                State::Undecided if round == 0 || soon() => continue,
                _ => return Ok(Some(false)),
            }
        }
        Ok(Some(false))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tune::model::Outcome;
    use crate::tune::search::testing::{REFERENCE, Running, Unused, candidate, config, runs, seat_reference};

    /// The first choice among a reference of mean 1 (spread 0.01, margin 0.05) and `candidates`.
    fn first_choice(candidates: Vec<Candidate>) -> usize {
        let config = config();
        let mut evaluator = Unused;
        let mut cx = Context::new(&config, &mut evaluator);
        seat_reference(&mut cx.result);
        cx.result.candidates = candidates;
        assert!(cx.result.candidates.iter().all(|c| cx.result.assess(c).state == State::Feasible));
        cx.next_to_verify(&HashSet::new(), f64::INFINITY, |_| true).unwrap()
    }

    #[test]
    fn a_slightly_dearer_candidate_a_round_would_likely_confirm_goes_before_a_cheaper_doubtful_one() {
        // Three seeds 3 % off (the margin is 5 %) at 40 % of the reference; six seeds on the
        // reference's mean at 42 %. Both are equivalent in the search.
        let doubtful = candidate(1, runs(40.0, &[1.02, 1.03, 1.04]));
        let sound = candidate(2, runs(42.0, &[0.995, 1.005, 1.0, 0.99, 1.01, 1.0]));
        assert_eq!(first_choice(vec![doubtful.clone(), sound.clone()]), 1, "the sound one (index 1)");
        // Where both are as sound, the cheaper goes first; and a large saving outweighs some doubt.
        let cheap_sound = candidate(3, runs(40.0, &[0.995, 1.005, 1.0, 0.99, 1.01, 1.0]));
        assert_eq!(first_choice(vec![sound.clone(), cheap_sound]), 1, "the cheaper of two sound ones");
        let much_cheaper = candidate(4, runs(10.0, &[1.0, 1.02, 1.03]));
        assert_eq!(first_choice(vec![sound, much_cheaper]), 1, "a quarter of the cost, some doubt");
    }

    /// The answer after a verification step `until` over a sound candidate at 42 % of the
    /// reference (verified first) and a doubtful one at 38 %, whose fresh runs all land on the
    /// reference's mean; and how many candidates were verified.
    fn answer_after(until: Until) -> (Option<usize>, usize) {
        let config = config();
        let run = |job: &Job| Outcome::settled(if job.candidate == 1 { 38.0 } else { 42.0 }, vec![1.0]);
        let mut evaluator = Running { run, unplaceable: Vec::new() };
        let mut cx = Context::new(&config, &mut evaluator);
        seat_reference(&mut cx.result);
        let doubtful = candidate(1, runs(38.0, &[1.02, 1.03, 1.04]));
        let sound = candidate(2, runs(42.0, &[0.995, 1.005, 1.0, 0.99, 1.01, 1.0]));
        cx.result.candidates = vec![doubtful, sound];
        cx.verify(|_| true, until).unwrap();
        let verified = cx.result.candidates.iter().filter(|c| !c.verification.is_empty()).count();
        (cx.result.recommended, verified)
    }

    #[test]
    fn the_last_step_spends_what_is_left_on_candidates_cheaper_than_the_answer() {
        // The sound one passes first; stopping there leaves the cheaper one unverified.
        assert_eq!(answer_after(Until::Answer), (Some(1), 1));
        assert_eq!(answer_after(Until::Spent), (Some(0), 2));
    }

    /// The answer and the candidates verified after a step [`Until::ClearlyCheaper`], with an
    /// answer verified at 50 % of the reference and one more candidate at `cost` in the search,
    /// feasible on six seeds, whose fresh runs land on the reference's mean.
    fn clearly_cheaper(cost: f64) -> (Option<usize>, usize) {
        verified_beside_answer(cost, Until::ClearlyCheaper)
    }

    /// As [`clearly_cheaper`], with a step `until`.
    fn verified_beside_answer(cost: f64, until: Until) -> (Option<usize>, usize) {
        let config = config();
        let run = |_: &Job| Outcome::settled(cost, vec![1.0]);
        let mut evaluator = Running { run, unplaceable: Vec::new() };
        let mut cx = Context::new(&config, &mut evaluator);
        seat_reference(&mut cx.result);
        let mut answer = candidate(1, runs(45.0, &REFERENCE[..3]));
        answer.verification = runs(50.0, &REFERENCE);
        let other = candidate(2, runs(cost, &[0.995, 1.005, 1.0, 0.99, 1.01, 1.0]));
        cx.result.candidates = vec![answer, other];
        cx.result.recommended = Some(0);
        cx.verify(|_| true, until).unwrap();
        let verified = cx.result.candidates.iter().filter(|c| !c.verification.is_empty()).count();
        (cx.result.recommended, verified)
    }

    #[test]
    fn before_the_search_a_feasible_corner_cheaper_than_the_standard_settings_is_verified_first() {
        // A standard setting at 60 % of the reference and the cheap corner at 40 %, both feasible
        // in the search on three seeds; every fresh run lands on the reference's mean.
        let config = config();
        let run = |job: &Job| Outcome::settled(if job.candidate == 1 { 60.0 } else { 40.0 }, vec![1.0]);
        let mut evaluator = Running { run, unplaceable: Vec::new() };
        let mut cx = Context::new(&config, &mut evaluator);
        seat_reference(&mut cx.result);
        let mut standard = candidate(1, runs(60.0, &REFERENCE[..3]));
        standard.standard = Some(0);
        let corner = candidate(2, runs(40.0, &REFERENCE[..3]));
        cx.result.candidates = vec![standard, corner];
        before_search(&mut cx).unwrap();
        assert_eq!(cx.result.recommended, Some(1), "the corner is the answer");
        assert!(cx.result.candidates[0].verification.is_empty(), "the dearer standard setting waits");
        // Without a feasible standard setting, the corner waits for the design's first seeds.
        cx.result.recommended = None;
        cx.result.candidates.remove(0);
        cx.result.candidates[0].verification.clear();
        before_search(&mut cx).unwrap();
        assert!(cx.result.candidates[0].verification.is_empty(), "nothing verified before the design");
    }

    #[test]
    fn a_candidate_clearly_cheaper_than_the_answer_is_verified_at_once_and_a_slightly_cheaper_one_waits() {
        assert_eq!(clearly_cheaper(40.0), (Some(1), 2), "80 % of the answer's verified cost");
        assert_eq!(clearly_cheaper(47.0), (Some(0), 1), "94 %: left to the last step");
    }

    #[test]
    fn the_last_step_leaves_a_candidate_within_five_percent_of_the_answer_unverified() {
        assert_eq!(verified_beside_answer(46.0, Until::Spent), (Some(1), 2), "92 % of the answer's verified cost");
        assert_eq!(verified_beside_answer(48.0, Until::Spent), (Some(0), 1), "96 %: nothing a round can show");
    }
}
