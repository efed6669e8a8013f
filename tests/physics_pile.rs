//! Pile metrics with known answers: a hexagonal lattice, a chain, settled piles with and without
//! wall friction.

mod common;

use demsweep::physics::config::{PlacementKind, SceneConfig};
use demsweep::physics::contact::HertzMindlin;
use demsweep::physics::contact_record::Partner;
use demsweep::physics::particles::InitialDisk;
use demsweep::physics::pile::{PileGeometry, fabric};
use demsweep::physics::run_scene;
use demsweep::physics::simulation::{Control, Simulation};
use demsweep::physics::stress::{band_stress, stress_profile};

/// A scene without gravity whose disks are given in memory, in a `width` x `height` box.
fn static_scene(width: f64, height: f64) -> SceneConfig {
    let mut s = SceneConfig::default();
    (s.domain.width, s.domain.height, s.gravity) = (width, height, [0.0, 0.0]);
    s.placement.kind = PlacementKind::File;
    s.placement.file = Some("in-memory".into());
    s
}

/// Disk centres of a hexagonal lattice with spacing `2 r (1 − 1e-6)` (every neighbour pair
/// overlaps slightly, so each contact carries force), `columns` x `rows`, resting on the floor.
fn hexagonal_lattice(r: f64, columns: usize, rows: usize) -> Vec<InitialDisk> {
    let a = 2.0 * r * (1.0 - 1e-6);
    let row_height = a * 3f64.sqrt() / 2.0;
    let row = |k: usize| (0..columns).map(move |j| (k, j));
    (0..rows)
        .flat_map(row)
        .map(|(k, j)| {
            let x = r + a * j as f64 + if k % 2 == 1 { 0.5 * a } else { 0.0 };
            InitialDisk { x, y: r + row_height * k as f64, r, ..Default::default() }
        })
        .collect()
}

#[test]
fn hexagonal_lattice_has_the_close_packed_fraction_and_six_contacts_inside() {
    let (r, columns, rows) = (0.01, 80, 90);
    let disks = hexagonal_lattice(r, columns, rows);
    let width = 2.0 * r * (columns as f64 + 0.5);
    let sim = Simulation::<HertzMindlin>::new(&static_scene(width, 3.0), &disks);
    let metrics = sim.pile_metrics();
    let close_packed = std::f64::consts::PI / (2.0 * 3f64.sqrt());
    println!("interior packing fraction {:.6} (hexagonal {close_packed:.6})", metrics["packing_fraction_interior"]);
    assert!((metrics["packing_fraction_interior"] / close_packed - 1.0).abs() < 0.005);
    let mut count = vec![0usize; disks.len()];
    for c in sim.contacts() {
        count[c.disk] += 1;
        if let Partner::Disk(j) = c.partner {
            count[j] += 1;
        }
    }
    let top = disks.iter().map(|d| d.y).fold(0.0, f64::max);
    let interior: Vec<usize> = (0..disks.len())
        .filter(|&i| disks[i].x > 0.1 && disks[i].x < width - 0.1 && disks[i].y > 0.1 && disks[i].y < top - 0.1)
        .collect();
    assert!(interior.len() > 3000);
    assert!(interior.iter().all(|&i| count[i] == 6), "every interior disk touches six");
    assert_eq!(metrics["rattler_fraction"], 0.0);
    println!("normal force width {:.3e} (every contact pressed alike)", metrics["normal_force_width"]);
    assert!(metrics["normal_force_width"] < 1e-6, "a uniformly loaded lattice has one normal force");
    assert!(
        metrics["coordination_number"] > 5.7 && metrics["coordination_number"] < 6.0,
        "{}",
        metrics["coordination_number"]
    );
}

