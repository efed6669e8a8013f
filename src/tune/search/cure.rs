//! Cures: the factor of a time step that brings a broken check under its limit, measured (the fitted
//! error model) or predicted (the ratio of its limit).

use super::context::Context;
use crate::physics::warning::{ValidityWarning, WarningKind};
use crate::tune::judge::cure_factor;
use crate::tune::model::{Evaluator, Rejection, State};

impl<E: Evaluator> Context<'_, E> {
    /// The factor that cures the measured check candidate `k`'s runs (its verification runs, when
    /// it has them) break, and `k`.
    pub(super) fn cure(&self, k: usize) -> Option<(f64, usize)> {
        let cand = &self.result.candidates[k];
        let a = match self.result.assess_verification(cand) {
            Some(a) => a,
            None => self.result.assess(cand),
        };
        let State::Infeasible(Rejection::Invalid(check)) = a.state else { return None };
        let reference = self.result.reference_checks.iter().find(|c| c.kind == check.kind);
        cure_factor(&check, reference, cand.relative_cost).map(|f| (f, k))
    }
}

/// The factor of the time step that brings a predicted warning that grows with it (a time step past
/// the contact-time or damping-rate limit, or capped by the latter) just under its limit; None for
/// one a smaller step does not cure.
pub(super) fn judge_time_step_cure(warning: &ValidityWarning) -> Option<f64> {
    let scales = matches!(
        warning.kind,
        WarningKind::TimeStepCapped
            | WarningKind::ContactTimeFraction
            | WarningKind::DampingRate
            | WarningKind::IntegratorStability
    );
    (scales && warning.value > 0.0).then(|| 0.99 * warning.limit / warning.value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_predicted_time_step_problem_is_cured_by_the_ratio_of_its_limit() {
        let capped = ValidityWarning::new(WarningKind::TimeStepCapped, 2e-5, 1e-5);
        assert!((judge_time_step_cure(&capped).unwrap() - 0.495).abs() < 1e-12);
        assert_eq!(judge_time_step_cure(&ValidityWarning::new(WarningKind::ImpactOverlap, 0.2, 0.1)), None);
    }
}
