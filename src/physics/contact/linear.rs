//! Linear spring-dashpot (Cundall-Strack) law: constant stiffness, viscous damping.

use serde::{Deserialize, Serialize};

use crate::physics::key_spec::scene_section;
use crate::physics::number::exact;

use super::{Coefficients, ContactLaw, PairProperties};

scene_section! {
/// `F_ne = k_n δ`, damping `2 β √(k m*)` (β is the damping ratio, so EDEM's e-β relation is exact
/// here), tangential stiffness `k_t = ratio · k_n`. Parameters: `[contact.linear]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LinearSpringDashpot {
    /// Normal stiffness (N/m); `None`: the Hertz secant stiffness at an overlap of 1 % of R*.
    #[key(unit: "N/m", range: "> 0", plausible: Some((1e-3, 1e13)))]
    pub normal_stiffness: Option<f64>,
    /// Tangential stiffness as a fraction of the normal stiffness.
    #[key(range: ">= 0")]
    pub tangential_stiffness_ratio: f64,
}
}

impl Default for LinearSpringDashpot {
    fn default() -> Self {
        Self { normal_stiffness: None, tangential_stiffness_ratio: 2.0 / 7.0 }
    }
}

/// The stiffness `k` (N/m) if given, else the Hertz secant stiffness at an overlap of 1 % of R*:
/// `4/3 E* √R* δ^{1/2}` at `δ = 0.01 R*`.
#[inline]
pub(super) fn stiffness_or_hertz_secant(k: Option<f64>, p: &PairProperties) -> f64 {
    k.unwrap_or((4.0 / 3.0) * p.e_star * p.r_star * 0.1)
}

/// Problems of a stiffness (N/m, optional, > 0) and a ratio (≥ 0), under their keys.
pub(super) fn stiffness_problems(
    stiffness: (&'static str, Option<f64>),
    ratio: (&'static str, f64),
) -> Vec<(&'static str, String)> {
    let mut problems = Vec::new();
    if let (key, Some(k)) = stiffness
        && !(k.is_finite() && k > 0.0)
    {
        problems.push((key, format!("must be a finite number > 0 (N/m), got {}", exact(k))));
    }
    if !(ratio.1.is_finite() && ratio.1 >= 0.0) {
        problems.push((ratio.0, format!("must be a finite number ≥ 0, got {}", exact(ratio.1))));
    }
    problems
}

impl ContactLaw for LinearSpringDashpot {
    type State = ();

    #[inline]
    fn coefficients(&self, p: &PairProperties, overlap: f64, _: &mut ()) -> Coefficients {
        let kn = stiffness_or_hertz_secant(self.normal_stiffness, p);
        let kt = self.tangential_stiffness_ratio * kn;
        Coefficients {
            normal_force: kn * overlap,
            normal_damping: 2.0 * p.beta * (kn * p.m_star).sqrt(),
            tangential_stiffness: kt,
            tangential_damping: 2.0 * p.beta * (kt * p.m_star).sqrt(),
        }
    }

    #[inline]
    fn normal_elastic_energy(&self, p: &PairProperties, overlap: f64, _: &()) -> f64 {
        0.5 * stiffness_or_hertz_secant(self.normal_stiffness, p) * overlap * overlap
    }

    fn name(&self) -> &'static str {
        "linear"
    }

    fn problems(&self) -> Vec<(&'static str, String)> {
        stiffness_problems(
            ("normal_stiffness", self.normal_stiffness),
            ("tangential_stiffness_ratio", self.tangential_stiffness_ratio),
        )
    }
}
