//! Building a simulation: the scene's time step resolved, disks, walls, materials and contact
//! classes set up, the neighbour list built and the forces evaluated at the initial state.

use super::protocol::Protocol;
use super::step::Simulation;
use crate::physics::config::SceneConfig;
use crate::physics::contact::{ContactLaw, ContactOptions, RegisteredLaw};
use crate::physics::contact_sums::ContactSums;
use crate::physics::diagnostics::ContactTotals;
use crate::physics::energy::EnergyLedger;
use crate::physics::forces::ContactParameters;
use crate::physics::integrator::{Integrator, StepContext};
use crate::physics::material::{ContactMaterial, Materials};
use crate::physics::memory_order::{MemoryOrder, Numbering};
use crate::physics::neighbors::NeighborList;
use crate::physics::parallel::Team;
use crate::physics::particles::{InitialContact, InitialDisk, Particles};
use crate::physics::pour::Inlet;
use crate::physics::rolling;
use crate::physics::time_step::with_time_step;
use crate::physics::walls::{BoxWalls, wrap};

impl<L: RegisteredLaw> Simulation<L> {
    /// A simulation of `scene` from `disks` at time zero, with forces evaluated at the initial
    /// state (a pour's `disks` are its reference disks, [`crate::physics::placement::generate`]'s:
    /// it starts from none). Panics unless `L` is the law of the models `scene.contact` names.
    pub fn new(scene: &SceneConfig, disks: &[InitialDisk]) -> Self {
        let law = L::chosen_in(&scene.contact)
            .unwrap_or_else(|| panic!("scene.contact is {}, not the Simulation's law", scene.contact.law_name()));
        Self::with_law(scene, disks, law)
    }
}

impl<L: ContactLaw> Simulation<L> {
    /// A simulation of `scene` with contact law `law` (whatever `scene.contact` says: for laws
    /// outside the registry), at time zero with forces evaluated at the initial state.
    pub fn with_law(scene: &SceneConfig, disks: &[InitialDisk], law: L) -> Self {
        Self::with_history(scene, disks, &[], law)
    }

    /// [`Self::with_law`], the contacts starting from the history `contacts` (a restart: the
    /// tangential springs and law states a pile's contacts had) instead of from none. Contacts whose
    /// bodies are too far apart to touch are dropped. The history is set once, at the first
    /// neighbour-list build: the step loop does not know of it.
    pub fn with_history(scene: &SceneConfig, disks: &[InitialDisk], contacts: &[InitialContact], law: L) -> Self {
        let protocol = Protocol::new(scene, &law, disks);
        let first = protocol.now();
        let scene = &with_time_step(scene, protocol.physical().dt);
        let materials = first.materials;
        let inlet = Inlet::of_scene(scene, materials.density);
        let mut particles = Particles::new(disks, materials.density, scene.particles.thickness);
        let skin = scene.neighbors.skin_ratio * particles.max_radius();
        if inlet.is_some() {
            // A pour's disks are its reference disks: the box starts empty.
            particles = Particles::default();
        }
        let walls = BoxWalls::new(&scene.domain);
        if let Some(width) = walls.period() {
            // Disks given past periodic sides (a file's, a dump's) start at their place in the box.
            wrap(&mut particles.x, width);
        }
        // Springs and spins are followed through the whole run if any stage has friction.
        let all = || protocol.stages.iter().map(|stage| &stage.materials);
        let tangential = all().any(|m| m.particle.friction > 0.0 || m.wall.friction > 0.0);
        let spinning = particles.omega.iter().any(|w| *w != 0.0);
        let rotation = all().any(Materials::has_friction) || spinning;
        let kind = |m: &ContactMaterial| ContactParameters {
            material: *m,
            options: ContactOptions { allow_tension: scene.contact.allow_tension, tangential, friction: m.friction },
            rotation,
            dt: first.dt,
        };
        let mut sim = Self {
            law,
            scene: scene.clone(),
            time_step_warning: protocol.physical().time_step_warning.clone(),
            neighbors: NeighborList::new(scene.neighbors.broad_phase, skin),
            disk_contacts: kind(&materials.particle),
            wall_contacts: kind(&materials.wall),
            touching: Box::default(),
            tables: Vec::new(),
            sums: ContactSums::default(),
            team: Team::new(1),
            moved: Vec::new(),
            rolling_resistance: materials.particle.rolling_friction > 0.0 || materials.wall.rolling_friction > 0.0,
            rolling_removed: rolling::Removed::default(),
            integrator: Integrator::new(first.scheme),
            particles,
            numbering: Numbering::default(),
            memory_order: MemoryOrder::default(),
            walls,
            step: 0,
            context: StepContext { dt: first.dt, gravity: scene.gravity, rotation, damping: first.damping },
            energy: EnergyLedger::default(),
            totals: ContactTotals::default(),
            protocol,
            inlet,
        };
        sim.rebuild_neighbors();
        sim.neighbors.seed_histories(contacts);
        sim.compute_forces::<true>();
        sim.energy.initial_elastic = sim.totals.elastic;
        // No step reads the rolling resistances at the start: cleared for the first contact stage.
        sim.particles.rolling.fill(0.0);
        sim
    }
}
