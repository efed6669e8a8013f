//! More seeds where they decide: undecided candidates that could still win get further seeds, after
//! more reference runs where the reference's own mean is in doubt.

use super::context::{Context, Flow};
use crate::tune::model::{Evaluator, TuneError};

/// The step: more seeds while any candidate gets them.
pub(super) fn step<E: Evaluator>(cx: &mut Context<'_, E>) -> Result<Flow, TuneError> {
    let search_end = cx.search_end();
    while cx.extra_seeds(search_end)? {}
    Ok(Flow::Next)
}

impl<E: Evaluator> Context<'_, E> {
    /// Gives more seeds to undecided candidates that could still win, after more reference runs
    /// where the reference's own mean is in doubt ([`Self::doubtful_reference`]); false when there
    /// are none.
    pub(super) fn extra_seeds(&mut self, end: usize) -> Result<bool, TuneError> {
        if let Some(growth) = self.doubtful_reference()
            && self.grow(growth)?
        {
            return Ok(true);
        }
        let (_, incumbent_cost) = self.incumbent();
        let reference = self.result.reference_cost();
        let (mut chosen, mut runs, mut price) = (Vec::new(), 0, 0.0);
        for (k, cand) in self.result.candidates.iter().enumerate() {
            let a = self.result.assess(cand);
            let Some(more) = self.more_seeds(cand).filter(|_| a.cost < incumbent_cost) else { continue };
            let cost = more as f64 * a.cost / reference;
            let own = (a.n + more).max(self.config.verify_seeds) as f64 * a.cost / reference;
            let reserve = own.max(self.pending_reservation().unwrap_or(0.0));
            if self.result.runs + runs + more <= end && self.fits_price(runs + more, price + cost + reserve) {
                chosen.push((k, more));
                (runs, price) = (runs + more, price + cost);
            }
        }
        if chosen.is_empty() {
            return self.grow_reference();
        }
        self.run_more(&chosen)?;
        Ok(true)
    }
}
