//! Exploration: the other standard settings, the cheap corner, a Halton design and a pattern search
//! around the incumbent.

use super::run::Search;
use super::spend::FirstRound;
use crate::stats::fit;
use crate::tune::design::{self, QUANT};
use crate::tune::judge::predicted_breach;
use crate::tune::model::{Candidate, Evaluator, NotRun, Origin, SearchEnd, TuneError};

impl<'a, E: Evaluator> Search<'a, E> {
    /// The other standard settings (exploration): each runs when the spend limit leaves room, and a
    /// rung whose runs break a measured check is stepped down once; then the undecided get more
    /// seeds and the best is verified when cheaper than the answer so far.
    pub(super) fn explore_ladder(&mut self) -> Result<(), TuneError> {
        let c = self.config;
        let search_end = c.budget.saturating_sub(3 * c.verify_seeds);
        for k in usize::from(c.path)..c.standards {
            if let Some(index) = self.propose_standard(k, Origin::Standard)
                && self.run_first(index)?
            {
                self.step_down(index)?;
            }
        }
        if let Some(k) = self.cheap_corner() {
            self.run_first(k)?;
        }
        while self.extra_seeds(search_end)? {}
        self.verify(|c| c.standard.is_some())
    }

    /// Runs candidate `k`'s first seeds when they fit the spend limit with room to verify it (cut
    /// where only that fits, [`Self::first_round`]); whether they ran.
    pub(super) fn run_first(&mut self, k: usize) -> Result<bool, TuneError> {
        let Some(round) = self.fits_candidate(k) else { return Ok(false) };
        self.cut_first_seeds(k, round);
        self.run_more(&[(k, self.config.seeds)])?;
        Ok(true)
    }

    /// Why nothing more can run: the run budget (below `search_end`) when a candidate's first seeds
    /// would pass it, else the spend limit.
    pub(super) fn stopped(&self, search_end: usize) -> SearchEnd {
        if self.result.runs + self.config.seeds > search_end { SearchEnd::RunBudget } else { SearchEnd::SpendLimit }
    }

    /// The pattern search and exploration until the budget or the spend limit ends it; why it
    /// ended.
    pub(super) fn pattern_search(&mut self, search_end: usize) -> Result<SearchEnd, TuneError> {
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

    /// A new candidate unless one resolves to the same runs; one predicted invalid (past a limit
    /// the reference does not break as much) or unable to start is recorded, not returned.
    pub(super) fn add(&mut self, point: Vec<f64>, standard: Option<usize>, origin: Origin) -> Option<usize> {
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

    pub(super) fn propose(&mut self, point: &[f64], origin: Origin) -> Option<usize> {
        let point = design::snap(point, &self.config.levels);
        self.add(point, None, origin)
    }

    pub(super) fn propose_standard(&mut self, k: usize, origin: Origin) -> Option<usize> {
        self.add(Vec::new(), Some(k), origin)
    }

    /// Whether a log-linear fit of the costs so far predicts `point` cheaper than the incumbent
    /// (true without an incumbent or a fit): only such points can still win.
    pub(super) fn promising(&self, point: &[f64]) -> bool {
        let (_, incumbent_cost) = self.incumbent();
        match incumbent_cost.is_finite().then(|| self.cost_fit()).flatten() {
            Some(b) => (b[0] + point.iter().zip(&b[1..]).map(|(x, c)| x * c).sum::<f64>()).exp() < incumbent_cost,
            None => true,
        }
    }

    /// Up to `count` new runnable Halton points that can still win.
    pub(super) fn explore(&mut self, count: usize, origin: Origin) -> Vec<usize> {
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

    /// The compass neighbours of `point` at `step`, and the last move repeated, leaving out those
    /// that cannot win (see [`Self::promising`]).
    pub(super) fn neighbours(&mut self, point: &[f64], step: f64, last_move: Option<&[f64]>) -> Vec<usize> {
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
    pub(super) fn cost_fit(&self) -> Option<Vec<f64>> {
        let rows: Vec<(Vec<f64>, f64)> = self
            .result
            .candidates
            .iter()
            .filter(|c| c.standard.is_none() && !c.runs.is_empty() && c.runs.iter().all(|o| o.failure.is_none()))
            .map(|c| (c.point.clone(), c.runs.iter().map(|o| o.cost).sum::<f64>() / c.runs.len() as f64))
            .collect();
        fit::log_linear(&rows, self.config.dims)
    }

    /// Runs `seeds` runs of each new candidate, cheapest predicted first (see
    /// [`Self::expected_cost`]), as many as fit below `end` and the spend limit (each with room to
    /// verify it, see [`Self::fits_candidate`]); returns how many candidates ran.
    pub(super) fn evaluate_new(&mut self, fresh: &[usize], end: usize) -> Result<usize, TuneError> {
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
            let runs = chosen.len() * seeds;
            if self.result.runs + runs + seeds > end {
                continue;
            }
            let Some(round) = self.first_round(k, runs, price, per_run) else { continue };
            price += seeds as f64
                * match round {
                    FirstRound::Whole => per_run,
                    FirstRound::Cut(cap) => cap / self.result.reference_cost(),
                };
            self.cut_first_seeds(k, round);
            chosen.push((k, seeds));
        }
        self.run_more(&chosen)?;
        Ok(chosen.len())
    }
}
