//! Periodic sides (`domain.periodic_x`): contacts across the boundary conserve momentum and energy
//! and act as they do in the middle of a box, a disk leaving on one side comes back on the other, a
//! settled periodic pile packs as the middle of a wide walled one, and the values the option cannot
//! work with are refused.

mod common;

use common::*;
use demsweep::physics::config::{IntegratorKind, SceneConfig};
use demsweep::physics::contact::HertzMindlin;
use demsweep::physics::particles::InitialDisk;
use demsweep::physics::pile::disk_area_in_rectangle;
use demsweep::physics::run_scene;
use demsweep::physics::simulation::{Control, Simulation};

const R: f64 = 0.01;
const WIDTH: f64 = 1.0;

/// A box without gravity, `WIDTH` wide, periodic or walled, stepped at `dt`; friction `friction`.
fn scene(periodic: bool, friction: f64, dt: f64) -> SceneConfig {
    let mut s = free_scene(1e7, IntegratorKind::VelocityVerlet, dt);
    s.domain.width = WIDTH;
    s.domain.periodic_x = periodic;
    s.material.friction = friction;
    s
}

/// Two disks drifting right at `drift` (m/s) that meet head-on (1 m/s apart) with the second
/// `offset` (m) higher, their contact starting at `x = meet` (m).
fn pair(meet: f64, drift: f64, offset: f64) -> [InitialDisk; 2] {
    let gap = 0.1 * R;
    let at = |x: f64| x.rem_euclid(WIDTH);
    [
        InitialDisk { x: at(meet - R - gap), y: 0.5, r: R, vx: drift + 0.5, ..Default::default() },
        InitialDisk { x: at(meet + R), y: 0.5 + offset, r: R, vx: drift - 0.5, ..Default::default() },
    ]
}

/// Steps `disks` until well after their impact; returns the simulation and the relative
/// velocity, the spins and the total momentum at the end, and the largest x seen.
fn collide(scene: &SceneConfig, disks: &[InitialDisk; 2], steps: usize) -> (Simulation<HertzMindlin>, [f64; 6], f64) {
    let mut sim = Simulation::<HertzMindlin>::new(scene, disks);
    let mut largest = 0.0_f64;
    for _ in 0..steps {
        sim.advance(false);
        largest = sim.particles().x.iter().copied().fold(largest, f64::max);
    }
    let p = sim.particles();
    let m = &p.mass;
    let motion = [
        p.vx[1] - p.vx[0],
        p.vy[1] - p.vy[0],
        p.omega[0],
        p.omega[1],
        m[0] * p.vx[0] + m[1] * p.vx[1],
        m[0] * p.vy[0] + m[1] * p.vy[1],
    ];
    (sim, motion, largest)
}

/// Kinetic energy, spin included (a disk's moment of inertia is `m r² / 2`).
fn kinetic(sim: &Simulation<HertzMindlin>) -> f64 {
    let p = sim.particles();
    (0..p.x.len())
        .map(|i| {
            0.5 * p.mass[i] * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + 0.5 * p.r[i] * p.r[i] * p.omega[i] * p.omega[i])
        })
        .sum()
}

/// The impact's step and the steps to run past it: 50 steps per Hertz contact, four contacts long.
fn stepping() -> (f64, usize) {
    let (_, duration) = hertz_impact(same_material_e_star(1e7, 0.3), R / 2.0, disk_mass(R) / 2.0, 1.0);
    (duration / 50.0, 400)
}

#[test]
fn a_head_on_impact_across_the_boundary_conserves_momentum_and_energy() {
    let (dt, steps) = stepping();
    let disks = pair(0.0, 0.0, 0.0);
    assert!(disks[0].x > 0.9 && disks[1].x < 0.1, "the disks start on either side: {disks:?}");
    let s = scene(true, 0.0, dt);
    let before = kinetic(&Simulation::<HertzMindlin>::new(&s, &disks));
    let (sim, motion, _) = collide(&s, &disks, steps);
    let p = sim.particles();
    assert!((motion[0] - 1.0).abs() < 1e-3, "elastic rebound: relative velocity {}", motion[0]);
    assert!(motion[4].abs() < 1e-15 * p.mass[0], "momentum stays 0: {}", motion[4]);
    assert!(((kinetic(&sim) - before) / before).abs() < 1e-3, "energy {} before, {} after", before, kinetic(&sim));
    assert!(p.x.iter().all(|x| (0.0..WIDTH).contains(x)), "positions stay in the box: {:?}", p.x);
    assert!(p.x[0] > 0.9 && p.x[1] < 0.1, "the disks went back where they came from: {:?}", p.x);
}

