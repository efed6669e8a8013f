//! The search's order of work ([`search`]): its steps, in turn, on one shared context.

use super::context::{Context, Flow, Step};
use super::{corner, explore, path, reference, seeds, standards, verify};
use crate::tune::design::PRIMES;
use crate::tune::model::{Evaluator, SearchConfig, SearchResult, TuneError};

/// Runs the search: each step in turn, until one stops it.
pub fn search<E: Evaluator>(config: &SearchConfig, evaluator: &mut E) -> Result<SearchResult, TuneError> {
    assert!(config.dims <= PRIMES.len(), "at most {} levers", PRIMES.len());
    let steps: [Step<E>; 8] = [
        reference::step,       // the reference's runs and margins; an undecidable metric stops here
        path::step,            // the time-step path
        standards::step,       // the other standard settings
        corner::step,          // the cheap corner
        seeds::step,           // more seeds where they decide
        verify::before_search, // the standard settings' and the corner's likeliest saving verified
        explore::step,         // the initial design and the pattern search
        verify::all,           // the cheapest candidates verified
    ];
    let mut cx = Context::new(config, evaluator);
    for step in steps {
        if step(&mut cx)? == Flow::Stop {
            break;
        }
    }
    Ok(cx.result)
}
