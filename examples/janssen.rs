//! The stress in a silo-like column against Janssen's profile: a narrow box with wall friction is
//! filled and settled, its stress measured per height band (`physics::stress::stress_profile`), and
//! the vertical stress at each depth compared with Janssen's
//! `σ_yy(z) = ρ_b g W / (2 μ_w K) (1 − exp(−2 μ_w K z / W))` (2D: two walls over the width `W`), with
//! the bulk density `ρ_b` and the lateral stress ratio `K = σ_xx / σ_yy` measured on the same pile
//! and `μ_w` the wall friction: nothing is fitted. Janssen assumes the wall friction fully
//! mobilised; the printed ratio of the wall's shear load to `μ_w` times its normal load says how far
//! the pile is from that, and the last column is Janssen's profile with the wall friction the pile
//! actually mobilises (the walls' shear over normal load) in place of `μ_w`.
//!
//! `cargo run --release --example janssen -- [SEEDS] [WALL_FRICTION]` (default 3 seeds, 0.5).

use demsweep::physics::config::SceneConfig;
use demsweep::physics::contact_record::Partner;
use demsweep::physics::pile::PileGeometry;
use demsweep::physics::run_scene;
use demsweep::physics::simulation::Control;
use demsweep::physics::stress::stress_profile;

/// A column 6 cm wide of 500 disks of radius 2-2.5 mm.
fn column(seed: u64, wall_friction: f64) -> SceneConfig {
    let mut s = SceneConfig::default();
    (s.particles.count, s.particles.radius, s.particles.radius_max) = (500, 0.002, Some(0.0025));
    (s.domain.width, s.domain.height) = (0.06, 0.6);
    s.material.restitution = Some(0.3);
    s.material.friction = 0.5;
    s.wall_material.friction = Some(wall_friction);
    s.placement.seed = seed;
    (s.settle.ubf_threshold, s.settle.hold_time, s.run.duration) = (2e-4, 0.05, 4.0);
    s
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let seeds: u64 = args.get(1).map_or(3, |a| a.parse().expect("SEEDS: a count"));
    let wall_friction: f64 = args.get(2).map_or(0.5, |a| a.parse().expect("WALL_FRICTION: a number"));
    println!(
        "seed  depth (m)  sigma_yy (Pa)  Janssen (Pa)  ratio  K  wall shear / (mu_w normal)  Janssen mobilised (Pa)"
    );
    for seed in 0..seeds {
        let s = column(seed, wall_friction);
        let rec = run_scene(&s, None, &mut |_| Control::Continue).expect("a valid scene");
        let state = &rec.final_state;
        let contacts = state.contacts.pile_contacts(&state.r);
        let g = -s.gravity[1];
        let mass = |r: f64| s.material.density * std::f64::consts::PI * r * r * s.particles.thickness;
        let weight = state.r.iter().map(|&r| mass(r) * g).sum();
        let geometry = PileGeometry {
            x: &state.x,
            y: &state.y,
            r: &state.r,
            weight,
            width: s.domain.width,
            thickness: s.particles.thickness,
            periodic: s.domain.periodic_x,
        };
        let surface = rec.pile["surface_height"];
        let band = 0.01;
        let edges: Vec<f64> = (0..).map(|k| k as f64 * band).take_while(|h| *h <= surface).collect();
        let profile = stress_profile(&geometry, &contacts, &edges);
        let k = rec.pile["stress_xx"] / rec.pile["stress_yy"];
        let bulk_density = weight / g / (s.domain.width * surface * s.particles.thickness);
        let walls = contacts.iter().filter(|c| matches!(c.partner, Partner::Wall(1 | 2)));
        let (shear, normal) = walls.fold((0.0, 0.0), |(t, n), c| (t + c.tangential_force.abs(), n + c.normal_force));
        let mobilised = shear / (wall_friction * normal);
        let janssen = |z: f64, friction: f64| {
            let length = s.domain.width / (2.0 * friction * k);
            bulk_density * g * length * (1.0 - (-z / length).exp())
        };
        println!(
            "{seed}  status {}, surface {surface:.4} m, floor load ratio {:.3}",
            rec.status.as_str(),
            rec.pile["floor_load_ratio"]
        );
        for (bottom, stress) in edges.iter().zip(&profile) {
            let depth = surface - (bottom + 0.5 * band);
            let predicted = janssen(depth, wall_friction);
            let actual = janssen(depth, mobilised * wall_friction);
            println!(
                "{seed}  {depth:.3}  {:.1}  {predicted:.1}  {:.3}  {k:.3}  {mobilised:.3}  {actual:.1}",
                stress.yy,
                stress.yy / predicted
            );
        }
    }
}
