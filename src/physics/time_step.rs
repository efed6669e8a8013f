//! The time step of a scene: given (`integrator.time_step`), or a fraction of one of the scene's
//! time scales (`integrator.contact_time_fraction`, `integrator.rayleigh_fraction`), resolved before
//! the run and capped by the integrator's damping-rate stability limit.
//!
//! - **Contact time** `t_c`: the contact law's duration of the scene's hardest impact (the estimate of
//!   [`super::stability`]; for Hertz `t_c ≈ 2.87 (m*² / (R* E*² v))^(1/5)`), with the smallest disk.
//!   The impact speed is bounded from the box for generated placements (a fall from the top of the box
//!   to the floor), so that every placement seed of a scene gets the same step; from the disks
//!   themselves for file placement (each falls until it lands on the body below: a pile at rest
//!   does not fall).
//! - **Rayleigh time** `T_R = π R √(ρ/G) / (0.1631 ν + 0.8766)` of the smallest disk (EDEM's
//!   convention; 20 % of it is common practice).
//!
//! With the step tied to the contact time, a stiffer material gets a smaller step (Hertz:
//! `dt ∝ E^(−2/5)`), so a stiffness sweep changes the cost of a run as users expect.

use super::config::SceneConfig;
use super::contact::ContactLaw;
use super::material::{Elastic, Materials};
use super::particles::InitialDisk;
use super::stability::{self, HardestImpact};
use super::walls::BoxWalls;
use super::warning::{ValidityWarning, WarningKind};

/// A scene's time step and how it was chosen.
#[derive(Clone, Debug, PartialEq)]
pub struct ResolvedTimeStep {
    /// The time step Δt (s).
    pub dt: f64,
    /// Set when the damping-rate limit lowered the requested step: both figures.
    pub warning: Option<ValidityWarning>,
}

/// Rayleigh time of a disk of radius `radius` (m): `π R √(ρ/G) / (0.1631 ν + 0.8766)` (s).
pub fn rayleigh_time(radius: f64, density: f64, elastic: &Elastic) -> f64 {
    std::f64::consts::PI * radius * (density / elastic.shear_modulus).sqrt() / (0.1631 * elastic.poisson_ratio + 0.8766)
}

/// Resolves the time step of a (validated) scene with contact law `law`. `disks`: the initial
/// disks of a file placement (the impact speed and smallest disk come from them); `None` for
/// generated placements.
pub fn resolve<L: ContactLaw>(law: &L, scene: &SceneConfig, disks: Option<&[InitialDisk]>) -> ResolvedTimeStep {
    if let Some(dt) = scene.integrator.fixed_time_step() {
        return ResolvedTimeStep { dt, warning: None };
    }
    let materials = Materials::from_scene(scene);
    let impact = hardest_impact(law, scene, &materials, disks);
    let m = &scene.material;
    let requested = match (scene.integrator.contact_time_fraction, scene.integrator.rayleigh_fraction) {
        (Some(f), _) => f * impact.contact_time,
        (None, Some(f)) => {
            let radius = disks.map_or_else(|| scene.smallest_radius(), smallest_radius);
            let elastic = Elastic::new(m.youngs_modulus, m.poisson_ratio, m.shear_modulus);
            f * rayleigh_time(radius, m.density, &elastic)
        }
        (None, None) => unreachable!("a scene without a fraction has a fixed time step"),
    };
    let limit = stability::damping_time_step_limit(scene, impact.damping_rate);
    if requested <= limit {
        return ResolvedTimeStep { dt: requested, warning: None };
    }
    let warning = ValidityWarning::new(WarningKind::TimeStepCapped, requested, limit);
    ResolvedTimeStep { dt: limit, warning: Some(warning) }
}

/// The hardest impact for the time step: smallest disk, fastest speed (see the module doc).
fn hardest_impact<L: ContactLaw>(
    law: &L,
    scene: &SceneConfig,
    materials: &Materials,
    disks: Option<&[InitialDisk]>,
) -> HardestImpact {
    let thickness = scene.particles.thickness;
    let mass = |r: f64| materials.density * std::f64::consts::PI * r * r * thickness;
    let g = scene.gravity;
    let walls = BoxWalls::new(&scene.domain);
    let (radius, speed) = match disks {
        Some(disks) if scene.placement.kind.reads_file() && !disks.is_empty() => {
            let column = |f: fn(&InitialDisk) -> f64| disks.iter().map(f).collect::<Vec<f64>>();
            let drops = stability::landing_drops(&column(|d| d.x), &column(|d| d.y), &column(|d| d.r), &walls, g);
            let falls = disks.iter().zip(drops).map(|(d, drop)| d.vx.hypot(d.vy) + (2.0 * drop).sqrt());
            (smallest_radius(disks), falls.fold(0.0, f64::max))
        }
        _ => {
            let r = scene.smallest_radius();
            let top = walls.lowest_point([-g[0], -g[1]], r);
            (r, (2.0 * potential_drop(g, top, walls.lowest_point(g, r))).sqrt())
        }
    };
    let speed = speed.max((2.0 * g[0].hypot(g[1]) * scene.largest_radius()).sqrt()).max(1e-3);
    stability::hardest_impact(law, materials, speed, radius, mass(radius), scene.damping.viscous)
}

