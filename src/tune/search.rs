//! The search: find the cheapest point of a normalized lever space `[0, 1]^d` whose replicated runs are
//! equivalent to the reference's on every kept metric, within a budget of runs.
//!
//! It is generic over an [`Evaluator`] (real runs through the runner, or a cheap analytic stand-in in
//! tests) and deterministic: every choice depends only on the configuration, its seed and the outcomes
//! of earlier batches, processed in job order.
//!
//! 1. The reference runs on `reference_seeds` seeds; each metric's margin is its tolerance times the
//!    reference mean (or the absolute tolerance).
//! 2. An initial design: a randomly shifted Halton sequence (Cranley-Patterson rotation seeded by the
//!    search seed), quantized to a 1/64 grid; points the evaluator predicts invalid (e.g. an impact
//!    overlap past the divergence limit) are recorded and never run.
//! 3. Every candidate starts with `seeds` runs. It is feasible when every run settled and every kept
//!    metric is equivalent by the two one-sided tests (Schuirmann 1987: the 90 % Welch interval of
//!    the difference inside ±margin); infeasible when a run diverged or did not settle, or a metric is
//!    different (interval wholly outside). An undecided candidate that could still beat the incumbent
//!    (the cheapest feasible one) gets `seeds` more runs, up to `max_seeds`.
//! 4. Refinement: a pattern search (compass search, Kolda, Lewis & Torczon 2003) around the incumbent
//!    (or, while none is feasible, around the candidate closest to equivalence): ±step along every lever
//!    plus the last successful move repeated, leaving out moves that a log-linear fit of the costs so far
//!    predicts dearer than the incumbent; the step halves when a round brings no improvement. Once the
//!    step is below the grid, further Halton points explore, until the budget is spent.
//! 5. Verification (`3 × verify_seeds` runs are kept for it): the cheapest feasible candidate (among
//!    those whose difference so far leaves room for the verification's interval, first) runs on
//!    `verify_seeds` fresh seeds never used in the search (once more when undecided), and is judged on
//!    those runs alone; when it fails, the next cheapest that stood further inside the tolerances is
//!    verified, as long as the budget allows.

use std::collections::HashSet;

use crate::physics::rng::Rng;
use crate::stats::{self, Decision, Equivalence};

/// Grid of the normalized coordinates: candidates closer than 1/QUANT are the same.
pub const QUANT: f64 = 64.0;

/// What a search needs to know.
#[derive(Clone, Debug, PartialEq)]
pub struct SearchConfig {
    /// Number of levers.
    pub dims: usize,
    /// Per lever: the number of values of a list lever (its coordinate snaps to bin centres), None for
    /// a continuous one.
    pub levels: Vec<Option<usize>>,
    /// Per kept metric: tolerance and whether it is absolute (else relative to the reference mean).
    pub tolerances: Vec<(f64, bool)>,
    /// Seeds each candidate starts with.
    pub seeds: usize,
    /// Most seeds of one candidate during the search.
    pub max_seeds: usize,
    /// Seeds of the reference.
    pub reference_seeds: usize,
    /// Fresh seeds of one verification.
    pub verify_seeds: usize,
    /// Runs at most, all included.
    pub budget: usize,
    /// Seed of the random shift of the design.
    pub seed: u64,
    /// Points of the initial design (None: from the dimension and the budget).
    pub initial: Option<usize>,
}

/// Why a run is wanted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// The reference scene.
    Reference,
    /// A candidate during the search.
    Search,
    /// A candidate on fresh seeds.
    Verify,
}

/// One run to make.
#[derive(Clone, Debug, PartialEq)]
pub struct Job {
    /// Candidate number (0 for the reference).
    pub candidate: usize,
    /// The normalized point (empty for the reference).
    pub point: Vec<f64>,
    /// Why.
    pub role: Role,
    /// Replicate number: the evaluator's placement seed is derived from it.
    pub seed: u64,
}

/// One run's result.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// Why the run cannot count (diverged, did not settle, failed); None when it settled.
    pub failure: Option<String>,
    /// Its cost (particle-steps or seconds).
    pub cost: f64,
    /// The kept metrics, in order.
    pub metrics: Vec<f64>,
}