#[test]
fn an_oblique_impact_drifting_across_the_boundary_is_the_impact_in_the_middle_of_a_box() {
    // Frictional, so that the tangential spring carries the outcome; the pair drifts 2 m/s, about
    // a disk diameter per contact time, so that the first disk wraps around while they touch.
    let (dt, steps) = stepping();
    let (drift, offset) = (2.0, 0.8 * R);
    let (sim, periodic, largest) = collide(&scene(true, 0.5, dt), &pair(0.0, drift, offset), steps);
    let (_, middle, _) = collide(&scene(false, 0.5, dt), &pair(0.3, drift, offset), steps);
    assert!(largest > WIDTH - 2.0 * R && sim.particles().x.iter().all(|x| *x < 0.5), "both disks wrapped around");
    assert!(middle[2].abs() > 1.0, "friction spun the disks: {} rad/s", middle[2]);
    for (a, b) in periodic.iter().zip(&middle) {
        assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "across the boundary {periodic:?}, in the middle {middle:?}");
    }
    let momentum = 2.0 * sim.particles().mass[0] * drift;
    assert!((periodic[4] - momentum).abs() < 1e-12 * momentum && periodic[5].abs() < 1e-12 * momentum, "{periodic:?}");
}

#[test]
fn a_lone_disk_leaves_on_one_side_and_comes_back_on_the_other_at_its_speed() {
    let (dt, _) = stepping();
    let disks = [InitialDisk { x: WIDTH - 0.5 * R, y: 0.5, r: R, vx: 3.0, vy: -0.25, ..Default::default() }];
    let mut sim = Simulation::<HertzMindlin>::new(&scene(true, 0.5, dt), &disks);
    for _ in 0..100 {
        sim.advance(false);
    }
    let p = sim.particles();
    let travelled = 100.0 * dt * 3.0;
    assert!((p.x[0] - (travelled - 0.5 * R)).abs() < 1e-12, "wrapped to {}", p.x[0]);
    assert_eq!((p.vx[0], p.vy[0], p.omega[0]), (3.0, -0.25, 0.0), "no wall touched it");
}

#[test]
fn periodic_sides_need_two_largest_diameters_and_gravity_down_and_combine_with_a_lid_and_a_pour() {
    let mut s = SceneConfig::default();
    s.domain.periodic_x = true;
    s.domain.lid = true;
    assert_eq!(s.validate(), Ok(()), "periodic with a lid");
    s.placement.kind = demsweep::physics::config::PlacementKind::Pour;
    s.placement.pour.rate = Some(1000.0);
    assert_eq!(s.validate(), Ok(()), "periodic with a pour");
    (s.placement.kind, s.placement.pour) = (demsweep::physics::config::PlacementKind::Random, Default::default());
    s.domain.width = 3.5 * s.particles.radius * 2.0 / 2.0;
    let issues = s.validate().unwrap_err();
    assert_eq!(issues.len(), 1, "{issues:?}");
    assert_eq!(issues[0].key, "domain.width");
    assert!(
        issues[0].reason.contains("two largest disk diameters") && issues[0].reason.contains("0.04"),
        "{}",
        issues[0]
    );
    s.domain.periodic_x = false;
    assert_eq!(s.validate(), Ok(()), "walled, the same box is wide enough");
    (s.domain.periodic_x, s.domain.width, s.gravity) = (true, 0.4, [1.0, -9.81]);
    let issues = s.validate().unwrap_err();
    assert_eq!(issues[0].key, "domain.periodic_x", "{issues:?}");
    assert!(issues[0].reason.contains("gravity straight down"), "{}", issues[0]);
}

