//! What a scene is: every input of one simulation, with defaults, as plain serde data.
//!
//! A study file's base scene and each swept run deserialize into [`SceneConfig`]; unknown keys are
//! rejected by serde, impossible values by [`SceneConfig::validate`], which names the key path.

use std::collections::HashSet;

use serde::{Deserialize, Serialize};

use super::key_spec::scene_section;
use super::number::{exact, significant};
use super::warning::WarningKind;

pub use super::contact::{ContactConfig, ContactLawKind};
pub use super::scheme::IntegratorKind;
pub use super::size_distribution::SizeDistribution;
pub use super::stage::{StageConfig, StageEnd};

scene_section! {
/// One simulation's complete input. Every field has a default (see [`Default`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
}

scene_section! {
/// Axis-aligned box: floor `y = 0`, side walls `x = 0` and `x = width` (or a periodic boundary
/// there), optional lid `y = height`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
}

scene_section! {
/// Disk count and radii. Radii: all `radius`; or uniform in `[radius, radius_max]`; or the list
/// `radii`; or drawn from `size_distribution`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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

scene_section! {
/// Initial placement of the disks.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
}

scene_section! {
/// Pouring at a rate (`placement.kind = "pour"`): the disks, radii drawn with the placement seed,
/// enter one after another during the run at seeded random spots of the inlet rectangle that overlap
/// no disk there; a disk that finds no free spot in `placement.max_attempts` tries is refused.
/// Give `rate` or `mass_rate`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
}

impl Default for PourConfig {
    fn default() -> Self {
        Self {
            rate: None,
            mass_rate: None,
            x_min: None,
            x_max: None,
            y_min: None,
            y_max: None,
            velocity: [0.0, 0.0],
            velocity_spread: 0.0,
        }
    }
}

impl PourConfig {
    /// The inlet rectangle `[x_min, x_max, y_min, y_max]` (m) in a `width` × `height` box for disks
    /// up to `largest` in radius, the keys not given filled in.
    pub fn inlet(&self, width: f64, height: f64, largest: f64) -> [f64; 4] {
        let y_max = self.y_max.unwrap_or(height);
        [self.x_min.unwrap_or(0.0), self.x_max.unwrap_or(width), self.y_min.unwrap_or(y_max - 4.0 * largest), y_max]
    }
}

scene_section! {
/// Particle material. Give `poisson_ratio` or `shear_modulus` (not both), `beta` or `restitution` (not both).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
}

scene_section! {
/// Wall material; `None` fields take the particle material's value.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
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
}

/// Time step used when none of `time_step`, `contact_time_fraction` and `rayleigh_fraction` is given (s).
pub const DEFAULT_TIME_STEP: f64 = 1e-5;

scene_section! {
/// Integrator choice and time step. The step is given as at most one of `time_step` (absolute),
/// `contact_time_fraction` or `rayleigh_fraction` (relative to a time scale of the scene, resolved
/// before the run by [`super::time_step`]); [`DEFAULT_TIME_STEP`] when none is given.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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

scene_section! {
/// Numerical damping, applied by the integrator to every disk's net force and torque (its forces:
/// `super::integrator`); its work is dissipated energy. Both off by default.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
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
}

impl DampingConfig {
    /// Whether any numerical damping acts.
    pub fn is_active(&self) -> bool {
        self.local > 0.0 || self.viscous > 0.0
    }
}

scene_section! {
/// Run length, sampling and recorded frames.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
}

scene_section! {
/// Settle criterion: UBF below `ubf_threshold` (and kinetic energy below its threshold, if given),
/// held continuously for `hold_time`. The settle time is when that stretch began.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
}

scene_section! {
/// Validity warnings and divergence limits.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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

scene_section! {
/// Neighbour list options.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
}

impl Default for SceneConfig {
    fn default() -> Self {
        Self {
            domain: DomainConfig::default(),
            particles: ParticlesConfig::default(),
            placement: PlacementConfig::default(),
            material: MaterialConfig::default(),
            wall_material: WallMaterialConfig::default(),
            contact: ContactConfig::default(),
            gravity: [0.0, -9.81],
            integrator: IntegratorConfig::default(),
            damping: DampingConfig::default(),
            run: RunConfig::default(),
            settle: SettleConfig::default(),
            limits: LimitsConfig::default(),
            neighbors: NeighborConfig::default(),
            stages: Vec::new(),
        }
    }
}

impl Default for DomainConfig {
    fn default() -> Self {
        Self { width: 0.4, height: 0.6, lid: false, periodic_x: false }
    }
}

impl Default for ParticlesConfig {
    fn default() -> Self {
        Self { count: 300, radius: 0.01, radius_max: None, radii: None, size_distribution: None, thickness: 1.0 }
    }
}

impl Default for PlacementConfig {
    fn default() -> Self {
        Self {
            kind: PlacementKind::Random,
            seed: 12345,
            lattice_gap: 0.05,
            lattice_hexagonal: false,
            file: None,
            contacts: None,
            max_attempts: 10_000,
            lowered_by: 0.0,
            pour: PourConfig::default(),
        }
    }
}

impl Default for MaterialConfig {
    fn default() -> Self {
        Self {
            density: 1000.0,
            youngs_modulus: 1e9,
            poisson_ratio: None,
            shear_modulus: None,
            beta: None,
            restitution: None,
            friction: 0.5,
            rolling_friction: 0.0,
        }
    }
}

impl Default for IntegratorConfig {
    fn default() -> Self {
        Self {
            scheme: IntegratorKind::AdamsBashforthMoulton,
            time_step: None,
            contact_time_fraction: None,
            rayleigh_fraction: None,
        }
    }
}

impl Default for DampingConfig {
    fn default() -> Self {
        Self { local: 0.0, local_gravity: true, viscous: 0.0 }
    }
}

impl Default for RunConfig {
    fn default() -> Self {
        Self {
            duration: 1.5,
            sample_interval: 1e-3,
            stop_at_settle: true,
            frame_times: Vec::new(),
            frame_interval: None,
        }
    }
}

impl Default for SettleConfig {
    fn default() -> Self {
        Self { ubf_threshold: 1e-2, hold_time: 0.05, kinetic_energy_threshold: None }
    }
}

impl Default for LimitsConfig {
    fn default() -> Self {
        Self {
            max_overlap_ratio: 0.5,
            overlap_warning_ratio: 0.1,
            energy_growth_ratio: 0.5,
            energy_balance_tolerance: 0.01,
            contact_time_fraction: 0.1,
            damping_rate_fraction: 0.5,
        }
    }
}

impl Default for NeighborConfig {
    fn default() -> Self {
        Self { broad_phase: BroadPhaseKind::Grid, skin_ratio: 0.3 }
    }
}

/// One invalid value: the dotted key path (as in a study file) and why it is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ConfigIssue {
    /// Dotted key path, e.g. `material.poisson_ratio`.
    pub key: String,
    /// What is wrong, in words.
    pub reason: String,
}

impl std::fmt::Display for ConfigIssue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.key, self.reason)
    }
}

