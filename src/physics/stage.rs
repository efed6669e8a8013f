//! Deposition protocols: stages a scene runs through before its own physics.
//!
//! A scene's `stages` (each `[[scene.stages]]` of a study file) run in order, each with a few keys
//! of the scene changed (numerical damping, restitution, sliding friction, the time step and the
//! integrator) until the first of its end conditions holds; then the scene itself runs as the last,
//! physical stage, which ends at settle as a scene without stages does. The state carries over
//! exactly at a switch: positions, velocities, spins, contact springs and law states; only the
//! changed keys change. A fall of friction (a compaction stage: the pile densifies under gravity
//! while its contacts slip easily) cuts each tangential spring back to the new Coulomb limit at the
//! switch, and the elastic energy it loses counts as dissipated, as sliding's does; a rise changes
//! no spring. Stiffness and gravity stay the scene's: changing them would change the stored elastic
//! or potential energy at a switch, which no work put there.

use serde::{Deserialize, Serialize};

use super::key_spec::scene_section;
use super::number::exact;
use super::scheme::IntegratorKind;

scene_section! {
/// One stage of a deposition protocol: its name, when it ends, and the keys it changes (those not
/// given keep the scene's values).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StageConfig {
    /// The stage's name, as sweeps (`"stages.NAME.damping.local"`), charts and results call it.
    #[key(range: "letters, digits, _ or -; unique")]
    pub name: String,
    /// When the stage ends: as soon as any of its conditions holds.
    #[key(table: Some(StageEnd::KEYS))]
    pub until: StageEnd,
    /// Numerical damping during the stage.
    #[key(table: Some(StageDamping::KEYS))]
    pub damping: StageDamping,
    /// Disk-disk damping and friction during the stage.
    #[key(table: Some(StageMaterial::KEYS))]
    pub material: StageMaterial,
    /// Disk-wall damping and friction during the stage (a wall friction the scene does not give
    /// follows the stage's disk friction, as it follows the scene's).
    #[key(table: Some(StageMaterial::KEYS))]
    pub wall_material: StageMaterial,
    /// Scheme and time step during the stage (a time step given here replaces the scene's).
    #[key(table: Some(StageIntegrator::KEYS))]
    pub integrator: StageIntegrator,
}
}

scene_section! {
/// The conditions that end a stage, checked at every sample (a `time` ends it on that very step).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StageEnd {
    /// Time spent in the stage (s).
    #[key(unit: "s", range: "> 0")]
    pub time: Option<f64>,
    /// The unbalanced force ratio falls below this.
    #[key(range: "> 0")]
    pub unbalanced_force_ratio: Option<f64>,
    /// The kinetic energy per disk, translational plus rotational, falls below this (J).
    #[key(unit: "J", range: "> 0")]
    pub kinetic_energy_per_disk: Option<f64>,
    /// Every disk touches a disk or a wall.
    #[key(range: "true or false")]
    pub all_in_contact: bool,
}
}

scene_section! {
/// Numerical damping keys a stage may change (see the scene's `[damping]`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StageDamping {
    /// Cundall local damping α in [0, 1).
    #[key(range: "[0, 1)")]
    pub local: Option<f64>,
    /// Whether gravity is part of the force local damping reduces.
    #[key(range: "true or false")]
    pub local_gravity: Option<bool>,
    /// Global viscous damping rate c (1/s).
    #[key(unit: "1/s", range: ">= 0")]
    pub viscous: Option<f64>,
}
}

scene_section! {
/// Contact keys a stage may change: β or the restitution it comes from (one replaces the other),
/// and the sliding friction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StageMaterial {
    /// The damping factor β (≥ 0).
    #[key(range: ">= 0")]
    pub beta: Option<f64>,
    /// Coefficient of restitution e in (0, 1].
    #[key(range: "(0, 1]")]
    pub restitution: Option<f64>,
    /// Sliding friction coefficient μ (≥ 0).
    #[key(range: ">= 0")]
    pub friction: Option<f64>,
}
}

scene_section! {
/// Integrator keys a stage may change. A step given in any of the three forms replaces the scene's
/// step; the stage's step is resolved before the run, from the same disks as the scene's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StageIntegrator {
    /// The scheme.
    #[key(one_of: &["adams_bashforth_moulton", "velocity_verlet"])]
    pub scheme: Option<IntegratorKind>,
    /// Time step Δt (s).
    #[key(unit: "s", range: "> 0")]
    pub time_step: Option<f64>,
    /// Δt as this fraction of the Hertz contact time of the scene's hardest impact.
    #[key(range: "(0, 1]")]
    pub contact_time_fraction: Option<f64>,
    /// Δt as this fraction of the Rayleigh time of the smallest disk.
    #[key(range: "(0, 1]")]
    pub rayleigh_fraction: Option<f64>,
}
}