/// Runs batches of jobs and predicts invalid points.
pub trait Evaluator {
    /// Why `point` is predicted to fail without running it (None when it may run).
    fn invalid(&mut self, point: &[f64]) -> Option<String>;
    /// Runs `jobs` (as one parallel batch); outcomes in job order.
    fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, String>;
}

/// Where a candidate came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// The initial design.
    Initial,
    /// A pattern-search move.
    Refine,
    /// Exploration after the pattern search converged.
    Explore,
}

impl Origin {
    /// In words.
    pub fn name(self) -> &'static str {
        match self {
            Origin::Initial => "initial",
            Origin::Refine => "refine",
            Origin::Explore => "explore",
        }
    }
}

/// A candidate's standing against the reference.
#[derive(Clone, Debug, PartialEq)]
pub enum State {
    /// Not run (predicted invalid, or no budget left).
    NotRun(String),
    /// Every run settled and every metric is equivalent.
    Feasible,
    /// A run failed or a metric differs: the reason.
    Infeasible(String),
    /// Not decided yet: more seeds needed.
    Undecided,
}

impl State {
    /// In one word.
    pub fn name(&self) -> &'static str {
        match self {
            State::NotRun(_) => "not_run",
            State::Feasible => "equivalent",
            State::Infeasible(_) => "infeasible",
            State::Undecided => "undecided",
        }
    }
}

/// Runs judged against the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Assessment {
    /// Runs.
    pub n: usize,
    /// Mean cost.
    pub cost: f64,
    /// One test per kept metric (empty when a run failed).
    pub tests: Vec<Equivalence>,
    /// Largest |difference| / margin over the metrics (infinite when a run failed).
    pub worst: f64,
    /// The standing.
    pub state: State,
}

/// A point of the lever space and its runs.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    /// Number, from 1 (0 is the reference).
    pub id: usize,
    /// Normalized coordinates.
    pub point: Vec<f64>,
    /// Where it came from.
    pub origin: Origin,
    /// Why it was not run, when it was predicted invalid.
    pub predicted_invalid: Option<String>,
    /// Search runs, on seeds 0, 1, ...
    pub runs: Vec<Outcome>,
    /// Verification runs and their seed numbers.
    pub verification: Vec<Outcome>,
    /// Seeds of the verification runs.
    pub verify_seeds: Vec<u64>,
}

/// What the search found.
#[derive(Clone, Debug, PartialEq)]
pub struct SearchResult {
    /// The reference's runs.
    pub reference: Vec<Outcome>,
    /// Absolute margin of every kept metric.
    pub margins: Vec<f64>,
    /// Every candidate, in the order they were made.
    pub candidates: Vec<Candidate>,
    /// The verified recommendation (index into `candidates`).
    pub recommended: Option<usize>,
    /// Runs made, all included.
    pub runs: usize,
    /// The budget.
    pub budget: usize,
}

impl SearchResult {
    /// A candidate's search runs judged against the reference.
    pub fn assess(&self, candidate: &Candidate) -> Assessment {
        match &candidate.predicted_invalid {
            Some(reason) => not_run(reason),
            None => assess(&self.reference, &candidate.runs, &self.margins),
        }
    }

    /// A candidate's verification runs judged against the reference.
    pub fn assess_verification(&self, candidate: &Candidate) -> Option<Assessment> {
        (!candidate.verification.is_empty()).then(|| assess(&self.reference, &candidate.verification, &self.margins))
    }

    /// The candidate closest to acceptable (smallest largest |difference|/margin among those whose runs
    /// all settled and that did not fail a verification), when nothing was recommended.
    pub fn closest(&self) -> Option<usize> {
        let scored = self
            .candidates
            .iter()
            .enumerate()
            .filter(|(_, c)| c.verification.is_empty())
            .map(|(i, c)| (i, self.assess(c).worst));
        scored.filter(|(_, w)| w.is_finite()).min_by(|a, b| a.1.total_cmp(&b.1)).map(|(i, _)| i)
    }

    /// Reference costs.
    pub fn reference_costs(&self) -> Vec<f64> {
        self.reference.iter().map(|o| o.cost).collect()
    }
}

