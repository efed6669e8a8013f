//! Viscoelastic damping (Kuwabara & Kono 1987; Brilliantov et al. 1996): a dashpot proportional
//! to the spring's stiffness.

use serde::{Deserialize, Serialize};

use crate::physics::key_spec::SceneKeys;
use crate::physics::number::exact;

use super::super::law::PairProperties;
use super::super::sub_model::{DampingModel, Problems, Stiffness};

/// `c = A S` for a spring of stiffness `S`, with `A` the material's dissipation time (the
/// material's β and restitution are not used). With a Hertz spring the restitution falls with the
/// impact speed, as for viscoelastic spheres; with a linear spring `k` it is that of a damping ratio
/// `A √(k/m*) / 2`. Parameters: `[contact.viscoelastic]`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct ViscoelasticDamping {
    /// Dissipation time A (s): damping coefficient over stiffness.
    #[key(unit: "s", range: ">= 0")]
    pub dissipation_time: f64,
}

impl DampingModel for ViscoelasticDamping {
    #[inline(always)]
    fn coefficient(&self, _: &PairProperties, spring: Stiffness) -> f64 {
        self.dissipation_time * spring.value()
    }

    fn problems(&self) -> Problems {
        let a = self.dissipation_time;
        if a.is_finite() && a >= 0.0 {
            Vec::new()
        } else {
            vec![("dissipation_time", format!("must be a finite number ≥ 0 (s), got {}", exact(a)))]
        }
    }
}
