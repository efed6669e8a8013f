//! Energies, the unbalanced force ratio and the settle criterion, computed on sampled steps only.

use super::config::SettleConfig;
use super::particles::Particles;
use super::record::History;

/// Contact quantities summed during a sampled force evaluation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactTotals {
    /// Elastic energy stored in all contacts (J).
    pub elastic: f64,
    /// Sum of contact force magnitudes (N).
    pub force_sum: f64,
    /// Number of contacts.
    pub contacts: u32,
    /// Largest overlap over the smaller radius of its pair.
    pub max_overlap_ratio: f64,
}

impl ContactTotals {
    /// Adds one contact.
    #[inline]
    pub fn add(&mut self, elastic: f64, force: f64, overlap_ratio: f64) {
        self.elastic += elastic;
        self.force_sum += force;
        self.contacts += 1;
        self.max_overlap_ratio = self.max_overlap_ratio.max(overlap_ratio);
    }
}

/// Diagnostics at one time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sample {
    /// Simulated time (s).
    pub time: f64,
    /// Σ ½ m v² (J).
    pub kinetic_translational: f64,
    /// Σ ½ I ω² (J).
    pub kinetic_rotational: f64,
    /// −Σ m g·x (J).
    pub potential: f64,
    /// Elastic energy in contacts (J).
    pub elastic: f64,
    /// Energy removed by damping and friction so far, numerical damping included (J).
    pub dissipated: f64,
    /// The part of `dissipated` removed by numerical damping (J).
    pub numerical_damping_dissipated: f64,
    /// Unbalanced force ratio; NaN without contacts.
    pub unbalanced_force_ratio: f64,
    /// Contact count.
    pub contacts: u32,
    /// Largest overlap ratio.
    pub max_overlap_ratio: f64,
}

impl Sample {
    /// Kinetic energy, translational plus rotational (J).
    pub fn kinetic(&self) -> f64 {
        self.kinetic_translational + self.kinetic_rotational
    }
    /// The paper's total energy: kinetic + potential (J).
    pub fn total(&self) -> f64 {
        self.kinetic() + self.potential
    }
    /// Mechanical energy: kinetic + potential + elastic (J).
    pub fn mechanical(&self) -> f64 {
        self.total() + self.elastic
    }
}

/// Σ ½ m v² and Σ ½ I ω² (J), with I = m R²/2.
pub fn kinetic_energies(p: &Particles) -> (f64, f64) {
    let mut trans = 0.0;
    let mut rot = 0.0;
    for i in 0..p.len() {
        trans += 0.5 * p.mass[i] * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i]);
        rot += 0.25 * p.mass[i] * p.r[i] * p.r[i] * p.omega[i] * p.omega[i];
    }
    (trans, rot)
}

/// Gravitational potential −Σ m g·x (J).
pub fn potential_energy(p: &Particles, g: [f64; 2]) -> f64 {
    (0..p.len()).map(|i| -p.mass[i] * (g[0] * p.x[i] + g[1] * p.y[i])).sum()
}

/// Unbalanced force ratio (Yade's definition): mean |net force| over disks, gravity included (at
/// rest the contacts carry the weight), divided by mean |contact force| over contacts.
/// `p.fx`, `p.fy` hold the contact forces; the weight `m g` is added here. NaN without contacts.
pub fn unbalanced_force_ratio(p: &Particles, g: [f64; 2], totals: &ContactTotals) -> f64 {
    if totals.contacts == 0 || p.is_empty() {
        return f64::NAN;
    }
    let net_force = |i: usize| {
        let (x, y) = (p.fx[i] + p.mass[i] * g[0], p.fy[i] + p.mass[i] * g[1]);
        (x * x + y * y).sqrt()
    };
    let net: f64 = (0..p.len()).map(net_force).sum();
    (net / p.len() as f64) / (totals.force_sum / totals.contacts as f64)
}

impl History {
    /// Appends one sample.
    pub fn push(&mut self, s: &Sample) {
        self.time.push(s.time);
        self.kinetic_translational.push(s.kinetic_translational);
        self.kinetic_rotational.push(s.kinetic_rotational);
        self.potential.push(s.potential);
        self.elastic.push(s.elastic);
        self.dissipated.push(s.dissipated);
        self.numerical_damping_dissipated.push(s.numerical_damping_dissipated);
        self.total.push(s.total());
        self.mechanical.push(s.mechanical());
        self.unbalanced_force_ratio.push(s.unbalanced_force_ratio);
        self.contacts.push(s.contacts);
        self.max_overlap_ratio.push(s.max_overlap_ratio);
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }
}

/// Tracks the settle criterion over successive samples.
#[derive(Clone, Debug)]
pub struct SettleDetector {
    criterion: SettleConfig,
    since: Option<f64>,
    /// When the criterion first held for the hold time: the start of that stretch (s).
    pub settle_time: Option<f64>,
}

impl SettleDetector {
    /// A detector for the given criterion.
    pub fn new(criterion: &SettleConfig) -> Self {
        Self { criterion: criterion.clone(), since: None, settle_time: None }
    }

    /// Feeds one sample; returns true once the pile has settled. Without `may_settle` (in a stage
    /// before the physics) the quiet stretch is followed but does not settle the pile yet.
    pub fn update(&mut self, s: &Sample, may_settle: bool) -> bool {
        if self.settle_time.is_some() {
            return true;
        }
        let quiet = s.unbalanced_force_ratio < self.criterion.ubf_threshold
            && self.criterion.kinetic_energy_threshold.is_none_or(|k| s.kinetic() < k);
        self.since = if quiet { self.since.or(Some(s.time)) } else { None };
        if let Some(start) = self.since
            && may_settle
            && s.time - start >= self.criterion.hold_time - 1e-12
        {
            self.settle_time = Some(start);
        }
        self.settle_time.is_some()
    }

    /// Starts the quiet stretch afresh (at a switch of stages that changes the run's settings).
    pub fn restart(&mut self) {
        self.since = None;
    }
}

super::run_state::persist_fields!(ContactTotals { elastic, force_sum, contacts, max_overlap_ratio });
super::run_state::persist_fields!(SettleDetector { since, settle_time });

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(time: f64, ubf: f64) -> Sample {
        Sample { time, unbalanced_force_ratio: ubf, ..Default::default() }
    }

    #[test]
    fn settle_needs_the_hold_time_and_restarts_after_a_spike() {
        let cfg = SettleConfig { ubf_threshold: 0.01, hold_time: 0.02, kinetic_energy_threshold: None };
        let mut d = SettleDetector::new(&cfg);
        let ubf = [f64::NAN, 0.5, 0.005, 0.005, 0.2, 0.004, 0.004, 0.004];
        let mut settled_at = None;
        for (k, u) in ubf.iter().enumerate() {
            if d.update(&sample(k as f64 * 0.01, *u), true) && settled_at.is_none() {
                settled_at = Some(k);
            }
        }
        assert_eq!(settled_at, Some(7));
        assert!((d.settle_time.unwrap() - 0.05).abs() < 1e-12);
    }
}
