//! The tune search on a cheap analytic stand-in with noise: the known optimum is found, the budget is
//! kept, the same configuration gives the same answer, the infeasible and predicted-invalid regions
//! are never the answer (and the predicted-invalid one is never run); runs that break a validity
//! check together make a candidate infeasible; settings that resolve to the same runs are one
//! candidate; a reference too noisy for its tolerance stops the search before it proposes anything;
//! the time-step path runs first and is the answer when nothing beats it; a rung whose runs break the
//! energy balance is stepped down by the fitted error model; one outlier seed does not veto a rung; a
//! reference that breaks a rule of thumb holds candidates to it instead of stopping the tune; a failed
//! verification is cured by a step-down even under a tight spend limit; runs that can no longer win
//! are cut.

mod tune_common;

use demsweep::physics::warning::{ValidityWarning, WarningKind};
use demsweep::tune::model::{
    Candidate, Evaluator, Job, Outcome, PathEnd, Reading, Rejection, Role, RunFailure, Screen, SearchConfig,
    SearchResult, State, TuneError,
};
use demsweep::tune::search::search;
use tune_common::normal;

/// cost = 10 − 4a − 3b (cheaper to the upper right); one metric, 1 + 0.1·max(0, a + b − 1.2) plus
/// Gaussian noise (`noise`, sd 0.005 by default) that depends only on the point and the seed; runs with
/// a > 0.95 diverge; a < 0.25 is predicted to overlap past its limit; runs with b > 0.9 measure an
/// overlap 7 times their limit; a above 0.97 resolves to 0.97 (like a capped time step), so those
/// points make the same runs. Standard setting k sits at `standards[k]`. Runs at b < 0.1 never settle
/// and cost 50 unless cut; the metric of runs at points of the lever space (not the reference's, not a
/// standard setting's) is shifted by `offset`. Every run of the reference (a = 0.3) and of a standard
/// setting measures an energy-balance error of `energy · a` times its 1 % tolerance (a plays the time
/// step; 2 % noise per seed; the seed `outlier` errs `outlier_factor` times more); `step_down` adds the
/// setting with `a` scaled. With `reference_overlap`, every setting but those at a < 0.25 is predicted
/// to overlap that much (past the 0.1 limit), as the reference does. Screens predict a setting's cost
/// over the reference's.
struct StandIn {
    runs: usize,
    jobs: Vec<Job>,
    batches: usize,
    screened: Vec<String>,
    noise: f64,
    offset: f64,
    standards: Vec<(f64, f64)>,
    energy: f64,
    /// The energy coefficient of verification runs, when it differs (fresh seeds that err more).
    verify_energy: Option<f64>,
    /// A seed whose runs err `outlier_factor` times more.
    outlier: Option<(u64, f64)>,
    reference_overlap: Option<f64>,
}

impl StandIn {
    fn new() -> Self {
        Self {
            runs: 0,
            jobs: Vec::new(),
            batches: 0,
            screened: Vec::new(),
            noise: 0.005,
            offset: 0.0,
            standards: Vec::new(),
            energy: 0.0,
            verify_energy: None,
            outlier: None,
            reference_overlap: None,
        }
    }

    /// The point a setting resolves to.
    fn resolved(&self, point: &[f64], standard: Option<usize>) -> (f64, f64) {
        let (a, b) = match standard {
            Some(k) => self.standards[k],
            None => (point[0], point[1]),
        };
        (a.min(0.97), b)
    }

    /// The predicted warnings of a setting at `a`.
    fn predicted(&self, a: f64) -> Vec<ValidityWarning> {
        match (a < 0.25, self.reference_overlap) {
            (true, _) => vec![ValidityWarning::new(WarningKind::ImpactOverlap, 0.2, 0.1)],
            (false, Some(overlap)) => vec![ValidityWarning::new(WarningKind::ImpactOverlap, overlap, 0.1)],
            (false, None) => Vec::new(),
        }
    }
}

/// The cost of a run at (a, b) that settles.
fn cost(a: f64, b: f64) -> f64 {
    10.0 - 4.0 * a - 3.0 * b
}

