//! The search: find the cheapest point of a normalized lever space `[0, 1]^d` (or setting of the
//! ladder) whose replicated runs are valid and equivalent to the reference's on every kept metric.
//!
//! It is generic over an [`Evaluator`] (real runs through the runner, or a cheap analytic stand-in in
//! tests) and deterministic: every choice depends only on the configuration, its seed and the outcomes
//! of earlier batches, processed in job order. Judgements are in `judge`.
//!
//! 1. The reference runs on `reference_seeds` seeds; each metric's margin is its tolerance times the
//!    reference mean (or the absolute tolerance). The reference's own validity figures are recorded:
//!    a check it breaks holds every candidate to no worse than it. A reference that diverges or does
//!    not settle stops the tune; so does a kept metric its spread cannot decide ([`decidability`]).
//!    A setting that resolves to the reference's own runs is never a candidate.
//! 2. **The time-step path** ([`Search::path`]), when a time-step key is a lever, before anything
//!    else: the first standard setting (the time-step lever alone at its largest valid value) and,
//!    below it, the same setting with a smaller time step, down to the reference's (valid and
//!    equivalent by definition). A rung whose runs break a measured check steps down by the fitted
//!    error model ([`cure_factor`]); one that differs bisects (geometric mean) towards the last good
//!    rung or the reference, until the two are within [`PATH_RESOLUTION`]; the cheapest good rung is
//!    verified on fresh seeds, and a failed verification leads to the rung that cures it and a new
//!    verification. Only the run budget and the spend limit stop it; nothing else runs before it ends.
//! 3. Exploration, with what is left of the spend limit: the other standard settings; an initial
//!    design (a randomly shifted Halton sequence, quantized to a 1/64 grid; points predicted invalid
//!    are recorded and never run); then a pattern search (compass search, Kolda, Lewis & Torczon
//!    2003) around the incumbent, leaving out moves a log-linear cost fit predicts dearer than it.
//!    Every candidate starts with `seeds` runs; an undecided one that could still win (and is not
//!    likely different) gets more, up to `max_seeds`, then sequentially the seeds that decide it;
//!    where the reference's own spread is what keeps it undecided, the reference grows
//!    ([`Search::grow_reference`]). A new candidate predicted dearer than the cheapest one still in
//!    the running runs one seed first, cut at that cost; points predicted [`FAR_TOO_DEAR`] are not
//!    run. The search records why it ended ([`SearchEnd`]).
//! 4. Verification of candidates cheaper than the answer so far, on fresh seeds never used in the
//!    search (they start past the run budget), judged on those runs alone: while there is no answer,
//!    as soon as a candidate is valid and equivalent; else when the search ends.

use std::collections::HashSet;

use super::design::{self, PRIMES, QUANT};
use super::judge::{
    check_figures, cure_factor, decidability, likely_different, predicted_breach, reference_stands_apart,
    runs_to_decide, runs_to_decide_with,
};
use super::model::{
    Candidate, Evaluator, Job, NotRun, Origin, Outcome, PathEnd, Rejection, Role, Screen, SearchConfig, SearchEnd,
    SearchResult, State, TuneError, first_verification_seed,
};
use crate::physics::rng::Rng;
use crate::physics::warning::{ValidityWarning, WarningKind};
use crate::stats::{self, Decision, fit};

/// A point of the lever space predicted (from its time step) to cost more than this times the cheapest
/// candidate still in the running is not run: levers that shorten settling (damping, fill height)
/// rarely take a third off the reference's settle time.
pub const FAR_TOO_DEAR: f64 = 1.5;

/// The time-step path stops bisecting when its best good rung's time step is within this factor of
/// the smallest bad one's: the answer then costs at most this much more than the boundary.
pub const PATH_RESOLUTION: f64 = 1.2;

/// Most rungs of the time-step path.
const PATH_RUNGS: usize = 8;

/// Most verification rounds of one candidate.
const VERIFY_ROUNDS: usize = 4;

/// A batch is priced this much above its predicted cost against the spend limit: settle times spread.
const PRICE_MARGIN: f64 = 1.1;

/// An undecided candidate whose mean cost is below this share of the incumbent's would win by a clear
/// margin: past `max_seeds` it gets the seeds that decide it (sequential testing).
const CLEAR_MARGIN: f64 = 0.9;

/// A candidate decided sequentially gets at most this many times `max_seeds` search seeds.
const SEQUENTIAL_SEEDS: usize = 4;

/// The share of what the spend limit leaves after the reference that the time-step path may spend
/// when other levers wait for the rest.
const PATH_SHARE: f64 = 0.5;

/// A lever whose end moves a setting's predicted cost by less than this fraction leaves the cheap
/// corner at the centre of its range.
const CORNER_SLOPE: f64 = 0.05;

/// Most tries of the cheap corner, each nearer the centre than the one predicted invalid (and most
/// halvings of one lever's distance to the centre within a try).
const CORNER_TRIES: usize = 4;

/// Runs the search.
pub fn search<E: Evaluator>(config: &SearchConfig, evaluator: &mut E) -> Result<SearchResult, TuneError> {
    Search::new(config, evaluator).run()
}

struct Search<'a, E> {
    config: &'a SearchConfig,
    evaluator: &'a mut E,
    result: SearchResult,
    seen: HashSet<String>,
    shift: Vec<f64>,
    halton_index: u64,
    /// Cost of every run so far.
    spent: f64,
    /// The next fresh seed of a verification.
    next_seed: u64,
    /// The most the spend may reach while the time-step path runs (cost units).
    path_limit: f64,
    /// The cheap corner once proposed: its candidate, if it was a new runnable one.
    corner: Option<Option<usize>>,
    /// The cost of the cheap corner's time step ([`Candidate::relative_cost`]), as the time-step path
    /// starts.
    corner_cost: Option<f64>,
}

/// More reference runs and what they are priced with.
struct Growth {
    /// Reference runs to add.
    runs: usize,
    /// Runs in all that the price covers (against the run budget).
    priced_runs: usize,
    /// Their price, in reference runs.
    price: f64,
}

/// What the time-step path does next.
enum PathStep {
    /// Run (or judge) the rung at this factor of the first rung's time step, stepped down from that
    /// candidate when it cures one.
    Rung(f64, Option<usize>),
    /// Verify this rung (candidate index).
    Verify(usize),
    /// It is over.
    End(PathEnd),
}

