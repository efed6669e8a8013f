//! New candidates: a point of the lever space or a standard setting, recorded once, with what its
//! screen predicts.

use super::context::Context;
use crate::tune::design;
use crate::tune::judge::predicted_breach;
use crate::tune::model::{Candidate, Evaluator, NotRun, Origin};

impl<E: Evaluator> Context<'_, E> {
    /// A new candidate unless one resolves to the same runs; one predicted invalid (past a limit
    /// the reference does not break as much) or unable to start is recorded, not returned.
    pub(super) fn add(&mut self, point: Vec<f64>, standard: Option<usize>, origin: Origin) -> Option<usize> {
        let screen = self.evaluator.screen(&point, standard);
        if !self.seen.insert(screen.identity.clone()) {
            return None;
        }
        let predicted_invalid = match screen.predicted {
            Ok(warnings) => {
                predicted_breach(&warnings, &self.result.reference_checks).map(|(_, w)| NotRun::Predicted(w))
            }
            Err(error) => Some(NotRun::Unstartable(error)),
        };
        let valid = predicted_invalid.is_none();
        let id = self.result.candidates.len() + 1;
        let point = if screen.resolved.is_empty() { point } else { screen.resolved };
        self.result.candidates.push(Candidate {
            id,
            point,
            standard,
            identity: screen.identity,
            origin,
            predicted_invalid,
            runs: Vec::new(),
            verification: Vec::new(),
            verify_seeds: Vec::new(),
            relative_cost: screen.relative_cost,
            stepped_from: None,
        });
        valid.then_some(id - 1)
    }

    pub(super) fn propose(&mut self, point: &[f64], origin: Origin) -> Option<usize> {
        let point = design::snap(point, &self.config.levels);
        self.add(point, None, origin)
    }

    pub(super) fn propose_standard(&mut self, k: usize, origin: Origin) -> Option<usize> {
        self.add(Vec::new(), Some(k), origin)
    }
}
