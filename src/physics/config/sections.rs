//! The scene's sections as declared: every key with its doc comment and `#[key(...)]` line (unit,
//! range, plausible values), and what the scene's values imply (its largest and smallest disk, its
//! step count).

use serde::{Deserialize, Serialize};

use super::{ContactConfig, IntegratorKind, SizeDistribution, StageConfig};
use crate::physics::key_spec::SceneKeys;

/// One simulation's complete input. Every field has a default (see [`Default`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct SceneConfig {
    /// The box the disks live in.
    #[key(table: Some(DomainConfig::KEYS))]
    pub domain: DomainConfig,
    /// Number, size and thickness of the disks.
    #[key(table: Some(ParticlesConfig::KEYS))]
    pub particles: ParticlesConfig,
    /// Where the disks start.
    #[key(table: Some(PlacementConfig::KEYS))]
    pub placement: PlacementConfig,
    /// Particle material, damping and friction.
    #[key(table: Some(MaterialConfig::KEYS))]
    pub material: MaterialConfig,
    /// Wall material; every missing field inherits the particle material's value.
    #[key(table: Some(WallMaterialConfig::KEYS))]
    pub wall_material: WallMaterialConfig,
    /// Which contact law and its options.
    #[key(table: Some(ContactConfig::KEYS))]
    pub contact: ContactConfig,
    /// Gravitational acceleration vector (m/s²); the paper's default points down.
    #[key(unit: "m/s²", range: "finite")]
    pub gravity: [f64; 2],
    /// Time stepping scheme and step.
    #[key(table: Some(IntegratorConfig::KEYS))]
    pub integrator: IntegratorConfig,
    /// Numerical (non-physical) damping: Cundall local damping and global viscous damping.
    #[key(table: Some(DampingConfig::KEYS))]
    pub damping: DampingConfig,
    /// Duration, sampling and frames.
    #[key(table: Some(RunConfig::KEYS))]
    pub run: RunConfig,
    /// When the pile counts as settled.
    #[key(table: Some(SettleConfig::KEYS))]
    pub settle: SettleConfig,
    /// Validity and divergence limits.
    #[key(table: Some(LimitsConfig::KEYS))]
    pub limits: LimitsConfig,
    /// How contacts are found.
    #[key(table: Some(NeighborConfig::KEYS))]
    pub neighbors: NeighborConfig,
    /// A deposition protocol: stages run in order before the scene's own physics, each changing a
    /// few keys until a condition ends it (`[[scene.stages]]`; none by default).
    #[key(table: Some(StageConfig::KEYS))]
    pub stages: Vec<StageConfig>,
}

/// Axis-aligned box: floor `y = 0`, side walls `x = 0` and `x = width` (or a periodic boundary
/// there), optional lid `y = height`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct DomainConfig {
    /// Box width (m).
    #[key(unit: "m", range: "> 0", plausible: Some((1e-5, 100.0)))]
    pub width: f64,
    /// Box height (m): the lid's position, and the top of the region random placement fills.
    #[key(unit: "m", range: "> 0", plausible: Some((1e-5, 100.0)))]
    pub height: f64,
    /// Whether a lid wall closes the box at `y = height`.
    #[key(range: "true or false")]
    pub lid: bool,
    /// Whether the sides are periodic: no side walls, a disk leaving at `x = width` comes back at
    /// `x = 0` and disks touch across the boundary; the box must be at least two largest disk
    /// diameters wide, gravity straight down.
    #[key(range: "true or false")]
    pub periodic_x: bool,
}

