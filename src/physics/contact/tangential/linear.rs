//! The linear tangential spring of the Cundall-Strack spring-dashpot.

use super::super::law::PairProperties;
use super::super::sub_model::{NormalModel, Stiffness, TangentialModel};

/// `k_t = ratio · S` with `S` the normal spring's stiffness and the ratio from the normal
/// spring's table (`tangential_stiffness_ratio`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LinearTangential;

impl TangentialModel for LinearTangential {
    #[inline(always)]
    fn stiffness<N: NormalModel>(
        &self,
        normal: &N,
        _: &PairProperties,
        _: f64,
        normal_stiffness: Stiffness,
    ) -> Stiffness {
        Stiffness::whole(normal.tangential_stiffness_ratio() * normal_stiffness.value())
    }
}
