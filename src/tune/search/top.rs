//! A point of the lever space at its own largest valid time step: where the other levers leave the
//! step room (less damping, another integrator scheme), the cheapest setting of those levers mostly
//! lies at the largest step they allow, so exploration tries every second point there
//! ([`Context::at_largest_step`]).

use super::context::Context;
use crate::tune::design;
use crate::tune::model::{Evaluator, State};
use crate::tune::validity::bisect;

/// Bisection steps of a point's largest valid time-step coordinate: finer than the grid that points
/// snap to ([`design::QUANT`]).
const TOP_STEPS: usize = 8;

impl<E: Evaluator> Context<'_, E> {
    /// `point` with its time-step lever raised to the largest value predicted valid at its other
    /// levers' values, no larger than the time-step path found equivalent (see
    /// [`Self::path_step_cap`]), snapped to the design's grid; `point` itself without a time-step
    /// lever, or where its own value does not qualify.
    pub(super) fn at_largest_step(&mut self, point: &[f64]) -> Vec<f64> {
        let Some(d) = self.config.time_step else { return point.to_vec() };
        let cap = self.path_step_cap();
        let mut at = |u: f64| {
            let mut p = point.to_vec();
            p[d] = u;
            let screen = self.evaluator.screen(&design::snap(&p, &self.config.levels), None);
            self.predicted_valid(&screen) && screen.relative_cost.is_some_and(|c| c >= cap)
        };
        let (low, high) = (point[d], 1.0);
        let largest = if at(high) {
            high
        } else if at(low) {
            bisect(|u| !at(u), low, high, TOP_STEPS)
        } else {
            low
        };
        let mut raised = point.to_vec();
        raised[d] = largest;
        design::snap(&raised, &self.config.levels)
    }

    /// The least time-step cost ([`Candidate::relative_cost`](crate::tune::model::Candidate::relative_cost))
    /// a raised point may have: where a rung of the time-step path came out invalid or different,
    /// that of its cheapest equivalent rung (above the largest bad rung's when none is), else none
    /// (0): a step the path found changes the pile at the reference's levers is not tried elsewhere.
    fn path_step_cap(&self) -> f64 {
        let rungs: Vec<(f64, State)> = self
            .result
            .path
            .0
            .iter()
            .map(|&k| {
                let cand = &self.result.candidates[k];
                (cand.relative_cost.unwrap_or(1.0), self.result.assess(cand).state)
            })
            .collect();
        let bad = rungs.iter().filter(|(_, s)| matches!(s, State::Infeasible(_))).map(|&(c, _)| c);
        let Some(largest_bad) = bad.reduce(f64::max) else { return 0.0 };
        let good = rungs.iter().filter(|(_, s)| *s == State::Feasible).map(|&(c, _)| c).reduce(f64::min);
        good.unwrap_or(largest_bad * super::path::PATH_RESOLUTION)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::warning::{ValidityWarning, WarningKind};
    use crate::tune::model::{Screen, SearchConfig};
    use crate::tune::search::testing::{Screening, candidate, config, runs};

    /// Two levers: the time step (lever 0, each unit of its coordinate halving the cost) and a
    /// damping (lever 1) that lowers the stable step: valid while `u0 + 0.6 u1 <= 1`.
    fn damped(point: &[f64]) -> Screen {
        let over = point[0] + 0.6 * point[1] - 1.0;
        let warnings = match over > 1e-12 {
            true => vec![ValidityWarning::new(WarningKind::ContactTimeFraction, 1.0 + over, 1.0)],
            false => Vec::new(),
        };
        Screen {
            identity: format!("{point:?}"),
            predicted: Ok(warnings),
            resolved: Vec::new(),
            relative_cost: Some(0.5f64.powf(point[0])),
        }
    }

    fn two_levers(time_step: Option<usize>) -> SearchConfig {
        SearchConfig {
            dims: 2,
            levels: vec![None, None],
            dissipation: vec![0.0; 2],
            home: vec![None; 2],
            time_step,
            ..config()
        }
    }

    #[test]
    fn a_point_rises_to_the_largest_step_its_own_damping_allows() {
        let config = two_levers(Some(0));
        let mut evaluator = Screening { screen: damped, standard_point: None };
        let mut cx = Context::new(&config, &mut evaluator);
        // No damping: the range's top; damping 0.5: 1 - 0.3, found within the bisection's resolution.
        assert_eq!(cx.at_largest_step(&[0.1, 0.0]), vec![1.0, 0.0]);
        let raised = cx.at_largest_step(&[0.1, 0.5]);
        assert!(raised[0] <= 0.7 && raised[0] > 0.7 - 1.0 / 64.0, "{raised:?}");
        // A point already past its own limit, or above the largest valid step, is left where it is.
        assert_eq!(cx.at_largest_step(&[0.875, 1.0]), vec![0.875, 1.0]);
        // Without a time-step lever nothing moves.
        let config = two_levers(None);
        let mut cx = Context::new(&config, &mut evaluator);
        assert_eq!(cx.at_largest_step(&[0.1, 0.0]), vec![0.1, 0.0]);
    }

    #[test]
    fn a_step_the_path_found_different_is_not_tried_at_other_levers() {
        let config = SearchConfig { tolerances: vec![(0.01, false)], ..two_levers(Some(0)) };
        let mut evaluator = Screening { screen: damped, standard_point: None };
        let mut cx = Context::new(&config, &mut evaluator);
        cx.result.reference = runs(1.0, &[1.0, 1.001, 0.999, 1.0, 1.0005, 0.9995, 1.0, 1.0]);
        cx.result.margins = vec![0.01];
        // The path's top rung (cost 0.5) differs by 10 %; its next (cost 0.6) is equivalent.
        let mut top = candidate(1, runs(0.5, &[1.1, 1.1005, 1.0995, 1.1]));
        top.relative_cost = Some(0.5);
        let mut next = candidate(2, runs(0.6, &[1.0, 1.0005, 0.9995, 1.0]));
        next.relative_cost = Some(0.6);
        cx.result.candidates = vec![top, next];
        cx.result.path.0 = vec![0, 1];
        let raised = cx.at_largest_step(&[0.1, 0.0]);
        let cost = 0.5f64.powf(raised[0]);
        assert!(cost >= 0.6 && cost < 0.6 * 0.5f64.powf(-1.0 / 64.0), "{raised:?} costs {cost}");
    }
}
