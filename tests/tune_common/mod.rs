//! The tiny tune file shared by the tune tests (and the Python module's: tests/data/tiny_tune.toml),
//! the noise of the stand-in evaluators, and the search settings and failure dump of the stand-in
//! searches.
#![allow(dead_code)]

use demsweep::tune::model::{SearchConfig, SearchResult};

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

/// The stand-in searches' settings: two levers, pile height kept within 5 %, the default seeds and
/// spend limit, no standard setting and no time-step path (tests override what they exercise).
pub fn stand_in_config() -> SearchConfig {
    SearchConfig {
        dims: 2,
        levels: vec![None, None],
        tolerances: vec![(0.05, true)],
        metrics: vec!["pile_height".to_string()],
        seeds: 3,
        max_seeds: 8,
        reference_seeds: 6,
        verify_seeds: 8,
        budget: 400,
        seed: 5,
        initial: None,
        dissipation: vec![0.0; 2],
        home: vec![None; 2],
        standards: 0,
        path: false,
        time_step: None,
        max_spend: 20.0,
        cut_runs: true,
    }
}

/// Every candidate of a stand-in search in a line (costs are reference depositions times 100), for
/// failure messages.
pub fn dump(result: &SearchResult) -> String {
    let lines = result.candidates.iter().map(|c| {
        let a = result.assess(c);
        let v = result.assess_verification(c).map(|v| format!("{} {:.3}", v.state.name(), v.cost / 100.0));
        format!("{} {:?} s{:?} n{} {:.3} {:?} {:?}", c.id, c.point, c.standard, a.n, a.cost / 100.0, a.state, v)
    });
    lines.collect::<Vec<_>>().join("\n")
}
