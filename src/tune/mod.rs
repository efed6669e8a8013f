//! `demsweep tune`: find the fastest deposition that still makes the same pile.
//!
//! A tune file ([`file`]) names a reference scene, the levers tune may move, the pile metrics to keep
//! and the search settings. [`search`] decides which runs to make; here they become batches of
//! [`PlannedRun`]s that the ordinary runner executes into one HDF5 file (every run lands there as
//! `run`'s do, so `--resume` after a kill replays the search from the file: the search is deterministic
//! and reads every outcome back from the file). [`report`] writes the recommendation, the best study,
//! the candidates table and the charts.

pub mod design;
mod file;
pub mod judge;
pub mod ladder;
mod measurable;
pub mod model;
pub mod report;
pub mod search;
pub mod spec;
pub mod validity;
pub mod wall_rate;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

pub use file::{is_tune_file, keepable_metrics, load, reference_warnings};
pub use model::{Evaluator, Job, Outcome, Role, Screen, SearchConfig, SearchResult, TuneError};
pub use spec::StandardSetting;
pub use spec::{Keep, Lever, LeverRange, Objective, SceneError, TuneSpec};

use crate::output::table::{ColumnData, SummaryTable};
use crate::physics::RunStatus;
use crate::physics::warning::{ValidityWarning, WarningKind};
use crate::runner::{self, NotePolicy, ProgressMode, RunNote, RunOptions, RunnerError};
use crate::study::{ParamValue, Plan, PlannedRun};
use model::{Reading, RunFailure, ScreenError};
use wall_rate::WallRates;

/// How to run a tune.
#[derive(Clone, Debug, Default)]
pub struct TuneOptions {
    /// Worker threads; 0 = the available cores.
    pub jobs: usize,
    /// Output directory; default `results/<name>/`.
    pub out_dir: Option<PathBuf>,
    /// Reuse the runs of an existing results file.
    pub resume: bool,
    /// With `resume`: reuse runs made by another demsweep version (else refused, naming them).
    pub accept_version: bool,
    /// Overwrite an existing results file.
    pub force: bool,
    /// Print one line per batch.
    pub verbose: bool,
    /// Set (e.g. by Ctrl-C) to stop.
    pub stop: Arc<AtomicBool>,
}

/// What a tune did.
#[derive(Clone, Debug)]
pub struct TuneReport {
    /// The search's result.
    pub result: SearchResult,
    /// The HDF5 file with every run.
    pub results: PathBuf,
    /// Runs that were already in the file (`--resume`).
    pub reused: usize,
    /// Runs made by this invocation.
    pub ran: usize,
    /// Particle-steps of every run, all included.
    pub total_particle_steps: f64,
    /// Stored runs of the results file that this tune did not replay (an earlier tune of the file
    /// that went another way): kept in the file, left out of its summary and report.
    pub unplanned: usize,
}

/// The search's configuration from a tune file.
pub fn search_config(spec: &TuneSpec) -> SearchConfig {
    let s = &spec.search;
    SearchConfig {
        dims: spec.levers.len(),
        levels: spec
            .levers
            .iter()
            .map(|l| match &l.range {
                LeverRange::List(values) => Some(values.len()),
                _ => None,
            })
            .collect(),
        tolerances: spec.keep.iter().map(|k| (k.tolerance, k.absolute)).collect(),
        metrics: spec.keep.iter().map(|k| k.metric.clone()).collect(),
        seeds: s.seeds,
        max_seeds: s.max_seeds,
        reference_seeds: s.reference_seeds(),
        verify_seeds: s.verify_seeds(),
        budget: s.budget,
        seed: s.seed,
        initial: s.initial,
        dissipation: spec.levers.iter().map(|l| ladder::dissipation(&l.key)).collect(),
        home: spec.reference_coordinates(),
        standards: spec.standards.len(),
        path: ladder::time_step_lever(&spec.levers).is_some() && !spec.standards.is_empty(),
        time_step: ladder::time_step_position(&spec.levers),
        max_spend: s.max_spend,
        cut_runs: s.objective == Objective::ParticleSteps,
    }
}

/// The results file of a tune: `OUT/<name>.h5`.
pub fn results_path(spec: &TuneSpec, out_dir: Option<&Path>) -> PathBuf {
    let dir = out_dir.map(Path::to_path_buf).unwrap_or_else(|| Path::new("results").join(&spec.name));
    dir.join(format!("{}.h5", spec.name))
}

