//! Engine speed: nanoseconds per particle-step, on one thread unless said otherwise.
//!
//! `cargo bench --bench engine` runs
//! 1. the reference scene of `docs/reference_scene.md` (300 disks, E 1e9 Pa, e 0.5, μ 0.5,
//!    dt 1e-5 s, 1.5 s = 150 000 steps, to the end), median and best of 5 — LAMMPS: 120
//!    ns/particle-step here;
//! 2. the same deposition at N = 300, 3 000, 30 000 and 100 000 disks, the box widened with N so the
//!    pile depth stays the same, over the reference scene's 1.5 s (some 15 minutes in all), or over
//!    each of the comma-separated durations in `DEMSWEEP_BENCH_DURATION` (s; e.g. `0.4,1.5`; 0.4 s
//!    is the fall, the impacts and most of the settling); median (and best) of 5, 3, 1 and 1 runs
//!    (the short runs repeated, as a shared machine's speed drifts by tens of percent over seconds;
//!    the best run is the one least slowed by other tenants); `DEMSWEEP_BENCH_DURATION=none` skips
//!    them (the reference scene alone, e.g. to compare two builds side by side).
//!
//! 3. big depositions (10 000, 40 000 and 100 000 disks, 0.3 s) on 1 and 2 threads, alternated,
//!    best of 3 each (the rows `threads_1`, `threads_2`; at 40 000 disks two threads should take at
//!    most 0.6 of one's time).
//! 4. memory order: a pile of 40 000 disks (the reference deposition's, on a touching hexagonal
//!    lattice) given in shuffled order, as a pile from another code's file may come, 0.05 s, with
//!    the engine's default numbering (renumbered before the first step:
//!    `src/physics/memory_order.rs`) and with the numbering kept, alternated, best of 3 each (rows
//!    `memory_default`, `memory_kept`).
//!
//! Results are printed and written to `results/bench_latest/engine.csv` (git ignores it);
//! `cargo bench --bench engine -- --update-results` writes the committed `results/bench/engine.csv`
//! instead.

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use demsweep::bench::{reference_deposition, reference_disks};
use demsweep::physics::config::{PlacementKind, SceneConfig};
use demsweep::physics::contact::HertzMindlin;
use demsweep::physics::memory_order::MemoryOrder;
use demsweep::physics::particles::InitialDisk;
use demsweep::physics::rng::Rng;
use demsweep::physics::simulation::Control;
use demsweep::physics::{Simulation, Threads, placement, run_scene_on};

/// Runs a scene once on `threads` threads; returns (ns per particle-step, steps, contacts at the end).
fn time_run(scene: &SceneConfig, disks: Option<Vec<InitialDisk>>, threads: usize) -> (f64, u64, u32) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
    let start = Instant::now();
    let rec = pool
        .install(|| {
            run_scene_on(scene, disks, None, Threads::new(threads), &AtomicBool::new(false), &mut |_| Control::Continue)
        })
        .expect("scene runs");
    let seconds = start.elapsed().as_secs_f64();
    let n = rec.final_state.x.len() as f64;
    (seconds * 1e9 / (n * rec.steps as f64), rec.steps, *rec.history.contacts.last().unwrap_or(&0))
}

/// Runs the Hertz-Mindlin `scene` from `disks` once on one thread with `policy`; returns (ns per
/// particle-step, steps).
fn time_policy(scene: &SceneConfig, disks: &[InitialDisk], policy: MemoryOrder) -> (f64, u64) {
    let mut sim = Simulation::<HertzMindlin>::new(scene, disks);
    sim.set_memory_order(policy);
    let start = Instant::now();
    let rec = sim.run(&mut |_| Control::Continue);
    (start.elapsed().as_secs_f64() * 1e9 / (disks.len() as f64 * rec.steps as f64), rec.steps)
}

/// The memory-order case: a pile of the reference deposition's `n` disks on a touching hexagonal
/// lattice, in shuffled order.
fn shuffled_pile(n: usize) -> (SceneConfig, Vec<InitialDisk>) {
    let mut scene = reference_deposition(n, 0.05);
    scene.placement.kind = PlacementKind::Lattice;
    (scene.placement.lattice_hexagonal, scene.placement.lattice_gap) = (true, 0.0);
    let mut disks = placement::generate(&scene).expect("placement");
    Rng::new(7).shuffle(&mut disks);
    (scene, disks)
}