impl StageConfig {
    /// The scene keys this stage sets (dotted, as in `[scene]`).
    pub(super) fn keys(&self) -> Vec<&'static str> {
        let d = &self.damping;
        let i = &self.integrator;
        let given = [
            ("damping.local", d.local.is_some()),
            ("damping.local_gravity", d.local_gravity.is_some()),
            ("damping.viscous", d.viscous.is_some()),
            ("material.beta", self.material.beta.is_some()),
            ("material.restitution", self.material.restitution.is_some()),
            ("material.friction", self.material.friction.is_some()),
            ("wall_material.beta", self.wall_material.beta.is_some()),
            ("wall_material.restitution", self.wall_material.restitution.is_some()),
            ("wall_material.friction", self.wall_material.friction.is_some()),
            ("integrator.scheme", i.scheme.is_some()),
            ("integrator.time_step", i.time_step.is_some()),
            ("integrator.contact_time_fraction", i.contact_time_fraction.is_some()),
            ("integrator.rayleigh_fraction", i.rayleigh_fraction.is_some()),
        ];
        given.into_iter().filter(|(_, set)| *set).map(|(key, _)| key).collect()
    }
}

impl StageMaterial {
    /// Whether the stage gives β or the restitution.
    pub(super) fn damping_given(&self) -> bool {
        self.beta.is_some() || self.restitution.is_some()
    }
}

impl StageEnd {
    /// Problems with the conditions, as (key within `until`, reason; an empty key: `until` itself).
    pub(super) fn problems(&self) -> Vec<(&'static str, String)> {
        let mut problems = Vec::new();
        let values = [
            ("time", self.time),
            ("unbalanced_force_ratio", self.unbalanced_force_ratio),
            ("kinetic_energy_per_disk", self.kinetic_energy_per_disk),
        ];
        for (key, value) in values {
            if let Some(v) = value.filter(|v| !(v.is_finite() && *v > 0.0)) {
                problems.push((key, format!("must be a finite number > 0, got {}", exact(v))));
            }
        }
        if values.iter().all(|(_, v)| v.is_none()) && !self.all_in_contact {
            let names = "time, unbalanced_force_ratio, kinetic_energy_per_disk or all_in_contact = true";
            problems.push(("", format!("a stage needs a condition that ends it: {names}")));
        }
        problems
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::config::SceneConfig;

    fn stage(text: &str) -> StageConfig {
        toml::from_str(text).expect("a stage")
    }

    #[test]
    fn a_stage_changes_only_its_keys_and_a_step_replaces_the_scenes() {
        let mut scene = SceneConfig::default();
        scene.integrator.time_step = Some(1e-6);
        scene.material.restitution = Some(0.5);
        let s = stage(
            "name = \"fill\"\nuntil.time = 0.1\ndamping.local = 0.4\nmaterial.beta = 0.2\nmaterial.friction = 0.1\n[integrator]\ncontact_time_fraction = 0.05\n",
        );
        let staged = scene.in_stage(&s);
        assert_eq!(staged.damping.local, 0.4);
        assert_eq!((staged.material.beta, staged.material.restitution), (Some(0.2), None));
        assert_eq!((staged.material.friction, staged.wall_material.friction), (0.1, None), "walls follow the disks");
        let walls = scene.in_stage(&stage("name = \"w\"\nuntil.time = 0.1\nwall_material.friction = 0.0\n"));
        assert_eq!((walls.material.friction, walls.wall_material.friction), (scene.material.friction, Some(0.0)));
        assert_eq!((staged.integrator.time_step, staged.integrator.contact_time_fraction), (None, Some(0.05)));
        let unchanged = SceneConfig {
            damping: scene.damping,
            material: scene.material.clone(),
            integrator: scene.integrator.clone(),
            ..staged
        };
        assert_eq!(unchanged, scene);
    }

    #[test]
    fn bad_stages_name_their_keys() {
        let scene = SceneConfig {
            stages: vec![
                stage("name = \"fill\"\nuntil.time = -1\ndamping.local = 1.5\n"),
                stage("name = \"fill\"\n"),
                stage("name = \"a b\"\nuntil.all_in_contact = true\nmaterial.restitution = 0.5\nmaterial.beta = 0.1\n"),
                stage("name = \"tiny\"\nuntil.time = 0.1\nintegrator.time_step = 5e-324\n"),
                stage("name = \"slip\"\nuntil.time = 0.1\nmaterial.friction = -0.1\nwall_material.friction = nan\n"),
            ],
            ..Default::default()
        };
        let keys: Vec<String> = scene.validate().unwrap_err().into_iter().map(|i| i.key).collect();
        assert_eq!(
            keys,
            [
                "stages.fill.until.time",
                "stages.fill.damping.local",
                "stages.fill.name",
                "stages.fill.until",
                "stages[2].name",
                "stages[2].material.restitution",
                "stages.tiny.integrator.time_step",
                "stages.slip.material.friction",
                "stages.slip.wall_material.friction",
            ]
        );
    }
}
