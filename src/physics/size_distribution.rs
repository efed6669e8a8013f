//! Size distributions of the disks' radii (`particles.size_distribution`), as DEM codes give them
//! (LIGGGHTS' `particledistribution/discrete`, EDEM's size distributions): a discrete mixture of
//! radii by number, area or mass fraction, or a continuous distribution (uniform, normal,
//! lognormal) truncated to `[min, max]`.
//!
//! A discrete mixture's counts are fixed by its fractions (largest remainders, so they sum to
//! `particles.count`) and only the disks' order is drawn; a continuous one's radii are drawn.
//! Both draw from the placement seed's stream, so the same seed gives the same disks.

use serde::{Deserialize, Serialize};

use super::number::exact;
use super::rng::Rng;

/// The shape of a size distribution.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DistributionKind {
    /// The radii `radii` in the proportions `fractions`.
    Discrete,
    /// Radii uniform in `[min, max]`.
    Uniform,
    /// Normal radii of mean `mean` and standard deviation `std`, truncated to `[min, max]`.
    Normal,
    /// Lognormal radii of mean `mean` and standard deviation `std` (of the radius), truncated to
    /// `[min, max]`.
    Lognormal,
}

impl DistributionKind {
    /// The name in scene files.
    pub fn name(self) -> &'static str {
        match self {
            DistributionKind::Discrete => "discrete",
            DistributionKind::Uniform => "uniform",
            DistributionKind::Normal => "normal",
            DistributionKind::Lognormal => "lognormal",
        }
    }
}

/// What a discrete mixture's fractions are shares of.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FractionBasis {
    /// Shares of the disks' number.
    #[default]
    Number,
    /// Shares of the disks' area (π r² each).
    Area,
    /// Shares of the disks' mass: for disks of one material and thickness, the same as area.
    Mass,
}

/// A size distribution of the disks' radii, drawn with the placement seed; each kind reads its own
/// keys (see [`SizeDistribution::issues`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SizeDistribution {
    /// The distribution: discrete (a mixture of `radii`), uniform, normal or lognormal (required;
    /// optional in the type so that each key of a study is checked on its own).
    pub kind: Option<DistributionKind>,
    /// Discrete: the radius of each class (m).
    pub radii: Option<Vec<f64>>,
    /// Discrete: each class's share, in the order of `radii` (scaled to sum to 1).
    pub fractions: Option<Vec<f64>>,
    /// Discrete: what the fractions are shares of (number by default).
    pub by: Option<FractionBasis>,
    /// Normal, lognormal: the mean radius before truncation (m).
    pub mean: Option<f64>,
    /// Normal, lognormal: the standard deviation of the radius before truncation (m).
    pub std: Option<f64>,
    /// Uniform, normal, lognormal: the smallest radius (m).
    pub min: Option<f64>,
    /// Uniform, normal, lognormal: the largest radius (m).
    pub max: Option<f64>,
}

/// What is wrong with a distribution: the key (under `particles.size_distribution.`) and why.
#[derive(Clone, Debug, PartialEq)]
pub struct DistributionIssue {
    /// The key, e.g. `fractions`.
    pub key: &'static str,
    /// Why.
    pub reason: String,
}

/// The keys each kind reads (the rest must be absent).
fn keys_of(kind: DistributionKind) -> &'static [&'static str] {
    match kind {
        DistributionKind::Discrete => &["radii", "fractions", "by"],
        DistributionKind::Uniform => &["min", "max"],
        DistributionKind::Normal | DistributionKind::Lognormal => &["mean", "std", "min", "max"],
    }
}

/// The share of a truncated distribution's mass below which `[min, max]` is refused (sampling by
/// rejection would take too many tries, and such a distribution is rarely meant).
const MIN_MASS_INSIDE: f64 = 1e-3;

