use demsweep::physics::config::{PlacementKind, SceneConfig};
use demsweep::physics::particles::InitialDisk;
use demsweep::physics::simulation::{Control, run_scene};

fn main() {
    let text = std::fs::read_to_string("../shared/reference/deposition_300.csv").unwrap();
    let disks: Vec<InitialDisk> = text
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            InitialDisk { x: v[0], y: v[1], r: v[2], ..Default::default() }
        })
        .collect();
    let mut scene = SceneConfig::default();
    scene.placement.kind = PlacementKind::File;
    scene.placement.file = Some("x".into());
    scene.material.restitution = Some(0.5);
    scene.run.stop_at_settle = std::env::args().nth(1).is_none();
    if let Ok(skin) = std::env::var("SKIN") {
        scene.neighbors.skin_ratio = skin.parse().unwrap();
    }
    let t0 = std::time::Instant::now();
    let rec = run_scene(&scene, Some(disks), &mut |_| Control::Continue).unwrap();
    let el = t0.elapsed().as_secs_f64();
    println!(
        "status {:?} {:?} settle {:?} steps {} wall {:.3}s ns/particle-step {:.1}",
        rec.status,
        rec.message,
        rec.settle_time,
        rec.steps,
        el,
        el * 1e9 / (rec.steps as f64 * 300.0)
    );
    println!("warnings {:?}", rec.warnings);
    println!("stability {:?}", rec.stability);
    let h = &rec.history;
    for t in [0.1, 0.2, 0.3, 0.5, 0.6, 1.0, 1.5] {
        if let Some(k) = h.time.iter().position(|x| (*x - t).abs() < 1e-9) {
            println!(
                "t={t} KE={:.4e} PE={:.4} el={:.4e} diss={:.4} mech+diss={:.6} ubf={:.3e} contacts={} ovl={:.4}",
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
    }
    println!("initial mech {:.6}", h.mechanical[0]);
}
