//! Judging runs against the reference: validity over a candidate's runs together ([`check_figures`]),
//! held to the reference's own figure where the reference breaks a rule of thumb; equivalence of every
//! kept metric by two one-sided tests ([`assess`]); whether a tolerance can be decided at all
//! ([`decidability`]); and how much smaller a time step cures a check it breaks ([`cure_factor`]).
//!
//! **The validity rule.** A measured check (energy balance, overlap) varies from seed to seed: it is
//! judged on the runs together. Its figure is the 75th percentile of the runs' values (linear
//! interpolation between order statistics); the runs pass when the figure is at most the limit and no
//! run is beyond twice it. One outlier seed of a setting whose other runs pass with margin cannot
//! break it; many marginal runs cannot pass. A predicted check (contact-time fraction, damping rate,
//! impact and static overlap, a capped time step) does not vary by seed: every run must pass.
//!
//! **Relative to the reference.** Where the reference's own figure of a check is beyond its limit, the
//! limit a candidate is held to is that figure: no worse than what the user runs today (a predicted
//! check: within [`PREDICTED_SLACK`] of it, for the placement's small effect on the prediction).

use std::collections::BTreeMap;

use super::model::{
    Assessment, Candidate, CheckFigure, NotRun, Outcome, Reading, Rejection, SearchResult, State, Undecidable,
    describe_metric,
};
use crate::physics::warning::{ValidityWarning, WarningKind};
use crate::stats::{self, Decision, Equivalence, fit};

/// The quantile of a measured check's values that must stay within the limit.
pub const CHECK_QUANTILE: f64 = 0.75;

/// How far past the limit a single run of a measured check may go, in limits.
pub const OUTLIER_FACTOR: f64 = 2.0;

/// Where the reference breaks a predicted check, how much above the reference's figure a candidate's
/// runs may go: the prediction (of the hardest impact) moves a little with the placement seed.
pub const PREDICTED_SLACK: f64 = 0.05;

/// What a smaller time step aims at: the excess (see [`CheckFigure::excess`]) brought to this
/// share, leaving room for seeds not yet run.
pub const STEP_DOWN_SAFETY: f64 = 0.8;

/// The order bounds of an integration error in the time step: at least 1 (any consistent
/// integrator), at most 2 (the schemes' order).
pub const ERROR_ORDER: (f64, f64) = (1.0, 2.0);

/// Each check the runs report, judged over them (see the module documentation), in kind order. A
/// check the reference breaks is held to the reference's figure (`reference`, as given by this same
/// function on the reference's runs).
pub fn check_figures(runs: &[Outcome], reference: &[CheckFigure]) -> Vec<CheckFigure> {
    let mut by_kind: BTreeMap<WarningKind, Vec<(usize, Reading)>> = BTreeMap::new();
    for (k, run) in runs.iter().enumerate().filter(|(_, r)| r.failure.is_none()) {
        for reading in &run.readings {
            by_kind.entry(reading.kind).or_default().push((k, *reading));
        }
    }
    by_kind
        .into_iter()
        .map(|(kind, readings)| {
            let values: Vec<f64> = readings.iter().map(|(_, r)| r.value).collect();
            let limit = readings.iter().map(|(_, r)| r.limit).fold(f64::INFINITY, f64::min);
            let (worst_run, worst) = readings
                .iter()
                .map(|(k, r)| (*k, r.value))
                .fold((0, f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a });
            let figure = if kind.is_measured() { fit::quantile(&values, CHECK_QUANTILE) } else { worst };
            let reference_figure = reference.iter().find(|c| c.kind == kind).map_or(0.0, |c| c.figure);
            let slack = if kind.is_measured() { 1.0 } else { 1.0 + PREDICTED_SLACK };
            let held_to = if reference_figure > limit { reference_figure * slack } else { limit };
            let tolerance = 1.0 + 1e-9;
            let outlier = if kind.is_measured() { OUTLIER_FACTOR } else { 1.0 };
            let passes = figure <= held_to * tolerance && worst <= outlier * held_to * tolerance;
            CheckFigure { kind, figure, worst, worst_run, limit, held_to, passes }
        })
        .collect()
}

/// The first check that predicted `warnings` break beyond what it is held to (see
/// [`check_figures`]), and the warning.
pub fn predicted_breach(
    warnings: &[ValidityWarning],
    reference: &[CheckFigure],
) -> Option<(CheckFigure, ValidityWarning)> {
    let runs = [Outcome { readings: warnings.iter().map(Into::into).collect(), ..Outcome::settled(0.0, Vec::new()) }];
    let broken = check_figures(&runs, reference).into_iter().find(|c| !c.passes)?;
    warnings.iter().find(|w| w.kind == broken.kind).map(|w| (broken, w.clone()))
}

