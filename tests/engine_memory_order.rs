//! Numbering the disks afresh ([`demsweep::physics::memory_order`]) changes where each disk lives
//! in memory and nothing else: outputs come back in the scene's numbering, a restart's contact
//! histories stay with their contacts, and a run that renumbers at every build gives the same bits on
//! any number of threads. The scenes here start from disks given in shuffled order, so that the
//! first renumbering moves nearly every disk.

use demsweep::physics::config::{ContactLawKind, IntegratorKind, SceneConfig};
use demsweep::physics::contact::{HertzMindlin, HystereticLinear, RegisteredLaw};
use demsweep::physics::contact_record::Partner;
use demsweep::physics::memory_order::MemoryOrder;
use demsweep::physics::particles::{InitialContact, InitialDisk};
use demsweep::physics::placement;
use demsweep::physics::record::RunRecord;
use demsweep::physics::rng::Rng;
use demsweep::physics::simulation::Control;
use demsweep::physics::{Simulation, Threads};

/// `items` in an order drawn from `seed`.
fn shuffled<T>(mut items: Vec<T>, seed: u64) -> Vec<T> {
    Rng::new(seed).shuffle(&mut items);
    items
}

/// `scene` from `disks` run on `threads` threads (the parallel path from any size on) with `policy`.
fn run(scene: &SceneConfig, disks: &[InitialDisk], threads: usize, policy: MemoryOrder) -> RunRecord {
    run_with::<HertzMindlin>(scene, disks, threads, policy)
}

/// [`run`] with the scene's law `L`.
fn run_with<L: RegisteredLaw>(
    scene: &SceneConfig,
    disks: &[InitialDisk],
    threads: usize,
    policy: MemoryOrder,
) -> RunRecord {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        let mut sim = Simulation::<L>::new(scene, disks);
        sim.set_threads(Threads { count: threads, min_disks: 0 });
        sim.set_memory_order(policy);
        sim.run(&mut |_| Control::Continue)
    })
}

/// The bits of a run's final state and contact network.
fn bits(record: &RunRecord) -> Vec<u64> {
    let f = &record.final_state;
    let c = &f.contacts;
    let columns = [
        &f.x,
        &f.y,
        &f.vx,
        &f.vy,
        &f.omega,
        &f.angle,
        &f.contact_force,
        &c.normal_x,
        &c.normal_force,
        &c.tangential_force,
    ];
    let mut bits: Vec<u64> = columns.iter().flat_map(|c| c.iter().map(|v| v.to_bits())).collect();
    bits.extend(c.first.iter().map(|&i| u64::from(i)));
    bits.extend(c.second.iter().map(|&j| j as u64));
    bits
}

/// A frictional deposition of `count` disks with spin, over `duration` s.
fn deposition(count: usize, width: f64, duration: f64) -> SceneConfig {
    let mut s = SceneConfig::default();
    s.particles.count = count;
    s.domain.width = width;
    s.material.restitution = Some(0.5);
    s.material.friction = 0.5;
    s.integrator.contact_time_fraction = Some(0.1);
    s.run.duration = duration;
    s.run.stop_at_settle = false;
    s
}

