//! The step loop: forces, integration, sampling, monitoring and stopping.
//!
//! One step: the integrator advances the state with the forces of the current state, the neighbour
//! list is refreshed if some disk moved far enough, forces are evaluated at the new state (with
//! contact sums only on sampled steps), and the integrator finishes the step. Diagnostics,
//! divergence checks and the settle criterion run on sampled steps only.

use super::config::{ContactLawKind, SceneConfig};
use super::contact::{ContactLaw, ContactOptions, HertzMindlin, Kinematics, LinearSpringDashpot};
use super::diagnostics::{self, ContactTotals, Sample, SettleDetector};
use super::forces::{ContactKind, TouchingPairs};
use super::integrator::{Integrator, StepContext};
use super::material::{ContactMaterial, Materials};
use super::monitor::{FrameSchedule, Monitor};
use super::neighbors::NeighborList;
use super::particles::{InitialDisk, Particles};
use super::pile::{Partner, PileContact, PileGeometry, PileMetrics};
use super::record::{History, RunRecord, RunStatus, Snapshot};
use super::stability::{self, StabilityReport};
use super::time_step::{self, ResolvedTimeStep};
use super::vector;
use super::walls::BoxWalls;

/// Disks per range of [`Simulation::move_disks`]: their arrays stay in cache from the integrator's
/// power sum to its update.
const SWEEP: usize = 512;

/// What a running simulation tells its caller at every sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    /// Steps taken.
    pub step: u64,
    /// Simulated time (s).
    pub time: f64,
    /// The run's full duration (s).
    pub duration: f64,
    /// Current unbalanced force ratio (NaN without contacts).
    pub unbalanced_force_ratio: f64,
    /// Current kinetic energy (J).
    pub kinetic_energy: f64,
}

/// The caller's answer to a [`Progress`] report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Control {
    /// Keep going.
    Continue,
    /// Stop now; the run ends as [`RunStatus::Interrupted`].
    Stop,
}

/// Builds and runs one scene with the contact law it names. `disks`: explicit initial states
/// (file placement), or `None` to generate them from the scene's placement.
pub fn run_scene(
    scene: &SceneConfig,
    disks: Option<Vec<InitialDisk>>,
    observer: &mut dyn FnMut(&Progress) -> Control,
) -> Result<RunRecord, String> {
    if let Err(issues) = scene.validate() {
        return Err(issues.iter().map(|i| i.to_string()).collect::<Vec<_>>().join("; "));
    }
    let disks = match disks {
        Some(d) => d,
        None => super::placement::generate(scene).map_err(|e| e.to_string())?,
    };
    if disks.is_empty() {
        return Err("particles.count: a scene needs at least one disk, got 0".into());
    }
    Ok(match scene.contact.law {
        ContactLawKind::HertzMindlin => Simulation::new(scene, &disks, HertzMindlin).run(observer),
        ContactLawKind::Linear => Simulation::new(scene, &disks, linear_law(scene)).run(observer),
    })
}

/// The time step a (validated) scene will run with; `disks`: the initial disks of a file placement.
pub fn scene_time_step(scene: &SceneConfig, disks: Option<&[InitialDisk]>) -> ResolvedTimeStep {
    match scene.contact.law {
        ContactLawKind::HertzMindlin => time_step::resolve(&HertzMindlin, scene, disks),
        ContactLawKind::Linear => time_step::resolve(&linear_law(scene), scene, disks),
    }
}

/// The scene with its time step fixed at `dt` (s), the fractions that chose it removed.
fn with_time_step(scene: &SceneConfig, dt: f64) -> SceneConfig {
    let mut scene = scene.clone();
    scene.integrator.time_step = Some(dt);
    (scene.integrator.contact_time_fraction, scene.integrator.rayleigh_fraction) = (None, None);
    scene
}

