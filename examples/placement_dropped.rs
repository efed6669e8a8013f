//! Dropped placement's cost and pile: seconds to place N disks (best of 3) next to random
//! placement's, at N = 10³ … 10⁶ (the reference scene's disks, the box widened with N so the pile
//! depth stays the same); then the interior packing fraction of dropped piles as placed and after
//! settling, against random placement settled, on the reference scene (300 disks, 4 seeds, E 1e9
//! Pa, e 0.5, μ 0.5, run until settled, at most 3 s), monodisperse and polydisperse (R 8-12 mm).
//!
//! `cargo run --release --example placement_dropped [N ...]` (default 1000 10000 100000 1000000);
//! `results/bench/placement_dropped.md` quotes it.

use std::time::Instant;

use demsweep::bench::reference_deposition;
use demsweep::physics::config::{PlacementKind, SceneConfig};
use demsweep::physics::particles::InitialDisk;
use demsweep::physics::pile::{PileGeometry, interior_packing_fraction};
use demsweep::physics::placement::{self, Fill};
use demsweep::physics::simulation::Control;

/// Best of 3 wall times (s) of placing the disks of `scene`, and the disks.
fn timed(scene: &SceneConfig) -> (f64, Vec<InitialDisk>) {
    let mut best = (f64::INFINITY, Vec::new());
    for _ in 0..3 {
        let start = Instant::now();
        let disks = placement::generate(scene).expect("placement");
        best = (best.0.min(start.elapsed().as_secs_f64()), disks);
    }
    best
}

fn interior(scene: &SceneConfig, x: &[f64], y: &[f64], r: &[f64]) -> f64 {
    interior_packing_fraction(&PileGeometry {
        x,
        y,
        r,
        weight: 0.0,
        width: scene.domain.width,
        thickness: scene.particles.thickness,
        periodic: scene.domain.periodic_x,
    })
}

fn interior_of(scene: &SceneConfig, disks: &[InitialDisk]) -> f64 {
    let column = |f: fn(&InitialDisk) -> f64| disks.iter().map(f).collect::<Vec<f64>>();
    interior(scene, &column(|d| d.x), &column(|d| d.y), &column(|d| d.r))
}

/// Interior packing fraction of the settled pile of `scene` started from `disks`, and its settle time.
fn settled(scene: &SceneConfig, disks: Vec<InitialDisk>) -> (f64, Option<f64>) {
    let rec = demsweep::physics::run_scene(scene, Some(disks), &mut |_| Control::Continue).expect("a run");
    let end = &rec.final_state;
    (interior(scene, &end.x, &end.y, &end.r), rec.settle_time)
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len() as f64
}

fn main() {
    let counts: Vec<usize> = std::env::args().skip(1).map(|a| a.parse().expect("a disk count")).collect();
    let counts = if counts.is_empty() { vec![1_000, 10_000, 100_000, 1_000_000] } else { counts };
    println!(
        "| N | dropped (s) | µs per disk | random (s) | dropped pile top / box height | area fraction below the top |"
    );
    println!("|---|---|---|---|---|---|");
    for n in counts {
        let mut scene = reference_deposition(n, 1.5);
        scene.placement.kind = PlacementKind::Dropped;
        let (dropped, disks) = timed(&scene);
        let fill = Fill::of(&scene, &disks);
        scene.placement.kind = PlacementKind::Random;
        let (random, _) = timed(&scene);
        println!(
            "| {n} | {dropped:.4} | {:.2} | {random:.4} | {:.3} | {:.3} |",
            dropped * 1e6 / n as f64,
            fill.height_fraction,
            fill.area_fraction
        );
    }
    println!();
    println!("| disks | dropped, as placed | dropped, settled | random, settled | settle time dropped / random (s) |");
    println!("|---|---|---|---|---|");
    for polydisperse in [false, true] {
        let (mut placed, mut from_dropped, mut from_random, mut times) = (vec![], vec![], vec![], vec![]);
        for seed in 1..=4 {
            let mut scene = reference_deposition(300, 3.0);
            scene.run.stop_at_settle = true;
            scene.placement.seed = seed;
            if polydisperse {
                (scene.particles.radius, scene.particles.radius_max) = (0.008, Some(0.012));
            }
            scene.placement.kind = PlacementKind::Dropped;
            let disks = placement::generate(&scene).expect("dropped placement");
            placed.push(interior_of(&scene, &disks));
            let (fraction, dropped_time) = settled(&scene, disks);
            from_dropped.push(fraction);
            scene.placement.kind = PlacementKind::Random;
            let (fraction, random_time) = settled(&scene, placement::generate(&scene).expect("random placement"));
            from_random.push(fraction);
            times.push(format!("{:.3} / {:.3}", dropped_time.unwrap_or(f64::NAN), random_time.unwrap_or(f64::NAN)));
        }
        println!(
            "| {} | {:.4} | {:.4} | {:.4} | {} |",
            if polydisperse { "R 8-12 mm" } else { "R 10 mm" },
            mean(&placed),
            mean(&from_dropped),
            mean(&from_random),
            times.join(", ")
        );
    }
}
