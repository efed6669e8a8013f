//! What a scene is: every input of one simulation, with defaults, as plain serde data.
//!
//! A study file's base scene and each swept run deserialize into [`SceneConfig`]; unknown keys are
//! rejected by serde, impossible values by [`SceneConfig::validate`], which names the key path.
//! `sections` declares the keys, `defaults` their defaults, `validate` the checks and `stages` the
//! scene as each stage runs it.

mod defaults;
mod sections;
mod stages;
mod validate;

pub use super::contact::{ContactConfig, ContactLawKind};
pub use super::scheme::IntegratorKind;
pub use super::size_distribution::SizeDistribution;
pub use super::stage::{StageConfig, StageEnd};
pub use sections::{
    BroadPhaseKind, DEFAULT_TIME_STEP, DampingConfig, DomainConfig, IntegratorConfig, LimitsConfig, MaterialConfig,
    NeighborConfig, ParticlesConfig, PlacementConfig, PlacementKind, PourConfig, RunConfig, SceneConfig, SettleConfig,
    WallMaterialConfig,
};
pub use validate::ConfigIssue;