impl<'a, E: Evaluator> Search<'a, E> {
    fn new(config: &'a SearchConfig, evaluator: &'a mut E) -> Self {
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
        }
    }

    fn run(mut self) -> Result<SearchResult, TuneError> {
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

    fn reference(&mut self) -> Result<(), TuneError> {
        let c = self.config;
        let jobs: Vec<Job> = (0..c.reference_seeds as u64).map(Job::reference).collect();
        self.seen.insert(self.evaluator.reference_identity());
        self.add_reference(&jobs)
    }

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
            let mean = stats::describe(&values).mean;
            let margin = if absolute { tolerance } else { tolerance * mean.abs() };
            if !(margin > 0.0 && margin.is_finite()) {
                let metric = c.metrics.get(k).cloned().unwrap_or_else(|| format!("number {}", k + 1));
                return Err(TuneError::NoMargin { metric, mean });
            }
            margins.push(margin);
        }
        self.result.reference_checks = check_figures(&outcomes, &[]);
        self.result.reference = outcomes;
        self.result.margins = margins;
        Ok(())
    }

    /// The cheapest way to decide undecided candidate `cand` when more of its own seeds alone cannot
    /// (the reference's spread is what keeps its interval wide): `g` more reference runs (a multiple
    /// of `seeds`, the reference at most doubled) and the candidate runs in all that then decide it
    /// (at most [`SEQUENTIAL_SEEDS`] times `max_seeds`), with the price of both and of verifying it
    /// on as many fresh seeds, in reference runs. None when no growth would.
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

    /// Grows the reference when that is what decides the cheapest undecided candidate that would beat
    /// the incumbent by a clear margin ([`CLEAR_MARGIN`]) and its own seeds alone cannot
    /// ([`Self::reference_growth`]), within the spend limit; whether it did. (A reference whose own
    /// mean is in doubt is grown first, by [`Self::extra_seeds`].)
    fn grow_reference(&mut self) -> Result<bool, TuneError> {
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

    /// Runs `growth`'s reference runs when its price fits the spend limit; whether it did.
    fn grow(&mut self, growth: Growth) -> Result<bool, TuneError> {
        if !self.fits_price(growth.priced_runs, growth.price) {
            return Ok(false);
        }
        let first = self.result.reference.len() as u64;
        let jobs: Vec<Job> = (first..first + growth.runs as u64).map(Job::reference).collect();
        self.add_reference(&jobs)?;
        Ok(true)
    }

    /// `seeds` more reference runs when the reference's own mean is in doubt: it stands apart
    /// ([`reference_stands_apart`]) from the candidates whose `seeds` or more search runs all settled,
    /// on a kept metric that leaves one cheaper than the reference undecided with its difference
    /// inside the margin (past it, the candidate is likely different whatever the reference's mean).
    /// Priced with a verification round of the cheapest candidate pending; the reference at most
    /// doubled.
    fn doubtful_reference(&self) -> Option<Growth> {
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

    /// Runs a batch, counting its runs and cost.
    fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, TuneError> {
        let outcomes = self.evaluator.evaluate(jobs)?;
        self.result.runs += jobs.len();
        self.spent += outcomes.iter().map(|o| o.cost).sum::<f64>();
        Ok(outcomes)
    }

    /// Whether `runs` more runs predicted at `relative_cost` of a reference run each fit the run budget
    /// and the spend limit.
    fn fits(&self, runs: usize, relative_cost: Option<f64>) -> bool {
        self.fits_price(runs, runs as f64 * relative_cost.unwrap_or(1.0))
    }

    /// Whether `runs` more runs costing `price` reference runs in all fit the run budget and the spend
    /// limit (priced [`PRICE_MARGIN`] above).
    fn fits_price(&self, runs: usize, price: f64) -> bool {
        let reference = self.result.reference_cost();
        let price = PRICE_MARGIN * price * reference;
        self.result.runs + runs <= self.config.budget && self.spent + price <= self.config.max_spend * reference
    }

    /// [`Self::fits_price`], and within the time-step path's share of the spend while none of its rungs
    /// is valid and equivalent in the search: a path whose rungs fail ends early and leaves the rest to
    /// the other levers.
    fn fits_path(&self, runs: usize, price: f64) -> bool {
        let reference = self.result.reference_cost();
        let result = &self.result;
        let found = result.path.0.iter().any(|&k| result.assess(&result.candidates[k]).state == State::Feasible);
        let within = found || self.spent + PRICE_MARGIN * price * reference <= self.path_limit;
        self.fits_price(runs, price) && within
    }

    /// The time-step path (see the module documentation): ends with its answer recommended, or
    /// with why there is none.
    fn path(&mut self) -> Result<(), TuneError> {
        if !self.config.path || self.config.standards == 0 {
            return Ok(());
        }
        let share = if self.config.dims > 1 { PATH_SHARE } else { 1.0 };
        // The cheap corner's time step is known before the path steps down, to weigh its rungs against.
        self.corner_cost = self.corner_cost();
        let left = self.config.max_spend * self.result.reference_cost() - self.spent;
        self.path_limit = self.spent + share * left.max(0.0);
        let mut step = PathStep::Rung(1.0, None);
        let mut rungs: Vec<(f64, usize)> = Vec::new();
        let end = loop {
            step = match step {
                PathStep::End(end) => break end,
                PathStep::Rung(..) if rungs.len() >= PATH_RUNGS => self.path_next(&rungs, None, true),
                PathStep::Rung(factor, from) => match self.path_rung(factor)? {
                    Ok(k) if rungs.iter().any(|&(_, r)| r == k) => self.path_next(&rungs, None, true),
                    Ok(k) => {
                        rungs.push((factor, k));
                        self.result.candidates[k].stepped_from = from;
                        self.result.path.0.push(k);
                        match self.settle_seeds(k)? {
                            true => self.path_next(&rungs, Some(k), false),
                            false => PathStep::End(PathEnd::OutOfBudget),
                        }
                    }
                    Err(next) => next,
                },
                PathStep::Verify(k) => match self.verify_candidate(k)? {
                    Some(passed) => {
                        if passed {
                            self.accept(k);
                        }
                        self.path_next(&rungs, Some(k), false)
                    }
                    None => PathStep::End(PathEnd::OutOfBudget),
                },
            };
        };
        self.result.path.1 = self.result.recommended.map_or(end, PathEnd::Verified);
        self.path_limit = f64::INFINITY;
        Ok(())
    }

    /// The rung at `factor` of the first standard setting's time step: its candidate index, or the
    /// path's next step when it cannot run (predicted past a limit a smaller step cures: that step;
    /// another predicted problem, or no cheaper than the reference: the end).
    fn path_rung(&mut self, factor: f64) -> Result<Result<usize, PathStep>, TuneError> {
        let standard = match factor {
            1.0 => Some(0),
            _ => self.evaluator.step_down(0, factor),
        };
        let nothing = Err(PathStep::End(PathEnd::NothingCheaper));
        let Some(standard) = standard else { return Ok(nothing) };
        let identity = self.evaluator.screen(&[], Some(standard)).identity;
        let k = match self.result.candidates.iter().position(|c| c.identity == identity) {
            Some(k) => k,
            None => match self.propose_standard(standard, Origin::Path) {
                Some(k) => k,
                None => self.result.candidates.len() - 1,
            },
        };
        let cand = &self.result.candidates[k];
        if cand.relative_cost.is_some_and(|r| r >= 1.0) {
            return Ok(nothing);
        }
        if let Some(NotRun::Predicted(warning)) = &cand.predicted_invalid {
            return Ok(Err(match judge_time_step_cure(warning) {
                Some(cure) => PathStep::Rung(factor * cure, None),
                None => PathStep::End(PathEnd::NothingCheaper),
            }));
        }
        Ok(if cand.predicted_invalid.is_some() { nothing } else { Ok(k) })
    }

    /// Runs candidate `k`'s search seeds, and more (up to `max_seeds`) while it is undecided; false
    /// when the budget or the spend limit stops that.
    fn settle_seeds(&mut self, k: usize) -> Result<bool, TuneError> {
        let c = self.config;
        loop {
            let a = self.result.assess(&self.result.candidates[k]);
            let more = match a.n {
                0 => c.seeds,
                n if a.state == State::Undecided && n < c.max_seeds => c.seeds.min(c.max_seeds - n),
                _ => return Ok(true),
            };
            if !self.fits_path(more, more as f64 * self.result.candidates[k].relative_cost.unwrap_or(1.0)) {
                return Ok(false);
            }
            let cap = self.config.cut_runs.then(|| self.result.reference_cost());
            self.run_batch(&[(k, more)], Some(cap))?;
        }
    }

    /// The path's next step after judging `last` (a rung run or verified), from every rung so far
    /// (factor, candidate): a rung is good when valid and equivalent in the search and not failed on
    /// fresh seeds, bad otherwise. While the smallest bad rung is more than [`PATH_RESOLUTION`] above
    /// the best good one (or the reference) and the spend limit leaves room for one more rung and a
    /// verification, the next rung is the one a measured check's cure gives (for a rung that broke
    /// one), or their geometric mean; else the best good rung is verified (the path's answer). A rung
    /// whose verification stays undecided beyond what the spend limit can decide ends the path, naming
    /// it. `exhausted`: out of rungs, or a rung rounded to one the path has.
    fn path_next(&self, rungs: &[(f64, usize)], last: Option<usize>, exhausted: bool) -> PathStep {
        let result = &self.result;
        let failed =
            |k: usize| result.assess_verification(&result.candidates[k]).is_some_and(|a| a.state != State::Feasible);
        let good = |k: usize| result.assess(&result.candidates[k]).state == State::Feasible && !failed(k);
        if let Some(k) = last.filter(|&k| self.undecidable_verification(k)) {
            return PathStep::End(PathEnd::Undecided(k));
        }
        let best_good = rungs.iter().filter(|r| good(r.1)).max_by(|a, b| a.0.total_cmp(&b.0)).copied();
        let verify_best = || match best_good {
            Some((_, k)) if result.candidates[k].verification.is_empty() => PathStep::Verify(k),
            Some((_, k)) => PathStep::End(PathEnd::Verified(k)),
            None => PathStep::End(PathEnd::NothingCheaper),
        };
        let (top, first) = rungs[0];
        let low = best_good.map_or(top * result.candidates[first].relative_cost.unwrap_or(1.0), |g| g.0);
        let smallest_bad = rungs.iter().filter(|r| !good(r.1)).map(|r| r.0).fold(f64::INFINITY, f64::min);
        if exhausted || smallest_bad.is_infinite() || smallest_bad / low < PATH_RESOLUTION {
            return verify_best();
        }
        let cured =
            last.and_then(|k| self.cure(k)).map(|(cure, k)| (cure * rungs.iter().find(|r| r.1 == k).unwrap().0, k));
        let (next, from) = match cured {
            Some((f, k)) if f > low * PATH_RESOLUTION.sqrt() => (f, Some(k)),
            _ => ((low * smallest_bad).sqrt(), None),
        };
        // Room for the next rung's seeds and then a verification (of it, or of the best good rung).
        let rung_cost = result.candidates[first].relative_cost.map(|r| r * top / next);
        let best_cost = best_good.and_then(|g| result.candidates[g.1].relative_cost);
        let (rung_cost, best_cost) = (rung_cost.unwrap_or(1.0), best_cost.unwrap_or(0.0));
        let (seeds, verify) = (self.config.seeds, self.config.verify_seeds);
        let price = seeds as f64 * rung_cost + verify as f64 * rung_cost.max(best_cost);
        // A bisection (no measured check to cure) to a step dearer than the cheap corner's is no longer
        // the cheapest thing left to try.
        let dearer = from.is_none() && self.corner_cost.is_some_and(|c| c * PATH_RESOLUTION < rung_cost);
        match self.fits_path(seeds + verify, price) && !dearer {
            true => PathStep::Rung(next, from),
            false => verify_best(),
        }
    }

    /// Whether candidate `k`'s verification stayed undecided (not different) and more fresh runs than
    /// the spend limit leaves would be needed to decide it ([`runs_to_decide`]).
    fn undecidable_verification(&self, k: usize) -> bool {
        let result = &self.result;
        let cand = &result.candidates[k];
        let undecided = result.assess_verification(cand).is_some_and(|a| a.state == State::Undecided);
        let needed = runs_to_decide(&result.reference, &cand.verification, &result.margins);
        let more = needed.map(|n| n.saturating_sub(cand.verification.len()));
        undecided && more.is_none_or(|more| !self.fits(more, cand.relative_cost))
    }

    /// The factor that cures the measured check candidate `k`'s runs (its verification runs, when it
    /// has them) break, and `k`.
    fn cure(&self, k: usize) -> Option<(f64, usize)> {
        let cand = &self.result.candidates[k];
        let a = match self.result.assess_verification(cand) {
            Some(a) => a,
            None => self.result.assess(cand),
        };
        let State::Infeasible(Rejection::Invalid(check)) = a.state else { return None };
        let reference = self.result.reference_checks.iter().find(|c| c.kind == check.kind);
        cure_factor(&check, reference, cand.relative_cost).map(|f| (f, k))
    }

    /// The other standard settings (exploration): each runs when the spend limit leaves room, and a
    /// rung whose runs break a measured check is stepped down once; then the undecided get more
    /// seeds and the best is verified when cheaper than the answer so far.
    fn explore_ladder(&mut self) -> Result<(), TuneError> {
        let c = self.config;
        let search_end = c.budget.saturating_sub(3 * c.verify_seeds);
        for k in usize::from(c.path)..c.standards {
            if let Some(index) = self.propose_standard(k, Origin::Standard)
                && self.fits_candidate(index)
            {
                self.run_more(&[(index, c.seeds)])?;
                self.step_down(index)?;
            }
        }
        if let Some(k) = self.cheap_corner()
            && self.fits_candidate(k)
        {
            self.run_more(&[(k, c.seeds)])?;
        }
        while self.extra_seeds(search_end)? {}
        self.verify(|c| c.standard.is_some())
    }

    /// Why nothing more can run: the run budget (below `search_end`) when a candidate's first seeds
    /// would pass it, else the spend limit.
    fn stopped(&self, search_end: usize) -> SearchEnd {
        if self.result.runs + self.config.seeds > search_end { SearchEnd::RunBudget } else { SearchEnd::SpendLimit }
    }

    /// The pattern search and exploration until the budget or the spend limit ends it; why it ended.
    fn pattern_search(&mut self, search_end: usize) -> Result<SearchEnd, TuneError> {
        let c = self.config;
        let mut step: f64 = 0.25;
        let mut center: Option<usize> = None;
        let mut last_move: Option<Vec<f64>> = None;
        let mut best_cost = f64::INFINITY;
        loop {
            if self.result.runs + c.seeds.min(c.max_seeds) > search_end || self.affordable() == 0 {
                return Ok(self.stopped(search_end));
            }
            if self.extra_seeds(search_end)? {
                continue;
            }
            // Without an answer, the cheapest feasible candidate is verified before the search spends
            // on, as the time-step path's and the standard settings' are: an answer in hand is worth
            // more than a slightly cheaper one the spend may not reach (on a noisy metric a
            // verification may take several rounds).
            if self.result.recommended.is_none() && self.incumbent().0.is_some() {
                let before = self.result.runs;
                self.verify(|_| true)?;
                if self.result.runs > before {
                    continue;
                }
            }
            // One pattern-search round, around the best point of the lever space.
            let cost = self.incumbent().1;
            let focus = self.focus();
            let improved = cost < best_cost;
            if improved {
                best_cost = cost;
            }
            match (focus, center) {
                (Some(f), Some(old)) if f != old => {
                    let (a, b) = (&self.result.candidates[old].point, &self.result.candidates[f].point);
                    last_move = Some(b.iter().zip(a).map(|(x, y)| x - y).collect());
                    center = Some(f);
                    step = step.max(0.125);
                }
                (Some(_), Some(_)) if !improved => {
                    step /= 2.0;
                    last_move = None;
                }
                (Some(f), None) => center = Some(f),
                _ => {}
            }
            let mut fresh = Vec::new();
            while let Some(f) = center.filter(|_| step >= 1.0 / QUANT) {
                let point = self.result.candidates[f].point.clone();
                fresh = self.neighbours(&point, step, last_move.as_deref());
                if !fresh.is_empty() {
                    break;
                }
                step /= 2.0;
                last_move = None;
            }
            if fresh.is_empty() {
                fresh = self.explore((c.dims + 1).max(2), Origin::Explore);
                if fresh.is_empty() {
                    // With a candidate in the running, unverified and cheaper than the answer so far,
                    // the spend left it there.
                    let answer = self.answer_cost();
                    let waiting = self.result.candidates.iter().any(|c| {
                        c.verification.is_empty() && self.in_running(c) && self.result.assess(c).cost < answer
                    });
                    return Ok(if waiting { self.stopped(search_end) } else { SearchEnd::Exhausted });
                }
            }
            if self.evaluate_new(&fresh, search_end)? == 0 {
                return Ok(self.stopped(search_end));
            }
        }
    }

    /// How many more candidates (at `seeds` runs each) the spend limit leaves room for, keeping a
    /// verification round of the candidate that would be verified. Runs are priced at the cheapest
    /// candidate still in the running, else at the least a runnable candidate may cost
    /// ([`Self::least_cost`]): a gate; each candidate is priced on its own when it runs
    /// ([`Self::evaluate_new`]).
    fn affordable(&self) -> usize {
        let c = self.config;
        let reference = self.result.reference_cost();
        let running = self.running_costs().into_iter().reduce(f64::min);
        let unit = running.unwrap_or_else(|| self.least_cost() * reference);
        let left = c.max_spend * reference - self.spent - c.verify_seeds as f64 * unit;
        if left > 0.0 { (left / (c.seeds as f64 * unit)).floor() as usize } else { 0 }
    }

    /// How many more search seeds candidate `cand` gets: an undecided one `seeds` at a time up to
    /// `max_seeds`; past that, one that would beat the incumbent by a clear margin ([`CLEAR_MARGIN`])
    /// gets the seeds its runs so far say decide it ([`runs_to_decide`]), up to [`SEQUENTIAL_SEEDS`]
    /// times `max_seeds` and within the spend limit. None: it gets no more (decided, it cannot be, or
    /// more seeds would most likely decide it different, [`likely_different`]).
    fn more_seeds(&self, cand: &Candidate) -> Option<usize> {
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
    fn in_running(&self, cand: &Candidate) -> bool {
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
    fn running_costs(&self) -> Vec<f64> {
        let running = self.result.candidates.iter().filter(|c| self.in_running(c));
        running.map(|c| self.result.assess(c).cost).collect()
    }

    /// A new candidate unless one resolves to the same runs; one predicted invalid (past a limit the
    /// reference does not break as much) or unable to start is recorded, not returned.
    fn add(&mut self, point: Vec<f64>, standard: Option<usize>, origin: Origin) -> Option<usize> {
        let screen = self.evaluator.screen(&point, standard);
        if !self.seen.insert(screen.identity.clone()) {
            return None;
        }
        let predicted_invalid = match screen.predicted {
            Ok(warnings) => {
                predicted_breach(&warnings, &self.result.reference_checks).map(|(_, w)| NotRun::Predicted(w))
            }
            Err(error) => Some(NotRun::Unstartable(error)),
        };
        let valid = predicted_invalid.is_none();
        let id = self.result.candidates.len() + 1;
        let point = if screen.resolved.is_empty() { point } else { screen.resolved };
        self.result.candidates.push(Candidate {
            id,
            point,
            standard,
            identity: screen.identity,
            origin,
            predicted_invalid,
            runs: Vec::new(),
            verification: Vec::new(),
            verify_seeds: Vec::new(),
            relative_cost: screen.relative_cost,
            stepped_from: None,
        });
        valid.then_some(id - 1)
    }

    fn propose(&mut self, point: &[f64], origin: Origin) -> Option<usize> {
        let point = design::snap(point, &self.config.levels);
        self.add(point, None, origin)
    }

    fn propose_standard(&mut self, k: usize, origin: Origin) -> Option<usize> {
        self.add(Vec::new(), Some(k), origin)
    }

    /// Whether a log-linear fit of the costs so far predicts `point` cheaper than the incumbent (true
    /// without an incumbent or a fit): only such points can still win.
    fn promising(&self, point: &[f64]) -> bool {
        let (_, incumbent_cost) = self.incumbent();
        match incumbent_cost.is_finite().then(|| self.cost_fit()).flatten() {
            Some(b) => (b[0] + point.iter().zip(&b[1..]).map(|(x, c)| x * c).sum::<f64>()).exp() < incumbent_cost,
            None => true,
        }
    }

    /// Up to `count` new runnable Halton points that can still win.
    fn explore(&mut self, count: usize, origin: Origin) -> Vec<usize> {
        let mut fresh = Vec::new();
        let mut tries = 0;
        while fresh.len() < count && tries < 50 * count + 200 {
            tries += 1;
            let point = design::halton(self.halton_index, &self.shift);
            self.halton_index += 1;
            if self.promising(&design::snap(&point, &self.config.levels)) {
                fresh.extend(self.propose(&point, origin).filter(|&k| !self.far_too_dear(k)));
            }
        }
        fresh
    }

    /// The compass neighbours of `point` at `step`, and the last move repeated, leaving out those that
    /// cannot win (see [`Self::promising`]).
    fn neighbours(&mut self, point: &[f64], step: f64, last_move: Option<&[f64]>) -> Vec<usize> {
        let mut moves = Vec::new();
        if let Some(m) = last_move {
            moves.push(point.iter().zip(m).map(|(x, d)| x + d).collect::<Vec<f64>>());
        }
        for d in 0..self.config.dims {
            let h = match self.config.levels[d] {
                Some(n) => step.max(1.0 / n as f64),
                None => step,
            };
            for sign in [-1.0, 1.0] {
                let mut p = point.to_vec();
                p[d] = (p[d] + sign * h).clamp(0.0, 1.0);
                moves.push(p);
            }
        }
        let mut fresh = Vec::new();
        for p in moves {
            if self.promising(&design::snap(&p, &self.config.levels)) {
                fresh.extend(self.propose(&p, Origin::Refine).filter(|&k| !self.far_too_dear(k)));
            }
        }
        fresh
    }

    /// The log-linear cost fit ([`fit::log_linear`]) over the lever-space candidates whose runs all
    /// settled (a failed run's cost says nothing about a settled one's).
    fn cost_fit(&self) -> Option<Vec<f64>> {
        let rows: Vec<(Vec<f64>, f64)> = self
            .result
            .candidates
            .iter()
            .filter(|c| c.standard.is_none() && !c.runs.is_empty() && c.runs.iter().all(|o| o.failure.is_none()))
            .map(|c| (c.point.clone(), c.runs.iter().map(|o| o.cost).sum::<f64>() / c.runs.len() as f64))
            .collect();
        fit::log_linear(&rows, self.config.dims)
    }

    /// Runs `seeds` runs of each new candidate (in order, as many whole candidates as fit below `end`);
    /// returns how many candidates ran.
    /// Runs `seeds` runs of each new candidate, cheapest predicted first (see [`Self::expected_cost`]),
    /// as many as fit below `end` and the spend limit (each with room to verify it, see
    /// [`Self::fits_candidate`]); returns how many candidates ran.
    fn evaluate_new(&mut self, fresh: &[usize], end: usize) -> Result<usize, TuneError> {
        let seeds = self.config.seeds;
        let mut order = fresh.to_vec();
        order.sort_by(|&a, &b| self.expected_cost(a).total_cmp(&self.expected_cost(b)).then(a.cmp(&b)));
        let (mut chosen, mut price) = (Vec::new(), 0.0);
        // Without a settle fit, a batch of new settings is priced at no less than the reference's
        // settle time: the one or two that settled fast say little of the next.
        let unfitted = self.settle_fit().is_none();
        for k in order {
            let time_step = self.result.candidates[k].relative_cost.unwrap_or(1.0);
            let per_run = if unfitted { self.expected_cost(k).max(time_step) } else { self.expected_cost(k) };
            let cost = seeds as f64 * per_run;
            let runs = (chosen.len() + 1) * seeds;
            if self.result.runs + runs <= end && self.fits_price(runs, price + cost + self.reservation(k)) {
                chosen.push((k, seeds));
                price += cost;
            }
        }
        self.run_more(&chosen)?;
        Ok(chosen.len())
    }

    /// Whether candidate `k`'s first seeds fit the spend limit with room to verify it.
    fn fits_candidate(&self, k: usize) -> bool {
        let seeds = self.config.seeds;
        self.fits_price(seeds, seeds as f64 * self.expected_cost(k) + self.reservation(k))
    }

    /// What a verification round would cost (in reference runs) when candidate `k` may be the one
    /// verified: the dearer of its round and [`Self::pending_reservation`].
    fn reservation(&self, k: usize) -> f64 {
        let seeds = self.config.verify_seeds;
        let own = seeds as f64 * self.expected_cost(k);
        self.pending_reservation().map_or(own, |pending| own.max(pending))
    }

    /// What verifying a candidate in the running not yet verified may cost (in reference runs, on as
    /// many seeds as its search runs, at least `verify_seeds`): the dearer of the cheapest one's round
    /// (verified first) and the cheapest feasible one's (the answer when the cheaper ones fail).
    fn pending_reservation(&self) -> Option<f64> {
        let rounds = [self.cheapest_pending(false, None), self.cheapest_pending(true, None)];
        rounds.into_iter().flatten().map(|(_, price)| price).reduce(f64::max)
    }

    /// The verification round (runs, price in reference runs: on as many seeds as its search runs, at
    /// least `verify_seeds`) of the cheapest candidate in the running not yet verified, other than
    /// `except`; with `feasible_only`, of the cheapest feasible one.
    fn cheapest_pending(&self, feasible_only: bool, except: Option<usize>) -> Option<(usize, f64)> {
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

    /// A candidate's predicted cost in reference runs: its time step's ([`Candidate::relative_cost`])
    /// times the settle time the settled runs so far predict at its point (the log-linear fit of
    /// measured cost over predicted, [`Self::settle_fit`]; without one, the mean settle time measured,
    /// else the reference's).
    fn expected_cost(&self, k: usize) -> f64 {
        let cand = &self.result.candidates[k];
        let factors: Vec<f64> = self.settle_factors().into_iter().map(|(_, f)| f).collect();
        let mean = if factors.is_empty() { 1.0 } else { stats::describe(&factors).mean };
        let settle = match (self.settle_fit(), cand.standard) {
            (Some(b), None) => (b[0] + cand.point.iter().zip(&b[1..]).map(|(x, c)| x * c).sum::<f64>()).exp(),
            _ => mean,
        };
        cand.relative_cost.unwrap_or(1.0) * settle.clamp(0.05, 20.0)
    }

    /// The least any runnable setting may cost in reference runs: the cheapest time step of those
    /// proposed (the cheap corner's, once proposed) at the shortest settle time measured so far.
    fn least_cost(&self) -> f64 {
        let runnable = self.result.candidates.iter().filter(|c| c.predicted_invalid.is_none());
        runnable.map(|c| self.optimistic_cost(c)).fold(self.optimistic_cost_at(1.0), f64::min)
    }

    /// The least a candidate may cost in reference runs: its time step's cost at the shortest settle
    /// time measured so far (relative to the reference's, at most 1).
    fn optimistic_cost(&self, cand: &Candidate) -> f64 {
        self.optimistic_cost_at(cand.relative_cost.unwrap_or(1.0))
    }

    /// [`Self::optimistic_cost`] of a setting whose time step costs `relative_cost`.
    fn optimistic_cost_at(&self, relative_cost: f64) -> f64 {
        let fastest = self.settle_factors().into_iter().map(|(_, f)| f).fold(1.0, f64::min);
        relative_cost * fastest
    }

    /// Per settled candidate (every run settled): its point and its mean cost over its time step's
    /// predicted cost, the settle time relative to the reference's.
    fn settle_factors(&self) -> Vec<(Vec<f64>, f64)> {
        let reference = self.result.reference_cost();
        self.result
            .candidates
            .iter()
            .filter(|c| !c.runs.is_empty() && c.runs.iter().all(|o| o.failure.is_none()))
            .map(|c| {
                let mean = c.runs.iter().map(|o| o.cost).sum::<f64>() / c.runs.len() as f64;
                (c.point.clone(), mean / (reference * c.relative_cost.unwrap_or(1.0)))
            })
            .collect()
    }

    /// The log-linear fit of the settle factors ([`Self::settle_factors`]) over the points of the
    /// lever space.
    fn settle_fit(&self) -> Option<Vec<f64>> {
        let rows: Vec<(Vec<f64>, f64)> =
            self.settle_factors().into_iter().filter(|(p, _)| p.len() == self.config.dims).collect();
        fit::log_linear(&rows, self.config.dims)
    }

    /// The point a DEM engineer tries first: every lever at the end of its range that the predicted
    /// time step (screened at both ends, the other levers at the centre) and the measured settle times
    /// (else the lever's dissipation, [`SearchConfig::dissipation`]) say is cheaper ([`CORNER_SLOPE`]:
    /// a lever that moves neither stays at the reference's value, [`SearchConfig::home`]); while
    /// predicted invalid, nearer the centre ([`Self::nearer_corner`]). Returns the runnable candidate,
    /// if one is new; proposed once, the same candidate after.
    fn cheap_corner(&mut self) -> Option<usize> {
        if let Some(corner) = self.corner {
            return corner;
        }
        let corner = self.propose_corner();
        self.corner = Some(corner);
        corner
    }

    fn propose_corner(&mut self) -> Option<usize> {
        let mut corner = self.corner_start();
        for _ in 0..CORNER_TRIES {
            let before = self.result.candidates.len();
            if let Some(k) = self.propose(&corner, Origin::Initial) {
                return Some(k);
            }
            if self.result.candidates.len() == before {
                return None;
            }
            corner = self.nearer_corner(&corner);
        }
        None
    }

    /// The next try after `corner` was predicted invalid: the cheapest predicted valid setting with
    /// one lever moved towards the centre (halving its distance up to [`CORNER_TRIES`] times; a
    /// restitution raised where it is the damping that breaks the step's limit keeps the step), else
    /// every lever halfway nearer.
    fn nearer_corner(&mut self, corner: &[f64]) -> Vec<f64> {
        let mut all = corner.to_vec();
        halfway_to_centre(&mut all);
        let mut best: Option<(Vec<f64>, f64)> = None;
        for d in 0..corner.len() {
            let mut one = corner.to_vec();
            for _ in 0..CORNER_TRIES {
                halfway_to_centre(&mut one[d..=d]);
                let screen = self.evaluator.screen(&design::snap(&one, &self.config.levels), None);
                if self.predicted_valid(&screen) {
                    let cost = screen.relative_cost.unwrap_or(f64::INFINITY);
                    if best.as_ref().is_none_or(|(_, c)| cost < *c) {
                        best = Some((one.clone(), cost));
                    }
                    break;
                }
            }
        }
        best.map_or(all, |(one, _)| one)
    }

    /// The cheap corner as first tried (see [`Self::cheap_corner`]), before any is found invalid.
    fn corner_start(&mut self) -> Vec<f64> {
        let time_step = self.time_step_slopes();
        let settle = self.settle_fit().map(|fit| fit[1..].to_vec());
        (0..self.config.dims)
            .map(|d| {
                let settle = settle.as_ref().map_or(-2.0 * CORNER_SLOPE * self.config.dissipation[d], |s| s[d]);
                match time_step[d] + settle {
                    slope if slope.abs() < CORNER_SLOPE => self.config.home.get(d).copied().flatten().unwrap_or(0.5),
                    slope if slope < 0.0 => 1.0,
                    _ => 0.0,
                }
            })
            .collect()
    }

    /// The predicted cost of the cheap corner's time step, screened without proposing it (nearer the
    /// centre while predicted invalid, as [`Self::cheap_corner`] does).
    fn corner_cost(&mut self) -> Option<f64> {
        let mut corner = self.corner_start();
        for _ in 0..CORNER_TRIES {
            let screen = self.evaluator.screen(&design::snap(&corner, &self.config.levels), None);
            if screen.predicted.is_err() {
                return None;
            }
            if self.predicted_valid(&screen) {
                return screen.relative_cost;
            }
            corner = self.nearer_corner(&corner);
        }
        None
    }

    /// Whether a screened setting starts and is predicted to break no limit beyond what the
    /// reference's own runs are held to.
    fn predicted_valid(&self, screen: &Screen) -> bool {
        matches!(&screen.predicted, Ok(w) if predicted_breach(w, &self.result.reference_checks).is_none())
    }

    /// Per lever: the log of the predicted cost at the top of its range over that at the bottom (the
    /// other levers at the centre), from the time steps the two settings resolve to; 0 where either
    /// cannot be predicted.
    fn time_step_slopes(&mut self) -> Vec<f64> {
        let dims = self.config.dims;
        (0..dims)
            .map(|d| {
                let mut cost = |u: f64| {
                    let mut point = vec![0.5; dims];
                    point[d] = u;
                    self.evaluator.screen(&design::snap(&point, &self.config.levels), None).relative_cost
                };
                match (cost(0.0), cost(1.0)) {
                    (Some(low), Some(high)) if low > 0.0 && high > 0.0 => (high / low).ln(),
                    _ => 0.0,
                }
            })
            .collect()
    }

    /// Gives more seeds to undecided candidates that could still win, after more reference runs where
    /// the reference's own mean is in doubt ([`Self::doubtful_reference`]); false when there are none.
    fn extra_seeds(&mut self, end: usize) -> Result<bool, TuneError> {
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

    /// The cost past which a further run of `cand` (which will then have `more` further runs) proves
    /// that it cannot beat the incumbent (the reference itself while there is none): with every other
    /// run costing nothing, its mean would still reach the incumbent's.
    ///
    /// A new candidate predicted dearer (see [`Candidate::relative_cost`]) than the cheapest one still
    /// in the running ([`Self::likely_cost`]: the incumbent, a valid undecided candidate or the
    /// reference) is expected to lose: its first run is stopped as soon as it alone costs that much,
    /// the point where the prediction is confirmed (a run that settles sooner than the reference's,
    /// e.g. with more damping, still ends below it and counts).
    fn cap(&self, cand: &Candidate, more: usize) -> Option<f64> {
        if cand.runs.is_empty() && self.predicted_dear(cand) {
            return self.config.cut_runs.then_some(self.likely_cost());
        }
        let incumbent = self.incumbent().1;
        let spent: f64 = cand.runs.iter().map(|o| o.cost).sum();
        self.config.cut_runs.then(|| (cand.runs.len() + more) as f64 * incumbent - spent).filter(|c| c.is_finite())
    }

    /// When candidate `k`'s search runs break a measured check that a smaller time step cures and `k`
    /// is a standard setting not itself stepped down: the same setting with its time step multiplied
    /// by [`cure_factor`] becomes a new standard setting and runs its search seeds (when the budget
    /// and the spend limit leave room for them and a verification).
    fn step_down(&mut self, k: usize) -> Result<(), TuneError> {
        let c = self.config;
        let cand = &self.result.candidates[k];
        let (Some(standard), None) = (cand.standard, cand.stepped_from) else { return Ok(()) };
        let Some((factor, _)) = self.cure(k) else { return Ok(()) };
        let Some(stepped) = self.evaluator.step_down(standard, factor) else { return Ok(()) };
        let Some(index) = self.propose_standard(stepped, Origin::Standard) else { return Ok(()) };
        self.result.candidates[index].stepped_from = Some(k);
        if self.fits(c.seeds + c.verify_seeds, self.result.candidates[index].relative_cost) {
            self.run_more(&[(index, c.seeds)])?;
        }
        Ok(())
    }

    /// Whether candidate `k` is predicted ([`Candidate::relative_cost`]) to cost more than
    /// [`FAR_TOO_DEAR`] times the cheapest candidate still in the running: it would have to settle in
    /// a third less time than the reference to win, so it is recorded and not run.
    fn far_too_dear(&self, k: usize) -> bool {
        let reference = self.result.reference_cost();
        let cand = &self.result.candidates[k];
        cand.relative_cost.is_some() && self.optimistic_cost(cand) * reference > FAR_TOO_DEAR * self.likely_cost()
    }

    /// Whether `cand` is predicted dearer than the cheapest candidate still in the running, even at
    /// the shortest settle time measured so far.
    fn predicted_dear(&self, cand: &Candidate) -> bool {
        let reference = self.result.reference_cost();
        self.config.cut_runs
            && cand.relative_cost.is_some()
            && self.optimistic_cost(cand) * reference > self.likely_cost()
    }

    /// Runs `more` further search seeds of each candidate, as one batch; a new candidate predicted
    /// dearer than the cheapest one in the running ([`Self::predicted_dear`]) first runs one seed
    /// alone, and the rest only when that run ended below its cap and valid.
    fn run_more(&mut self, chosen: &[(usize, usize)]) -> Result<(), TuneError> {
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
    fn run_batch(&mut self, chosen: &[(usize, usize)], cap: Option<Option<f64>>) -> Result<(), TuneError> {
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

    /// The mean cost of the cheapest candidate still in the running (feasible, or undecided with every
    /// run settled and valid), the reference's when none is cheaper: what the answer will likely cost.
    fn likely_cost(&self) -> f64 {
        self.running_costs().into_iter().fold(self.result.reference_cost(), f64::min)
    }

    /// The cheapest feasible candidate, standard settings included, and its cost (infinite when
    /// there is none).
    fn incumbent(&self) -> (Option<usize>, f64) {
        self.result.cheapest_feasible(|_| true)
    }

    /// Where the pattern search centres: the cheapest feasible point of the lever space, else the one
    /// closest to equivalence.
    fn focus(&self) -> Option<usize> {
        self.result.cheapest_feasible(|c| c.standard.is_none()).0.or_else(|| self.result.closest_point())
    }

    /// Whether fresh runs would likely confirm a feasible candidate: on every metric, its difference so
    /// far plus the 90 % interval half-width expected with `2 × verify_seeds` fresh runs stays below
    /// 0.9 of the margin (the search's winners look better than they are: the 0.9 allows for that).
    fn verifiable(&self, cand: &Candidate) -> bool {
        let n = (2 * self.config.verify_seeds) as f64;
        let reference = &self.result.reference;
        (0..self.result.margins.len()).all(|k| {
            let r = stats::describe(&reference.iter().map(|o| o.metrics[k]).collect::<Vec<_>>());
            let c = stats::describe(&cand.runs.iter().map(|o| o.metrics[k]).collect::<Vec<_>>());
            let se = (c.std * c.std / n + r.std * r.std / r.n as f64).sqrt();
            let t = stats::student_t_quantile(0.95, n + r.n as f64 - 2.0);
            let upper = (c.mean - r.mean).abs() + if se > 0.0 { t * se } else { 0.0 };
            upper < 0.9 * self.result.margins[k]
        })
    }

    /// Verifies the cheapest feasible candidates among those `keep` accepts (and cheaper than the
    /// recommendation so far) on fresh seeds until one passes (it becomes the recommendation) or the
    /// budget ends. After a failure, only candidates that stood further inside the tolerances during
    /// the search (largest |difference|/tolerance below 0.9 of the failed one's) are tried: the failure
    /// says the edge of the acceptable region is nearer than the search runs showed.
    fn verify(&mut self, keep: impl Fn(&Candidate) -> bool) -> Result<(), TuneError> {
        let mut tried = HashSet::new();
        let mut limit = f64::INFINITY;
        let bound = self.answer_cost();
        while let Some(k) = self.next_to_verify(&tried, limit, |c| keep(c) && self.result.assess(c).cost < bound) {
            tried.insert(k);
            match self.verify_candidate(k)? {
                Some(true) => {
                    if self.accept(k) {
                        return Ok(());
                    }
                }
                Some(false) => {
                    let cand = &self.result.candidates[k];
                    if self.result.assess_verification(cand).is_some_and(|a| a.state != State::Undecided) {
                        limit = 0.9 * self.result.assess(cand).worst;
                    }
                }
                None => return Ok(()),
            }
        }
        Ok(())
    }

    /// The verified cost of the answer so far (infinite without one).
    fn answer_cost(&self) -> f64 {
        let verified = |k: usize| self.result.assess_runs(&self.result.candidates[k].verification).cost;
        self.result.recommended.map_or(f64::INFINITY, verified)
    }

    /// Makes candidate `k`, which passed its verification, the answer when its verified cost is below
    /// the answer so far's and the reference's: the answer is the cheapest verified candidate, and one
    /// that saves nothing on its fresh seeds is none. Whether it did.
    fn accept(&mut self, k: usize) -> bool {
        let verified = self.result.assess_runs(&self.result.candidates[k].verification).cost;
        let cheaper = verified < self.answer_cost().min(self.result.reference_cost());
        if cheaper {
            self.result.recommended = Some(k);
        }
        cheaper
    }

    /// The next candidate to verify: feasible in the search, cheaper than the reference, not tried,
    /// standing inside `limit`; those whose difference leaves room for the verification's interval
    /// first, then the cheapest.
    fn next_to_verify(&self, tried: &HashSet<usize>, limit: f64, keep: impl Fn(&Candidate) -> bool) -> Option<usize> {
        let result = &self.result;
        result
            .candidates
            .iter()
            .enumerate()
            .filter(|(k, cand)| !tried.contains(k) && cand.verification.is_empty() && keep(cand))
            .filter_map(|(k, cand)| {
                let a = result.assess(cand);
                let cheaper = result.cheapest_feasible(|c| c.id == cand.id).0.is_some();
                (cheaper && a.state == State::Feasible && a.worst < limit).then(|| (k, a.cost, self.verifiable(cand)))
            })
            .min_by(|a, b| b.2.cmp(&a.2).then(a.1.total_cmp(&b.1)).then(a.0.cmp(&b.0)))
            .map(|(k, _, _)| k)
    }

    /// Runs candidate `k` on fresh seeds, `verify_seeds` at a time: once more when undecided, and
    /// again (up to [`VERIFY_ROUNDS`]) while the runs so far say two more rounds would decide it
    /// ([`runs_to_decide`]). Some(true) when it passes, Some(false) when it fails, None when the budget
    /// or the spend limit leaves no room.
    fn verify_candidate(&mut self, k: usize) -> Result<Option<bool>, TuneError> {
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
            let cand = &self.result.candidates[k];
            let seeds: Vec<u64> = (self.next_seed..self.next_seed + size as u64).collect();
            self.next_seed += size as u64;
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

/// The mean of kept metric `k` over `runs`.
fn column_mean(runs: &[Outcome], k: usize) -> f64 {
    stats::describe(&runs.iter().map(|o| o.metrics[k]).collect::<Vec<_>>()).mean
}

/// Moves a point of the lever space halfway to the centre of every lever's range.
fn halfway_to_centre(point: &mut [f64]) {
    point.iter_mut().for_each(|x| *x = 0.5 + 0.5 * (*x - 0.5));
}

/// The factor of the time step that brings a predicted warning that grows with it (a time step past
/// the contact-time or damping-rate limit, or capped by the latter) just under its limit; None for
/// one a smaller step does not cure.
fn judge_time_step_cure(warning: &ValidityWarning) -> Option<f64> {
    let scales = matches!(
        warning.kind,
        WarningKind::TimeStepCapped
            | WarningKind::ContactTimeFraction
            | WarningKind::DampingRate
            | WarningKind::IntegratorStability
    );
    (scales && warning.value > 0.0).then(|| 0.99 * warning.limit / warning.value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_predicted_time_step_problem_is_cured_by_the_ratio_of_its_limit() {
        let capped = ValidityWarning::new(WarningKind::TimeStepCapped, 2e-5, 1e-5);
        assert!((judge_time_step_cure(&capped).unwrap() - 0.495).abs() < 1e-12);
        assert_eq!(judge_time_step_cure(&ValidityWarning::new(WarningKind::ImpactOverlap, 0.2, 0.1)), None);
    }
}
