//! The brute-force yardstick of `bench tune`: every setting a DEM engineer would try over the tune's
//! own levers, on fresh seeds no tune run used (where the reference's disks can be placed, as tune's
//! runs), judged exactly as tune judges.
//!
//! The rungs: tune's answer (so that it is judged on the same seeds as the rest), the standard
//! settings of its levers and the time-step rungs below the first ([`LADDER_FACTORS`]), and a full
//! grid over the levers (each continuous lever at evenly spaced levels, as many as keep the grid within
//! [`MAX_GRID`] points; a list lever at every value); then the half-steps around the cheapest valid,
//! equivalent grid point. A fresh reference on the same seeds (at least [`LADDER_SEEDS`]) is the
//! yardstick: every rung is judged against it (validity over the runs together, every kept metric
//! equivalent by two one-sided tests), and runs are stopped at [`DEAR`] times its mean cost, where they
//! can no longer be an answer. The rungs race: every one runs on the first seeds, and only those that
//! can still be the cheapest valid, equivalent one get the rest (see `run_settings`).
//!
//! The cheapest of some hundred judgements is partly luck (on a noisy metric, one rung among many
//! undecided ones comes out equivalent by chance), so the ladder's answer is confirmed as tune's is
//! verified: the equivalent rungs, cheapest first, run on as many further fresh seeds and are judged
//! on those alone; the first that passes is the ladder's best (`confirm`).

use super::BenchError;
use crate::tune::judge::{check_figures, predicted_breach};
use crate::tune::model::{Job, Outcome, Rejection, Role, SearchResult, State};
use crate::tune::report::settings;
use crate::tune::search::placeable_seeds;
use crate::tune::spec::{Lever, LeverRange, Objective};
use crate::tune::{Evaluator, RunEvaluator, TuneError, TuneOptions, TuneSpec};

/// The time-step rungs: fractions of the first standard setting's time step.
pub const LADDER_FACTORS: [f64; 7] = [1.0, 0.9, 0.8, 0.7, 0.6, 0.5, 0.4];

/// One rung of the ladder.
#[derive(Clone, Debug, PartialEq)]
pub struct Rung {
    /// Its setting, in words.
    pub setting: String,
    /// Its cost over the reference's (mean over its runs; NaN when not run).
    pub cost_ratio: f64,
    /// Its standing (`equivalent`, `infeasible`, `undecided`, `not_run`).
    pub state: String,
    /// Why, when it is not valid and equivalent.
    pub reason: String,
}

/// The first seed number of the ladder: far past any seed tune gives its reference, search or
/// verification runs.
pub const FRESH_SEEDS: u64 = 1_000_000;

/// The ladder runs every rung on this many fresh seeds by default (the reference's count when larger).
pub const LADDER_SEEDS: usize = 10;

/// The first seed of the confirmation runs: past the ladder's own seeds.
const CONFIRM_SEEDS: u64 = FRESH_SEEDS + 500_000;

/// Most equivalent rungs whose confirmation is tried.
const CONFIRM_TRIES: usize = 3;

/// The grid holds at most this many points.
pub const MAX_GRID: usize = 81;

/// A continuous lever takes at most this many levels.
const MAX_LEVELS: usize = 7;

/// The standing of a rung that stopped after its first seeds.
pub const RACED_OUT: &str = "raced_out";

/// Every setting runs on this many seeds first.
const FIRST_SEEDS: usize = 2;

/// Settings that get the other seeds in one round.
const ROUND: usize = 6;

/// Runs stop at this multiple of the fresh reference's mean cost: a setting that dear is no answer.
pub const DEAR: f64 = 1.5;

/// One setting to run on every fresh seed.
#[derive(Clone, Debug)]
struct Setting {
    name: String,
    /// Runs on every seed whatever its first runs show (tune's answer).
    complete: bool,
    point: Vec<f64>,
    standard: Option<usize>,
}

/// The ladder's best rung: its setting and cost ratios.
#[derive(Clone, Debug, PartialEq)]
pub struct LadderBest {
    /// Its setting.
    pub setting: String,
    /// Cost ratio over both sets of runs: the seeds that chose it and its confirmation's.
    pub cost_ratio: f64,
    /// Cost ratio on its confirmation seeds alone: runs that did not choose it, so not biased low by
    /// the choice among many rungs, as tune's verified cost is not.
    pub confirmation_cost_ratio: f64,
}

