//! The time-step path: the time-step lever alone at its largest valid value, stepped down or
//! bisected towards the reference's until a rung is valid, equivalent and verified.

use super::context::{Context, Flow};
use super::cure::judge_time_step_cure;
use super::spend::PRICE_MARGIN;
use crate::tune::judge::runs_to_decide;
use crate::tune::model::{Evaluator, NotRun, Origin, PathEnd, RunFailure, State, TuneError};

/// The time-step path stops bisecting when its best good rung's time step is within this factor of
/// the smallest bad one's: the answer then costs at most this much more than the boundary.
pub(super) const PATH_RESOLUTION: f64 = 1.2;

/// Most rungs of the time-step path.
const PATH_RUNGS: usize = 8;

/// The share of what the spend limit leaves after the reference that the time-step path may spend
/// when other levers wait for the rest.
const PATH_SHARE: f64 = 0.5;

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

/// The time-step path's own bounds, set as it starts.
struct Path {
    /// The most the spend may reach while none of its rungs is valid and equivalent (cost units).
    limit: f64,
    /// The cost of the cheap corner's time step
    /// ([`Candidate::relative_cost`](crate::tune::model::Candidate::relative_cost)).
    corner_cost: Option<f64>,
}

/// The step (see the module documentation of `search`): ends with its answer recommended, or with
/// why there is none.
pub(super) fn step<E: Evaluator>(cx: &mut Context<'_, E>) -> Result<Flow, TuneError> {
    if !cx.config.path || cx.config.standards == 0 {
        return Ok(Flow::Next);
    }
    let share = if cx.config.dims > 1 { PATH_SHARE } else { 1.0 };
    // The cheap corner's time step is known before the path steps down, to weigh its rungs against.
    let corner_cost = cx.corner_cost();
    let left = cx.config.max_spend * cx.result.reference_cost() - cx.spent;
    let path = Path { limit: cx.spent + share * left.max(0.0), corner_cost };
    let end = path.walk(cx)?;
    cx.result.path.1 = cx.result.recommended.map_or(end, PathEnd::Verified);
    Ok(Flow::Next)
}

impl Path {
    /// Steps down the rungs until the path ends; how it ended.
    fn walk<E: Evaluator>(&self, cx: &mut Context<'_, E>) -> Result<PathEnd, TuneError> {
        let mut step = PathStep::Rung(1.0, None);
        let mut rungs: Vec<(f64, usize)> = Vec::new();
        loop {
            step = match step {
                PathStep::End(end) => return Ok(end),
                PathStep::Rung(..) if rungs.len() >= PATH_RUNGS => self.next(cx, &rungs, None, true),
                PathStep::Rung(factor, from) => match cx.path_rung(factor)? {
                    Ok(k) if rungs.iter().any(|&(_, r)| r == k) => self.next(cx, &rungs, None, true),
                    Ok(k) => {
                        rungs.push((factor, k));
                        cx.result.candidates[k].stepped_from = from;
                        cx.result.path.0.push(k);
                        match self.settle_seeds(cx, k)? {
                            true => self.next(cx, &rungs, Some(k), false),
                            false => PathStep::End(PathEnd::OutOfBudget),
                        }
                    }
                    Err(next) => next,
                },
                PathStep::Verify(k) => match cx.verify_candidate(k)? {
                    Some(passed) => {
                        if passed {
                            cx.accept(k);
                        }
                        self.next(cx, &rungs, Some(k), false)
                    }
                    None => PathStep::End(PathEnd::OutOfBudget),
                },
            };
        }
    }

    /// Runs candidate `k`'s search seeds, and more (up to `max_seeds`) while it is undecided; false
    /// when the budget or the spend limit stops that.
    fn settle_seeds<E: Evaluator>(&self, cx: &mut Context<'_, E>, k: usize) -> Result<bool, TuneError> {
        let c = cx.config;
        loop {
            let a = cx.result.assess(&cx.result.candidates[k]);
            let more = match a.n {
                0 => c.seeds,
                n if a.state == State::Undecided && n < c.max_seeds => c.seeds.min(c.max_seeds - n),
                _ => return Ok(true),
            };
            if !self.fits_share(cx, more, more as f64 * cx.result.candidates[k].relative_cost.unwrap_or(1.0)) {
                return Ok(false);
            }
            // Cut where it could no longer win: at the cheapest other candidate still in the running.
            let cap = cx.config.cut_runs.then(|| cx.likely_cost_besides(k));
            cx.run_batch(&[(k, more)], Some(cap))?;
        }
    }

