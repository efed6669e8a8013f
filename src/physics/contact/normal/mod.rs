//! Normal springs ([`super::sub_model::NormalModel`]), one file each.

mod hertz;
mod hysteretic;
mod linear;

pub use hertz::HertzNormal;
pub(super) use hertz::contact_radius;
pub use hysteretic::{HystereticNormal, LargestOverlap};
pub use linear::LinearNormal;
