//! Where the tune spends: on stand-ins whose cost is its time step's times a settle time, the search
//! evaluates damping levers that leave the time step alone (never the reference's own setting again),
//! a time-step path whose rungs all fail leaves spend for the other levers, and a cheap corner that
//! needs more than `max_seeds` seeds to decide gets them and is the answer.

mod tune_common;

use demsweep::physics::warning::{ValidityWarning, WarningKind};
use demsweep::tune::model::{
    Evaluator, Job, Outcome, Role, RunFailure, Screen, SearchConfig, SearchEnd, SearchResult, State, TuneError,
};
use demsweep::tune::search::search;
use tune_common::{dump, hash, normal, stand_in_config};

/// A function of a point of the lever space.
type Field = fn(&[f64]) -> f64;

/// A reference run costs 100 (time step 1, settle time 1, metric 1 plus `reference_bias(seed)` with
/// spread `reference_spread`, 0 and 0.01 unless set). A setting at
/// point `p` has time step `1 / step_cost(p)` and settle time `settle(p)`: a run costs
/// `100 · step_cost · settle`; its metric is `1 + offset(p)` plus Gaussian noise of sd `spread(p)`. A
/// run at a point where `settles` is false never settles and costs five times as much, unless cut.
/// Standard setting k is the point `standards[k].0` with its time step divided by `standards[k].1`
/// (`step_down` adds the same point with a smaller step). The reference is the setting at point
/// `reference_at` when one is given (a lever space that contains it), else no point. A point where
/// `unstable` holds is predicted past the integrator's stable step. A verification run settles
/// `verify_settle` times as long as a search run at the same point (1 unless set).
struct StandIn {
    step_cost: Field,
    settle: Field,
    offset: Field,
    spread: Field,
    settles: fn(&[f64], bool) -> bool,
    reference_spread: f64,
    reference_bias: fn(u64) -> f64,
    reference_at: Option<Vec<f64>>,
    unstable: Field,
    standards: Vec<(Vec<f64>, f64)>,
    verify_settle: f64,
    jobs: Vec<Job>,
}

impl StandIn {
    fn new() -> Self {
        Self {
            step_cost: |_| 1.0,
            settle: |_| 1.0,
            offset: |_| 0.0,
            spread: |_| 0.01,
            settles: |_, _| true,
            reference_spread: 0.01,
            reference_bias: |_| 0.0,
            reference_at: None,
            unstable: |_| 0.0,
            standards: Vec::new(),
            verify_settle: 1.0,
            jobs: Vec::new(),
        }
    }

    /// The point, the time step's cost factor and whether it is a standard setting.
    fn setting(&self, point: &[f64], standard: Option<usize>) -> (Vec<f64>, f64, bool) {
        match standard {
            Some(k) => {
                let (p, scale) = &self.standards[k];
                (p.clone(), (self.step_cost)(p) / scale, true)
            }
            None => (point.to_vec(), (self.step_cost)(point), false),
        }
    }
}

impl Evaluator for StandIn {
    fn screen(&mut self, point: &[f64], standard: Option<usize>) -> Screen {
        let (p, step, _) = self.setting(point, standard);
        let unstable = (self.unstable)(&p);
        let warnings = if unstable > 0.0 {
            vec![ValidityWarning::new(WarningKind::IntegratorStability, 1.0 + unstable, 1.0)]
        } else {
            Vec::new()
        };
        Screen {
            identity: identity(&p, step),
            predicted: Ok(warnings),
            resolved: Vec::new(),
            relative_cost: Some(step),
        }
    }

    fn reference_identity(&mut self) -> String {
        self.reference_at.as_ref().map_or("reference".to_string(), |p| identity(p, (self.step_cost)(p)))
    }

    fn step_down(&mut self, standard: usize, factor: f64) -> Option<usize> {
        let (p, scale) = self.standards[standard].clone();
        self.standards.push((p, scale * factor));
        Some(self.standards.len() - 1)
    }

    fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, TuneError> {
        self.jobs.extend(jobs.iter().cloned());
        Ok(jobs
            .iter()
            .map(|job| {
                if job.role == Role::Reference {
                    let metric = 1.0 + (self.reference_bias)(job.seed) + self.reference_spread * normal(job.seed);
                    return Outcome::settled(100.0, vec![metric]);
                }
                let (p, step, standard) = self.setting(&job.point, job.standard);
                let key =
                    p.iter().fold(step.to_bits(), |h, x| hash(h ^ x.to_bits())) ^ job.seed.wrapping_mul(0x9e37_79b9);
                let metric = 1.0 + (self.offset)(&p) + (self.spread)(&p) * normal(key);
                let settles = (self.settles)(&p, standard);
                let fresh = if job.role == Role::Verify { self.verify_settle } else { 1.0 };
                let cost = 100.0 * step * if settles { (self.settle)(&p) * fresh } else { 5.0 };
                let mut outcome = Outcome::settled(cost, vec![metric]);
                if !settles {
                    outcome.failure = Some(RunFailure::NotSettled);
                }
                if let Some(cap) = job.cap.filter(|&cap| cost > cap) {
                    (outcome.cost, outcome.failure) = (cap, Some(RunFailure::Cut { cap }));
                }
                outcome
            })
            .collect())
    }
}

fn identity(point: &[f64], step: f64) -> String {
    format!("{point:?} {step}")
}

/// What a search spent: the cost of every run it made (reference depositions times 100).
fn spent(result: &SearchResult) -> f64 {
    let candidates = result.candidates.iter().flat_map(|c| c.runs.iter().chain(&c.verification));
    result.reference.iter().chain(candidates).map(|o| o.cost).sum()
}

/// The answer's verified mean cost over the reference's, and the answer.
fn answer(result: &SearchResult) -> (f64, &demsweep::tune::model::Candidate) {
    let best = &result.candidates[result.recommended.unwrap_or_else(|| panic!("no answer:\n{}", dump(result)))];
    let verified = result.assess_verification(best).expect("verified");
    assert_eq!(verified.state, State::Feasible);
    (verified.cost / result.reference_cost(), best)
}

#[test]
fn a_damping_only_tune_evaluates_damping_settings() {
    // Two damping levers: the time step never moves; more of either settles sooner. The standard
    // setting (local damping 0.2, at the centre) settles at 0.65 of the reference; more damping is
    // cheaper and as good.
    let stand_in =
        StandIn { settle: |p| 1.0 - 0.5 * p[0] - 0.2 * p[1], standards: vec![(vec![0.5, 0.5], 1.0)], ..StandIn::new() };
    let mut stand_in = stand_in;
    let result = search(&SearchConfig { standards: 1, max_spend: 30.0, ..stand_in_config() }, &mut stand_in).unwrap();
    let evaluated = result.candidates.iter().filter(|c| c.standard.is_none() && !c.runs.is_empty()).count();
    assert!(evaluated >= 3, "the damping levers were searched: {evaluated} settings\n{}", dump(&result));
    let (cost, best) = answer(&result);
    assert!(best.standard.is_none() && cost < 0.55, "a cheaper damping setting is the answer: {cost}");
}

#[test]
fn a_numerical_damping_tune_never_reruns_the_references_own_setting() {
    // Two numerical damping levers (no cheap end: the corner stays at the reference's values, the
    // origin) that shorten the settle time a little: the reference's own setting is no candidate,
    // and the spend goes to damping settings that can win.
    let stand_in =
        StandIn { settle: |p| 1.0 - 0.1 * p[0] - 0.05 * p[1], reference_at: Some(vec![0.0, 0.0]), ..StandIn::new() };
    let mut stand_in = stand_in;
    let config = SearchConfig { home: vec![Some(0.0), Some(0.0)], ..stand_in_config() };
    let result = search(&config, &mut stand_in).unwrap();
    let origin = stand_in.jobs.iter().filter(|j| j.role != Role::Reference && j.point == [0.0, 0.0]).count();
    assert_eq!(origin, 0, "the reference's setting ran as a candidate:\n{}", dump(&result));
    let (cost, best) = answer(&result);
    assert!(cost < 0.95, "a damping setting is the answer: {cost} at {:?}", best.point);
}