/// The pre-run stability estimate of a scene starting from `disks`, without building a simulation
/// (a time step capped by the damping-rate limit is its first warning).
pub fn predict_stability(scene: &SceneConfig, disks: &[InitialDisk]) -> StabilityReport {
    let resolved = scene_time_step(scene, Some(disks));
    let scene = &with_time_step(scene, resolved.dt);
    let materials = Materials::from_scene(scene);
    let particles = Particles::new(disks, materials.density, scene.particles.thickness);
    let walls = BoxWalls::new(&scene.domain);
    let mut report = match scene.contact.law {
        ContactLawKind::HertzMindlin => stability::assess(&HertzMindlin, scene, &particles, &materials, &walls),
        ContactLawKind::Linear => stability::assess(&linear_law(scene), scene, &particles, &materials, &walls),
    };
    report.warnings.splice(0..0, resolved.warning);
    report
}

/// The linear spring-dashpot law of a scene.
fn linear_law(scene: &SceneConfig) -> LinearSpringDashpot {
    LinearSpringDashpot {
        normal_stiffness: scene.contact.normal_stiffness,
        tangential_ratio: scene.contact.tangential_stiffness_ratio,
    }
}

/// One simulation of a scene with contact law `L`.
pub struct Simulation<L: ContactLaw> {
    law: L,
    /// The scene, with its time step resolved.
    scene: SceneConfig,
    time_step_warning: Option<String>,
    /// The disks.
    pub particles: Particles,
    walls: BoxWalls,
    neighbors: NeighborList,
    materials: Materials,
    disk_kind: ContactKind,
    wall_kind: ContactKind,
    touching: Box<TouchingPairs>,
    integrator: Integrator,
    rolling_resistance: bool,
    /// Steps taken.
    pub step: u64,
    context: StepContext,
    work: f64,
    last_power: Option<f64>,
    /// Work of the numerical damping so far (J, ≤ 0) and its power at the last step's start (W).
    damping_work: f64,
    last_damping_power: f64,
    totals: ContactTotals,
    initial_elastic: f64,
}

