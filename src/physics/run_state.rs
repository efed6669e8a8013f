//! A run's state mid-run, as bytes: what a checkpoint holds (after LAMMPS's `write_restart` and
//! Yade's `O.save`), so that a run continued from it ends with the bits of the run never stopped.
//!
//! Every piece of state saves and loads itself through [`Persist`]; the pieces of a run are listed
//! once, in `Simulation::pieces` (`simulation/resume.rs`), which both saving and loading go
//! through. A struct's fields are listed once too, by `persist_fields!`. Numbers are stored
//! little-endian, floats by their bits (NaN and infinities included), lengths before vectors.

use std::fmt;

/// One piece of run state that can be written to bytes and read back in place.
pub trait Persist {
    /// Appends the value's bytes to `out`.
    fn save(&self, out: &mut Vec<u8>);
    /// Reads the value from `input` into `self` (whose buffers are reused).
    fn load(&mut self, input: &mut Input<'_>) -> Result<(), StateError>;
}

/// Bytes being read back, and where.
pub struct Input<'a> {
    bytes: &'a [u8],
    at: usize,
    /// The piece being read, for errors.
    piece: &'static str,
}

impl<'a> Input<'a> {
    /// The bytes of a run state, read from their start.
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, at: 0, piece: "" }
    }

    /// The next `n` bytes.
    fn take(&mut self, n: usize) -> Result<&'a [u8], StateError> {
        let end = self.at.checked_add(n).filter(|end| *end <= self.bytes.len());
        let end = end.ok_or(StateError { piece: self.piece, reason: StateReason::Truncated })?;
        let taken = &self.bytes[self.at..end];
        self.at = end;
        Ok(taken)
    }

    fn u64(&mut self) -> Result<u64, StateError> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().expect("eight bytes")))
    }

    /// A length written by [`Persist`] for `usize`, checked against the bytes left (`each`: bytes
    /// per element at least), so that damaged bytes cannot ask for a huge allocation.
    fn length(&mut self, each: usize) -> Result<usize, StateError> {
        let n = self.u64()?;
        let left = (self.bytes.len() - self.at) as u64;
        match n.checked_mul(each.max(1) as u64) {
            Some(bytes) if bytes <= left => Ok(n as usize),
            _ => Err(self.error(StateReason::Truncated)),
        }
    }

    /// An error in the piece being read.
    pub fn error(&self, reason: StateReason) -> StateError {
        StateError { piece: self.piece, reason }
    }

    /// Whether every byte was read.
    pub fn finished(&self) -> bool {
        self.at == self.bytes.len()
    }
}

/// What goes through the pieces of a run state: the bytes being written (each piece saved) or
/// read (each piece loaded).
pub trait Visit {
    /// Saves or loads the piece `name`.
    fn piece(&mut self, name: &'static str, value: &mut dyn Persist) -> Result<(), StateError>;
}

impl Visit for Vec<u8> {
    fn piece(&mut self, _: &'static str, value: &mut dyn Persist) -> Result<(), StateError> {
        value.save(self);
        Ok(())
    }
}

impl Visit for Input<'_> {
    fn piece(&mut self, name: &'static str, value: &mut dyn Persist) -> Result<(), StateError> {
        self.piece = name;
        value.load(self)
    }
}

/// Why a run state cannot be read back.
#[derive(Clone, Debug, PartialEq)]
pub struct StateError {
    /// The piece being read (`particles`, `neighbors`, …).
    pub piece: &'static str,
    /// What is wrong with it.
    pub reason: StateReason,
}

/// What is wrong with a piece of run state.
#[derive(Clone, Debug, PartialEq)]
pub enum StateReason {
    /// The bytes end before the piece does.
    Truncated,
    /// Bytes are left after the last piece.
    TrailingBytes,
    /// A value no state has (an unknown variant tag, a vector of another length than the run's).
    Invalid {
        /// What was found.
        found: u64,
        /// What was expected.
        expected: u64,
    },
}

impl fmt::Display for StateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.reason {
            StateReason::Truncated => write!(f, "run state cut short in {}", self.piece),
            StateReason::TrailingBytes => write!(f, "run state has bytes after its last piece ({})", self.piece),
            StateReason::Invalid { found, expected } => {
                write!(f, "run state piece {}: found {found} where this run has {expected}", self.piece)
            }
        }
    }
}

impl std::error::Error for StateError {}

