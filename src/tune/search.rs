//! The search: find the cheapest point of a normalized lever space `[0, 1]^d` whose replicated runs are
//! equivalent to the reference's on every kept metric, within a budget of runs.
//!
//! It is generic over an [`Evaluator`] (real runs through the runner, or a cheap analytic stand-in in
//! tests) and deterministic: every choice depends only on the configuration, its seed and the outcomes
//! of earlier batches, processed in job order.
//!
//! 1. The reference runs on `reference_seeds` seeds; each metric's margin is its tolerance times the
//!    reference mean (or the absolute tolerance).
//! 2. The ladder of standard settings the evaluator knows runs first, each judged like any candidate.
//!    A rung whose runs break only limits a smaller time step cures is stepped down once
//!    ([`step_down_factor`]); the best valid rung gets its extra seeds and is verified on fresh seeds
//!    before the search (step 6), so that the answer never costs more than it. A new candidate
//!    predicted dearer than the cheapest one still in the running runs one seed first, cut at that
//!    cost; points predicted [`FAR_TOO_DEAR`] are not run.
//! 3. An initial design: a randomly shifted Halton sequence (Cranley-Patterson rotation seeded by the
//!    search seed), quantized to a 1/64 grid; points the evaluator predicts invalid (e.g. an impact
//!    overlap past the divergence limit) are recorded and never run.
//! 4. Every candidate starts with `seeds` runs. It is feasible when every run settled and every kept
//!    metric is equivalent by the two one-sided tests (Schuirmann 1987: the 90 % Welch interval of
//!    the difference inside ±margin); infeasible when a run diverged or did not settle, or a metric is
//!    different (interval wholly outside). An undecided candidate that could still beat the incumbent
//!    (the cheapest feasible one) gets `seeds` more runs, up to `max_seeds`.
//! 5. Refinement: a pattern search (compass search, Kolda, Lewis & Torczon 2003) around the incumbent
//!    (or, while none is feasible, around the candidate closest to equivalence): ±step along every lever
//!    plus the last successful move repeated, leaving out moves that a log-linear fit of the costs so far
//!    predicts dearer than the incumbent; the step halves when a round brings no improvement. Once the
//!    step is below the grid, further Halton points explore, until the budget is spent.
//! 6. Verification (`3 × verify_seeds` runs are kept for it): the cheapest feasible candidate (among
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
    /// Standard settings the evaluator knows (the ladder), evaluated before the search.
    pub standards: usize,
    /// Most the whole tune may spend, in mean reference runs' cost (the search stops proposing
    /// when the next round and the verification would pass it).
    pub max_spend: f64,
    /// Whether runs that can no longer win are cut at a cost cap (see [`Job::cap`]).
    pub cut_runs: bool,
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
    /// The standard setting (index into the evaluator's ladder) instead of a point.
    pub standard: Option<usize>,
    /// Cost past which the run is stopped: by then its candidate cannot beat the incumbent whatever
    /// its other runs cost (None: run to the end).
    pub cap: Option<f64>,
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
    /// The run's validity warnings (any one makes its candidate infeasible).
    pub warnings: Vec<String>,
    /// Whether the run was stopped at its cost cap.
    pub cut: bool,
    /// Every pile metric of the summary (the evaluator's list), kept or not, for the answer sheet.
    pub pile: Vec<f64>,
    /// When every warning of the run is one a smaller time step cures (energy balance, overlap): the
    /// largest measured value over its limit (e.g. 1.08 for an energy-balance error of 1.08 % against
    /// a 1 % tolerance). None when the run has no warning or another kind of problem.
    pub excess: Option<f64>,
}

impl Outcome {
    /// A settled run without warnings.
    pub fn settled(cost: f64, metrics: Vec<f64>) -> Self {
        Self { failure: None, cost, metrics, warnings: Vec::new(), cut: false, pile: Vec::new(), excess: None }
    }

    /// Why the run cannot count: its failure, else its first validity warning.
    pub fn problem(&self) -> Option<String> {
        self.failure.clone().or_else(|| self.warnings.first().map(|w| format!("validity warning: {w}")))
    }
}