impl Evaluator for StandIn {
    fn screen(&mut self, point: &[f64], standard: Option<usize>) -> Screen {
        let (a, b) = self.resolved(point, standard);
        self.screened.push(format!("{a} {b}"));
        let resolved = if standard.is_some() { Vec::new() } else { vec![a, b] };
        let relative_cost = Some(cost(a, b) / cost(0.3, 0.2));
        Screen { identity: format!("{a} {b}"), predicted: Ok(self.predicted(a)), resolved, relative_cost }
    }

    fn reference_identity(&mut self) -> String {
        "0.3 0.2".to_string()
    }

    fn step_down(&mut self, standard: usize, factor: f64) -> Option<usize> {
        let (a, b) = self.standards[standard];
        self.standards.push((a * factor, b));
        Some(self.standards.len() - 1)
    }

    fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, TuneError> {
        self.runs += jobs.len();
        self.batches += 1;
        self.jobs.extend(jobs.iter().cloned());
        Ok(jobs
            .iter()
            .map(|job| {
                let (a, b) =
                    if job.role == Role::Reference { (0.3, 0.2) } else { self.resolved(&job.point, job.standard) };
                let key = a.to_bits() ^ b.to_bits().rotate_left(17) ^ job.seed.wrapping_mul(0x9e37_79b9);
                let shift = if job.role == Role::Reference || job.standard.is_some() { 0.0 } else { self.offset };
                let metric = 1.0 + 0.1 * (a + b - 1.2).max(0.0) + self.noise * normal(key) + shift;
                let stuck = job.role != Role::Reference && b < 0.1;
                let cost = if stuck { 50.0 } else { cost(a, b) };
                let mut outcome = Outcome::settled(cost, vec![metric]);
                outcome.failure = (a > 0.95).then(|| RunFailure::Diverged("blew up".into()));
                if stuck {
                    outcome.failure = Some(RunFailure::NotSettled);
                }
                if let Some(cap) = job.cap.filter(|&cap| cost > cap) {
                    (outcome.cost, outcome.failure) = (cap, Some(RunFailure::Cut { cap }));
                }
                outcome.readings = self.predicted(a).iter().map(Reading::from).collect();
                if b > 0.9 {
                    outcome.readings.push(Reading { kind: WarningKind::Overlap, value: 0.7, limit: 0.1 });
                }
                let energy =
                    if job.role == Role::Verify { self.verify_energy.unwrap_or(self.energy) } else { self.energy };
                let outlier = match self.outlier {
                    Some((seed, factor)) if seed == job.seed => factor,
                    _ => 1.0,
                };
                let error = 0.01 * energy * a * outlier * (1.0 + 0.02 * normal(key ^ 0xe4e7));
                if job.standard.is_some() || job.role == Role::Reference {
                    outcome.readings.push(Reading { kind: WarningKind::EnergyBalance, value: error, limit: 0.01 });
                }
                outcome
            })
            .collect())
    }
}

fn config() -> SearchConfig {
    SearchConfig {
        dims: 2,
        levels: vec![None, None],
        tolerances: vec![(0.02, true)],
        metrics: vec!["pile_height".to_string()],
        seeds: 3,
        max_seeds: 8,
        reference_seeds: 8,
        verify_seeds: 6,
        budget: 200,
        seed: 11,
        initial: None,
        dissipation: vec![0.0; 2],
        home: vec![None; 2],
        standards: 0,
        path: true,
        time_step: None,
        max_spend: 1e9,
        cut_runs: false,
    }
}

fn run(config: &SearchConfig) -> (SearchResult, StandIn) {
    run_on(config, StandIn::new())
}

fn run_on(config: &SearchConfig, mut stand_in: StandIn) -> (SearchResult, StandIn) {
    let result = search(config, &mut stand_in).expect("the search runs");
    (result, stand_in)
}