/// The big scenes run on 1 and 2 threads: disks, simulated seconds (the fall and the first impacts).
const THREADS_CASES: [(usize, f64); 3] = [(10_000, 0.3), (40_000, 0.3), (100_000, 0.3)];

fn main() {
    // Names, then units (the header of every CSV demsweep writes, docs/results.md).
    let mut csv =
        String::from("case,particles,steps,ns_per_particle_step,best_ns_per_particle_step,final_contacts\n,,,ns,ns,\n");
    let mut scene = reference_deposition(300, 1.5);
    scene.placement.kind = PlacementKind::File;
    scene.placement.file = Some("tests/data/deposition_300.csv".into());
    let mut times: Vec<f64> = (0..5).map(|_| time_run(&scene, Some(reference_disks()), 1).0).collect();
    times.sort_by(f64::total_cmp);
    println!(
        "reference scene (300 disks, 150 000 steps): {:.1} ns/particle-step (median of 5; best {:.1}; all {times:.1?})",
        times[2], times[0]
    );
    csv += &format!("reference,300,150000,{:.2},{:.2},\n", times[2], times[0]);

    // Big runs on 1 and 2 threads, alternated (a shared machine's speed drifts), best of 3.
    for (n, duration) in THREADS_CASES {
        let big = reference_deposition(n, duration);
        let mut best = [f64::INFINITY; 2];
        let mut last = (0, 0);
        for _ in 0..3 {
            for (slot, threads) in [1, 2].into_iter().enumerate() {
                let (ns, steps, contacts) = time_run(&big, None, threads);
                best[slot] = best[slot].min(ns);
                last = (steps, contacts);
            }
        }
        println!(
            "N = {n}, {duration} s on 1 / 2 threads: {:.1} / {:.1} ns/particle-step (best of 3), 2 threads take {:.2} of the time",
            best[0],
            best[1],
            best[1] / best[0]
        );
        for (slot, threads) in [1, 2].into_iter().enumerate() {
            csv += &format!(
                "threads_{threads},{n},{},{:.2},{:.2},{}
",
                last.0, best[slot], best[slot], last.1
            );
        }
    }

    let (scene, disks) = shuffled_pile(40_000);
    let policies = [("memory_default", MemoryOrder::default()), ("memory_kept", MemoryOrder::KEPT)];
    let mut best = [(f64::INFINITY, 0); 2];
    for _ in 0..3 {
        for (slot, (_, policy)) in policies.iter().enumerate() {
            let (ns, steps) = time_policy(&scene, &disks, *policy);
            best[slot] = (best[slot].0.min(ns), steps);
        }
    }
    println!(
        "N = 40000, a pile given shuffled, 0.05 s: {:.1} ns/particle-step renumbered (the default), {:.1} kept (best of 3)",
        best[0].0, best[1].0
    );
    for ((name, _), (ns, steps)) in policies.iter().zip(best) {
        csv += &format!("{name},40000,{steps},{ns:.2},{ns:.2},\n");
    }

    let durations = std::env::var("DEMSWEEP_BENCH_DURATION").unwrap_or_else(|_| "1.5".into());
    let durations = durations
        .split(',')
        .filter(|d| d.trim() != "none")
        .map(|d| d.trim().parse::<f64>().expect("DEMSWEEP_BENCH_DURATION: seconds or none"));
    let cases = [(300usize, 5), (3_000, 3), (30_000, 1), (100_000, 1)];
    for (duration, (n, repeats)) in durations.flat_map(|d| cases.map(|case| (d, case))) {
        let s = reference_deposition(n, duration);
        let mut runs: Vec<_> = (0..repeats).map(|_| time_run(&s, None, 1)).collect();
        runs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let ((ns, steps, contacts), best) = (runs[repeats / 2], runs[0].0);
        println!(
            "N = {n:>6}, {duration} s: {ns:.1} ns/particle-step over {steps} steps, best {best:.1} ({contacts} contacts at the end)"
        );
        csv += &format!("scaling_{duration}s,{n},{steps},{ns:.2},{best:.2},{contacts}\n");
    }
    let update = std::env::args().any(|a| a == "--update-results");
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(if update {
        demsweep::bench::COMMITTED_DIR
    } else {
        demsweep::bench::LATEST_DIR
    });
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    let path = dir.join("engine.csv");
    std::fs::write(&path, csv).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    println!("wrote {}", path.display());
}