impl Persist for u64 {
    fn save(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
    fn load(&mut self, input: &mut Input<'_>) -> Result<(), StateError> {
        *self = input.u64()?;
        Ok(())
    }
}

impl Persist for f64 {
    fn save(&self, out: &mut Vec<u8>) {
        self.to_bits().save(out);
    }
    fn load(&mut self, input: &mut Input<'_>) -> Result<(), StateError> {
        *self = f64::from_bits(input.u64()?);
        Ok(())
    }
}

/// Narrow integers and flags, stored as `u64` and checked on the way back.
macro_rules! persist_as_u64 {
    ($($t:ty),*) => {$(
        impl Persist for $t {
            fn save(&self, out: &mut Vec<u8>) {
                (*self as u64).save(out);
            }
            fn load(&mut self, input: &mut Input<'_>) -> Result<(), StateError> {
                let n = input.u64()?;
                *self = <$t>::try_from(n).map_err(|_| input.error(StateReason::Invalid { found: n, expected: <$t>::MAX as u64 }))?;
                Ok(())
            }
        }
    )*};
}
persist_as_u64!(u32, usize, u8);

impl Persist for i64 {
    fn save(&self, out: &mut Vec<u8>) {
        (*self as u64).save(out);
    }
    fn load(&mut self, input: &mut Input<'_>) -> Result<(), StateError> {
        *self = input.u64()? as i64;
        Ok(())
    }
}

impl Persist for bool {
    fn save(&self, out: &mut Vec<u8>) {
        u64::from(*self).save(out);
    }
    fn load(&mut self, input: &mut Input<'_>) -> Result<(), StateError> {
        *self = match input.u64()? {
            0 => false,
            1 => true,
            found => return Err(input.error(StateReason::Invalid { found, expected: 1 })),
        };
        Ok(())
    }
}

impl<T: Persist + Default> Persist for Vec<T> {
    fn save(&self, out: &mut Vec<u8>) {
        self.len().save(out);
        for value in self {
            value.save(out);
        }
    }
    fn load(&mut self, input: &mut Input<'_>) -> Result<(), StateError> {
        let n = input.length(8)?;
        self.resize_with(n, T::default);
        self.iter_mut().try_for_each(|value| value.load(input))
    }
}

impl<T: Persist + Default> Persist for Option<T> {
    fn save(&self, out: &mut Vec<u8>) {
        self.is_some().save(out);
        if let Some(value) = self {
            value.save(out);
        }
    }
    fn load(&mut self, input: &mut Input<'_>) -> Result<(), StateError> {
        let mut some = false;
        some.load(input)?;
        *self = if some { Some(T::default()) } else { None };
        self.as_mut().map_or(Ok(()), |value| value.load(input))
    }
}

impl<T: Persist, const N: usize> Persist for [T; N] {
    fn save(&self, out: &mut Vec<u8>) {
        self.iter().for_each(|value| value.save(out));
    }
    fn load(&mut self, input: &mut Input<'_>) -> Result<(), StateError> {
        self.iter_mut().try_for_each(|value| value.load(input))
    }
}

impl<A: Persist, B: Persist> Persist for (A, B) {
    fn save(&self, out: &mut Vec<u8>) {
        self.0.save(out);
        self.1.save(out);
    }
    fn load(&mut self, input: &mut Input<'_>) -> Result<(), StateError> {
        self.0.load(input)?;
        self.1.load(input)
    }
}

/// Implements [`Persist`] for a struct by its listed fields, in order (invoked where the fields are
/// visible): `persist_fields!(Type { a, b, c });` A field left out is not saved: list every field
/// that a later step reads.
macro_rules! persist_fields {
    ($t:ty { $($field:ident),* $(,)? }) => {
        impl $crate::physics::run_state::Persist for $t {
            fn save(&self, out: &mut Vec<u8>) {
                $( $crate::physics::run_state::Persist::save(&self.$field, out); )*
            }
            fn load(
                &mut self,
                input: &mut $crate::physics::run_state::Input<'_>,
            ) -> Result<(), $crate::physics::run_state::StateError> {
                $( $crate::physics::run_state::Persist::load(&mut self.$field, input)?; )*
                Ok(())
            }
        }
    };
}
pub(crate) use persist_fields;

/// A run's state at one step, as bytes (see [`crate::physics::Simulation::run_resumable`]).
#[derive(Clone, Debug, PartialEq)]
pub struct RunState {
    /// Steps taken.
    pub step: u64,
    /// Simulated time (s).
    pub time: f64,
    /// Every piece, in the order of `Simulation::pieces`.
    pub bytes: Vec<u8>,
}

/// Where a run's state goes while it runs: asked at every sample whether a state is due, and
/// given one then and when the run is stopped before its end.
pub trait Checkpoints {
    /// Whether a state should be saved now, at sample `step` (a run asks only between samples).
    fn due(&mut self, step: u64) -> bool;
    /// Keeps `state` (the latest replaces any before).
    fn save(&mut self, state: RunState);
}

/// No checkpoints: nothing is ever due.
pub struct NoCheckpoints;

impl Checkpoints for NoCheckpoints {
    fn due(&mut self, _: u64) -> bool {
        false
    }
    fn save(&mut self, _: RunState) {}
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Default, PartialEq)]
    struct Piece {
        a: f64,
        b: Vec<u32>,
        c: Option<(bool, i64)>,
    }
    persist_fields!(Piece { a, b, c });

    #[test]
    fn values_come_back_bit_for_bit_and_damage_is_named() {
        let piece = Piece { a: f64::NAN, b: vec![1, u32::MAX], c: Some((true, -3)) };
        let mut bytes = Vec::new();
        piece.save(&mut bytes);
        let mut back = Piece::default();
        let mut input = Input::new(&bytes);
        input.piece("piece", &mut back).unwrap();
        assert!(input.finished());
        assert_eq!((back.a.to_bits(), &back.b, back.c), (f64::NAN.to_bits(), &piece.b, piece.c));
        let cut = &bytes[..bytes.len() - 3];
        let error = Input::new(cut).piece("piece", &mut back).unwrap_err();
        assert_eq!(error, StateError { piece: "piece", reason: StateReason::Truncated });
        let mut flag = false;
        let error = Input::new(&7u64.to_le_bytes()).piece("flag", &mut flag).unwrap_err();
        assert_eq!(error.to_string(), "run state piece flag: found 7 where this run has 1");
    }
}