/// What an evaluator predicts of a setting before running it.
#[derive(Clone, Debug, PartialEq)]
pub struct Screen {
    /// Identifies the runs the setting makes, as resolved (e.g. the time step that actually runs):
    /// settings with the same identity are one candidate.
    pub identity: String,
    /// Why the setting is predicted to break a validity limit or fail (it is recorded, never run).
    pub invalid: Option<String>,
    /// The normalized point of the values that actually run (empty: the point as asked, or a
    /// standard setting); the candidate records this one.
    pub resolved: Vec<f64>,
    /// Predicted cost of a run relative to a reference run's, from the time step that runs (the
    /// settle time taken from the reference): the reference's time step over this one, times the
    /// disk count over the reference's. None when it cannot be predicted.
    pub relative_cost: Option<f64>,
}

/// Runs batches of jobs and screens settings.
pub trait Evaluator {
    /// What `point` (or standard setting `standard`, when given) resolves to and whether it is
    /// predicted invalid.
    fn screen(&mut self, point: &[f64], standard: Option<usize>) -> Screen;
    /// Runs `jobs` (as one parallel batch); outcomes in job order.
    fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, String>;
    /// A new standard setting: standard `standard` with the fraction of the time scale that sets its
    /// time step multiplied by at most `factor` (< 1; the evaluator rounds the new fraction down).
    /// Returns its index in the ladder, or None when the setting's time step is not set by a fraction.
    fn step_down(&mut self, standard: usize, factor: f64) -> Option<usize>;
}

/// A point of the lever space predicted (from its time step) to cost more than this times the cheapest
/// candidate still in the running is not run: levers that shorten settling (damping, fill height)
/// rarely take a third off the reference's settle time.
pub const FAR_TOO_DEAR: f64 = 1.5;

/// What a stepped-down time step aims at: the measured excess (see [`Outcome::excess`]) brought to
/// this share of its limit, leaving room for seeds not yet run.
pub const STEP_DOWN_SAFETY: f64 = 0.8;

/// The factor a time step is multiplied by when its runs' largest measured excess over a validity
/// limit is `excess` and a run of it is predicted to cost `relative_cost` of a reference run (the
/// reference's time step over its own).
///
/// The error of a fixed-step integrator follows a power of the time step, `e ∝ dt^p`. Two points
/// bound p: the rung's runs (`excess` times the limit) and the reference's, which passed (at most the
/// limit) with a time step `relative_cost` times the rung's; so `p ≥ ln(excess) / ln(1 /
/// relative_cost)`, and p ≥ 1 for any consistent integrator. With the smallest p these allow, the
/// step is the largest that can still miss the limit, scaled so that the excess lands on
/// [`STEP_DOWN_SAFETY`]: `(STEP_DOWN_SAFETY / excess)^(1/p)`. A larger true p only leaves more margin.
/// None when there is no excess to cure or the stepped rung would cost the reference's or more.
pub fn step_down_factor(excess: f64, relative_cost: Option<f64>) -> Option<f64> {
    if !(excess.is_finite() && excess > STEP_DOWN_SAFETY) {
        return None;
    }
    let order = match relative_cost.filter(|r| *r > 0.0 && *r < 1.0) {
        Some(r) => (excess.ln() / (1.0 / r).ln()).max(1.0),
        None => 1.0,
    };
    let factor = (STEP_DOWN_SAFETY / excess).powf(1.0 / order);
    relative_cost.is_none_or(|r| r / factor < 1.0).then_some(factor)
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
    /// A standard setting of the ladder.
    Standard,
}

