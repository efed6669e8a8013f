//! One deposition timed, with a fingerprint of its final state: for before/after comparisons of
//! engine changes (`scripts/engine_compare.sh`).
//!
//! `cargo run --release --example engine_run -- SCENE [DURATION [THREADS [POOL]]]`: SCENE is `reference`
//! (the scene of `docs/reference_scene.md`, 1.5 s unless DURATION, in s, says otherwise) or a disk
//! count N (the reference deposition at N disks, the box widened with N, 0.1 s unless DURATION says
//! otherwise); THREADS (default 1): threads the run is given (used from 8 000 disks on), in a pool of
//! POOL threads (default THREADS; `… 40000 0.3 2 1` shows what the parallel path costs on one thread).
//! Prints `ns_per_particle_step=… steps=… fingerprint=…`, the fingerprint a hash of the bits of the
//! final positions, velocities, spins and angles (equal fingerprints: bit-identical final states).
//! `DEMSWEEP_VECTOR=baseline|avx2|avx512` runs the hot loops in that width (default: as detected);
//! `DEMSWEEP_PARALLEL_MIN_DISKS` sets from how many disks THREADS are used (default 8 000);
//! `ENGINE_RUN_VERLET=1` runs the scene with velocity Verlet instead of the paper's integrator;
//! `ENGINE_RUN_LAW=NAME` with that `contact.law` (e.g. `linear`, `hysteretic_linear`);
//! `ENGINE_RUN_ROLLING=μ0` with that `material.rolling_friction`; `ENGINE_RUN_CONTACT=TOML` with
//! that `[contact]` table (e.g. `damping = "viscous"`: a composition no preset has).

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use demsweep::bench::{reference_deposition, reference_disks};
use demsweep::physics::config::IntegratorKind;
use demsweep::physics::simulation::Control;
use demsweep::physics::{Threads, run_scene_on};
use demsweep::runner;

/// FNV-1a over the bits of every value.
fn fingerprint(columns: &[&Vec<f64>]) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    for value in columns.iter().flat_map(|c| c.iter()) {
        for byte in value.to_bits().to_le_bytes() {
            hash = (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3);
        }
    }
    hash
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: engine_run reference|N [DURATION [THREADS [POOL]]]";
    let which = args.first().expect(usage);
    let (mut s, disks) = if which == "reference" {
        (reference_deposition(300, 1.5), Some(reference_disks()))
    } else {
        (reference_deposition(which.parse().expect(usage), 0.1), None)
    };
    if let Some(d) = args.get(1) {
        s.run.duration = d.parse().expect(usage);
    }
    if std::env::var("ENGINE_RUN_VERLET").is_ok() {
        s.integrator.scheme = IntegratorKind::VelocityVerlet;
    }
    if let Ok(law) = std::env::var("ENGINE_RUN_LAW") {
        s.contact.law = toml::Value::String(law).try_into().expect("ENGINE_RUN_LAW: a contact.law name");
    }
    if let Ok(contact) = std::env::var("ENGINE_RUN_CONTACT") {
        s.contact = toml::from_str(&contact).expect("ENGINE_RUN_CONTACT: a [contact] table");
    }
    if let Ok(rolling) = std::env::var("ENGINE_RUN_ROLLING") {
        s.material.rolling_friction = rolling.parse().expect("ENGINE_RUN_ROLLING: a number");
    }
    let threads: usize = args.get(2).map_or(1, |t| t.parse().expect(usage));
    let pool_threads: usize = args.get(3).map_or(threads, |t| t.parse().expect(usage));
    runner::use_vector_width().unwrap_or_else(|e| panic!("{e}"));
    let min_disks = runner::parallel_min_disks().unwrap_or_else(|e| panic!("{e}"));
    let given = Threads { count: threads.max(1), min_disks };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(pool_threads).build().expect("a thread pool");
    let start = Instant::now();
    let rec = pool
        .install(|| run_scene_on(&s, disks, None, given, &AtomicBool::new(false), &mut |_| Control::Continue))
        .expect("scene runs");
    let seconds = start.elapsed().as_secs_f64();
    let f = &rec.final_state;
    let n = f.x.len() as f64;
    println!(
        "ns_per_particle_step={:.2} steps={} seconds={seconds:.3} fingerprint={:016x}",
        seconds * 1e9 / (n * rec.steps as f64),
        rec.steps,
        fingerprint(&[&f.x, &f.y, &f.vx, &f.vy, &f.omega, &f.angle])
    );
}