/// Collects issues while validating.
struct Checker(Vec<ConfigIssue>);

impl Checker {
    fn fail(&mut self, key: &str, reason: impl Into<String>) {
        self.0.push(ConfigIssue { key: key.to_string(), reason: reason.into() });
    }
    fn positive(&mut self, key: &str, value: f64) {
        if !(value.is_finite() && value > 0.0) {
            self.fail(key, format!("must be a finite number > 0, got {}", exact(value)));
        }
    }
    fn non_negative(&mut self, key: &str, value: f64) {
        if !(value.is_finite() && value >= 0.0) {
            self.fail(key, format!("must be a finite number >= 0, got {}", exact(value)));
        }
    }
    fn finite(&mut self, key: &str, value: f64) {
        if !value.is_finite() {
            self.fail(key, format!("must be finite, got {}", exact(value)));
        }
    }
    fn poisson(&mut self, key: &str, nu: f64) {
        if !(nu > -1.0 && nu <= 0.5) {
            self.fail(key, format!("Poisson's ratio must lie in (-1, 0.5], got {}", exact(nu)));
        }
    }
    fn restitution(&mut self, key: &str, e: f64) {
        if !(e > 0.0 && e <= 1.0) {
            self.fail(key, format!("restitution must lie in (0, 1], got {}", exact(e)));
        }
    }
    fn exclusive(&mut self, a: &str, a_set: bool, b: &str, b_set: bool) {
        if a_set && b_set {
            self.fail(b, format!("give either {a} or {b}, not both"));
        }
    }
}