/// The ladder on one tune: every rung judged, the cheapest valid, equivalent one, and tune's answer on
/// the same seeds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GridLadder {
    /// Every rung: tune's answer (when there is one) first, then the standard settings, the grid and the
    /// half-steps.
    pub rungs: Vec<Rung>,
    /// The cheapest valid, equivalent rung other than tune's answer that its confirmation runs also
    /// show valid and equivalent.
    pub best: Option<LadderBest>,
    /// Tune's answer on the ladder's seeds: its rung.
    pub answer: Option<Rung>,
    /// Runs made, the fresh reference's included.
    pub runs: usize,
    /// Fresh seeds a rung may run on (as many again confirm the best).
    pub seeds: usize,
}

/// Runs the ladder of `spec` (after its tune: `spec.standards` holds every standard setting tune ran) on
/// `seeds` fresh seeds, or the reference's count when larger.
pub fn grid_ladder(
    spec: &TuneSpec,
    result: &SearchResult,
    options: TuneOptions,
    seeds: usize,
) -> Result<GridLadder, BenchError> {
    let mut evaluator = RunEvaluator::new(spec, &options);
    let count = result.reference.len().max(seeds);
    let seeds = placeable_seeds(&mut evaluator, FRESH_SEEDS, count);
    let reference_jobs: Vec<Job> = seeds.iter().copied().map(Job::reference).collect();
    let reference = evaluator.evaluate(&reference_jobs).map_err(BenchError::Tune)?;
    if let Some((seed, failure)) = seeds.iter().zip(&reference).find_map(|(&s, o)| Some((s, o.failure.clone()?))) {
        return Err(BenchError::Tune(TuneError::ReferenceFailed { seed, failure }));
    }
    let mut judged = result.clone();
    judged.margins = spec.keep.iter().enumerate().map(|(k, keep)| keep.margin(mean(&reference, k))).collect();
    judged.reference_checks = check_figures(&reference, &[]);
    judged.reference = reference;
    let cap = (spec.search.objective == Objective::ParticleSteps).then(|| DEAR * judged.reference_cost());
    let mut ladder = GridLadder { runs: seeds.len(), seeds: seeds.len(), ..GridLadder::default() };

    let answer = result.recommended.map(|k| &result.candidates[k]);
    let mut first = Vec::new();
    if let Some(c) = answer {
        first.push(Setting {
            name: format!("tune's answer: {}", settings(spec, c)),
            complete: true,
            point: c.point.clone(),
            standard: c.standard,
        });
    }
    first.extend(standard_rungs(spec, &mut evaluator));
    let grid = grid(&spec.levers);
    first.extend(grid.iter().map(|p| point_setting(spec, p)));
    let mut judged_rungs = run_settings(&mut evaluator, &judged, &first, &seeds, cap, &mut ladder.runs)?;
    if answer.is_some() {
        ladder.answer = Some(judged_rungs.remove(0));
        first.remove(0);
    }
    let best_point = judged_rungs
        .iter()
        .zip(&first)
        .filter(|(rung, s)| rung.state == "equivalent" && s.standard.is_none())
        .min_by(|a, b| a.0.cost_ratio.total_cmp(&b.0.cost_ratio))
        .map(|(_, s)| s.point.clone());
    if let Some(point) = best_point {
        let near: Vec<Setting> = half_steps(&spec.levers, &point).iter().map(|p| point_setting(spec, p)).collect();
        judged_rungs.extend(run_settings(&mut evaluator, &judged, &near, &seeds, cap, &mut ladder.runs)?);
        first.extend(near);
    }
    let confirm_seeds = placeable_seeds(&mut evaluator, CONFIRM_SEEDS, count);
    let mut trial =
        Trial { evaluator: &mut evaluator, judged: &judged, seeds: &confirm_seeds, cap, runs: &mut ladder.runs };
    ladder.best = confirm(&mut trial, &first, &mut judged_rungs)?;
    ladder.rungs = ladder.answer.iter().cloned().chain(judged_rungs).collect();
    Ok(ladder)
}

