//! The answer sheet's parts on hand-made search results.

use super::course::end_line;
use super::phrases::resolved_time_step;
use super::sheet::run_counts;
use crate::physics::number::short;
use crate::tune::model::{Candidate, Origin, Outcome, PathEnd, Rejection, RunFailure, SearchEnd, SearchResult, State};

fn candidate(id: usize, standard: Option<usize>, runs: Vec<Outcome>) -> Candidate {
    Candidate {
        id,
        point: if standard.is_some() { Vec::new() } else { vec![0.5] },
        standard,
        identity: id.to_string(),
        origin: if standard.is_some() { Origin::Standard } else { Origin::Initial },
        predicted_invalid: None,
        runs,
        verification: Vec::new(),
        verify_seeds: Vec::new(),
        relative_cost: Some(0.5),
        stepped_from: None,
    }
}

fn result(candidates: Vec<Candidate>) -> SearchResult {
    SearchResult {
        replicates: Vec::new(),
        unplaceable: Vec::new(),
        reference: vec![Outcome::settled(1.0, vec![1.0]); 4],
        margins: vec![0.1],
        reference_checks: Vec::new(),
        candidates,
        recommended: None,
        runs: 0,
        budget: 100,
        undecidable: Vec::new(),
        path: (Vec::new(), PathEnd::NotRun),
        end: SearchEnd::NotSearched,
        wall_rates: Vec::new(),
    }
}

/// A tune whose levers are two stages' steps: a contact-time fraction and a time step.
const STAGED: &str = r#"
[scene]
particles.count = 30
particles.radius = 0.005
domain.width = 0.1
domain.height = 0.15
material.youngs_modulus = 5e10
integrator.time_step = 7e-6
run.duration = 1.0
[[scene.stages]]
name = "fill"
until.time = 0.1
damping.local = 0.5
[[scene.stages]]
name = "calm"
until.time = 0.1
damping.local = 0.3
[levers]
"stages.fill.integrator.contact_time_fraction" = [0.02, 0.04]
"stages.calm.integrator.time_step" = [2e-6, 3e-6]
[keep]
pile_height = 0.25
"#;

/// [`STAGED`] loaded from a file of its own (`name`).
fn staged_spec(name: &str) -> crate::tune::TuneSpec {
    crate::tune::file::load_text(name, STAGED)
}

#[test]
fn the_sheet_states_the_step_of_a_stage_whose_step_a_lever_sets() {
    let spec = staged_spec("staged-tune");
    let cand = Candidate { point: vec![0.0, 0.0], ..candidate(1, None, Vec::new()) };
    let scene = crate::tune::candidate_scene(&spec, &cand).unwrap();
    let dt = |k: usize| crate::physics::scene_time_step(&scene.in_stage(&scene.stages[k]), None).dt;
    let text = resolved_time_step(&spec, &cand);
    assert!(text.starts_with(&format!("time step {} s (", short(7e-6))), "{text}");
    assert!(text.contains(&format!("; in stage \"fill\": time step {} s;", short(dt(0)))), "{text}");
    assert!(text.contains(&format!("; in stage \"calm\": time step {} s (", short(2e-6))), "{text}");
    assert!(text.ends_with(" of the contact time)") && dt(0) != 7e-6 && dt(1) == 2e-6, "{text}");
}

#[test]
fn the_sheet_says_why_the_search_ended_never_overstating_what_was_left() {
    assert_eq!(end_line(SearchEnd::NotSearched, 150, 14.0), "");
    let spend = end_line(SearchEnd::SpendLimit, 150, 6.27);
    assert!(spend.contains("spend limit") && spend.ends_with("6.2 reference depositions were left. "), "{spend}");
    assert!(end_line(SearchEnd::SpendLimit, 150, -0.3).contains(": 0 reference depositions were left"));
    assert!(end_line(SearchEnd::RunBudget, 150, 9.0).contains("the run budget (150 runs"));
    assert!(end_line(SearchEnd::Exhausted, 150, 9.0).contains("no new setting that could still win"));
}

