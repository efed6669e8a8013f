//! The hysteretic linear spring (Walton & Braun 1986): a plastic contact whose restitution comes
//! from unloading along a stiffer spring than it was loaded on.

use serde::{Deserialize, Serialize};

use crate::physics::key_spec::SceneKeys;
use crate::physics::number::exact;

use super::super::law::{ContactState, PairProperties};
use super::super::sub_model::{NormalModel, Problems, Stiffness};
use super::linear::{ratio_problems, stiffness_or_hertz_secant, stiffness_problems};

/// Loading along `F = k₁ δ`, unloading and reloading along `F = k₂ (δ − δ₀)` with
/// `δ₀ = δ_max (1 − k₁/k₂)` and `δ_max` the largest overlap so far (the contact's own state):
/// `F = max(0, min(k₁ δ, k₂ (δ − δ₀)))`. A head-on impact without dashpot rebounds with
/// restitution `√(k₁/k₂)` after `π/2 (√(m*/k₁) + √(m*/k₂))`. Damping and tangential models scale
/// with k₁. Parameters: `[contact.hysteretic_linear]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct HystereticNormal {
    /// Loading stiffness k₁ (N/m); `None`: the Hertz secant stiffness at an overlap of 1 % of R*.
    #[key(unit: "N/m", range: "> 0", plausible: Some((1e-3, 1e13)))]
    pub loading_stiffness: Option<f64>,
    /// Unloading stiffness over loading stiffness, `k₂/k₁ ≥ 1` (1: elastic).
    #[key(range: ">= 1")]
    pub unloading_stiffness_ratio: f64,
    /// Tangential stiffness as a fraction of the loading stiffness.
    #[key(range: ">= 0")]
    pub tangential_stiffness_ratio: f64,
}

impl Default for HystereticNormal {
    fn default() -> Self {
        Self { loading_stiffness: None, unloading_stiffness_ratio: 4.0, tangential_stiffness_ratio: 2.0 / 7.0 }
    }
}

/// The contact's largest overlap so far, δ_max (m).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LargestOverlap(pub f64);

impl ContactState for LargestOverlap {
    fn to_number(self) -> f64 {
        self.0
    }
    fn from_number(value: f64) -> Self {
        Self(value)
    }
}

impl HystereticNormal {
    /// The unloading branch's elastic force at `overlap` with `δ_max` = `largest` (N, may be < 0).
    #[inline]
    fn unloading_force(&self, k1: f64, overlap: f64, largest: f64) -> f64 {
        let k2 = k1 * self.unloading_stiffness_ratio;
        k2 * (overlap - largest) + k1 * largest
    }
}

impl NormalModel for HystereticNormal {
    type State = LargestOverlap;

    #[inline(always)]
    fn load(&self, p: &PairProperties, overlap: f64, state: &mut LargestOverlap) -> (f64, Stiffness) {
        let k1 = stiffness_or_hertz_secant(self.loading_stiffness, p);
        state.0 = state.0.max(overlap);
        // With δ ≤ δ_max the unloading line lies below the loading line: one expression for both.
        (self.unloading_force(k1, overlap, state.0).max(0.0), Stiffness::whole(k1))
    }

    #[inline]
    fn elastic_energy(&self, p: &PairProperties, overlap: f64, state: &LargestOverlap) -> f64 {
        let k1 = stiffness_or_hertz_secant(self.loading_stiffness, p);
        let force = self.unloading_force(k1, overlap, state.0.max(overlap)).max(0.0);
        0.5 * force * force / (k1 * self.unloading_stiffness_ratio)
    }

    fn tangential_stiffness_ratio(&self) -> f64 {
        self.tangential_stiffness_ratio
    }

    fn problems(&self) -> Problems {
        let mut problems = stiffness_problems(("loading_stiffness", self.loading_stiffness));
        problems.extend(ratio_problems(("tangential_stiffness_ratio", self.tangential_stiffness_ratio)));
        let ratio = self.unloading_stiffness_ratio;
        if !(ratio.is_finite() && ratio >= 1.0) {
            problems.push((
                "unloading_stiffness_ratio",
                format!("must be a finite number ≥ 1 (k₂/k₁), got {}", exact(ratio)),
            ));
        }
        problems
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pair() -> PairProperties {
        PairProperties { e_star: 1e9, g_star: 4e8, r_star: 0.01, m_star: 0.1, beta: 0.0 }
    }

    #[test]
    fn unloading_follows_the_stiffer_line_and_reloading_retraces_it() {
        let spring = HystereticNormal { loading_stiffness: Some(100.0), ..Default::default() };
        let mut state = LargestOverlap::default();
        let force = |d: f64, s: &mut LargestOverlap| spring.load(&pair(), d, s).0;
        assert_eq!(force(0.01, &mut state), 1.0);
        // Back to δ₀ = δ_max (1 − 1/4) = 7.5 mm the force is gone; halfway it is k₂ (δ − δ₀).
        assert!(force(0.0075, &mut state).abs() < 1e-12);
        assert!((force(0.00875, &mut state) - 400.0 * 0.00125).abs() < 1e-12);
        // Reloading retraces the unloading line up to δ_max, then loads along k₁ again.
        assert!((force(0.01, &mut state) - 1.0).abs() < 1e-12);
        assert!((force(0.02, &mut state) - 2.0).abs() < 1e-12);
        assert_eq!(state, LargestOverlap(0.02));
    }
}
