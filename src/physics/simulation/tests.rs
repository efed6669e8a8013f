use super::Simulation;
use crate::physics::config::SceneConfig;
use crate::physics::contact::RegisteredLaw;
use crate::physics::contact::{ContactForce, ContactLawKind, DampingKind, LawVisitor, NormalKind};
use crate::physics::contact_record::Partner;
use crate::physics::particles::InitialDisk;

/// Settles a small frictional pile with law `L`, then compares at that state the one-contact
/// evaluation with the block stages: per-disk force, torque and force-magnitude sums, each
/// added up in the block stages' order, to the bit.
fn one_contact_path_matches_block_path<L: RegisteredLaw>(scene: &SceneConfig) {
    let disks = crate::physics::placement::generate(scene).expect("placement");
    let mut sim = Simulation::<L>::new(scene, &disks);
    let steps = (0.4 / sim.time_step()).round() as u64;
    for _ in 0..steps {
        sim.advance(false);
    }
    let contacts = sim.contacts();
    let n = sim.particles.len();
    let (mut fx, mut fy, mut torque, mut magnitude) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let r = sim.particles.r.clone();
    for c in &contacts {
        let force = ContactForce { normal: c.normal_force, tangential: c.tangential_force, tangential_stiffness: 0.0 };
        let [x, y] = force.on_first_body(c.normal[0], c.normal[1]);
        let i = c.disk;
        (fx[i], fy[i], torque[i], magnitude[i]) =
            (fx[i] + x, fy[i] + y, torque[i] + force.tangential * r[i], magnitude[i] + force.magnitude());
        if let Partner::Disk(j) = c.partner {
            (fx[j], fy[j], torque[j], magnitude[j]) =
                (fx[j] - x, fy[j] - y, torque[j] + force.tangential * r[j], magnitude[j] + force.magnitude());
        }
    }
    let p = &mut sim.particles;
    for column in [&mut p.fx, &mut p.fy, &mut p.torque] {
        column.fill(0.0);
    }
    sim.compute_forces::<true>();
    let p = &sim.particles;
    let sliding = contacts.iter().filter(|c| c.is_sliding()).count();
    assert!(contacts.len() > n && sliding > 0, "{} contacts, {sliding} sliding", contacts.len());
    assert_eq!(sim.totals.contacts as usize, contacts.len());
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&p.fx), bits(&fx), "fx");
    assert_eq!(bits(&p.fy), bits(&fy), "fy");
    assert_eq!(bits(&p.torque), bits(&torque), "torque");
    assert_eq!(bits(&p.contact_force), bits(&magnitude), "force magnitudes");
}

#[test]
fn rolling_resistances_are_cleared_from_the_start_and_by_their_last_reader() {
    // Three spinning disks pressed into the floor and into each other at time zero, so that
    // the first force evaluation (at construction) already sums rolling resistances.
    let mut scene = SceneConfig::default();
    scene.material.rolling_friction = 0.1;
    let r = 0.01;
    let disk =
        |k: u32| InitialDisk { x: 0.1 + 1.9 * r * f64::from(k), y: 0.98 * r, r, omega: 5.0, ..Default::default() };
    let disks: Vec<InitialDisk> = (0..3).map(disk).collect();
    let mut sim = Simulation::<crate::physics::contact::HertzMindlin>::new(&scene, &disks);
    assert!(sim.totals.contacts >= 5, "{} contacts at the start", sim.totals.contacts);
    let cleared = |sim: &Simulation<_>| sim.particles.rolling.iter().all(|&m| m == 0.0);
    assert!(cleared(&sim), "the next contact stage starts from zero");
    for _ in 0..20 {
        sim.advance(false);
        assert!(cleared(&sim), "cleared by the pass that applied them");
    }
}

#[test]
fn one_contact_evaluation_gives_the_block_stages_forces_to_the_bit_for_every_law() {
    struct Check<'a>(&'a SceneConfig);
    impl LawVisitor for Check<'_> {
        type Output = ();
        fn visit<L: RegisteredLaw>(self, _: &L) {
            one_contact_path_matches_block_path::<L>(self.0);
        }
    }
    let mut scene = SceneConfig::default();
    scene.particles.count = 120;
    scene.domain.width = 0.2;
    scene.material.restitution = Some(0.5);
    scene.material.friction = 0.5;
    scene.integrator.contact_time_fraction = Some(0.05);
    for &law in ContactLawKind::ALL {
        scene.contact.law = law;
        scene.contact.dispatch(Check(&scene));
    }
    // Compositions no preset has, run by the law whose models are chosen at run time.
    scene.contact.law = ContactLawKind::Linear;
    scene.contact.damping = Some(DampingKind::Paper);
    assert_eq!(scene.contact.preset(), None);
    scene.contact.dispatch(Check(&scene));
    scene.contact.normal = Some(NormalKind::HystereticLinear);
    scene.contact.damping = Some(DampingKind::Viscoelastic);
    scene.contact.viscoelastic.dissipation_time = 1e-5;
    scene.contact.dispatch(Check(&scene));
}
