//! What the search works with: its configuration, the runs it asks for ([`Job`]) and gets back
//! ([`Outcome`]), what an evaluator predicts of a setting ([`Screen`]), the candidates and the
//! result. Judgements are in `judge`, the search itself in `search`.

use std::fmt;
use std::path::PathBuf;

use super::spec::SceneError;
use crate::physics::number::short;
use crate::physics::placement::PlacementError;
use crate::physics::warning::{ValidityWarning, WarningKind};
use crate::runner::RunnerError;
use crate::stats::{self, Describe, Equivalence};

/// The first seed of the verification runs (seed numbers count from the reference's placement seed):
/// past the run budget, which neither the reference nor any candidate's search seeds can reach, so
/// verification runs are always fresh.
pub fn first_verification_seed(budget: usize, reference_seeds: usize) -> u64 {
    budget.max(reference_seeds) as u64
}

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
    /// Per kept metric: its name, for messages.
    pub metrics: Vec<String>,
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
    /// Per lever: +1 where raising it makes the contacts dissipate more (a contact damping), -1 where
    /// lowering it does (a restitution), 0 otherwise: until measured settle times say otherwise, the
    /// cheap corner takes the dissipative end (settling sooner).
    pub dissipation: Vec<f64>,
    /// Per lever: the coordinate of the reference's value, when in range: where the cheap corner
    /// leaves a lever that moves neither the time step nor, as far as known, the settle time
    /// (numerical damping stays the user's); None: the centre.
    pub home: Vec<Option<f64>>,
    /// Standard settings the evaluator knows (the ladder).
    pub standards: usize,
    /// Whether the first standard setting is the time step alone at its largest valid value: the top
    /// of the time-step path (a time-step key is a lever).
    pub path: bool,
    /// The lever that sets the time step (raising it lengthens the step), when one does.
    pub time_step: Option<usize>,
    /// Most the whole tune may spend, in mean reference runs' cost.
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

impl Job {
    /// The reference's run on replicate `seed`.
    pub fn reference(seed: u64) -> Self {
        Job { candidate: 0, point: Vec::new(), role: Role::Reference, seed, standard: None, cap: None }
    }
}

/// Why a run cannot count.
#[derive(Clone, Debug, PartialEq)]
pub enum RunFailure {
    /// Ended because its state became invalid (the simulation's reason).
    Diverged(String),
    /// The duration elapsed without settling.
    NotSettled,
    /// Stopped at its cost cap: its candidate could no longer win.
    Cut {
        /// The cap (cost units).
        cap: f64,
    },
    /// The run failed without a record (the runner's message).
    Error(String),
}

impl fmt::Display for RunFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunFailure::Diverged(why) => write!(f, "diverged: {why}"),
            RunFailure::NotSettled => write!(f, "did not settle"),
            RunFailure::Cut { cap } => write!(f, "cut at {}: its candidate could no longer win", short(*cap)),
            RunFailure::Error(why) => write!(f, "failed: {why}"),
        }
    }
}

/// One validity check's value in a run: measured checks for every finished run, predicted ones
/// where they pass their limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reading {
    /// Which check.
    pub kind: WarningKind,
    /// Its value.
    pub value: f64,
    /// The scene's limit.
    pub limit: f64,
}

impl From<&ValidityWarning> for Reading {
    fn from(w: &ValidityWarning) -> Self {
        Reading { kind: w.kind, value: w.value, limit: w.limit }
    }
}

/// One run's result.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// Why the run cannot count; None when it settled.
    pub failure: Option<RunFailure>,
    /// Its cost (particle-steps or seconds).
    pub cost: f64,
    /// The kept metrics, in order.
    pub metrics: Vec<f64>,
    /// Its validity checks (see [`Reading`]).
    pub readings: Vec<Reading>,
    /// Every pile metric of the summary (the evaluator's list), kept or not, for the answer sheet.
    pub pile: Vec<f64>,
}

/// Kept metric `k` over `runs` described (its non-finite values skipped).
pub fn describe_metric(runs: &[Outcome], k: usize) -> Describe {
    stats::describe(&runs.iter().map(|o| o.metrics[k]).collect::<Vec<_>>())
}