/// The keys the particle and the wall material share, as their checks see them: the section they
/// are under and each value given (a wall's missing value follows the particle material's).
struct SharedMaterialKeys {
    section: &'static str,
    youngs_modulus: Option<f64>,
    poisson_ratio: Option<f64>,
    shear_modulus: Option<f64>,
    beta: Option<f64>,
    restitution: Option<f64>,
    friction: Option<f64>,
    rolling_friction: Option<f64>,
}

impl SharedMaterialKeys {
    /// Checks each value given; a shear modulus gives ν with this section's Young's modulus, else
    /// with `youngs_modulus` (the particle material's).
    fn check(&self, c: &mut Checker, youngs_modulus: f64) {
        let key = |name: &str| format!("{}.{name}", self.section);
        if let Some(e) = self.youngs_modulus {
            c.positive(&key("youngs_modulus"), e);
        }
        let (poisson, shear) = (key("poisson_ratio"), key("shear_modulus"));
        c.exclusive(&poisson, self.poisson_ratio.is_some(), &shear, self.shear_modulus.is_some());
        if let Some(nu) = self.poisson_ratio {
            c.poisson(&poisson, nu);
        }
        if let Some(g) = self.shear_modulus {
            c.positive(&shear, g);
            c.poisson(&shear, self.youngs_modulus.unwrap_or(youngs_modulus) / (2.0 * g) - 1.0);
        }
        let (beta, restitution) = (key("beta"), key("restitution"));
        c.exclusive(&beta, self.beta.is_some(), &restitution, self.restitution.is_some());
        if let Some(b) = self.beta {
            c.non_negative(&beta, b);
        }
        if let Some(e) = self.restitution {
            c.restitution(&restitution, e);
        }
        if let Some(f) = self.friction {
            c.non_negative(&key("friction"), f);
        }
        if let Some(f) = self.rolling_friction {
            c.non_negative(&key("rolling_friction"), f);
        }
    }
}

impl MaterialConfig {
    fn shared_keys(&self) -> SharedMaterialKeys {
        SharedMaterialKeys {
            section: "material",
            youngs_modulus: Some(self.youngs_modulus),
            poisson_ratio: self.poisson_ratio,
            shear_modulus: self.shear_modulus,
            beta: self.beta,
            restitution: self.restitution,
            friction: Some(self.friction),
            rolling_friction: Some(self.rolling_friction),
        }
    }
}

impl WallMaterialConfig {
    fn shared_keys(&self) -> SharedMaterialKeys {
        SharedMaterialKeys {
            section: "wall_material",
            youngs_modulus: self.youngs_modulus,
            poisson_ratio: self.poisson_ratio,
            shear_modulus: self.shear_modulus,
            beta: self.beta,
            restitution: self.restitution,
            friction: self.friction,
            rolling_friction: self.rolling_friction,
        }
    }
}

impl SceneConfig {
    /// Checks every value; returns all problems at once, each naming its key path.
    pub fn validate(&self) -> Result<(), Vec<ConfigIssue>> {
        let mut c = Checker(Vec::new());
        self.check_geometry(&mut c);
        self.check_material(&mut c);
        self.check_time(&mut c);
        c.0.extend(stage_issues(self));
        if c.0.is_empty() { Ok(()) } else { Err(c.0) }
    }

