//! demsweep as a library: a scene built in code, run to settle, its settle time and pile measures
//! printed. Writes nothing.
//!
//! `cargo run --release --example library` (a few seconds).

use demsweep::physics::{Control, RunStatus, SceneConfig};
use demsweep::physics::{RunError, run_scene};

fn main() -> Result<(), RunError> {
    // The paper's deposition, smaller: 60 disks of 1 cm radius poured into a 16 cm wide box.
    let mut scene = SceneConfig::default();
    scene.particles.count = 60;
    scene.domain.width = 0.16;
    scene.material.restitution = Some(0.5);
    scene.material.friction = 0.5;
    scene.run.duration = 1.5;

    // Every step reports its progress; returning `Control::Stop` would end the run early.
    let record = run_scene(&scene, None, &mut |_| Control::Continue)?;

    println!("status: {}", record.status);
    match (record.status, record.settle_time) {
        (RunStatus::Settled, Some(t)) => println!("settled at t = {t:.3} s after {} steps", record.steps),
        _ => println!("did not settle within {} s", scene.run.duration),
    }
    // Every pile metric, with its unit, from the one declaration of per-run quantities.
    for metric in demsweep::physics::quantity::PILE_METRICS {
        println!("{} ({}): {:.4}", metric.name, metric.unit, record.pile[metric.name]);
    }
    Ok(())
}
