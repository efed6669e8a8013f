//! Dampings ([`super::sub_model::DampingModel`]), one file each; `beta` holds what the β-scaled
//! ones share.

mod beta;
mod paper;
mod viscoelastic;
mod viscous;

pub use paper::PaperDamping;
pub use viscoelastic::ViscoelasticDamping;
pub use viscous::ViscousDamping;