    fn check_geometry(&self, c: &mut Checker) {
        let d = &self.domain;
        c.positive("domain.width", d.width);
        c.positive("domain.height", d.height);
        let p = &self.particles;
        if p.count == 0 && !self.placement.kind.reads_file() {
            c.fail("particles.count", "a scene needs at least one disk, got 0");
        }
        c.positive("particles.radius", p.radius);
        c.positive("particles.thickness", p.thickness);
        if let Some(rmax) = p.radius_max
            && !(rmax.is_finite() && rmax >= p.radius)
        {
            c.fail(
                "particles.radius_max",
                format!("must be >= particles.radius ({}), got {}", exact(p.radius), exact(rmax)),
            );
        }
        c.exclusive("particles.radius_max", p.radius_max.is_some(), "particles.radii", p.radii.is_some());
        let distribution = p.size_distribution.is_some();
        c.exclusive("particles.radius_max", p.radius_max.is_some(), "particles.size_distribution", distribution);
        c.exclusive("particles.radii", p.radii.is_some(), "particles.size_distribution", distribution);
        for issue in p.size_distribution.iter().flat_map(SizeDistribution::issues) {
            c.fail(&format!("particles.size_distribution.{}", issue.key), issue.reason);
        }
        if let Some(radii) = &p.radii {
            if radii.len() != p.count {
                c.fail("particles.radii", format!("has {} entries but particles.count is {}", radii.len(), p.count));
            }
            if let Some(bad) = radii.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
                c.fail("particles.radii", format!("every radius must be > 0, found {}", exact(*bad)));
            }
        }
        let largest = self.largest_radius();
        if largest.is_finite() && 2.0 * largest > d.width {
            c.fail(
                "domain.width",
                format!("{} m is narrower than the largest disk diameter {} m", exact(d.width), exact(2.0 * largest)),
            );
        } else if d.periodic_x && largest.is_finite() && 4.0 * largest > d.width {
            c.fail(
                "domain.width",
                format!(
                    "{} m is narrower than two largest disk diameters ({} m): with domain.periodic_x a disk would touch another and its image",
                    exact(d.width),
                    exact(4.0 * largest)
                ),
            );
        }
        if self.placement.kind.reads_file() && self.placement.file.is_none() {
            c.fail("placement.file", "placement.kind = \"file\" or \"lammps\" needs placement.file (a file path)");
        }
        if !self.placement.kind.reads_file() && self.placement.contacts.is_some() {
            c.fail("placement.contacts", "a contact history needs its disks: set placement.kind = \"file\"");
        }
        c.non_negative("placement.lattice_gap", self.placement.lattice_gap);
        if self.placement.max_attempts == 0 {
            c.fail("placement.max_attempts", "must be at least 1");
        }
        self.check_lowering(c, largest);
        self.check_pour(c, largest);
        c.finite("gravity[0]", self.gravity[0]);
        c.finite("gravity[1]", self.gravity[1]);
        if d.periodic_x && self.gravity[0] != 0.0 {
            c.fail(
                "domain.periodic_x",
                format!(
                    "periodic sides need gravity straight down, got gravity[0] = {}: the energy balance counts gravity's work by position, which a disk wrapping around would jump",
                    exact(self.gravity[0])
                ),
            );
        }
        let n = &self.neighbors;
        c.positive("neighbors.skin_ratio", n.skin_ratio);
    }

    /// Dropped placement and a lowered start move disks along −y: both need gravity straight down.
    fn check_lowering(&self, c: &mut Checker, largest: f64) {
        let (p, g) = (&self.placement, self.gravity);
        let down = g[0] == 0.0 && g[1] < 0.0;
        let gravity = format!("gravity = [0, g] with g < 0, got [{}, {}]", exact(g[0]), exact(g[1]));
        if p.kind == PlacementKind::Dropped && !down {
            c.fail(
                "placement.kind",
                format!("dropped placement rests each disk on what lies below it: it needs {gravity}"),
            );
        }
        c.non_negative("placement.lowered_by", p.lowered_by);
        if !p.lowered_by.is_finite() || p.lowered_by <= 0.0 {
            return;
        }
        let room = self.domain.height - p.lowered_by;
        if !matches!(p.kind, PlacementKind::Random | PlacementKind::Lattice) {
            c.fail(
                "placement.lowered_by",
                "lowers a random or lattice placement: dropped disks start at rest on the pile, file disks with their own velocities",
            );
        } else if !down {
            c.fail("placement.lowered_by", format!("lowers the disks along gravity straight down: it needs {gravity}"));
        } else if largest.is_finite() && room < 2.0 * largest {
            c.fail(
                "placement.lowered_by",
                format!(
                    "{} m leaves {} m of domain.height = {} m for the disks, less than the largest diameter {} m",
                    exact(p.lowered_by),
                    significant(room, 6),
                    exact(self.domain.height),
                    exact(2.0 * largest)
                ),
            );
        }
    }

    /// A pour needs one rate and an inlet inside the box that holds its largest disk.
    fn check_pour(&self, c: &mut Checker, largest: f64) {
        let (pour, d) = (&self.placement.pour, &self.domain);
        if let Some(rate) = pour.rate {
            c.positive("placement.pour.rate", rate);
        }
        if let Some(rate) = pour.mass_rate {
            c.positive("placement.pour.mass_rate", rate);
        }
        c.exclusive("placement.pour.rate", pour.rate.is_some(), "placement.pour.mass_rate", pour.mass_rate.is_some());
        c.finite("placement.pour.velocity[0]", pour.velocity[0]);
        c.finite("placement.pour.velocity[1]", pour.velocity[1]);
        c.non_negative("placement.pour.velocity_spread", pour.velocity_spread);
        if self.placement.kind != PlacementKind::Pour {
            if *pour != PourConfig::default() {
                c.fail("placement.pour", "sets a pour: it needs placement.kind = \"pour\"");
            }
            return;
        }
        if pour.rate.is_none() && pour.mass_rate.is_none() {
            c.fail("placement.pour.rate", "a pour needs placement.pour.rate or placement.pour.mass_rate");
        }
        if !largest.is_finite() {
            return;
        }
        let [x0, x1, y0, y1] = pour.inlet(d.width, d.height, largest);
        let sides =
            [("x_min", x0, 0.0, x1), ("x_max", x1, x0, d.width), ("y_min", y0, 0.0, y1), ("y_max", y1, y0, d.height)];
        for (key, value, low, high) in sides {
            if !(value.is_finite() && value >= low && value <= high) {
                let range = format!("[{}, {}]", significant(low, 6), significant(high, 6));
                c.fail(
                    &format!("placement.pour.{key}"),
                    format!("must lie in {range} (the box and the inlet's other side), got {}", exact(value)),
                );
            }
        }
        let room = (x1 - x0).min(y1 - y0);
        if room.is_finite() && room < 2.0 * largest {
            c.fail(
                "placement.pour",
                format!(
                    "the inlet [{}, {}] x [{}, {}] m is narrower than the largest disk diameter {} m",
                    significant(x0, 6),
                    significant(x1, 6),
                    significant(y0, 6),
                    significant(y1, 6),
                    exact(2.0 * largest)
                ),
            );
        }
    }

    fn check_material(&self, c: &mut Checker) {
        let m = &self.material;
        c.positive("material.density", m.density);
        m.shared_keys().check(c, m.youngs_modulus);
        self.wall_material.shared_keys().check(c, m.youngs_modulus);
        for (key, reason) in self.contact.problems() {
            c.fail(&key, reason);
        }
    }

    fn check_time(&self, c: &mut Checker) {
        let i = &self.integrator;
        if let Some(dt) = i.time_step {
            c.positive("integrator.time_step", dt);
        }
        for (key, fraction) in [
            ("integrator.contact_time_fraction", i.contact_time_fraction),
            ("integrator.rayleigh_fraction", i.rayleigh_fraction),
        ] {
            if let Some(f) = fraction
                && !(f.is_finite() && f > 0.0 && f <= 1.0)
            {
                c.fail(key, format!("must lie in (0, 1], got {}", exact(f)));
            }
            c.exclusive("integrator.time_step", i.time_step.is_some(), key, fraction.is_some());
        }
        c.exclusive(
            "integrator.contact_time_fraction",
            i.contact_time_fraction.is_some(),
            "integrator.rayleigh_fraction",
            i.rayleigh_fraction.is_some(),
        );
        let d = &self.damping;
        if !(d.local.is_finite() && (0.0..1.0).contains(&d.local)) {
            c.fail("damping.local", format!("must lie in [0, 1), got {}", exact(d.local)));
        }
        c.non_negative("damping.viscous", d.viscous);
        let r = &self.run;
        c.positive("run.duration", r.duration);
        c.positive("run.sample_interval", r.sample_interval);
        if let Some(i) = r.frame_interval {
            c.positive("run.frame_interval", i);
        }
        if let Some(t) = r.frame_times.iter().find(|t| !(t.is_finite() && **t >= 0.0)) {
            c.fail("run.frame_times", format!("frame times must be >= 0, found {}", exact(*t)));
        }
        let dt = i.fixed_time_step().unwrap_or(f64::INFINITY);
        let steps = r.duration / dt;
        // (A step or duration refused above is not counted again.)
        if dt > 0.0 && r.duration.is_finite() && steps > 1e12 {
            c.fail("run.duration", format!("needs {steps:.3e} steps of integrator.time_step; at most 1e12"));
        }
        let s = &self.settle;
        c.positive("settle.ubf_threshold", s.ubf_threshold);
        c.non_negative("settle.hold_time", s.hold_time);
        if let Some(k) = s.kinetic_energy_threshold {
            c.positive("settle.kinetic_energy_threshold", k);
        }
        let l = &self.limits;
        c.positive("limits.max_overlap_ratio", l.max_overlap_ratio);
        c.positive("limits.overlap_warning_ratio", l.overlap_warning_ratio);
        c.positive("limits.energy_growth_ratio", l.energy_growth_ratio);
        c.positive("limits.energy_balance_tolerance", l.energy_balance_tolerance);
        c.positive("limits.contact_time_fraction", l.contact_time_fraction);
        c.positive("limits.damping_rate_fraction", l.damping_rate_fraction);
    }

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