#[test]
fn finds_the_known_optimum_within_the_budget() {
    let config = config();
    let (result, stand_in) = run(&config);
    assert!(result.runs <= config.budget, "{} runs of a budget of {}", result.runs, config.budget);
    assert_eq!(result.runs, stand_in.runs, "every run the search counts was made, and no more");
    assert!(stand_in.batches > 3, "runs go in batches");
    let best = &result.candidates[result.recommended.expect("a recommendation")];
    let (a, b) = (best.point[0], best.point[1]);
    let cost = 10.0 - 4.0 * a - 3.0 * b;
    assert!(cost < 5.4, "recommended a = {a}, b = {b}, cost {cost}; the optimum costs about 5");
    assert!(a <= 0.95, "the diverging region is never the answer");
    let verified = result.assess_verification(best).unwrap();
    assert_eq!(verified.state, State::Feasible);
    // Verification seeds were never used during the search.
    let search_seeds: Vec<u64> = stand_in.jobs.iter().filter(|j| j.role != Role::Verify).map(|j| j.seed).collect();
    assert!(best.verify_seeds.iter().all(|s| !search_seeds.contains(s)));
    // Undecided candidates got more seeds than they started with.
    assert!(result.candidates.iter().any(|c| c.runs.len() > config.seeds));
    assert!(result.candidates.iter().all(|c| c.runs.len() <= config.max_seeds));
}

#[test]
fn the_same_configuration_gives_the_same_answer() {
    let (first, _) = run(&config());
    let (second, _) = run(&config());
    assert_eq!(first, second);
    let (other, _) = run(&SearchConfig { seed: 12, ..config() });
    assert_ne!(first.candidates, other.candidates, "the search seed moves the design");
}

#[test]
fn predicted_invalid_points_are_never_run_and_failures_never_recommended() {
    let (result, stand_in) = run(&SearchConfig { initial: Some(12), ..config() });
    assert!(stand_in.jobs.iter().filter(|j| j.role != Role::Reference).all(|j| j.point[0] >= 0.25));
    assert!(result.candidates.iter().any(|c| c.predicted_invalid.is_some()), "the design touched the region");
    for c in result.candidates.iter().filter(|c| c.runs.iter().any(|o| o.failure.is_some())) {
        assert!(matches!(result.assess(c).state, State::Infeasible(_)));
    }
}

#[test]
fn nothing_acceptable_names_the_closest_candidate() {
    // Every candidate's metric sits 0.05 off the reference's, past the tolerance of 0.02.
    let config = SearchConfig { budget: 80, ..config() };
    let (result, stand_in) = run_on(&config, StandIn { offset: 0.05, ..StandIn::new() });
    assert_eq!(result.recommended, None);
    assert!(result.closest().is_some());
    assert!(result.runs <= config.budget && stand_in.runs == result.runs);
}

#[test]
fn runs_that_break_a_validity_check_make_a_candidate_infeasible() {
    let (result, _) = run(&config());
    let warned: Vec<_> = result.candidates.iter().filter(|c| c.runs.iter().any(Outcome::has_warning)).collect();
    assert!(!warned.is_empty(), "the search ran into the warning region");
    for c in warned {
        assert!(matches!(result.assess(c).state, State::Infeasible(_)), "{:?}", result.assess(c).state);
    }
    let best = &result.candidates[result.recommended.expect("a recommendation")];
    assert!(best.runs.iter().chain(&best.verification).all(|o| !o.has_warning()));
    let warned_only =
        |c: &&Candidate| c.runs.iter().all(|o| o.failure.is_none()) && c.runs.iter().any(Outcome::has_warning);
    let c = result.candidates.iter().find(warned_only).expect("a candidate whose runs settled with warnings");
    let State::Infeasible(Rejection::Invalid(check)) = result.assess(c).state else { panic!("{:?}", result.assess(c)) };
    assert_eq!((check.kind, check.worst, check.limit), (WarningKind::Overlap, 0.7, 0.1), "{check:?}");
}

#[test]
fn settings_that_resolve_to_the_same_runs_are_one_candidate() {
    let (result, stand_in) = run(&config());
    let mut identities: Vec<&str> = result.candidates.iter().map(|c| c.identity.as_str()).collect();
    let count = identities.len();
    identities.sort_unstable();
    identities.dedup();
    assert_eq!(identities.len(), count, "no two candidates resolve to the same runs");
    let mut screened = stand_in.screened.clone();
    screened.sort_unstable();
    screened.dedup();
    assert!(screened.len() < stand_in.screened.len(), "some proposals resolved to an existing candidate");
    // Besides the candidates, only the cheap corner's predictions at each lever's two ends are screened.
    let dims = config().dims;
    assert!((count..=count + 2 * dims).contains(&screened.len()), "and were dropped, not run again");
    assert!(result.candidates.iter().all(|c| c.point[0] <= 0.97), "candidates record the resolved values");
    assert!(result.candidates.iter().any(|c| c.point[0] == 0.97), "the search reached past the cap");
}

