//! Exploration: an initial design (a Halton sequence and the cheap corner), then points on the edge
//! of equivalence and a pattern search around the incumbent, until the budget or the spend limit
//! ends it.

use super::context::{Context, Flow};
use super::reserve::FirstRound;
use super::verify::Until;
use crate::physics::rng::Rng;
use crate::stats::fit;
use crate::tune::design::{self, QUANT};
use crate::tune::model::{Evaluator, Origin, SearchEnd, TuneError};

/// The step: the initial design's candidates run, then the pattern search; the search records why
/// it ended.
pub(super) fn step<E: Evaluator>(cx: &mut Context<'_, E>) -> Result<Flow, TuneError> {
    let c = cx.config;
    let search_end = cx.search_end();
    let room = (search_end.saturating_sub(cx.result.runs)) / (2 * c.seeds);
    let initial = c.initial.unwrap_or((2 * c.dims + 2).max(6)).min(room).min(cx.affordable());
    cx.result.end = if initial > 0 {
        let mut halton = Halton::new(c.seed, c.dims);
        let mut fresh = halton.explore(cx, initial.max(2), Origin::Initial);
        // The corner, when the standard settings' turn left no room to run it.
        fresh.extend(cx.corner.filter(|&k| cx.result.candidates[k].runs.is_empty()));
        cx.evaluate_new(&fresh, search_end)?;
        halton.pattern_search(cx, search_end)?
    } else {
        cx.stopped(search_end)
    };
    Ok(Flow::Next)
}

/// The randomly shifted Halton sequence that new points of the lever space come from.
struct Halton {
    shift: Vec<f64>,
    /// The next point's index.
    index: u64,
}

/// The pattern search's state: its step, its centre (a candidate), the last move of the centre and
/// the cheapest incumbent cost seen.
struct Pattern {
    step: f64,
    center: Option<usize>,
    last_move: Option<Vec<f64>>,
    best_cost: f64,
}

impl Halton {
    /// The sequence of the search's `seed` in `dims` levers: the search's only randomness is its
    /// random shift.
    fn new(seed: u64, dims: usize) -> Self {
        let mut rng = Rng::new(seed ^ 0x7475_6e65);
        Self { shift: (0..dims).map(|_| rng.unit()).collect(), index: 1 }
    }

    /// Up to `count` new runnable Halton points that can still win.
    fn explore<E: Evaluator>(&mut self, cx: &mut Context<'_, E>, count: usize, origin: Origin) -> Vec<usize> {
        let mut fresh = Vec::new();
        let mut tries = 0;
        while fresh.len() < count && tries < 50 * count + 200 {
            tries += 1;
            let halton = design::halton(self.index, &self.shift);
            // Every second point at its own largest valid time step (see `top`).
            let point = if self.index % 2 == 1 { cx.at_largest_step(&halton) } else { halton };
            self.index += 1;
            if cx.promising(&design::snap(&point, &cx.config.levels)) {
                fresh.extend(cx.propose(&point, origin).filter(|&k| !cx.far_too_dear(k)));
            }
        }
        fresh
    }

    /// The pattern search and exploration until the budget or the spend limit ends it; why it
    /// ended.
    fn pattern_search<E: Evaluator>(
        &mut self,
        cx: &mut Context<'_, E>,
        search_end: usize,
    ) -> Result<SearchEnd, TuneError> {
        let c = cx.config;
        let mut pattern = Pattern { step: 0.25, center: None, last_move: None, best_cost: f64::INFINITY };
        loop {
            if cx.result.runs + c.seeds.min(c.max_seeds) > search_end || cx.affordable() == 0 {
                return Ok(cx.stopped(search_end));
            }
            if cx.extra_seeds(search_end)? {
                continue;
            }
            // A feasible candidate cheaper than the answer by a clear margin (any, without an
            // answer) is verified before the search spends on, as the time-step path's and the
            // standard settings' are: an answer in hand is worth more than a slightly cheaper one
            // the spend may not reach (on a noisy metric a verification may take several rounds),
            // and its round, held in reserve, is not left to search runs that cost more than priced.
            if cx.incumbent().0.is_some() {
                let before = cx.result.runs;
                cx.verify(|_| true, Until::ClearlyCheaper)?;
                if cx.result.runs > before {
                    continue;
                }
            }
            // The edge of equivalence first (see `edge`), else one pattern-search round around the
            // best point of the lever space.
            let mut fresh = cx.edge_points();
            if fresh.is_empty() {
                pattern.recentre(cx);
                fresh = pattern.moves(cx);
            }
            if fresh.is_empty() {
                fresh = self.explore(cx, (c.dims + 1).max(2), Origin::Explore);
                if fresh.is_empty() {
                    return Ok(cx.exhausted(search_end));
                }
            }
            if cx.evaluate_new(&fresh, search_end)? == 0 {
                return Ok(cx.stopped(search_end));
            }
        }
    }
}

