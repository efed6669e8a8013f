//! Watching a run: when frames are due, when it has diverged, and what to warn about.

use super::config::{LimitsConfig, SceneConfig};
use super::diagnostics::{self, Sample};
use super::particles::Particles;
use super::walls::BoxWalls;
use super::warning::{ValidityWarning, WarningKind};

/// Steps at which full frames are recorded, in order.
pub(super) struct FrameSchedule {
    steps: Vec<u64>,
    next: usize,
}

impl FrameSchedule {
    /// The frame steps of a scene run with time step `dt` (s) from step and time (s) `origin` on,
    /// up to `last_step` (frames before `origin` are not its).
    pub(super) fn new(scene: &SceneConfig, origin: (u64, f64), dt: f64, last_step: u64) -> Self {
        let mut times = scene.run.frame_times.clone();
        if let Some(interval) = scene.run.frame_interval {
            let count = (scene.run.duration / interval).floor() as u64;
            times.extend((0..=count).map(|k| k as f64 * interval));
        }
        let (first, start) = origin;
        let step_of = |t: f64| (first + ((t - start) / dt).round() as u64).min(last_step);
        let mut steps: Vec<u64> = times.iter().filter(|t| **t >= start).map(|t| step_of(*t)).collect();
        steps.sort_unstable();
        steps.dedup();
        Self { steps, next: 0 }
    }

    /// Whether a frame is due at `step` (steps must be asked in increasing order).
    pub(super) fn due(&mut self, step: u64) -> bool {
        while self.next < self.steps.len() && self.steps[self.next] < step {
            self.next += 1;
        }
        self.next < self.steps.len() && self.steps[self.next] == step
    }
}

/// Watches samples for divergence and validity problems.
pub(super) struct Monitor {
    initial_mechanical: Option<f64>,
    /// Energy brought in by a pour's disks so far (J): part of the initial energy.
    brought_in: f64,
    energy_scale: f64,
    worst_overlap: (f64, f64),
    worst_imbalance: (f64, f64),
}

impl Monitor {
    /// A monitor for a run starting from `p` with `initial_elastic` J stored in its contacts.
    pub(super) fn new(p: &Particles, walls: &BoxWalls, g: [f64; 2], initial_elastic: f64) -> Self {
        let gmag = g[0].hypot(g[1]);
        let (kt, kr) = diagnostics::kinetic_energies(p);
        let potential_drop: f64 = (0..p.len())
            .map(|i| {
                let low = walls.lowest_point(g, p.r[i]);
                (p.mass[i] * (g[0] * (low[0] - p.x[i]) + g[1] * (low[1] - p.y[i]))).max(0.0)
            })
            .sum();
        let floor_scale: f64 = (0..p.len()).map(|i| p.mass[i] * gmag * p.r[i]).sum();
        Self {
            initial_mechanical: None,
            brought_in: 0.0,
            energy_scale: (kt + kr + initial_elastic + potential_drop).max(floor_scale).max(f64::MIN_POSITIVE),
            worst_overlap: (0.0, 0.0),
            worst_imbalance: (0.0, 0.0),
        }
    }

    /// Sets the energy a pour's disks brought in so far (J).
    pub(super) fn bring_in(&mut self, energy: f64) {
        self.brought_in = energy;
    }

    /// Records one sample.
    pub(super) fn observe(&mut self, s: &Sample) {
        let initial = *self.initial_mechanical.get_or_insert(s.mechanical()) + self.brought_in;
        if s.max_overlap_ratio > self.worst_overlap.0 {
            self.worst_overlap = (s.max_overlap_ratio, s.time);
        }
        let imbalance = (s.mechanical() + s.dissipated - initial).abs();
        if imbalance > self.worst_imbalance.0 {
            self.worst_imbalance = (imbalance, s.time);
        }
    }

    /// The largest energy-balance error seen, `|mechanical + dissipated − initial|` over the energy
    /// available (the ratio `limits.energy_balance_tolerance` bounds).
    pub(super) fn energy_balance_error(&self) -> f64 {
        self.worst_imbalance.0 / self.energy_scale
    }

    /// The largest overlap seen, over the smaller radius of its pair (the ratio
    /// `limits.overlap_warning_ratio` bounds).
    pub(super) fn largest_overlap_ratio(&self) -> f64 {
        self.worst_overlap.0
    }

    /// Why the run must end now, if it must: non-finite state, overlap or energy growth beyond limits.
    pub(super) fn divergence(
        &self,
        s: &Sample,
        p: &Particles,
        power_finite: bool,
        limits: &LimitsConfig,
    ) -> Option<String> {
        let finite = s.kinetic().is_finite() && p.x.iter().chain(&p.y).all(|v| v.is_finite()) && power_finite;
        if !finite {
            return Some(format!(
                "non-finite state (NaN or infinity) at t = {:.6} s: the time step is far too large",
                s.time
            ));
        }
        let limit = limits.max_overlap_ratio;
        if s.max_overlap_ratio > limit {
            // Plain while readable: a run that blew up can report overlaps of 1e120 radii.
            let ratio = s.max_overlap_ratio;
            let overlap = if ratio < 1e4 { format!("{ratio:.3}") } else { format!("{ratio:.3e}") };
            return Some(format!(
                "overlap of {overlap} radii at t = {:.6} s exceeds limits.max_overlap_ratio = {limit}: contacts are not resolved (time step too large or material too soft)",
                s.time
            ));
        }
        let growth = s.mechanical() - self.initial_mechanical.map_or(s.mechanical(), |e| e + self.brought_in);
        let allowed = limits.energy_growth_ratio * self.energy_scale;
        if growth > allowed {
            return Some(format!(
                "mechanical energy grew by {growth:.4e} J by t = {:.6} s (more than {} of the {:.4e} J available, limits.energy_growth_ratio): the integration is unstable",
                s.time, limits.energy_growth_ratio, self.energy_scale
            ));
        }
        None
    }

    /// Validity warnings gathered over the run.
    pub(super) fn warnings(&self, limits: &LimitsConfig) -> Vec<ValidityWarning> {
        let mut w = Vec::new();
        let (ratio, time) = self.worst_overlap;
        if ratio > limits.overlap_warning_ratio {
            w.push(ValidityWarning {
                time: Some(time),
                ..ValidityWarning::new(WarningKind::Overlap, ratio, limits.overlap_warning_ratio)
            });
        }
        let (error, time) = (self.energy_balance_error(), self.worst_imbalance.1);
        if error > limits.energy_balance_tolerance {
            w.push(ValidityWarning {
                time: Some(time),
                ..ValidityWarning::new(WarningKind::EnergyBalance, error, limits.energy_balance_tolerance)
            });
        }
        w
    }
}

super::run_state::persist_fields!(Monitor { initial_mechanical, energy_scale, worst_overlap, worst_imbalance });