fn not_run(reason: &str) -> Assessment {
    Assessment {
        n: 0,
        cost: f64::NAN,
        tests: Vec::new(),
        worst: f64::INFINITY,
        state: State::NotRun(reason.to_string()),
    }
}

/// Judges runs against the reference's runs on every metric (margins absolute).
pub fn assess(reference: &[Outcome], runs: &[Outcome], margins: &[f64]) -> Assessment {
    if runs.is_empty() {
        return not_run("no runs");
    }
    let cost = runs.iter().map(|o| o.cost).sum::<f64>() / runs.len() as f64;
    let base = Assessment { n: runs.len(), cost, tests: Vec::new(), worst: f64::INFINITY, state: State::Undecided };
    if let Some(failure) = runs.iter().find_map(|o| o.failure.clone()) {
        return Assessment { state: State::Infeasible(failure), ..base };
    }
    let column = |set: &[Outcome], k: usize| set.iter().map(|o| o.metrics[k]).collect::<Vec<f64>>();
    let tests: Vec<Equivalence> =
        (0..margins.len()).map(|k| stats::equivalence(&column(reference, k), &column(runs, k), margins[k])).collect();
    let worst = tests.iter().zip(margins).map(|(t, m)| t.difference.abs() / m).fold(0.0, f64::max);
    let state = if let Some(k) = tests.iter().position(|t| t.decision == Decision::Different) {
        State::Infeasible(format!("metric {} differs", k + 1))
    } else if tests.iter().all(|t| t.decision == Decision::Equivalent) {
        State::Feasible
    } else {
        State::Undecided
    };
    Assessment { n: runs.len(), cost, tests, worst, state }
}

/// The radical inverse of `index` in base `base` (van der Corput), the Halton sequence's coordinate.
fn radical_inverse(mut index: u64, base: u64) -> f64 {
    let (mut result, mut f) = (0.0, 1.0 / base as f64);
    while index > 0 {
        result += f * (index % base) as f64;
        index /= base;
        f /= base as f64;
    }
    result
}

const PRIMES: [u64; 16] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53];

/// Runs the search.
pub fn search<E: Evaluator>(config: &SearchConfig, evaluator: &mut E) -> Result<SearchResult, String> {
    Search::new(config, evaluator).run()
}

struct Search<'a, E> {
    config: &'a SearchConfig,
    evaluator: &'a mut E,
    result: SearchResult,
    seen: HashSet<Vec<i64>>,
    shift: Vec<f64>,
    halton_index: u64,
}

impl<'a, E: Evaluator> Search<'a, E> {
    fn new(config: &'a SearchConfig, evaluator: &'a mut E) -> Self {
        // The search's only randomness: the Halton sequence's random shift.
        let mut rng = Rng::new(config.seed ^ 0x7475_6e65);
        let shift = (0..config.dims).map(|_| rng.unit()).collect();
        let result = SearchResult {
            reference: Vec::new(),
            margins: Vec::new(),
            candidates: Vec::new(),
            recommended: None,
            runs: 0,
            budget: config.budget,
        };
        Self { config, evaluator, result, seen: HashSet::new(), shift, halton_index: 1 }
    }

