//! The time-step path's further seeds of a rung are cut only where another candidate would win: on a
//! stand-in whose top rung is valid and equivalent but needs more than its first seeds to be decided,
//! and whose runs' costs spread around their mean, none of its further runs is cut (they were cut at
//! the rung's own mean, so its slower seeds failed and the path lost its answer), and the rung is
//! verified.

mod tune_common;

use demsweep::tune::model::{Evaluator, Job, Outcome, Role, RunFailure, Screen, SearchConfig, State, TuneError};
use demsweep::tune::search::search;
use tune_common::{dump, hash, normal, stand_in_config};

/// The reference's time step as a fraction of the contact time.
const REFERENCE_FRACTION: f64 = 0.02;

/// One lever, the time step's fraction (log range 0.01 to 0.2); a run costs 100 times the
/// reference's fraction over its own, spread by 25 % from seed to seed, and keeps the pile (metric
/// 1, sd 0.04 against a margin of 0.05: three seeds leave a setting undecided). The one standard
/// setting is the top of the time-step path, at the range's end (a fraction of 0.2), so that the cheap
/// corner is the rung itself and the rung is the answer.
struct StandIn {
    standards: Vec<f64>,
    jobs: Vec<Job>,
}

impl StandIn {
    fn fraction(&self, job: &Job) -> f64 {
        match (job.role, job.standard) {
            (Role::Reference, _) => REFERENCE_FRACTION,
            (_, Some(k)) => self.standards[k],
            (_, None) => 0.01 * 20f64.powf(job.point[0]),
        }
    }
}

impl Evaluator for StandIn {
    fn screen(&mut self, point: &[f64], standard: Option<usize>) -> Screen {
        let f = match standard {
            Some(k) => self.standards[k],
            None => 0.01 * 20f64.powf(point[0]),
        };
        Screen {
            identity: format!("{f}"),
            predicted: Ok(Vec::new()),
            resolved: Vec::new(),
            relative_cost: Some(REFERENCE_FRACTION / f),
        }
    }

    fn reference_identity(&mut self) -> String {
        format!("{REFERENCE_FRACTION}")
    }

    fn step_down(&mut self, standard: usize, factor: f64) -> Option<usize> {
        self.standards.push(self.standards[standard] * factor);
        Some(self.standards.len() - 1)
    }

    fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, TuneError> {
        self.jobs.extend(jobs.iter().cloned());
        let outcome = |job: &Job| {
            let f = self.fraction(job);
            let key = hash(f.to_bits()) ^ job.seed.wrapping_mul(0x9e37_79b9) ^ u64::from(job.role == Role::Verify);
            let cost = 100.0 * REFERENCE_FRACTION / f * (1.0 + 0.25 * normal(key ^ 0x5eed)).max(0.3);
            let mut outcome = Outcome::settled(cost, vec![1.0 + 0.04 * normal(key)]);
            if let Some(cap) = job.cap.filter(|&cap| cost > cap) {
                (outcome.cost, outcome.failure) = (cap, Some(RunFailure::Cut { cap }));
            }
            outcome
        };
        Ok(jobs.iter().map(outcome).collect())
    }
}

fn config() -> SearchConfig {
    SearchConfig {
        dims: 1,
        levels: vec![None],
        home: vec![Some((REFERENCE_FRACTION / 0.01).ln() / 20f64.ln())],
        dissipation: vec![0.0],
        standards: 1,
        path: true,
        time_step: Some(0),
        ..stand_in_config()
    }
}

#[test]
fn a_rungs_further_seeds_are_not_cut_at_its_own_mean_and_it_is_verified() {
    let mut stand_in = StandIn { standards: vec![0.2], jobs: Vec::new() };
    let result = search(&config(), &mut stand_in).unwrap();
    let top = result.candidates.iter().find(|c| c.standard == Some(0)).expect("the top rung ran");
    assert!(top.runs.len() > 3, "the top rung needs more than its first seeds here:\n{}", dump(&result));
    assert!(top.runs.iter().all(|o| !o.is_cut()), "a run of the top rung was cut:\n{}", dump(&result));
    let verified = result.assess_verification(top).map(|v| v.state);
    assert_eq!(verified, Some(State::Feasible), "the path's answer is verified:\n{}", dump(&result));
}