/// Disk count and radii. Radii: all `radius`; or uniform in `[radius, radius_max]`; or the list
/// `radii`; or drawn from `size_distribution`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct ParticlesConfig {
    /// Number of disks (ignored when placement reads a file: the file's rows count).
    #[key(range: ">= 1")]
    pub count: usize,
    /// Radius (m), or the smallest radius of a uniform distribution.
    #[key(unit: "m", range: "> 0", plausible: Some((1e-7, 1.0)))]
    pub radius: f64,
    /// Largest radius (m) of a uniform radius distribution, drawn with the placement seed.
    #[key(unit: "m", range: ">= particles.radius", plausible: Some((1e-7, 1.0)))]
    pub radius_max: Option<f64>,
    /// Explicit radius per disk (m); its length must equal `count`.
    #[key(unit: "m", range: "each > 0")]
    pub radii: Option<Vec<f64>>,
    /// A size distribution of the radii, drawn with the placement seed: a discrete mixture by
    /// number, area or mass fraction; uniform; truncated normal or lognormal (docs/studies.md).
    #[key(range: "a table: kind and its keys")]
    pub size_distribution: Option<SizeDistribution>,
    /// Disk thickness `h` (m): mass = density·π·R²·h (paper eq 4 with unit height).
    #[key(unit: "m", range: "> 0", plausible: Some((1e-7, 100.0)))]
    pub thickness: f64,
}

/// How initial positions are made.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlacementKind {
    /// Seeded random sequential placement without overlaps (the paper's generator).
    Random,
    /// Rows of touching-free disks filled from the floor up.
    Lattice,
    /// Each disk, in an order and at an x drawn from the seed, falls straight down onto the pile and
    /// rolls to rest on the floor, or on two disks or a disk and a wall (sequential deposition):
    /// a pile at rest, with none of the impacts.
    Dropped,
    /// Explicit initial states read by the caller from a CSV file and passed to the simulation.
    File,
    /// Explicit initial states read by the caller from a LAMMPS data or dump file.
    Lammps,
    /// Disks poured into the running simulation from an inlet region at a rate (`[placement.pour]`).
    Pour,
}

impl PlacementKind {
    /// Whether the disks come from `placement.file` (read by the caller) rather than a generator.
    pub fn reads_file(self) -> bool {
        matches!(self, PlacementKind::File | PlacementKind::Lammps)
    }
}

/// Initial placement of the disks.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct PlacementConfig {
    /// Which generator.
    #[key(one_of: &["random", "lattice", "dropped", "file", "lammps", "pour"])]
    pub kind: PlacementKind,
    /// Seed for random placement and random radii; same seed, same positions on every platform.
    #[key(range: ">= 0")]
    pub seed: u64,
    /// Lattice: gap between neighbouring disk surfaces, as a fraction of the largest diameter.
    #[key(range: ">= 0")]
    pub lattice_gap: f64,
    /// Lattice: hexagonal (true) or square (false) rows.
    #[key(range: "true or false")]
    pub lattice_hexagonal: bool,
    /// File placement: path of a CSV with `x,y` and optional `r,vx,vy,omega,angle` columns, or
    /// (`kind = "lammps"`) of a LAMMPS data or dump file (read by the caller).
    #[key(range: "a CSV or LAMMPS file path")]
    pub file: Option<String>,
    /// File placement: path of a CSV with the contacts' history (tangential springs, law states) to
    /// start from, as `demsweep export --format csv` writes it (read by the caller; a restart).
    #[key(range: "a CSV path")]
    pub contacts: Option<String>,
    /// Random placement tries per disk before giving up.
    #[key(range: ">= 1")]
    pub max_attempts: u32,
    /// Random or lattice placement: the disks are placed between this height and `domain.height`,
    /// then moved down by it, falling at `√(2 g lowered_by)` (g: gravity's magnitude): the impacts
    /// of that pour without the time of its free fall (m; 0: they start at rest where placed).
    #[key(unit: "m", range: ">= 0")]
    pub lowered_by: f64,
    /// Pour placement: the inlet, its rate and the disks' initial velocity.
    #[key(table: Some(PourConfig::KEYS))]
    pub pour: PourConfig,
}

