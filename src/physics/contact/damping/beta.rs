//! What the dampings scaled by the material's β share.

use super::super::law::PairProperties;
use super::super::sub_model::Stiffness;

/// `prefactor · β · √(S m*)` for a spring of stiffness `S`, computed as
/// `prefactor β √(grade m*) √scale`: one square root per contact, the class constant's a loop
/// invariant.
#[inline(always)]
pub(super) fn scaled_by_beta(prefactor: f64, p: &PairProperties, spring: Stiffness) -> f64 {
    prefactor * p.beta * (spring.grade * p.m_star).sqrt() * spring.scale.sqrt()
}
