//! Running a loop in the widest vector instructions the CPU runs well.
//!
//! The hot loops are written as plain loops over equal-length slices, which the compiler vectorises
//! for the baseline instruction set (SSE2 on x86-64: 2 lanes of f64). [`widest`] runs such a loop
//! in a copy compiled for AVX2 (4 lanes) or AVX-512 (8 lanes), as [`width`] says. All copies do the
//! same IEEE operations in the same order (Rust never fuses a multiply and an add on its own), so
//! results are bit-identical whichever copy runs, on whichever CPU.

use std::sync::atomic::{AtomicU8, Ordering};

/// The instruction sets the hot loops are compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Width {
    /// The target's baseline (SSE2 on x86-64).
    Baseline = 1,
    /// AVX2, 4 lanes of f64.
    Avx2 = 2,
    /// AVX-512 (F, VL, DQ), 8 lanes of f64.
    Avx512 = 3,
}

impl Width {
    /// Every width, narrowest first.
    pub const ALL: [Width; 3] = [Width::Baseline, Width::Avx2, Width::Avx512];

    /// The width named `name` (`baseline`, `avx2`, `avx512`).
    pub fn parse(name: &str) -> Option<Width> {
        Self::ALL.into_iter().find(|w| w.name() == name)
    }

    /// Its name, as [`Self::parse`] reads it.
    pub fn name(self) -> &'static str {
        match self {
            Width::Baseline => "baseline",
            Width::Avx2 => "avx2",
            Width::Avx512 => "avx512",
        }
    }

    /// Whether this CPU can run it.
    pub fn supported(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            match self {
                Width::Baseline => true,
                Width::Avx2 => std::arch::is_x86_feature_detected!("avx2"),
                Width::Avx512 => {
                    std::arch::is_x86_feature_detected!("avx512f")
                        && std::arch::is_x86_feature_detected!("avx512vl")
                        && std::arch::is_x86_feature_detected!("avx512dq")
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            self == Width::Baseline
        }
    }

    /// The width the loops run in unless told otherwise: AVX-512 on CPUs that run 512-bit vectors
    /// at full width (AMD family 1Ah, Zen 5, and later), else AVX2 where the CPU has it (Intel
    /// CPUs with AVX-512 lower their clock for it, so AVX2 is faster there), else the baseline
    /// (results/bench/performance.md has the figures).
    fn detected() -> Width {
        if Width::Avx512.supported() && full_width_avx512() {
            Width::Avx512
        } else if Width::Avx2.supported() {
            Width::Avx2
        } else {
            Width::Baseline
        }
    }
}

/// Whether the CPU is an AMD one of family 1Ah or later (Zen 5: 512-bit data paths).
fn full_width_avx512() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::__cpuid;
        let vendor = __cpuid(0);
        let amd = [vendor.ebx, vendor.edx, vendor.ecx] == [0x6874_7541, 0x6974_6e65, 0x444d_4163]; // "AuthenticAMD"
        let eax = __cpuid(1).eax;
        let family = ((eax >> 8) & 0xf) + if (eax >> 8) & 0xf == 0xf { (eax >> 20) & 0xff } else { 0 };
        amd && family >= 0x1a
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// The width in use (0: not yet decided).
static CHOSEN: AtomicU8 = AtomicU8::new(0);

/// The width the hot loops run in: the one set by [`use_width`], else the detected one.
#[inline]
pub fn width() -> Width {
    match CHOSEN.load(Ordering::Relaxed) {
        1 => Width::Baseline,
        2 => Width::Avx2,
        3 => Width::Avx512,
        _ => {
            let detected = Width::detected();
            CHOSEN.store(detected as u8, Ordering::Relaxed);
            detected
        }
    }
}