impl Outcome {
    /// A settled run without readings.
    pub fn settled(cost: f64, metrics: Vec<f64>) -> Self {
        Self { failure: None, cost, metrics, readings: Vec::new(), pile: Vec::new() }
    }

    /// Whether the run was stopped at its cost cap.
    pub fn is_cut(&self) -> bool {
        matches!(self.failure, Some(RunFailure::Cut { .. }))
    }

    /// The reading of `kind`, if the run has one.
    pub fn reading(&self, kind: WarningKind) -> Option<&Reading> {
        self.readings.iter().find(|r| r.kind == kind)
    }

    /// Whether a reading passes its own limit.
    pub fn has_warning(&self) -> bool {
        self.readings.iter().any(|r| r.value > r.limit)
    }
}

/// Why a setting cannot start.
#[derive(Clone, Debug, PartialEq)]
pub enum ScreenError {
    /// Its scene is invalid.
    Scene(SceneError),
    /// Its placement fails.
    Placement(PlacementError),
}

impl fmt::Display for ScreenError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ScreenError::Scene(why) => write!(f, "invalid scene: {why}"),
            ScreenError::Placement(e) => write!(f, "placement fails: {e}"),
        }
    }
}

/// What an evaluator predicts of a setting before running it.
#[derive(Clone, Debug, PartialEq)]
pub struct Screen {
    /// Identifies the runs the setting makes, as resolved (e.g. the time step that actually runs):
    /// settings with the same identity are one candidate.
    pub identity: String,
    /// The validity warnings predicted for it, or why it cannot start.
    pub predicted: Result<Vec<ValidityWarning>, ScreenError>,
    /// The normalized point of the values that actually run (empty: the point as asked, or a
    /// standard setting); the candidate records this one.
    pub resolved: Vec<f64>,
    /// Predicted cost of a run relative to a reference run's, from the time step that runs (the
    /// settle time taken from the reference): the reference's time step over this one, times the
    /// disk count over the reference's. None when it cannot be predicted.
    pub relative_cost: Option<f64>,
}

/// Why a tune could not go on.
#[derive(Debug, Clone, PartialEq)]
pub enum TuneError {
    /// The runner or the results file failed.
    Runner(RunnerError),
    /// A run the tune made is not in the results file.
    MissingRun {
        /// The results file.
        results: PathBuf,
        /// The run id.
        run: String,
    },
    /// Stopped by Ctrl-C; the finished runs are in the file.
    Interrupted,
    /// The reference itself diverged or did not settle on a seed.
    ReferenceFailed {
        /// Its replicate number.
        seed: u64,
        /// How.
        failure: RunFailure,
    },
    /// A kept metric is undefined (NaN) on some of the reference's runs, so it gives no margin.
    UndefinedMetric {
        /// The kept metric's name.
        metric: String,
        /// The replicate numbers of the runs it is undefined on.
        replicates: Vec<u64>,
        /// The reference's runs in all.
        runs: usize,
    },
    /// A kept metric's reference mean is zero, so a relative tolerance gives no margin.
    NoMargin {
        /// The kept metric's name.
        metric: String,
        /// The reference mean.
        mean: f64,
    },
}

impl fmt::Display for TuneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TuneError::Runner(e) => write!(f, "{e}"),
            TuneError::MissingRun { results, run } => {
                write!(f, "{}: run {run} is missing from the results file", results.display())
            }
            TuneError::Interrupted => write!(f, "interrupted: finished runs are kept; continue with --resume"),
            TuneError::ReferenceFailed { seed, failure } => {
                let (what, fix) = match failure {
                    RunFailure::Error(_) => ("cannot run", "fix it first"),
                    RunFailure::NotSettled => (
                        "does not settle",
                        "lengthen the scene's run.duration, or damp it more (or relax its settle.* criteria)",
                    ),
                    _ => ("does not settle", "fix it first"),
                };
                write!(f, "the reference scene itself {what} on every seed (replicate {seed} {failure}): {fix}")
            }
            TuneError::UndefinedMetric { metric, replicates, runs } => write!(
                f,
                "kept metric {metric} is undefined (NaN) on {} of the reference's {runs} runs (replicates {}): the \
                 pile has no room for it (docs/deposition.md says where each pile metric is defined); keep another \
                 metric",
                replicates.len(),
                replicates.iter().map(u64::to_string).collect::<Vec<_>>().join(", ")
            ),
            TuneError::NoMargin { metric, mean } => write!(
                f,
                "kept metric {metric} has mean {} in the reference: a relative tolerance gives no margin; give \
                 an absolute one (keep.{metric} = {{ absolute = … }})",
                short(*mean)
            ),
        }
    }
}

