use demsweep::physics::config::SceneConfig;
use demsweep::physics::simulation::{Control, run_scene};

fn main() {
    let mut scene = SceneConfig::default();
    scene.material.youngs_modulus = 20000.0;
    scene.material.shear_modulus = Some(20000.0);
    scene.material.beta = Some(10.0);
    scene.material.friction = 0.5;
    scene.material.rolling_friction = std::env::var("MU0").map(|v| v.parse().unwrap()).unwrap_or(0.5);
    scene.integrator.time_step = 1e-4;
    scene.run.duration = 3.0;
    scene.run.stop_at_settle = false;
    scene.limits.max_overlap_ratio = 10.0;
    let t0 = std::time::Instant::now();
    let rec = run_scene(&scene, None, &mut |_| Control::Continue).unwrap();
    println!(
        "status {:?} {:?} settle {:?} steps {} wall {:.3}s",
        rec.status,
        rec.message,
        rec.settle_time,
        rec.steps,
        t0.elapsed().as_secs_f64()
    );
    for w in &rec.warnings {
        println!("W: {w}");
    }
    let h = &rec.history;
    for k in (0..h.len()).step_by(250) {
        println!(
            "t={:.3} KE={:.4e} PE={:.4} el={:.4e} diss={:.4} mech+diss={:.6} ubf={:.3e} contacts={} ovl={:.4}",
            h.time[k],
            h.kinetic_translational[k] + h.kinetic_rotational[k],
            h.potential[k],
            h.elastic[k],
            h.dissipated[k],
            h.mechanical[k] + h.dissipated[k],
            h.unbalanced_force_ratio[k],
            h.contacts[k],
            h.max_overlap_ratio[k]
        );
    }
    let below = rec.final_state.y.iter().filter(|y| **y < 0.0).count();
    println!("pile height {:.4} below floor {}", rec.pile_height(), below);
}
