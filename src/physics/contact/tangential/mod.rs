//! Tangential springs ([`super::sub_model::TangentialModel`]), one file each.

mod linear;
mod mindlin;

pub use linear::LinearTangential;
pub use mindlin::MindlinTangential;
