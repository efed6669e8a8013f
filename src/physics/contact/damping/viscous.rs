//! Viscous damping at a fraction β of critical.

use super::super::law::PairProperties;
use super::super::sub_model::{DampingModel, Stiffness};
use super::beta::scaled_by_beta;

/// `c = 2 β √(S m*)` for a spring of stiffness `S`: β is the damping ratio, so that EDEM's
/// restitution-β relation is exact for a linear spring.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ViscousDamping;

impl DampingModel for ViscousDamping {
    #[inline(always)]
    fn coefficient(&self, p: &PairProperties, spring: Stiffness) -> f64 {
        scaled_by_beta(2.0, p, spring)
    }
}
