//! A run's identity is its content: the resolved value of every setting that affects its physics
//! (its seed included), the content of its input files (placement and contact history) and the
//! version of the physics. Runs of any study with the same identity give the same results, so a
//! results file reuses a stored run whatever study plans it again (`run --resume` of an edited
//! study, `merge` of different studies).
//!
//! Written `<settings>-<inputs>-p<physics>`: two 64-bit FNV-1a digests in hex and the physics
//! version, so that two identities of one run say which part changed.

use std::collections::HashMap;
use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

use super::PlannedRun;
use crate::physics::PHYSICS_VERSION;
use crate::physics::contact_record::Partner;
use crate::physics::time_step::with_time_step;

/// What a run's results depend on (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct RunIdentity {
    /// Digest of the resolved scene (time step resolved; output-only settings and file paths left out).
    pub settings: u64,
    /// Digest of the disks and contact history read from input files (of nothing when there are none).
    pub inputs: u64,
    /// The physics version that made (or will make) the run.
    pub physics: u32,
}

impl RunIdentity {
    /// The identity of a planned run (its input files' digest computed here: see [`Self::all`]
    /// for many runs that share files).
    pub fn of(run: &PlannedRun) -> Self {
        Self::with_inputs(run, inputs_digest(run))
    }

    fn with_inputs(run: &PlannedRun, inputs: u64) -> Self {
        let mut scene = with_time_step(&run.scene, run.time_step);
        (scene.placement.file, scene.placement.contacts) = (None, None);
        (scene.run.frame_times, scene.run.frame_interval) = (Vec::new(), None);
        let settings = fnv(serde_json::to_string(&scene).unwrap_or_default().bytes());
        Self { settings, inputs, physics: PHYSICS_VERSION }
    }

    /// What differs between this identity and `other`; empty when they are equal.
    pub fn changes(&self, other: &Self) -> Vec<IdentityChange> {
        let mut changed = Vec::new();
        if self.settings != other.settings {
            changed.push(IdentityChange::Settings);
        }
        if self.inputs != other.inputs {
            changed.push(IdentityChange::InputFiles);
        }
        if self.physics != other.physics {
            changed.push(IdentityChange::Physics { from: self.physics, to: other.physics });
        }
        changed
    }
}

/// One part of a run's identity that differs between two identities (see [`RunIdentity::changes`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum IdentityChange {
    /// The resolved settings.
    Settings,
    /// The content of the input files (placement and contact history).
    InputFiles,
    /// The physics version.
    Physics {
        /// The version before.
        from: u32,
        /// The version now.
        to: u32,
    },
}

impl fmt::Display for IdentityChange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IdentityChange::Settings => write!(f, "settings"),
            IdentityChange::InputFiles => write!(f, "input files (placement.file, placement.contacts)"),
            IdentityChange::Physics { from, to } => write!(f, "physics version {from} → {to}"),
        }
    }
}

impl fmt::Display for RunIdentity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:016x}-{:016x}-p{}", self.settings, self.inputs, self.physics)
    }
}

/// Text that is not a run identity (the text).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NotAnIdentity(pub String);

impl fmt::Display for NotAnIdentity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "`{}` is not a run identity (<16 hex digits>-<16 hex digits>-p<version>)", self.0)
    }
}

impl std::error::Error for NotAnIdentity {}

impl FromStr for RunIdentity {
    type Err = NotAnIdentity;

    fn from_str(s: &str) -> Result<Self, NotAnIdentity> {
        let bad = || NotAnIdentity(s.to_string());
        let mut parts = s.split('-');
        let (Some(settings), Some(inputs), Some(physics), None) =
            (parts.next(), parts.next(), parts.next(), parts.next())
        else {
            return Err(bad());
        };
        let hex = |t: &str| if t.len() == 16 { u64::from_str_radix(t, 16).map_err(|_| bad()) } else { Err(bad()) };
        let physics = physics.strip_prefix('p').and_then(|v| v.parse().ok()).ok_or_else(bad)?;
        Ok(Self { settings: hex(settings)?, inputs: hex(inputs)?, physics })
    }
}

impl RunIdentity {
    /// The identities of `runs`, each input file's content digested once however many runs share it.
    pub fn all(runs: &[PlannedRun]) -> Vec<RunIdentity> {
        let mut digests: HashMap<(usize, usize), u64> = HashMap::new();
        runs.iter()
            .map(|run| {
                let key = (
                    run.initial.as_ref().map_or(0, |d| Arc::as_ptr(d) as usize),
                    run.initial_contacts.as_ref().map_or(0, |c| Arc::as_ptr(c) as usize),
                );
                let inputs = *digests.entry(key).or_insert_with(|| inputs_digest(run));
                RunIdentity::with_inputs(run, inputs)
            })
            .collect()
    }
}

/// Digest of what a run reads from input files: the placement file's disks (not those a generated
/// placement gives: the settings say them) and the contact history.
fn inputs_digest(run: &PlannedRun) -> u64 {
    let from_file = run.scene.placement.file.is_some();
    let disks = run.initial.iter().filter(|_| from_file).flat_map(|d| d.iter());
    let disks = disks.flat_map(|d| [d.x, d.y, d.r, d.vx, d.vy, d.omega, d.angle]);
    let contacts = run.initial_contacts.iter().flat_map(|c| c.iter()).flat_map(|c| {
        let partner = match c.partner {
            Partner::Disk(j) => j as f64,
            Partner::Wall(k) => -1.0 - k as f64,
        };
        [c.disk as f64, partner, c.tangential_spring, c.law_state]
    });
    let values = [f64::from(u8::from(from_file))].into_iter().chain(disks).chain([f64::NAN]).chain(contacts);
    fnv(values.flat_map(|x| x.to_bits().to_le_bytes()))
}

/// FNV-1a 64 of `bytes`.
pub(crate) fn fnv(bytes: impl IntoIterator<Item = u8>) -> u64 {
    bytes.into_iter().fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_identity_reads_back_and_names_what_changed() {
        let a = RunIdentity { settings: 0x0123_4567_89ab_cdef, inputs: 7, physics: 1 };
        assert_eq!(a.to_string(), "0123456789abcdef-0000000000000007-p1");
        assert_eq!(a.to_string().parse::<RunIdentity>(), Ok(a));
        for bad in ["", "0123-0000000000000007-p1", "0123456789abcdef-0000000000000007-1", "a-b-c-d"] {
            assert!(bad.parse::<RunIdentity>().is_err(), "{bad}");
        }
        let b = RunIdentity { inputs: 8, physics: 2, ..a };
        assert_eq!(a.changes(&b), [IdentityChange::InputFiles, IdentityChange::Physics { from: 1, to: 2 }]);
        let words: Vec<String> = a.changes(&b).iter().map(ToString::to_string).collect();
        assert_eq!(words, ["input files (placement.file, placement.contacts)", "physics version 1 → 2"]);
        assert!(a.changes(&a).is_empty());
    }
}
