//! Small fits tune makes from its runs: a log-linear model of cost over the levers, the order of an
//! error that follows a power of the time step, and an empirical quantile.

/// Least-squares fit of `ln(cost) = b0 + Σ b_d x_d` over `(x, cost)` rows (non-finite logs left
/// out): the coefficients `[b0, b1, …]`, None with fewer than `dims + 3` usable rows or a singular
/// system.
pub fn log_linear(rows: &[(Vec<f64>, f64)], dims: usize) -> Option<Vec<f64>> {
    let n = dims + 1;
    let rows: Vec<(Vec<f64>, f64)> = rows
        .iter()
        .map(|(x, cost)| (std::iter::once(1.0).chain(x.iter().copied()).collect::<Vec<f64>>(), cost.ln()))
        .filter(|(x, y)| y.is_finite() && x.len() == n)
        .collect();
    if rows.len() < n + 2 {
        return None;
    }
    // Normal equations (with a tiny ridge), solved by Gaussian elimination with partial pivoting.
    let mut a = vec![vec![0.0; n + 1]; n];
    for (x, y) in &rows {
        for i in 0..n {
            for j in 0..n {
                a[i][j] += x[i] * x[j];
            }
            a[i][n] += x[i] * y;
        }
    }
    for (i, row) in a.iter_mut().enumerate() {
        row[i] += 1e-9;
    }
    for col in 0..n {
        let pivot = (col..n).max_by(|&p, &q| a[p][col].abs().total_cmp(&a[q][col].abs()))?;
        a.swap(col, pivot);
        if a[col][col].abs() < 1e-12 {
            return None;
        }
        let pivot_row = a[col].clone();
        for (i, row) in a.iter_mut().enumerate() {
            if i != col {
                let f = row[col] / pivot_row[col];
                row.iter_mut().zip(&pivot_row).skip(col).for_each(|(x, p)| *x -= f * p);
            }
        }
    }
    Some((0..n).map(|i| a[i][n] / a[i][i]).collect())
}

/// The order `p` of an error `e ∝ dt^p` through two points: `error_large` at a time step `ratio`
/// (> 1) times the one of `error_small`, clamped to `[low, high]`; `low` when the points do not
/// give one (an error that does not grow, or a missing value).
pub fn error_order(error_small: f64, error_large: f64, ratio: f64, (low, high): (f64, f64)) -> f64 {
    let order = (error_large / error_small).ln() / ratio.ln();
    if order.is_finite() && ratio > 1.0 { order.clamp(low, high) } else { low }
}

/// The empirical `q`-quantile of the finite values (linear interpolation between order statistics,
/// Hyndman and Fan's type 7, R's default); NaN without any.
pub fn quantile(values: &[f64], q: f64) -> f64 {
    let mut sorted: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted.sort_by(f64::total_cmp);
    let h = (sorted.len() - 1) as f64 * q.clamp(0.0, 1.0);
    let (low, frac) = (h.floor() as usize, h.fract());
    let high = (low + 1).min(sorted.len() - 1);
    sorted[low] + frac * (sorted[high] - sorted[low])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantile_interpolates_between_order_statistics() {
        assert_eq!(quantile(&[4.0, 1.0, 3.0, 2.0, 5.0], 0.75), 4.0);
        assert_eq!(quantile(&[0.4, 1.12, 0.5], 0.75), 0.5 + 0.5 * (1.12 - 0.5));
        assert!(quantile(&[], 0.5).is_nan());
    }

    #[test]
    fn the_error_order_is_read_from_two_points_and_clamped() {
        assert!((error_order(0.01, 0.04, 2.0, (1.0, 2.0)) - 2.0).abs() < 1e-12);
        assert!((error_order(0.01, 0.03, 2.0, (1.0, 2.0)) - 3f64.log2()).abs() < 1e-12);
        assert_eq!(error_order(0.01, 0.5, 2.0, (1.0, 2.0)), 2.0);
        assert_eq!(error_order(0.02, 0.01, 2.0, (1.0, 2.0)), 1.0);
        assert_eq!(error_order(f64::NAN, 0.01, 2.0, (1.0, 2.0)), 1.0);
    }

    #[test]
    fn a_log_linear_cost_is_recovered() {
        let rows: Vec<(Vec<f64>, f64)> =
            (0..6).map(|k| (vec![k as f64 / 5.0], (1.0 - 0.5 * k as f64 / 5.0f64).exp())).collect();
        let b = log_linear(&rows, 1).unwrap();
        assert!((b[0] - 1.0).abs() < 1e-6 && (b[1] + 0.5).abs() < 1e-6, "{b:?}");
        assert!(log_linear(&rows[..2], 1).is_none());
    }
}
