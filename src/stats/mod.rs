//! Statistics of replicated runs: description, Student t quantiles, equivalence (TOST) and ratios.
//!
//! Placeholder with the agreed public API (issue 14); the real module lands on main.

/// Summary of a sample (NaN values skipped).
#[derive(Clone, Debug, PartialEq)]
pub struct Describe {
    /// Number of values.
    pub n: usize,
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation (n − 1).
    pub std: f64,
    /// 95 % confidence half-width of the mean (Student t, n − 1 degrees of freedom).
    pub half_width_95: f64,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
}

/// Describes a sample; NaN values are skipped.
pub fn describe(values: &[f64]) -> Describe {
    let v: Vec<f64> = values.iter().copied().filter(|x| !x.is_nan()).collect();
    let n = v.len();
    if n == 0 {
        return Describe { n, mean: f64::NAN, std: f64::NAN, half_width_95: f64::NAN, min: f64::NAN, max: f64::NAN };
    }
    let mean = v.iter().sum::<f64>() / n as f64;
    let std =
        if n > 1 { (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt() } else { f64::NAN };
    let half_width_95 =
        if n > 1 { student_t_quantile(0.975, (n - 1) as f64) * std / (n as f64).sqrt() } else { f64::NAN };
    let min = v.iter().copied().fold(f64::INFINITY, f64::min);
    let max = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Describe { n, mean, std, half_width_95, min, max }
}

/// The `p` quantile of Student's t distribution with `df` degrees of freedom.
pub fn student_t_quantile(p: f64, df: f64) -> f64 {
    if !(0.0..=1.0).contains(&p) || df.is_nan() || df <= 0.0 {
        return f64::NAN;
    }
    if p == 0.5 {
        return 0.0;
    }
    if p < 0.5 {
        return -student_t_quantile(1.0 - p, df);
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    while t_cdf(hi, df) < p {
        hi *= 2.0;
        if hi > 1e12 {
            return f64::INFINITY;
        }
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if t_cdf(mid, df) < p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

fn t_cdf(t: f64, df: f64) -> f64 {
    let x = df / (df + t * t);
    let tail = 0.5 * incomplete_beta(0.5 * df, 0.5, x);
    if t >= 0.0 { 1.0 - tail } else { tail }
}

/// Regularized incomplete beta I_x(a, b) (continued fraction, Numerical Recipes 6.4).
fn incomplete_beta(a: f64, b: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let front = (ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln()).exp();
    if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_fraction(a, b, x) / a
    } else {
        1.0 - front * beta_fraction(b, a, 1.0 - x) / b
    }
}

fn beta_fraction(a: f64, b: f64, x: f64) -> f64 {
    let tiny = 1e-300;
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 - qab * x / qap;
    if d.abs() < tiny {
        d = tiny;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..300 {
        let m = m as f64;
        let m2 = 2.0 * m;
        let aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 + aa * d;
        d = if d.abs() < tiny { 1.0 / tiny } else { 1.0 / d };
        c = 1.0 + aa / c;
        if c.abs() < tiny {
            c = tiny;
        }
        h *= d * c;
        let aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 + aa * d;
        d = if d.abs() < tiny { 1.0 / tiny } else { 1.0 / d };
        c = 1.0 + aa / c;
        if c.abs() < tiny {
            c = tiny;
        }
        let del = d * c;
        h *= del;
        if (del - 1.0).abs() < 1e-15 {
            break;
        }
    }
    h
}

/// ln Γ(x) (Lanczos, g = 7).
fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        return (std::f64::consts::PI / (std::f64::consts::PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let sum = C[0] + C.iter().enumerate().skip(1).map(|(i, c)| c / (x + i as f64)).sum::<f64>();
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}

/// Outcome of an equivalence test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Decision {
    /// The 90 % interval lies inside (−margin, +margin).
    Equivalent,
    /// The 90 % interval lies wholly outside (−margin, +margin).
    Different,
    /// Neither: more seeds needed.
    Undecided,
}

/// Two one-sided tests (Schuirmann 1987) of mean(candidate) − mean(reference) against ±margin.
#[derive(Clone, Debug, PartialEq)]
pub struct Equivalence {
    /// mean(candidate) − mean(reference).
    pub difference: f64,
    /// Lower end of the 90 % Welch interval.
    pub low: f64,
    /// Upper end of the 90 % Welch interval.
    pub high: f64,
    /// The decision.
    pub decision: Decision,
    /// About how many seeds per side would decide an undecided case (None when decided or hopeless).
    pub seeds_needed: Option<usize>,
}

/// TOST with a 90 % Welch interval of mean(candidate) − mean(reference) and an absolute margin.
pub fn equivalence(reference: &[f64], candidate: &[f64], margin: f64) -> Equivalence {
    let (r, c) = (describe(reference), describe(candidate));
    let difference = c.mean - r.mean;
    let (vr, vc) = (variance_of_mean(&r), variance_of_mean(&c));
    let se = (vr + vc).sqrt();
    let t = if se > 0.0 {
        let df = (vr + vc).powi(2) / (vr * vr / (r.n as f64 - 1.0) + vc * vc / (c.n as f64 - 1.0));
        student_t_quantile(0.95, df)
    } else {
        0.0
    };
    let (low, high) = (difference - t * se, difference + t * se);
    let decision = if low.is_nan() || high.is_nan() {
        Decision::Undecided
    } else if low > -margin && high < margin {
        Decision::Equivalent
    } else if low >= margin || high <= -margin {
        Decision::Different
    } else {
        Decision::Undecided
    };
    let seeds_needed = if decision == Decision::Undecided && difference.abs() < margin && r.n > 1 && c.n > 1 {
        let s2 = r.std.powi(2) + c.std.powi(2);
        (2..10_000).find(|&n| {
            let t = student_t_quantile(0.95, (2 * n - 2) as f64);
            difference.abs() + t * (s2 / n as f64).sqrt() < margin
        })
    } else {
        None
    };
    Equivalence { difference, low, high, decision, seeds_needed }
}

fn variance_of_mean(d: &Describe) -> f64 {
    if d.n > 1 { d.std * d.std / d.n as f64 } else { f64::NAN }
}

/// A ratio of means with its confidence interval.
#[derive(Clone, Debug, PartialEq)]
pub struct Ratio {
    /// mean(candidate) / mean(reference).
    pub ratio: f64,
    /// Lower end of the 95 % interval.
    pub low: f64,
    /// Upper end of the 95 % interval.
    pub high: f64,
}

/// mean(candidate) / mean(reference) with a 95 % interval (delta method on the log ratio, Welch df).
pub fn ratio_interval(reference: &[f64], candidate: &[f64]) -> Ratio {
    let (r, c) = (describe(reference), describe(candidate));
    let ratio = c.mean / r.mean;
    let vr = variance_of_mean(&r) / (r.mean * r.mean);
    let vc = variance_of_mean(&c) / (c.mean * c.mean);
    let v = vr + vc;
    if !(v > 0.0) {
        return Ratio { ratio, low: ratio, high: ratio };
    }
    let df = v * v / (vr * vr / (r.n as f64 - 1.0) + vc * vc / (c.n as f64 - 1.0));
    let t = student_t_quantile(0.975, df);
    let k = (t * v.sqrt()).exp();
    Ratio { ratio, low: ratio / k, high: ratio * k }
}
