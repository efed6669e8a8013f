//! Statistics over replicates (no I/O): per-point descriptions, equivalence of a setting with a
//! reference by two one-sided tests, ratios of means with intervals.
//!
//! A *point* is the set of runs of a study that differ only by placement seed ([`points`]);
//! [`compare`] sets every point against a reference point (`demsweep compare`). See
//! `docs/deposition.md`, "Statistics".

mod distribution;
mod errors;

pub use errors::{CompareError, UnknownMetric};

pub mod compare;
pub mod fit;
pub mod points;

/// n, mean, sample std, 95% Student-t half-width, min, max of the finite values (NaN skipped).
///
/// With no value every field but `n` is NaN; with one value `std` and `half_width_95` are NaN.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Describe {
    /// Number of finite values.
    pub n: usize,
    /// Their mean.
    pub mean: f64,
    /// Sample standard deviation (n − 1 in the denominator).
    pub std: f64,
    /// Half-width of the 95 % confidence interval of the mean: t(0.975, n − 1) · std / √n.
    pub half_width_95: f64,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
}

/// Describes the finite values of `values` (NaN and infinities are skipped).
pub fn describe(values: &[f64]) -> Describe {
    let finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    let n = finite.len();
    let nan = f64::NAN;
    if n == 0 {
        return Describe { n, mean: nan, std: nan, half_width_95: nan, min: nan, max: nan };
    }
    let mean = finite.iter().sum::<f64>() / n as f64;
    let (std, half_width_95) = if n < 2 {
        (nan, nan)
    } else {
        let variance = finite.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let std = variance.sqrt();
        (std, student_t_quantile(0.975, (n - 1) as f64) * std / (n as f64).sqrt())
    };
    let min = finite.iter().copied().fold(f64::INFINITY, f64::min);
    let max = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Describe { n, mean, std, half_width_95, min, max }
}

/// Quantile of Student's t distribution with `df` degrees of freedom (df may be fractional, Welch), p in (0,1).
///
/// Computed by bisection on the distribution function (regularized incomplete beta function) to
/// about 15 significant digits; NaN for p outside (0, 1) or df ≤ 0.
pub fn student_t_quantile(p: f64, df: f64) -> f64 {
    distribution::t_quantile(p, df)
}

/// Distribution function of Student's t distribution with `df` degrees of freedom, P(T ≤ t); NaN for
/// df ≤ 0.
pub fn student_t_cdf(t: f64, df: f64) -> f64 {
    distribution::t_cdf(t, df)
}

/// Outcome of an equivalence test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Decision {
    /// The 90 % interval of the difference lies inside (−margin, +margin).
    Equivalent,
    /// The interval lies wholly outside: entirely ≥ margin or entirely ≤ −margin.
    Different,
    /// Neither: more seeds are needed (or a group has fewer than 2 values).
    Undecided,
}

impl Decision {
    /// The decision in words: `equivalent`, `different` or `undecided`.
    pub fn as_str(self) -> &'static str {
        match self {
            Decision::Equivalent => "equivalent",
            Decision::Different => "different",
            Decision::Undecided => "undecided",
        }
    }
}

/// A candidate set against a reference set on one metric.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Equivalence {
    /// mean(candidate) − mean(reference).
    pub difference: f64,
    /// Lower end of its 90 % Welch interval (NaN when a group has fewer than 2 values).
    pub low: f64,
    /// Upper end of its 90 % Welch interval.
    pub high: f64,
    /// Equivalent, different or undecided.
    pub decision: Decision,
    /// For an undecided test: the rough number of values per group at which the interval would
    /// decide (see [`equivalence`]); `None` otherwise, or when it cannot be estimated.
    pub seeds_needed: Option<usize>,
}

/// Largest per-group count that [`equivalence`] reports as seeds needed.
const MAX_SEEDS: usize = 100_000;

