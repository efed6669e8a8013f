//! Validity warnings as values: which rule of thumb a run (or its prediction) broke, the `limits.*`
//! key that sets it, the measured or predicted value, the limit and when. Text is made only where a
//! person reads it ([`std::fmt::Display`]); tune and the report compare values.

use std::fmt;

use serde::{Deserialize, Serialize};

use super::number::short;

/// Which validity rule a warning is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WarningKind {
    /// The damping-rate limit lowered the time step asked for: value = the step asked for (s),
    /// limit = the step that runs (s).
    TimeStepCapped,
    /// Predicted: time step over the contact time of the hardest impact.
    ContactTimeFraction,
    /// Predicted: time step over the contact time, against the integrator's measured stable step at the
    /// scene's damping ratio (see [`super::stability::stable_contact_time_fraction`]).
    IntegratorStability,
    /// Predicted: time step times the largest damping rate, against the integrator's stability limit.
    DampingRate,
    /// Predicted: largest overlap of the hardest impact, over the radius.
    ImpactOverlap,
    /// Predicted: overlap at the floor under the settled pile's weight, over the radius.
    StaticOverlap,
    /// Measured: largest overlap of the run, over the smaller radius of its pair.
    Overlap,
    /// Measured: largest error of the energy balance, over the energy available.
    EnergyBalance,
}

impl WarningKind {
    /// Every kind, in the order warnings are listed.
    pub const ALL: [WarningKind; 8] = [
        WarningKind::TimeStepCapped,
        WarningKind::ContactTimeFraction,
        WarningKind::IntegratorStability,
        WarningKind::DampingRate,
        WarningKind::ImpactOverlap,
        WarningKind::StaticOverlap,
        WarningKind::Overlap,
        WarningKind::EnergyBalance,
    ];

    /// The key that sets the limit: a `limits.*` key, or the scheme whose measured stable step it is.
    pub fn limit_key(self) -> &'static str {
        match self {
            WarningKind::IntegratorStability => "integrator.scheme",
            WarningKind::TimeStepCapped | WarningKind::DampingRate => "limits.damping_rate_fraction",
            WarningKind::ContactTimeFraction => "limits.contact_time_fraction",
            WarningKind::ImpactOverlap | WarningKind::StaticOverlap | WarningKind::Overlap => {
                "limits.overlap_warning_ratio"
            }
            WarningKind::EnergyBalance => "limits.energy_balance_tolerance",
        }
    }

    /// Whether the value is measured during a run (and so varies from seed to seed), not predicted
    /// before it.
    pub fn is_measured(self) -> bool {
        matches!(self, WarningKind::Overlap | WarningKind::EnergyBalance)
    }

    /// In a few words, for grouping and tables.
    pub fn name(self) -> &'static str {
        match self {
            WarningKind::TimeStepCapped => "time step capped by the damping rate",
            WarningKind::ContactTimeFraction => "time step over the contact time",
            WarningKind::IntegratorStability => "time step past the integrator's stable step",
            WarningKind::DampingRate => "time step times the damping rate",
            WarningKind::ImpactOverlap => "predicted impact overlap",
            WarningKind::StaticOverlap => "predicted static overlap at the floor",
            WarningKind::Overlap => "measured overlap",
            WarningKind::EnergyBalance => "energy-balance error",
        }
    }
}

/// One broken rule of thumb.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ValidityWarning {
    /// Which rule.
    pub kind: WarningKind,
    /// The measured or predicted value, in the limit's unit (see [`WarningKind`]).
    pub value: f64,
    /// The limit it passed.
    pub limit: f64,
    /// Simulated time of a measured value (s); None for a prediction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
    /// The speed of the predicted impact (m/s), for predicted warnings about it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub impact_speed: Option<f64>,
    /// The largest time step that passes (s), where a smaller step cures the warning.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub safe_time_step: Option<f64>,
}

