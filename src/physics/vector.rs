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