#[test]
fn a_reference_too_noisy_for_its_tolerance_stops_before_the_search() {
    let stand_in = StandIn { noise: 0.05, ..StandIn::new() };
    let asked = config();
    let (result, stand_in) = run_on(&asked, stand_in);
    assert_eq!(result.undecidable.len(), 1, "{:?}", result.undecidable);
    let u = &result.undecidable[0];
    assert!(u.decidable_margin > 0.02 && u.spread > 0.02, "{u:?}");
    assert!(u.seeds_needed.is_none_or(|n| n > asked.max_seeds), "{u:?}");
    assert_eq!(stand_in.runs, asked.reference_seeds, "only the reference ran");
    assert!(result.candidates.is_empty() && result.recommended.is_none());
    // The same spread with a decidable tolerance searches.
    let (result, _) =
        run_on(&SearchConfig { tolerances: vec![(0.2, true)], ..asked }, StandIn { noise: 0.05, ..StandIn::new() });
    assert!(result.undecidable.is_empty() && !result.candidates.is_empty());
}

#[test]
fn the_standard_ladder_runs_first_and_is_the_answer_when_nothing_beats_it() {
    // Standard 0 is equivalent (a = 0.9, b = 0.3, cost 5.5); standard 1 is predicted invalid.
    let stand_in = StandIn { standards: vec![(0.9, 0.3), (0.1, 0.1)], ..StandIn::new() };
    let (result, stand_in) = run_on(&SearchConfig { standards: 2, ..config() }, stand_in);
    let first_batch: Vec<&Job> = stand_in.jobs.iter().filter(|j| j.role != Role::Reference).take(3).collect();
    assert!(first_batch.iter().all(|j| j.standard == Some(0)), "the ladder runs before the design");
    assert!(result.candidates[1].predicted_invalid.is_some(), "an invalid standard is recorded, not run");
    assert_eq!(result.best_standard(), Some(0));
    let best = &result.candidates[result.recommended.expect("a recommendation")];
    let cost = |c: &Candidate| result.assess(c).cost;
    assert!(cost(best) <= cost(&result.candidates[0]), "the answer never costs more than the best standard");
    // With every point of the lever space off the reference, nothing beats the standard: it is the answer.
    let stand_in = StandIn { standards: vec![(0.9, 0.3)], offset: 0.05, ..StandIn::new() };
    let (result, _) = run_on(&SearchConfig { standards: 1, ..config() }, stand_in);
    assert_eq!(result.recommended, Some(0), "the standard setting is the answer");
}

#[test]
fn runs_that_can_no_longer_win_are_cut() {
    let stand_in = || StandIn { standards: vec![(0.9, 0.3)], ..StandIn::new() };
    let uncut = SearchConfig { standards: 1, initial: Some(12), ..config() };
    let (whole, whole_stand_in) = run_on(&uncut, stand_in());
    let (cut, cut_stand_in) = run_on(&SearchConfig { cut_runs: true, ..uncut }, stand_in());
    let cut_runs: Vec<&Outcome> = cut.candidates.iter().flat_map(|c| &c.runs).filter(|o| o.is_cut()).collect();
    assert!(!cut_runs.is_empty(), "the never-settling region was entered and cut");
    let incumbent_bound = 3.0 * 5.5 * 1.01;
    assert!(cut_runs.iter().all(|o| o.cost < incumbent_bound && o.failure.is_some()));
    assert!(whole.candidates.iter().flat_map(|c| &c.runs).all(|o| !o.is_cut()), "no cap, no cut");
    assert!(cut_stand_in.jobs.iter().all(|j| j.role != Role::Verify || j.cap.is_none()), "verification is whole");
    let spent = |r: &SearchResult| {
        r.candidates.iter().flat_map(|c| c.runs.iter().chain(&c.verification)).map(|o| o.cost).sum::<f64>()
    };
    assert!(spent(&cut) < spent(&whole), "cutting saves: {} vs {}", spent(&cut), spent(&whole));
    assert_eq!(whole_stand_in.runs, whole.runs);
}

