//! Before a run: is the time step small enough, and is the material stiff enough for Hertz theory?
//!
//! The hardest impact of a scene is estimated from its energy: every disk may fall to the lowest point
//! of the box (plus its initial speed); the disks of a file placement fall only until they land on
//! the body below them ([`landing_drops`]), so a pile read back at rest is not a fall from the top. For that impact, with the smallest disks, the contact law's
//! undamped head-on impact gives the contact time `t_c` and the largest overlap, and the law's normal
//! damping gives the largest damping rate `c_n / m*`. Explicit schemes need `Δt ≪ t_c` to resolve a
//! contact and `Δt · c_n/m* < 1` (Adams-Bashforth 2's real stability interval) or `< 2` (velocity
//! Verlet) to keep the damping stable. Below both, a pile can still fail to come to rest: its
//! contacts keep rattling (a limit cycle) at a step the single impact tolerates, the sooner the
//! stronger the damping. [`stable_contact_time_fraction`] is each scheme's largest step that lets a
//! deposition settle, straight through and restarted from its own state, measured as a function of
//! the damping ratio ([`damping_ratio`]).

use serde::{Deserialize, Serialize};

use super::config::{IntegratorKind, PlacementKind, SceneConfig};
use super::contact::{ContactLaw, PairProperties, estimate_impact};
use super::material::{ContactMaterial, Materials, effective_mass, effective_radius};
use super::particles::Particles;
use super::walls::BoxWalls;
use super::warning::{ValidityWarning, WarningKind};

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
    /// Damping ratio of that impact's contact plus the viscous damping ([`damping_ratio`]).
    #[serde(default)]
    pub damping_ratio: f64,
    /// The integrator's largest stable Δt / t_c at that damping ratio, with its margin
    /// ([`stable_contact_time_fraction`]).
    #[serde(default)]
    pub stable_fraction: f64,
    /// Δt / t_c.
    pub dt_over_contact_time: f64,
    /// Δt · c_n/m*.
    pub dt_times_damping_rate: f64,
    /// Largest time step that passes both checks (s).
    pub safe_time_step: f64,
    /// What is wrong (empty when nothing is).
    pub warnings: Vec<ValidityWarning>,
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

/// Damping ratio ζ of a contact of duration `contact_time` (s) damped at `damping_rate` (1/s):
/// `rate · t_c / 2π`, the linear spring-dashpot's `ζ` (`rate = 2ζω`, `t_c = π/ω`) for light damping.
pub fn damping_ratio(damping_rate: f64, contact_time: f64) -> f64 {
    damping_rate * contact_time / std::f64::consts::TAU
}

/// The largest Δt / t_c at which every deposition of the measurement (`demsweep bench stable-step`,
/// results/bench/stable_step.md) settled with its energy balance within tolerance, straight
/// through and restarted mid-deposition from its own state, by damping ratio ζ: `(ζ, Adams-Bashforth-
/// Moulton, velocity Verlet)`. Past it a pile keeps rattling (a limit cycle) or blows up.
const MEASURED_STABLE_FRACTIONS: [(f64, f64, f64); 7] = [
    (0.0, 0.04, 0.25),
    (0.039, 0.07, 0.25),
    (0.132, 0.085, 0.25),
    (0.252, 0.1, 0.15),
    (0.328, 0.085, 0.15),
    (0.534, 0.06, 0.1),
    (0.693, 0.04, 0.07),
];

/// The share of the measured stable step (`MEASURED_STABLE_FRACTIONS`) a scene may use without a
/// warning: the margin for scenes and seeds the measurement did not see.
pub const STABLE_STEP_MARGIN: f64 = 0.8;

/// The largest Δt / t_c the scheme `kind` keeps stable at damping ratio `ratio`, with the
/// [`STABLE_STEP_MARGIN`]: linear between the measured damping ratios; past the last, inversely
/// with the damping ratio (where `Δt` times the damping rate is what limits the step).
pub fn stable_contact_time_fraction(kind: IntegratorKind, ratio: f64) -> f64 {
    let column = |row: &(f64, f64, f64)| match kind {
        IntegratorKind::AdamsBashforthMoulton => row.1,
        IntegratorKind::VelocityVerlet => row.2,
    };
    let table = &MEASURED_STABLE_FRACTIONS;
    let last = &table[table.len() - 1];
    let measured = match table.windows(2).find(|pair| ratio <= pair[1].0) {
        Some([low, high]) => {
            let t = ((ratio - low.0) / (high.0 - low.0)).clamp(0.0, 1.0);
            column(low) + t * (column(high) - column(low))
        }
        _ => column(last) * last.0 / ratio,
    };
    STABLE_STEP_MARGIN * measured
}