#[test]
fn disks_that_touch_only_walls_renumbered_at_every_build_move_to_the_same_bits() {
    // Spinning disks dropped far enough apart that none meets another: each disk's forces come
    // from the walls alone, in the same order whatever the numbering, so the renumbered run must
    // give every disk the same bits (the diagnostics sum over disks in another order: rounding).
    let mut scene = deposition(36, 3.0, 1.5);
    scene.domain.height = 1.0;
    // Viscous damping gives every disk its own acceleration, so the integrator's history is
    // renumbered with different values at every build.
    scene.damping.viscous = 0.5;
    let mut rng = Rng::new(5);
    let disk = |k: usize| InitialDisk {
        x: 0.04 + 0.08 * k as f64,
        y: rng.range(0.02, 0.9),
        r: rng.range(0.008, 0.012),
        vx: rng.range(-0.005, 0.005),
        omega: rng.range(-5.0, 5.0),
        ..Default::default()
    };
    let disks = shuffled((0..36).map(disk).collect(), 7);
    let kept = run(&scene, &disks, 1, MemoryOrder::KEPT);
    let renumbered = run(&scene, &disks, 1, MemoryOrder::EVERY_BUILD);
    let c = &kept.final_state.contacts;
    assert!(c.second.iter().all(|&j| j < 0), "no disk met another");
    assert!(c.second.iter().filter(|&&j| j == -1).count() == 36, "every disk on the floor");
    assert!(kept.final_state.omega.iter().all(|&w| w != 0.0), "spinning");
    assert!(bits(&renumbered) == bits(&kept), "renumbering changed a disk's bits");
    let (a, b) = (&kept.history.kinetic_translational, &renumbered.history.kinetic_translational);
    assert!(a.iter().zip(b).all(|(a, b)| (a - b).abs() <= 1e-12 * a.abs()), "sums over disks in another order");
}

#[test]
fn a_pile_renumbered_at_every_build_is_bit_identical_on_1_2_and_3_threads() {
    let scene = deposition(1600, 2.1, 0.3);
    let disks = shuffled(placement::generate(&scene).unwrap(), 11);
    let one = run(&scene, &disks, 1, MemoryOrder::EVERY_BUILD);
    let contacts = *one.history.contacts.last().unwrap() as usize;
    assert!(contacts > 1600, "{contacts} contacts at the end");
    for threads in [2, 3] {
        assert!(
            bits(&run(&scene, &disks, threads, MemoryOrder::EVERY_BUILD)) == bits(&one),
            "{threads} threads differ from one"
        );
    }
    // The same pile without renumbering: the last bits differ, the pile does not.
    let kept = run(&scene, &disks, 1, MemoryOrder::KEPT);
    let mean_height = |r: &RunRecord| r.final_state.y.iter().sum::<f64>() / 1600.0;
    let (a, b) = (mean_height(&one), mean_height(&kept));
    assert!((a - b).abs() < 0.02 * b, "mean height {a} renumbered, {b} kept");
}

#[test]
fn verlet_with_rolling_friction_and_a_law_with_state_renumbered_at_every_build_is_bit_identical_on_1_and_2_threads() {
    // The law's own state goes through the permutation with the springs; Verlet keeps no history.
    let mut scene = deposition(1100, 1.5, 0.25);
    scene.integrator.scheme = IntegratorKind::VelocityVerlet;
    scene.material.rolling_friction = 0.05;
    scene.contact.law = ContactLawKind::HystereticLinear;
    let disks = shuffled(placement::generate(&scene).unwrap(), 13);
    let one = run_with::<HystereticLinear>(&scene, &disks, 1, MemoryOrder::EVERY_BUILD);
    assert!(one.final_state.contacts.law_state.iter().any(|&s| s > 0.0), "contacts with a law state");
    let two = run_with::<HystereticLinear>(&scene, &disks, 2, MemoryOrder::EVERY_BUILD);
    assert!(bits(&two) == bits(&one), "2 threads differ from one");
    let kept = run_with::<HystereticLinear>(&scene, &disks, 1, MemoryOrder::KEPT);
    let mean_height = |r: &RunRecord| r.final_state.y.iter().sum::<f64>() / 1100.0;
    let (a, b) = (mean_height(&one), mean_height(&kept));
    assert!((a - b).abs() < 0.02 * b, "mean height {a} renumbered, {b} kept");
}

