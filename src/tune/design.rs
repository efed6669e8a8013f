//! Where new candidates come from: a randomly shifted Halton sequence (Cranley-Patterson rotation)
//! snapped to a grid of the normalized lever space.

/// Grid of the normalized coordinates: candidates closer than 1/QUANT are the same.
pub const QUANT: f64 = 64.0;

/// The primes of the Halton sequence's bases: one lever each.
pub const PRIMES: [u64; 16] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53];

/// The radical inverse of `index` in base `base` (van der Corput), the Halton sequence's coordinate.
pub fn radical_inverse(mut index: u64, base: u64) -> f64 {
    let (mut result, mut f) = (0.0, 1.0 / base as f64);
    while index > 0 {
        result += f * (index % base) as f64;
        index /= base;
        f /= base as f64;
    }
    result
}

/// Point `index` of the Halton sequence shifted by `shift` (modulo 1), one coordinate per shift.
pub fn halton(index: u64, shift: &[f64]) -> Vec<f64> {
    shift.iter().enumerate().map(|(d, s)| (radical_inverse(index, PRIMES[d]) + s).fract()).collect()
}

/// `point` clamped to [0, 1] and snapped: a list lever (`Some(values)`) to its bin centre, a
/// continuous one to the 1/[`QUANT`] grid.
pub fn snap(point: &[f64], levels: &[Option<usize>]) -> Vec<f64> {
    point
        .iter()
        .zip(levels)
        .map(|(x, levels)| {
            let x = x.clamp(0.0, 1.0);
            match levels {
                Some(n) => {
                    let k = ((x * *n as f64).floor() as i64).min(*n as i64 - 1);
                    (k as f64 + 0.5) / *n as f64
                }
                None => (x * QUANT).round() / QUANT,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halton_is_the_van_der_corput_sequence() {
        assert_eq!(radical_inverse(1, 2), 0.5);
        assert_eq!(radical_inverse(3, 2), 0.75);
        assert!((radical_inverse(1, 3) - 1.0 / 3.0).abs() < 1e-15);
        assert_eq!(halton(1, &[0.75, 0.0]), vec![0.25, 1.0 / 3.0]);
    }

    #[test]
    fn snapping_keeps_list_levers_in_their_bins() {
        assert_eq!(snap(&[0.49, 1.2], &[Some(2), None]), vec![0.25, 1.0]);
        assert_eq!(snap(&[0.3], &[None]), vec![19.0 / 64.0]);
    }
}