/// Runs a tune: the search with real runs, into `OUT/<name>.h5`.
///
/// The search may add standard settings (a rung stepped down to a valid time step); `spec.standards`
/// holds the ladder as it ran afterwards, so that the candidates' `standard` indices name them.
pub fn tune(spec: &mut TuneSpec, options: &TuneOptions) -> Result<TuneReport, TuneError> {
    let mut evaluator = RunEvaluator::new(spec, options);
    let searched = search::search(&search_config(spec), &mut evaluator);
    let (reused, ran, total_particle_steps) = (evaluator.reused, evaluator.ran, evaluator.particle_steps);
    let unplanned = evaluator.unplanned;
    let wall_rates = evaluator.wall_rates.all().to_vec();
    spec.standards = evaluator.standards;
    let mut result = searched?;
    result.wall_rates = wall_rates;
    Ok(TuneReport {
        result,
        results: results_path(spec, options.out_dir.as_deref()),
        reused,
        ran,
        total_particle_steps,
        unplanned,
    })
}

/// The parameters of a job's run: the lever values (a standard setting's keys, from `ladder`), then
/// the placement seed and the candidate.
fn job_parameters(spec: &TuneSpec, ladder: &[StandardSetting], job: &Job) -> Vec<(String, ParamValue)> {
    let mut values: Vec<(String, ParamValue)> = match (job.role, job.standard) {
        (Role::Reference, _) => spec.reference_values().into_iter().map(|(k, v, _)| (k, v)).collect(),
        (_, Some(k)) => ladder[k].values.clone(),
        _ => spec.values(&job.point),
    };
    let seed = spec.reference.placement.seed.wrapping_add(job.seed);
    values.push(("placement.seed".into(), ParamValue::Int(seed as i64)));
    values.push(("tune.candidate".into(), ParamValue::Int(job.candidate as i64)));
    let role = match job.role {
        Role::Reference => "reference",
        Role::Search => "search",
        Role::Verify => "verify",
    };
    values.push(("tune.role".into(), ParamValue::Text(role.into())));
    if let Some(cap) = job.cap {
        values.push(("tune.cap".into(), ParamValue::Float(cap)));
    }
    values
}

/// The scene of a candidate's first seed.
pub fn candidate_scene(
    spec: &TuneSpec,
    candidate: &model::Candidate,
) -> Result<crate::physics::SceneConfig, SceneError> {
    setting_scene(spec, &spec.standards, &candidate.point, candidate.standard, 0)
}

/// The scene of a job or a candidate: standard setting `standard` of `ladder`, or the levers at `point`.
fn setting_scene(
    spec: &TuneSpec,
    ladder: &[StandardSetting],
    point: &[f64],
    standard: Option<usize>,
    seed: u64,
) -> Result<crate::physics::SceneConfig, SceneError> {
    let mut scene = match standard {
        Some(k) => spec.standard_scene(&ladder[k])?,
        None => spec.scene(&spec.values(point))?,
    };
    scene.placement.seed = spec.reference.placement.seed.wrapping_add(seed);
    Ok(scene)
}

/// Placement seeds of a list of seed numbers, as text: `2024-2031` or `2024, 2030`.
pub fn seed_text(spec: &TuneSpec, seeds: &[u64]) -> String {
    let base = spec.reference.placement.seed;
    let actual: Vec<u64> = seeds.iter().map(|s| base.wrapping_add(*s)).collect();
    match actual.as_slice() {
        [] => String::new(),
        [one] => one.to_string(),
        [first, .., last] if actual.windows(2).all(|w| w[1] == w[0] + 1) => format!("{first}-{last}"),
        _ => actual.iter().map(|s| s.to_string()).collect::<Vec<_>>().join(", "),
    }
}

/// The real evaluator: every batch of jobs becomes runs appended to one growing plan, run (or found in
/// the file) by the runner.
pub struct RunEvaluator<'a> {
    spec: &'a TuneSpec,
    options: &'a TuneOptions,
    plan: Plan,
    batches: usize,
    /// The reference's time step (s), the yardstick of predicted costs.
    reference_dt: f64,
    /// The ladder: the spec's standard settings and those the search stepped down.
    pub standards: Vec<StandardSetting>,
    /// Runs found in the results file.
    pub reused: usize,
    /// Runs made.
    pub ran: usize,
    /// Particle-steps of every run evaluated.
    pub particle_steps: f64,
    /// Stored runs the latest batch's plan did not hold.
    pub unplanned: usize,
    /// With wall time as the objective: each configuration's wall time per particle-step.
    pub wall_rates: WallRates,
}

