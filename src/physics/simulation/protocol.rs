//! A run's stages (see [`crate::physics::stage`]): the settings each stage runs with, resolved
//! before the first step, when a stage is over, and the switch to the next.

use crate::physics::config::{DampingConfig, IntegratorKind, SceneConfig, StageEnd};
use crate::physics::contact::ContactLaw;
use crate::physics::diagnostics::Sample;
use crate::physics::material::Materials;
use crate::physics::particles::InitialDisk;
use crate::physics::record::StageEndTime;
use crate::physics::time_step::{self, with_time_step};
use crate::physics::warning::ValidityWarning;

/// What one stage runs with.
pub(super) struct StageSettings {
    /// The stage's name; `None` for the scene's own, physical stage.
    pub(super) name: Option<String>,
    /// When it ends; `None` for the physical stage, which ends at settle.
    pub(super) until: Option<StageEnd>,
    pub(super) dt: f64,
    pub(super) time_step_warning: Option<ValidityWarning>,
    pub(super) damping: DampingConfig,
    pub(super) scheme: IntegratorKind,
    pub(super) materials: Materials,
}

impl StageSettings {
    /// The settings of `scene` (a stage's scene or the physical one) with `law`, its time step
    /// resolved from the run's initial `disks`.
    fn of<L: ContactLaw>(scene: &SceneConfig, law: &L, disks: &[InitialDisk]) -> Self {
        let resolved = time_step::resolve(law, scene, Some(disks));
        Self {
            name: None,
            until: None,
            dt: resolved.dt,
            time_step_warning: resolved.warning,
            damping: scene.damping,
            scheme: scene.integrator.scheme,
            materials: Materials::from_scene(&with_time_step(scene, resolved.dt)),
        }
    }
}

/// The stages of a run and where it is in them.
pub(super) struct Protocol {
    /// Every stage in order, the physical one last.
    pub(super) stages: Vec<StageSettings>,
    /// The stage running now.
    pub(super) current: usize,
    /// The step the current stage began at.
    pub(super) began: u64,
    /// The step and time (s) the current time step began at: the run's clock, and with it the
    /// sampling grid, counts from there, through switches that keep the step.
    pub(super) clock: (u64, f64),
    /// The step at which the current stage's `until.time` ends it (`u64::MAX`: none).
    pub(super) time_limit: u64,
    /// When each finished stage ended (s).
    pub(super) ended: Vec<f64>,
}

impl Protocol {
    /// The stages of `scene` (its `stages`, then itself) with `law`, from the initial `disks`.
    pub(super) fn new<L: ContactLaw>(scene: &SceneConfig, law: &L, disks: &[InitialDisk]) -> Self {
        let mut stages: Vec<StageSettings> = scene
            .stages
            .iter()
            .map(|stage| StageSettings {
                name: Some(stage.name.clone()),
                until: Some(stage.until.clone()),
                ..StageSettings::of(&scene.in_stage(stage), law, disks)
            })
            .collect();
        stages.push(StageSettings::of(scene, law, disks));
        let mut protocol =
            Self { stages, current: 0, began: 0, clock: (0, 0.0), time_limit: u64::MAX, ended: Vec::new() };
        protocol.time_limit = protocol.limit_of_current();
        protocol
    }

    /// The settings running now.
    pub(super) fn now(&self) -> &StageSettings {
        &self.stages[self.current]
    }

    /// The physical stage's settings.
    pub(super) fn physical(&self) -> &StageSettings {
        self.stages.last().expect("a protocol ends with the physical stage")
    }

    /// Whether the physical stage is running.
    pub(super) fn in_physical_stage(&self) -> bool {
        self.current + 1 == self.stages.len()
    }

    /// Ends the current stage at `step` and time `time` (s) and begins the next.
    pub(super) fn begin_next(&mut self, step: u64, time: f64) {
        self.ended.push(time);
        let dt = self.now().dt;
        self.current += 1;
        self.began = step;
        if self.now().dt != dt {
            self.clock = (step, time);
        }
        self.time_limit = self.limit_of_current();
    }

    fn limit_of_current(&self) -> u64 {
        let stage = self.now();
        match stage.until.as_ref().and_then(|u| u.time) {
            Some(t) => self.began.saturating_add((t / stage.dt).round().max(1.0) as u64),
            None => u64::MAX,
        }
    }

    /// Whether the current stage is over at `step` with sample `s` (`in_contact`: whether every
    /// disk touches something).
    pub(super) fn stage_over(&self, step: u64, s: &Sample, disks: usize, in_contact: impl FnOnce() -> bool) -> bool {
        let Some(until) = &self.now().until else { return false };
        step >= self.time_limit
            || until.unbalanced_force_ratio.is_some_and(|limit| s.unbalanced_force_ratio < limit)
            || until.kinetic_energy_per_disk.is_some_and(|limit| s.kinetic() / (disks as f64) < limit)
            || (until.all_in_contact && in_contact())
    }

    /// When each stage before the physical one ended (`None`: the run ended first).
    pub(super) fn end_times(&self) -> Vec<StageEndTime> {
        let before = &self.stages[..self.stages.len() - 1];
        before
            .iter()
            .enumerate()
            .map(|(k, stage)| StageEndTime {
                name: stage.name.clone().unwrap_or_default(),
                time: self.ended.get(k).copied(),
            })
            .collect()
    }
}

crate::physics::run_state::persist_fields!(Protocol { current, began, clock, time_limit, ended });