    /// The path's next step after judging `last` (a rung run or verified), from every rung so far
    /// (factor, candidate): a rung is good when valid and equivalent in the search and not failed
    /// on fresh seeds, bad otherwise. While the smallest bad rung is more than [`PATH_RESOLUTION`]
    /// above the best good one (or the reference) and the spend limit leaves room for one more rung
    /// and a verification, the next rung is the one a measured check's cure gives (for a rung that
    /// broke one), or their geometric mean; else the best good rung is verified (the path's
    /// answer); so is it after a rung whose runs did not settle. A rung whose verification stays undecided beyond what the spend limit can decide
    /// ends the path, naming it. `exhausted`: out of rungs, or a rung rounded to one the path has.
    fn next<E: Evaluator>(
        &self,
        cx: &Context<'_, E>,
        rungs: &[(f64, usize)],
        last: Option<usize>,
        exhausted: bool,
    ) -> PathStep {
        let result = &cx.result;
        let failed =
            |k: usize| result.assess_verification(&result.candidates[k]).is_some_and(|a| a.state != State::Feasible);
        let good = |k: usize| result.assess(&result.candidates[k]).state == State::Feasible && !failed(k);
        if let Some(k) = last.filter(|&k| cx.undecidable_verification(k)) {
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
        // A rung that does not settle (a limit cycle) ends the path: the spend goes to the other levers.
        let unsettled = last
            .is_some_and(|k| cx.result.candidates[k].runs.iter().any(|o| o.failure == Some(RunFailure::NotSettled)));
        if exhausted || unsettled || smallest_bad.is_infinite() || smallest_bad / low < PATH_RESOLUTION {
            return verify_best();
        }
        let cured =
            last.and_then(|k| cx.cure(k)).map(|(cure, k)| (cure * rungs.iter().find(|r| r.1 == k).unwrap().0, k));
        let (next, from) = match cured {
            Some((f, k)) if f > low * PATH_RESOLUTION.sqrt() => (f, Some(k)),
            _ => ((low * smallest_bad).sqrt(), None),
        };
        // Room for the next rung's seeds and then a verification (of it, or of the best good rung).
        let rung_cost = result.candidates[first].relative_cost.map(|r| r * top / next);
        let best_cost = best_good.and_then(|g| result.candidates[g.1].relative_cost);
        let (rung_cost, best_cost) = (rung_cost.unwrap_or(1.0), best_cost.unwrap_or(0.0));
        let (seeds, verify) = (cx.config.seeds, cx.config.verify_seeds);
        let price = seeds as f64 * rung_cost + verify as f64 * rung_cost.max(best_cost);
        // A bisection (no measured check to cure) to a step dearer than the cheap corner's is no longer
        // the cheapest thing left to try.
        let dearer = from.is_none() && self.corner_cost.is_some_and(|c| c * PATH_RESOLUTION < rung_cost);
        match self.fits_share(cx, seeds + verify, price) && !dearer {
            true => PathStep::Rung(next, from),
            false => verify_best(),
        }
    }

    /// [`Context::fits_price`], and within the path's share of the spend while none of its rungs is
    /// valid and equivalent in the search: a path whose rungs fail ends early and leaves the rest
    /// to the other levers.
    fn fits_share<E: Evaluator>(&self, cx: &Context<'_, E>, runs: usize, price: f64) -> bool {
        let reference = cx.result.reference_cost();
        let result = &cx.result;
        let found = result.path.0.iter().any(|&k| result.assess(&result.candidates[k]).state == State::Feasible);
        let within = found || cx.spent + PRICE_MARGIN * price * reference <= self.limit;
        cx.fits_price(runs, price) && within
    }
}

impl<E: Evaluator> Context<'_, E> {
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

    /// Whether candidate `k`'s verification stayed undecided (not different) and more fresh runs
    /// than the spend limit leaves would be needed to decide it ([`runs_to_decide`]).
    fn undecidable_verification(&self, k: usize) -> bool {
        let result = &self.result;
        let cand = &result.candidates[k];
        let undecided = result.assess_verification(cand).is_some_and(|a| a.state == State::Undecided);
        let needed = runs_to_decide(&result.reference, &cand.verification, &result.margins);
        let more = needed.map(|n| n.saturating_sub(cand.verification.len()));
        undecided && more.is_none_or(|more| !self.fits(more, cand.relative_cost))
    }
}
