//! What numbering the disks afresh at neighbour-list builds ([`demsweep::physics::memory_order`])
//! gains in a large deposition: deposits N disks for T1 seconds from the same placement twice, with
//! the disks' numbering kept and with the engine's default (renumbered where neighbours drifted
//! apart in memory); then, from the kept deposit's state (mixed by its fall), times T2 seconds with
//! the numbering kept, with the default, and from the disks shuffled with the default (how quickly
//! it recovers any order), alternated over ROUNDS rounds.
//!
//! `cargo run --release --example memory_order -- N T1 T2 [ROUNDS [THREADS [WIDTH]]]` (WIDTH: the
//! box's width in m, its height then set for the same area as the reference deposition's) prints,
//! per run, `order=… ns_per_particle_step=… renumberings=… far_contacts_at_end=…`, the last being
//! the share of disk-disk contacts whose disks are more than 512 places apart in memory. The steps
//! are taken without samples; the continuations start without tangential springs (the same for
//! all), so they time the same kind of steps, not the same trajectory.

use std::time::Instant;

use demsweep::bench::reference_deposition;
use demsweep::physics::config::SceneConfig;
use demsweep::physics::contact::HertzMindlin;
use demsweep::physics::memory_order::{FAR_PLACES, MemoryOrder};
use demsweep::physics::particles::InitialDisk;
use demsweep::physics::placement;
use demsweep::physics::record::Snapshot;
use demsweep::physics::rng::Rng;
use demsweep::physics::{Simulation, Threads};

/// Share of the disk-disk contacts whose disks sit more than [`FAR_PLACES`] places apart in the
/// simulation's own numbering.
fn far_share(sim: &Simulation<HertzMindlin>) -> f64 {
    let places = sim.numbering().places();
    let place = |k: usize| places.as_ref().map_or(k as i64, |p| i64::from(p[k]));
    let c = &sim.snapshot().contacts;
    let pairs = c.first.iter().zip(&c.second).filter(|(_, j)| **j >= 0);
    let (far, all) = pairs.fold((0, 0), |(far, all), (&i, &j)| {
        let apart = (place(i as usize) - place(j as usize)).abs() > i64::from(FAR_PLACES);
        (far + usize::from(apart), all + 1)
    });
    far as f64 / all.max(1) as f64
}

/// Runs `scene` from `disks` on `threads` with `policy`; prints and returns the final state.
fn timed(scene: &SceneConfig, disks: &[InitialDisk], threads: Threads, policy: MemoryOrder, name: &str) -> Snapshot {
    let mut sim = Simulation::<HertzMindlin>::new(scene, disks);
    sim.set_threads(threads);
    sim.set_memory_order(policy);
    let steps = scene.total_steps(sim.time_step());
    let start = Instant::now();
    for _ in 0..steps {
        sim.advance(false);
    }
    let ns = start.elapsed().as_secs_f64() * 1e9 / (disks.len() as f64 * steps as f64);
    let (renumberings, far) = (sim.numbering().renumberings(), far_share(&sim));
    println!("order={name} ns_per_particle_step={ns:.2} renumberings={renumberings} far_contacts_at_end={far:.4}");
    sim.snapshot()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: memory_order N T1 T2 [ROUNDS [THREADS [WIDTH]]]";
    let number = |k: usize| args.get(k).expect(usage).parse::<f64>().expect(usage);
    let (count, deposit, cont) = (number(0) as usize, number(1), number(2));
    let rounds = args.get(3).map_or(3, |r| r.parse().expect(usage));
    let threads = Threads::new(args.get(4).map_or(1, |t| t.parse().expect(usage)));
    let box_of = |duration| {
        let mut scene = reference_deposition(count, duration);
        if let Some(width) = args.get(5).map(|w| w.parse::<f64>().expect(usage)) {
            scene.domain.height *= scene.domain.width / width;
            scene.domain.width = width;
        }
        scene
    };
    let deposit_box = box_of(deposit);
    let placed = placement::generate(&deposit_box).expect("placement");
    let mixed = timed(&deposit_box, &placed, threads, MemoryOrder::KEPT, "deposit_kept").initial_disks();
    timed(&deposit_box, &placed, threads, MemoryOrder::default(), "deposit_default");
    let mut shuffled = mixed.clone();
    Rng::new(7).shuffle(&mut shuffled);
    let scene = box_of(cont);
    for round in 0..rounds {
        println!("round={round}");
        timed(&scene, &mixed, threads, MemoryOrder::KEPT, "kept");
        timed(&scene, &mixed, threads, MemoryOrder::default(), "default");
        timed(&scene, &shuffled, threads, MemoryOrder::default(), "shuffled_default");
    }
}