/// TOST (Schuirmann 1987): 90% Welch interval of mean(candidate) - mean(reference), absolute margin `margin` > 0.
///
/// Two one-sided t tests at 5 % each are equivalent to asking whether the 90 % confidence interval
/// d ± t(0.95, ν) · √(s_c²/n_c + s_r²/n_r) (Welch–Satterthwaite ν) lies inside (−margin, +margin).
/// Different when it lies wholly outside; undecided otherwise, and always when a group has fewer than
/// 2 finite values. `seeds_needed` (undecided only) assumes the observed difference d and both groups'
/// standard deviations stay as they are and n values in each group: it is the smallest n, above both
/// counts so far (they did not decide), whose Welch half-width is below | margin − |d| |, where the
/// interval clears the nearer margin; `None` when d sits on the margin or more than 100 000 would be
/// needed.
pub fn equivalence(reference: &[f64], candidate: &[f64], margin: f64) -> Equivalence {
    let (r, c) = (describe(reference), describe(candidate));
    let difference = c.mean - r.mean;
    if r.n < 2 || c.n < 2 {
        let nan = f64::NAN;
        return Equivalence { difference, low: nan, high: nan, decision: Decision::Undecided, seeds_needed: None };
    }
    let (vr, vc) = (r.std.powi(2) / r.n as f64, c.std.powi(2) / c.n as f64);
    let half =
        if vr + vc > 0.0 { student_t_quantile(0.95, welch_df(vr, r.n, vc, c.n)) * (vr + vc).sqrt() } else { 0.0 };
    let (low, high) = (difference - half, difference + half);
    let decision = if -margin < low && high < margin {
        Decision::Equivalent
    } else if low >= margin || high <= -margin {
        Decision::Different
    } else {
        Decision::Undecided
    };
    let seeds_needed =
        if decision == Decision::Undecided { seeds_to_decide(difference, (&r, &c), margin) } else { None };
    Equivalence { difference, low, high, decision, seeds_needed }
}

/// Welch–Satterthwaite degrees of freedom of a sum of two variance terms v = s²/n.
fn welch_df(v1: f64, n1: usize, v2: f64, n2: usize) -> f64 {
    (v1 + v2).powi(2) / (v1.powi(2) / (n1 - 1) as f64 + v2.powi(2) / (n2 - 1) as f64)
}

/// Smallest per-group n, above both groups' counts (which did not decide), whose 90 % Welch
/// half-width with the groups' own spreads, `t(0.95, ν) · √((s_r² + s_c²)/n)`, is below
/// |margin − |d||.
fn seeds_to_decide(difference: f64, (r, c): (&Describe, &Describe), margin: f64) -> Option<usize> {
    let gap = (margin - difference.abs()).abs();
    let variance = r.std.powi(2) + c.std.powi(2);
    if !(gap > 0.0 && variance.is_finite()) {
        return None;
    }
    let half_width = |n: usize| {
        let (vr, vc) = (r.std.powi(2) / n as f64, c.std.powi(2) / n as f64);
        student_t_quantile(0.95, welch_df(vr, n, vc, n)) * (variance / n as f64).sqrt()
    };
    let decides = |n: usize| half_width(n) < gap;
    if !decides(MAX_SEEDS) {
        return None;
    }
    // The half-width falls with n: bisect between a count that does not decide and one that does.
    let (mut low, mut high) = (r.n.max(c.n).max(1), MAX_SEEDS);
    while high - low > 1 {
        let mid = (low + high) / 2;
        if decides(mid) {
            high = mid;
        } else {
            low = mid;
        }
    }
    Some(high)
}

/// Ratio of means mean(candidate)/mean(reference) with a 95% interval (say which method: Fieller or delta method on logs).
///
/// Delta method on logs: ln r = ln m_c − ln m_r with variance s_c²/(n_c m_c²) + s_r²/(n_r m_r²)
/// and Welch–Satterthwaite degrees of freedom; the interval is exp(ln r ± t(0.975, ν) · se), so it
/// never includes zero or negative ratios. `low` and `high` are NaN when a group has fewer than
/// 2 finite values or a mean is not positive; equal to the ratio when neither group varies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ratio {
    /// mean(candidate) / mean(reference).
    pub ratio: f64,
    /// Lower end of the 95 % interval.
    pub low: f64,
    /// Upper end of the 95 % interval.
    pub high: f64,
}