impl std::error::Error for TuneError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            TuneError::Runner(e) => Some(e),
            _ => None,
        }
    }
}

impl From<RunnerError> for TuneError {
    fn from(error: RunnerError) -> Self {
        TuneError::Runner(error)
    }
}

/// Runs batches of jobs and screens settings.
pub trait Evaluator {
    /// What `point` (or standard setting `standard`, when given) resolves to and what it is
    /// predicted to break.
    fn screen(&mut self, point: &[f64], standard: Option<usize>) -> Screen;
    /// What the reference resolves to (see [`Screen::identity`]): a setting that resolves to the
    /// same runs is the reference, never a candidate.
    fn reference_identity(&mut self) -> String;
    /// Runs `jobs` (as one parallel batch); outcomes in job order.
    fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, TuneError>;
    /// A new standard setting: standard `standard` with the fraction of the time scale that sets its
    /// time step multiplied by at most `factor` (< 1; the evaluator rounds the new fraction down).
    /// Returns its index in the ladder, or None when the setting's time step is not set by a fraction.
    fn step_down(&mut self, standard: usize, factor: f64) -> Option<usize>;
    /// Standard setting `standard`'s normalized point of the lever space (each lever at the value
    /// it sets, else at the reference's); None where a lever has no value there or it lies outside
    /// the lever's range.
    fn standard_point(&mut self, _standard: usize) -> Option<Vec<f64>> {
        None
    }
    /// Whether the reference's disks can be placed on seed number `seed`: a seed where they cannot
    /// is no deposition of the reference, and no run is made on it.
    fn placeable(&mut self, _seed: u64) -> bool {
        true
    }
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
    /// A point on the edge of equivalence, between the incumbent and a cheaper point that differs.
    Edge,
    /// A standard setting of the ladder.
    Standard,
    /// A rung of the time-step path (the first standard setting with a smaller time step).
    Path,
}

impl Origin {
    /// In words.
    pub fn name(self) -> &'static str {
        match self {
            Origin::Initial => "initial",
            Origin::Refine => "refine",
            Origin::Explore => "explore",
            Origin::Edge => "edge",
            Origin::Standard => "standard",
            Origin::Path => "time-step path",
        }
    }
}

/// A validity check judged over a set of runs (see `judge::check_figures`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CheckFigure {
    /// Which check.
    pub kind: WarningKind,
    /// The rule's figure: the 75th percentile of the runs' values for a measured check, the largest
    /// for a predicted one.
    pub figure: f64,
    /// The largest value.
    pub worst: f64,
    /// The run (position in the set) with the largest value.
    pub worst_run: usize,
    /// The scene's limit.
    pub limit: f64,
    /// The limit the runs are held to: the scene's, or the reference's own figure where the
    /// reference breaks it ("no worse than the reference").
    pub held_to: f64,
    /// Whether the runs pass.
    pub passes: bool,
}

impl CheckFigure {
    /// How far past what it is held to: the larger of the figure over `held_to` and the worst run
    /// over twice `held_to` (at most 1 when it passes).
    pub fn excess(&self) -> f64 {
        (self.figure / self.held_to).max(self.worst / (2.0 * self.held_to))
    }
}

/// Why a candidate was not run.
#[derive(Clone, Debug, PartialEq)]
pub enum NotRun {
    /// Predicted to break a validity limit more than the reference does.
    Predicted(ValidityWarning),
    /// It cannot start.
    Unstartable(ScreenError),
    /// No runs yet.
    NoRuns,
}

impl fmt::Display for NotRun {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NotRun::Predicted(w) => write!(f, "predicted: {w}"),
            NotRun::Unstartable(e) => write!(f, "{e}"),
            NotRun::NoRuns => write!(f, "no runs"),
        }
    }
}

