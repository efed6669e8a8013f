//! Before a run: is the time step small enough, and is the material stiff enough for Hertz theory?
//!
//! The hardest impact of a scene is estimated from its energy: every disk may fall to the lowest point
//! of the box (plus its initial speed). For that impact, with the smallest disks, the contact law's
//! undamped head-on impact gives the contact time `t_c` and the largest overlap, and the law's normal
//! damping gives the largest damping rate `c_n / m*`. Explicit schemes need `Δt ≪ t_c` to resolve a
//! contact and `Δt · c_n/m* < 1` (Adams-Bashforth 2's real stability interval) or `< 2` (velocity
//! Verlet) to keep the damping stable.

use serde::{Deserialize, Serialize};

use super::config::{IntegratorKind, SceneConfig};
use super::contact::{ContactLaw, PairProperties, estimate_impact};
use super::material::{ContactMaterial, Materials, effective_mass, effective_radius};
use super::particles::Particles;
use super::walls::BoxWalls;

/// Packing fraction assumed for the settled pile when estimating the weight on the floor.
const PILE_PACKING: f64 = 0.82;

/// The pre-run estimate and its warnings.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StabilityReport {
    /// Speed of the hardest expected impact (m/s).
    pub impact_speed: f64,
    /// The contact law's contact time of that impact for the smallest disks (s).
    pub contact_time: f64,
    /// Predicted largest overlap of that impact, over the radius.
    pub impact_overlap_ratio: f64,
    /// Predicted static overlap at the floor under the weight of the settled pile, over the radius.
    pub static_overlap_ratio: f64,
    /// Largest normal damping rate `c_n/m*` during that impact, plus the viscous damping rate (1/s).
    pub damping_rate: f64,
    /// Δt / t_c.
    pub dt_over_contact_time: f64,
    /// Δt · c_n/m*.
    pub dt_times_damping_rate: f64,
    /// Largest time step that passes both checks (s).
    pub safe_time_step: f64,
    /// What is wrong, in words (empty when nothing is).
    pub warnings: Vec<String>,
}

/// The hardest impact of a scene, for the time step and its checks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HardestImpact {
    /// Shorter of the disk-disk and disk-wall contact durations (s).
    pub contact_time: f64,
    /// Larger of the two impacts' largest overlaps (m).
    pub max_overlap: f64,
    /// Largest damping rate: the contacts' `c_n/m*` plus the viscous rate (1/s).
    pub damping_rate: f64,
}

/// Head-on impacts at `speed` of the smallest disk (`radius`, `mass`) on its twin and on a wall.
/// `viscous`: the numerical viscous damping rate (1/s), added to the contacts' damping rate.
pub fn hardest_impact<L: ContactLaw>(
    law: &L,
    materials: &Materials,
    speed: f64,
    radius: f64,
    mass: f64,
    viscous: f64,
) -> HardestImpact {
    let pair = |m: &ContactMaterial, r2: f64, m2: f64| PairProperties {
        e_star: m.e_star,
        g_star: m.g_star,
        r_star: effective_radius(radius, r2),
        m_star: effective_mass(mass, m2),
        beta: m.beta,
    };
    let disk_disk = estimate_impact(law, &pair(&materials.particle, radius, mass), speed);
    let disk_wall = estimate_impact(law, &pair(&materials.wall, f64::INFINITY, f64::INFINITY), speed);
    HardestImpact {
        contact_time: disk_disk.duration.min(disk_wall.duration),
        max_overlap: disk_disk.max_overlap.max(disk_wall.max_overlap),
        damping_rate: disk_disk.max_damping_rate.max(disk_wall.max_damping_rate) + viscous,
    }
}

/// Largest time step whose `Δt · damping_rate` stays within `limits.damping_rate_fraction` of the
/// integrator's stability limit (s; infinite without damping).
pub fn damping_time_step_limit(scene: &SceneConfig, damping_rate: f64) -> f64 {
    let limit = scene.limits.damping_rate_fraction * damping_stability_limit(scene.integrator.scheme);
    if damping_rate > 0.0 { limit / damping_rate } else { f64::INFINITY }
}

/// Largest `Δt · rate` of a linear decay `v' = −rate·v` that the scheme keeps stable.
pub fn damping_stability_limit(kind: IntegratorKind) -> f64 {
    match kind {
        IntegratorKind::AdamsBashforthMoulton => 1.0,
        IntegratorKind::VelocityVerlet => 2.0,
    }
}

/// Speed of the hardest impact: initial speed plus a fall to the box's lowest point, at least the
/// speed of a fall through one radius.
pub fn impact_speed(p: &Particles, walls: &BoxWalls, g: [f64; 2]) -> f64 {
    let gmag = g[0].hypot(g[1]);
    let fastest = (0..p.len())
        .map(|i| {
            let low = walls.lowest_point(g, p.r[i]);
            let drop = (g[0] * (low[0] - p.x[i]) + g[1] * (low[1] - p.y[i])).max(0.0);
            p.vx[i].hypot(p.vy[i]) + (2.0 * drop).sqrt()
        })
        .fold(0.0, f64::max);
    fastest.max((2.0 * gmag * p.max_radius()).sqrt()).max(1e-3)
}