#[test]
fn a_candidate_likely_different_gets_no_more_seeds() {
    // The cheap half of the first lever (a stiffness) shifts the metric by twice the margin, with a
    // seed-to-seed spread that leaves its first 3 runs undecided: more of them would only decide it
    // different. The rest keeps the pile.
    let stand_in = StandIn {
        step_cost: |p| 1.0 - 0.5 * p[0],
        offset: |p| if p[0] > 0.5 { 0.1 } else { 0.0 },
        spread: |p| if p[0] > 0.5 { 0.05 } else { 0.01 },
        ..StandIn::new()
    };
    let mut stand_in = stand_in;
    let config = SearchConfig { max_spend: 30.0, ..stand_in_config() };
    let result = search(&config, &mut stand_in).unwrap();
    let shifted: Vec<_> = result.candidates.iter().filter(|c| c.point.first().is_some_and(|&x| x > 0.5)).collect();
    let undecided = shifted.iter().filter(|c| result.assess(c).state == State::Undecided).count();
    assert!(undecided > 0, "a shifted setting ran and stayed undecided:\n{}", dump(&result));
    for cand in shifted.iter().filter(|c| result.assess(c).state == State::Undecided) {
        assert_eq!(cand.runs.len(), config.seeds, "no seeds past its first:\n{}", dump(&result));
    }
    let (cost, best) = answer(&result);
    assert!(best.point[0] <= 0.5 && cost < 0.8, "{cost} at {:?}", best.point);
}

#[test]
fn the_search_says_whether_the_spend_limit_the_run_budget_or_its_settings_ended_it() {
    // A damping lever that shortens settling a little: each limit in turn is the one that binds.
    let stand_in = || StandIn { settle: |p| 1.0 - 0.2 * p[0], ..StandIn::new() };
    let spend = search(&SearchConfig { max_spend: 12.0, ..stand_in_config() }, &mut stand_in()).unwrap();
    assert_eq!(spend.end, SearchEnd::SpendLimit, "{}", dump(&spend));
    let runs = search(&SearchConfig { budget: 40, max_spend: 100.0, ..stand_in_config() }, &mut stand_in()).unwrap();
    assert_eq!(runs.end, SearchEnd::RunBudget, "{}", dump(&runs));
    assert!(runs.runs <= 40);
    // Two values of each lever: every setting runs, and the search runs out of settings.
    let few = SearchConfig { levels: vec![Some(2), Some(2)], max_spend: 100.0, ..stand_in_config() };
    let exhausted = search(&few, &mut stand_in()).unwrap();
    assert_eq!(exhausted.end, SearchEnd::Exhausted, "{}", dump(&exhausted));
}

#[test]
fn a_time_step_path_whose_rungs_all_fail_leaves_spend_for_the_other_levers() {
    // The time step at its largest value never settles, nor does any smaller step the path tries; the
    // other lever (the second coordinate, a damping) settles sooner where it is larger.
    let stand_in = StandIn {
        step_cost: |p| 1.0 - 0.5 * p[0],
        settle: |p| 1.0 - 0.4 * p[1],
        settles: |_, standard| !standard,
        standards: vec![(vec![1.0, 0.5], 1.0)],
        ..StandIn::new()
    };
    let mut stand_in = stand_in;
    let result = search(&SearchConfig { standards: 1, path: true, ..stand_in_config() }, &mut stand_in).unwrap();
    assert!(!result.path.0.is_empty(), "the path ran: {:?}\n{}", result.path, dump(&result));
    assert!(
        result
            .path
            .0
            .iter()
            .all(|&k| matches!(result.assess(&result.candidates[k]).state, State::Infeasible(_) | State::Cut))
    );
    let evaluated = result.candidates.iter().filter(|c| c.standard.is_none() && !c.runs.is_empty()).count();
    assert!(evaluated >= 2, "the other levers were evaluated: {evaluated} settings");
    let (cost, best) = answer(&result);
    assert!(best.standard.is_none() && cost < 0.8, "{cost}");
}

