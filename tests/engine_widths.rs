//! The hot loops give the same bits in every vector width the CPU has (baseline, AVX2, AVX-512):
//! the width the engine picks on a machine changes its speed, never its results.

use std::process::Command;
use std::sync::atomic::AtomicBool;

use demsweep::physics::config::{ContactLawKind, IntegratorKind, SceneConfig};
use demsweep::physics::simulation::Control;
use demsweep::physics::vector::{self, Width};
use demsweep::physics::{Threads, run_scene_on};

/// A deposition of 700 disks over 0.25 s with friction: the paper's integrator and Hertz-Mindlin
/// (variant 0), the same with local and viscous damping (1), or velocity Verlet with rolling
/// friction, local damping and a law with state (2).
fn scene(variant: u8) -> SceneConfig {
    let mut s = SceneConfig::default();
    s.particles.count = 700;
    s.domain.width = 0.9;
    s.material.restitution = Some(0.5);
    s.material.friction = 0.5;
    s.integrator.contact_time_fraction = Some(0.1);
    s.run.duration = 0.25;
    s.run.stop_at_settle = false;
    if variant == 1 {
        (s.damping.local, s.damping.viscous) = (0.1, 2.0);
    }
    if variant == 2 {
        s.integrator.scheme = IntegratorKind::VelocityVerlet;
        s.material.rolling_friction = 0.05;
        s.damping.local = 0.1;
        s.contact.law = ContactLawKind::HystereticLinear;
    }
    s
}

/// The bits of the final state and the kinetic energy history of `scene` run in `width`.
fn bits_in(width: Width, scene: &SceneConfig) -> Vec<u64> {
    assert_eq!(vector::use_width(width), width);
    let record =
        run_scene_on(scene, None, None, Threads::new(1), &AtomicBool::new(false), &mut |_| Control::Continue).unwrap();
    let (f, h) = (&record.final_state, &record.history);
    let columns = [&f.x, &f.y, &f.vx, &f.vy, &f.omega, &f.angle, &f.contact_force, &h.kinetic_translational];
    columns.iter().flat_map(|c| c.iter().map(|v| v.to_bits())).collect()
}

#[test]
fn every_vector_width_gives_the_same_bits() {
    let widths: Vec<Width> = Width::ALL.into_iter().filter(|w| w.supported()).collect();
    if widths.len() < 2 {
        eprintln!("only {widths:?} on this CPU: nothing to compare");
        return;
    }
    for variant in [0, 1, 2] {
        let s = scene(variant);
        let first = bits_in(widths[0], &s);
        assert!(first.len() > 7 * 700);
        for &width in &widths[1..] {
            assert!(bits_in(width, &s) == first, "{width:?} differs from {:?} (variant {variant})", widths[0]);
        }
    }
}

#[test]
fn an_unknown_width_is_refused_by_name() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("engine_widths_cli");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("tiny.toml");
    std::fs::write(&study, "name = \"tiny\"\n[scene]\nparticles.count = 20\nrun.duration = 0.01\n").unwrap();
    let run = |width: &str| {
        Command::new(env!("CARGO_BIN_EXE_demsweep"))
            .args(["run", study.to_str().unwrap(), "--out", dir.join(width).to_str().unwrap(), "--progress", "quiet"])
            .env("DEMSWEEP_VECTOR", width)
            .output()
            .unwrap()
    };
    assert!(run("baseline").status.success());
    let bad = run("avx1024");
    let message = String::from_utf8_lossy(&bad.stderr);
    assert!(!bad.status.success() && message.contains("DEMSWEEP_VECTOR") && message.contains("avx512"), "{message}");
}
