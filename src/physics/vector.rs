//! Running a loop in the widest vector instructions the CPU has.
//!
//! The hot loops are written as plain loops over equal-length slices, which the compiler vectorises
//! for the baseline instruction set (SSE2 on x86-64: 2 lanes of f64). [`widest`] runs such a loop
//! in a copy compiled for AVX2 (4 lanes) when the CPU supports it. Both copies do the same IEEE
//! operations in the same order (Rust never fuses a multiply and an add on its own), so results
//! are bit-identical whichever copy runs.

/// Runs `kernel`, compiled for AVX2 where the CPU has it. Mark the closure `#[inline(always)]`:
/// only code inlined into the AVX2 copy is compiled for AVX2.
#[inline(always)]
pub fn widest<R>(kernel: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    #[allow(unsafe_code)]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2, checked just above.
        return unsafe { avx2(kernel) };
    }
    kernel()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn avx2<R>(kernel: impl FnOnce() -> R) -> R {
    kernel()
}

/// `Σ term(i)` for `i` in `0..n`, added up in four interleaved partial sums, combined at the end.
/// A single running sum waits for each addition to finish before the next (some four cycles);
/// four independent ones fill a vector register and keep the adder busy.
#[inline(always)]
pub fn lane_sum(n: usize, term: impl Fn(usize) -> f64) -> f64 {
    let mut lanes = [0.0; 4];
    let whole = n - n % 4;
    for i in (0..whole).step_by(4) {
        for (lane, sum) in lanes.iter_mut().enumerate() {
            *sum += term(i + lane);
        }
    }
    for i in whole..n {
        lanes[i % 4] += term(i);
    }
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3])
}

/// The largest `x² + y²` of a loop, NaN if any is NaN, in a form that keeps the loop vectorised:
/// the maximum of the values' bit patterns. For non-negative numbers those order as the numbers do,
/// and every NaN's is above infinity's. (`f64::max` would skip NaNs, and as a running maximum of
/// floats it keeps the compiler from vectorising the loop.)
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LargestSquare(u64);

impl LargestSquare {
    /// Takes `x² + y²` into account.
    #[inline(always)]
    pub fn add(&mut self, x: f64, y: f64) {
        self.0 = self.0.max((x * x + y * y).to_bits());
    }

    /// The larger of two.
    pub fn max(self, other: Self) -> Self {
        Self(self.0.max(other.0))
    }

    /// The square root of the largest `x² + y²` so far (0 before any): the longest vector `(x, y)`.
    pub fn root(self) -> f64 {
        f64::from_bits(self.0).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::{LargestSquare, lane_sum};

    #[test]
    fn lane_sum_adds_every_term_once_with_any_tail() {
        for n in 0..11 {
            // Powers of two: every partial sum is exact, so any order gives the exact total.
            let total = lane_sum(n, |i| f64::from(1u32 << i));
            assert_eq!(total, f64::from((1u32 << n) - 1), "n = {n}");
        }
    }

    #[test]
    fn largest_square_is_the_longest_vector_and_keeps_nan() {
        let mut a = LargestSquare::default();
        assert_eq!(a.root(), 0.0);
        for (x, y) in [(3.0, -4.0), (0.0, 1.0), (-1e-300, 0.0), (2.0, 2.0)] {
            a.add(x, y);
        }
        assert_eq!(a.root(), 5.0);
        let mut b = LargestSquare::default();
        b.add(f64::INFINITY, 0.0);
        assert_eq!(a.max(b).root(), f64::INFINITY);
        b.add(f64::NAN, 1.0);
        b.add(7.0, 0.0);
        assert!(b.root().is_nan() && a.max(b).root().is_nan() && b.max(a).root().is_nan());
    }
}
