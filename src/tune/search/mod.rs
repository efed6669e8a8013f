//! The search: find the cheapest point of a normalized lever space `[0, 1]^d` (or setting of the
//! ladder) whose replicated runs are valid and equivalent to the reference's on every kept metric.
//!
//! It is generic over an [`Evaluator`](crate::tune::model::Evaluator) (real runs through the
//! runner, or a cheap analytic stand-in in tests) and deterministic: every choice depends only on
//! the configuration, its seed and the outcomes of earlier batches, processed in job order.
//! Judgements are in `judge`.
//!
//! 1. The reference runs on `reference_seeds` seeds; each metric's margin is its tolerance times
//!    the reference mean (or the absolute tolerance). The reference's own validity figures are
//!    recorded: a check it breaks holds every candidate to no worse than it. A reference that
//!    diverges or does not settle stops the tune; so does a kept metric its spread cannot decide
//!    ([`decidability`](crate::tune::judge::decidability)). A setting that resolves to the
//!    reference's own runs is never a candidate.
//! 2. **The time-step path** (`path`), when a time-step key is a lever, before
//!    anything else: the first standard setting (the time-step lever alone at its largest valid
//!    value) and, below it, the same setting with a smaller time step, down to the
//!    reference's (valid and equivalent by definition). A rung whose runs break a measured check
//!    steps down by the fitted error model ([`cure_factor`](crate::tune::judge::cure_factor)); one
//!    that differs bisects (geometric mean) towards the last good rung or the reference, until the
//!    two are within `PATH_RESOLUTION`; the cheapest good rung is verified
//!    on fresh seeds, and a failed verification leads to the rung that cures it and a new
//!    verification. Only the run budget, the spend limit and a rung whose runs do not settle (a
//!    limit cycle) stop it; a rung's runs are cut at the cheapest other candidate still in the running.
//!    Nothing else runs before it ends.
//! 3. Exploration, with what is left of the spend limit: the other standard settings; an initial
//!    design (the cheap corner, each list lever such as `integrator.scheme` at the value whose own
//!    valid corner has the cheapest time step; a randomly shifted Halton sequence, quantized to a 1/64
//!    grid, every second point at its own largest valid time step (`top`); points predicted
//!    invalid are recorded and never run); then, each round, points on the edge of equivalence
//!    (`edge`) or else a pattern search (compass search, Kolda, Lewis &
//!    Torczon 2003) around the incumbent, leaving out moves a log-linear cost fit predicts dearer
//!    than it. Every candidate starts with `seeds` runs; an undecided one that could still win (and
//!    is not likely different) gets more, up to `max_seeds`, then sequentially the seeds that
//!    decide it; where the reference's own spread is what keeps it undecided, the reference grows
//!    (`grow_reference`). A new candidate predicted dearer
//!    than the cheapest one still in the running runs one seed first, cut at that cost; points
//!    predicted `FAR_TOO_DEAR` are not run. The search records why it
//!    ended ([`SearchEnd`](crate::tune::model::SearchEnd)).
//! 4. Verification of candidates cheaper than the answer so far, on fresh seeds never used in the
//!    search (they start past the run budget), judged on those runs alone: while there is no
//!    answer, as soon as a candidate is valid and equivalent; else when the search ends. The answer
//!    is the cheapest verified candidate that costs less than the reference on its fresh seeds.
//!
//! The files: `run` lists the steps in their order of work, each a function of one shared
//! `Context` (the configuration, the evaluator, the candidate table, the spend
//! and the fresh seeds) in a file of its own: `reference` (1), `path` (2), `standards`, `corner`,
//! `seeds` (more seeds where they decide) and `explore` (3), `verify` (4). Beneath them, what the
//! steps share, each file calling only those below it: `batch` runs a candidate's further seeds,
//! `propose` records new candidates, `reserve` keeps a verification round in reserve, `predict`
//! prices a setting before it runs, `standing` says which candidates are still in the running,
//! `cure` by how much a smaller time step cures a broken check, `replicates` which placement seeds
//! runs are made on, `top` raises a point to its own
//! largest valid time step and `spend` says whether runs fit the budget and the spend limit.

mod batch;
mod context;
mod corner;
mod cure;
mod edge;
mod explore;
mod path;
mod predict;
mod propose;
mod reference;
mod replicates;
mod reserve;
mod run;
mod seeds;
mod spend;
mod standards;
mod standing;
#[cfg(test)]
mod testing;
mod top;
mod verify;

pub use replicates::placeable_seeds;
pub use run::search;
pub use spend::{KEPT_ROUNDS, PRICE_MARGIN, SpendPlan, spend_plan};
