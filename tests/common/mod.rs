//! Shared helpers for the physics tests: small scenes and theory.
#![allow(dead_code)]

use demsweep::physics::config::{IntegratorKind, PlacementKind, SceneConfig};
use demsweep::physics::contact::RegisteredLaw;
use demsweep::physics::particles::InitialDisk;
use demsweep::physics::record::History;
use demsweep::physics::simulation::Simulation;

/// Integral ∫₀¹ (1 − x^{5/2})^{−1/2} dx = √π Γ(2/5) / (5/2 Γ(9/10)): Hertz contact time factor / 2.
pub const HERTZ_TIME_INTEGRAL: f64 = 1.4716375921623521;

/// Both integrators.
pub const SCHEMES: [IntegratorKind; 2] = [IntegratorKind::AdamsBashforthMoulton, IntegratorKind::VelocityVerlet];

/// A scene without gravity, damping or friction in a 1 m box, with the given material.
pub fn free_scene(youngs_modulus: f64, scheme: IntegratorKind, dt: f64) -> SceneConfig {
    let mut s = SceneConfig::default();
    s.domain.width = 1.0;
    s.domain.height = 1.0;
    s.gravity = [0.0, 0.0];
    s.material.youngs_modulus = youngs_modulus;
    s.material.poisson_ratio = Some(0.3);
    s.material.beta = Some(0.0);
    s.material.friction = 0.0;
    s.material.rolling_friction = 0.0;
    s.integrator.scheme = scheme;
    s.integrator.time_step = Some(dt);
    s.placement.kind = PlacementKind::File;
    s.placement.file = Some("in-memory".into());
    s.run.stop_at_settle = false;
    s
}

/// Hertz theory of a head-on impact: (max overlap, contact duration) for F = 4/3 E* √R* δ^{3/2}.
pub fn hertz_impact(e_star: f64, r_star: f64, m_star: f64, speed: f64) -> (f64, f64) {
    let k = 4.0 / 3.0 * e_star * r_star.sqrt();
    let max_overlap = (5.0 * m_star * speed * speed / (4.0 * k)).powf(0.4);
    (max_overlap, 2.0 * HERTZ_TIME_INTEGRAL * max_overlap / speed)
}

/// E* of two bodies of the same material.
pub fn same_material_e_star(e: f64, nu: f64) -> f64 {
    e / (2.0 * (1.0 - nu * nu))
}

/// Disk mass for density 1000 kg/m³ and thickness 1 m.
pub fn disk_mass(r: f64) -> f64 {
    1000.0 * std::f64::consts::PI * r * r
}

/// Time and value at which a sampled signal crosses zero between samples k-1 and k (linear).
pub fn crossing(t: &[f64], v: &[f64], k: usize) -> f64 {
    t[k - 1] + (t[k] - t[k - 1]) * (0.0 - v[k - 1]) / (v[k] - v[k - 1])
}

/// Peak of a sampled signal refined by a parabola through the largest sample and its neighbours.
pub fn refined_peak(v: &[f64]) -> f64 {
    let k = (1..v.len() - 1).max_by(|a, b| v[*a].total_cmp(&v[*b])).unwrap();
    let (a, b, c) = (v[k - 1], v[k], v[k + 1]);
    let denom = a - 2.0 * b + c;
    if denom == 0.0 { b } else { b - 0.125 * (a - c) * (a - c) / denom }
}

/// Contact duration and max of an overlap signal sampled every step (first contact only).
pub fn contact_of(t: &[f64], overlap: &[f64]) -> (f64, f64) {
    let start = overlap.iter().position(|d| *d > 0.0).expect("contact starts");
    let len = overlap[start..].iter().position(|d| *d <= 0.0).expect("contact ends");
    let end = start + len;
    let duration = crossing(t, overlap, end) - crossing(t, overlap, start);
    (duration, refined_peak(&overlap[start - 1..=end]))
}

/// The reference scene's initial disks (tests/data/deposition_300.csv, see docs/reference_scene.md).
pub fn reference_disks() -> Vec<InitialDisk> {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/deposition_300.csv")).unwrap();
    text.lines()
        .skip(1)
        .map(|line| {
            let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
            InitialDisk { x: v[0], y: v[1], r: v[2], ..Default::default() }
        })
        .collect()
}

/// The reference scene (docs/reference_scene.md): E 1e9, ν 0.3, e 0.5, μ 0.5, dt 1e-5.
pub fn reference_scene() -> SceneConfig {
    let mut s = SceneConfig::default();
    s.material.restitution = Some(0.5);
    s.material.friction = 0.5;
    s.placement.kind = PlacementKind::File;
    s.placement.file = Some("deposition_300.csv".into());
    s.integrator.time_step = Some(1e-5);
    s
}

/// Bit patterns of a float series (NaN-safe exact comparison).
pub fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Largest |mechanical + dissipated − initial mechanical| energy over the samples (J).
pub fn largest_balance_error(h: &History) -> f64 {
    (0..h.len()).map(|k| (h.mechanical[k] + h.dissipated[k] - h.mechanical[0]).abs()).fold(0.0, f64::max)
}

/// A disk of radius `radius` starting 1 % of its radius above the floor at 1 m/s towards it in
/// `scene` (no gravity: see [`free_scene`]), run under law `L` until it has left the floor; returns
/// its velocity then and the contact's duration, measured from per-step overlaps.
pub fn floor_impact<L: RegisteredLaw>(scene: &SceneConfig, radius: f64) -> (f64, f64) {
    let gap = 0.01 * radius;
    let disks = [InitialDisk { x: 0.5, y: radius + gap, r: radius, vy: -1.0, ..Default::default() }];
    let mut sim = Simulation::<L>::new(scene, &disks);
    let (mut t, mut overlap) = (vec![0.0], vec![-gap]);
    while !(*overlap.last().unwrap() < 0.0 && overlap.iter().any(|d| *d > 0.0)) {
        sim.advance(false);
        t.push(sim.time());
        overlap.push(radius - sim.particles().y[0]);
    }
    (sim.particles().vy[0], contact_of(&t, &overlap).0)
}