#[test]
fn a_large_shuffled_scene_is_renumbered_before_its_first_step_and_its_restart_histories_stay_on_their_contacts() {
    // 20 000 disks on a square lattice, each pressed into its four neighbours, given in shuffled
    // order: nearly every pair is far apart in memory, so the disks are renumbered at once.
    let (columns, rows, r) = (200, 100, 0.005);
    // Place p holds lattice site site_of[p]; site s sits at place_of[s].
    let site_of = shuffled((0..columns * rows).collect::<Vec<usize>>(), 3);
    let mut place_of = vec![0; site_of.len()];
    site_of.iter().enumerate().for_each(|(p, &s)| place_of[s] = p);
    let at = |s: usize| InitialDisk {
        x: r + 1.98 * r * (s % columns) as f64,
        y: r + 1.98 * r * (s / columns) as f64,
        r,
        ..Default::default()
    };
    let disks: Vec<InitialDisk> = site_of.iter().map(|&s| at(s)).collect();
    let mut scene = SceneConfig::default();
    (scene.domain.width, scene.domain.height) = (2.0 * r * columns as f64, 2.0 * r * rows as f64 + 0.1);
    scene.material.friction = 0.5;
    scene.contact.law = ContactLawKind::HystereticLinear;
    // The pairs' overlap (m): the lattice's spacing is 1.98 radii.
    let overlap = 0.02 * r;
    // A spring, and a largest overlap so far above the present one, on every tenth pair of a site
    // and its right-hand neighbour, named from the right.
    let seeded: Vec<InitialContact> = (0..site_of.len())
        .filter(|s| s % 10 == 0 && s % columns + 1 < columns)
        .map(|s| InitialContact {
            disk: place_of[s + 1],
            partner: Partner::Disk(place_of[s]),
            tangential_spring: 1e-7 * (1 + s % 97) as f64,
            law_state: overlap * (1.0 + 1e-3 * (1 + s % 97) as f64),
        })
        .collect();
    assert!(seeded.len() > 1500);
    let law = HystereticLinear::chosen_in(&scene.contact).unwrap();
    let mut sim = Simulation::with_history(&scene, &disks, &seeded, law);
    assert!(sim.numbering().is_scene_order(), "numbered as given until the first step");
    sim.advance(false);
    assert!(!sim.numbering().is_scene_order(), "renumbered before the first step");
    let contacts = sim.contacts();
    let pairs: Vec<_> = contacts
        .iter()
        .filter_map(|c| match c.partner {
            Partner::Disk(j) => Some(((c.disk, j), c.history)),
            Partner::Wall(_) => None,
        })
        .collect();
    assert!(pairs.windows(2).all(|w| w[0].0 < w[1].0), "pairs sorted by their scene disks");
    for c in &seeded {
        let Partner::Disk(j) = c.partner else { unreachable!() };
        let key = (c.disk.min(j), c.disk.max(j));
        let (spring, largest) = pairs.binary_search_by_key(&key, |p| p.0).map(|k| pairs[k].1).expect("a contact");
        // One step on: the spring has moved by the step's slip only (which its own force drives);
        // the largest overlap so far is still the seeded one.
        let seeded = c.tangential_spring;
        assert!((spring - seeded).abs() < 1e-2 * seeded, "pair {key:?}: spring {spring}, seeded {seeded}");
        assert_eq!(largest, c.law_state, "pair {key:?}");
    }
    // The others have only the slip of one step (some 1e-8 m at most) and their present overlap.
    let with_springs = pairs.iter().filter(|p| p.1.0.abs() >= 0.5e-7).count();
    assert_eq!(with_springs, seeded.len(), "no other pair has a spring of the seeded size");
    let with_states = pairs.iter().filter(|p| p.1.1 > overlap * 1.0005).count();
    assert_eq!(with_states, seeded.len(), "no other pair has a largest overlap of the seeded size");
    let snapshot = sim.snapshot();
    let moved = disks.iter().zip(&snapshot.x).map(|(d, x)| (x - d.x).abs()).fold(0.0, f64::max);
    assert!(moved < 1e-6, "the snapshot in the scene's numbering: a disk {moved} m from where it was");
}
