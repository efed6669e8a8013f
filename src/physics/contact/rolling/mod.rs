//! Rolling resistances ([`super::sub_model::RollingModel`]), one file each.

mod constant_torque;
mod none;

pub use constant_torque::ConstantTorque;
pub use none::NoRolling;