/// Runs the hot loops in `wanted`, or in the widest width below it that the CPU has (results are
/// the same bits in every width: this only changes the speed). Returns the width now in use.
pub fn use_width(wanted: Width) -> Width {
    let used = Width::ALL.into_iter().rev().find(|w| *w <= wanted && w.supported()).unwrap_or(Width::Baseline);
    CHOSEN.store(used as u8, Ordering::Relaxed);
    used
}

/// Runs `kernel` compiled for the width in use ([`width`]). Mark the closure `#[inline(always)]`:
/// only code inlined into a copy is compiled for its width.
#[inline(always)]
pub fn widest<R>(kernel: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    #[allow(unsafe_code)]
    match width() {
        // SAFETY: `width` names only widths the CPU supports.
        Width::Avx512 => return unsafe { avx512(kernel) },
        // SAFETY: as above.
        Width::Avx2 => return unsafe { avx2(kernel) },
        Width::Baseline => {}
    }
    kernel()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn avx2<R>(kernel: impl FnOnce() -> R) -> R {
    kernel()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq")]
fn avx512<R>(kernel: impl FnOnce() -> R) -> R {
    kernel()
}

/// `Σ_i (a_1[i] b_1[i] + … + a_K[i] b_K[i])` over columns of one length (`K ≥ 1`; each term's
/// products added in that order), added up in four interleaved partial sums, combined at the end.
/// A single running sum waits for each addition to finish before the next (some four cycles);
/// four independent ones fill a vector register and keep the adder busy. The columns are taken
/// four rows at a time as arrays, so the loop has no bounds checks and vectorises; the partial
/// sums are the same four whatever the vector width, so is the result.
#[inline(always)]
pub fn lane_dot<const K: usize>(a: [&[f64]; K], b: [&[f64]; K]) -> f64 {
    let n = a[0].len();
    let (a, b) = (a.map(|s| &s[..n]), b.map(|s| &s[..n]));
    let term = |i: usize| (1..K).fold(a[0][i] * b[0][i], |t, k| t + a[k][i] * b[k][i]);
    let (a4, b4) = (a.map(|s| s.as_chunks::<4>().0), b.map(|s| s.as_chunks::<4>().0));
    let whole = n / 4;
    let mut lanes = [0.0; 4];
    for c in 0..whole {
        for (lane, sum) in lanes.iter_mut().enumerate() {
            *sum += (1..K).fold(a4[0][c][lane] * b4[0][c][lane], |t, k| t + a4[k][c][lane] * b4[k][c][lane]);
        }
    }
    for i in 4 * whole..n {
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
    use super::{LargestSquare, lane_dot};

    #[test]
    fn lane_dot_adds_every_term_once_with_any_tail() {
        for n in 0..11 {
            // Powers of two: every partial sum is exact, so any order gives the exact total.
            let (a, b): (Vec<f64>, Vec<f64>) = (0..n).map(|i| (f64::from(1u32 << i), 3.0)).unzip();
            let c = vec![1.0; n];
            assert_eq!(lane_dot([&a], [&b]), 3.0 * f64::from((1u32 << n) - 1), "n = {n}");
            assert_eq!(lane_dot([&a, &c], [&b, &a]), 4.0 * f64::from((1u32 << n) - 1), "n = {n}");
        }
    }

    #[test]
    fn lane_dot_sums_each_term_in_its_lane_in_order() {
        // Lane sums that round: the result is that of adding term i to partial sum i mod 4, the
        // two products of each term first, then the lanes pairwise.
        let n = 23;
        let column = |seed: f64| (0..n).map(|i| (seed * (i as f64 + 1.0)).sin() * 1e3).collect::<Vec<f64>>();
        let (a0, b0, a1, b1) = (column(1.1), column(2.3), column(0.7), column(5.9));
        let mut lanes = [0.0; 4];
        for i in 0..n {
            lanes[i % 4] += a0[i] * b0[i] + a1[i] * b1[i];
        }
        let expected = (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
        assert_eq!(lane_dot([&a0, &a1], [&b0, &b1]).to_bits(), expected.to_bits());
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