#[test]
fn hexagonal_patch_is_isotropic() {
    // A hexagon of the lattice (axial coordinates |i|, |j|, |i + j| ≤ 6): the same number of
    // contacts along each of the three lattice directions.
    let (r, rings) = (0.01, 6i32);
    let a = 2.0 * r * (1.0 - 1e-6);
    let disks: Vec<InitialDisk> = (-rings..=rings)
        .flat_map(|i| (-rings..=rings).map(move |j| (i, j)))
        .filter(|(i, j)| (i + j).abs() <= rings)
        .map(|(i, j)| InitialDisk {
            x: 0.5 + a * (i as f64 + 0.5 * j as f64),
            y: 0.5 + a * 3f64.sqrt() / 2.0 * j as f64,
            r,
            ..Default::default()
        })
        .collect();
    let sim = Simulation::<HertzMindlin>::new(&static_scene(1.0, 1.0), &disks);
    let contacts = sim.contacts();
    assert_eq!(disks.len(), (3 * rings * rings + 3 * rings + 1) as usize);
    assert_eq!(contacts.len(), (3 * (3 * rings * rings + rings)) as usize, "bonds of a hexagon of {rings} rings");
    let (anisotropy, _) = fabric(&contacts);
    println!("hexagonal patch: {} contacts, anisotropy {anisotropy:.3e}", contacts.len());
    assert!(anisotropy.abs() < 1e-9);
}

#[test]
fn a_chain_of_disks_has_anisotropy_two_along_its_line() {
    let angle: f64 = 0.4;
    let a = 0.02 * (1.0 - 1e-6);
    let disks: Vec<InitialDisk> = (0..12)
        .map(|k| InitialDisk {
            x: 0.2 + a * k as f64 * angle.cos(),
            y: 0.2 + a * k as f64 * angle.sin(),
            r: 0.01,
            ..Default::default()
        })
        .collect();
    let metrics = Simulation::<HertzMindlin>::new(&static_scene(1.0, 1.0), &disks).pile_metrics();
    assert!((metrics["fabric_anisotropy"] - 2.0).abs() < 1e-9, "{}", metrics["fabric_anisotropy"]);
    assert!((metrics["fabric_direction"] - angle).abs() < 1e-9, "{}", metrics["fabric_direction"]);
    assert!((metrics["coordination_number"] - 2.0 * 11.0 / 12.0).abs() < 1e-12);
    assert_eq!(metrics["rattler_fraction"], 1.0, "a chain has two disks with one contact, and unravels from there");
}

/// A pile of `count` disks poured into a `width`-wide box and run until it is at rest.
/// At rest: the unbalanced force ratio bounds the floor's deviation from the weight (the disks' net
/// vertical forces add up to floor load minus weight).
fn settled_pile(count: usize, width: f64, height: f64, wall_friction: f64) -> demsweep::physics::RunRecord {
    let mut s = SceneConfig::default();
    s.particles.count = count;
    s.particles.radius_max = Some(0.012);
    (s.domain.width, s.domain.height) = (width, height);
    s.wall_material.friction = Some(wall_friction);
    s.material.restitution = Some(0.3);
    s.settle.ubf_threshold = 2e-4;
    s.settle.hold_time = 0.05;
    s.run.duration = 3.0;
    let rec = run_scene(&s, None, &mut |_| Control::Continue).unwrap();
    assert_eq!(rec.status.as_str(), "settled", "{:?}", rec.message);
    rec
}

#[test]
fn frictionless_side_walls_put_the_whole_weight_on_the_floor() {
    let rec = settled_pile(120, 0.2, 0.8, 0.0);
    println!("frictionless walls: floor load ratio {:.5}", rec.pile["floor_load_ratio"]);
    assert!((rec.pile["floor_load_ratio"] - 1.0).abs() < 0.01);
    let (width, floor_force) = (rec.pile["normal_force_width"], rec.pile["floor_mean_contact_force"]);
    println!("normal force width {width:.4}, floor mean contact force {floor_force:.4e} N");
    assert!(width > 0.2 && width < 2.0, "a pile under its weight is loaded unevenly (force chains)");
    assert!(floor_force > 0.0, "the floor carries the pile");
    // The surface height is the height of the bulk: the disk area over the width at it packs about as
    // densely as the interior, while the highest disk top lies above it.
    let area: f64 = rec.final_state.r.iter().map(|r| std::f64::consts::PI * r * r).sum();
    let (surface, top) = (rec.pile["surface_height"], rec.pile["pile_height"]);
    let packing = area / (0.2 * surface);
    println!("surface height {surface:.5} m, pile height {top:.5} m, packing below the surface {packing:.4}");
    assert!(surface < top, "{surface} against {top}");
    assert!((packing / rec.pile["packing_fraction_interior"] - 1.0).abs() < 0.1, "{packing}");
}

