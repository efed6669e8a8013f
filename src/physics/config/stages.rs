//! The scene as each stage runs it, and the stage keys its warnings name (`stages.NAME.KEY`).

use super::{DEFAULT_TIME_STEP, SceneConfig, StageConfig};
use crate::physics::number::exact;
use crate::physics::warning::WarningKind;

impl SceneConfig {
    /// The key whose value a validity warning of `kind` is about, dotted as in `[scene]`, and its
    /// value: the time step in the form it is given for the rules of the step and the energy
    /// balance, the Young's modulus for overlaps. For stage `stage` (an index of `stages`), the
    /// stage's key (`stages.NAME.KEY`) where the stage sets it.
    pub fn key_at_fault(&self, kind: WarningKind, stage: Option<usize>) -> (String, f64) {
        let stage = stage.map(|k| &self.stages[k]);
        let i = stage.map_or(self.integrator.clone(), |s| self.in_stage(s).integrator);
        let (key, value) = match (kind, i.contact_time_fraction, i.rayleigh_fraction) {
            (WarningKind::ImpactOverlap | WarningKind::StaticOverlap | WarningKind::Overlap, _, _) => {
                ("material.youngs_modulus", self.material.youngs_modulus)
            }
            (_, Some(fraction), _) => ("integrator.contact_time_fraction", fraction),
            (_, None, Some(fraction)) => ("integrator.rayleigh_fraction", fraction),
            _ => ("integrator.time_step", i.time_step.unwrap_or(DEFAULT_TIME_STEP)),
        };
        match stage {
            Some(s) if s.keys().contains(&key) => (format!("stages.{}.{key}", s.name), value),
            _ => (key.to_string(), value),
        }
    }

    /// The scene as `stage` runs it: this scene with the stage's keys in place (and no stages).
    pub fn in_stage(&self, stage: &StageConfig) -> SceneConfig {
        let mut s = SceneConfig { stages: Vec::new(), ..self.clone() };
        stage.merge_into(&mut s);
        s
    }

    /// The stage whose end makes the stages that can end only by time (`until.time` alone) take the
    /// whole `run.duration`, as (its `until.time` key, why): the physics after them never starts, so
    /// no run of the scene can settle. None when the physics starts (or may start) within the run.
    pub fn stages_past_the_run(&self) -> Option<(String, String)> {
        let mut least = 0.0;
        for stage in &self.stages {
            let u = &stage.until;
            let only_time =
                u.unbalanced_force_ratio.is_none() && u.kinetic_energy_per_disk.is_none() && !u.all_in_contact;
            least += u.time.filter(|_| only_time).unwrap_or(0.0);
            if least >= self.run.duration {
                let reason = format!(
                    "the stages up to {:?} last {} s, run.duration = {} s: the physics after the stages never \
                     starts, so no run can settle (shorten the stages or lengthen run.duration)",
                    stage.name,
                    exact(least),
                    exact(self.run.duration)
                );
                return Some((format!("stages.{}.until.time", stage.name), reason));
            }
        }
        None
    }
}
