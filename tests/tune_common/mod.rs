//! The tiny tune file shared by the tune tests (and the Python module's: tests/data/tiny_tune.toml).

/// 30 disks falling 15 cm (about 30-60 ms of computing per run): two levers, one kept metric; the
/// tune is named `tiny_tune`.
pub const TUNE: &str = include_str!("../data/tiny_tune.toml");