/// Why a candidate is not acceptable.
#[derive(Clone, Debug, PartialEq)]
pub enum Rejection {
    /// A run diverged, did not settle or failed.
    Failed(RunFailure),
    /// Its runs together break a validity check (see [`CheckFigure`]).
    Invalid(CheckFigure),
    /// A kept metric differs from the reference's (index).
    Differs(usize),
}

impl fmt::Display for Rejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Rejection::Failed(failure) => write!(f, "a run {failure}"),
            Rejection::Invalid(c) => write!(
                f,
                "validity: {} ({}) {} over its runs (worst {}) against {}{}",
                c.kind.name(),
                c.kind.limit_key(),
                short(c.figure),
                short(c.worst),
                short(c.held_to),
                if c.held_to > c.limit { " (the reference's own figure)" } else { "" }
            ),
            Rejection::Differs(k) => write!(f, "kept metric {} differs", k + 1),
        }
    }
}

/// A candidate's standing against the reference.
#[derive(Clone, Debug, PartialEq)]
pub enum State {
    /// Not run.
    NotRun(NotRun),
    /// Every run settled, the runs pass every validity check and every metric is equivalent.
    Feasible,
    /// Not acceptable: why.
    Infeasible(Rejection),
    /// Its runs were cut at their cost cap once it could no longer win, before they settled.
    Cut,
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
            State::Cut => "cut",
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
    /// Every validity check over the runs.
    pub checks: Vec<CheckFigure>,
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
    /// Why it was not run, when it was predicted invalid or cannot start.
    pub predicted_invalid: Option<NotRun>,
    /// Search runs, on seeds 0, 1, ...
    pub runs: Vec<Outcome>,
    /// Verification runs.
    pub verification: Vec<Outcome>,
    /// Seeds of the verification runs.
    pub verify_seeds: Vec<u64>,
    /// Predicted cost relative to the reference's (see [`Screen::relative_cost`]).
    pub relative_cost: Option<f64>,
    /// The candidate (index) this one was stepped down from, for a smaller time step.
    pub stepped_from: Option<usize>,
}

/// A kept metric the search cannot decide (see `judge::decidability`).
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

/// How the time-step path ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathEnd {
    /// Not started (the ladder has no time-step rung, or the search stopped before it).
    NotRun,
    /// A rung passed its verification on fresh seeds: the path's answer (candidate index).
    Verified(usize),
    /// No rung cheaper than the reference is valid and equivalent within the path's resolution.
    NothingCheaper,
    /// The spend limit or the run budget stopped it.
    OutOfBudget,
    /// This rung's verification stayed undecided on a kept metric, and deciding it would take more
    /// fresh runs than the spend limit leaves (candidate index).
    Undecided(usize),
}

/// Why the search over the levers ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SearchEnd {
    /// It did not start: a kept metric the reference cannot decide stopped the tune.
    NotSearched,
    /// What the spend limit left paid for neither another setting's first seeds nor the seeds that
    /// would decide one, each with a verification round in reserve.
    SpendLimit,
    /// The run budget, less its verification reserve, is used up.
    RunBudget,
    /// Neither the pattern search nor the design proposed a new setting that could still win, and
    /// none is left in the running.
    Exhausted,
}

/// What the search found.
#[derive(Clone, Debug, PartialEq)]
pub struct SearchResult {
    /// The reference's runs.
    pub reference: Vec<Outcome>,
    /// Absolute margin of every kept metric.
    pub margins: Vec<f64>,
    /// The reference's own validity figures, one per check its runs report: where one breaks its
    /// limit, candidates are held to no worse than it.
    pub reference_checks: Vec<CheckFigure>,
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
    /// The time-step path's rungs (candidate indices, in the order run) and how it ended.
    pub path: (Vec<usize>, PathEnd),
    /// Why the search over the levers ended.
    pub end: SearchEnd,
    /// With wall time as the objective: the rate each configuration's runs were priced at.
    pub wall_rates: Vec<super::wall_rate::WallRate>,
    /// The seeds of the reference's and the search's runs, by run number: every seed from 0 on
    /// where the reference's disks can be placed.
    pub replicates: Vec<u64>,
    /// The seeds stepped over because the reference's disks cannot be placed on them.
    pub unplaceable: Vec<u64>,
}