/// Assesses a scene about to run.
pub fn assess<L: ContactLaw>(
    law: &L,
    scene: &SceneConfig,
    p: &Particles,
    materials: &Materials,
    walls: &BoxWalls,
) -> StabilityReport {
    if p.is_empty() {
        return StabilityReport::default();
    }
    let dt = scene.integrator.fixed_time_step().expect("assessed scenes have a resolved time step");
    let speed = impact_speed(p, walls, scene.gravity);
    let rmin = p.r.iter().cloned().fold(f64::INFINITY, f64::min);
    let mmin = p.mass.iter().cloned().fold(f64::INFINITY, f64::min);
    let impact = hardest_impact(law, materials, speed, rmin, mmin, scene.damping.viscous);
    let static_overlap = static_floor_overlap(law, scene, p, materials);
    let limits = &scene.limits;
    let damping_limit = limits.damping_rate_fraction * damping_stability_limit(scene.integrator.scheme);
    let mut report = StabilityReport {
        impact_speed: speed,
        contact_time: impact.contact_time,
        impact_overlap_ratio: impact.max_overlap / rmin,
        static_overlap_ratio: static_overlap / p.max_radius(),
        damping_rate: impact.damping_rate,
        dt_over_contact_time: dt / impact.contact_time,
        dt_times_damping_rate: dt * impact.damping_rate,
        safe_time_step: (limits.contact_time_fraction * impact.contact_time)
            .min(damping_time_step_limit(scene, impact.damping_rate)),
        warnings: Vec::new(),
    };
    report.warnings = warnings(scene, &report, damping_limit, law.name());
    report
}

fn warnings(scene: &SceneConfig, r: &StabilityReport, damping_limit: f64, law: &str) -> Vec<String> {
    let limits = &scene.limits;
    let mut w = Vec::new();
    if r.dt_over_contact_time > limits.contact_time_fraction {
        w.push(format!(
            "time step {:.3e} s is {:.3} of the contact time {:.3e} s of an impact at {:.3} m/s (limit {} = limits.contact_time_fraction): contacts are under-resolved and the run may blow up; use a time step below {:.3e} s",
            r.dt_over_contact_time * r.contact_time, r.dt_over_contact_time, r.contact_time, r.impact_speed, limits.contact_time_fraction, r.safe_time_step
        ));
    }
    if r.dt_times_damping_rate > damping_limit {
        w.push(format!(
            "time step x damping rate = {:.3} exceeds {:.3} ({} of the integrator's stability limit {}): the damping (beta, damping.viscous) is too strong for this time step; use a time step below {:.3e} s",
            r.dt_times_damping_rate, damping_limit, limits.damping_rate_fraction, damping_stability_limit(scene.integrator.scheme), r.safe_time_step
        ));
    }
    if r.impact_overlap_ratio > limits.overlap_warning_ratio {
        w.push(format!(
            "an impact at {:.3} m/s would overlap {:.3} radii (contact laws are valid below {} = limits.overlap_warning_ratio): the contacts ({}, E = {:.3e} Pa) are too soft for this scene",
            r.impact_speed, r.impact_overlap_ratio, limits.overlap_warning_ratio, law, scene.material.youngs_modulus
        ));
    }
    if r.static_overlap_ratio > limits.overlap_warning_ratio {
        w.push(format!(
            "the settled pile's weight would press the bottom disks {:.3} radii into the floor (contact laws are valid below {}): the contacts ({}, E = {:.3e} Pa) are too soft for this pile",
            r.static_overlap_ratio, limits.overlap_warning_ratio, law, scene.material.youngs_modulus
        ));
    }
    w
}

/// Overlap at the floor under a column of the settled pile (m): the pile's depth from its area at
/// [`PILE_PACKING`], the column's weight on the bottom disk, and the law's static overlap for it.
fn static_floor_overlap<L: ContactLaw>(law: &L, scene: &SceneConfig, p: &Particles, materials: &Materials) -> f64 {
    let gmag = scene.gravity[0].hypot(scene.gravity[1]);
    let r = p.max_radius();
    let area: f64 = p.r.iter().map(|r| std::f64::consts::PI * r * r).sum();
    let depth = area / (scene.domain.width * PILE_PACKING);
    let mean_mass = p.mass.iter().sum::<f64>() / p.len() as f64;
    let weight = mean_mass * gmag * (depth / (2.0 * r)).max(1.0);
    let pair = PairProperties {
        e_star: materials.wall.e_star,
        g_star: materials.wall.g_star,
        r_star: r,
        m_star: mean_mass,
        beta: 0.0,
    };
    static_overlap(law, &pair, weight)
}

/// Overlap at which the law's elastic normal force equals `force` (bisection), m.
pub fn static_overlap<L: ContactLaw>(law: &L, pair: &PairProperties, force: f64) -> f64 {
    let (mut lo, mut hi) = (0.0_f64, pair.r_star);
    while law.loading_coefficients(pair, hi).normal_force < force && hi < 1e6 {
        hi *= 2.0;
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if law.loading_coefficients(pair, mid).normal_force < force { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}
