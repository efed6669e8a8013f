use super::stages::COMPUTED;
use super::table::{ContactParameters, TouchingPairs};
use crate::physics::contact::{self, ContactLaw, ContactOptions, HertzMindlin, Kinematics};
use crate::physics::contact_sums::BLOCK;
use crate::physics::diagnostics::ContactTotals;
use crate::physics::material::ContactMaterial;
use crate::physics::neighbors::{Candidates, NeighborList, NeighborPair, WallPair};
use crate::physics::particles::{InitialDisk, Particles};
use crate::physics::walls::Walled;

fn kind(allow_tension: bool) -> ContactParameters {
    let material = ContactMaterial { e_star: 5e8, g_star: 2e8, beta: 0.4, friction: 0.5, rolling_friction: 0.0 };
    let options = ContactOptions { allow_tension, tangential: true, friction: material.friction };
    ContactParameters { material, options, rotation: true, dt: 1e-5 }
}

/// The walls of an open box 1 m wide, 4 m high.
fn open_box() -> crate::physics::walls::BoxWalls {
    crate::physics::walls::BoxWalls::new(&crate::physics::config::DomainConfig {
        width: 1.0,
        height: 4.0,
        lid: false,
        periodic_x: false,
    })
}

/// Touching pairs with assorted geometry and motion: sticking, sliding both ways, separating
/// fast (normal force clamped or tensile), coincident centres.
fn table() -> TouchingPairs<()> {
    let mut t = TouchingPairs::default();
    t.rows.len = 101;
    for c in 0..t.rows.len {
        let (a, w) = (c as f64 * 0.37, (c as f64 * 0.91).sin());
        let d = if c == 7 { 0.0 } else { 0.0199 - 1e-6 * (c % 13) as f64 };
        (t.dx[c], t.dy[c]) = (d * a.cos(), d * a.sin());
        (t.rows.ri[c], t.rows.rj[c]) = (0.01, 0.01 - 1e-5 * (c % 3) as f64);
        (t.rows.r_star[c], t.rows.m_star[c]) = (0.005, 0.15);
        (t.dvx[c], t.dvy[c]) = (3.0 * w * a.cos(), -2.0 * w);
        (t.omega_i[c], t.omega_j[c]) = (50.0 * w, -20.0);
        t.rows.spring[c] = 1e-6 * (c as f64 - 50.0);
    }
    t
}

#[test]
fn narrow_phase_with_and_without_branch_agree() {
    // A 6 x 6 lattice squeezed so that neighbours overlap, shaken, with assorted velocities.
    let disks: Vec<_> = (0..36)
        .map(|k| {
            let w = (k as f64 * 1.7).sin();
            InitialDisk {
                x: 0.0195 * (k % 6) as f64 + 0.002 * w,
                y: 0.0195 * (k / 6) as f64 - 0.001 * w,
                r: 0.01,
                vx: w,
                vy: -0.5 * w,
                omega: 3.0 * w,
                angle: 0.0,
            }
        })
        .collect();
    let mut particles = Particles::new(&disks, 1000.0, 1.0);
    let (s, _) = particles.split();
    let near = |i: u32, j: u32| {
        let (a, b) = (&disks[i as usize], &disks[j as usize]);
        (a.x - b.x).hypot(a.y - b.y) < 0.026
    };
    let pairs: Vec<_> = (0..36u32)
        .flat_map(|i| (i + 1..36).map(move |j| (i, j)))
        .filter(|&(i, j)| near(i, j))
        .map(|(i, j)| NeighborPair { i, j, r_star: 0.005, m_star: 0.1 + f64::from(j) })
        .collect();
    let springs: Vec<f64> = (0..pairs.len()).map(|k| 1e-6 * (k % 5) as f64).collect();
    let (mut branchy, mut branch_free) = (TouchingPairs::<()>::default(), TouchingPairs::<()>::default());
    let (mut springs_branchy, mut springs_branch_free) = (springs.clone(), springs);
    let mut states = vec![(); pairs.len()];
    branchy.collect::<Walled, true, true>((&s, Walled), &pairs, (&mut springs_branchy, &mut states));
    branch_free.collect::<Walled, false, false>((&s, Walled), &pairs, (&mut springs_branch_free, &mut states));
    let touching = branchy.rows.len;
    assert!(touching > 10 && touching < pairs.len() - 10, "{touching} of {} touch", pairs.len());
    assert_eq!(branch_free.rows.len, touching);
    let rows = |t: &TouchingPairs<()>| {
        let columns = [
            t.dx,
            t.dy,
            t.rows.ri,
            t.rows.rj,
            t.rows.r_star,
            t.rows.m_star,
            t.dvx,
            t.dvy,
            t.omega_i,
            t.omega_j,
            t.rows.spring,
        ];
        (0..t.rows.len)
            .map(|c| (t.rows.candidate[c], t.bodies(c), columns.map(|column| column[c].to_bits())))
            .collect::<Vec<_>>()
    };
    assert_eq!(rows(&branchy), rows(&branch_free));
    // Out of contact: spring cleared; touching: the scatter stores the new one.
    let cleared_out_of_contact = |springs: &[f64]| {
        springs
            .iter()
            .enumerate()
            .filter(|(k, _)| !branchy.rows.candidate[..touching].contains(k))
            .all(|(_, &s)| s == 0.0)
    };
    assert!(cleared_out_of_contact(&springs_branchy) && cleared_out_of_contact(&springs_branch_free));
}

