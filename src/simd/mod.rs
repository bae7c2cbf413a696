//! Kernels on slices: every hand-vectorised loop of the crate, apart from the physics that
//! calls it.
//!
//! Each kernel has a scalar twin, the same multiply–adds in the same order written as plain
//! loops, and the tests compare the two (bit for bit where the kernel promises the same
//! rounding, to round-off where it does not). The vector versions exist only where the
//! compiler left a loop scalar; they are compiled for AVX2 + FMA (and AVX-512F for the band
//! right-hand side) and called only after the processor has been checked for those
//! features. The contract: a kernel's const parameter `FMA` is `true` only in code that
//! runs after [`has_fma`] returned true (the integrator's AVX2 build), and the 512-bit
//! kernel is called only after [`has_avx512`]; each `unsafe` call site states which.
//!
//! The kernels use `std::arch` intrinsics rather than a portable-SIMD layer (such as
//! `pulp`): their contract with the scalar twins is bit-for-bit equality, which fixes the
//! lane assignment and where each fused multiply–add falls, and that is stated most plainly
//! in the intrinsics themselves.
//!
//! A model or integrator change never needs to read this module: the integrator
//! ([`crate::solve::band_newmark`]) states what each kernel computes, in the physics'
//! terms, where it calls it.

// The kernels index several arrays with one row index on purpose: that is the form the
// vectoriser and the reader both follow.
#![allow(clippy::needless_range_loop)]

pub mod band;
pub mod lanes;
pub mod update;

pub use lanes::madd;

/// Whether the processor runs the AVX2 + FMA kernels.
pub fn has_fma() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    false
}

/// Whether the processor has AVX-512F.
pub fn has_avx512() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx512f")
    }
    #[cfg(not(target_arch = "x86_64"))]
    false
}

/// The builds this processor can run: the baseline, and the FMA build where it has one.
#[cfg(test)]
pub(crate) fn builds() -> Vec<bool> {
    let mut b = vec![false];
    if has_fma() {
        b.push(true);
    }
    b
}