impl<'a> RunEvaluator<'a> {
    /// An evaluator writing `OUT/<name>.h5` for the spec.
    pub fn new(spec: &'a TuneSpec, options: &'a TuneOptions) -> Self {
        let plan = Plan {
            study_path: spec.path.clone(),
            study_text: spec.text.clone(),
            name: spec.name.clone(),
            fingerprint: spec.fingerprint.clone(),
            output: spec.output.clone(),
            runs: Vec::new(),
            warnings: Vec::new(),
        };
        let reference_dt =
            crate::physics::scene_time_step(&spec.reference, spec.initial.as_deref().map(Vec::as_slice)).dt;
        Self {
            spec,
            options,
            plan,
            batches: 0,
            reference_dt,
            standards: spec.standards.clone(),
            reused: 0,
            ran: 0,
            particle_steps: 0.0,
            unplanned: 0,
            wall_rates: WallRates::default(),
        }
    }

    fn planned_run(&self, job: &Job, index: usize) -> PlannedRun {
        let parameters = job_parameters(self.spec, &self.standards, job);
        let scene = match job.role {
            Role::Reference => Ok(self.spec.reference_at(job.seed)),
            _ => setting_scene(self.spec, &self.standards, &job.point, job.standard, job.seed),
        };
        // An invalid scene becomes a run that fails with the reason (status error): the runner
        // records it like any failed run.
        let mut scene = scene.unwrap_or_else(|_| {
            let mut scene = self.spec.reference.clone();
            scene.particles.count = 0;
            scene
        });
        if let Some(cap) = job.cap {
            // Particle-steps past the cap prove the candidate cannot win: stop there.
            let dt = crate::physics::scene_time_step(&scene, self.spec.initial.as_deref().map(Vec::as_slice)).dt;
            let steps = (cap / scene.particles.count.max(1) as f64).ceil();
            scene.run.duration = scene.run.duration.min(steps * dt);
        }
        PlannedRun::new(format!("r{index:05}"), index, parameters, scene, self.spec.initial.clone())
    }
}