#[test]
fn the_stress_of_a_pile_at_rest_balances_its_weight() {
    // 120 disks settled with frictionless side walls: across every horizontal line the contacts
    // carry the weight of the disks above it, so each band's σ_yy times the width and thickness is
    // the band's mean of that weight; just above the floor (below every centre) it is the whole
    // weight.
    let rec = settled_pile(120, 0.2, 0.8, 0.0);
    let state = &rec.final_state;
    let contacts = state.contacts.pile_contacts(&state.r);
    let default = SceneConfig::default();
    let (density, thickness, g) = (default.material.density, default.particles.thickness, -default.gravity[1]);
    let weights: Vec<f64> = state.r.iter().map(|r| density * std::f64::consts::PI * r * r * thickness * g).collect();
    let total: f64 = weights.iter().sum();
    let geometry =
        PileGeometry { x: &state.x, y: &state.y, r: &state.r, weight: total, width: 0.2, thickness, periodic: false };
    let lowest_centre = state.y.iter().cloned().fold(f64::INFINITY, f64::min);
    let floor = band_stress(&geometry, &contacts, [0.0, 0.5 * lowest_centre]);
    println!("floor band: σ_yy W h = {:.6} N, weight {total:.6} N", floor.yy * 0.2 * thickness);
    assert!((floor.yy * 0.2 * thickness / total - 1.0).abs() < 0.01, "{floor:?}");
    // Bands of 2 cm through the pile: the mean over the band of the weight above each line in it.
    let weight_above_mean = |[bottom, top]: [f64; 2]| {
        let lines = 200;
        let weight_above = |h: f64| state.y.iter().zip(&weights).filter(|(y, _)| **y > h).map(|(_, w)| w).sum::<f64>();
        (0..lines).map(|k| weight_above(bottom + (k as f64 + 0.5) / lines as f64 * (top - bottom))).sum::<f64>()
            / lines as f64
    };
    let top = rec.pile["surface_height"];
    let edges: Vec<f64> = (0..).map(|k| 0.02 * k as f64).take_while(|h| *h < top).collect();
    for (band, stress) in edges.windows(2).zip(stress_profile(&geometry, &contacts, &edges)) {
        let expected = weight_above_mean([band[0], band[1]]);
        let carried = stress.yy * 0.2 * thickness;
        println!("band {:.2}-{:.2} m: σ_yy W h {carried:.5} N, weight above {expected:.5} N", band[0], band[1]);
        assert!((carried - expected).abs() < 0.01 * total, "band {band:?}: {carried} against {expected}");
    }
    // The pile's mean stress is compressive, vertical larger than horizontal without wall friction.
    let (p, q) = (rec.pile["stress_pressure"], rec.pile["stress_deviatoric"]);
    assert!(p > 0.0 && q > 0.0 && rec.pile["stress_yy"] > rec.pile["stress_xx"], "{p} {q}");
}

#[test]
fn wall_friction_carries_part_of_a_narrow_column() {
    let rec = settled_pile(60, 0.05, 1.2, 0.8);
    println!("wall friction 0.8, narrow column: floor load ratio {:.5}", rec.pile["floor_load_ratio"]);
    assert!(rec.pile["floor_load_ratio"] < 0.95, "the walls carry weight (Janssen)");
    assert!(rec.pile["floor_load_ratio"] > 0.1);
}
