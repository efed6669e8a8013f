//! The placement seeds runs are made on: a seed where the reference's disks cannot be placed (a
//! random placement near its jamming limit fits on some seeds and not on others) is no deposition
//! of the reference, and no run is made on it; the search steps over it.

use super::context::Context;
use crate::tune::model::Evaluator;

/// Most seeds in a row stepped over as unplaceable: the next is taken anyway (its runs then fail,
/// naming why), so that a scene that can hardly be placed does not search for seeds forever.
const MOST_UNPLACEABLE: u64 = 64;

impl<E: Evaluator> Context<'_, E> {
    /// The seed of the reference's and every candidate's search run number `position`: the
    /// `position`-th seed from 0 on where the reference's disks can be placed.
    pub(super) fn replicate(&mut self, position: usize) -> u64 {
        while self.result.replicates.len() <= position {
            let next = self.result.replicates.last().map_or(0, |&seed| seed + 1);
            let seed = self.placeable_from(next);
            self.result.replicates.push(seed);
        }
        self.result.replicates[position]
    }

    /// The next fresh seed of a verification, one where the reference's disks can be placed.
    pub(super) fn fresh_seed(&mut self) -> u64 {
        let seed = self.placeable_from(self.next_seed);
        self.next_seed = seed + 1;
        seed
    }

    /// The first seed from `from` on where the reference's disks can be placed; those stepped over
    /// are recorded.
    fn placeable_from(&mut self, from: u64) -> u64 {
        next_placeable(self.evaluator, from, &mut self.result.unplaceable)
    }
}

/// The first seed from `from` on where the reference's disks can be placed (at most
/// [`MOST_UNPLACEABLE`] stepped over), those stepped over into `stepped_over`.
pub fn next_placeable<E: Evaluator>(evaluator: &mut E, from: u64, stepped_over: &mut Vec<u64>) -> u64 {
    let mut seed = from;
    while seed - from < MOST_UNPLACEABLE && !evaluator.placeable(seed) {
        stepped_over.push(seed);
        seed += 1;
    }
    seed
}

/// `count` seeds from `from` on where the reference's disks can be placed.
pub fn placeable_seeds<E: Evaluator>(evaluator: &mut E, from: u64, count: usize) -> Vec<u64> {
    let mut seeds: Vec<u64> = Vec::with_capacity(count);
    while seeds.len() < count {
        let next = seeds.last().map_or(from, |&seed| seed + 1);
        seeds.push(next_placeable(evaluator, next, &mut Vec::new()));
    }
    seeds
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tune::model::{Job, Outcome, first_verification_seed};
    use crate::tune::search::testing::{Running, config};

    /// An evaluator that makes no run, whose reference's disks cannot be placed on `unplaceable`.
    fn holes(unplaceable: Vec<u64>) -> Running<impl FnMut(&Job) -> Outcome> {
        Running { run: |_: &Job| -> Outcome { unreachable!() }, unplaceable }
    }

    #[test]
    fn runs_step_over_the_seeds_the_references_disks_cannot_be_placed_on() {
        let config = config();
        let first_fresh = first_verification_seed(config.budget, config.reference_seeds);
        let mut holes = holes(vec![2, 3, 7, first_fresh + 1]);
        let mut cx = Context::new(&config, &mut holes);
        // Run numbers 0-5 of the reference and of every candidate's search: the same seeds.
        let search: Vec<u64> = (0..6).map(|p| cx.replicate(p)).collect();
        assert_eq!(search, [0, 1, 4, 5, 6, 8]);
        assert_eq!((0..6).map(|p| cx.replicate(p)).collect::<Vec<_>>(), search, "asked again, the same");
        let fresh: Vec<u64> = (0..3).map(|_| cx.fresh_seed()).collect();
        assert_eq!(fresh, [first_fresh, first_fresh + 2, first_fresh + 3]);
        assert_eq!(cx.result.unplaceable, [2, 3, 7, first_fresh + 1]);
    }

    #[test]
    fn a_scene_that_can_hardly_be_placed_is_not_searched_for_seeds_forever() {
        let config = config();
        let mut holes = holes((0..1000).collect());
        let mut cx = Context::new(&config, &mut holes);
        assert_eq!(cx.replicate(0), MOST_UNPLACEABLE);
        assert_eq!(cx.result.unplaceable.len(), MOST_UNPLACEABLE as usize);
    }
}