#[test]
fn a_cheap_corner_that_needs_more_than_max_seeds_to_decide_is_found() {
    // The stiffness-like first lever halves the time step's cost at its top end (1 - 0.6 x); the
    // second, a damping, shortens the settle time. Every setting keeps the pile, but above x = 0.85
    // the metric spreads ten times more from seed to seed: about 15 seeds decide it, past max_seeds = 8.
    let stand_in = StandIn {
        step_cost: |p| 1.0 - 0.6 * p[0],
        settle: |p| 1.0 - 0.3 * p[1],
        spread: |p| if p[0] > 0.85 { 0.1 } else { 0.01 },
        ..StandIn::new()
    };
    let mut stand_in = stand_in;
    let config = SearchConfig { max_spend: 40.0, ..stand_in_config() };
    let result = search(&config, &mut stand_in).unwrap();
    let (cost, best) = answer(&result);
    assert!(best.point[0] > 0.85, "the cheap corner is the answer: {:?} at {cost}", best.point);
    assert!(best.runs.len() > config.max_seeds, "it got the seeds that decide it: {}", best.runs.len());
    let searched: Vec<u64> = stand_in.jobs.iter().filter(|j| j.role != Role::Verify).map(|j| j.seed).collect();
    assert!(best.verify_seeds.iter().all(|s| !searched.contains(s)), "verified on seeds the search never ran");
    let spent = spent(&result);
    assert!(spent <= config.max_spend * 100.0, "{spent}");
}

#[test]
fn the_cheap_corner_lowers_the_restitution_and_keeps_the_users_numerical_damping() {
    // A restitution (first lever, dissipative downwards) and a local damping (second, the user's 0 at
    // coordinate 0): the lowest restitution settles soonest and keeps the pile; local damping past
    // 0.3 of its range changes it.
    let stand_in =
        StandIn { settle: |p| 0.6 + 0.4 * p[0], offset: |p| if p[1] > 0.3 { 0.2 } else { 0.0 }, ..StandIn::new() };
    let mut stand_in = stand_in;
    let config = SearchConfig { dissipation: vec![-1.0, 0.0], home: vec![Some(0.75), Some(0.0)], ..stand_in_config() };
    let result = search(&config, &mut stand_in).unwrap();
    let first = result.candidates.iter().find(|c| c.standard.is_none()).expect("a search point");
    assert_eq!(first.point, vec![0.0, 0.0], "the corner comes first:\n{}", dump(&result));
    let (cost, best) = answer(&result);
    assert!(best.point[1] <= 0.3 && cost < 0.7, "{cost} at {:?}", best.point);
}

#[test]
fn a_cheap_corner_past_the_stable_step_backs_off_the_damping_and_keeps_the_step() {
    // A restitution (first lever, dissipative downwards) and a time-step fraction (second, cheaper
    // upwards): the lowest restitution at the largest step is past the stable step, which grows with
    // the restitution. Raising the restitution a quarter keeps the largest step and is valid; the step
    // lowered is valid too but dearer, and so is moving both.
    let stand_in = StandIn {
        step_cost: |p| 1.0 - 0.6 * p[1],
        settle: |p| 0.6 + 0.4 * p[0],
        unstable: |p| p[1] - 0.8 - 0.8 * p[0],
        ..StandIn::new()
    };
    let mut stand_in = stand_in;
    let config = SearchConfig { dissipation: vec![-1.0, 0.0], ..stand_in_config() };
    let result = search(&config, &mut stand_in).unwrap();
    let skipped: Vec<_> = result.candidates.iter().filter(|c| c.predicted_invalid.is_some()).collect();
    assert_eq!(skipped.first().map(|c| c.point.clone()), Some(vec![0.0, 1.0]), "the corner:\n{}", dump(&result));
    let first = result.candidates.iter().find(|c| c.predicted_invalid.is_none()).expect("a runnable point");
    assert_eq!(first.point, vec![0.25, 1.0], "the step kept, the restitution raised:\n{}", dump(&result));
    let (cost, _) = answer(&result);
    assert!(cost < 0.33, "{cost}");
}

#[test]
fn after_a_time_step_path_left_undecided_the_search_prices_its_points_at_their_own_time_step() {
    // The first lever, a stiffness, makes the time step up to four times cheaper (1 - 0.75 x); above
    // x = 0.9 the pile moves by 0.045 against a margin of 0.05, which no number of seeds decides. The
    // time-step path runs there and stays undecided, leaving 7 of 16 reference runs: priced at the
    // reference's time step, a verification round alone would take 8; priced at their own time step,
    // the other settings still fit and hold the answer.
    let stand_in = StandIn {
        step_cost: |p| 1.0 - 0.75 * p[0],
        offset: |p| if p[0] > 0.9 { 0.045 } else { 0.0 },
        standards: vec![(vec![1.0, 0.5], 1.0)],
        ..StandIn::new()
    };
    let mut stand_in = stand_in;
    let config = SearchConfig { standards: 1, path: true, max_spend: 16.0, ..stand_in_config() };
    let result = search(&config, &mut stand_in).unwrap();
    assert!(!result.path.0.is_empty(), "the path ran: {:?}\n{}", result.path, dump(&result));
    let (cost, best) = answer(&result);
    assert!(
        best.standard.is_none() && best.point[0] <= 0.9 && cost < 0.6,
        "{cost} at {:?}\n{}",
        best.point,
        dump(&result)
    );
}