impl SceneConfig {
    /// The key whose value a validity warning of `kind` is about, dotted as in `[scene]`, and its
    /// value: the time step in the form it is given for the rules of the step and the energy
    /// balance, the Young's modulus for overlaps. For stage `stage` (an index of `stages`), the
    /// stage's key (`stages.NAME.KEY`) where the stage sets it.
    pub fn key_at_fault(&self, kind: WarningKind, stage: Option<usize>) -> (String, f64) {
        let stage = stage.map(|k| &self.stages[k]);
        let i = stage.map_or(self.integrator.clone(), |s| self.in_stage(s).integrator);
        let (key, value) = match (kind, i.contact_time_fraction, i.rayleigh_fraction) {
            (WarningKind::ImpactOverlap | WarningKind::StaticOverlap | WarningKind::Overlap, _, _) => {
                ("material.youngs_modulus", self.material.youngs_modulus)
            }
            (_, Some(fraction), _) => ("integrator.contact_time_fraction", fraction),
            (_, None, Some(fraction)) => ("integrator.rayleigh_fraction", fraction),
            _ => ("integrator.time_step", i.time_step.unwrap_or(DEFAULT_TIME_STEP)),
        };
        match stage {
            Some(s) if s.keys().contains(&key) => (format!("stages.{}.{key}", s.name), value),
            _ => (key.to_string(), value),
        }
    }