impl Evaluator for RunEvaluator<'_> {
    fn screen(&mut self, point: &[f64], standard: Option<usize>) -> Screen {
        let scene = match setting_scene(self.spec, &self.standards, point, standard, 0) {
            Ok(scene) => scene,
            Err(reason) => {
                return Screen {
                    identity: format!("{point:?} {standard:?}"),
                    predicted: Err(ScreenError::Scene(reason)),
                    resolved: Vec::new(),
                    relative_cost: None,
                };
            }
        };
        let disks = self.spec.initial.as_deref().map(Vec::as_slice);
        let identity = validity::identity(&scene, disks);
        let dt = crate::physics::scene_time_step(&scene, disks).dt;
        let disks_ratio = scene.particles.count as f64 / self.spec.reference.particles.count.max(1) as f64;
        let relative_cost = Some(self.reference_dt / dt * disks_ratio).filter(|r| r.is_finite() && *r > 0.0);
        let predicted = validity::predicted_warnings(&scene, disks);
        // The coordinates of the values as written to the scene (rounded, list bins).
        let resolved = match standard {
            Some(_) => Vec::new(),
            None => self
                .spec
                .levers
                .iter()
                .zip(point)
                .map(|(lever, &u)| lever.coordinate(&lever.value(u)).unwrap_or(u))
                .collect(),
        };
        Screen { identity, predicted, resolved, relative_cost }
    }

    fn reference_identity(&mut self) -> String {
        validity::identity(&self.spec.reference, self.spec.initial.as_deref().map(Vec::as_slice))
    }

    fn placeable(&mut self, seed: u64) -> bool {
        self.spec.placement_failure(seed).is_none()
    }

    fn step_down(&mut self, standard: usize, factor: f64) -> Option<usize> {
        let stepped = ladder::stepped_down(&self.standards[standard], factor)?;
        self.standards.push(stepped);
        Some(self.standards.len() - 1)
    }

    fn standard_point(&mut self, standard: usize) -> Option<Vec<f64>> {
        self.spec.lever_point(&self.standards[standard].values)
    }

    fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, TuneError> {
        let first_index = self.plan.runs.len();
        for (k, job) in jobs.iter().enumerate() {
            let run = self.planned_run(job, first_index + k);
            self.plan.runs.push(run);
        }
        let first = self.batches == 0;
        self.batches += 1;
        let options = RunOptions {
            jobs: self.options.jobs,
            out_dir: Some(results_path(self.spec, self.options.out_dir.as_deref()).parent().unwrap().to_path_buf()),
            resume: !first || self.options.resume,
            accept_version: self.options.accept_version,
            force: first && self.options.force,
            progress: ProgressMode::Quiet,
            stop: self.options.stop.clone(),
            notes: NotePolicy::PlanGrows,
            ..Default::default()
        };
        let report = runner::run_plan(&self.plan, &options)?;
        self.unplanned = report
            .notes
            .iter()
            .find_map(|n| match n {
                RunNote::Unplanned { ids, .. } => Some(ids.len()),
                _ => None,
            })
            .unwrap_or(0);
        if report.interrupted {
            return Err(TuneError::Interrupted);
        }
        let reused = jobs.len().saturating_sub(report.ran);
        self.reused += reused;
        self.ran += report.ran;
        let mut rows = Rows::new(&report.summary);
        if (first_index..self.plan.runs.len()).any(|i| rows.warned(i)) {
            rows.warnings = typed_warnings(&report.results)?;
        }
        let mut outcomes = Vec::with_capacity(jobs.len());
        let mut steps = Vec::with_capacity(jobs.len());
        for (k, job) in jobs.iter().enumerate() {
            let run = &self.plan.runs[first_index + k];
            let (outcome, particle_steps) = rows
                .outcome(run, job, self.spec)
                .ok_or_else(|| TuneError::MissingRun { results: report.results.clone(), run: run.id.clone() })?;
            self.particle_steps += particle_steps;
            outcomes.push(outcome);
            steps.push(particle_steps);
        }
        if self.spec.search.objective == Objective::WallTime {
            let configurations: Vec<String> =
                self.plan.runs[first_index..].iter().map(|r| wall_rate::configuration(&r.scene)).collect();
            self.price_wall_time(&configurations, &steps, &mut outcomes);
        }
        if self.options.verbose {
            crate::output::terminal::out(format_args!(
                "{}\n",
                batch_line(self.batches, jobs, reused, self.plan.runs.len())
            ));
        }
        Ok(outcomes)
    }
}

impl RunEvaluator<'_> {
    /// Prices each run's wall time at its configuration's rate ([`wall_rate`]), measuring the rates of
    /// this batch first (a run's cost is its measured wall time until then).
    fn price_wall_time(&mut self, configurations: &[String], steps: &[f64], outcomes: &mut [Outcome]) {
        let mut seen: Vec<&String> = configurations.iter().collect();
        seen.sort();
        seen.dedup();
        for configuration in seen {
            let per_run: Vec<f64> = (0..configurations.len())
                .filter(|&k| &configurations[k] == configuration)
                .map(|k| outcomes[k].cost / steps[k])
                .collect();
            self.wall_rates.record(configuration, &per_run);
        }
        for (k, outcome) in outcomes.iter_mut().enumerate() {
            let rate = self.wall_rates.rate(&configurations[k]);
            if rate.is_finite() && steps[k] > 0.0 {
                outcome.cost = steps[k] * rate;
            }
        }
    }
}

/// One line per batch: its runs, whose they are and how many came from the file.
fn batch_line(batch: usize, jobs: &[Job], reused: usize, total: usize) -> String {
    let mut c: Vec<usize> = jobs.iter().map(|j| j.candidate).collect();
    c.dedup();
    let whose = match (c.first(), c.last()) {
        (Some(0), _) => "reference".to_string(),
        (Some(a), Some(b)) if a == b => format!("candidate {a}"),
        (Some(a), Some(b)) => format!("candidates {a}-{b}"),
        _ => String::new(),
    };
    let role = if jobs.iter().any(|j| j.role == Role::Verify) { "verification of " } else { "" };
    let from_file = if reused > 0 { format!(", {reused} from the file") } else { String::new() };
    format!("batch {batch}: {} runs ({role}{whose}){from_file}; {total} runs so far", jobs.len())
}