#[test]
fn the_spend_limit_bounds_the_whole_tune() {
    let (result, _) = run(&SearchConfig { max_spend: 30.0, cut_runs: true, ..config() });
    let reference_cost = 10.0 - 4.0 * 0.3 - 3.0 * 0.2;
    assert!(result.recommended.is_some(), "the limit leaves room for an answer");
    let total = result
        .reference
        .iter()
        .chain(result.candidates.iter().flat_map(|c| c.runs.iter().chain(&c.verification)))
        .map(|o| o.cost)
        .sum::<f64>();
    assert!(total <= 30.0 * reference_cost, "{total} > 30 reference runs of {reference_cost}");
    let (unlimited, _) = run(&config());
    assert!(unlimited.runs > result.runs, "the limit stopped the search early");
}

/// The energy-balance check of a set of runs.
fn energy_check(result: &SearchResult, runs: &[Outcome]) -> demsweep::tune::model::CheckFigure {
    *result.assess_runs(runs).checks.iter().find(|c| c.kind == WarningKind::EnergyBalance).expect("an energy check")
}

#[test]
fn a_rung_past_the_energy_limit_steps_down_by_the_fitted_error_order_and_is_the_answer() {
    // Standard 0 (a = 0.9) breaks the energy balance by about 1.08x its tolerance on every run, the
    // reference (a = 0.3) errs 0.36 % at a step 5.5 / 8.2 of the rung's cost: the fitted order is
    // above 2, so the step follows order 2. Nothing in the lever space is equivalent, so the answer can
    // only be the ladder's.
    let stand_in = StandIn { standards: vec![(0.9, 0.3)], energy: 1.2, offset: 0.05, ..StandIn::new() };
    let (result, stand_in) = run_on(&SearchConfig { standards: 1, ..config() }, stand_in);
    let warned = &result.candidates[0];
    assert!(matches!(result.assess(warned).state, State::Infeasible(Rejection::Invalid(_))));
    let check = energy_check(&result, &warned.runs);
    assert!(check.figure > 0.01 && check.excess() > 1.0, "the rung broke the limit: {check:?}");
    let stepped = &result.candidates[1];
    assert_eq!((stepped.stepped_from, stepped.standard), (Some(0), Some(1)), "the rung was stepped down once");
    let (a, _) = stand_in.standards[1];
    let expected = 0.9 * (0.8 / check.excess()).sqrt();
    assert!((a - expected).abs() < 1e-12, "a = {a}, expected {expected}: the step follows the fitted order");
    let ladder_jobs: Vec<Option<usize>> =
        stand_in.jobs.iter().filter(|j| j.role != Role::Reference).take(6).map(|j| j.standard).collect();
    assert_eq!(ladder_jobs, [Some(0), Some(0), Some(0), Some(1), Some(1), Some(1)], "stepped before the design");
    assert_eq!(result.candidates.iter().filter(|c| c.stepped_from.is_some()).count(), 1, "once");
    assert_eq!(result.recommended, Some(1), "the stepped rung is the answer");
    assert_eq!(result.path.1, PathEnd::Verified(1));
    assert!(stepped.runs.iter().chain(&stepped.verification).all(|o| !o.has_warning()));
    assert_eq!(result.assess_verification(stepped).unwrap().state, State::Feasible);
}