impl Pattern {
    /// Follows the incumbent: the centre moves to the focus (remembering the move, the step at
    /// least 1/8), or the step halves when the round improved nothing.
    fn recentre<E: Evaluator>(&mut self, cx: &Context<'_, E>) {
        let cost = cx.incumbent().1;
        let focus = cx.focus();
        let improved = cost < self.best_cost;
        if improved {
            self.best_cost = cost;
        }
        match (focus, self.center) {
            (Some(f), Some(old)) if f != old => {
                let (a, b) = (&cx.result.candidates[old].point, &cx.result.candidates[f].point);
                self.last_move = Some(b.iter().zip(a).map(|(x, y)| x - y).collect());
                self.center = Some(f);
                self.step = self.step.max(0.125);
            }
            (Some(_), Some(_)) if !improved => {
                self.step /= 2.0;
                self.last_move = None;
            }
            (Some(f), None) => self.center = Some(f),
            _ => {}
        }
    }

    /// The new candidates around the centre, the step halved while there are none (down to the
    /// lever grid's resolution).
    fn moves<E: Evaluator>(&mut self, cx: &mut Context<'_, E>) -> Vec<usize> {
        let mut fresh = Vec::new();
        while let Some(f) = self.center.filter(|_| self.step >= 1.0 / QUANT) {
            let point = cx.result.candidates[f].point.clone();
            fresh = cx.neighbours(&point, self.step, self.last_move.as_deref());
            if !fresh.is_empty() {
                break;
            }
            self.step /= 2.0;
            self.last_move = None;
        }
        fresh
    }
}

impl<E: Evaluator> Context<'_, E> {
    /// Why the search ended with no new point to try: with a candidate in the running, unverified
    /// and cheaper than the answer so far by what the last verification step requires
    /// ([`Until::Spent`]), the spend left it there ([`Self::stopped`]); else the lever space is
    /// exhausted.
    fn exhausted(&self, search_end: usize) -> SearchEnd {
        let answer = Until::Spent.share() * self.answer_cost();
        let waiting = self
            .result
            .candidates
            .iter()
            .any(|c| c.verification.is_empty() && self.in_running(c) && self.result.assess(c).cost < answer);
        if waiting { self.stopped(search_end) } else { SearchEnd::Exhausted }
    }

    /// Why nothing more can run: the run budget (below `search_end`) when a candidate's first seeds
    /// would pass it, else the spend limit.
    fn stopped(&self, search_end: usize) -> SearchEnd {
        if self.result.runs + self.config.seeds > search_end { SearchEnd::RunBudget } else { SearchEnd::SpendLimit }
    }

    /// Whether a log-linear fit of the costs so far predicts `point` cheaper than the incumbent
    /// (true without an incumbent or a fit): only such points can still win.
    fn promising(&self, point: &[f64]) -> bool {
        let (_, incumbent_cost) = self.incumbent();
        match incumbent_cost.is_finite().then(|| self.cost_fit()).flatten() {
            Some(b) => (b[0] + point.iter().zip(&b[1..]).map(|(x, c)| x * c).sum::<f64>()).exp() < incumbent_cost,
            None => true,
        }
    }

    /// The compass neighbours of `point` at `step`, and the last move repeated, leaving out those
    /// that cannot win (see [`Self::promising`]).
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

    /// Runs `seeds` runs of each new candidate, cheapest predicted first (see
    /// [`Self::expected_cost`]), as many as fit below `end` and the spend limit (each with room to
    /// verify it, see [`Self::fits_candidate`]); returns how many candidates ran.
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