/// A pile of `count` disks (radii 0.008-0.012 m) poured at random into a box `width` wide (m),
/// periodic or walled, settled.
fn settled(count: usize, width: f64, periodic: bool, seed: u64) -> demsweep::physics::RunRecord {
    let mut s = SceneConfig::default();
    s.particles.count = count;
    // Radii spread by half: nearly equal disks order in a narrow periodic box.
    (s.particles.radius, s.particles.radius_max) = (0.008, Some(0.012));
    (s.domain.width, s.domain.height, s.domain.periodic_x) = (width, 0.6, periodic);
    s.placement.seed = seed;
    s.material.restitution = Some(0.3);
    s.settle.ubf_threshold = 2e-4;
    s.settle.hold_time = 0.05;
    // Nothing pins a periodic pile sideways: it creeps longer than between walls before it settles.
    s.run.duration = 6.0;
    let rec = run_scene(&s, None, &mut |_| Control::Continue).unwrap();
    let ubf = rec.history.unbalanced_force_ratio.last();
    assert_eq!(rec.status.as_str(), "settled", "periodic {periodic}, seed {seed}: unbalanced force ratio {ubf:?}");
    rec
}

/// Disk area over the area of the band `[x0, x1]` from two largest diameters above the floor to
/// two below the pile's surface height (its mean free surface, the same in a wide box as in a narrow
/// one, where the highest disk top rises with the width), the disks also at `x + shift` for each
/// of `shifts` (m).
fn band_packing(rec: &demsweep::physics::RunRecord, [x0, x1]: [f64; 2], shifts: &[f64]) -> f64 {
    let f = &rec.final_state;
    let d_max = 2.0 * f.r.iter().copied().fold(0.0, f64::max);
    let window = [x0, x1, 2.0 * d_max, rec.pile["surface_height"] - 2.0 * d_max];
    let area = |i: usize| shifts.iter().map(move |s| disk_area_in_rectangle(f.x[i] + s, f.y[i], f.r[i], window));
    let covered: f64 = (0..f.x.len()).flat_map(area).sum();
    covered / ((x1 - x0) * (window[3] - window[2]))
}

/// Mean and sample standard deviation.
fn mean_and_spread(v: &[f64]) -> (f64, f64) {
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    let variance = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (v.len() - 1) as f64;
    (mean, variance.sqrt())
}

#[test]
fn a_settled_periodic_pile_packs_as_the_middle_of_a_wide_walled_box() {
    // 100 disks periodic over 0.18 m; 300 in a walled box three times as wide, measured in its
    // middle third, two largest diameters and more from either wall.
    let (count, width) = (100, 0.18);
    let mut periodic = Vec::new();
    let mut walled = Vec::new();
    for seed in 1..=4 {
        let rec = settled(count, width, true, seed);
        let (alone, with_images) = ([0.0], [-width, 0.0, width]);
        let (whole, interior) =
            (band_packing(&rec, [0.0, width], &alone), band_packing(&rec, [0.0, width], &with_images));
        assert!(whole < interior, "the disks across the seam count on both sides: {whole} {interior}");
        periodic.push(interior);
        walled.push(band_packing(&settled(3 * count, 3.0 * width, false, seed), [width, 2.0 * width], &alone));
        println!("seed {seed}: packing_fraction_interior {}", rec.pile["packing_fraction_interior"]);
        let floor = rec.pile["floor_load_ratio"];
        assert!((floor - 1.0).abs() < 1e-3, "no side wall carries weight: the floor carries {floor} of it");
    }
    let ((p, p_spread), (w, w_spread)) = (mean_and_spread(&periodic), mean_and_spread(&walled));
    println!("packing: periodic {p:.4} ± {p_spread:.4} {periodic:?}, walled middle {w:.4} ± {w_spread:.4} {walled:?}");
    let noise = ((p_spread * p_spread + w_spread * w_spread) / periodic.len() as f64).sqrt();
    assert!((p - w).abs() < 3.0 * noise + 0.002, "periodic {p} against walled {w}, noise {noise}");
    assert!(p > 0.78 && p < 0.9, "a random disk packing: {p}");
}

