//! Whether re-sorting the disks of a large deposition in memory would make its steps faster:
//! deposits N disks for T1 seconds, then continues from that state for T2 seconds with the disks
//! (a) in the order they have, (b) re-sorted in strips as placement orders them, and (c) in a random
//! order (how much memory order matters at all); and (d) from a second deposit whose disks were
//! placed in columns whatever the box's shape (placement's order for a wide box), as that deposit
//! left them; alternated over ROUNDS rounds.
//!
//! `cargo run --release --example memory_order -- N T1 T2 [ROUNDS [THREADS [WIDTH]]]` (WIDTH: the
//! box's width in m, its height then set for the same area as the reference deposition's) prints, per
//! continuation, `order=… ns_per_particle_step=…`, and the share of contacts whose two disks are
//! more than 512 places apart in memory (one integrator chunk) in each order. The continuations
//! start without tangential springs (the same for all four), so they time the same kind of steps,
//! not the same trajectory.

use std::time::Instant;

use demsweep::bench::reference_deposition;
use demsweep::physics::config::SceneConfig;
use demsweep::physics::particles::InitialDisk;
use demsweep::physics::placement::{self, order_for_locality};
use demsweep::physics::record::Snapshot;
use demsweep::physics::rng::Rng;
use demsweep::physics::simulation::Control;
use demsweep::physics::{Threads, run_scene_on};

/// The disks of a snapshot, in its order.
fn disks_of(s: &Snapshot) -> Vec<InitialDisk> {
    (0..s.x.len())
        .map(|k| InitialDisk {
            x: s.x[k],
            y: s.y[k],
            r: s.r[k],
            vx: s.vx[k],
            vy: s.vy[k],
            omega: s.omega[k],
            angle: s.angle[k],
        })
        .collect()
}

/// Share of the disk-disk contacts of a snapshot whose disks are more than 512 places apart.
fn far_share(s: &Snapshot) -> f64 {
    let c = &s.contacts;
    let disk_pairs = c.first.iter().zip(&c.second).filter(|(_, j)| **j >= 0);
    let (far, all) =
        disk_pairs.fold((0, 0), |(far, all), (i, j)| (far + usize::from((i64::from(*i) - j).abs() > 512), all + 1));
    far as f64 / all.max(1) as f64
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: memory_order N T1 T2 [ROUNDS [THREADS [WIDTH]]]";
    let number = |k: usize| args.get(k).expect(usage).parse::<f64>().expect(usage);
    let (count, deposit, cont) = (number(0) as usize, number(1), number(2));
    let rounds = args.get(3).map_or(3, |r| r.parse().expect(usage));
    let threads = Threads::new(args.get(4).map_or(1, |t| t.parse().expect(usage)));
    let run = |scene: &SceneConfig, disks: Option<Vec<InitialDisk>>| {
        run_scene_on(scene, disks, None, threads, &mut |_| Control::Continue).expect("scene runs")
    };
    let box_of = |duration| {
        let mut scene = reference_deposition(count, duration);
        if let Some(width) = args.get(5).map(|w| w.parse::<f64>().expect(usage)) {
            scene.domain.height *= scene.domain.width / width;
            scene.domain.width = width;
        }
        scene
    };
    let deposit_box = box_of(deposit);
    let first = run(&deposit_box, None);
    let scene = box_of(cont);
    let as_is = disks_of(&first.final_state);
    let mut strips = as_is.clone();
    let r_max = as_is.iter().map(|d| d.r).fold(0.0, f64::max);
    order_for_locality(&mut strips, scene.domain.width, scene.domain.height, 2.0 * r_max);
    let mut shuffled = as_is.clone();
    let mut rng = Rng::new(7);
    for k in (1..shuffled.len()).rev() {
        shuffled.swap(k, (rng.next_u64() % (k as u64 + 1)) as usize);
    }
    let mut columns = placement::generate(&deposit_box).expect("placement");
    // Placement's order for a box wider than tall: columns.
    order_for_locality(&mut columns, 1.0, 0.0, 2.0 * r_max);
    let second = run(&deposit_box, Some(columns));
    let columns_placed = disks_of(&second.final_state);
    let (far, far_columns) = (far_share(&first.final_state), far_share(&second.final_state));
    println!("after the deposit: far contacts {far:.4}; placed in columns: {far_columns:.4}");
    for round in 0..rounds {
        for (name, disks) in
            [("as_is", &as_is), ("strips", &strips), ("shuffled", &shuffled), ("columns_placed", &columns_placed)]
        {
            let start = Instant::now();
            let rec = run(&scene, Some(disks.clone()));
            let seconds = start.elapsed().as_secs_f64();
            let ns = seconds * 1e9 / (count as f64 * rec.steps as f64);
            let far = far_share(&rec.final_state);
            println!("round={round} order={name} ns_per_particle_step={ns:.2} far_contacts_at_end={far:.4}");
        }
    }
}