#[test]
fn one_outlier_seed_does_not_veto_a_rung_and_many_marginal_runs_do() {
    // Standard 0's runs err 0.41 % of the energy against a 1 % tolerance; seed 1 errs 2.7 times more
    // (1.1 %). Judged together (75th percentile within the limit, none beyond twice it) the rung is
    // valid: it is the answer, with no step down.
    let outlier = || StandIn {
        standards: vec![(0.9, 0.3)],
        energy: 0.45,
        outlier: Some((1, 2.7)),
        offset: 0.05,
        ..StandIn::new()
    };
    let (result, _) = run_on(&SearchConfig { standards: 1, ..config() }, outlier());
    let rung = &result.candidates[0];
    assert!(rung.runs[1].reading(WarningKind::EnergyBalance).unwrap().value > 0.01, "seed 1 is past the limit");
    let check = energy_check(&result, &rung.runs);
    assert!(check.passes && check.worst > 0.01 && check.figure < 0.01, "{check:?}");
    assert_eq!(check.worst_run, 1, "the answer sheet names the worst run");
    assert_eq!(result.assess(rung).state, State::Feasible);
    assert_eq!(result.recommended, Some(0), "the rung is the answer");
    assert!(result.candidates.iter().all(|c| c.stepped_from.is_none()), "and was not stepped down");
    // Every run just past the limit (1.05 %): the rung is invalid and stepped down.
    let marginal = StandIn { standards: vec![(0.9, 0.3)], energy: 1.17, offset: 0.05, ..StandIn::new() };
    let (result, _) = run_on(&SearchConfig { standards: 1, ..config() }, marginal);
    let check = energy_check(&result, &result.candidates[0].runs);
    assert!(!check.passes && check.worst < 0.011, "{check:?}");
    assert!(result.candidates.iter().any(|c| c.stepped_from == Some(0)));
}

#[test]
fn a_reference_that_breaks_a_limit_holds_candidates_to_it_instead_of_stopping() {
    // Every setting is predicted to overlap 0.12 radii against the 0.1 limit, the reference too; the
    // points at a < 0.25 would overlap 0.2 radii: worse than the reference, so never run.
    let stand_in = StandIn { standards: vec![(0.9, 0.3)], reference_overlap: Some(0.12), ..StandIn::new() };
    let (result, stand_in) = run_on(&SearchConfig { standards: 1, initial: Some(12), ..config() }, stand_in);
    let broken = demsweep::tune::judge::broken_by_reference(&result.reference_checks);
    assert_eq!(broken.len(), 1, "{:?}", result.reference_checks);
    assert_eq!((broken[0].kind, broken[0].figure, broken[0].limit), (WarningKind::ImpactOverlap, 0.12, 0.1));
    let best = &result.candidates[result.recommended.expect("an answer despite the reference's overlap")];
    let verified = result.assess_verification(best).unwrap();
    let overlap = verified.checks.iter().find(|c| c.kind == WarningKind::ImpactOverlap).unwrap();
    assert!(overlap.passes && overlap.figure > overlap.limit && overlap.held_to >= 0.12, "{overlap:?}");
    assert!(result.candidates.iter().any(|c| c.predicted_invalid.is_some()), "worse points were recorded");
    assert!(
        stand_in.jobs.iter().filter(|j| j.standard.is_none() && j.role != Role::Reference).all(|j| j.point[0] >= 0.25)
    );
    let text = demsweep::tune::report::reference_breaks(&result);
    assert!(
        text.starts_with("WARNING: the reference itself breaks 1 rule")
            && text.contains(" 0.12 against 0.1 (limits.overlap_warning_ratio)"),
        "{text}"
    );
}

#[test]
fn a_failed_verification_is_cured_by_a_step_down_under_a_tight_spend_limit() {
    // Standard 0 (cost 5.5) passes its search seeds, but its fresh verification seeds err about 1.04x
    // the energy tolerance. A second rung (a = 0.8, cost 5.9) exists; 23 reference runs of spend leave
    // room for the path's cure and its verification only if nothing else runs first.
    let stand_in =
        StandIn { standards: vec![(0.9, 0.3), (0.8, 0.3)], verify_energy: Some(1.15), offset: 0.05, ..StandIn::new() };
    let limit = 23.0;
    let (result, stand_in) = run_on(&SearchConfig { standards: 2, max_spend: limit, ..config() }, stand_in);
    let failed = &result.candidates[0];
    assert_eq!(result.assess(failed).state, State::Feasible, "valid during the search");
    assert!(matches!(result.assess_verification(failed).unwrap().state, State::Infeasible(Rejection::Invalid(_))));
    let stepped = result.candidates.iter().position(|c| c.stepped_from == Some(0)).expect("a stepped rung");
    assert_eq!(result.recommended, Some(stepped), "the cured rung is the verified answer");
    assert_eq!(result.assess_verification(&result.candidates[stepped]).unwrap().state, State::Feasible);
    let check = energy_check(&result, &failed.verification);
    let a = stand_in.standards[result.candidates[stepped].standard.unwrap()].0;
    assert!((a - 0.9 * 0.8 / check.excess()).abs() < 1e-12, "first order without a reference error: {a}");
    let total: f64 = result
        .reference
        .iter()
        .chain(result.candidates.iter().flat_map(|c| c.runs.iter().chain(&c.verification)))
        .map(|o| o.cost)
        .sum();
    assert!(total <= limit * cost(0.3, 0.2), "{total} within the spend limit");
}

