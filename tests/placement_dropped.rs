//! Dropped placement (`placement.kind = "dropped"`): no overlaps, every disk held by the floor or by
//! two contacts (disks, side walls) whose normals straddle the vertical, fixed by the seed; the pile
//! is at rest when simulated; and the lowered start keeps the impact speeds.

use demsweep::physics::config::{PlacementKind, SceneConfig};
use demsweep::physics::particles::InitialDisk;
use demsweep::physics::placement::{self, Fill};
use demsweep::physics::simulation::Control;

/// A dropped scene of `n` disks (radius 1 mm, or 0.5-1.5 mm `mixed`) in a box widened with `n`.
fn scene(n: usize, mixed: bool, seed: u64) -> SceneConfig {
    let mut s = SceneConfig::default();
    s.particles.count = n;
    s.particles.radius = if mixed { 0.0005 } else { 0.001 };
    s.particles.radius_max = mixed.then_some(0.0015);
    s.domain.width = 0.002 * (n as f64).sqrt() * 2.0;
    s.domain.height = 0.002 * (n as f64).sqrt();
    s.placement.kind = PlacementKind::Dropped;
    s.placement.seed = seed;
    s
}

/// For each disk, its neighbours closer than `reach` (surface to surface, m), from a grid.
fn neighbours(disks: &[InitialDisk], reach: f64) -> Vec<Vec<usize>> {
    let cell = 2.0 * disks.iter().map(|d| d.r).fold(0.0, f64::max) + reach;
    let key = |d: &InitialDisk| ((d.x / cell).floor() as i64, (d.y / cell).floor() as i64);
    let mut grid = std::collections::HashMap::<(i64, i64), Vec<usize>>::new();
    for (i, d) in disks.iter().enumerate() {
        grid.entry(key(d)).or_default().push(i);
    }
    let near = |(i, a): (usize, &InitialDisk)| {
        let (cx, cy) = key(a);
        let cells = (cx - 1..=cx + 1).flat_map(move |x| (cy - 1..=cy + 1).map(move |y| (x, y)));
        let found = cells.flat_map(|c| grid.get(&c).into_iter().flatten().copied());
        found.filter(|&j| j != i && (a.x - disks[j].x).hypot(a.y - disks[j].y) < a.r + disks[j].r + reach).collect()
    };
    disks.iter().enumerate().map(near).collect()
}

/// Whether two of the contact normals' angles (rad) hold a disk against gravity: one on each side
/// of the upward vertical, less than half a turn apart.
fn held(angles: &[f64]) -> bool {
    let (up, turn) = (std::f64::consts::FRAC_PI_2, std::f64::consts::TAU);
    let pairs = (0..angles.len()).flat_map(|i| (0..angles.len()).filter(move |&j| j != i).map(move |j| (i, j)));
    pairs
        .map(|(i, j)| (angles[i], angles[j].rem_euclid(turn)))
        .any(|(a, b)| (-up..=up).contains(&a) && (up..=3.0 * up).contains(&b) && b - a <= std::f64::consts::PI)
}

/// Checks a dropped pile: inside the box, no overlap, every disk on the floor or held by two
/// contacts (a gap below 1e-6 of the radii counts as a contact).
fn check_pile(s: &SceneConfig, disks: &[InitialDisk]) {
    assert_eq!(disks.len(), s.particles.count);
    let (w, h) = (s.domain.width, s.domain.height);
    let touch = 1e-6 * disks.iter().map(|d| d.r).fold(0.0, f64::max);
    for (i, (d, near)) in disks.iter().zip(neighbours(disks, touch)).enumerate() {
        assert!(d.x - d.r >= 0.0 && d.x + d.r <= w && d.y - d.r >= 0.0 && d.y + d.r <= h, "disk {i} {d:?}");
        let mut normals = Vec::new();
        for j in near {
            let e = &disks[j];
            let gap = (d.x - e.x).hypot(d.y - e.y) - (d.r + e.r);
            assert!(gap > 0.0, "disks {i} and {j} overlap by {}", -gap);
            normals.push((d.y - e.y).atan2(d.x - e.x));
        }
        if d.y - d.r < touch {
            continue;
        }
        if d.x - d.r < touch {
            normals.push(0.0);
        }
        if w - d.x - d.r < touch {
            normals.push(std::f64::consts::PI);
        }
        assert!(held(&normals), "disk {i} at ({}, {}) is not held: contact normals {normals:?}", d.x, d.y);
    }
}