/// `g·(to − from)` per unit mass: the potential energy released falling from `from` to `to` (J/kg).
fn potential_drop(g: [f64; 2], from: [f64; 2], to: [f64; 2]) -> f64 {
    (g[0] * (to[0] - from[0]) + g[1] * (to[1] - from[1])).max(0.0)
}

fn smallest_radius(disks: &[InitialDisk]) -> f64 {
    disks.iter().map(|d| d.r).fold(f64::INFINITY, f64::min)
}

/// The scene with its time step fixed at `dt` (s), the fractions that chose it removed.
pub fn with_time_step(scene: &SceneConfig, dt: f64) -> SceneConfig {
    let mut scene = scene.clone();
    scene.integrator.time_step = Some(dt);
    (scene.integrator.contact_time_fraction, scene.integrator.rayleigh_fraction) = (None, None);
    scene
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::contact::HertzMindlin;

    fn scene() -> SceneConfig {
        let mut s = SceneConfig::default();
        s.integrator.contact_time_fraction = Some(0.1);
        s
    }

    #[test]
    fn hertz_step_scales_as_e_to_the_minus_two_fifths() {
        let mut soft = scene();
        soft.material.youngs_modulus = 1e7;
        let mut stiff = scene();
        stiff.material.youngs_modulus = 1e9;
        let ratio =
            resolve(&HertzMindlin::default(), &soft, None).dt / resolve(&HertzMindlin::default(), &stiff, None).dt;
        assert!((ratio - 100f64.powf(0.4)).abs() < 1e-3 * ratio, "ratio {ratio}");
    }

    #[test]
    fn contact_time_matches_the_hertz_formula() {
        // Fall from 0.6 m − 2R to the floor; the disk-disk impact is the shorter one: R* = R/2, m* = m/2.
        let s = scene();
        let m = Materials::from_scene(&s);
        let (r, mass) = (0.005, 0.5 * 1000.0 * std::f64::consts::PI * 0.01 * 0.01);
        let v = (2.0 * 9.81 * (0.6 - 2.0 * 0.01_f64)).sqrt();
        let e_star = m.particle.e_star;
        let formula = 2.87 * (mass * mass / (r * e_star * e_star * v)).powf(0.2);
        let dt = resolve(&HertzMindlin::default(), &s, None).dt;
        assert!((dt / 0.1 - formula).abs() < 0.01 * formula, "t_c {} vs {formula}", dt / 0.1);
    }

    #[test]
    fn rayleigh_step_follows_edem_convention() {
        let mut s = SceneConfig::default();
        s.integrator.rayleigh_fraction = Some(0.2);
        let e = Elastic::new(1e9, Some(0.3), None);
        let expected = 0.2 * std::f64::consts::PI * 0.01 * (1000.0 / e.shear_modulus).sqrt() / (0.1631 * 0.3 + 0.8766);
        assert!((resolve(&HertzMindlin::default(), &s, None).dt - expected).abs() < 1e-15);
    }

    #[test]
    fn strong_viscous_damping_caps_the_step_and_says_so() {
        let mut s = scene();
        s.damping.viscous = 1e5;
        let resolved = resolve(&HertzMindlin::default(), &s, None);
        let limit = 0.5 * 1.0 / 1e5;
        assert!(resolved.dt < limit && resolved.dt > 0.9 * limit, "{}", resolved.dt);
        assert_eq!(resolved.warning.unwrap().kind, WarningKind::TimeStepCapped);
        assert!(resolve(&HertzMindlin::default(), &scene(), None).warning.is_none());
    }

    #[test]
    fn the_step_does_not_depend_on_the_placement_seed() {
        let mut a = scene();
        a.particles.radius_max = Some(0.015);
        let mut b = a.clone();
        b.placement.seed += 1;
        assert_eq!(resolve(&HertzMindlin::default(), &a, None), resolve(&HertzMindlin::default(), &b, None));
    }
}
