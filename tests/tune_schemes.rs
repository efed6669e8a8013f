//! The search over an integrator lever on a stand-in: where the user's scheme only rattles (its
//! time-step rungs never settle), the time-step path ends at its first unsettled rung and the cheap
//! corner takes the other scheme, whose stable step is larger, and wins.

mod tune_common;

use demsweep::physics::warning::{ValidityWarning, WarningKind};
use demsweep::tune::model::{
    Evaluator, Job, Outcome, PathEnd, Role, RunFailure, Screen, SearchConfig, State, TuneError,
};
use demsweep::tune::search::search;
use tune_common::normal;

/// Levers (a, s): a plays the time step (a run costs 10 − 8a), s the scheme (s < 0.5: the user's,
/// stable only up to a = 0.4 and predicted past its stable step above; s ≥ 0.5: one stable up to
/// a = 1). The reference runs at a = 0.2 with the user's scheme; every other run of the user's scheme
/// never settles (a limit cycle: it costs 50 unless cut). One metric, 1 plus noise of sd 0.005.
/// Standard setting k (the time-step path's rungs) is `rungs[k]`, always the user's scheme.
struct Schemes {
    rungs: Vec<f64>,
    jobs: Vec<Job>,
}

impl Schemes {
    fn setting(&self, point: &[f64], standard: Option<usize>) -> (f64, bool) {
        match standard {
            Some(k) => (self.rungs[k], false),
            None => (point[0], point[1] >= 0.5),
        }
    }
}

fn cost(a: f64) -> f64 {
    10.0 - 8.0 * a
}

impl Evaluator for Schemes {
    fn screen(&mut self, point: &[f64], standard: Option<usize>) -> Screen {
        let (a, other) = self.setting(point, standard);
        let predicted = match (other, a > 0.4) {
            (false, true) => vec![ValidityWarning::new(WarningKind::IntegratorStability, a, 0.4)],
            _ => Vec::new(),
        };
        Screen {
            identity: format!("{a} {other}"),
            predicted: Ok(predicted),
            resolved: Vec::new(),
            relative_cost: Some(cost(a) / cost(0.2)),
        }
    }

    fn reference_identity(&mut self) -> String {
        "0.2 false".to_string()
    }

    fn step_down(&mut self, standard: usize, factor: f64) -> Option<usize> {
        self.rungs.push(self.rungs[standard] * factor);
        Some(self.rungs.len() - 1)
    }

    fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, TuneError> {
        self.jobs.extend(jobs.iter().cloned());
        Ok(jobs
            .iter()
            .map(|job| {
                let (a, other) =
                    if job.role == Role::Reference { (0.2, false) } else { self.setting(&job.point, job.standard) };
                let rattles = job.role != Role::Reference && !other;
                let metric = 1.0 + 0.005 * normal(a.to_bits() ^ job.seed.wrapping_mul(0x9e37_79b9) ^ other as u64);
                let mut outcome = Outcome::settled(if rattles { 50.0 } else { cost(a) }, vec![metric]);
                if rattles {
                    outcome.failure = Some(RunFailure::NotSettled);
                }
                if let Some(cap) = job.cap.filter(|&cap| outcome.cost > cap) {
                    (outcome.cost, outcome.failure) = (cap, Some(RunFailure::Cut { cap }));
                }
                outcome
            })
            .collect())
    }
}

#[test]
fn the_other_schemes_corner_wins_where_the_users_scheme_never_settles() {
    let config = SearchConfig {
        dims: 2,
        levels: vec![None, Some(2)],
        tolerances: vec![(0.02, true)],
        metrics: vec!["pile_height".to_string()],
        seeds: 3,
        max_seeds: 6,
        reference_seeds: 6,
        verify_seeds: 6,
        budget: 120,
        seed: 5,
        initial: None,
        dissipation: vec![0.0; 2],
        home: vec![None, Some(0.25)],
        standards: 1,
        path: true,
        max_spend: 14.0,
        cut_runs: true,
    };
    let mut stand_in = Schemes { rungs: vec![0.4], jobs: Vec::new() };
    let result = search(&config, &mut stand_in).expect("the search runs");
    assert_eq!(result.path.0.len(), 1, "an unsettled rung ends the path: {:?}", result.path);
    assert_eq!(result.path.1, PathEnd::NothingCheaper);
    let best = &result.candidates[result.recommended.expect("an answer")];
    assert_eq!(best.point, vec![1.0, 0.75], "the other scheme at its largest step");
    assert_eq!(result.assess_verification(best).unwrap().state, State::Feasible);
    let users_scheme_runs = stand_in.jobs.iter().filter(|j| j.standard.is_some()).count();
    assert_eq!(users_scheme_runs, config.seeds, "the rattling rung ran its first seeds only");
}
