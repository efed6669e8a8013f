//! Student's t distribution: distribution function through the regularized incomplete beta function,
//! quantile by bisection on it.
//!
//! Sources: the incomplete beta continued fraction (modified Lentz) and the symmetry switch follow
//! Press et al., *Numerical Recipes*, 3rd ed. (2007), §6.4; ln Γ is Lanczos' approximation with
//! g = 7 and 9 coefficients (Godfrey's table, relative error below 1e-15); the t distribution
//! function is P(T ≤ t) = 1 − ½ I_{ν/(ν+t²)}(ν/2, ½) for t ≥ 0 (Abramowitz & Stegun 26.7.1).

/// Degrees of freedom beyond which the t distribution is evaluated at this value (the quantiles
/// then agree with the normal ones to about 1e-7, and ln Γ keeps its precision).
const MAX_DF: f64 = 1e7;

/// ln Γ(x) for x > 0 (Lanczos, g = 7).
fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
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
        // Reflection: Γ(x) Γ(1 − x) = π / sin(π x).
        return (std::f64::consts::PI / (std::f64::consts::PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let series = C[1..].iter().enumerate().fold(C[0], |sum, (i, c)| sum + c / (x + i as f64 + 1.0));
    let t = x + G + 0.5;
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + series.ln()
}

/// The regularized incomplete beta function I_x(a, b) for a, b > 0 and x in [0, 1].
fn incomplete_beta(x: f64, a: f64, b: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let ln_front = ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln();
    let front = ln_front.exp();
    // The continued fraction converges fast for x below (a + 1) / (a + b + 2); use symmetry above.
    if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_fraction(x, a, b) / a
    } else {
        1.0 - front * beta_fraction(1.0 - x, b, a) / b
    }
}

/// The continued fraction of the incomplete beta function (modified Lentz's method).
fn beta_fraction(x: f64, a: f64, b: f64) -> f64 {
    const TINY: f64 = 1e-300;
    const EPS: f64 = 1e-16;
    let clamp = |v: f64| if v.abs() < TINY { TINY } else { v };
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 / clamp(1.0 - qab * x / qap);
    let mut h = d;
    for m in 1..=10_000 {
        let m = f64::from(m);
        let m2 = 2.0 * m;
        let even = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 / clamp(1.0 + even * d);
        c = clamp(1.0 + even / c);
        h *= d * c;
        let odd = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 / clamp(1.0 + odd * d);
        c = clamp(1.0 + odd / c);
        let step = d * c;
        h *= step;
        if (step - 1.0).abs() < EPS {
            break;
        }
    }
    h
}

/// P(T > t) for t ≥ 0 with `df` degrees of freedom.
fn upper_tail(t: f64, df: f64) -> f64 {
    0.5 * incomplete_beta(df / (df + t * t), 0.5 * df, 0.5)
}

/// The distribution function of Student's t distribution (see [`super::student_t_cdf`]).
pub(super) fn t_cdf(t: f64, df: f64) -> f64 {
    if t.is_nan() || df.is_nan() || df <= 0.0 {
        return f64::NAN;
    }
    let tail = upper_tail(t.abs(), df.min(MAX_DF));
    if t >= 0.0 { 1.0 - tail } else { tail }
}

/// The quantile of Student's t distribution (see [`super::student_t_quantile`]).
pub(super) fn t_quantile(p: f64, df: f64) -> f64 {
    if !(p > 0.0 && p < 1.0) || df.is_nan() || df <= 0.0 {
        return f64::NAN;
    }
    if p == 0.5 {
        return 0.0;
    }
    let df = df.min(MAX_DF);
    let tail = p.min(1.0 - p);
    let mut high = 1.0;
    while upper_tail(high, df) > tail {
        high *= 2.0;
    }
    let mut low = 0.0;
    // Bisection: the upper tail falls monotonically with t.
    while high - low > 1e-15 * high {
        let mid = 0.5 * (low + high);
        if mid <= low || mid >= high {
            break;
        }
        if upper_tail(mid, df) > tail {
            low = mid;
        } else {
            high = mid;
        }
    }
    let t = 0.5 * (low + high);
    if p > 0.5 { t } else { -t }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_distribution_function_inverts_the_quantile_and_is_symmetric() {
        for (p, df) in [(0.95, 3.0), (0.7, 12.5), (0.999, 1e8), (0.2, 2.0)] {
            assert!((t_cdf(t_quantile(p, df), df) - p).abs() < 1e-12, "p {p} df {df}");
        }
        assert!((t_cdf(-1.3, 7.0) + t_cdf(1.3, 7.0) - 1.0).abs() < 1e-15);
        assert!((t_cdf(1.959_963_984_540_054, 1e9) - 0.975).abs() < 1e-7, "the normal limit");
        assert!(t_cdf(f64::INFINITY, 4.0) == 1.0 && t_cdf(0.0, 4.0) == 0.5);
    }

    #[test]
    fn ln_gamma_matches_factorials_and_the_half() {
        for (n, factorial) in [(1.0, 1.0), (2.0, 1.0), (5.0, 24.0), (11.0, 3_628_800.0)] {
            assert!((ln_gamma(n) - f64::ln(factorial)).abs() < 1e-12, "ln Γ({n})");
        }
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-13);
    }

    #[test]
    fn incomplete_beta_has_closed_forms() {
        // I_x(1, 1) = x, I_x(a, 1) = x^a, I_x(1, b) = 1 − (1 − x)^b.
        for x in [0.1, 0.5, 0.93] {
            assert!((incomplete_beta(x, 1.0, 1.0) - x).abs() < 1e-14);
            assert!((incomplete_beta(x, 3.5, 1.0) - x.powf(3.5)).abs() < 1e-14);
            assert!((incomplete_beta(x, 1.0, 2.5) - (1.0 - (1.0 - x).powf(2.5))).abs() < 1e-14);
        }
    }
}
