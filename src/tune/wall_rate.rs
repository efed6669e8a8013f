//! Wall time as the objective, priced so that it reproduces: a run costs its particle-steps times the
//! wall time per particle-step of its configuration (integrator, contact law, disk count and the
//! switches that change the work per step), measured on the first batch that ran the configuration
//! (the median over its runs) and held from then on. A run's own wall time follows the machine's load
//! of the moment; the particle-steps do not, and a rate measured once keeps settings of the same
//! configuration in the ratio of their particle-steps. Later batches measure the rate again: their
//! spread is stated with the answer.

use crate::physics::SceneConfig;

/// The configuration of a scene, as far as it sets the work per particle-step.
pub fn configuration(scene: &SceneConfig) -> String {
    let mut words = vec![
        format!("{:?}", scene.integrator.scheme),
        scene.contact.law_name(),
        format!("rolling {:?}", scene.contact.rolling),
        format!("{} disks", scene.particles.count),
    ];
    let switches = [
        (scene.material.friction == 0.0, "frictionless"),
        (scene.damping.local > 0.0, "local damping"),
        (scene.damping.viscous > 0.0, "viscous damping"),
        (!scene.stages.is_empty(), "stages"),
    ];
    words.extend(switches.iter().filter(|(on, _)| *on).map(|(_, word)| word.to_string()));
    words.join(", ")
}

/// The measured rate of one configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct WallRate {
    /// The configuration, in words.
    pub configuration: String,
    /// The rate runs are priced at: the first batch's median (s per particle-step).
    pub rate: f64,
    /// The smallest and largest batch median (s per particle-step).
    pub low: f64,
    /// See `low`.
    pub high: f64,
    /// Batches that measured it.
    pub batches: usize,
}

/// Every configuration's rate, in the order first measured.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WallRates(Vec<WallRate>);

impl WallRates {
    /// Records one batch's runs of `configuration` (wall time over particle-steps of each).
    pub fn record(&mut self, configuration: &str, per_run: &[f64]) {
        let mut rates: Vec<f64> = per_run.iter().copied().filter(|r| r.is_finite() && *r > 0.0).collect();
        if rates.is_empty() {
            return;
        }
        rates.sort_by(f64::total_cmp);
        let median = rates[rates.len() / 2];
        match self.0.iter_mut().find(|r| r.configuration == configuration) {
            Some(r) => {
                r.low = r.low.min(median);
                r.high = r.high.max(median);
                r.batches += 1;
            }
            None => self.0.push(WallRate {
                configuration: configuration.to_string(),
                rate: median,
                low: median,
                high: median,
                batches: 1,
            }),
        }
    }

    /// The rate runs of `configuration` are priced at (NaN before it is measured).
    pub fn rate(&self, configuration: &str) -> f64 {
        self.0.iter().find(|r| r.configuration == configuration).map_or(f64::NAN, |r| r.rate)
    }

    /// Every configuration's rate.
    pub fn all(&self) -> &[WallRate] {
        &self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_batch_sets_the_rate_and_later_ones_its_spread() {
        let mut rates = WallRates::default();
        rates.record("a", &[3e-8, 1e-8, 2e-8, f64::NAN]);
        rates.record("a", &[5e-8, 5e-8]);
        rates.record("b", &[]);
        assert_eq!(rates.rate("a"), 2e-8);
        assert!(rates.rate("b").is_nan());
        assert_eq!(
            rates.all(),
            &[WallRate { configuration: "a".into(), rate: 2e-8, low: 2e-8, high: 5e-8, batches: 2 }]
        );
    }

    #[test]
    fn the_configuration_names_what_changes_the_work_per_step() {
        let mut scene = SceneConfig::default();
        let plain = configuration(&scene);
        scene.integrator.time_step = Some(1e-6);
        scene.material.restitution = Some(0.1);
        assert_eq!(
            configuration(&scene),
            plain,
            "the time step and the damping ratio change the steps, not their work"
        );
        scene.damping.local = 0.2;
        assert_ne!(configuration(&scene), plain);
    }
}
