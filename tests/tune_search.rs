//! The tune search on a cheap analytic stand-in with noise: the known optimum is found, the budget is
//! kept, the same configuration gives the same answer, the infeasible and predicted-invalid regions
//! are never the answer (and the predicted-invalid one is never run).

use demsweep::tune::search::{Evaluator, Job, Outcome, Role, SearchConfig, SearchResult, State, search};

/// cost = 10 − 4a − 3b (cheaper to the upper right); one metric, 1 + 0.1·max(0, a + b − 1.2) plus
/// Gaussian noise (sd 0.005) that depends only on the point and the seed; runs with a > 0.95 diverge;
/// a < 0.25 is predicted invalid. With an absolute tolerance of 0.02 the optimum lies near a = 0.95,
/// b ≈ 0.4 (cost ≈ 4.9-5.1).
struct StandIn {
    runs: usize,
    jobs: Vec<Job>,
    batches: usize,
}

fn hash(mut x: u64) -> u64 {
    x ^= x >> 33;
    x = x.wrapping_mul(0xff51_afd7_ed55_8ccd);
    x ^= x >> 33;
    x = x.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    x ^ (x >> 33)
}

fn normal(key: u64) -> f64 {
    let u1 = ((hash(key) >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
    let u2 = ((hash(key ^ 0x5555) >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

impl Evaluator for StandIn {
    fn invalid(&mut self, point: &[f64]) -> Option<String> {
        (point[0] < 0.25).then(|| "predicted to overlap too much".to_string())
    }

    fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, String> {
        self.runs += jobs.len();
        self.batches += 1;
        self.jobs.extend(jobs.iter().cloned());
        Ok(jobs
            .iter()
            .map(|job| {
                let (a, b) = if job.role == Role::Reference { (0.3, 0.2) } else { (job.point[0], job.point[1]) };
                let key = a.to_bits() ^ b.to_bits().rotate_left(17) ^ job.seed.wrapping_mul(0x9e37_79b9);
                let metric = 1.0 + 0.1 * (a + b - 1.2).max(0.0) + 0.005 * normal(key);
                let failure = (a > 0.95).then(|| "diverged".to_string());
                Outcome { failure, cost: 10.0 - 4.0 * a - 3.0 * b, metrics: vec![metric] }
            })
            .collect())
    }
}

fn config() -> SearchConfig {
    SearchConfig {
        dims: 2,
        levels: vec![None, None],
        tolerances: vec![(0.02, true)],
        seeds: 3,
        max_seeds: 8,
        reference_seeds: 8,
        verify_seeds: 6,
        budget: 200,
        seed: 11,
        initial: None,
    }
}

fn run(config: &SearchConfig) -> (SearchResult, StandIn) {
    let mut stand_in = StandIn { runs: 0, jobs: Vec::new(), batches: 0 };
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
    let (result, stand_in) = run(&config());
    assert!(stand_in.jobs.iter().filter(|j| j.role != Role::Reference).all(|j| j.point[0] >= 0.25));
    assert!(result.candidates.iter().any(|c| c.predicted_invalid.is_some()), "the design touched the region");
    for c in result.candidates.iter().filter(|c| c.runs.iter().any(|o| o.failure.is_some())) {
        assert!(matches!(result.assess(c).state, State::Infeasible(_)));
    }
}

#[test]
fn nothing_acceptable_names_the_closest_candidate() {
    // An absolute tolerance far below the noise: nothing can be shown equivalent.
    let config = SearchConfig { tolerances: vec![(1e-4, true)], budget: 80, ..config() };
    let (result, stand_in) = run(&config);
    assert_eq!(result.recommended, None);
    assert!(result.closest().is_some());
    assert!(result.runs <= config.budget && stand_in.runs == result.runs);
}