#[test]
fn a_rung_predicted_dearer_than_the_incumbent_is_cut_at_the_incumbents_cost() {
    // Standard 0 costs 5.5 and is equivalent; standard 1 (a = 0.26, b = 0.12) is predicted at 8.6 / 8.2
    // of the reference, dearer than the incumbent: its first run goes alone and stops as soon as it
    // costs an incumbent run, and no other runs follow.
    let stand_in = StandIn { standards: vec![(0.9, 0.3), (0.26, 0.12)], ..StandIn::new() };
    let (result, stand_in) = run_on(&SearchConfig { standards: 2, cut_runs: true, ..config() }, stand_in);
    let incumbent = result.assess(&result.candidates[0]).cost;
    assert_eq!(result.assess(&result.candidates[0]).state, State::Feasible);
    let dear = &result.candidates[1];
    assert!(dear.relative_cost.unwrap() > 1.0);
    assert!(dear.runs.iter().all(|o| o.is_cut() && o.cost <= incumbent), "{:?}", dear.runs);
    let caps: Vec<f64> = stand_in.jobs.iter().filter(|j| j.standard == Some(1)).filter_map(|j| j.cap).collect();
    assert_eq!(caps, vec![incumbent], "one run, capped at the incumbent's mean cost");
    assert_eq!(result.best_standard(), Some(0));
}

#[test]
fn the_best_standard_is_verified_before_the_search_and_bounds_the_answer() {
    // Standard 0 (cost 5.5) is equivalent; the lever space holds cheaper equivalent points.
    let stand_in = StandIn { standards: vec![(0.9, 0.3)], ..StandIn::new() };
    let (result, stand_in) = run_on(&SearchConfig { standards: 1, ..config() }, stand_in);
    let first_verify = stand_in.jobs.iter().position(|j| j.role == Role::Verify).expect("a verification");
    let first_point = stand_in.jobs.iter().position(|j| j.standard.is_none() && j.role == Role::Search).unwrap();
    assert!(first_verify < first_point, "the standard is verified before any point of the lever space runs");
    assert_eq!(stand_in.jobs[first_verify].standard, Some(0));
    assert_eq!(result.assess_verification(&result.candidates[0]).unwrap().state, State::Feasible);
    let best = &result.candidates[result.recommended.expect("a recommendation")];
    let cost = |c: &Candidate| result.assess(c).cost;
    assert!(cost(best) <= cost(&result.candidates[0]), "the answer never costs more than the verified standard");
    // Only candidates cheaper than the verified standard were verified after it.
    for c in result.candidates.iter().skip(1).filter(|c| !c.verification.is_empty()) {
        assert!(cost(c) < cost(&result.candidates[0]), "candidate {} verified at {}", c.id, cost(c));
    }
}

#[test]
fn a_relative_tolerance_without_margin_names_its_metric() {
    let error = search(&SearchConfig { tolerances: vec![(0.0, false)], ..config() }, &mut StandIn::new())
        .expect_err("a zero relative tolerance gives no margin");
    assert!(matches!(&error, TuneError::NoMargin { metric, .. } if metric == "pile_height"), "{error:?}");
    let text = error.to_string();
    assert!(text.starts_with("kept metric pile_height has mean "), "{text}");
    assert!(text.contains("keep.pile_height = { absolute"), "{text}");
}