#[test]
fn a_candidate_the_references_own_spread_leaves_undecided_gets_a_larger_reference() {
    // The reference's metric spreads more than any candidate's (its first seed is an outlier), and
    // every setting sits 0.025 from it against a margin of 0.05: with the reference's 6 runs no number
    // of candidate seeds decides (the interval never gets narrower than about 0.022 around the
    // difference); with 12 a few more do.
    let stand_in =
        StandIn { settle: |p| 1.0 - 0.5 * p[0], offset: |_| 0.025, reference_spread: 0.015, ..StandIn::new() };
    let mut stand_in = stand_in;
    let config = SearchConfig { max_spend: 30.0, ..stand_in_config() };
    let result = search(&config, &mut stand_in).unwrap();
    assert!(
        result.reference.len() > config.reference_seeds,
        "the reference grew: {}\n{}",
        result.reference.len(),
        dump(&result)
    );
    assert!(result.reference.len() <= 2 * config.reference_seeds, "at most doubled: {}", result.reference.len());
    let (cost, _) = answer(&result);
    assert!(cost < 0.8, "{cost}\n{}", dump(&result));
    let seeds: Vec<u64> = stand_in.jobs.iter().filter(|j| j.role == Role::Reference).map(|j| j.seed).collect();
    assert_eq!(seeds, (0..result.reference.len() as u64).collect::<Vec<_>>(), "each reference seed once");
}

#[test]
fn the_time_step_path_stops_stepping_down_where_the_cheap_corner_is_cheaper() {
    // The first lever, a stiffness, makes the time step up to five times cheaper (1 - 0.8 x). The
    // time-step path's first rung (the reference's stiffness at 2.5 times its step) sits on the
    // margin; a smaller step only costs more, while the softest stiffness costs 0.2 and keeps the pile.
    let stand_in = StandIn {
        step_cost: |p| 1.0 - 0.8 * p[0],
        offset: |p| if p[0] < 0.1 { 0.045 } else { 0.0 },
        standards: vec![(vec![0.0, 0.5], 2.5)],
        ..StandIn::new()
    };
    let mut stand_in = stand_in;
    let config = SearchConfig { standards: 1, path: true, max_spend: 30.0, ..stand_in_config() };
    let result = search(&config, &mut stand_in).unwrap();
    assert_eq!(result.path.0.len(), 1, "one rung, no step down: {:?}\n{}", result.path, dump(&result));
    let (cost, best) = answer(&result);
    assert!(best.standard.is_none() && cost < 0.3, "{cost} at {:?}\n{}", best.point, dump(&result));
}

#[test]
fn a_reference_whose_first_seeds_drew_high_grows_and_the_pile_is_kept() {
    // Every setting keeps the pile (metric 1, margin 0.05; spread 0.02, the reference's 0.01) and
    // more of the first lever settles sooner, but the reference's six seeds drew 0.04 high: against
    // them every candidate sits 0.04 off, and no number of candidate seeds decides (the reference
    // alone keeps the interval about as wide as the 0.01 left). Its further seeds draw true.
    let stand_in = StandIn {
        settle: |p| 1.0 - 0.5 * p[0],
        spread: |_| 0.02,
        reference_bias: |seed| if seed < 6 { 0.04 } else { 0.0 },
        ..StandIn::new()
    };
    let mut stand_in = stand_in;
    let config = SearchConfig { max_spend: 30.0, ..stand_in_config() };
    let result = search(&config, &mut stand_in).unwrap();
    assert!(result.reference.len() > config.reference_seeds, "the reference grew\n{}", dump(&result));
    let (cost, _) = answer(&result);
    assert!(cost < 0.8, "{cost}\n{}", dump(&result));
}