/// The ratio of the means of `candidate` and `reference` with its 95 % interval (see [`Ratio`]).
pub fn ratio_interval(reference: &[f64], candidate: &[f64]) -> Ratio {
    let (r, c) = (describe(reference), describe(candidate));
    let ratio = c.mean / r.mean;
    let nan = f64::NAN;
    if r.n < 2 || c.n < 2 || !(r.mean > 0.0 && c.mean > 0.0) {
        return Ratio { ratio, low: nan, high: nan };
    }
    let vr = (r.std / r.mean).powi(2) / r.n as f64;
    let vc = (c.std / c.mean).powi(2) / c.n as f64;
    if vr + vc == 0.0 {
        return Ratio { ratio, low: ratio, high: ratio };
    }
    let half = student_t_quantile(0.975, welch_df(vr, r.n, vc, c.n)) * (vr + vc).sqrt();
    Ratio { ratio, low: ratio * (-half).exp(), high: ratio * half.exp() }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tolerance: f64) -> bool {
        (a - b).abs() <= tolerance
    }

    #[test]
    fn seeds_to_decide_is_never_a_count_the_groups_already_have() {
        // A tight reference (10 runs) against a spread candidate (8 runs): the equal-n pooled formula
        // answered about 10, a count the reference already had without deciding.
        let reference: Vec<f64> = (0..10).map(|k| 1.0 + 0.01 * ((k % 3) as f64 - 1.0)).collect();
        let candidate: Vec<f64> = (0..8).map(|k| 1.05 + 0.1 * ((k % 3) as f64 - 1.0)).collect();
        let e = equivalence(&reference, &candidate, 0.08);
        assert_eq!(e.decision, Decision::Undecided, "{e:?}");
        let n = e.seeds_needed.expect("an estimate");
        assert!(n > 10, "{n}");
        let (r, c) = (describe(&reference), describe(&candidate));
        let half = |n: usize| {
            let (vr, vc) = (r.std.powi(2) / n as f64, c.std.powi(2) / n as f64);
            student_t_quantile(0.95, welch_df(vr, n, vc, n)) * (vr + vc).sqrt()
        };
        let gap = 0.08 - e.difference.abs();
        assert!(half(n) < gap && half(n - 1) >= gap, "n = {n}");
    }

    #[test]
    fn t_quantiles_match_the_tables() {
        // Two-sided 90 % and 95 % critical values (e.g. NIST/SEMATECH e-Handbook, table 1.3.6.7.2).
        let table = [
            (1.0, 6.3138, 12.7062),
            (2.0, 2.9200, 4.3027),
            (3.0, 2.3534, 3.1824),
            (4.0, 2.1318, 2.7764),
            (5.0, 2.0150, 2.5706),
            (10.0, 1.8125, 2.2281),
            (30.0, 1.6973, 2.0423),
        ];
        for (df, t95, t975) in table {
            assert!(close(student_t_quantile(0.95, df), t95, 5e-5), "t(0.95, {df})");
            assert!(close(student_t_quantile(0.975, df), t975, 5e-5), "t(0.975, {df})");
            assert!(close(student_t_quantile(0.025, df), -t975, 5e-5), "symmetric");
        }
    }

    #[test]
    fn t_quantiles_match_closed_forms_and_the_normal_limit() {
        for p in [0.6, 0.9, 0.975, 0.999] {
            let cauchy = (std::f64::consts::PI * (p - 0.5)).tan();
            assert!(close(student_t_quantile(p, 1.0), cauchy, 1e-9 * cauchy), "df 1, p {p}");
            let two = (2.0 * p - 1.0) / (2.0 * p * (1.0 - p)).sqrt();
            assert!(close(student_t_quantile(p, 2.0), two, 1e-10 * two), "df 2, p {p}");
        }
        assert!(close(student_t_quantile(0.975, 1e9), 1.959_964, 1e-6));
        // Fractional (Welch) degrees of freedom fall between their neighbours.
        let t = student_t_quantile(0.95, 3.5);
        assert!(t < student_t_quantile(0.95, 3.0) && t > student_t_quantile(0.95, 4.0));
        assert_eq!(student_t_quantile(0.5, 7.0), 0.0);
        assert!(student_t_quantile(1.0, 3.0).is_nan() && student_t_quantile(0.9, 0.0).is_nan());
    }

    #[test]
    fn describe_skips_missing_values() {
        let d = describe(&[2.0, f64::NAN, 4.0, 6.0, 8.0]);
        assert_eq!((d.n, d.mean, d.min, d.max), (4, 5.0, 2.0, 8.0));
        // Sample variance (9 + 1 + 1 + 9) / 3.
        assert!(close(d.std, (20.0f64 / 3.0).sqrt(), 1e-15));
        assert!(close(d.half_width_95, 3.182_446_305 * d.std / 2.0, 1e-8));
        let one = describe(&[3.0]);
        assert_eq!((one.n, one.mean, one.min, one.max), (1, 3.0, 3.0, 3.0));
        assert!(one.std.is_nan() && one.half_width_95.is_nan());
        assert!(describe(&[f64::NAN]).mean.is_nan());
    }
}