/// Pouring at a rate (`placement.kind = "pour"`): the disks, radii drawn with the placement seed,
/// enter one after another during the run at seeded random spots of the inlet rectangle that overlap
/// no disk there; a disk that finds no free spot in `placement.max_attempts` tries is refused.
/// Give `rate` or `mass_rate`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct PourConfig {
    /// Disks inserted per second: disk k is due at k / rate.
    #[key(unit: "1/s", range: "> 0", plausible: Some((1e-3, 1e7)))]
    pub rate: Option<f64>,
    /// Mass inserted per second: disk k is due when the disks before it weigh mass_rate times the time.
    #[key(unit: "kg/s", range: "> 0")]
    pub mass_rate: Option<f64>,
    /// The inlet's left edge (m); 0 when not given.
    #[key(unit: "m", range: "[0, domain.width)")]
    pub x_min: Option<f64>,
    /// The inlet's right edge (m); `domain.width` when not given.
    #[key(unit: "m", range: "(inlet x_min, domain.width]")]
    pub x_max: Option<f64>,
    /// The inlet's bottom (m); two largest diameters below `y_max` when not given.
    #[key(unit: "m", range: "[0, inlet y_max)")]
    pub y_min: Option<f64>,
    /// The inlet's top (m); `domain.height` when not given.
    #[key(unit: "m", range: "(inlet y_min, domain.height]")]
    pub y_max: Option<f64>,
    /// Initial velocity of each disk (m/s).
    #[key(unit: "m/s", range: "finite")]
    pub velocity: [f64; 2],
    /// Each velocity component is drawn uniform within this of `velocity` (m/s).
    #[key(unit: "m/s", range: ">= 0")]
    pub velocity_spread: f64,
}

impl PourConfig {
    /// The inlet rectangle `[x_min, x_max, y_min, y_max]` (m) in a `width` × `height` box for disks
    /// up to `largest` in radius, the keys not given filled in.
    pub fn inlet(&self, width: f64, height: f64, largest: f64) -> [f64; 4] {
        let y_max = self.y_max.unwrap_or(height);
        [self.x_min.unwrap_or(0.0), self.x_max.unwrap_or(width), self.y_min.unwrap_or(y_max - 4.0 * largest), y_max]
    }
}

/// Particle material. Give `poisson_ratio` or `shear_modulus` (not both), `beta` or `restitution` (not both).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct MaterialConfig {
    /// Density (kg/m³).
    #[key(unit: "kg/m³", range: "> 0", plausible: Some((50.0, 25_000.0)))]
    pub density: f64,
    /// Young's modulus E (Pa).
    #[key(unit: "Pa", range: "> 0", plausible: Some((1e5, 1e13)))]
    pub youngs_modulus: f64,
    /// Poisson's ratio ν in (-1, 0.5]; 0.3 when neither it nor `shear_modulus` is given.
    #[key(range: "(-1, 0.5]")]
    pub poisson_ratio: Option<f64>,
    /// Shear modulus G (Pa); then ν = E/(2G) − 1 (paper eq 2).
    #[key(unit: "Pa", range: "> 0", plausible: Some((1e5, 1e13)))]
    pub shear_modulus: Option<f64>,
    /// The paper's damping factor β (≥ 0).
    #[key(range: ">= 0")]
    pub beta: Option<f64>,
    /// Coefficient of restitution e in (0, 1], mapped to β by EDEM's relation; 0.5 when neither is given.
    #[key(range: "(0, 1]")]
    pub restitution: Option<f64>,
    /// Sliding friction coefficient μ (≥ 0).
    #[key(range: ">= 0")]
    pub friction: f64,
    /// Rolling friction coefficient μ0 (≥ 0): constant directional torque μ0·Fn·R.
    #[key(range: ">= 0")]
    pub rolling_friction: f64,
}