#[test]
fn a_setting_that_saves_nothing_on_its_fresh_seeds_is_no_answer() {
    // One damping lever that shortens settling by at most 5 % on the search's seeds; on fresh seeds
    // every setting settles 10 % later (the search's seeds drew short): each verified candidate
    // passes on the pile but costs more than the reference there.
    let mut stand_in = StandIn { settle: |p| 1.0 - 0.05 * p[0], verify_settle: 1.1, ..StandIn::new() };
    let config =
        SearchConfig { dims: 1, levels: vec![None], dissipation: vec![0.0], home: vec![None], ..stand_in_config() };
    let result = search(&config, &mut stand_in).unwrap();
    let passed: Vec<_> = result
        .candidates
        .iter()
        .filter(|c| result.assess_verification(c).is_some_and(|v| v.state == State::Feasible))
        .collect();
    assert!(!passed.is_empty(), "a candidate passed its verification\n{}", dump(&result));
    for cand in passed {
        let verified = result.assess_verification(cand).expect("verified").cost;
        assert!(verified > result.reference_cost(), "dearer on its fresh seeds: {verified}");
    }
    assert_eq!(result.recommended, None, "no answer\n{}", dump(&result));
}

#[test]
fn a_fixed_time_step_damping_only_tune_with_ten_reference_seeds_evaluates_a_damping_setting() {
    // Two damping levers and a fixed time step; the reference runs on 10 seeds, leaving 10 of the 20
    // reference depositions. Priced at the reference's cost, a candidate's first 3 seeds and its
    // verification (8) come to 12.1 with the margin: nothing would run. The standard setting settles
    // at 0.7 of the reference and every setting keeps the pile: its first seeds, cut where they could
    // no longer leave room to verify it, are information, and it and its verification fit.
    let stand_in =
        StandIn { settle: |p| 0.9 - 0.3 * p[0] - 0.1 * p[1], standards: vec![(vec![0.5, 0.5], 1.0)], ..StandIn::new() };
    let mut stand_in = stand_in;
    let config = SearchConfig { standards: 1, reference_seeds: 10, ..stand_in_config() };
    let result = search(&config, &mut stand_in).unwrap();
    let evaluated = result.candidates.iter().filter(|c| !c.runs.is_empty()).count();
    assert!(evaluated >= 1, "a damping setting ran: {evaluated} settings\n{}", dump(&result));
    let (cost, _) = answer(&result);
    assert!(cost < 0.9, "a damping setting is the answer: {cost}\n{}", dump(&result));
    let spent = spent(&result);
    assert!(spent <= config.max_spend * 100.0, "within the spend limit: {spent}");
}

#[test]
fn the_sheet_lists_a_cheaper_undecided_candidate_and_a_larger_spend_resumed_decides_it() {
    // The cheap corner of the stiffness-like first lever (above x = 0.85, about a third of the
    // reference's cost) keeps the pile but its metric spreads ten times more: within 20 reference
    // depositions its verification stays undecided. The sheet names it, its metric, its seeds a side
    // and the spend that decides it; the tune resumed with that spend replays every stored run and
    // goes on verifying it to a decision.
    let stand_in = || StandIn {
        step_cost: |p| 1.0 - 0.6 * p[0],
        settle: |p| 1.0 - 0.3 * p[1],
        spread: |p| if p[0] > 0.85 { 0.1 } else { 0.01 },
        ..StandIn::new()
    };
    let spec = demsweep::tune::load(std::path::Path::new("tests/data/tiny_tune.toml")).unwrap();
    let mut first = stand_in();
    let result = search(&stand_in_config(), &mut first).unwrap();
    let out = std::path::Path::new("elsewhere/tiny");
    let sheet = demsweep::tune::report::paragraph(&spec, &result, Some(out));
    let listed = sheet.lines().find(|l| l.starts_with("Undecided, cheaper: candidate "));
    let listed = listed.unwrap_or_else(|| panic!("the sheet lists the undecided candidate:\n{sheet}"));
    assert!(listed.contains("pile_height undecided") && listed.contains("seeds a side"), "{listed}");
    assert!(!sheet.contains("nothing cheaper"), "{sheet}");
    let id: usize = listed["Undecided, cheaper: candidate ".len()..].split(' ').next().unwrap().parse().unwrap();
    // The command names the --out folder the tune was given, where its stored runs are.
    assert!(
        sheet.contains("`demsweep tune tests/data/tiny_tune.toml --out elsewhere/tiny --resume --max-spend "),
        "{sheet}"
    );
    let resume = sheet.split("--resume --max-spend ").nth(1).and_then(|r| r.split('`').next()?.parse::<f64>().ok());
    let max_spend = resume.unwrap_or_else(|| panic!("the sheet names the spend:\n{sheet}"));
    let mut second = stand_in();
    let more = search(&SearchConfig { max_spend, ..stand_in_config() }, &mut second).unwrap();
    let stored: Vec<String> = first.jobs.iter().map(|j| format!("{j:?}")).collect();
    let replayed: Vec<String> = second.jobs.iter().map(|j| format!("{j:?}")).collect();
    assert!(stored.iter().all(|j| replayed.contains(j)), "every stored run replayed:\n{}", dump(&more));
    let (before, after) = (&result.candidates[id - 1], &more.candidates[id - 1]);
    assert_eq!(before.point, after.point);
    assert!(after.verification.len() > before.verification.len(), "verified further:\n{}", dump(&more));
    let decided = more.assess_verification(after).expect("verified").state;
    assert_ne!(decided, State::Undecided, "decided on its fresh seeds:\n{}", dump(&more));
}

