//! The edge of equivalence: the levers that shorten settling (damping, a larger time step) also move
//! the pile, so the cheapest equivalent setting mostly lies where a kept metric's difference nears
//! its tolerance. Between the incumbent (equivalent) and a cheaper point whose kept metrics differ,
//! the search tries the point where the differences, interpolated linearly along the segment, first
//! reach [`EDGE_SHARE`] of a tolerance ([`Context::edge_points`]); the runs there move the incumbent
//! or the far end, and the next round narrows the segment again (a secant search of the edge).

use super::context::Context;
use super::standing::CLEAR_MARGIN;
use crate::tune::design;
use crate::tune::model::{Evaluator, Origin, Rejection, State};

/// The share of a kept metric's tolerance an edge point aims at: room for the seed-to-seed spread
/// of the search's few seeds and of a verification's fresh ones.
pub(super) const EDGE_SHARE: f64 = 0.5;

/// The most new edge points a round proposes.
const EDGE_MOVES: usize = 2;

impl<E: Evaluator> Context<'_, E> {
    /// New runnable candidates on the edge of equivalence (see the module documentation), at most
    /// [`EDGE_MOVES`], from the cheapest far ends first: each between the incumbent and a lever-space
    /// candidate decided different whose runs cost less, on the same value of every discrete lever,
    /// where the cost interpolated geometrically between the two ends is below [`CLEAR_MARGIN`] of
    /// the incumbent's.
    pub(super) fn edge_points(&mut self) -> Vec<usize> {
        let (Some(incumbent), incumbent_cost) = self.incumbent() else { return Vec::new() };
        let Some(from) = self.lever_point(incumbent) else { return Vec::new() };
        let near = self.result.assess(&self.result.candidates[incumbent]);
        let near_differences: Vec<f64> = near.tests.iter().map(|t| t.difference).collect();
        let mut far_ends: Vec<(f64, Vec<f64>, Vec<f64>)> = self
            .result
            .candidates
            .iter()
            .filter(|c| c.standard.is_none() && c.point.len() == from.len() && !self.discrete_apart(&from, &c.point))
            .map(|c| (c, self.result.assess(c)))
            .filter(|(_, a)| matches!(a.state, State::Infeasible(Rejection::Differs(_))) && a.cost < incumbent_cost)
            .map(|(c, a)| (a.cost, c.point.clone(), a.tests.iter().map(|t| t.difference).collect()))
            .collect();
        far_ends.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut fresh = Vec::new();
        for (far_cost, to, far_differences) in far_ends {
            if fresh.len() == EDGE_MOVES {
                break;
            }
            let Some(t) = edge_fraction(&near_differences, &far_differences, &self.result.margins) else { continue };
            if incumbent_cost.powf(1.0 - t) * far_cost.powf(t) >= CLEAR_MARGIN * incumbent_cost {
                continue;
            }
            let point: Vec<f64> = from.iter().zip(&to).map(|(a, b)| a + t * (b - a)).collect();
            fresh.extend(self.propose(&point, Origin::Edge).filter(|&k| !self.far_too_dear(k)));
        }
        fresh
    }

    /// Whether two points of the lever space lie on different values of a discrete lever.
    fn discrete_apart(&self, a: &[f64], b: &[f64]) -> bool {
        (0..a.len()).any(|d| self.config.levels[d].is_some() && a[d] != b[d])
    }

    /// A candidate's point of the lever space; a standard setting's from the evaluator.
    fn lever_point(&mut self, k: usize) -> Option<Vec<f64>> {
        let cand = &self.result.candidates[k];
        match cand.standard {
            Some(standard) => self.evaluator.standard_point(standard),
            None => Some(cand.point.clone()),
        }
        .filter(|p| p.len() == self.config.dims)
        .map(|p| design::snap(&p, &self.config.levels))
    }
}

