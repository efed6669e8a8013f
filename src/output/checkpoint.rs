//! Checkpoint files: a run's state mid-run ([`RunState`]) beside the results, in
//! `OUT/<name>.checkpoints/<run id>.checkpoint`, written whole or not at all (a temporary file,
//! synced, renamed over the last one), read back only by the same run of the same physics.
//!
//! Layout, little-endian: the magic `DEMSWCKP`, the format version and [`PHYSICS_VERSION`] (`u32`
//! each), the run's identity (length `u64`, UTF-8), the step (`u64`), the time (`f64` bits), the
//! state's bytes (length `u64`, bytes), then a CRC-32 of everything before it.

use std::fmt;
use std::path::{Path, PathBuf};

use super::guard::{self, Existing, GuardError};
use crate::physics::PHYSICS_VERSION;
use crate::physics::run_state::RunState;

/// The version of this file layout; bumped when it changes.
pub const FORMAT_VERSION: u32 = 1;

const MAGIC: &[u8; 8] = b"DEMSWCKP";

/// The folder of the checkpoints of the runs of results file `results` (`OUT/<name>.checkpoints`).
pub fn checkpoint_dir(results: &Path) -> PathBuf {
    let stem = results.file_stem().map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    results.with_file_name(format!("{stem}.checkpoints"))
}

/// The checkpoint of run `run_id` beside results file `results`.
pub fn checkpoint_path(results: &Path, run_id: &str) -> PathBuf {
    checkpoint_dir(results).join(format!("{run_id}.checkpoint"))
}

/// Why a checkpoint cannot be used.
#[derive(Clone, Debug, PartialEq)]
pub enum CheckpointError {
    /// It cannot be read or written (the system's reason, or the guard's refusal).
    Io(String),
    /// It is no checkpoint (another kind of file, or cut short).
    NotACheckpoint,
    /// It was written with another layout.
    Format {
        /// Its format version.
        found: u32,
    },
    /// It was written by another version of the physics.
    Physics {
        /// Its physics version.
        found: u32,
    },
    /// It holds another run (of another study, or another run of this one).
    OtherRun {
        /// The identity of its run.
        found: String,
    },
    /// Its checksum does not match its bytes.
    Damaged,
}

/// A checkpoint file and what is wrong with it.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckpointFileError {
    /// The file.
    pub path: PathBuf,
    /// What is wrong.
    pub error: CheckpointError,
}

impl fmt::Display for CheckpointFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: ", self.path.display())?;
        match &self.error {
            CheckpointError::Io(reason) => write!(f, "{reason}"),
            CheckpointError::NotACheckpoint => write!(f, "not a demsweep checkpoint (or cut short)"),
            CheckpointError::Format { found } => {
                write!(f, "checkpoint format {found}, this demsweep reads format {FORMAT_VERSION}")
            }
            CheckpointError::Physics { found } => {
                write!(f, "checkpoint of physics version {found}, this demsweep runs version {PHYSICS_VERSION}")
            }
            CheckpointError::OtherRun { found } => write!(f, "checkpoint of another run ({found})"),
            CheckpointError::Damaged => write!(f, "checkpoint damaged (its checksum does not match)"),
        }
    }
}

impl std::error::Error for CheckpointFileError {}