/// What running settings on some seeds needs: the evaluator, the yardstick, the seeds, the cost cap
/// and the run count to add to.
struct Trial<'a> {
    evaluator: &'a mut RunEvaluator<'a>,
    judged: &'a SearchResult,
    seeds: &'a [u64],
    cap: Option<f64>,
    runs: &'a mut usize,
}

/// The ladder's best: the equivalent rungs, cheapest first (at most [`CONFIRM_TRIES`]), each run on
/// the confirmation seeds and judged on those runs alone; the first that is valid and equivalent there
/// too, with its cost over both sets. Each tried rung's reason says how its confirmation went.
fn confirm(trial: &mut Trial, settings: &[Setting], rungs: &mut [Rung]) -> Result<Option<LadderBest>, BenchError> {
    let mut order: Vec<usize> = (0..rungs.len()).filter(|&k| rungs[k].state == "equivalent").collect();
    order.sort_by(|&a, &b| rungs[a].cost_ratio.total_cmp(&rungs[b].cost_ratio));
    let reference = trial.judged.reference_cost();
    for k in order.into_iter().take(CONFIRM_TRIES) {
        let mut outcomes = vec![Vec::new()];
        let setting = std::slice::from_ref(&settings[k]);
        run_round(trial.evaluator, setting, &[0], trial.seeds, trial.cap, &mut outcomes, trial.runs)?;
        let a = trial.judged.assess_runs(&outcomes[0]);
        let n = trial.seeds.len();
        if a.state == State::Feasible {
            let confirmation_cost_ratio = a.cost / reference;
            rungs[k].reason = format!("confirmed on {n} more fresh seeds (cost there {confirmation_cost_ratio:.3})");
            let cost_ratio = (rungs[k].cost_ratio + confirmation_cost_ratio) / 2.0;
            return Ok(Some(LadderBest { setting: rungs[k].setting.clone(), cost_ratio, confirmation_cost_ratio }));
        }
        let why = match &a.state {
            State::Infeasible(why) => why.to_string(),
            other => other.name().to_string(),
        };
        rungs[k].reason = format!("not confirmed on {n} more fresh seeds: {why}");
    }
    Ok(None)
}

fn mean(outcomes: &[crate::tune::model::Outcome], k: usize) -> f64 {
    outcomes.iter().map(|o| o.metrics[k]).sum::<f64>() / outcomes.len().max(1) as f64
}

fn job(candidate: usize, point: &[f64], standard: Option<usize>, role: Role, seed: u64, cap: Option<f64>) -> Job {
    Job { candidate, point: point.to_vec(), role, seed, standard, cap }
}

/// The standard settings tune ran, and the time-step rungs below the first when it sets the time step.
fn standard_rungs(spec: &TuneSpec, evaluator: &mut RunEvaluator) -> Vec<Setting> {
    let mut rungs: Vec<Setting> = (0..spec.standards.len())
        .map(|k| Setting {
            name: spec.standards[k].name.clone(),
            complete: false,
            point: Vec::new(),
            standard: Some(k),
        })
        .collect();
    if crate::tune::ladder::time_step_lever(&spec.levers).is_some() && !spec.standards.is_empty() {
        for &factor in &LADDER_FACTORS[1..] {
            if let Some(k) = evaluator.step_down(0, factor) {
                let name = evaluator.standards[k].name.clone();
                rungs.push(Setting { name, complete: false, point: Vec::new(), standard: Some(k) });
            }
        }
    }
    rungs
}

fn point_setting(spec: &TuneSpec, point: &[f64]) -> Setting {
    let values = spec.values(point);
    let name = values.iter().map(|(k, v)| format!("{k} = {v}")).collect::<Vec<_>>().join(", ");
    Setting { name, complete: false, point: point.to_vec(), standard: None }
}

