//! The linear spring of the Cundall-Strack spring-dashpot.

use serde::{Deserialize, Serialize};

use crate::physics::key_spec::SceneKeys;
use crate::physics::number::exact;

use super::super::law::PairProperties;
use super::super::sub_model::{NormalModel, Problems, Stiffness};

/// `F_ne = k_n δ`. Parameters: `[contact.linear]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct LinearNormal {
    /// Normal stiffness (N/m); `None`: the Hertz secant stiffness at an overlap of 1 % of R*.
    #[key(unit: "N/m", range: "> 0", plausible: Some((1e-3, 1e13)))]
    pub normal_stiffness: Option<f64>,
    /// Tangential stiffness as a fraction of the normal stiffness.
    #[key(range: ">= 0")]
    pub tangential_stiffness_ratio: f64,
}

impl Default for LinearNormal {
    fn default() -> Self {
        Self { normal_stiffness: None, tangential_stiffness_ratio: 2.0 / 7.0 }
    }
}

/// The stiffness `k` (N/m) if given, else the Hertz secant stiffness at an overlap of 1 % of R*:
/// `4/3 E* √R* δ^{1/2}` at `δ = 0.01 R*`.
#[inline(always)]
pub(super) fn stiffness_or_hertz_secant(k: Option<f64>, p: &PairProperties) -> f64 {
    k.unwrap_or((4.0 / 3.0) * p.e_star * p.r_star * 0.1)
}

/// Problems of a stiffness (N/m, optional, > 0), under its key.
pub(super) fn stiffness_problems((key, stiffness): (&'static str, Option<f64>)) -> Problems {
    match stiffness {
        Some(k) if !(k.is_finite() && k > 0.0) => {
            vec![(key, format!("must be a finite number > 0 (N/m), got {}", exact(k)))]
        }
        _ => Vec::new(),
    }
}

/// Problems of a ratio (≥ 0), under its key.
pub(super) fn ratio_problems((key, ratio): (&'static str, f64)) -> Problems {
    if ratio.is_finite() && ratio >= 0.0 {
        Vec::new()
    } else {
        vec![(key, format!("must be a finite number ≥ 0, got {}", exact(ratio)))]
    }
}

impl NormalModel for LinearNormal {
    type State = ();

    #[inline(always)]
    fn load(&self, p: &PairProperties, overlap: f64, _: &mut ()) -> (f64, Stiffness) {
        let k = stiffness_or_hertz_secant(self.normal_stiffness, p);
        (k * overlap, Stiffness::whole(k))
    }

    #[inline]
    fn elastic_energy(&self, p: &PairProperties, overlap: f64, _: &()) -> f64 {
        0.5 * stiffness_or_hertz_secant(self.normal_stiffness, p) * overlap * overlap
    }

    fn tangential_stiffness_ratio(&self) -> f64 {
        self.tangential_stiffness_ratio
    }

    fn problems(&self) -> Problems {
        let mut problems = stiffness_problems(("normal_stiffness", self.normal_stiffness));
        problems.extend(ratio_problems(("tangential_stiffness_ratio", self.tangential_stiffness_ratio)));
        problems
    }
}
