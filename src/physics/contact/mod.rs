//! Contact force laws, composed of sub-models.
//!
//! A law ([`ContactLaw`], in `law`) says how stiff and how damped a contact is at a given overlap
//! and how much elastic energy it stores; `law`'s shared machinery turns that into forces. Each
//! law is a [`Composed`] of a normal spring ([`normal`]), a damping ([`damping`]) and a tangential
//! spring ([`tangential`]); rolling resistance ([`rolling`]) acts beside it. The table of [`table`]
//! declares every model and the presets `contact.law` names (`registry` makes their implementations).

mod composed;
pub mod damping;
mod impact;
mod law;
pub mod normal;
mod registry;
pub mod rolling;
mod sub_model;
pub mod table;
pub mod tangential;

pub use composed::Composed;
pub use impact::{ImpactEstimate, estimate_impact};
pub use law::{
    Coefficients, ContactForce, ContactLaw, ContactOptions, ContactState, Kinematics, PairProperties, elastic_energy,
    resolve,
};
pub use sub_model::{DampingModel, NormalModel, Problems, RollingModel, Stiffness, TangentialModel};
pub use table::{
    AnyDamping, AnyLaw, AnyNormal, AnyRolling, AnyState, AnyTangential, Composition, ContactConfig, ContactLawKind,
    DampingKind, HertzMindlin, HystereticLinear, LawVisitor, LinearSpringDashpot, NoParameters, NormalKind,
    RegisteredLaw, RollingKind, SubModel, TangentialKind,
};

#[cfg(test)]
mod tests;