/// The levels of each lever in normalized coordinates: every value of a list, evenly spaced levels of a
/// continuous range, as many as keep the grid within [`MAX_GRID`] points.
pub fn levels(levers: &[Lever]) -> Vec<Vec<f64>> {
    let lists: usize = levers
        .iter()
        .filter_map(|l| match &l.range {
            LeverRange::List(values) => Some(values.len()),
            _ => None,
        })
        .product();
    let continuous = levers.iter().filter(|l| !matches!(l.range, LeverRange::List(_))).count() as i32;
    let room = (MAX_GRID / lists.max(1)).max(2) as f64;
    let count = if continuous == 0 { 1 } else { (room.powf(1.0 / continuous as f64) + 1e-9).floor() as usize };
    let count = count.clamp(2, MAX_LEVELS);
    levers
        .iter()
        .map(|l| match &l.range {
            LeverRange::List(values) => (0..values.len()).map(|k| (k as f64 + 0.5) / values.len() as f64).collect(),
            _ => (0..count).map(|k| k as f64 / (count - 1) as f64).collect(),
        })
        .collect()
}

/// Every combination of the levers' [`levels`].
pub fn grid(levers: &[Lever]) -> Vec<Vec<f64>> {
    levels(levers).iter().fold(vec![Vec::new()], |points, axis| {
        points.iter().flat_map(|p| axis.iter().map(move |&u| [p.as_slice(), &[u]].concat())).collect()
    })
}

/// The points half a grid step from `point` along each continuous lever, inside the range.
pub fn half_steps(levers: &[Lever], point: &[f64]) -> Vec<Vec<f64>> {
    let levels = levels(levers);
    let mut near = Vec::new();
    for (d, lever) in levers.iter().enumerate() {
        if matches!(lever.range, LeverRange::List(_)) || levels[d].len() < 2 {
            continue;
        }
        let half = 0.5 / (levels[d].len() - 1) as f64;
        for u in [point[d] - half, point[d] + half] {
            if (0.0..=1.0).contains(&u) {
                let mut p = point.to_vec();
                p[d] = u;
                near.push(p);
            }
        }
    }
    near
}

/// Races the settings: every one not predicted invalid or far dearer than the reference runs on the
/// first [`FIRST_SEEDS`] seeds; those still possible (equivalent or undecided so far, cheaper than the
/// reference) get the other seeds, cheapest first, [`ROUND`] at a time, until a round holds a valid,
/// equivalent setting and no setting left looked cheaper than it. Each is judged on all the runs it
/// has; a setting left behind keeps its first runs' standing, named as such.
fn run_settings(
    evaluator: &mut RunEvaluator,
    judged: &SearchResult,
    settings: &[Setting],
    seeds: &[u64],
    cap: Option<f64>,
    runs: &mut usize,
) -> Result<Vec<Rung>, BenchError> {
    let mut rungs: Vec<Rung> = Vec::with_capacity(settings.len());
    let mut outcomes: Vec<Vec<Outcome>> = vec![Vec::new(); settings.len()];
    let (first, rest) = seeds.split_at(FIRST_SEEDS.min(seeds.len()));
    let mut racing = Vec::new();
    for (k, s) in settings.iter().enumerate() {
        let screen = evaluator.screen(&s.point, s.standard);
        let skip = match (&screen.predicted, screen.relative_cost) {
            (Err(e), _) => Some(e.to_string()),
            (Ok(w), r) => match predicted_breach(w, &judged.reference_checks) {
                Some((check, _)) => Some(Rejection::Invalid(check).to_string()),
                None => r.filter(|&r| r > DEAR).map(|r| format!("predicted {r:.2} of the reference's cost")),
            },
        };
        rungs.push(Rung {
            setting: s.name.clone(),
            cost_ratio: f64::NAN,
            state: "not_run".into(),
            reason: skip.unwrap_or_default(),
        });
        if rungs[k].reason.is_empty() {
            racing.push(k);
        }
    }
    run_round(evaluator, settings, &racing, first, cap, &mut outcomes, runs)?;
    let complete: Vec<usize> = racing.iter().copied().filter(|&k| settings[k].complete).collect();
    run_round(evaluator, settings, &complete, rest, cap, &mut outcomes, runs)?;
    let reference = judged.reference_cost();
    let mut best = f64::INFINITY;
    loop {
        let mut open: Vec<(f64, usize)> = racing
            .iter()
            .filter(|&&k| outcomes[k].len() < seeds.len())
            .map(|&k| (judged.assess_runs(&outcomes[k]), k))
            .filter(|(a, _)| matches!(a.state, State::Feasible | State::Undecided) && a.cost < reference.min(best))
            .map(|(a, k)| (a.cost, k))
            .collect();
        if open.is_empty() {
            break;
        }
        open.sort_by(|a, b| a.0.total_cmp(&b.0));
        let round: Vec<usize> = open.iter().take(ROUND).map(|&(_, k)| k).collect();
        run_round(evaluator, settings, &round, rest, cap, &mut outcomes, runs)?;
        for &k in &round {
            let a = judged.assess_runs(&outcomes[k]);
            if a.state == State::Feasible {
                best = best.min(a.cost);
            }
        }
    }
    for &k in &racing {
        let a = judged.assess_runs(&outcomes[k]);
        let reason = match &a.state {
            State::Infeasible(why) => why.to_string(),
            State::Cut => format!("stopped at {DEAR} times the reference's cost"),
            _ => String::new(),
        };
        rungs[k].cost_ratio = a.cost / reference;
        rungs[k].reason = reason;
        rungs[k].state = a.state.name().to_string();
        if outcomes[k].len() < seeds.len() && matches!(a.state, State::Feasible | State::Undecided) {
            rungs[k].reason =
                format!("{} on its first {} seeds: it could not be the cheapest", rungs[k].state, outcomes[k].len());
            rungs[k].state = RACED_OUT.into();
        }
    }
    Ok(rungs)
}

