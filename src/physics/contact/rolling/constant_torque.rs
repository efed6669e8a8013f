//! EDEM's rolling resistance (spec).

use super::super::sub_model::RollingModel;

/// A constant directional torque `μ0 F_n R` with the material's rolling friction μ0.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ConstantTorque;

impl RollingModel for ConstantTorque {
    fn coefficient(&self, rolling_friction: f64) -> f64 {
        rolling_friction
    }
}
