//! The standard settings: the tune's ladder of settings other than the time-step path's first,
//! each run when the spend limit leaves room, a rung whose runs break a measured check stepped down
//! once.

use super::context::{Context, Flow};
use crate::tune::model::{Evaluator, Origin, TuneError};

/// The step: the other standard settings proposed and their first seeds run in turn.
pub(super) fn step<E: Evaluator>(cx: &mut Context<'_, E>) -> Result<Flow, TuneError> {
    for k in usize::from(cx.config.path)..cx.config.standards {
        if let Some(index) = cx.propose_standard(k, Origin::Standard)
            && cx.run_first(index)?
        {
            cx.step_down(index)?;
        }
    }
    Ok(Flow::Next)
}

impl<E: Evaluator> Context<'_, E> {
    /// When candidate `k`'s search runs break a measured check that a smaller time step cures and
    /// `k` is a standard setting not itself stepped down: the same setting with its time step
    /// multiplied by [`cure_factor`](crate::tune::judge::cure_factor) becomes a new standard setting and runs its search seeds (when
    /// the budget and the spend limit leave room for them and a verification).
    fn step_down(&mut self, k: usize) -> Result<(), TuneError> {
        let c = self.config;
        let cand = &self.result.candidates[k];
        let (Some(standard), None) = (cand.standard, cand.stepped_from) else { return Ok(()) };
        let Some((factor, _)) = self.cure(k) else { return Ok(()) };
        let Some(stepped) = self.evaluator.step_down(standard, factor) else { return Ok(()) };
        let Some(index) = self.propose_standard(stepped, Origin::Standard) else { return Ok(()) };
        self.result.candidates[index].stepped_from = Some(k);
        if self.fits(c.seeds + c.verify_seeds, self.result.candidates[index].relative_cost) {
            self.run_more(&[(index, c.seeds)])?;
        }
        Ok(())
    }
}