    fn run(mut self) -> Result<SearchResult, String> {
        let c = self.config;
        assert!(c.dims <= PRIMES.len(), "at most {} levers", PRIMES.len());
        self.reference()?;
        let reserve = 3 * c.verify_seeds;
        let search_end = c.budget.saturating_sub(reserve);
        let initial = c.initial.unwrap_or((2 * c.dims + 2).max(6)).min((search_end - self.result.runs) / (2 * c.seeds));
        let fresh = self.explore(initial.max(2), Origin::Initial);
        self.evaluate_new(&fresh, search_end)?;
        let mut step: f64 = 0.25;
        let mut center: Option<usize> = None;
        let mut last_move: Option<Vec<f64>> = None;
        let mut best_cost = f64::INFINITY;
        loop {
            if self.result.runs + c.seeds.min(c.max_seeds) > search_end {
                break;
            }
            if self.extra_seeds(search_end)? {
                continue;
            }
            // One pattern-search round.
            let (incumbent, cost) = self.incumbent();
            let focus = incumbent.or_else(|| self.result.closest());
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
                    break;
                }
            }
            if self.evaluate_new(&fresh, search_end)? == 0 {
                break;
            }
        }
        self.verify()?;
        Ok(self.result)
    }

    fn reference(&mut self) -> Result<(), String> {
        let c = self.config;
        let jobs: Vec<Job> = (0..c.reference_seeds as u64)
            .map(|seed| Job { candidate: 0, point: Vec::new(), role: Role::Reference, seed })
            .collect();
        let outcomes = self.evaluator.evaluate(&jobs)?;
        self.result.runs += jobs.len();
        if let Some(failure) = outcomes.iter().find_map(|o| o.failure.clone()) {
            return Err(format!("the reference scene itself does not settle on every seed ({failure}): fix it first"));
        }
        let mut margins = Vec::new();
        for (k, &(tolerance, absolute)) in c.tolerances.iter().enumerate() {
            let values: Vec<f64> = outcomes.iter().map(|o| o.metrics[k]).collect();
            let mean = stats::describe(&values).mean;
            let margin = if absolute { tolerance } else { tolerance * mean.abs() };
            if !(margin > 0.0 && margin.is_finite()) {
                return Err(format!(
                    "kept metric {} has mean {mean} in the reference: a relative tolerance gives no margin; \
                     give an absolute one",
                    k + 1
                ));
            }
            margins.push(margin);
        }
        self.result.reference = outcomes;
        self.result.margins = margins;
        Ok(())
    }

    /// The point snapped to the grid (list levers to bin centres).
    fn snap(&self, point: &[f64]) -> (Vec<f64>, Vec<i64>) {
        let mut snapped = Vec::with_capacity(point.len());
        let mut key = Vec::with_capacity(point.len());
        for (x, levels) in point.iter().zip(&self.config.levels) {
            let x = x.clamp(0.0, 1.0);
            match levels {
                Some(n) => {
                    let k = ((x * *n as f64).floor() as i64).min(*n as i64 - 1);
                    snapped.push((k as f64 + 0.5) / *n as f64);
                    key.push(k);
                }
                None => {
                    let k = (x * QUANT).round() as i64;
                    snapped.push(k as f64 / QUANT);
                    key.push(k);
                }
            }
        }
        (snapped, key)
    }

    /// A new candidate at `point` unless one is there already; predicted-invalid ones are recorded, not
    /// returned.
    fn propose(&mut self, point: &[f64], origin: Origin) -> Option<usize> {
        let (point, key) = self.snap(point);
        if !self.seen.insert(key) {
            return None;
        }
        let predicted_invalid = self.evaluator.invalid(&point);
        let valid = predicted_invalid.is_none();
        let id = self.result.candidates.len() + 1;
        self.result.candidates.push(Candidate {
            id,
            point,
            origin,
            predicted_invalid,
            runs: Vec::new(),
            verification: Vec::new(),
            verify_seeds: Vec::new(),
        });
        valid.then_some(id - 1)
    }

    /// Up to `count` new runnable Halton points.
    fn explore(&mut self, count: usize, origin: Origin) -> Vec<usize> {
        let mut fresh = Vec::new();
        let mut tries = 0;
        while fresh.len() < count && tries < 50 * count + 200 {
            tries += 1;
            let i = self.halton_index;
            self.halton_index += 1;
            let point: Vec<f64> =
                (0..self.config.dims).map(|d| (radical_inverse(i, PRIMES[d]) + self.shift[d]).fract()).collect();
            if let Some(k) = self.propose(&point, origin) {
                fresh.push(k);
            }
        }
        fresh
    }

    /// The compass neighbours of `point` at `step`, and the last move repeated; while there is an
    /// incumbent, neighbours that a log-linear fit of the costs so far predicts dearer than it are left
    /// out (they could not win: with several levers that halves a round).
    fn neighbours(&mut self, point: &[f64], step: f64, last_move: Option<&[f64]>) -> Vec<usize> {
        let (incumbent, incumbent_cost) = self.incumbent();
        let fit = incumbent.and_then(|_| self.cost_fit());
        let promising = |p: &[f64]| match &fit {
            Some(b) => (b[0] + p.iter().zip(&b[1..]).map(|(x, c)| x * c).sum::<f64>()).exp() < incumbent_cost,
            None => true,
        };
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
            if promising(&self.snap(&p).0) {
                fresh.extend(self.propose(&p, Origin::Refine));
            }
        }
        fresh
    }

    /// Least-squares fit of ln(mean cost) = b0 + Σ b_d u_d over the candidates whose runs all settled
    /// (a failed run's cost says nothing about a settled one's); None with too few of them.
    fn cost_fit(&self) -> Option<Vec<f64>> {
        let n = self.config.dims + 1;
        let rows: Vec<(Vec<f64>, f64)> = self
            .result
            .candidates
            .iter()
            .filter(|c| !c.runs.is_empty() && c.runs.iter().all(|o| o.failure.is_none()))
            .map(|c| {
                let cost = c.runs.iter().map(|o| o.cost).sum::<f64>() / c.runs.len() as f64;
                (std::iter::once(1.0).chain(c.point.iter().copied()).collect(), cost.ln())
            })
            .filter(|(_, y)| y.is_finite())
            .collect();
        if rows.len() < n + 2 {
            return None;
        }
        // Normal equations (with a tiny ridge), solved by Gaussian elimination with partial pivoting.
        let mut a = vec![vec![0.0; n + 1]; n];
        for (x, y) in &rows {
            for i in 0..n {
                for j in 0..n {
                    a[i][j] += x[i] * x[j];
                }
                a[i][n] += x[i] * y;
            }
        }
        for (i, row) in a.iter_mut().enumerate() {
            row[i] += 1e-9;
        }
        for col in 0..n {
            let pivot = (col..n).max_by(|&p, &q| a[p][col].abs().total_cmp(&a[q][col].abs()))?;
            a.swap(col, pivot);
            if a[col][col].abs() < 1e-12 {
                return None;
            }
            let pivot_row = a[col].clone();
            for (i, row) in a.iter_mut().enumerate() {
                if i != col {
                    let f = row[col] / pivot_row[col];
                    row.iter_mut().zip(&pivot_row).skip(col).for_each(|(x, p)| *x -= f * p);
                }
            }
        }
        Some((0..n).map(|i| a[i][n] / a[i][i]).collect())
    }

    /// Runs `seeds` runs of each new candidate (in order, as many whole candidates as fit below `end`);
    /// returns how many candidates ran.
    fn evaluate_new(&mut self, fresh: &[usize], end: usize) -> Result<usize, String> {
        let seeds = self.config.seeds;
        let fit = end.saturating_sub(self.result.runs) / seeds;
        let chosen: Vec<(usize, usize)> = fresh.iter().take(fit).map(|&k| (k, seeds)).collect();
        self.run_more(&chosen)?;
        Ok(chosen.len())
    }

    /// Gives more seeds to undecided candidates that could still win; false when there are none.
    fn extra_seeds(&mut self, end: usize) -> Result<bool, String> {
        let c = self.config;
        let (_, incumbent_cost) = self.incumbent();
        let mut chosen = Vec::new();
        let mut room = end.saturating_sub(self.result.runs);
        for (k, cand) in self.result.candidates.iter().enumerate() {
            let a = self.result.assess(cand);
            if a.state == State::Undecided && a.n < c.max_seeds && a.cost < incumbent_cost {
                let more = c.seeds.min(c.max_seeds - a.n);
                if more <= room {
                    chosen.push((k, more));
                    room -= more;
                }
            }
        }
        if chosen.is_empty() {
            return Ok(false);
        }
        self.run_more(&chosen)?;
        Ok(true)
    }

    /// Runs `more` further search seeds of each candidate, as one batch.
    fn run_more(&mut self, chosen: &[(usize, usize)]) -> Result<(), String> {
        let jobs: Vec<Job> = chosen
            .iter()
            .flat_map(|&(k, more)| {
                let cand = &self.result.candidates[k];
                let first = cand.runs.len() as u64;
                (first..first + more as u64).map(move |seed| Job {
                    candidate: cand.id,
                    point: cand.point.clone(),
                    role: Role::Search,
                    seed,
                })
            })
            .collect();
        if jobs.is_empty() {
            return Ok(());
        }
        let outcomes = self.evaluator.evaluate(&jobs)?;
        self.result.runs += jobs.len();
        for (job, outcome) in jobs.iter().zip(outcomes) {
            self.result.candidates[job.candidate - 1].runs.push(outcome);
        }
        Ok(())
    }

    /// The cheapest feasible candidate and its cost (infinite when there is none).
    fn incumbent(&self) -> (Option<usize>, f64) {
        let mut best = (None, f64::INFINITY);
        for (k, cand) in self.result.candidates.iter().enumerate() {
            let a = self.result.assess(cand);
            if a.state == State::Feasible && a.cost < best.1 {
                best = (Some(k), a.cost);
            }
        }
        best
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

    /// Verifies the cheapest feasible candidates on fresh seeds until one passes or the budget ends.
    /// After a failure, only candidates that stood further inside the tolerances during the search
    /// (largest |difference|/tolerance below 0.9 of the failed one's) are tried: the failure says the
    /// edge of the acceptable region is nearer than the search runs showed.
    fn verify(&mut self) -> Result<(), String> {
        let c = self.config;
        let mut order: Vec<(usize, f64, f64, bool)> = self
            .result
            .candidates
            .iter()
            .enumerate()
            .filter_map(|(k, cand)| {
                let a = self.result.assess(cand);
                (a.state == State::Feasible).then(|| (k, a.cost, a.worst, self.verifiable(cand)))
            })
            .collect();
        order.sort_by(|a, b| b.3.cmp(&a.3).then(a.1.total_cmp(&b.1)).then(a.0.cmp(&b.0)));
        let mut next_seed = c.reference_seeds.max(c.max_seeds) as u64;
        let mut limit = f64::INFINITY;
        for (k, _, worst, _) in order {
            if worst >= limit {
                continue;
            }
            for round in 0..2 {
                if self.result.runs + c.verify_seeds > c.budget {
                    return Ok(());
                }
                let cand = &self.result.candidates[k];
                let seeds: Vec<u64> = (next_seed..next_seed + c.verify_seeds as u64).collect();
                next_seed += c.verify_seeds as u64;
                let jobs: Vec<Job> = seeds
                    .iter()
                    .map(|&seed| Job { candidate: cand.id, point: cand.point.clone(), role: Role::Verify, seed })
                    .collect();
                let outcomes = self.evaluator.evaluate(&jobs)?;
                self.result.runs += jobs.len();
                let cand = &mut self.result.candidates[k];
                cand.verification.extend(outcomes);
                cand.verify_seeds.extend(seeds);
                let state = assess(&self.result.reference, &cand.verification, &self.result.margins).state;
                match state {
                    State::Feasible => {
                        self.result.recommended = Some(k);
                        return Ok(());
                    }
                    State::Undecided if round == 0 => continue,
                    _ => break,
                }
            }
            limit = 0.9 * worst;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halton_is_the_van_der_corput_sequence() {
        assert_eq!(radical_inverse(1, 2), 0.5);
        assert_eq!(radical_inverse(3, 2), 0.75);
        assert!((radical_inverse(1, 3) - 1.0 / 3.0).abs() < 1e-15);
    }

    #[test]
    fn assessment_follows_the_tests() {
        let run = |m: f64| Outcome { failure: None, cost: 1.0, metrics: vec![m] };
        let reference: Vec<Outcome> = [1.0, 1.01, 0.99, 1.0].iter().map(|&m| run(m)).collect();
        let same: Vec<Outcome> = [1.0, 1.005, 0.995].iter().map(|&m| run(m)).collect();
        assert_eq!(assess(&reference, &same, &[0.05]).state, State::Feasible);
        let far: Vec<Outcome> = [1.5, 1.505, 1.495].iter().map(|&m| run(m)).collect();
        assert!(matches!(assess(&reference, &far, &[0.05]).state, State::Infeasible(_)));
        let failed = vec![Outcome { failure: Some("diverged".into()), ..run(1.0) }];
        assert!(matches!(assess(&reference, &failed, &[0.05]).state, State::Infeasible(_)));
    }
}
