//! The paper's Hertz-Mindlin law (eqs 6-12) with the spec's fixes.

use serde::{Deserialize, Serialize};

use crate::physics::key_spec::scene_section;

use super::{Coefficients, ContactLaw, PairProperties};

/// `2·√(5/6)`: the paper's damping prefactor (eqs 7 and 12).
const DAMPING_PREFACTOR: f64 = 1.825_741_858_350_553_8;

scene_section! {
/// Hertz normal force `F_ne = 4/3 E* √R* δ^{3/2}` (eq 6), normal stiffness `S_n = 2 E* √(R* δ)` (eq 8),
/// Mindlin tangential stiffness `S_t = 8 G* √(R* δ)` (eq 11, **fix**: the normal overlap under the
/// root, not the tangential one), damping `2√(5/6) β √(S m*)` (eqs 7, 12). Its constants are
/// the materials' (no parameters of its own: `[contact.hertz_mindlin]` is empty).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HertzMindlin {}
}

impl ContactLaw for HertzMindlin {
    type State = ();

    #[inline]
    fn coefficients(&self, p: &PairProperties, overlap: f64, _: &mut ()) -> Coefficients {
        let root = (p.r_star * overlap).sqrt();
        let normal_stiffness = 2.0 * p.e_star * root;
        // √(S m*) = √(2E* or 8G*) · √(√(R*δ) m*): one square root per contact, the material
        // constants' roots are loop invariants.
        let damping = DAMPING_PREFACTOR * p.beta * (root * p.m_star).sqrt();
        Coefficients {
            normal_force: (2.0 / 3.0) * normal_stiffness * overlap,
            normal_damping: damping * (2.0 * p.e_star).sqrt(),
            tangential_stiffness: 8.0 * p.g_star * root,
            tangential_damping: damping * (8.0 * p.g_star).sqrt(),
        }
    }

    #[inline]
    fn normal_elastic_energy(&self, p: &PairProperties, overlap: f64, _: &()) -> f64 {
        (8.0 / 15.0) * p.e_star * p.r_star.sqrt() * overlap * overlap * overlap.sqrt()
    }

    fn name(&self) -> &'static str {
        "hertz_mindlin"
    }
}
