//! What one run produces: status, histories, final state and frames.

use serde::{Deserialize, Serialize};

use super::contact_record::Partner;
use super::particles::{InitialContact, InitialDisk};
use super::pile::PileMetrics;
use super::pour::PourCount;
use super::stability::StabilityReport;
use super::warning::ValidityWarning;

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    /// The settle criterion held (the run stopped there unless asked to run to the end).
    Settled,
    /// The duration elapsed without the settle criterion holding.
    NotSettled,
    /// The run was ended because its state became invalid (see the message).
    Diverged,
    /// The caller asked the run to stop early (e.g. Ctrl-C).
    Interrupted,
    /// The run failed without a record (its scene could not be built, or it panicked): set by the
    /// runner, never by the simulation.
    Error,
}

impl RunStatus {
    /// The statuses a results file holds, in the order of its per-status columns (interrupted runs
    /// are not recorded).
    pub const RECORDED: [RunStatus; 4] =
        [RunStatus::Settled, RunStatus::NotSettled, RunStatus::Diverged, RunStatus::Error];

    /// The snake_case name used in files.
    pub fn as_str(self) -> &'static str {
        match self {
            RunStatus::Settled => "settled",
            RunStatus::NotSettled => "not_settled",
            RunStatus::Diverged => "diverged",
            RunStatus::Interrupted => "interrupted",
            RunStatus::Error => "error",
        }
    }

    /// The status named `text` in a file ([`Self::as_str`]), if any.
    pub fn parse(text: &str) -> Option<RunStatus> {
        [RunStatus::Interrupted].into_iter().chain(RunStatus::RECORDED).find(|s| s.as_str() == text)
    }
}