/// Where along the segment from `near` to `far` (each kept metric's difference from the reference at
/// the two ends; `margins` their tolerances) the linearly interpolated differences first reach
/// [`EDGE_SHARE`] of a tolerance: the least such fraction in (0, 1); None when `near` is not inside
/// that share on every metric or `far` on none is past it.
pub(super) fn edge_fraction(near: &[f64], far: &[f64], margins: &[f64]) -> Option<f64> {
    let share = |k: usize| EDGE_SHARE * margins[k];
    if near.len() != margins.len() || far.len() != margins.len() || (0..near.len()).any(|k| near[k].abs() >= share(k)) {
        return None;
    }
    let crossing =
        |k: usize| (far[k].abs() > share(k)).then(|| (share(k) * far[k].signum() - near[k]) / (far[k] - near[k]));
    (0..margins.len()).filter_map(crossing).filter(|t| *t > 0.0 && *t < 1.0).reduce(f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tune::model::{Outcome, Screen, SearchConfig};
    use crate::tune::search::testing::{Screening, candidate, config, runs};

    /// Every setting valid at the reference's time step.
    fn flat(point: &[f64]) -> Screen {
        Screen { identity: format!("{point:?}"), predicted: Ok(Vec::new()), resolved: Vec::new(), relative_cost: None }
    }

    /// A kept metric's runs at `difference` from the reference's mean of 1, with a tiny spread.
    fn at(cost: f64, difference: f64) -> Vec<Outcome> {
        runs(cost, &[1.0 + difference, 1.0 + difference + 0.0005, 1.0 + difference - 0.0005, 1.0 + difference])
    }

    #[test]
    fn the_search_tries_the_point_where_the_difference_reaches_half_the_tolerance_between_incumbent_and_cheaper_different_point()
     {
        let config = SearchConfig {
            dims: 2,
            levels: vec![None, None],
            dissipation: vec![0.0; 2],
            home: vec![None; 2],
            ..config()
        };
        let mut evaluator = Screening { screen: flat, standard_point: Some(vec![1.0, 0.0]) };
        let mut cx = Context::new(&config, &mut evaluator);
        cx.result.reference = runs(1.0, &[1.0, 1.001, 0.999, 1.0, 1.0005, 0.9995, 1.0, 1.0]);
        cx.result.margins = vec![0.05];
        // The incumbent: the standard setting at (1, 0), 0.1 of the tolerance off, costing 0.2. A
        // point at (1, 0.8) costs 0.07 and differs by 1.6 tolerances; a dearer one is no far end.
        let mut standard = candidate(1, at(0.2, 0.005));
        (standard.standard, standard.point) = (Some(0), Vec::new());
        let mut cheap = candidate(2, at(0.07, 0.08));
        cheap.point = vec![1.0, 0.8];
        let mut dear = candidate(3, at(0.5, 0.08));
        dear.point = vec![0.2, 0.2];
        cx.result.candidates = vec![standard, cheap, dear];
        let fresh = cx.edge_points();
        assert_eq!(fresh.len(), 1, "{:?}", cx.result.candidates);
        let edge = &cx.result.candidates[fresh[0]];
        // (0.5 − 0.1) / (1.6 − 0.1) of the way from (1, 0) to (1, 0.8), on the design's grid.
        let expected = 0.8 * 0.4 / 1.5;
        assert_eq!(edge.origin, Origin::Edge);
        assert!(edge.point[0] == 1.0 && (edge.point[1] - expected).abs() <= 0.5 / 64.0, "{:?}", edge.point);
        assert!(cx.edge_points().is_empty(), "the same edge is proposed once");
        // An incumbent past half its tolerance has no edge to aim at.
        cx.result.candidates.truncate(3);
        cx.seen.clear();
        cx.result.candidates[0].runs = at(0.2, 0.03);
        assert!(cx.edge_points().is_empty());
    }

    #[test]
    fn the_edge_is_where_the_first_metric_reaches_its_share_of_the_tolerance() {
        // One metric: 0.1 of its tolerance at the incumbent, 1.5 (past it) at the far end: the
        // half-tolerance crossing lies (0.5 - 0.1) / 1.4 of the way.
        let t = edge_fraction(&[0.01], &[0.15], &[0.1]).unwrap();
        assert!((t - 0.4 / 1.4).abs() < 1e-12, "{t}");
        // A negative far difference crosses the negative side.
        let t = edge_fraction(&[0.01], &[-0.19], &[0.1]).unwrap();
        assert!((t - 0.06 / 0.2).abs() < 1e-12, "{t}");
        // Two metrics: the one that crosses first sets the fraction.
        let t = edge_fraction(&[0.0, 0.0], &[0.2, 0.06], &[0.1, 0.1]).unwrap();
        assert!((t - 0.25).abs() < 1e-12, "{t}");
    }

    #[test]
    fn no_edge_from_an_incumbent_past_the_share_or_towards_a_far_end_inside_it() {
        assert_eq!(edge_fraction(&[0.06], &[0.3], &[0.1]), None, "the incumbent is past half its tolerance");
        assert_eq!(edge_fraction(&[0.01], &[0.04], &[0.1]), None, "the far end is inside half its tolerance");
        assert_eq!(edge_fraction(&[0.01], &[0.3], &[0.1, 0.1]), None, "one difference per kept metric");
    }
}