#[test]
fn the_sheet_names_the_keep_line_that_would_hold_an_unkept_metric_beyond_two_sigma() {
    // The answer's fresh runs read fabric_anisotropy (not kept) ten reference spreads higher than the
    // reference's and every other pile metric as the reference does.
    let mut stand_in =
        StandIn { settle: |p| 1.0 - 0.5 * p[0] - 0.2 * p[1], standards: vec![(vec![0.5, 0.5], 1.0)], ..StandIn::new() };
    let mut result =
        search(&SearchConfig { standards: 1, max_spend: 30.0, ..stand_in_config() }, &mut stand_in).unwrap();
    let names = demsweep::tune::keepable_metrics();
    let pile = |shift: f64, key: u64| {
        names.iter().map(|n| 1.0 + 0.01 * normal(key) + if n == "fabric_anisotropy" { shift } else { 0.0 }).collect()
    };
    for (i, run) in result.reference.iter_mut().enumerate() {
        run.pile = pile(0.0, i as u64);
    }
    let k = result.recommended.unwrap_or_else(|| panic!("an answer\n{}", dump(&result)));
    for (i, run) in result.candidates[k].verification.iter_mut().enumerate() {
        run.pile = pile(0.1, 1000 + i as u64);
    }
    let spec = demsweep::tune::load(std::path::Path::new("tests/data/tiny_tune.toml")).unwrap();
    let sheet = demsweep::tune::report::paragraph(&spec, &result, None);
    let line = sheet.lines().find(|l| l.trim_start().starts_with("fabric_anisotropy:"));
    let line = line.unwrap_or_else(|| panic!("a fabric_anisotropy line:\n{sheet}"));
    assert!(line.contains("beyond 2σ; to hold it within 2σ, add `fabric_anisotropy = { absolute = "), "{line}");
    let kept = sheet.lines().find(|l| l.trim_start().starts_with("pile_height:")).expect("pile_height");
    assert!(!kept.contains("beyond 2σ"), "{kept}");
}

#[test]
fn first_seeds_that_fit_only_cut_run_one_at_a_time_and_stop_at_the_first_cut() {
    // As above without the standard setting, and every point of the lever space settles at 0.95 of
    // the reference: past the cap (0.83) that leaves room to verify it. A point's first seed is cut
    // there, and its other two never run.
    let mut stand_in = StandIn { settle: |_| 0.95, ..StandIn::new() };
    let config = SearchConfig { reference_seeds: 10, ..stand_in_config() };
    let result = search(&config, &mut stand_in).unwrap();
    let cut: Vec<_> = result.candidates.iter().filter(|c| c.runs.iter().any(Outcome::is_cut)).collect();
    assert!(!cut.is_empty(), "a point's first seeds were cut to fit the spend\n{}", dump(&result));
    for cand in cut {
        assert_eq!(cand.runs.len(), 1, "one cut run, not {}\n{}", cand.runs.len(), dump(&result));
    }
    let spent = spent(&result);
    assert!(spent <= config.max_spend * 100.0, "within the spend limit: {spent}");
}