#[test]
fn blocks_gathered_unchanged_give_the_narrow_phase_bits_as_contacts_come_and_go() {
    // A 16 x 16 lattice of disks that just touch (four blocks of candidates), its columns 7
    // and 8 a tenth of a millimetre apart, its rows 13 and 14 0.8 mm; four disks of the first
    // three blocks wobble on circles larger than the overlap: their pairs come into and out of
    // contact from step to step (pairs apart near touching), the others stay; the right half
    // of row 3 closes its gap, slowly, and the rows from 14 up theirs, faster (far pairs).
    let disks: Vec<_> = (0..256)
        .map(|k| {
            let w = (k as f64 * 1.3).sin();
            let column = 0.01998 * (k % 16) as f64 + if k % 16 > 7 { 1.2e-4 } else { 0.0 };
            let row = 0.01998 * (k / 16) as f64 + if k / 16 > 13 { 8e-4 } else { 0.0 };
            let (x, y) = (0.05 + column, 0.05 + row);
            InitialDisk { x, y, r: 0.01, vx: w, vy: -0.5 * w, omega: 3.0 * w, angle: 0.0 }
        })
        .collect();
    let mut particles = Particles::new(&disks, 1000.0, 1.0);
    let walls = open_box();
    let team = crate::physics::parallel::Team::new(1);
    let mut list = NeighborList::<()>::new(crate::physics::config::BroadPhaseKind::Grid, 0.004);
    list.rebuild(&particles, &walls, &team);
    let (law, kind) = (HertzMindlin::default(), kind(false));
    let (mut kept, mut totals) = (TouchingPairs::<()>::default(), ContactTotals::default());
    let mut blocks = 0;
    for step in 0..80 {
        // The disks moved, and the list told how far (as the integrator tells it).
        let mut longest = 0.0_f64;
        for (k, disk) in disks.iter().enumerate() {
            let wobble = if k % 50 == 7 && k < 192 { 3e-5 } else { 0.0 };
            let phase = 0.3 * step as f64 + k as f64;
            let closing = if k / 16 == 3 && k % 16 > 7 { 2e-6 * step as f64 } else { 0.0 };
            let falling = if k / 16 > 13 { 1.2e-5 * step as f64 } else { 0.0 };
            let (x, y) = (disk.x - closing + wobble * phase.cos(), disk.y - falling + wobble * phase.sin());
            longest = longest.max((x - particles.x[k]).hypot(y - particles.y[k]));
            (particles.x[k], particles.y[k]) = (x, y);
        }
        assert!(!list.note_step(longest), "no build needed");
        // The same step through a table that has no rows of earlier steps (and a list with
        // the springs the kept rows hold newer).
        let mut afresh = list.clone();
        afresh.pairs.springs = kept.springs_of(&list.pairs).into_owned();
        let mut forces = Vec::new();
        for (table, list) in [(&mut kept, &mut list), (&mut TouchingPairs::default(), &mut afresh)] {
            let (s, mut f) = particles.split();
            table.contacts::<_, _, false>(
                &law,
                [&kind, &kind],
                (&walls.walls, Walled, &mut *list),
                &s,
                &mut f,
                &mut totals,
            );
            let columns = [&f.fx, &f.fy, &f.torque].map(|c| c.iter().map(|v| v.to_bits()).collect::<Vec<_>>());
            let springs = table.springs_of(&list.pairs).iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            forces.push((columns, springs));
            for column in [f.fx, f.fy, f.torque] {
                column.fill(0.0);
            }
        }
        assert!(forces[0] == forces[1], "step {step}: forces or springs differ");
        assert!(forces[0].1.iter().any(|&b| b != 0), "tangential springs");
        blocks += list.pairs.entries.len().div_ceil(BLOCK);
    }
    let (unchanged, skipped, far_tests) = (kept.unchanged_blocks, kept.apart_tests_skipped, kept.far_tests);
    assert!(unchanged >= blocks / 4 && blocks - unchanged >= blocks / 20, "{unchanged} of {blocks} blocks unchanged");
    assert!(skipped >= 10 && far_tests >= 5, "far pairs apart: {skipped} gathers skipped, {far_tests} tested");
}

