//! Pouring at a rate (`placement.kind = "pour"`, after LAMMPS `fix pour` and LIGGGHTS
//! `fix insert/rate/region`): the [`Inlet`] hands the running simulation its next disks when they are
//! due, each at a seeded random spot of the inlet rectangle where it overlaps no disk already there.
//! A disk that finds no free spot in `placement.max_attempts` tries is refused and counted.
//!
//! The inlet's whole state is one serializable struct (its random stream included), so that a
//! checkpoint saves and restores it whole.

use serde::{Deserialize, Serialize};

use super::config::SceneConfig;
use super::particles::{InitialDisk, Particles};
use super::placement;
use super::rng::Rng;
use super::walls::BoxWalls;

/// How many disks a pour inserted and refused, and the particle steps its disks took.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PourCount {
    /// Disks inserted.
    pub inserted: u64,
    /// Disks refused: no free spot in the inlet.
    pub refused: u64,
    /// Steps times disks present, summed over the steps: the run's cost.
    pub particle_steps: u64,
}

/// The inserter of a pour: the disks still to come, when the next is due, the random stream of
/// the spots and velocities, and what it did so far.
#[derive(Clone, Debug, PartialEq)]
pub struct Inlet {
    /// The radii of all disks in pouring order (m), drawn with the placement seed.
    radii: Vec<f64>,
    /// The next disk to pour.
    next: usize,
    /// When it is due (s).
    due: f64,
    /// Mass of the disks before the next (kg), for a mass rate.
    mass_before: f64,
    /// The stream of spots and velocities (after the radii's draws).
    rng: Rng,
    /// `[x_min, x_max, y_min, y_max]` (m).
    region: [f64; 4],
    /// Disks per second, or kg per second with `by_mass`.
    rate: f64,
    by_mass: bool,
    velocity: [f64; 2],
    spread: f64,
    max_attempts: u32,
    density: f64,
    thickness: f64,
    /// The box's periodic sides, if any: a new disk must clear the disks across them too.
    walls: BoxWalls,
    /// Sum over inserted disks of the step each entered at (the particle steps not taken).
    steps_absent: u64,
    inserted: u64,
    refused: u64,
    /// Kinetic plus potential energy the inserted disks brought in (J).
    energy_in: f64,
}

// What a checkpoint keeps: the inlet's progress; the rest follows from the scene.
super::run_state::persist_fields!(Inlet { next, due, mass_before, rng, steps_absent, inserted, refused, energy_in });

impl Inlet {
    /// The inlet of a pour scene with disks of `density` (kg/m³); `None` for other placements.
    pub fn of_scene(scene: &SceneConfig, density: f64) -> Option<Self> {
        let placement = &scene.placement;
        if placement.kind != super::config::PlacementKind::Pour {
            return None;
        }
        let mut rng = Rng::new(placement.seed);
        let radii = placement::radii(scene, &mut rng);
        let pour = &placement.pour;
        let largest = radii.iter().copied().fold(0.0, f64::max);
        let (rate, by_mass) = match (pour.rate, pour.mass_rate) {
            (Some(rate), _) => (rate, false),
            (None, mass_rate) => (mass_rate.unwrap_or(f64::INFINITY), true),
        };
        Some(Self {
            radii,
            next: 0,
            due: 0.0,
            mass_before: 0.0,
            rng,
            region: pour.inlet(scene.domain.width, scene.domain.height, largest),
            rate,
            by_mass,
            velocity: pour.velocity,
            spread: pour.velocity_spread,
            max_attempts: placement.max_attempts,
            density,
            thickness: scene.particles.thickness,
            walls: BoxWalls::new(&scene.domain),
            steps_absent: 0,
            inserted: 0,
            refused: 0,
            energy_in: 0.0,
        })
    }

    /// The disks of the pour as the run's estimates see them ([`placement::pour_reference`]).
    pub fn reference(&self, scene: &SceneConfig) -> Particles {
        Particles::new(&placement::pour_reference(scene, &self.radii), self.density, self.thickness)
    }

    /// Whether a disk is due by time `t` (s).
    #[inline]
    pub fn due_by(&self, t: f64) -> bool {
        self.next < self.radii.len() && self.due <= t
    }

    /// Whether every disk was inserted or refused.
    pub fn done(&self) -> bool {
        self.next == self.radii.len()
    }

    /// Kinetic plus potential energy the inserted disks brought in (J).
    pub fn energy_in(&self) -> f64 {
        self.energy_in
    }

    /// Disks inserted so far.
    pub fn inserted(&self) -> usize {
        self.inserted as usize
    }

    /// What the pour did by step `steps`, with `present` disks in the box.
    pub fn count(&self, steps: u64, present: usize) -> PourCount {
        PourCount {
            inserted: self.inserted,
            refused: self.refused,
            particle_steps: steps * present as u64 - self.steps_absent,
        }
    }

    /// Inserts into `p` every disk due by time `t` (s) at step `step` (gravity `g`), or refuses
    /// it; returns how many it inserted.
    pub fn pour(&mut self, p: &mut Particles, t: f64, step: u64, g: [f64; 2]) -> usize {
        let before = p.len();
        let reach = 2.0 * self.radii.iter().copied().fold(0.0, f64::max);
        let mut near: Vec<usize> = (0..p.len()).filter(|&k| p.y[k] + p.r[k] + reach > self.region[2]).collect();
        while self.due_by(t) {
            let r = self.radii[self.next];
            let mass = self.density * std::f64::consts::PI * r * r * self.thickness;
            match self.free_spot(p, &near, r) {
                Some(disk) => {
                    near.push(p.len());
                    p.push(&disk, self.density, self.thickness);
                    let speed2 = disk.vx * disk.vx + disk.vy * disk.vy;
                    self.energy_in += 0.5 * mass * speed2 - mass * (g[0] * disk.x + g[1] * disk.y);
                    self.steps_absent += step;
                    self.inserted += 1;
                }
                None => self.refused += 1,
            }
            self.mass_before += mass;
            self.next += 1;
            self.due = if self.by_mass { self.mass_before / self.rate } else { self.next as f64 / self.rate };
        }
        p.len() - before
    }

    /// A disk of radius `r` at a random spot of the inlet overlapping none of the disks `near` of
    /// `p` (nor their images across periodic sides), with a drawn velocity; `None` after
    /// `max_attempts` tries.
    fn free_spot(&mut self, p: &Particles, near: &[usize], r: f64) -> Option<InitialDisk> {
        let [x0, x1, y0, y1] = self.region;
        let free = |x: f64, y: f64| {
            near.iter().all(|&k| {
                let (dx, dy, d) = (self.walls.dx(p.x[k] - x), p.y[k] - y, p.r[k] + r);
                dx * dx + dy * dy >= d * d
            })
        };
        let (x, y) = (0..self.max_attempts).find_map(|_| {
            let (x, y) = (self.rng.range(x0 + r, x1 - r), self.rng.range(y0 + r, y1 - r));
            free(x, y).then_some((x, y))
        })?;
        let spread = self.spread;
        let mut drawn = |v: f64| if spread > 0.0 { v + spread * (2.0 * self.rng.unit() - 1.0) } else { v };
        let (vx, vy) = (drawn(self.velocity[0]), drawn(self.velocity[1]));
        Some(InitialDisk { x, y, r, vx, vy, ..Default::default() })
    }
}