impl SizeDistribution {
    /// The keys given, by name.
    fn given(&self) -> [(&'static str, bool); 7] {
        [
            ("radii", self.radii.is_some()),
            ("fractions", self.fractions.is_some()),
            ("by", self.by.is_some()),
            ("mean", self.mean.is_some()),
            ("std", self.std.is_some()),
            ("min", self.min.is_some()),
            ("max", self.max.is_some()),
        ]
    }

    /// Every problem: keys the kind does not read or lacks, and impossible values.
    pub fn issues(&self) -> Vec<DistributionIssue> {
        let Some(kind) = self.kind else {
            let reason = "a size distribution needs its kind: discrete, uniform, normal or lognormal".to_string();
            return vec![DistributionIssue { key: "kind", reason }];
        };
        let mut issues = self.key_issues(kind);
        if !issues.is_empty() {
            return issues;
        }
        let mut fail = |key: &'static str, reason: String| issues.push(DistributionIssue { key, reason });
        match kind {
            DistributionKind::Discrete => self.discrete_issues(&mut fail),
            _ => self.continuous_issues(kind, &mut fail),
        }
        issues
    }

    /// Keys the kind does not read, and those it needs that are missing.
    fn key_issues(&self, kind: DistributionKind) -> Vec<DistributionIssue> {
        let (kind, wanted) = (kind.name(), keys_of(kind));
        let issue = |(key, given): (&'static str, bool)| match (given, wanted.contains(&key)) {
            (true, false) => Some(format!("is not read by a {kind} distribution (it reads {})", wanted.join(", "))),
            (false, true) if key != "by" => Some(format!("a {kind} distribution needs it")),
            _ => None,
        };
        self.given().into_iter().filter_map(|g| issue(g).map(|reason| DistributionIssue { key: g.0, reason })).collect()
    }

    fn discrete_issues(&self, fail: &mut impl FnMut(&'static str, String)) {
        let (radii, fractions) = (self.radii.as_deref().unwrap_or(&[]), self.fractions.as_deref().unwrap_or(&[]));
        if radii.is_empty() {
            fail("radii", "needs at least one radius".into());
        }
        if let Some(bad) = radii.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
            fail("radii", format!("every radius must be > 0, found {}", exact(*bad)));
        }
        if fractions.len() != radii.len() {
            fail("fractions", format!("has {} entries but radii has {}", fractions.len(), radii.len()));
        }
        if let Some(bad) = fractions.iter().find(|f| !(f.is_finite() && **f >= 0.0)) {
            fail("fractions", format!("every fraction must be >= 0, found {}", exact(*bad)));
        } else if !fractions.is_empty() && fractions.iter().sum::<f64>() <= 0.0 {
            fail("fractions", "must not all be 0".into());
        } else if fractions.len() == radii.len() && radii.iter().all(|r| r.is_finite() && *r > 0.0) {
            let total: f64 = self.number_weights().iter().sum();
            if !(total.is_finite() && total > 0.0) {
                fail(
                    "fractions",
                    "and radii lie too many orders of magnitude apart to give shares of the number".into(),
                );
            }
        }
    }

    fn continuous_issues(&self, kind: DistributionKind, fail: &mut impl FnMut(&'static str, String)) {
        let (min, max) = (self.min.unwrap_or(f64::NAN), self.max.unwrap_or(f64::NAN));
        if !(min.is_finite() && min > 0.0) {
            fail("min", format!("must be a finite number > 0, got {}", exact(min)));
        }
        if !(max.is_finite() && max > min) {
            fail("max", format!("must be finite and > min ({}), got {}", exact(min), exact(max)));
        }
        if kind == DistributionKind::Uniform {
            return;
        }
        for (key, value) in [("mean", self.mean), ("std", self.std)] {
            let value = value.unwrap_or(f64::NAN);
            if !(value.is_finite() && value > 0.0) {
                fail(key, format!("must be a finite number > 0, got {}", exact(value)));
            }
        }
        if let Some(normal) = self.underlying().filter(|_| min > 0.0 && max > min) {
            let (lo, hi) = self.transformed(min, max);
            let inside = normal.cdf(hi) - normal.cdf(lo);
            if inside.is_nan() || inside < MIN_MASS_INSIDE {
                fail(
                    "max",
                    format!("[min, max] holds {} of the distribution: widen it or move the mean", exact(inside)),
                );
            }
        }
    }

    /// The normal distribution the radii (normal) or their logarithms (lognormal) follow before
    /// truncation; `None` for the other kinds or while a parameter is missing.
    fn underlying(&self) -> Option<Normal> {
        let (mean, std) = (self.mean?, self.std?);
        match self.kind.unwrap_or(DistributionKind::Discrete) {
            DistributionKind::Normal => Some(Normal { mean, std }),
            DistributionKind::Lognormal => {
                let variance = (1.0 + (std / mean).powi(2)).ln();
                Some(Normal { mean: mean.ln() - variance / 2.0, std: variance.sqrt() })
            }
            _ => None,
        }
    }

    /// `[min, max]` where the underlying normal lives (logarithms for a lognormal).
    fn transformed(&self, min: f64, max: f64) -> (f64, f64) {
        if self.kind == Some(DistributionKind::Lognormal) { (min.ln(), max.ln()) } else { (min, max) }
    }

    /// A discrete mixture's weights by number (an area or mass share `f` of radius `r` weighs
    /// `f / r²`), scaled by powers of two (exact) so that the largest fraction and the smallest
    /// radius lie in [1, 2): their sum is finite however large the fractions. Empty for the other kinds.
    fn number_weights(&self) -> Vec<f64> {
        let (Some(radii), Some(fractions)) = (&self.radii, &self.fractions) else { return Vec::new() };
        let by_number = self.by.unwrap_or_default() == FractionBasis::Number;
        let f_scale = binade(fractions.iter().copied().fold(0.0, f64::max));
        let r_scale = binade(radii.iter().copied().fold(f64::INFINITY, f64::min));
        let weight = |r: f64, f: f64| if by_number { f / f_scale } else { f / f_scale / (r / r_scale).powi(2) };
        radii.iter().zip(fractions).map(|(r, f)| weight(*r, *f)).collect()
    }

    /// The smallest and largest radius the distribution can give (of a valid distribution).
    pub fn bounds(&self) -> (f64, f64) {
        match self.kind.unwrap_or(DistributionKind::Discrete) {
            DistributionKind::Discrete => {
                let radii = self.radii.as_deref().unwrap_or(&[]);
                (radii.iter().copied().fold(f64::INFINITY, f64::min), radii.iter().copied().fold(0.0, f64::max))
            }
            _ => (self.min.unwrap_or(f64::NAN), self.max.unwrap_or(f64::NAN)),
        }
    }

    /// A discrete mixture's number of disks of each class for `count` disks: the fractions turned
    /// into shares of the number (`Self::number_weights`), rounded by largest remainders so that
    /// they sum to `count`. Empty for the other kinds.
    pub fn class_counts(&self, count: usize) -> Vec<usize> {
        let weights = self.number_weights();
        let total: f64 = weights.iter().sum();
        let exact: Vec<f64> = weights.iter().map(|w| w / total * count as f64).collect();
        let mut counts: Vec<usize> = exact.iter().map(|x| x.floor() as usize).collect();
        let mut order: Vec<usize> = (0..counts.len()).collect();
        order.sort_by(|&a, &b| (exact[b] - exact[b].floor()).total_cmp(&(exact[a] - exact[a].floor())));
        let short = count - counts.iter().sum::<usize>();
        order.iter().take(short).for_each(|&k| counts[k] += 1);
        counts
    }

    /// `count` radii drawn from the distribution with `rng` (the placement seed's stream).
    pub fn sample(&self, count: usize, rng: &mut Rng) -> Vec<f64> {
        match self.kind.unwrap_or(DistributionKind::Discrete) {
            DistributionKind::Discrete => {
                let radii = self.radii.as_deref().unwrap_or(&[]);
                let counts = self.class_counts(count);
                let mut all: Vec<f64> =
                    radii.iter().zip(counts).flat_map(|(r, n)| std::iter::repeat_n(*r, n)).collect();
                rng.shuffle(&mut all);
                all
            }
            DistributionKind::Uniform => {
                let (min, max) = self.bounds();
                (0..count).map(|_| rng.range(min, max)).collect()
            }
            DistributionKind::Normal | DistributionKind::Lognormal => self.sample_truncated(count, rng),
        }
    }

    /// Truncated normal or lognormal radii, by rejection (valid distributions keep at least
    /// [`MIN_MASS_INSIDE`] of their mass inside `[min, max]`).
    fn sample_truncated(&self, count: usize, rng: &mut Rng) -> Vec<f64> {
        let normal = self.underlying().expect("a valid normal or lognormal distribution");
        let (min, max) = self.bounds();
        let (lo, hi) = self.transformed(min, max);
        let back = |x: f64| if self.kind == Some(DistributionKind::Lognormal) { x.exp().clamp(min, max) } else { x };
        (0..count)
            .map(|_| {
                loop {
                    let x = normal.mean + normal.std * standard_normal(rng);
                    if (lo..=hi).contains(&x) {
                        break back(x);
                    }
                }
            })
            .collect()
    }
}

/// What a distribution gives a scene: the disks of each radius class (a discrete mixture's; empty
/// for a continuous distribution) and the drawn radii's smallest, mean and largest.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawnSizes {
    /// The distribution's kind.
    pub kind: DistributionKind,
    /// Radius (m) and number of disks of each class of a discrete mixture.
    pub classes: Vec<(f64, usize)>,
    /// The number of disks.
    pub count: usize,
    /// The smallest radius drawn (m).
    pub min: f64,
    /// The mean radius drawn (m).
    pub mean: f64,
    /// The largest radius drawn (m).
    pub max: f64,
}

impl SizeDistribution {
    /// The sizes `count` disks get from the placement seed `seed` (as placement draws them).
    pub fn drawn(&self, count: usize, seed: u64) -> DrawnSizes {
        let radii = self.sample(count, &mut Rng::new(seed));
        let classes = self.radii.iter().flatten().copied().zip(self.class_counts(count)).collect();
        let min = radii.iter().copied().fold(f64::INFINITY, f64::min);
        let max = radii.iter().copied().fold(0.0, f64::max);
        let mean = radii.iter().sum::<f64>() / count.max(1) as f64;
        DrawnSizes { kind: self.kind.unwrap_or(DistributionKind::Discrete), classes, count, min, mean, max }
    }
}

/// The power of two at or below a positive normal `x` (1 for any other `x`): dividing by it is exact.
fn binade(x: f64) -> f64 {
    let power = f64::from_bits(x.to_bits() & 0x7FF0_0000_0000_0000);
    if power.is_normal() && x.is_finite() { power } else { 1.0 }
}

/// A normal distribution.
#[derive(Clone, Copy, Debug)]
struct Normal {
    mean: f64,
    std: f64,
}

impl Normal {
    /// The probability of a value below `x`.
    fn cdf(&self, x: f64) -> f64 {
        0.5 * erfc(-(x - self.mean) / (self.std * std::f64::consts::SQRT_2))
    }
}

/// The complementary error function, to a relative error below 1.2e-7 (Numerical Recipes' erfcc,
/// a Chebyshev fit), enough to judge how much of a distribution a truncation keeps.
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = [
        -1.265_512_23,
        1.000_023_68,
        0.374_091_96,
        0.096_784_18,
        -0.186_288_06,
        0.278_868_07,
        -1.135_203_98,
        1.488_515_87,
        -0.822_152_23,
        0.170_872_77,
    ];
    let sum = poly.iter().rev().fold(0.0, |acc, c| acc * t + c);
    let value = t * (-z * z + sum).exp();
    if x >= 0.0 { value } else { 2.0 - value }
}