/// The checks the reference's own runs break (held to themselves, they pass): what tune says up front.
pub fn broken_by_reference(reference_checks: &[CheckFigure]) -> Vec<&CheckFigure> {
    reference_checks.iter().filter(|c| c.figure > c.limit).collect()
}

/// Judges runs against the reference's runs: failures first, then validity (see
/// [`check_figures`]), then every kept metric (margins absolute). A run that failed (diverged, did
/// not settle in its whole duration) makes it infeasible; else runs cut at their cost cap make the
/// candidate [`State::Cut`].
pub fn assess(
    reference: &[Outcome],
    reference_checks: &[CheckFigure],
    runs: &[Outcome],
    margins: &[f64],
) -> Assessment {
    if runs.is_empty() {
        return not_run(NotRun::NoRuns);
    }
    let cost = runs.iter().map(|o| o.cost).sum::<f64>() / runs.len() as f64;
    let checks = check_figures(runs, reference_checks);
    let base =
        Assessment { n: runs.len(), cost, tests: Vec::new(), checks, worst: f64::INFINITY, state: State::Undecided };
    if let Some(failure) = runs.iter().find_map(|o| o.failure.clone().filter(|_| !o.is_cut())) {
        return Assessment { state: State::Infeasible(Rejection::Failed(failure)), ..base };
    }
    if runs.iter().any(Outcome::is_cut) {
        return Assessment { state: State::Cut, ..base };
    }
    if let Some(broken) = base.checks.iter().find(|c| !c.passes) {
        return Assessment { state: State::Infeasible(Rejection::Invalid(*broken)), ..base };
    }
    let column = |set: &[Outcome], k: usize| set.iter().map(|o| o.metrics[k]).collect::<Vec<f64>>();
    let tests: Vec<Equivalence> =
        (0..margins.len()).map(|k| stats::equivalence(&column(reference, k), &column(runs, k), margins[k])).collect();
    let worst = tests.iter().zip(margins).map(|(t, m)| t.difference.abs() / m).fold(0.0, f64::max);
    let state = if let Some(k) = tests.iter().position(|t| t.decision == Decision::Different) {
        State::Infeasible(Rejection::Differs(k))
    } else if tests.iter().all(|t| t.decision == Decision::Equivalent) {
        State::Feasible
    } else {
        State::Undecided
    };
    Assessment { tests, worst, state, ..base }
}

/// The assessment of a candidate that was not run.
pub fn not_run(why: NotRun) -> Assessment {
    Assessment {
        n: 0,
        cost: f64::NAN,
        tests: Vec::new(),
        checks: Vec::new(),
        worst: f64::INFINITY,
        state: State::NotRun(why),
    }
}

/// The factor a time step is multiplied by to cure a broken measured check, when a run of it costs
/// `relative_cost` of a reference run (the reference's time step over its own) and the reference's
/// figure of the same check is `reference`.
///
/// The error follows a power of the time step, `e ∝ dt^p`. Through the reference's figure and the
/// rung's, `p` is fitted and kept within [`ERROR_ORDER`] (where the reference's figure says nothing,
/// as for an overlap that is mostly physical, p is 1: the smallest step). The step brings the excess
/// to [`STEP_DOWN_SAFETY`]: `(STEP_DOWN_SAFETY / excess)^(1/p)`. None when the check is not measured,
/// nothing is to cure, or the stepped rung would cost the reference's or more.
pub fn cure_factor(check: &CheckFigure, reference: Option<&CheckFigure>, relative_cost: Option<f64>) -> Option<f64> {
    let excess = check.excess();
    if !(check.kind.is_measured() && excess.is_finite() && excess > STEP_DOWN_SAFETY) {
        return None;
    }
    let order = match (reference, relative_cost.filter(|r| *r > 0.0 && *r < 1.0)) {
        (Some(r), Some(cost)) => fit::error_order(r.figure, check.figure, 1.0 / cost, ERROR_ORDER),
        _ => ERROR_ORDER.0,
    };
    let factor = (STEP_DOWN_SAFETY / excess).powf(1.0 / order);
    relative_cost.is_none_or(|r| r / factor < 1.0).then_some(factor)
}