#[test]
fn vector_stage_equals_one_contact_at_a_time_bit_for_bit() {
    for allow_tension in [false, true] {
        let (law, kind) = (HertzMindlin::default(), kind(allow_tension));
        let mut t = table();
        let before = t.rows.spring;
        t.compute_forces::<_, COMPUTED>(&law, &kind);
        let (mut sliding, mut clamped) = (0, 0);
        for (c, &spring_before) in before.iter().enumerate().take(t.rows.len) {
            // One contact at a time, opaque to the compiler, so it cannot be vectorised.
            let d = std::hint::black_box(t.dx[c] * t.dx[c] + t.dy[c] * t.dy[c]).sqrt();
            let (nx, ny) = if d > 0.0 { (t.dx[c] * (1.0 / d), t.dy[c] * (1.0 / d)) } else { (1.0, 0.0) };
            let motion = Kinematics {
                overlap: (t.rows.ri[c] + t.rows.rj[c]) - d,
                approach_speed: t.dvx[c] * nx + t.dvy[c] * ny,
                tangential_speed: -t.dvx[c] * ny
                    + t.dvy[c] * nx
                    + t.omega_i[c] * t.rows.ri[c]
                    + t.omega_j[c] * t.rows.rj[c],
            };
            let coefficients =
                law.coefficients(&kind.pair_properties(t.rows.r_star[c], t.rows.m_star[c]), motion.overlap, &mut ());
            let mut spring = spring_before;
            let force = contact::resolve(&coefficients, &kind.options, &motion, &mut spring, kind.dt);
            let expect = force.on_first_body(nx, ny);
            assert_eq!([t.force_x[c].to_bits(), t.force_y[c].to_bits()], expect.map(f64::to_bits), "force {c}");
            assert_eq!(t.torque_j[c].to_bits(), (force.tangential * t.rows.rj[c]).to_bits(), "torque {c}");
            assert_eq!(t.rows.spring[c].to_bits(), spring.to_bits(), "spring {c}");
            assert_eq!(t.normal[c].to_bits(), force.normal.to_bits(), "normal {c}");
            sliding += usize::from(force.tangential.abs() == kind.options.friction * force.normal.max(0.0));
            clamped += usize::from(force.normal <= 0.0);
        }
        assert!(sliding > 5 && sliding < 95 && clamped > 5, "cases covered: {sliding} sliding, {clamped} clamped");
        assert_eq!(t.force_x[7].to_bits(), (-t.normal[7] - 0.0 * t.tangential[7]).to_bits());
    }
}

#[test]
fn wall_contacts_equal_one_contact_at_a_time_bit_for_bit() {
    // 150 disks (more than a block), half along the floor, half up the left wall, every third
    // one clear of its wall, with assorted velocities and spins; candidates for both walls.
    let disks: Vec<_> = (0..150)
        .map(|k| {
            let w = (k as f64 * 0.77).sin();
            let off_wall = 0.01 + if k % 3 == 0 { 1e-3 } else { -1e-5 * (1.0 + w) };
            let along = 0.05 + 0.02 * (k % 75) as f64;
            let (x, y) = if k < 75 { (along, off_wall) } else { (off_wall, along) };
            InitialDisk { x, y, r: 0.01, vx: w, vy: 0.3 * w - 0.1, omega: 20.0 * w, angle: 0.0 }
        })
        .collect();
    let mut particles = Particles::new(&disks, 1000.0, 1.0);
    let walls = open_box();
    let mut candidates = Candidates::<WallPair>::default();
    let m_star = particles.mass[0];
    candidates.entries = (0..150u32).flat_map(|i| [0, 1].map(|wall| WallPair { i, wall, m_star })).collect();
    candidates.springs = (0..300).map(|k| 1e-6 * ((k % 7) as f64 - 3.0)).collect();
    candidates.states = vec![(); 300];
    let before = candidates.springs.clone();
    let (law, kind) = (HertzMindlin::default(), kind(false));
    let (s, mut f) = particles.split();
    let mut totals = ContactTotals::default();
    let mut t = TouchingPairs::<()>::default();
    t.wall_contacts::<_, true>(&law, &kind, &walls.walls, &mut candidates, 0..300, &s, &mut f, &mut totals);
    let mut touching = 0;
    for i in 0..150 {
        let (mut fx, mut fy, mut torque) = (0.0, 0.0, 0.0);
        for k in [2 * i, 2 * i + 1] {
            let wall = &walls.walls[candidates.entries[k].wall as usize];
            let overlap = wall.overlap(s.x[i], s.y[i], s.r[i]);
            if overlap <= 0.0 {
                assert_eq!(candidates.springs[k], 0.0);
                continue;
            }
            touching += 1;
            let [nx, ny] = wall.normal;
            let motion = Kinematics {
                overlap,
                approach_speed: s.vx[i] * nx + s.vy[i] * ny,
                tangential_speed: -s.vx[i] * ny + s.vy[i] * nx + s.omega[i] * s.r[i],
            };
            let c = law.coefficients(&kind.pair_properties(s.r[i], m_star), overlap, &mut ());
            let mut spring = before[k];
            let force = contact::resolve(&c, &kind.options, &motion, &mut spring, kind.dt);
            let [force_x, force_y] = force.on_first_body(nx, ny);
            (fx, fy, torque) = (fx + force_x, fy + force_y, torque + force.tangential * s.r[i]);
            assert_eq!(candidates.springs[k].to_bits(), spring.to_bits(), "spring {k}");
        }
        assert_eq!([f.fx[i], f.fy[i], f.torque[i]].map(f64::to_bits), [fx, fy, torque].map(f64::to_bits), "disk {i}");
    }
    assert_eq!((touching, totals.contacts), (100, 100), "all but every third disk touch one wall");
}
