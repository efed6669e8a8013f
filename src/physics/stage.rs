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

use super::config::SceneConfig;
use super::key_spec::SceneKeys;
use super::number::exact;
use super::scheme::IntegratorKind;

/// One stage of a deposition protocol: its name, when it ends, and the keys it changes (those not
/// given keep the scene's values).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, SceneKeys)]
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

/// The conditions that end a stage, checked at every sample (a `time` ends it on that very step).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, SceneKeys)]
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

/// Numerical damping keys a stage may change (see the scene's `[damping]`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, SceneKeys)]
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

/// Contact keys a stage may change: β or the restitution it comes from (one replaces the other),
/// and the sliding friction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, SceneKeys)]
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

/// Integrator keys a stage may change. A step given in any of the three forms replaces the scene's
/// step; the stage's step is resolved before the run, from the same disks as the scene's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, SceneKeys)]
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

/// A scene key a stage may change: its dotted path (as in `[scene]`), whether a stage gives it, and
/// how the stage's value goes into the scene. Each is one [`stage_key!`] entry of [`STAGE_KEYS`].
pub(super) struct StageKey {
    /// Dotted path, e.g. `damping.local`.
    pub path: &'static str,
    given: fn(&StageConfig) -> bool,
    merge: fn(&StageConfig, &mut SceneConfig),
}

/// The entry of `section.key`: given when the stage's `section.key` is, it then replaces the scene's
/// (a value or an optional value alike). Keys after `with` form a group with it (β and the
/// restitution it comes from; the step's three forms): the stage's group replaces the scene's
/// whole, so the one given clears the others.
macro_rules! stage_key {
    ($section:ident . $key:ident $(with $($other:ident),+)?) => {
        StageKey {
            path: concat!(stringify!($section), ".", stringify!($key)),
            given: |stage| stage.$section.$key.is_some(),
            merge: |stage, scene| {
                if let Some(value) = stage.$section.$key {
                    scene.$section.$key = value.into();
                }
                $($(scene.$section.$other = stage.$section.$other;)+)?
            },
        }
    };
}

/// Every key a stage may change, in the order `keys` lists them; its value's range is the scene's
/// key's, checked on the scene as the stage runs it ([`SceneConfig::in_stage`]).
pub(super) const STAGE_KEYS: &[StageKey] = &[
    stage_key!(damping.local),
    stage_key!(damping.local_gravity),
    stage_key!(damping.viscous),
    stage_key!(material.beta with restitution),
    stage_key!(material.restitution with beta),
    stage_key!(material.friction),
    stage_key!(wall_material.beta with restitution),
    stage_key!(wall_material.restitution with beta),
    stage_key!(wall_material.friction),
    stage_key!(integrator.scheme),
    stage_key!(integrator.time_step with contact_time_fraction, rayleigh_fraction),
    stage_key!(integrator.contact_time_fraction with time_step, rayleigh_fraction),
    stage_key!(integrator.rayleigh_fraction with time_step, contact_time_fraction),
];

impl StageConfig {
    /// The scene keys this stage sets (dotted, as in `[scene]`).
    pub(super) fn keys(&self) -> Vec<&'static str> {
        STAGE_KEYS.iter().filter(|k| (k.given)(self)).map(|k| k.path).collect()
    }

    /// Puts the keys this stage sets into `scene`.
    pub(super) fn merge_into(&self, scene: &mut SceneConfig) {
        for key in STAGE_KEYS.iter().filter(|k| (k.given)(self)) {
            (key.merge)(self, scene);
        }
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

    /// The keys of a stage's sections that change the scene (all but `name` and `until`), dotted.
    fn declared_keys() -> Vec<String> {
        let sections = StageConfig::KEYS.iter().filter(|f| f.name != "until");
        let sections = sections.filter_map(|f| Some((f.name, f.spec.table?)));
        sections.flat_map(|(section, table)| table.iter().map(move |k| format!("{section}.{}", k.name))).collect()
    }

    /// Every leaf of a JSON tree (arrays whole) with its dotted path.
    fn leaves(value: &serde_json::Value, path: &str, out: &mut Vec<(String, serde_json::Value)>) {
        match value {
            serde_json::Value::Object(fields) => {
                for (name, field) in fields {
                    let inner = if path.is_empty() { name.clone() } else { format!("{path}.{name}") };
                    leaves(field, &inner, out);
                }
            }
            leaf => out.push((path.to_string(), leaf.clone())),
        }
    }

    /// The dotted keys whose values differ between two scenes, with the value in `b`.
    fn changed(a: &SceneConfig, b: &SceneConfig) -> Vec<(String, serde_json::Value)> {
        let (mut old, mut new) = (Vec::new(), Vec::new());
        leaves(&serde_json::to_value(a).unwrap(), "", &mut old);
        leaves(&serde_json::to_value(b).unwrap(), "", &mut new);
        old.into_iter().zip(new).filter(|(o, n)| o != n).map(|(_, n)| n).collect()
    }

    #[test]
    fn every_key_a_stage_declares_is_merged_and_range_checked_as_the_scenes() {
        let listed: Vec<&str> = STAGE_KEYS.iter().map(|k| k.path).collect();
        assert_eq!(listed, declared_keys(), "each key of a stage's sections is one STAGE_KEYS entry");
        let keys = crate::physics::keys::scene_keys();
        let find = |path: &str| keys.iter().find(|k| k.path == path).unwrap_or_else(|| panic!("{path}"));
        let scene = SceneConfig::default();
        for key in STAGE_KEYS {
            let (own, scenes) = (find(&format!("stages.{}", key.path)), find(key.path));
            assert_eq!((own.unit, &own.range), (scenes.unit, &scenes.range), "{}: the scene key's range", key.path);
            // A value inside every numeric range and unlike the scene's default; -1 lies outside them.
            let (value, bad) = match own.range.strip_prefix("one of ") {
                Some(words) => (format!("{:?}", words.rsplit(", ").next().unwrap()), None),
                None if own.range == "true or false" => ("false".to_string(), None),
                None => ("0.25".to_string(), Some("-1")),
            };
            let given = |value: &str| stage(&format!("name = \"s\"\nuntil.time = 0.1\n{} = {value}\n", key.path));
            let staged = given(&value);
            assert_eq!(staged.keys(), [key.path]);
            let expected =
                serde_json::to_value(toml::from_str::<toml::Value>(&format!("v = {value}")).unwrap()["v"].clone());
            assert_eq!(changed(&scene, &scene.in_stage(&staged)), [(key.path.to_string(), expected.unwrap())]);
            if let Some(bad) = bad {
                let refused = SceneConfig { stages: vec![given(bad)], ..Default::default() };
                let issues = refused.validate().unwrap_err();
                assert!(issues.iter().any(|i| i.key == format!("stages.s.{}", key.path)), "{}: {issues:?}", key.path);
            }
        }
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
