//! The step loop: forces, integration, sampling, monitoring and stopping.
//!
//! One step: the integrator advances the state with the forces of the current state, the neighbour
//! list is refreshed if some disk moved far enough, forces are evaluated at the new state (with
//! contact sums only on sampled steps), and the integrator finishes the step. Diagnostics,
//! divergence checks and the settle criterion run on sampled steps only.

mod protocol;
mod readout;
mod resume;
mod run_loop;
mod setup;
mod step;
mod switch;
#[cfg(test)]
mod tests;

pub use run_loop::Resumed;
pub use step::{Control, Progress, Simulation};