impl Origin {
    /// In words.
    pub fn name(self) -> &'static str {
        match self {
            Origin::Initial => "initial",
            Origin::Refine => "refine",
            Origin::Explore => "explore",
            Origin::Standard => "standard",
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
    /// Normalized coordinates (empty for a standard setting).
    pub point: Vec<f64>,
    /// The standard setting it is (index into the ladder), if it is one.
    pub standard: Option<usize>,
    /// What it resolves to (see [`Screen::identity`]).
    pub identity: String,
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
    /// Predicted cost relative to the reference's (see [`Screen::relative_cost`]).
    pub relative_cost: Option<f64>,
    /// The candidate (index) whose runs broke a validity limit that a smaller time step cures, when
    /// this one is that setting with its time step stepped down.
    pub stepped_from: Option<usize>,
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
    /// Kept metrics whose tolerance the reference's own spread cannot decide within `max_seeds`:
    /// when any, the search stopped before proposing anything.
    pub undecidable: Vec<Undecidable>,
}

/// A kept metric the search cannot decide (see [`decidability`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Undecidable {
    /// Index of the kept metric.
    pub metric: usize,
    /// The reference's mean.
    pub mean: f64,
    /// The reference's seed-to-seed standard deviation.
    pub spread: f64,
    /// The asked absolute margin.
    pub margin: f64,
    /// The smallest absolute margin decidable with `max_seeds` seeds (the 90 % half-width of an
    /// equal-spread candidate with no difference at all).
    pub decidable_margin: f64,
    /// Seeds per candidate that would decide the asked margin with the reference as run; None when
    /// no number would (the reference needs more seeds too).
    pub seeds_needed: Option<usize>,
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
        self.closest_where(|_| true)
    }

    /// [`Self::closest`] among the points of the lever space (standard settings left out).
    pub fn closest_point(&self) -> Option<usize> {
        self.closest_where(|c| c.standard.is_none())
    }

    fn closest_where(&self, keep: impl Fn(&Candidate) -> bool) -> Option<usize> {
        let scored = self
            .candidates
            .iter()
            .enumerate()
            .filter(|(_, c)| c.verification.is_empty() && keep(c))
            .map(|(i, c)| (i, self.assess(c).worst));
        scored.filter(|(_, w)| w.is_finite()).min_by(|a, b| a.1.total_cmp(&b.1)).map(|(i, _)| i)
    }

    /// The cheapest candidate feasible in the search among those `keep` accepts, and its mean cost
    /// (infinite when there is none); one dearer than the reference itself, or one that failed its
    /// verification, never counts.
    pub fn cheapest_feasible(&self, keep: impl Fn(&Candidate) -> bool) -> (Option<usize>, f64) {
        let mut best = (None, stats::describe(&self.reference_costs()).mean);
        let failed = |c: &Candidate| self.assess_verification(c).is_some_and(|a| a.state != State::Feasible);
        for (k, cand) in self.candidates.iter().enumerate().filter(|(_, c)| keep(c) && !failed(c)) {
            let a = self.assess(cand);
            if a.state == State::Feasible && a.cost < best.1 {
                best = (Some(k), a.cost);
            }
        }
        best
    }

    /// The cheapest standard setting that was feasible in the search (valid and equivalent).
    pub fn best_standard(&self) -> Option<usize> {
        self.cheapest_feasible(|c| c.standard.is_some()).0
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
    if let Some(failure) = runs.iter().find_map(Outcome::problem) {
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

/// The kept metrics whose margin cannot be decided within `max_seeds` candidate seeds given the
/// reference's own spread: even a candidate with exactly the reference's mean and spread would leave
/// its 90 % interval, `t(0.95, n + n_r − 2) · s · √(1/n + 1/n_r)`, wider than the margin.
pub fn decidability(reference: &[Outcome], margins: &[f64], max_seeds: usize) -> Vec<Undecidable> {
    let n_r = reference.len();
    let half = |s: f64, n: usize| {
        stats::student_t_quantile(0.95, (n + n_r - 2) as f64) * s * (1.0 / n as f64 + 1.0 / n_r as f64).sqrt()
    };
    margins
        .iter()
        .enumerate()
        .filter_map(|(k, &margin)| {
            let r = stats::describe(&reference.iter().map(|o| o.metrics[k]).collect::<Vec<_>>());
            let decidable_margin = half(r.std, max_seeds.max(2));
            (decidable_margin >= margin).then(|| Undecidable {
                metric: k,
                mean: r.mean,
                spread: r.std,
                margin,
                decidable_margin,
                seeds_needed: first_deciding(max_seeds.max(2), |n| half(r.std, n) < margin),
            })
        })
        .collect()
}

/// The smallest count from `low` up to 100 000 for which `decides` holds (it must stay true above
/// it), by bisection; None when even 100 000 does not decide.
fn first_deciding(low: usize, decides: impl Fn(usize) -> bool) -> Option<usize> {
    let (mut low, mut high) = (low, 100_000);
    if !decides(high) {
        return None;
    }
    while low < high {
        let mid = (low + high) / 2;
        if decides(mid) { high = mid } else { low = mid + 1 }
    }
    Some(high)
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
    seen: HashSet<String>,
    shift: Vec<f64>,
    halton_index: u64,
    /// Cost of every run so far.
    spent: f64,
    /// The next fresh seed of a verification.
    next_seed: u64,
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
            undecidable: Vec::new(),
        };
        let next_seed = config.reference_seeds.max(config.max_seeds) as u64;
        Self { config, evaluator, result, seen: HashSet::new(), shift, halton_index: 1, spent: 0.0, next_seed }
    }

    fn run(mut self) -> Result<SearchResult, String> {
        let c = self.config;
        assert!(c.dims <= PRIMES.len(), "at most {} levers", PRIMES.len());
        self.reference()?;
        self.result.undecidable = decidability(&self.result.reference, &self.result.margins, c.max_seeds);
        if !self.result.undecidable.is_empty() {
            return Ok(self.result);
        }
        let reserve = 3 * c.verify_seeds;
        let search_end = c.budget.saturating_sub(reserve);
        // The ladder always runs (it is the yardstick of the answer), one setting per batch so that
        // each is cut against the best so far.
        for k in 0..c.standards {
            if let Some(index) = self.propose_standard(k) {
                self.run_more(&[(index, c.seeds)])?;
                self.step_down(index, false)?;
            }
        }
        // The best standard setting is settled and verified first: it is the answer unless the
        // search verifies a cheaper one.
        while self.extra_seeds(search_end)? {}
        self.verify(|c| c.standard.is_some())?;
        let room = (search_end.saturating_sub(self.result.runs)) / (2 * c.seeds);
        let initial = c.initial.unwrap_or((2 * c.dims + 2).max(6)).min(room).min(self.affordable());
        let fresh = self.explore(initial.max(2), Origin::Initial);
        self.evaluate_new(&fresh, search_end)?;
        let mut step: f64 = 0.25;
        let mut center: Option<usize> = None;
        let mut last_move: Option<Vec<f64>> = None;
        let mut best_cost = f64::INFINITY;
        loop {
            if self.result.runs + c.seeds.min(c.max_seeds) > search_end || self.affordable() == 0 {
                break;
            }
            if self.extra_seeds(search_end)? {
                continue;
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
                    break;
                }
            }
            if self.evaluate_new(&fresh, search_end)? == 0 {
                break;
            }
        }
        self.verify(|_| true)?;
        Ok(self.result)
    }

    fn reference(&mut self) -> Result<(), String> {
        let c = self.config;
        let jobs: Vec<Job> = (0..c.reference_seeds as u64)
            .map(|seed| Job { candidate: 0, point: Vec::new(), role: Role::Reference, seed, standard: None, cap: None })
            .collect();
        let outcomes = self.evaluate(&jobs)?;
        if let Some(failure) = outcomes.iter().find_map(|o| o.failure.clone()) {
            return Err(format!("the reference scene itself does not settle on every seed ({failure}): fix it first"));
        }
        if let Some(warning) = outcomes.iter().find_map(|o| o.warnings.first()) {
            return Err(format!(
                "the reference scene itself breaks a validity limit ({warning}): no candidate can be held to the \
                 limits it breaks; fix it first"
            ));
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

    /// Runs a batch, counting its runs and cost.
    fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, String> {
        let outcomes = self.evaluator.evaluate(jobs)?;
        self.result.runs += jobs.len();
        self.spent += outcomes.iter().map(|o| o.cost).sum::<f64>();
        Ok(outcomes)
    }

    /// How many more candidates (at `seeds` runs each) the spend limit leaves room for, keeping two
    /// verification rounds. A candidate's run is priced at the cheapest candidate still in the running
    /// (feasible, or undecided with every run valid), a verification run at the dearest of them, the
    /// one that may have to be verified (without any: both at the mean of the runs so far, else the
    /// reference's).
    fn affordable(&self) -> usize {
        let c = self.config;
        let reference = stats::describe(&self.result.reference_costs()).mean;
        let running = self.running_costs();
        let tried: Vec<f64> = self.result.candidates.iter().flat_map(|c| &c.runs).map(|o| o.cost).collect();
        let fallback = if tried.is_empty() { reference } else { stats::describe(&tried).mean };
        let unit = running.iter().copied().reduce(f64::min).unwrap_or(fallback);
        let verification = running.iter().copied().reduce(f64::max).unwrap_or(fallback);
        let left = c.max_spend * reference - self.spent - (2 * c.verify_seeds) as f64 * verification;
        if left > 0.0 { (left / (c.seeds as f64 * unit)).floor() as usize } else { 0 }
    }

    /// The mean costs of the candidates still in the running (feasible, or undecided with every run
    /// settled and valid) that are cheaper than the reference.
    fn running_costs(&self) -> Vec<f64> {
        let reference = stats::describe(&self.result.reference_costs()).mean;
        self.result
            .candidates
            .iter()
            .map(|cand| self.result.assess(cand))
            .filter(|a| matches!(a.state, State::Feasible | State::Undecided) && a.cost < reference)
            .map(|a| a.cost)
            .collect()
    }

    /// The point snapped to the grid (list levers to bin centres).
    fn snap(&self, point: &[f64]) -> Vec<f64> {
        point
            .iter()
            .zip(&self.config.levels)
            .map(|(x, levels)| {
                let x = x.clamp(0.0, 1.0);
                match levels {
                    Some(n) => {
                        let k = ((x * *n as f64).floor() as i64).min(*n as i64 - 1);
                        (k as f64 + 0.5) / *n as f64
                    }
                    None => (x * QUANT).round() / QUANT,
                }
            })
            .collect()
    }

    /// A new candidate unless one resolves to the same runs; predicted-invalid ones are recorded, not
    /// returned.
    fn add(&mut self, point: Vec<f64>, standard: Option<usize>, origin: Origin) -> Option<usize> {
        let screen = self.evaluator.screen(&point, standard);
        if !self.seen.insert(screen.identity.clone()) {
            return None;
        }
        let valid = screen.invalid.is_none();
        let id = self.result.candidates.len() + 1;
        let point = if screen.resolved.is_empty() { point } else { screen.resolved };
        self.result.candidates.push(Candidate {
            id,
            point,
            standard,
            identity: screen.identity,
            origin,
            predicted_invalid: screen.invalid,
            runs: Vec::new(),
            verification: Vec::new(),
            verify_seeds: Vec::new(),
            relative_cost: screen.relative_cost,
            stepped_from: None,
        });
        valid.then_some(id - 1)
    }

    fn propose(&mut self, point: &[f64], origin: Origin) -> Option<usize> {
        let point = self.snap(point);
        self.add(point, None, origin)
    }

    fn propose_standard(&mut self, k: usize) -> Option<usize> {
        self.add(Vec::new(), Some(k), Origin::Standard)
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
            let i = self.halton_index;
            self.halton_index += 1;
            let point: Vec<f64> =
                (0..self.config.dims).map(|d| (radical_inverse(i, PRIMES[d]) + self.shift[d]).fract()).collect();
            if self.promising(&self.snap(&point)) {
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
            if self.promising(&self.snap(&p)) {
                fresh.extend(self.propose(&p, Origin::Refine).filter(|&k| !self.far_too_dear(k)));
            }
        }
        fresh
    }

    /// Least-squares fit of ln(mean cost) = b0 + Σ b_d u_d over the lever-space candidates whose runs
    /// all settled (a failed run's cost says nothing about a settled one's); None with too few of them.
    fn cost_fit(&self) -> Option<Vec<f64>> {
        let n = self.config.dims + 1;
        let rows: Vec<(Vec<f64>, f64)> = self
            .result
            .candidates
            .iter()
            .filter(|c| c.standard.is_none() && !c.runs.is_empty() && c.runs.iter().all(|o| o.failure.is_none()))
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
        let fit = (end.saturating_sub(self.result.runs) / seeds).min(self.affordable());
        let chosen: Vec<(usize, usize)> = fresh.iter().take(fit).map(|&k| (k, seeds)).collect();
        self.run_more(&chosen)?;
        Ok(chosen.len())
    }

    /// Gives more seeds to undecided candidates that could still win; false when there are none.
    fn extra_seeds(&mut self, end: usize) -> Result<bool, String> {
        let c = self.config;
        let (_, incumbent_cost) = self.incumbent();
        let mut chosen = Vec::new();
        let mut room = end.saturating_sub(self.result.runs).min(self.affordable() * c.seeds);
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
        self.config.cut_runs.then(|| (cand.runs.len() + more) as f64 * incumbent - spent)
    }

    /// When every problem of candidate `k`'s runs (its verification runs when `verified`) is a
    /// validity warning that a smaller time step cures, and `k` is a standard setting not itself
    /// stepped down: the same setting with its time step multiplied by [`step_down_factor`] of the
    /// largest measured excess becomes a new standard setting and runs its search seeds (when the
    /// budget and the spend limit leave room for them and a verification). Returns its index.
    fn step_down(&mut self, k: usize, verified: bool) -> Result<Option<usize>, String> {
        let c = self.config;
        let cand = &self.result.candidates[k];
        let runs = if verified { &cand.verification } else { &cand.runs };
        let (Some(standard), None) = (cand.standard, cand.stepped_from) else { return Ok(None) };
        if self.result.candidates.iter().any(|other| other.stepped_from == Some(k)) {
            return Ok(None);
        }
        let warned = runs.iter().filter(|o| o.failure.is_some() || !o.warnings.is_empty());
        let excess = warned.map(|o| o.excess.filter(|_| o.failure.is_none())).collect::<Option<Vec<f64>>>();
        let largest = excess.and_then(|e| e.into_iter().reduce(f64::max));
        let Some(factor) = largest.and_then(|e| step_down_factor(e, cand.relative_cost)) else {
            return Ok(None);
        };
        let Some(stepped) = self.evaluator.step_down(standard, factor) else { return Ok(None) };
        let Some(index) = self.propose_standard(stepped) else { return Ok(None) };
        self.result.candidates[index].stepped_from = Some(k);
        let reference = stats::describe(&self.result.reference_costs()).mean;
        let unit = self.result.candidates[index].relative_cost.map_or(reference, |r| r * reference);
        let price = (c.seeds + c.verify_seeds) as f64 * unit;
        if self.result.runs + c.seeds + c.verify_seeds > c.budget || self.spent + price > c.max_spend * reference {
            return Ok(None);
        }
        self.run_more(&[(index, c.seeds)])?;
        Ok(Some(index))
    }

    /// Whether candidate `k` is predicted ([`Candidate::relative_cost`]) to cost more than
    /// [`FAR_TOO_DEAR`] times the cheapest candidate still in the running: it would have to settle in
    /// a third less time than the reference to win, so it is recorded and not run.
    fn far_too_dear(&self, k: usize) -> bool {
        let reference = stats::describe(&self.result.reference_costs()).mean;
        let cand = &self.result.candidates[k];
        cand.relative_cost.is_some_and(|r| r * reference > FAR_TOO_DEAR * self.likely_cost())
    }

    /// Whether `cand` is predicted dearer than the cheapest candidate still in the running.
    fn predicted_dear(&self, cand: &Candidate) -> bool {
        let reference = stats::describe(&self.result.reference_costs()).mean;
        self.config.cut_runs && cand.relative_cost.is_some_and(|r| r * reference > self.likely_cost())
    }

    /// Runs `more` further search seeds of each candidate, as one batch; a new candidate predicted
    /// dearer than the cheapest one in the running ([`Self::predicted_dear`]) first runs one seed
    /// alone, and the rest only when that run ended below its cap and valid.
    fn run_more(&mut self, chosen: &[(usize, usize)]) -> Result<(), String> {
        let probe =
            |s: &Self, k: usize| s.result.candidates[k].runs.is_empty() && s.predicted_dear(&s.result.candidates[k]);
        let probes: Vec<(usize, usize)> =
            chosen.iter().filter(|&&(k, more)| more > 1 && probe(self, k)).map(|&(k, _)| (k, 1)).collect();
        if probes.is_empty() {
            return self.run_batch(chosen);
        }
        self.run_batch(&probes)?;
        let rest: Vec<(usize, usize)> = chosen
            .iter()
            .filter_map(|&(k, more)| match probes.iter().any(|&(p, _)| p == k) {
                true if self.result.candidates[k].runs.iter().any(|o| o.problem().is_some()) => None,
                true => Some((k, more - 1)),
                false => Some((k, more)),
            })
            .collect();
        self.run_batch(&rest)
    }

    /// Runs `more` further search seeds of each candidate, as one batch.
    fn run_batch(&mut self, chosen: &[(usize, usize)]) -> Result<(), String> {
        let mut jobs = Vec::new();
        for &(k, more) in chosen {
            let cand = &self.result.candidates[k];
            let cap = self.cap(cand, more);
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
        let reference = stats::describe(&self.result.reference_costs()).mean;
        self.running_costs().into_iter().fold(reference, f64::min)
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
    /// says the edge of the acceptable region is nearer than the search runs showed. A standard
    /// setting whose fresh runs broke a limit that a smaller time step cures is stepped down
    /// ([`Self::step_down`]) and the stepped setting joins the queue.
    fn verify(&mut self, keep: impl Fn(&Candidate) -> bool) -> Result<(), String> {
        let mut tried = HashSet::new();
        let mut limit = f64::INFINITY;
        let bound =
            self.result.recommended.map_or(f64::INFINITY, |k| self.result.assess(&self.result.candidates[k]).cost);
        while let Some(k) = self.next_to_verify(&tried, limit, |c| keep(c) && self.result.assess(c).cost < bound) {
            tried.insert(k);
            match self.verify_candidate(k)? {
                Some(true) => {
                    self.result.recommended = Some(k);
                    return Ok(());
                }
                Some(false) => {}
                None => return Ok(()),
            }
            if self.step_down(k, true)?.is_none() {
                limit = 0.9 * self.result.assess(&self.result.candidates[k]).worst;
            }
        }
        Ok(())
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

    /// Runs candidate `k` on fresh seeds (once more when undecided): Some(true) when it passes,
    /// Some(false) when it fails, None when the budget or the spend limit leaves no room.
    fn verify_candidate(&mut self, k: usize) -> Result<Option<bool>, String> {
        let c = self.config;
        for round in 0..2 {
            let reference = stats::describe(&self.result.reference_costs()).mean;
            let price = c.verify_seeds as f64 * self.result.assess(&self.result.candidates[k]).cost;
            let first = self.result.candidates.iter().all(|c| c.verification.is_empty());
            if self.result.runs + c.verify_seeds > c.budget || (!first && self.spent + price > c.max_spend * reference)
            {
                return Ok(None);
            }
            let cand = &self.result.candidates[k];
            let seeds: Vec<u64> = (self.next_seed..self.next_seed + c.verify_seeds as u64).collect();
            self.next_seed += c.verify_seeds as u64;
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
            match assess(&self.result.reference, &cand.verification, &self.result.margins).state {
                State::Feasible => return Ok(Some(true)),
                State::Undecided if round == 0 => continue,
                _ => return Ok(Some(false)),
            }
        }
        Ok(Some(false))
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
        let run = |m: f64| Outcome::settled(1.0, vec![m]);
        let reference: Vec<Outcome> = [1.0, 1.01, 0.99, 1.0].iter().map(|&m| run(m)).collect();
        let same: Vec<Outcome> = [1.0, 1.005, 0.995].iter().map(|&m| run(m)).collect();
        assert_eq!(assess(&reference, &same, &[0.05]).state, State::Feasible);
        let far: Vec<Outcome> = [1.5, 1.505, 1.495].iter().map(|&m| run(m)).collect();
        assert!(matches!(assess(&reference, &far, &[0.05]).state, State::Infeasible(_)));
        let failed = vec![Outcome { failure: Some("diverged".into()), ..run(1.0) }];
        assert!(matches!(assess(&reference, &failed, &[0.05]).state, State::Infeasible(_)));
    }
}