#[test]
fn run_counts_say_which_runs_failed_and_why_and_when_no_search_run_was_made() {
    let unsettled = Outcome { failure: Some(RunFailure::NotSettled), ..Outcome::settled(2.0, vec![1.0]) };
    let cut = Outcome { failure: Some(RunFailure::Cut { cap: 1.0 }), ..Outcome::settled(1.0, vec![1.0]) };
    let standard = candidate(1, Some(0), vec![unsettled.clone(), unsettled.clone(), cut.clone()]);
    let counts = run_counts(&result(vec![standard.clone()]));
    assert_eq!(
        counts,
        "7 runs: 4 reference, 3 standard settings (1 cut once they could no longer win; 2 failed: 2 did not \
         settle), no search run was made, 0 verification"
    );
    let searched = result(vec![standard, candidate(2, None, vec![cut.clone(), cut])]);
    assert!(run_counts(&searched).contains(", 2 search (2 cut once they could no longer win), "));
    let a = searched.assess(&searched.candidates[0]);
    assert!(matches!(a.state, State::Infeasible(Rejection::Failed(RunFailure::NotSettled))), "{:?}", a.state);
}

#[test]
fn a_setting_cut_below_the_answers_cost_is_listed_as_perhaps_cheaper_not_as_unable_to_win() {
    let spec = staged_spec("cut-tune");
    let point = |cand: Candidate| Candidate { point: vec![0.0, 0.0], ..cand };
    let cut = |cost: f64| Outcome { failure: Some(RunFailure::Cut { cap: cost }), ..Outcome::settled(cost, vec![1.0]) };
    let mut answer = point(candidate(1, None, vec![Outcome::settled(0.6, vec![1.0]); 3]));
    answer.verification = vec![Outcome::settled(0.6, vec![1.0]); 4];
    let cheap_cut = point(candidate(2, None, vec![cut(0.3)]));
    let dear_cut = point(candidate(3, None, vec![cut(0.9)]));
    let mut result = result(vec![answer, cheap_cut, dear_cut]);
    result.recommended = Some(0);
    let sheet = super::paragraph(&spec, &result, None);
    assert!(sheet.contains("Cut before it settled, perhaps cheaper: candidate 2 ("), "{sheet}");
    assert!(sheet.contains("on 1 seed, cut at 0.3 of the reference, below the answer's cost in the search (0.6)"));
    assert!(!sheet.contains("candidate 3 ("), "{sheet}");
    assert!(sheet.contains("--resume --max-spend "), "{sheet}");
    let counts = run_counts(&result);
    assert!(
        counts.contains(
            "search (1 cut once they could no longer win; 1 cut below the answer's cost before they settled)"
        ),
        "{counts}"
    );
}

#[test]
fn an_undecided_candidate_that_needs_more_runs_than_the_budget_leaves_names_the_budget_that_decides_it() {
    let spec = staged_spec("budget-tune");
    let runs = |cost: f64, values: &[f64]| values.iter().map(|&v| Outcome::settled(cost, vec![v])).collect::<Vec<_>>();
    let undecided = Candidate { point: vec![0.0, 0.0], ..candidate(1, None, runs(0.5, &[1.02, 1.14, 0.9, 0.98])) };
    let mut result = result(vec![undecided]);
    result.reference = runs(1.0, &[1.0, 1.1, 0.9, 1.05]);
    let a = result.assess(&result.candidates[0]);
    assert_eq!(a.state, State::Undecided, "{a:?}");
    let needed = a.tests[0].seeds_needed.expect("seeds that decide it");
    let within = super::paragraph(&spec, &result, None);
    assert!(within.contains(&format!("about {needed} seeds a side")), "{within}");
    assert!(!within.contains("budget ="), "room within the budget of 100 runs: {within}");
    result.runs = 100 - needed;
    let beyond = super::paragraph(&spec, &result, None);
    assert!(beyond.contains("and budget = ") && beyond.contains("(more runs than the run budget of 100 leaves)"));
    assert!(beyond.contains("once `[search] budget = "), "{beyond}");
}