/// The typed warnings of every run in a results file, by run index.
fn typed_warnings(results: &Path) -> Result<HashMap<usize, Vec<ValidityWarning>>, TuneError> {
    let error = |e| TuneError::Runner(RunnerError::from(e));
    let file = crate::output::reader::open(results).map_err(error)?;
    let rows = crate::output::reader::rows(&file, results).map_err(error)?;
    Ok(rows.into_iter().map(|row| (row.index, row.warnings)).collect())
}

/// The measured validity checks of every finished run: summary column and the scene's limit.
const MEASURED: [(WarningKind, &str); 2] =
    [(WarningKind::EnergyBalance, "energy_balance_error"), (WarningKind::Overlap, "largest_overlap_ratio")];

/// The share of its cap a run's particle-steps reach when the cap stopped it (the cap rounds up to
/// whole steps).
const CAP_REACHED: f64 = 0.999;

/// The summary's rows by run index.
struct Rows<'a> {
    table: &'a SummaryTable,
    by_index: HashMap<i64, usize>,
    /// Typed warnings by run index, read from the file when a run has any.
    warnings: HashMap<usize, Vec<ValidityWarning>>,
    /// Every pile metric of the summary.
    pile: Vec<String>,
}

impl<'a> Rows<'a> {
    fn new(table: &'a SummaryTable) -> Self {
        let by_index = match table.column("index").map(|c| &c.data) {
            Some(ColumnData::Int(v)) => v.iter().enumerate().map(|(row, &i)| (i, row)).collect(),
            _ => HashMap::new(),
        };
        Self { table, by_index, warnings: HashMap::new(), pile: file::keepable_metrics() }
    }

    /// Whether run `index` has validity warnings.
    fn warned(&self, index: usize) -> bool {
        self.by_index.get(&(index as i64)).is_some_and(|&row| self.number("warnings", row) > 0.0)
    }

    fn number(&self, column: &str, row: usize) -> f64 {
        match self.table.column(column).map(|c| &c.data) {
            Some(ColumnData::Float(v)) => v[row],
            Some(ColumnData::Int(v)) => v[row] as f64,
            _ => f64::NAN,
        }
    }

    fn text(&self, column: &str, row: usize) -> String {
        self.table.column(column).map(|c| c.data.text(row)).unwrap_or_default()
    }

    /// The run's outcome and particle-steps, when it is in the table under its id.
    fn outcome(&self, run: &PlannedRun, job: &Job, spec: &TuneSpec) -> Option<(Outcome, f64)> {
        let row = *self.by_index.get(&(run.index as i64))?;
        if self.text("run_id", row) != run.id {
            return None;
        }
        let status = RunStatus::parse(&self.text("status", row));
        let message = self.text("message", row);
        let mut particle_steps = self.number("particle_steps", row);
        if particle_steps.is_nan() {
            particle_steps = self.number("steps", row) * run.scene.particles.count as f64;
        }
        // A run that did not settle was cut only when it reached its cap; one that ran its whole
        // duration below the cap failed.
        let failure = match (status, job.cap) {
            (Some(RunStatus::Settled), _) => None,
            (Some(RunStatus::NotSettled), Some(cap)) if particle_steps >= CAP_REACHED * cap => {
                Some(RunFailure::Cut { cap })
            }
            (Some(RunStatus::NotSettled), _) => Some(RunFailure::NotSettled),
            (Some(RunStatus::Diverged), _) => Some(RunFailure::Diverged(message)),
            _ => Some(RunFailure::Error(message)),
        };
        let cost = match spec.search.objective {
            Objective::ParticleSteps => particle_steps,
            Objective::WallTime => self.number("wall_time", row),
        };
        let metrics = spec.keep.iter().map(|k| self.number(&k.metric, row)).collect();
        let pile = self.pile.iter().map(|m| self.number(m, row)).collect();
        let warnings = self.warnings.get(&run.index).map(Vec::as_slice).unwrap_or_default();
        let limits = &run.scene.limits;
        let measured = MEASURED.iter().map(|&(kind, column)| {
            let limit = match kind {
                WarningKind::EnergyBalance => limits.energy_balance_tolerance,
                _ => limits.overlap_warning_ratio,
            };
            Reading { kind, value: self.number(column, row), limit }
        });
        let predicted = warnings.iter().filter(|w| !w.kind.is_measured()).map(Reading::from);
        let readings = predicted.chain(measured.filter(|r| r.value.is_finite())).collect();
        Some((Outcome { failure, cost, metrics, readings, pile }, particle_steps))
    }
}