/// The bytes of a checkpoint of the run `identity` in `state`.
fn encode(identity: &str, state: &RunState) -> Vec<u8> {
    let mut out = Vec::with_capacity(state.bytes.len() + identity.len() + 64);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&PHYSICS_VERSION.to_le_bytes());
    out.extend_from_slice(&(identity.len() as u64).to_le_bytes());
    out.extend_from_slice(identity.as_bytes());
    out.extend_from_slice(&state.step.to_le_bytes());
    out.extend_from_slice(&state.time.to_bits().to_le_bytes());
    out.extend_from_slice(&(state.bytes.len() as u64).to_le_bytes());
    out.extend_from_slice(&state.bytes);
    let crc = crc32fast::hash(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// The state of run `identity` in checkpoint bytes `bytes`.
fn decode(bytes: &[u8], identity: &str) -> Result<RunState, CheckpointError> {
    let mut at: usize = 0;
    let mut take = |n: usize| {
        let part = bytes.get(at..at.checked_add(n)?)?;
        at += n;
        Some(part)
    };
    let u32_at = |b: &[u8]| u32::from_le_bytes(b.try_into().expect("four bytes"));
    let u64_at = |b: &[u8]| u64::from_le_bytes(b.try_into().expect("eight bytes"));
    if take(8) != Some(MAGIC.as_slice()) {
        return Err(CheckpointError::NotACheckpoint);
    }
    let cut = CheckpointError::NotACheckpoint;
    let format = u32_at(take(4).ok_or(cut.clone())?);
    if format != FORMAT_VERSION {
        return Err(CheckpointError::Format { found: format });
    }
    let physics = u32_at(take(4).ok_or(cut.clone())?);
    if physics != PHYSICS_VERSION {
        return Err(CheckpointError::Physics { found: physics });
    }
    let (body, crc) = bytes.split_at(bytes.len().checked_sub(4).ok_or(cut.clone())?);
    if crc32fast::hash(body) != u32_at(crc) {
        return Err(CheckpointError::Damaged);
    }
    let length = usize::try_from(u64_at(take(8).ok_or(cut.clone())?)).map_err(|_| cut.clone())?;
    let found = String::from_utf8_lossy(take(length).ok_or(cut.clone())?).into_owned();
    if found != identity {
        return Err(CheckpointError::OtherRun { found });
    }
    let step = u64_at(take(8).ok_or(cut.clone())?);
    let time = f64::from_bits(u64_at(take(8).ok_or(cut.clone())?));
    let length = usize::try_from(u64_at(take(8).ok_or(cut.clone())?)).map_err(|_| cut.clone())?;
    let state = take(length).ok_or(cut.clone())?.to_vec();
    Ok(RunState { step, time, bytes: state })
}

/// Writes the checkpoint of run `identity` to `path`, whole or not at all (its folder is made).
pub fn write(path: &Path, identity: &str, state: &RunState) -> Result<(), CheckpointFileError> {
    let failed = |error| CheckpointFileError { path: path.to_path_buf(), error };
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)
            .map_err(|e| failed(CheckpointError::Io(format!("cannot create its folder: {e}"))))?;
    }
    let bytes = encode(identity, state);
    guard::write_with(path, &[], Existing::Any, |out| out.write_all(&bytes))
        .map_err(|e: GuardError| failed(CheckpointError::Io(e.refusal.to_string())))
}

/// The state in the checkpoint `path` of run `identity`; `Ok(None)` when there is none.
pub fn read(path: &Path, identity: &str) -> Result<Option<RunState>, CheckpointFileError> {
    let failed = |error| CheckpointFileError { path: path.to_path_buf(), error };
    match std::fs::read(path) {
        Ok(bytes) => decode(&bytes, identity).map(Some).map_err(failed),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(failed(CheckpointError::Io(format!("cannot read: {e}")))),
    }
}

/// Removes the checkpoint `path` if it is one (a file demsweep wrote: other files stay), and its
/// folder once empty.
pub fn remove(path: &Path) -> Result<(), CheckpointFileError> {
    let failed = |error| CheckpointFileError { path: path.to_path_buf(), error };
    let ours = std::fs::read(path).is_ok_and(|bytes| bytes.starts_with(MAGIC));
    if ours {
        std::fs::remove_file(path).map_err(|e| failed(CheckpointError::Io(format!("cannot remove: {e}"))))?;
        if let Some(dir) = path.parent() {
            // Fails, as it should, while the folder holds anything.
            let _ = std::fs::remove_dir(dir);
        }
    }
    Ok(())
}