/// Wall material; `None` fields take the particle material's value.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct WallMaterialConfig {
    /// Young's modulus of the walls (Pa).
    #[key(unit: "Pa", range: "> 0", plausible: Some((1e5, 1e13)))]
    pub youngs_modulus: Option<f64>,
    /// Poisson's ratio of the walls.
    #[key(range: "(-1, 0.5]")]
    pub poisson_ratio: Option<f64>,
    /// Shear modulus of the walls (Pa).
    #[key(unit: "Pa", range: "> 0", plausible: Some((1e5, 1e13)))]
    pub shear_modulus: Option<f64>,
    /// Damping factor β of disk-wall contacts.
    #[key(range: ">= 0")]
    pub beta: Option<f64>,
    /// Restitution of disk-wall contacts.
    #[key(range: "(0, 1]")]
    pub restitution: Option<f64>,
    /// Sliding friction of disk-wall contacts.
    #[key(range: ">= 0")]
    pub friction: Option<f64>,
    /// Rolling friction of disk-wall contacts.
    #[key(range: ">= 0")]
    pub rolling_friction: Option<f64>,
}

/// Time step used when none of `time_step`, `contact_time_fraction` and `rayleigh_fraction` is given (s).
pub const DEFAULT_TIME_STEP: f64 = 1e-5;

/// Integrator choice and time step. The step is given as at most one of `time_step` (absolute),
/// `contact_time_fraction` or `rayleigh_fraction` (relative to a time scale of the scene, resolved
/// before the run by [`crate::physics::time_step`]); [`DEFAULT_TIME_STEP`] when none is given.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct IntegratorConfig {
    /// The scheme.
    #[key(one_of: &["adams_bashforth_moulton", "velocity_verlet"])]
    pub scheme: IntegratorKind,
    /// Time step Δt (s).
    #[key(unit: "s", range: "> 0", plausible: Some((1e-12, 0.1)))]
    pub time_step: Option<f64>,
    /// Δt as this fraction of the Hertz contact time of the scene's hardest impact.
    #[key(range: "(0, 1]")]
    pub contact_time_fraction: Option<f64>,
    /// Δt as this fraction of the Rayleigh time of the smallest disk (EDEM's convention).
    #[key(range: "(0, 1]")]
    pub rayleigh_fraction: Option<f64>,
}

impl IntegratorConfig {
    /// The absolute time step when the scene fixes one (given, or the default); `None` when it is
    /// relative to a time scale of the scene and must be resolved.
    pub fn fixed_time_step(&self) -> Option<f64> {
        match (self.contact_time_fraction, self.rayleigh_fraction) {
            (None, None) => Some(self.time_step.unwrap_or(DEFAULT_TIME_STEP)),
            _ => None,
        }
    }
}

/// Numerical damping, applied by the integrator to every disk's net force and torque (its forces:
/// `crate::physics::integrator`); its work is dissipated energy. Both off by default.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct DampingConfig {
    /// Cundall local (non-viscous) damping α in [0, 1): every component of the net force and the
    /// torque is reduced against the velocity, `F_k ← F_k − α |F_k| sign(v_k)` (Cundall 1987).
    #[key(range: "[0, 1)")]
    pub local: f64,
    /// Whether gravity is part of the force that local damping reduces (Yade's convention).
    #[key(range: "true or false")]
    pub local_gravity: bool,
    /// Global viscous damping rate c (1/s): `F ← F − c m v`, `M ← M − c I ω`.
    #[key(unit: "1/s", range: ">= 0")]
    pub viscous: f64,
}

impl DampingConfig {
    /// Whether any numerical damping acts.
    pub fn is_active(&self) -> bool {
        self.local > 0.0 || self.viscous > 0.0
    }
}