impl SearchResult {
    /// A candidate's search runs judged against the reference.
    pub fn assess(&self, candidate: &Candidate) -> Assessment {
        match &candidate.predicted_invalid {
            Some(why) => not_run(why.clone()),
            None => self.assess_runs(&candidate.runs),
        }
    }

    /// Runs judged against the reference.
    pub fn assess_runs(&self, runs: &[Outcome]) -> Assessment {
        assess(&self.reference, &self.reference_checks, runs, &self.margins)
    }

    /// A candidate's verification runs judged against the reference.
    pub fn assess_verification(&self, candidate: &Candidate) -> Option<Assessment> {
        (!candidate.verification.is_empty()).then(|| self.assess_runs(&candidate.verification))
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

    /// The mean reference cost.
    pub fn reference_cost(&self) -> f64 {
        stats::describe(&self.reference_costs()).mean
    }
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
            let r = describe_metric(reference, k);
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

/// Whether more seeds are futile (a stopping rule for futility, as in sequential trials): on some
/// kept metric an undecided test's difference lies past its margin and its 90 % interval wholly on
/// that side of zero, so that more runs would most likely decide it different.
pub fn likely_different(tests: &[Equivalence], margins: &[f64]) -> bool {
    let past = |t: &Equivalence, m: f64| (t.difference > m && t.low > 0.0) || (t.difference < -m && t.high < 0.0);
    tests.iter().zip(margins).any(|(t, &m)| t.decision == Decision::Undecided && past(t, m))
}

/// Whether the reference's mean of some kept metric among `metrics` stands apart from the candidates':
/// every candidate mean in `means` (per candidate, per metric; at least two candidates) lies on the
/// same side of it, and their median lies outside the reference mean's own 95 % interval,
/// `t(0.975, n_r − 1) · s_r / √n_r`. A few reference seeds may be a chance draw; more of them tell a
/// lucky reference from a real shift of every setting.
pub fn reference_stands_apart(reference: &[Outcome], means: &[Vec<f64>], metrics: &[bool]) -> bool {
    let n_r = reference.len();
    if n_r < 2 || means.len() < 2 {
        return false;
    }
    (0..metrics.len()).filter(|&k| metrics[k]).any(|k| {
        let r = describe_metric(reference, k);
        let half = stats::student_t_quantile(0.975, (n_r - 1) as f64) * r.std / (n_r as f64).sqrt();
        let column: Vec<f64> = means.iter().map(|m| m[k] - r.mean).collect();
        let median = fit::quantile(&column, 0.5);
        let one_side = column.iter().all(|d| d.signum() == median.signum());
        one_side && median.abs() > half
    })
}

/// How many candidate runs in all would decide every kept metric with the reference as run, when
/// the candidate's difference and spread stay as they are: the smallest n with
/// `t(0.95, n + n_r − 2) · √(s²/n + s_r²/n_r) < margin − |d|`; None when no number would (the
/// difference sits on the margin, or the reference's own runs leave too wide an interval).
pub fn runs_to_decide(reference: &[Outcome], runs: &[Outcome], margins: &[f64]) -> Option<usize> {
    runs_to_decide_with(reference, runs, margins, reference.len())
}

/// [`runs_to_decide`] with the reference grown to `reference_runs` runs whose mean and spread stay as
/// they are.
pub fn runs_to_decide_with(
    reference: &[Outcome],
    runs: &[Outcome],
    margins: &[f64],
    reference_runs: usize,
) -> Option<usize> {
    let n_r = reference_runs.max(reference.len());
    margins.iter().enumerate().try_fold(runs.len(), |most, (k, &margin)| {
        let (r, c) = (describe_metric(reference, k), describe_metric(runs, k));
        let room = margin - (c.mean - r.mean).abs();
        let half = |n: usize| {
            let se = (c.std.powi(2) / n as f64 + r.std.powi(2) / n_r as f64).sqrt();
            stats::student_t_quantile(0.95, (n + n_r).saturating_sub(2).max(1) as f64) * se
        };
        (room > 0.0).then(|| first_deciding(runs.len().max(2), |n| half(n) < room)).flatten().map(|n| most.max(n))
    })
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

#[cfg(test)]
mod tests {
    use super::*;

    fn energy(values: &[f64]) -> Vec<Outcome> {
        let reading = |value| Reading { kind: WarningKind::EnergyBalance, value, limit: 0.01 };
        values.iter().map(|&v| Outcome { readings: vec![reading(v)], ..Outcome::settled(1.0, vec![1.0]) }).collect()
    }

    #[test]
    fn one_outlier_seed_cannot_break_a_check_and_many_marginal_runs_cannot_pass() {
        let outlier = check_figures(&energy(&[0.004, 0.0112, 0.005, 0.004, 0.0045, 0.0038, 0.005, 0.0042]), &[]);
        assert!(outlier[0].passes, "{outlier:?}");
        assert_eq!((outlier[0].worst, outlier[0].worst_run), (0.0112, 1));
        let marginal = check_figures(&energy(&[0.0105, 0.0102, 0.0098, 0.0104, 0.0101, 0.0099, 0.0103, 0.0106]), &[]);
        assert!(!marginal[0].passes, "{marginal:?}");
        let far = check_figures(&energy(&[0.004, 0.021, 0.005]), &[]);
        assert!(!far[0].passes, "a run beyond twice the limit breaks it: {far:?}");
    }

    #[test]
    fn a_reference_stands_apart_only_when_every_candidate_sits_on_one_side_past_its_interval() {
        // Reference mean 1.0, standard deviation 0.0141 over 6 runs: its 95 % interval is ±0.0148.
        let reference: Vec<Outcome> =
            [0.99, 1.01, 0.98, 1.02, 1.0, 1.0].iter().map(|&v| Outcome::settled(1.0, vec![v])).collect();
        let means = |values: &[f64]| values.iter().map(|&v| vec![v]).collect::<Vec<_>>();
        assert!(reference_stands_apart(&reference, &means(&[0.97, 0.975, 0.96]), &[true]));
        assert!(!reference_stands_apart(&reference, &means(&[0.97, 0.975, 0.96]), &[false]), "not a metric asked");
        assert!(!reference_stands_apart(&reference, &means(&[0.97, 1.01, 0.96]), &[true]), "one on the other side");
        assert!(!reference_stands_apart(&reference, &means(&[0.995, 0.99, 0.97]), &[true]), "median inside");
        assert!(!reference_stands_apart(&reference, &means(&[0.96]), &[true]), "one candidate says little");
    }

    #[test]
    fn more_seeds_are_futile_only_past_the_margin_and_clear_of_zero() {
        let reference = [0.99, 1.01, 0.98, 1.02, 1.0, 1.0];
        let test = |candidate: &[f64]| stats::equivalence(&reference, candidate, 0.05);
        let far = test(&[1.04, 1.10, 1.07]);
        assert_eq!(far.decision, Decision::Undecided, "{far:?}");
        assert!(likely_different(&[far], &[0.05]), "past the margin, its interval clear of zero: {far:?}");
        let near = test(&[1.01, 1.07, 1.05]);
        assert!(near.difference < 0.05 && near.decision == Decision::Undecided, "{near:?}");
        assert!(!likely_different(&[near], &[0.05]), "inside the margin more seeds may decide it: {near:?}");
        let wide = test(&[0.95, 1.25, 0.98]);
        assert!(wide.difference > 0.05 && wide.low < 0.0, "{wide:?}");
        assert!(!likely_different(&[wide], &[0.05]), "an interval across zero says little: {wide:?}");
    }

    #[test]
    fn a_check_the_reference_breaks_holds_candidates_to_the_reference() {
        let reference = check_figures(&energy(&[0.013, 0.012, 0.014]), &[]);
        assert!(!reference[0].passes && broken_by_reference(&reference).len() == 1, "it breaks the 1 % limit");
        let same = check_figures(&energy(&[0.0125, 0.0135, 0.012]), &reference);
        assert!(same[0].passes && same[0].held_to > 0.01, "{same:?}");
        let worse = check_figures(&energy(&[0.02, 0.019, 0.021]), &reference);
        assert!(!worse[0].passes, "{worse:?}");
    }

    #[test]
    fn the_cure_follows_the_fitted_error_order() {
        let reference = check_figures(&energy(&[0.001, 0.001, 0.001]), &[]);
        let rung = check_figures(&energy(&[0.02, 0.02, 0.02]), &reference);
        // A step 4 times the reference's with 20 times its error: order ln 20 / ln 4 = 2.16, kept at 2.
        let factor = cure_factor(&rung[0], Some(&reference[0]), Some(0.25)).unwrap();
        assert!((factor - (0.8f64 / 2.0).sqrt()).abs() < 1e-12, "{factor}");
        assert!((cure_factor(&rung[0], None, Some(0.25)).unwrap() - 0.4).abs() < 1e-12, "first order without one");
        assert_eq!(cure_factor(&rung[0], Some(&reference[0]), Some(0.9)), None, "no cheaper than the reference");
    }
}