impl<L: ContactLaw> Simulation<L> {
    /// A simulation at time zero with forces evaluated at the initial state.
    pub fn new(scene: &SceneConfig, disks: &[InitialDisk], law: L) -> Self {
        let resolved = time_step::resolve(&law, scene, Some(disks));
        let scene = &with_time_step(scene, resolved.dt);
        let materials = Materials::from_scene(scene);
        let particles = Particles::new(disks, materials.density, scene.particles.thickness);
        let walls = BoxWalls::new(&scene.domain);
        let tangential = materials.particle.friction > 0.0 || materials.wall.friction > 0.0;
        let spinning = particles.omega.iter().any(|w| *w != 0.0);
        let rotation = materials.has_friction() || spinning;
        let kind = |m: &ContactMaterial| ContactKind {
            material: *m,
            options: ContactOptions { allow_tension: scene.contact.allow_tension, tangential, friction: m.friction },
            rotation,
            dt: resolved.dt,
        };
        let skin = scene.neighbors.skin_ratio * particles.max_radius();
        let mut sim = Self {
            law,
            scene: scene.clone(),
            time_step_warning: resolved.warning,
            neighbors: NeighborList::new(scene.neighbors.broad_phase, skin),
            disk_kind: kind(&materials.particle),
            wall_kind: kind(&materials.wall),
            touching: Box::default(),
            rolling_resistance: materials.particle.rolling_friction > 0.0 || materials.wall.rolling_friction > 0.0,
            integrator: Integrator::new(scene.integrator.scheme),
            particles,
            walls,
            materials,
            step: 0,
            context: StepContext { dt: resolved.dt, gravity: scene.gravity, rotation, damping: scene.damping },
            work: 0.0,
            last_power: None,
            damping_work: 0.0,
            last_damping_power: 0.0,
            totals: ContactTotals::default(),
            initial_elastic: 0.0,
        };
        sim.neighbors.rebuild(&sim.particles, &sim.walls);
        sim.compute_forces::<true>();
        sim.initial_elastic = sim.totals.elastic;
        sim
    }

    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.step as f64 * self.context.dt
    }

    /// The pre-run stability estimate for this scene.
    pub fn stability(&self) -> StabilityReport {
        stability::assess(&self.law, &self.scene, &self.particles, &self.materials, &self.walls)
    }

    /// Advances one time step; `sample` requests contact sums for diagnostics at the new state.
    pub fn advance(&mut self, sample: bool) {
        let (power, damping_power, stale) = self.move_disks();
        if let Some(last) = self.last_power {
            self.work += 0.5 * (last + power) * self.context.dt;
            self.damping_work += 0.5 * (self.last_damping_power + damping_power) * self.context.dt;
        }
        self.last_power = Some(power);
        self.last_damping_power = damping_power;
        if stale {
            self.neighbors.rebuild(&self.particles, &self.walls);
        }
        if sample {
            self.compute_forces::<true>();
        } else {
            self.compute_forces::<false>();
        }
        self.integrator.finish(&mut self.particles, &self.context);
        if self.rolling_resistance {
            self.work -= self.apply_rolling_resistance();
        }
        self.step += 1;
    }

    /// The integrator's update, `SWEEP` disks at a time. Returns the power of the contact forces and
    /// of the numerical damping at the start of the step, and whether the neighbour list must be rebuilt.
    fn move_disks(&mut self) -> (f64, f64, bool) {
        let n = self.particles.len();
        let (mut power, mut damping_power, mut longest) = (0.0, 0.0, vector::LargestSquare::default());
        for start in (0..n).step_by(SWEEP) {
            let disks = start..(start + SWEEP).min(n);
            let moved = self.integrator.advance(&mut self.particles, &self.context, disks);
            power += moved.power;
            damping_power += moved.damping_power;
            longest = longest.max(moved.longest);
        }
        (power, damping_power, self.neighbors.note_step(longest.root()))
    }

    /// Diagnostics at the current state; valid after a sampled step (or at time zero).
    pub fn sample(&self) -> Sample {
        let (kt, kr) = diagnostics::kinetic_energies(&self.particles);
        // Work of the contacts up to now: the stored trapezoids end one step back; close the last one.
        let work =
            self.work + self.last_power.map_or(0.0, |last| 0.5 * (last + self.contact_power()) * self.context.dt);
        let damping_work = self.damping_work + self.closing_damping_work();
        Sample {
            time: self.time(),
            kinetic_translational: kt,
            kinetic_rotational: kr,
            potential: diagnostics::potential_energy(&self.particles, self.scene.gravity),
            elastic: self.totals.elastic,
            dissipated: self.initial_elastic - self.totals.elastic - work - damping_work,
            numerical_damping_dissipated: -damping_work,
            unbalanced_force_ratio: diagnostics::unbalanced_force_ratio(
                &self.particles,
                self.scene.gravity,
                &self.totals,
            ),
            contacts: self.totals.contacts,
            max_overlap_ratio: self.totals.max_overlap_ratio,
        }
    }

    /// Full state now (contact forces as of the last sampled step).
    pub fn snapshot(&self) -> Snapshot {
        let p = &self.particles;
        Snapshot {
            time: self.time(),
            x: p.x.clone(),
            y: p.y.clone(),
            vx: p.vx.clone(),
            vy: p.vy.clone(),
            omega: p.omega.clone(),
            r: p.r.clone(),
            contact_force: p.contact_force.clone(),
        }
    }

    /// Power of the contact forces and torques at the current velocities (W). Integrated by the
    /// trapezoid rule over steps it gives the work of the contacts, and with it the energy dissipated.
    /// Each step gets it from the integrator's pass; this is for closing the last step at a sample.
    fn contact_power(&self) -> f64 {
        let p = &self.particles;
        let n = p.len();
        let (fx, fy, vx, vy) = (&p.fx[..n], &p.fy[..n], &p.vx[..n], &p.vy[..n]);
        let mut power = vector::lane_sum(n, |i| fx[i] * vx[i] + fy[i] * vy[i]);
        if self.context.rotation {
            let (torque, omega) = (&p.torque[..n], &p.omega[..n]);
            power += vector::lane_sum(n, |i| torque[i] * omega[i]);
        }
        power
    }

    /// The numerical damping's work since the start of the last step (J), closing its trapezoid at
    /// the current state as [`Self::sample`] does for the contacts.
    fn closing_damping_work(&self) -> f64 {
        let d = &self.context.damping;
        if !d.is_active() || self.last_power.is_none() {
            return 0.0;
        }
        let now = d.power(&self.particles, self.context.gravity, self.context.rotation);
        0.5 * (self.last_damping_power + now) * self.context.dt
    }

    /// The contacts at the current state (after a sampled step, or at time zero), with their forces.
    pub fn contacts(&self) -> Vec<PileContact> {
        let p = &self.particles;
        let mut contacts = Vec::new();
        let pairs = self.neighbors.pairs.entries.iter().zip(&self.neighbors.pairs.springs);
        for (pair, &spring) in pairs {
            let (i, j) = (pair.i as usize, pair.j as usize);
            let (dx, dy) = (p.x[j] - p.x[i], p.y[j] - p.y[i]);
            let distance = (dx * dx + dy * dy).sqrt();
            let overlap = p.r[i] + p.r[j] - distance;
            if overlap > 0.0 && distance > 0.0 {
                let normal = [dx / distance, dy / distance];
                let relative = [p.vx[i] - p.vx[j], p.vy[i] - p.vy[j]];
                let spin = p.omega[i] * p.r[i] + p.omega[j] * p.r[j];
                let motion = kinematics(overlap, normal, relative, spin);
                let force = self.disk_kind.force_of(&self.law, pair.r_star, pair.m_star, &motion, spring);
                let ratio = overlap / p.r[i].min(p.r[j]);
                contacts.push(pile_contact(i, Partner::Disk(j), normal, force, &self.disk_kind, ratio));
            }
        }
        let walls = self.neighbors.walls.entries.iter().zip(&self.neighbors.walls.springs);
        for (candidate, &spring) in walls {
            let (i, k) = (candidate.i as usize, candidate.wall as usize);
            let wall = &self.walls.walls[k];
            let overlap = wall.overlap(p.x[i], p.y[i], p.r[i]);
            if overlap > 0.0 {
                let motion = kinematics(overlap, wall.normal, [p.vx[i], p.vy[i]], p.omega[i] * p.r[i]);
                let force = self.wall_kind.force_of(&self.law, p.r[i], candidate.m_star, &motion, spring);
                let ratio = overlap / p.r[i];
                contacts.push(pile_contact(i, Partner::Wall(k), wall.normal, force, &self.wall_kind, ratio));
            }
        }
        contacts
    }

    /// The pile measures of the current state (see [`Self::contacts`]).
    pub fn pile_metrics(&self) -> PileMetrics {
        let p = &self.particles;
        let g = self.scene.gravity[0].hypot(self.scene.gravity[1]);
        let geometry =
            PileGeometry { x: &p.x, y: &p.y, r: &p.r, weight: p.mass.iter().sum::<f64>() * g, width: self.walls.width };
        PileMetrics::measure(&geometry, &self.contacts())
    }

    /// Evaluates all forces and torques at the current state. With `SAMPLE`, also fills the
    /// contact sums and per-disk contact force magnitudes.
    fn compute_forces<const SAMPLE: bool>(&mut self) {
        // Forces and torques were cleared by the integrator, which read them last.
        let p = &mut self.particles;
        if self.rolling_resistance {
            p.rolling.fill(0.0);
        }
        if SAMPLE {
            p.contact_force.fill(0.0);
            self.totals = ContactTotals::default();
        }
        let (s, mut f) = p.split();
        self.touching.contacts::<L, SAMPLE>(
            &self.law,
            [&self.disk_kind, &self.wall_kind],
            &mut self.neighbors.pairs,
            (&self.walls.walls, &mut self.neighbors.walls),
            &s,
            &mut f,
            &mut self.totals,
        );
    }

    /// Rolling resistance (EDEM's constant directional torque, spec): `μ0 F_n R` summed per disk,
    /// acting against the spin. It is applied to the angular velocity after the integrator's update,
    /// as the change `Δω = −sign(ω) min(|ω|, M_r Δt / I)`: it can stop a spin within one step but
    /// never reverse it (as a torque inside a multistep scheme it would overshoot and chatter).
    /// Returns the kinetic energy it removed (J).
    fn apply_rolling_resistance(&mut self) -> f64 {
        let p = &mut self.particles;
        let mut removed = 0.0;
        for i in 0..p.len() {
            let w = p.omega[i];
            if p.rolling[i] > 0.0 && w != 0.0 {
                let slowed = (w.abs() - p.rolling[i] * p.inv_inertia[i] * self.context.dt).max(0.0).copysign(w);
                removed += 0.5 * (w * w - slowed * slowed) / p.inv_inertia[i];
                p.omega[i] = slowed;
            }
        }
        removed
    }

    /// Runs to the end, to settling, to divergence, or until the observer says stop.
    pub fn run(mut self, observer: &mut dyn FnMut(&Progress) -> Control) -> RunRecord {
        let stability = self.stability();
        let mut warnings: Vec<String> = self.time_step_warning.iter().cloned().collect();
        warnings.extend(stability.warnings.iter().cloned());
        let total_steps = self.scene.total_steps(self.context.dt);
        let sample_every = ((self.scene.run.sample_interval / self.context.dt).round() as u64).max(1);
        let mut frames = FrameSchedule::new(&self.scene, self.context.dt, total_steps);
        let mut monitor = Monitor::new(&self.particles, &self.walls, self.scene.gravity, self.initial_elastic);
        let mut settle = SettleDetector::new(&self.scene.settle);
        let mut history = History::default();
        let mut recorded_frames = Vec::new();
        let (status, message) = loop {
            let s = self.sample();
            if frames.due(self.step) {
                recorded_frames.push(self.snapshot());
            }
            history.push(&s);
            monitor.observe(&s);
            let power_finite = self.last_power.is_none_or(f64::is_finite);
            if let Some(reason) = monitor.divergence(&s, &self.particles, power_finite, &self.scene.limits) {
                break (RunStatus::Diverged, Some(reason));
            }
            let settled = settle.update(&s);
            let progress = Progress {
                step: self.step,
                time: s.time,
                duration: self.scene.run.duration,
                unbalanced_force_ratio: s.unbalanced_force_ratio,
                kinetic_energy: s.kinetic(),
            };
            if observer(&progress) == Control::Stop {
                break (RunStatus::Interrupted, Some(format!("stopped by request at t = {:.6} s", s.time)));
            }
            if settled && self.scene.run.stop_at_settle {
                break (RunStatus::Settled, None);
            }
            if self.step >= total_steps {
                break (if settled { RunStatus::Settled } else { RunStatus::NotSettled }, None);
            }
            // Step to the next sample, recording frames on the way; a non-finite power ends early.
            let next = (self.step + sample_every).min(total_steps);
            while self.step < next {
                let frame_due = self.step + 1 < next && frames.due(self.step + 1);
                self.advance(frame_due || self.step + 1 == next);
                if frame_due {
                    recorded_frames.push(self.snapshot());
                }
                if self.last_power.is_some_and(|p| !p.is_finite()) {
                    break;
                }
            }
        };
        warnings.extend(monitor.warnings(&self.scene.limits));
        RunRecord {
            status,
            message,
            warnings,
            settle_time: settle.settle_time,
            steps: self.step,
            time_step: self.context.dt,
            simulated_time: self.time(),
            pile: self.pile_metrics(),
            stability,
            history,
            final_state: self.snapshot(),
            frames: recorded_frames,
        }
    }
}

/// Relative motion of a contact with unit normal `normal` from body i to j, relative velocity
/// `v_i − v_j` and spin term `ω_i r_i + ω_j r_j` (conventions of [`super::contact`]).
fn kinematics(overlap: f64, normal: [f64; 2], relative: [f64; 2], spin: f64) -> Kinematics {
    let [nx, ny] = normal;
    Kinematics {
        overlap,
        approach_speed: relative[0] * nx + relative[1] * ny,
        tangential_speed: -relative[0] * ny + relative[1] * nx + spin,
    }
}

fn pile_contact(
    disk: usize,
    partner: Partner,
    normal: [f64; 2],
    force: super::contact::ContactForce,
    kind: &ContactKind,
    overlap_ratio: f64,
) -> PileContact {
    PileContact {
        disk,
        partner,
        normal,
        normal_force: force.normal,
        tangential_force: force.tangential,
        friction: if kind.options.tangential { kind.options.friction } else { 0.0 },
        overlap_ratio,
    }
}