/// Runs `which` settings on `seeds`, in one batch, appending to their outcomes.
fn run_round(
    evaluator: &mut RunEvaluator,
    settings: &[Setting],
    which: &[usize],
    seeds: &[u64],
    cap: Option<f64>,
    outcomes: &mut [Vec<Outcome>],
    runs: &mut usize,
) -> Result<(), BenchError> {
    let jobs: Vec<Job> = which
        .iter()
        .flat_map(|&k| seeds.iter().map(move |&seed| (k, seed)))
        .map(|(k, seed)| job(k + 1, &settings[k].point, settings[k].standard, Role::Search, seed, cap))
        .collect();
    if jobs.is_empty() {
        return Ok(());
    }
    let done = evaluator.evaluate(&jobs).map_err(BenchError::Tune)?;
    *runs += jobs.len();
    for (job, outcome) in jobs.iter().zip(done) {
        outcomes[job.candidate - 1].push(outcome);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::ParamValue;

    #[test]
    fn the_grid_spans_every_lever_within_its_size() {
        let linear = |k: &str| Lever::new(k, LeverRange::Linear { low: 0.1, high: 0.9, integer: false });
        let list = Lever::new(
            "integrator.scheme",
            LeverRange::List(vec![ParamValue::Text("a".into()), ParamValue::Text("b".into())]),
        );
        for levers in [vec![linear("a")], vec![linear("a"), linear("b")], vec![linear("a"), linear("b"), list.clone()]]
        {
            let grid = grid(&levers);
            assert!(grid.len() <= MAX_GRID && grid.len() >= 4, "{}", grid.len());
            for d in 0..levers.len() {
                let (lo, hi) = grid.iter().fold((1.0f64, 0.0f64), |(lo, hi), p| (lo.min(p[d]), hi.max(p[d])));
                match levers[d].range {
                    LeverRange::List(_) => assert_eq!((lo, hi), (0.25, 0.75)),
                    _ => assert_eq!((lo, hi), (0.0, 1.0)),
                }
            }
        }
        assert_eq!(grid(&[linear("a"), linear("b"), linear("c"), linear("d")]).len(), 81);
    }

    #[test]
    fn half_steps_stay_inside_the_range_and_leave_lists_alone() {
        let levers = [
            Lever::new("a", LeverRange::Linear { low: 0.0, high: 1.0, integer: false }),
            Lever::new("b", LeverRange::List(vec![ParamValue::Int(1), ParamValue::Int(2)])),
        ];
        let step = 1.0 / (levels(&levers)[0].len() - 1) as f64;
        assert_eq!(half_steps(&levers, &[0.0, 0.25]), vec![vec![step / 2.0, 0.25]]);
        assert_eq!(half_steps(&levers, &[1.0, 0.75]).len(), 1);
        assert_eq!(half_steps(&levers, &[0.5, 0.75]).len(), 2);
    }
}