/// A standard normal draw (Box-Muller, one of the pair).
fn standard_normal(rng: &mut Rng) -> f64 {
    let u = 1.0 - rng.unit(); // in (0, 1]
    let v = rng.unit();
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn distribution(text: &str) -> SizeDistribution {
        toml::from_str(text).unwrap()
    }

    fn moments(radii: &[f64]) -> (f64, f64) {
        let n = radii.len() as f64;
        let mean = radii.iter().sum::<f64>() / n;
        (mean, (radii.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt())
    }

    #[test]
    fn a_discrete_mixture_has_the_counts_of_its_fractions_in_a_drawn_order() {
        let mix = distribution("kind = \"discrete\"\nradii = [0.004, 0.006]\nfractions = [1, 3]\n");
        assert_eq!(mix.class_counts(900), [225, 675]);
        let radii = mix.sample(900, &mut Rng::new(7));
        assert_eq!(radii.iter().filter(|r| **r == 0.004).count(), 225);
        assert_ne!(radii, mix.sample(900, &mut Rng::new(8)), "the order comes from the seed");
        assert_eq!(radii, mix.sample(900, &mut Rng::new(7)), "the same seed, the same disks");
        let three = distribution("kind = \"discrete\"\nradii = [1, 2, 3]\nfractions = [1, 1, 1]\n");
        assert_eq!(three.class_counts(10), [4, 3, 3], "largest remainders: the counts sum to the count");
    }

    #[test]
    fn the_counts_sum_to_the_count_however_large_the_fractions() {
        for by in ["number", "area"] {
            for (radii, fractions) in [("[0.002, 0.004]", "[1e308, 1e308]"), ("[0.002, 0.004]", "[5e-324, 1e308]")] {
                let text = format!("kind = \"discrete\"\nradii = {radii}\nfractions = {fractions}\nby = \"{by}\"\n");
                let mix = distribution(&text);
                assert!(mix.issues().is_empty(), "{text}");
                assert_eq!(mix.class_counts(16).iter().sum::<usize>(), 16, "{text}");
                assert_eq!(mix.sample(16, &mut Rng::new(1)).len(), 16, "{text}");
            }
        }
        let huge = distribution("kind = \"discrete\"\nradii = [0.002, 0.004]\nfractions = [1e308, 1e308]\n");
        assert_eq!(huge.class_counts(16), [8, 8], "equal shares");
        let apart =
            distribution("kind = \"discrete\"\nradii = [1e-200, 1]\nfractions = [1e-300, 1e308]\nby = \"area\"\n");
        assert!(apart.issues()[0].reason.contains("orders of magnitude apart"), "{:?}", apart.issues());
    }

    #[test]
    fn area_and_mass_fractions_are_shares_of_r_squared() {
        // Equal areas of radii 1 and 2: four times as many small disks as large ones.
        for by in ["area", "mass"] {
            let mix = distribution(&format!(
                "kind = \"discrete\"\nradii = [1.0, 2.0]\nfractions = [0.5, 0.5]\nby = \"{by}\"\n"
            ));
            let counts = mix.class_counts(500);
            assert_eq!(counts, [400, 100], "{by}");
            let radii = mix.sample(500, &mut Rng::new(1));
            let area = |r: f64| radii.iter().filter(|x| **x == r).map(|x| x * x).sum::<f64>();
            assert_eq!(area(1.0), area(2.0), "{by}: equal shares of area");
        }
    }

    #[test]
    fn continuous_draws_have_the_distributions_moments_within_their_bounds() {
        let n = 40_000;
        let uniform = distribution("kind = \"uniform\"\nmin = 0.002\nmax = 0.006\n");
        let (mean, std) = moments(&uniform.sample(n, &mut Rng::new(3)));
        assert!((mean - 0.004).abs() < 4.0 * 0.004 / 12f64.sqrt() / (n as f64).sqrt(), "{mean}");
        assert!((std / (0.004 / 12f64.sqrt()) - 1.0).abs() < 0.02, "{std}");
        // Wide bounds (±5 standard deviations): the moments are the untruncated ones.
        for kind in ["normal", "lognormal"] {
            let text = format!("kind = \"{kind}\"\nmean = 0.005\nstd = 0.0005\nmin = 0.0025\nmax = 0.0075\n");
            let radii = distribution(&text).sample(n, &mut Rng::new(4));
            let (mean, std) = moments(&radii);
            assert!((mean - 0.005).abs() < 4.0 * 0.0005 / (n as f64).sqrt(), "{kind}: mean {mean}");
            assert!((std / 0.0005 - 1.0).abs() < 0.03, "{kind}: std {std}");
            assert!(radii.iter().all(|r| (0.0025..=0.0075).contains(r)));
        }
        // Tight bounds cut the tails: every radius inside, the spread smaller.
        let cut = distribution("kind = \"normal\"\nmean = 0.005\nstd = 0.001\nmin = 0.0045\nmax = 0.006\n");
        let radii = cut.sample(n, &mut Rng::new(5));
        assert!(radii.iter().all(|r| (0.0045..=0.006).contains(r)));
        // The truncated normal's mean: μ + σ (φ(α) − φ(β)) / (Φ(β) − Φ(α)), α = −0.5, β = 1.
        let phi = |z: f64| (-z * z / 2.0).exp() / (std::f64::consts::TAU).sqrt();
        let big_phi = |z: f64| 0.5 * erfc(-z / std::f64::consts::SQRT_2);
        let expected = 0.005 + 0.001 * (phi(-0.5) - phi(1.0)) / (big_phi(1.0) - big_phi(-0.5));
        assert!((moments(&radii).0 - expected).abs() < 2e-6, "{} vs {expected}", moments(&radii).0);
    }

    #[test]
    fn each_kind_names_what_it_lacks_or_does_not_read() {
        let issues = |text: &str| -> Vec<String> {
            distribution(text).issues().iter().map(|i| format!("{}: {}", i.key, i.reason)).collect()
        };
        assert_eq!(issues("kind = \"uniform\"\nmin = 0.001\nmax = 0.002\n"), Vec::<String>::new());
        assert_eq!(
            issues("kind = \"uniform\"\nmin = 0.001\nmean = 0.002\n"),
            ["mean: is not read by a uniform distribution (it reads min, max)", "max: a uniform distribution needs it"]
        );
        assert_eq!(
            issues("kind = \"discrete\"\nradii = [0.001, 0.002]\nfractions = [1]\n"),
            ["fractions: has 1 entries but radii has 2"]
        );
        let far = issues("kind = \"normal\"\nmean = 0.005\nstd = 0.0001\nmin = 0.006\nmax = 0.007\n");
        assert!(far[0].starts_with("max: [min, max] holds"), "{far:?}");
        assert!(
            issues("kind = \"lognormal\"\nmean = 0.005\nstd = 0.001\nmin = 0.004\nmax = 0.003\n")[0]
                .starts_with("max: must be")
        );
    }

    #[test]
    fn erfc_is_the_complementary_error_function() {
        for (x, expected) in
            [(0.0, 1.0), (0.5, 0.479_500_122), (1.0, 0.157_299_207), (-1.0, 1.842_700_793), (3.0, 2.209_049_7e-5)]
        {
            assert!((erfc(x) - expected).abs() < 2e-7 * expected.max(1e-3), "erfc({x}) = {}", erfc(x));
        }
    }
}