/// Speed of the hardest impact: initial speed and a fall to the box's lowest point (to the body
/// below, for a file or dropped placement, whose disks may rest on each other: see
/// [`landing_drops`]), at least the speed of a fall through one radius.
pub fn impact_speed(p: &Particles, walls: &BoxWalls, g: [f64; 2], placement: PlacementKind) -> f64 {
    let gmag = g[0].hypot(g[1]);
    let drops = match placement {
        PlacementKind::File | PlacementKind::Lammps | PlacementKind::Dropped => {
            landing_drops(&p.x, &p.y, &p.r, walls, g)
        }
        _ => (0..p.len()).map(|i| floor_drop(walls, g, [p.x[i], p.y[i]], p.r[i])).collect(),
    };
    // A generated placement's disks fall freely from where they start (a lowered start's at the speed
    // of the height it skipped): energy gives √(v² + 2 g d). A file's velocities may be anything
    // (a pile in motion): their sum with the fall's speed bounds it.
    let landing = |v: f64, drop: f64| {
        if placement.reads_file() { v + (2.0 * drop).sqrt() } else { (v * v + 2.0 * drop).sqrt() }
    };
    let fastest = drops.iter().enumerate().map(|(i, drop)| landing(p.vx[i].hypot(p.vy[i]), *drop));
    fastest.fold(0.0, f64::max).max((2.0 * gmag * p.max_radius()).sqrt()).max(1e-3)
}

/// `g·(low − x)`: the energy per unit mass (J/kg) a disk of radius `r` at `x` releases falling to
/// the box's lowest point.
fn floor_drop(walls: &BoxWalls, g: [f64; 2], x: [f64; 2], r: f64) -> f64 {
    let low = walls.lowest_point(g, r);
    (g[0] * (low[0] - x[0]) + g[1] * (low[1] - x[1])).max(0.0)
}

/// Energy per unit mass (J/kg) each disk releases before it lands, when all fall from where they
/// are: a disk lands on the box's lowest point or on the disk below it, after that disk has landed
/// (drop = the lower disk's drop + `|g|` × the gap between them along `g`), whichever comes first.
/// Disks resting on each other drop (almost) nothing. Cost: sorting plus a few neighbours per disk.
pub fn landing_drops(x: &[f64], y: &[f64], r: &[f64], walls: &BoxWalls, g: [f64; 2]) -> Vec<f64> {
    let gmag = g[0].hypot(g[1]);
    let mut drops: Vec<f64> = (0..x.len()).map(|i| floor_drop(walls, g, [x[i], y[i]], r[i])).collect();
    if gmag == 0.0 || x.is_empty() {
        return drops;
    }
    let down = [g[0] / gmag, g[1] / gmag];
    let depth = |i: usize| down[0] * x[i] + down[1] * y[i];
    let across = |i: usize| down[1] * x[i] - down[0] * y[i];
    let reach = 2.0 * r.iter().copied().fold(0.0, f64::max);
    let mut order: Vec<usize> = (0..x.len()).collect();
    order.sort_by(|&a, &b| depth(b).total_cmp(&depth(a)));
    let low = order.iter().map(|&i| across(i)).fold(f64::INFINITY, f64::min);
    let column = |i: usize| ((across(i) - low) / reach) as usize;
    let mut columns: Vec<Vec<usize>> = vec![Vec::new(); column_count(&order, column)];
    for &i in &order {
        let c = column(i);
        let mut best = drops[i];
        for landed in columns[c.saturating_sub(1)..(c + 2).min(columns.len())].iter() {
            for &j in landed.iter().rev() {
                let below = depth(j) - depth(i);
                if gmag * (below - reach) >= best {
                    break;
                }
                let contact = r[i] + r[j];
                let offset = (across(j) - across(i)).abs();
                if offset < contact {
                    let gap = (below - (contact * contact - offset * offset).sqrt()).max(0.0);
                    best = best.min(drops[j] + gmag * gap);
                }
            }
        }
        drops[i] = best;
        columns[c].push(i);
    }
    drops
}

/// Number of columns `column` maps the disks into.
fn column_count(order: &[usize], column: impl Fn(usize) -> usize) -> usize {
    order.iter().map(|&i| column(i)).max().map_or(0, |c| c + 1)
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
    let speed = impact_speed(p, walls, scene.gravity, scene.placement.kind);
    let rmin = p.r.iter().cloned().fold(f64::INFINITY, f64::min);
    let mmin = p.mass.iter().cloned().fold(f64::INFINITY, f64::min);
    let impact = hardest_impact(law, materials, speed, rmin, mmin, scene.damping.viscous);
    let static_overlap = static_floor_overlap(law, scene, p, materials);
    let limits = &scene.limits;
    let damping_limit = limits.damping_rate_fraction * damping_stability_limit(scene.integrator.scheme);
    let ratio = damping_ratio(impact.damping_rate, impact.contact_time);
    let stable_fraction = stable_contact_time_fraction(scene.integrator.scheme, ratio);
    let mut report = StabilityReport {
        impact_speed: speed,
        contact_time: impact.contact_time,
        impact_overlap_ratio: impact.max_overlap / rmin,
        static_overlap_ratio: static_overlap / p.max_radius(),
        damping_rate: impact.damping_rate,
        damping_ratio: ratio,
        stable_fraction,
        dt_over_contact_time: dt / impact.contact_time,
        dt_times_damping_rate: dt * impact.damping_rate,
        safe_time_step: (limits.contact_time_fraction.min(stable_fraction) * impact.contact_time)
            .min(damping_time_step_limit(scene, impact.damping_rate)),
        warnings: Vec::new(),
    };
    report.warnings = warnings(scene, &report, damping_limit);
    report
}