    /// The scene as `stage` runs it: this scene with the stage's keys in place (and no stages).
    pub fn in_stage(&self, stage: &StageConfig) -> SceneConfig {
        let mut s = SceneConfig { stages: Vec::new(), ..self.clone() };
        stage.merge_into(&mut s);
        s
    }
}

/// Every problem of `scene`'s stages, each naming its key as a study file writes it
/// (`stages.NAME.damping.local`; `stages[K]` for a stage without a usable name).
fn stage_issues(scene: &SceneConfig) -> Vec<ConfigIssue> {
    let mut issues = Vec::new();
    let mut names = HashSet::new();
    for (k, stage) in scene.stages.iter().enumerate() {
        let bare =
            !stage.name.is_empty() && stage.name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
        let label = if bare { format!("stages.{}", stage.name) } else { format!("stages[{k}]") };
        let mut fail = |key: &str, reason: String| {
            let key = if key.is_empty() { label.clone() } else { format!("{label}.{key}") };
            issues.push(ConfigIssue { key, reason });
        };
        if !bare {
            fail("name", format!("a stage needs a name of letters, digits, _ or - (got {:?})", stage.name));
        } else if !names.insert(stage.name.as_str()) {
            fail("name", format!("two stages are named {:?}", stage.name));
        }
        for (key, reason) in stage.until.problems() {
            fail(&if key.is_empty() { "until".to_string() } else { format!("until.{key}") }, reason);
        }
        let set = stage.keys();
        for issue in scene.in_stage(stage).validate().err().unwrap_or_default() {
            // Too many steps of the stage's own time step: that step is the key at fault.
            let step = "integrator.time_step";
            let key = if issue.key == "run.duration" && set.contains(&step) { step } else { issue.key.as_str() };
            if set.contains(&key) {
                fail(key, issue.reason);
            }
        }
    }
    issues
}

