//! A silo-like column's wall load from its stress profile: Janssen's model rests on the column's
//! vertical balance, the side walls' friction carrying the weight the floor does not. Measured on
//! settled columns of 200 disks with rough walls, three seeds: the profile's wall shear summed over
//! its bands plus the floor's load is the disks' weight within 0.5 % (measured: within 0.1 %, while
//! the walls' share is −12 % to +4 % of the weight: settling compacts the column and the walls then
//! hold it down as often as up, far from Janssen's fully mobilised friction).

use demsweep::physics::config::SceneConfig;
use demsweep::physics::run_scene;
use demsweep::physics::simulation::Control;
use demsweep::physics::stress::StressProfile;

/// A column 4 cm wide of 200 disks of radius 2-2.5 mm, walls with friction 0.9.
fn column(seed: u64) -> SceneConfig {
    let mut s = SceneConfig::default();
    (s.particles.count, s.particles.radius, s.particles.radius_max) = (200, 0.002, Some(0.0025));
    (s.domain.width, s.domain.height) = (0.04, 0.3);
    (s.material.youngs_modulus, s.material.restitution, s.material.friction) = (5e9, Some(0.3), 0.5);
    s.wall_material.friction = Some(0.9);
    s.placement.seed = seed;
    (s.settle.ubf_threshold, s.settle.hold_time, s.run.duration) = (2e-4, 0.05, 3.0);
    s
}

#[test]
fn the_walls_and_the_floor_carry_the_column_s_weight() {
    for seed in 1..=3 {
        let s = column(seed);
        let rec = run_scene(&s, None, &mut |_| Control::Continue).expect("a valid scene");
        assert_eq!(rec.status.as_str(), "settled", "seed {seed}");
        let state = &rec.final_state;
        let g = -s.gravity[1];
        let mass = |r: &f64| s.material.density * std::f64::consts::PI * r * r * s.particles.thickness;
        let weight: f64 = state.r.iter().map(mass).sum::<f64>() * g;
        let profile = StressProfile::of_state(state, s.domain.width, s.particles.thickness);
        let bands = profile.bottom.iter().zip(&profile.top).zip(&profile.wall_shear);
        let walls: f64 = bands.map(|((b, t), shear)| shear * 2.0 * (t - b) * s.particles.thickness).sum();
        let floor = rec.pile["floor_load_ratio"] * weight;
        let gap = (walls + floor - weight) / weight;
        assert!(gap.abs() < 0.005, "seed {seed}: walls {walls} N + floor {floor} N against weight {weight} N");
    }
}
