//! The paper's Hertz spring (eqs 6, 8).

use serde::{Deserialize, Serialize};

use crate::physics::key_spec::SceneKeys;

use super::super::law::PairProperties;
use super::super::sub_model::{NormalModel, Problems, Stiffness};
use super::linear::ratio_problems;

/// Hertz force `F_ne = 4/3 E* √R* δ^{3/2}` (eq 6) with stiffness `S_n = 2 E* √(R* δ)` (eq 8), from
/// the materials' constants. Parameters: `[contact.hertz]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct HertzNormal {
    /// Tangential stiffness as a fraction of `S_n`, for `contact.tangential = "linear"`.
    #[key(range: ">= 0")]
    pub tangential_stiffness_ratio: f64,
}

impl Default for HertzNormal {
    fn default() -> Self {
        Self { tangential_stiffness_ratio: 2.0 / 7.0 }
    }
}

impl NormalModel for HertzNormal {
    type State = ();

    #[inline(always)]
    fn load(&self, p: &PairProperties, overlap: f64, _: &mut ()) -> (f64, Stiffness) {
        let stiffness = Stiffness { scale: 2.0 * p.e_star, grade: contact_radius(p, overlap) };
        ((2.0 / 3.0) * stiffness.value() * overlap, stiffness)
    }

    #[inline]
    fn elastic_energy(&self, p: &PairProperties, overlap: f64, _: &()) -> f64 {
        (8.0 / 15.0) * p.e_star * p.r_star.sqrt() * overlap * overlap * overlap.sqrt()
    }

    fn tangential_stiffness_ratio(&self) -> f64 {
        self.tangential_stiffness_ratio
    }

    fn hertzian(&self) -> bool {
        true
    }

    fn problems(&self) -> Problems {
        ratio_problems(("tangential_stiffness_ratio", self.tangential_stiffness_ratio))
    }
}

/// The Hertz contact radius `a = √(R* δ)` (m), which the normal and the Mindlin stiffness grow with.
#[inline(always)]
pub(in crate::physics::contact) fn contact_radius(p: &PairProperties, overlap: f64) -> f64 {
    (p.r_star * overlap).sqrt()
}