#[test]
fn a_poured_disk_clears_the_disks_across_the_periodic_boundary() {
    // Disks resting in the inlet band along the right side; a pour of many disks into the band
    // at the left side: none may overlap them through the boundary.
    let mut s = SceneConfig::default();
    (s.domain.width, s.domain.height, s.domain.periodic_x) = (0.1, 0.3, true);
    s.particles.count = 40;
    s.placement.kind = demsweep::physics::config::PlacementKind::Pour;
    // The inlet along the left side, within reach of the resting disks through the boundary.
    (s.placement.pour.rate, s.placement.pour.x_max) = (Some(1e6), Some(0.035));
    s.validate().unwrap();
    let mut inlet = demsweep::physics::pour::Inlet::of_scene(&s, 1000.0).unwrap();
    let resting: Vec<InitialDisk> = (0..6)
        .map(|k| InitialDisk { x: 0.1 - 0.004, y: 0.27 + 0.005 * k as f64, r: 0.01, ..Default::default() })
        .collect();
    let mut p = demsweep::physics::particles::Particles::new(&resting, 1000.0, 1.0);
    let inserted = inlet.pour(&mut p, 1.0, 0, s.gravity);
    assert!(inserted >= 1, "{inserted} disks poured");
    let nearest = |dx: f64| dx - 0.1 * (dx / 0.1).round();
    for new in resting.len()..p.x.len() {
        for old in 0..resting.len() {
            let d = nearest(p.x[new] - p.x[old]).hypot(p.y[new] - p.y[old]);
            assert!(d >= p.r[new] + p.r[old], "disk {new} at x {} overlaps disk {old} across the boundary", p.x[new]);
        }
    }
}

/// Keeps the run's state at its `at`-th sample.
struct KeepAt(u64, Vec<demsweep::physics::run_state::RunState>);

impl demsweep::physics::run_state::Checkpoints for KeepAt {
    fn due(&mut self, _: u64) -> bool {
        self.0 -= 1;
        self.0 == 0
    }
    fn save(&mut self, state: demsweep::physics::run_state::RunState) {
        self.1.push(state);
    }
}

#[test]
fn a_periodic_pile_resumed_from_a_checkpoint_is_bit_identical_to_the_straight_run() {
    // Disks touch across the boundary while the state is saved.
    let mut s = SceneConfig::default();
    (s.particles.count, s.particles.radius, s.particles.radius_max) = (150, 0.006, Some(0.009));
    (s.domain.width, s.domain.height, s.domain.periodic_x) = (0.15, 0.4, true);
    (s.run.duration, s.run.stop_at_settle) = (0.4, false);
    let disks = demsweep::physics::placement::generate(&s).unwrap();
    let straight = Simulation::<HertzMindlin>::new(&s, &disks).run(&mut |_| Control::Continue);
    let stop = std::sync::atomic::AtomicBool::new(false);
    let mut keep = KeepAt(150, Vec::new());
    Simulation::<HertzMindlin>::new(&s, &disks).run_resumable(None, &stop, &mut |_| Control::Continue, &mut keep);
    let state = &keep.1[0];
    let mut sim = Simulation::<HertzMindlin>::new(&s, &disks);
    let from = sim.resume(state).unwrap();
    let resumed = sim.run_resumable(
        Some(from),
        &stop,
        &mut |_| Control::Continue,
        &mut demsweep::physics::run_state::NoCheckpoints,
    );
    assert!(state.step > 0 && state.step < straight.steps, "saved mid-run, at step {}", state.step);
    assert_eq!(format!("{resumed:?}"), format!("{straight:?}"), "resumed from step {}", state.step);
    let f = &straight.final_state;
    let c = &f.contacts;
    let across = (0..c.len())
        .filter(|&k| usize::try_from(c.second[k]).is_ok_and(|j| (f.x[j] - f.x[c.first[k] as usize]).abs() > 0.075));
    assert!(across.count() > 0, "contacts across the boundary");
}
