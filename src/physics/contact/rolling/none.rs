//! No rolling resistance.

use super::super::sub_model::RollingModel;

/// No moment against the spin, whatever the material's rolling friction.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NoRolling;

impl RollingModel for NoRolling {
    fn coefficient(&self, _: f64) -> f64 {
        0.0
    }
}