/// Run length, sampling and recorded frames.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct RunConfig {
    /// Simulated time (s): the run ends here unless it settles or diverges first.
    #[key(unit: "s", range: "> 0", plausible: Some((1e-9, 1e6)))]
    pub duration: f64,
    /// Interval between diagnostic samples (s), rounded to whole steps (at least one).
    #[key(unit: "s", range: "> 0")]
    pub sample_interval: f64,
    /// Stop as soon as the settle criterion holds.
    #[key(range: "true or false")]
    pub stop_at_settle: bool,
    /// Times (s) at which full states are recorded as frames.
    #[key(unit: "s", range: "each >= 0")]
    pub frame_times: Vec<f64>,
    /// Record a frame every this many seconds (in addition to `frame_times`).
    #[key(unit: "s", range: "> 0")]
    pub frame_interval: Option<f64>,
}

/// Settle criterion: UBF below `ubf_threshold` (and kinetic energy below its threshold, if given),
/// held continuously for `hold_time`. The settle time is when that stretch began.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct SettleConfig {
    /// Unbalanced force ratio threshold.
    #[key(range: "> 0")]
    pub ubf_threshold: f64,
    /// How long (s) the criterion must hold.
    #[key(unit: "s", range: ">= 0")]
    pub hold_time: f64,
    /// Optional total kinetic energy threshold (J).
    #[key(unit: "J", range: "> 0")]
    pub kinetic_energy_threshold: Option<f64>,
}

/// Validity warnings and divergence limits.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct LimitsConfig {
    /// A run diverges when any overlap exceeds this fraction of the smaller radius.
    #[key(range: "> 0")]
    pub max_overlap_ratio: f64,
    /// Overlaps beyond this fraction of the radius are reported as outside Hertz validity.
    #[key(range: "> 0")]
    pub overlap_warning_ratio: f64,
    /// A run diverges when mechanical energy grows by more than this fraction of the energy available.
    #[key(range: "> 0")]
    pub energy_growth_ratio: f64,
    /// Warn when the energy balance (mechanical + dissipated = initial) is off by more than this
    /// fraction of the energy available (default 0.01).
    #[key(range: "> 0")]
    pub energy_balance_tolerance: f64,
    /// Warn when Δt exceeds this fraction of the predicted Hertz contact time.
    #[key(range: "> 0")]
    pub contact_time_fraction: f64,
    /// Warn when Δt times the largest contact damping rate exceeds this (per integrator stability).
    #[key(range: "> 0")]
    pub damping_rate_fraction: f64,
}

/// Broad phase selection.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BroadPhaseKind {
    /// Cell grid: O(N) per neighbour-list build.
    Grid,
    /// All pairs: O(N²), kept as a reference for tests.
    AllPairs,
}

/// Neighbour list options.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields, default)]
pub struct NeighborConfig {
    /// Broad phase used to build the neighbour list.
    #[key(one_of: &["grid", "all_pairs"])]
    pub broad_phase: BroadPhaseKind,
    /// Verlet skin as a fraction of the largest radius: the list is rebuilt when any disk moved
    /// more than half the skin.
    #[key(range: "> 0")]
    pub skin_ratio: f64,
}

impl SceneConfig {
    /// The largest disk radius the configuration can produce (m).
    pub fn largest_radius(&self) -> f64 {
        let p = &self.particles;
        match (&p.radii, p.radius_max, &p.size_distribution) {
            (Some(radii), _, _) => radii.iter().cloned().fold(0.0, f64::max),
            (None, Some(rmax), _) => rmax,
            (None, None, Some(distribution)) => distribution.bounds().1,
            (None, None, None) => p.radius,
        }
    }

    /// Number of time steps of the full duration at time step `dt` (s).
    pub fn total_steps(&self, dt: f64) -> u64 {
        (self.run.duration / dt).round().max(1.0) as u64
    }

    /// The smallest disk radius the configuration can produce (m).
    pub fn smallest_radius(&self) -> f64 {
        let p = &self.particles;
        match (&p.radii, &p.size_distribution) {
            (Some(radii), _) => radii.iter().cloned().fold(f64::INFINITY, f64::min),
            (None, Some(distribution)) => distribution.bounds().0,
            (None, None) => p.radius,
        }
    }
}