impl SceneConfig {
    /// The stage whose end makes the stages that can end only by time (`until.time` alone) take the
    /// whole `run.duration`, as (its `until.time` key, why): the physics after them never starts, so
    /// no run of the scene can settle. None when the physics starts (or may start) within the run.
    pub fn stages_past_the_run(&self) -> Option<(String, String)> {
        let mut least = 0.0;
        for stage in &self.stages {
            let u = &stage.until;
            let only_time =
                u.unbalanced_force_ratio.is_none() && u.kinetic_energy_per_disk.is_none() && !u.all_in_contact;
            least += u.time.filter(|_| only_time).unwrap_or(0.0);
            if least >= self.run.duration {
                let reason = format!(
                    "the stages up to {:?} last {} s, run.duration = {} s: the physics after the stages never \
                     starts, so no run can settle (shorten the stages or lengthen run.duration)",
                    stage.name,
                    exact(least),
                    exact(self.run.duration)
                );
                return Some((format!("stages.{}.until.time", stage.name), reason));
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The issues of a scene given as TOML, each as text with `wall_material.` read as `material.`.
    fn issues(text: &str) -> Vec<String> {
        let scene: SceneConfig = toml::from_str(text).expect("a scene");
        let issues = scene.validate().err().unwrap_or_default();
        issues.iter().map(|i| i.to_string().replace("wall_material.", "material.")).collect()
    }

    #[test]
    fn the_particle_and_the_wall_material_refuse_the_same_values_alike() {
        let cases = [
            "youngs_modulus = -1",
            "poisson_ratio = 0.7",
            "shear_modulus = -5",
            "shear_modulus = 1e3\npoisson_ratio = 0.2",
            "beta = -1",
            "restitution = 2",
            "beta = 0.1\nrestitution = 0",
            "friction = nan",
            "rolling_friction = -1",
        ];
        for case in cases {
            let particle = issues(&format!("[material]\n{case}\n"));
            assert!(!particle.is_empty(), "{case}");
            assert_eq!(issues(&format!("[wall_material]\n{case}\n")), particle, "{case}");
        }
        assert_eq!(
            issues("[material]\nbeta = 0.1\nrestitution = 0\n"),
            [
                "material.restitution: give either material.beta or material.restitution, not both",
                "material.restitution: restitution must lie in (0, 1], got 0"
            ]
        );
    }
}