/// Relative rounding within which a step resolved at a fraction of the contact time counts as at it:
/// the step and the assessment compute the contact time separately, to the last bits.
const RESOLVED_AT_LIMIT: f64 = 1e-9;

fn warnings(scene: &SceneConfig, r: &StabilityReport, damping_limit: f64) -> Vec<ValidityWarning> {
    let limits = &scene.limits;
    let warning = |kind, value, limit| ValidityWarning::new(kind, value, limit);
    let mut w = Vec::new();
    let past = |fraction: f64| r.dt_over_contact_time > fraction * (1.0 + RESOLVED_AT_LIMIT);
    if past(limits.contact_time_fraction) {
        w.push(ValidityWarning {
            impact_speed: Some(r.impact_speed),
            safe_time_step: Some(r.safe_time_step),
            ..warning(WarningKind::ContactTimeFraction, r.dt_over_contact_time, limits.contact_time_fraction)
        });
    }
    if past(r.stable_fraction) {
        w.push(ValidityWarning {
            safe_time_step: Some(r.safe_time_step),
            ..warning(WarningKind::IntegratorStability, r.dt_over_contact_time, r.stable_fraction)
        });
    }
    if r.dt_times_damping_rate > damping_limit {
        w.push(ValidityWarning {
            safe_time_step: Some(r.safe_time_step),
            ..warning(WarningKind::DampingRate, r.dt_times_damping_rate, damping_limit)
        });
    }
    if r.impact_overlap_ratio > limits.overlap_warning_ratio {
        w.push(ValidityWarning {
            impact_speed: Some(r.impact_speed),
            ..warning(WarningKind::ImpactOverlap, r.impact_overlap_ratio, limits.overlap_warning_ratio)
        });
    }
    if r.static_overlap_ratio > limits.overlap_warning_ratio {
        w.push(warning(WarningKind::StaticOverlap, r.static_overlap_ratio, limits.overlap_warning_ratio));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::config::DomainConfig;

    #[test]
    fn the_stable_step_falls_with_strong_damping_and_is_smaller_for_the_paper_integrator() {
        let (paper, verlet) = (IntegratorKind::AdamsBashforthMoulton, IntegratorKind::VelocityVerlet);
        for ratio in [0.0, 0.02, 0.1, 0.3, 0.6, 1.0, 5.0] {
            let (a, v) = (stable_contact_time_fraction(paper, ratio), stable_contact_time_fraction(verlet, ratio));
            assert!(a > 0.0 && a < v, "ζ = {ratio}: {a} vs {v}");
        }
        // Between measured damping ratios the limit is interpolated; past the last it falls as 1/ζ.
        let last = MEASURED_STABLE_FRACTIONS[MEASURED_STABLE_FRACTIONS.len() - 1];
        let at = |ratio| stable_contact_time_fraction(paper, ratio);
        assert!((at(last.0) - STABLE_STEP_MARGIN * last.1).abs() < 1e-12);
        assert!((at(2.0 * last.0) - 0.5 * at(last.0)).abs() < 1e-12);
        let (a, b) = (MEASURED_STABLE_FRACTIONS[4], MEASURED_STABLE_FRACTIONS[5]);
        assert!((at(0.5 * (a.0 + b.0)) - STABLE_STEP_MARGIN * 0.5 * (a.1 + b.1)).abs() < 1e-12);
    }

    #[test]
    fn disks_land_on_the_disk_below_not_on_the_floor() {
        let walls = BoxWalls::new(&DomainConfig { width: 1.0, height: 2.0, lid: false, periodic_x: false });
        let g = [0.0, -9.81];
        // A resting column of three disks (touching), one disk 0.5 m above it, one alone 1 m up.
        let x = [0.5, 0.5, 0.5, 0.5, 0.2];
        let y = [0.1, 0.3, 0.5, 1.1, 1.0];
        let drops = landing_drops(&x, &y, &[0.1; 5], &walls, g);
        for resting in &drops[..3] {
            assert!(resting.abs() < 1e-12, "{drops:?}");
        }
        assert!((drops[3] - 9.81 * 0.4).abs() < 1e-9, "lands on the column's top after a 0.4 m gap: {drops:?}");
        assert!((drops[4] - 9.81 * 0.9).abs() < 1e-9, "falls to the floor: {drops:?}");
    }
}
