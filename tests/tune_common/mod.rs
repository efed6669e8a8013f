//! The tiny tune file shared by the tune tests (and the Python module's: tests/data/tiny_tune.toml),
//! and the noise of the stand-in evaluators.
#![allow(dead_code)]

/// 30 disks falling 15 cm (about 30-60 ms of computing per run): two levers, one kept metric; the
/// tune is named `tiny_tune`.
pub const TUNE: &str = include_str!("../data/tiny_tune.toml");

/// A 64-bit mix of `x` (splitmix64's finaliser): the stand-in evaluators' noise, the same on every run.
pub fn hash(mut x: u64) -> u64 {
    x ^= x >> 33;
    x = x.wrapping_mul(0xff51_afd7_ed55_8ccd);
    x ^= x >> 33;
    x = x.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    x ^ (x >> 33)
}

/// A standard normal number drawn from `key` (Box-Muller on two hashes of it).
pub fn normal(key: u64) -> f64 {
    let u1 = ((hash(key) >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
    let u2 = ((hash(key ^ 0x5555) >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}