#[test]
fn a_dropped_pile_has_no_overlap_and_every_disk_is_held() {
    for (n, mixed, seed) in [(2000, false, 1), (2000, true, 2), (100_000, true, 3)] {
        let s = scene(n, mixed, seed);
        check_pile(&s, &placement::generate(&s).unwrap_or_else(|e| panic!("{n} disks: {e}")));
    }
}

#[test]
fn the_seed_fixes_the_pile() {
    let s = scene(500, true, 7);
    let a = placement::generate(&s).unwrap();
    assert_eq!(a, placement::generate(&s).unwrap(), "same seed, same pile");
    let b = placement::generate(&scene(500, true, 8)).unwrap();
    assert_ne!(a, b);
    let moved = a.iter().zip(&b).filter(|(p, q)| p.x != q.x).count();
    assert!(moved > 400, "another seed is another pile: {moved} of 500 disks moved");
}

#[test]
fn a_narrow_box_holds_a_column_against_its_walls() {
    // 2.5 diameters across: every disk above the first row leans on a wall or lies in a pocket.
    let mut s = scene(200, false, 4);
    (s.domain.width, s.domain.height) = (0.005, 0.2);
    let disks = placement::generate(&s).unwrap();
    check_pile(&s, &disks);
    let on_walls = disks.iter().filter(|d| d.x - d.r < 1e-9 || s.domain.width - d.x - d.r < 1e-9).count();
    assert!(on_walls > 100, "{on_walls} disks touch a wall");
}

#[test]
fn a_box_too_low_says_how_many_disks_fit() {
    let mut s = scene(2000, false, 1);
    s.domain.height *= 0.3;
    let e = placement::generate(&s).unwrap_err();
    assert_eq!(e.key, "placement.kind");
    assert!(e.reason.starts_with("dropped placement fit only "), "{e}");
    assert!(
        e.reason.contains(" of 2000 disks in the 0.1788854382 m wide box below domain.height = 0.02683281573 m"),
        "{e}"
    );
    assert!(e.reason.contains("the next disk would rest with its top at 0.02"), "{e}");
}

#[test]
fn a_dropped_pile_is_denser_than_random_placement_and_fills_less_of_the_box() {
    let s = scene(2000, true, 5);
    let dropped = Fill::of(&s, &placement::generate(&s).unwrap());
    let mut random = s.clone();
    random.placement.kind = PlacementKind::Random;
    let random = Fill::of(&s, &placement::generate(&random).unwrap());
    assert!(dropped.area_fraction > 0.6 && dropped.area_fraction < 0.9, "{dropped:?}");
    assert!(dropped.top < 0.7 * random.top, "{dropped:?} {random:?}");
}

#[test]
fn a_dropped_pile_of_stiff_disks_stays_at_rest() {
    let mut s = SceneConfig::default();
    s.placement.kind = PlacementKind::Dropped;
    s.particles.radius_max = Some(0.015);
    s.material.youngs_modulus = 1e11;
    (s.integrator.time_step, s.integrator.contact_time_fraction) = (None, Some(0.05));
    (s.run.duration, s.run.stop_at_settle) = (0.05, false);
    let disks = placement::generate(&s).unwrap();
    let record = demsweep::physics::run_scene(&s, Some(disks.clone()), &mut |_| Control::Continue).unwrap();
    let end = &record.final_state;
    let moved = disks.iter().enumerate().map(|(i, d)| (end.x[i] - d.x).hypot(end.y[i] - d.y) / d.r).fold(0.0, f64::max);
    // Unheld, a disk would fall 12 mm (1.2 radii) in 0.05 s; held, the disks move as the contacts
    // take the pile's weight (softer disks compress the pile more and start local collapses).
    assert!(moved < 0.2, "a disk moved {moved} radii");
}

#[test]
fn a_dropped_pile_is_predicted_to_make_no_hard_impact() {
    let impact = |kind| {
        let mut s = SceneConfig::default();
        (s.placement.kind, s.material.youngs_modulus) = (kind, 2e8);
        let disks = placement::generate(&s).unwrap();
        let report = demsweep::physics::predict_stability(&s, &disks);
        report.warnings.iter().any(|w| w.kind == demsweep::physics::warning::WarningKind::ImpactOverlap)
    };
    assert!(impact(PlacementKind::Random), "disks falling from up to 0.6 m overlap too much on soft contacts");
    assert!(!impact(PlacementKind::Dropped), "dropped disks rest on the pile: they fall through no height");
}