impl std::fmt::Display for RunStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Sampled diagnostics over time, one entry per sample (see [`super::diagnostics::Sample`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct History {
    /// Simulated time (s).
    pub time: Vec<f64>,
    /// Translational kinetic energy Σ ½ m v² (J).
    pub kinetic_translational: Vec<f64>,
    /// Rotational kinetic energy Σ ½ I ω² (J).
    pub kinetic_rotational: Vec<f64>,
    /// Gravitational potential energy −Σ m g·x (J); zero at the origin.
    pub potential: Vec<f64>,
    /// Elastic energy stored in contacts, normal and tangential springs (J).
    pub elastic: Vec<f64>,
    /// Energy removed by damping and friction since the start, numerical damping included (J).
    pub dissipated: Vec<f64>,
    /// The part of `dissipated` removed by numerical damping (`damping.local`, `damping.viscous`) (J).
    pub numerical_damping_dissipated: Vec<f64>,
    /// The paper's total: kinetic + potential (J).
    pub total: Vec<f64>,
    /// Mechanical total: kinetic + potential + elastic (J).
    pub mechanical: Vec<f64>,
    /// Unbalanced force ratio (gravity included); NaN while there are no contacts.
    pub unbalanced_force_ratio: Vec<f64>,
    /// Number of contacts, disk-disk and disk-wall.
    pub contacts: Vec<u32>,
    /// Largest overlap divided by the smaller radius of its pair.
    pub max_overlap_ratio: Vec<f64>,
}

/// Full state of all disks at one time.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    /// Simulated time (s).
    pub time: f64,
    /// Centre x (m).
    pub x: Vec<f64>,
    /// Centre y (m).
    pub y: Vec<f64>,
    /// Velocity x (m/s).
    pub vx: Vec<f64>,
    /// Velocity y (m/s).
    pub vy: Vec<f64>,
    /// Angular velocity (rad/s), counter-clockwise positive.
    pub omega: Vec<f64>,
    /// Rotation angle (rad), counter-clockwise positive.
    #[serde(default)]
    pub angle: Vec<f64>,
    /// Radius (m).
    pub r: Vec<f64>,
    /// Sum of contact force magnitudes on each disk (N).
    pub contact_force: Vec<f64>,
    /// The contacts with their forces.
    #[serde(default)]
    pub contacts: super::contact_network::ContactNetwork,
}

impl Snapshot {
    /// The disks of this state as a simulation's starting state, in the scene's numbering.
    pub fn initial_disks(&self) -> Vec<InitialDisk> {
        (0..self.x.len())
            .map(|k| InitialDisk {
                x: self.x[k],
                y: self.y[k],
                r: self.r[k],
                vx: self.vx[k],
                vy: self.vy[k],
                omega: self.omega[k],
                angle: self.angle[k],
            })
            .collect()
    }

    /// The contact history of this state as a simulation's starting history (a restart from it).
    pub fn initial_contacts(&self) -> Vec<InitialContact> {
        let c = &self.contacts;
        let partner = |second: i64| match usize::try_from(second) {
            Ok(disk) => Partner::Disk(disk),
            Err(_) => Partner::Wall((-1 - second) as usize),
        };
        (0..c.len())
            .map(|k| InitialContact {
                disk: c.first[k] as usize,
                partner: partner(c.second[k]),
                tangential_spring: c.tangential_spring[k],
                law_state: c.law_state[k],
            })
            .collect()
    }
}

/// One per-disk column of a [`Snapshot`]: the one declaration the state tables of results files
/// (their fields, in this order) and their read-back go by.
pub struct DiskField {
    /// Name in files.
    pub name: &'static str,
    /// SI unit symbol.
    pub unit: &'static str,
    /// The column of a snapshot.
    pub values: fn(&Snapshot) -> &Vec<f64>,
    /// The same, to fill it.
    pub values_mut: fn(&mut Snapshot) -> &mut Vec<f64>,
    /// The value of every disk in a file written before the field existed (`None`: required).
    pub when_absent: Option<f64>,
}

/// A [`DiskField`] for the `Snapshot` field `$field`.
macro_rules! disk_field {
    ($field:ident, $unit:literal, $when_absent:expr) => {
        DiskField {
            name: stringify!($field),
            unit: $unit,
            values: |s| &s.$field,
            values_mut: |s| &mut s.$field,
            when_absent: $when_absent,
        }
    };
}

/// The per-disk columns of a snapshot, in file order.
pub const DISK_FIELDS: [DiskField; 8] = [
    disk_field!(x, "m", None),
    disk_field!(y, "m", None),
    disk_field!(vx, "m/s", None),
    disk_field!(vy, "m/s", None),
    disk_field!(omega, "rad/s", None),
    disk_field!(angle, "rad", Some(0.0)),
    disk_field!(r, "m", None),
    disk_field!(contact_force, "N", None),
];

/// Everything one run produces.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// How it ended.
    pub status: RunStatus,
    /// Why it diverged or was interrupted; `None` otherwise.
    pub message: Option<String>,
    /// Validity warnings from the pre-run estimate and from the run itself.
    pub warnings: Vec<ValidityWarning>,
    /// Start of the stretch over which the settle criterion held (s).
    pub settle_time: Option<f64>,
    /// Time steps taken.
    pub steps: u64,
    /// The time step used (s): given, or resolved from the scene's time scales.
    pub time_step: f64,
    /// Simulated time reached (s).
    pub simulated_time: f64,
    /// Largest energy-balance error over the sampled steps, as a share of the energy available.
    pub energy_balance_error: f64,
    /// Largest overlap over the sampled steps, over the smaller radius of its pair.
    pub largest_overlap_ratio: f64,
    /// Structure of the pile at the end of the run.
    pub pile: PileMetrics,
    /// Pre-run stability estimate.
    pub stability: StabilityReport,
    /// Sampled diagnostics.
    pub history: History,
    /// State at the end of the run.
    pub final_state: Snapshot,
    /// States recorded at the requested frame times.
    pub frames: Vec<Snapshot>,
    /// When each stage before the physical one ended, in order (none for a scene without stages).
    #[serde(default)]
    pub stage_ends: Vec<StageEndTime>,
    /// What a pour inserted and refused (`None` for other placements).
    #[serde(default)]
    pub pour: Option<PourCount>,
}

/// When one stage of a deposition protocol ended.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StageEndTime {
    /// The stage's name.
    pub name: String,
    /// Simulated time at its end (s); `None` when the run ended before the stage did.
    pub time: Option<f64>,
}

impl RunRecord {
    /// Time steps times disks present, summed over the steps: the run's cost.
    pub fn particle_steps(&self) -> u64 {
        self.pour.map_or(self.steps * self.final_state.x.len() as u64, |pour| pour.particle_steps)
    }

    /// Last sampled value of a history series, NaN when there is none.
    pub fn last(series: &[f64]) -> f64 {
        series.last().copied().unwrap_or(f64::NAN)
    }
}

super::run_state::persist_fields!(History {
    time,
    kinetic_translational,
    kinetic_rotational,
    potential,
    elastic,
    dissipated,
    numerical_damping_dissipated,
    total,
    mechanical,
    unbalanced_force_ratio,
    contacts,
    max_overlap_ratio,
});
super::run_state::persist_fields!(Snapshot { time, x, y, vx, vy, omega, angle, r, contact_force, contacts });