impl ValidityWarning {
    /// A warning with no time, impact or safe step.
    pub fn new(kind: WarningKind, value: f64, limit: f64) -> Self {
        Self { kind, value, limit, time: None, impact_speed: None, safe_time_step: None }
    }

    /// The value over its limit.
    pub fn excess(&self) -> f64 {
        self.value / self.limit
    }
}

impl fmt::Display for ValidityWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (value, limit, key) = (short(self.value), short(self.limit), self.kind.limit_key());
        let at = self.time.map(|t| format!(" at t = {} s", short(t))).unwrap_or_default();
        let impact = self.impact_speed.map(|v| format!(" of an impact at {} m/s", short(v))).unwrap_or_default();
        let below =
            self.safe_time_step.map(|dt| format!("; use a time step below {} s", short(dt))).unwrap_or_default();
        match self.kind {
            WarningKind::TimeStepCapped => {
                write!(f, "time step capped at {limit} s by the damping-rate limit ({key}); {value} s was asked for")
            }
            WarningKind::ContactTimeFraction => write!(
                f,
                "time step is {value} of the contact time{impact} (limit {limit} = {key}): contacts are \
                 under-resolved and the run may blow up{below}"
            ),
            WarningKind::IntegratorStability => write!(
                f,
                "time step is {value} of the contact time, past {limit}, the stable step of the integrator \
                 ({key}) at the scene's damping ratio (restitution, beta, damping.viscous): piles may never come to rest \
                 (their contacts keep rattling) or blow up{below}"
            ),
            WarningKind::DampingRate => write!(
                f,
                "time step x damping rate = {value} exceeds {limit} ({key} of the integrator's stability \
                 limit): the damping (beta, damping.viscous) is too strong for this time step{below}"
            ),
            WarningKind::ImpactOverlap => write!(
                f,
                "an impact{} would overlap {value} radii (contact laws are valid below {limit} = {key}): the \
                 contacts are too soft for this scene",
                self.impact_speed.map(|v| format!(" at {} m/s", short(v))).unwrap_or_default()
            ),
            WarningKind::StaticOverlap => write!(
                f,
                "the settled pile's weight would press the bottom disks {value} radii into the floor (contact \
                 laws are valid below {limit} = {key}): the contacts are too soft for this pile"
            ),
            WarningKind::Overlap => {
                write!(f, "largest overlap {value} radii{at} is beyond the Hertz validity limit {limit} ({key})")
            }
            WarningKind::EnergyBalance => write!(
                f,
                "energy balance (mechanical + dissipated = initial) is off by {} % of the energy available{at}: \
                 the integration is inaccurate (time step too large for the contact stiffness or damping; limit \
                 {key} = {limit})",
                short(100.0 * self.value)
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_warning_round_trips_through_json_and_names_its_limit_in_its_text() {
        let w = ValidityWarning { time: Some(0.5), ..ValidityWarning::new(WarningKind::EnergyBalance, 0.0108, 0.01) };
        let back: ValidityWarning = serde_json::from_str(&serde_json::to_string(&w).unwrap()).unwrap();
        assert_eq!(back, w);
        assert!((w.excess() - 1.08).abs() < 1e-12);
        let text = w.to_string();
        assert!(text.contains("1.08 %") && text.contains("limits.energy_balance_tolerance"), "{text}");
    }

    #[test]
    fn a_diverged_value_prints_four_significant_digits_not_two_hundred() {
        let w = ValidityWarning {
            impact_speed: Some(1e177),
            safe_time_step: Some(3.3333e-9),
            ..ValidityWarning::new(WarningKind::ContactTimeFraction, 2.4e177, 0.1)
        };
        assert_eq!(
            w.to_string(),
            "time step is 2.400e177 of the contact time of an impact at 1.000e177 m/s (limit 0.1 = \
             limits.contact_time_fraction): contacts are under-resolved and the run may blow up; use a time step \
             below 3.333e-9 s"
        );
    }
}
