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
//! kernel is called only after [`has_avx512`]; each `unsafe` call site states which. Code
//! outside this module changes build only through [`dispatch`], which checks the processor.
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
pub mod complex_rows;
pub mod lanes;
pub mod twofold;
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

/// Work on `Self` with an argument `A`, compiled in two builds for [`dispatch`]: the baseline
/// (`FMA` false) and AVX2 + FMA.
pub trait Builds<A> {
    /// What the work returns.
    type Out;
    /// The work in build `FMA`. Implementations mark it `#[inline(always)]`, so that the
    /// whole work, kernels included, is compiled into [`dispatch`]'s AVX2 + FMA function.
    fn run<const FMA: bool>(&mut self, arg: A) -> Self::Out;
}

/// Runs the work of `on` in its AVX2 + FMA build where `fma` asks for it and the processor
/// has those features, else in its baseline build: the one place a whole integrator step
/// changes build, so that the caller needs no `unsafe`. `on` is passed on as the `&mut` it
/// is, so that the compiler still knows nothing else aliases it.
#[inline(always)]
pub fn dispatch<A, T: Builds<A>>(fma: bool, on: &mut T, arg: A) -> T::Out {
    #[cfg(target_arch = "x86_64")]
    if fma && has_fma() {
        // SAFETY: the processor reports AVX2 and FMA.
        return unsafe { run_fma(on, arg) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = fma;
    on.run::<false>(arg)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn run_fma<A, T: Builds<A>>(on: &mut T, arg: A) -> T::Out {
    on.run::<true>(arg)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain of multiply–adds whose rounding tells the builds apart.
    struct Chain;

    impl Builds<f64> for Chain {
        type Out = f64;
        #[inline(always)]
        fn run<const FMA: bool>(&mut self, x: f64) -> f64 {
            (0..64).fold(x, |acc, i| madd::<FMA>(acc, 1.0 + 1e-3 * i as f64, 1.0 / 3.0))
        }
    }

    /// `dispatch` runs the build it is asked for where the processor has it, and the baseline
    /// otherwise: the same bits as calling that build directly.
    #[test]
    fn dispatch_runs_the_build_asked_for() {
        let x = 0.1;
        assert_eq!(dispatch(false, &mut Chain, x).to_bits(), Chain.run::<false>(x).to_bits());
        let fma = if has_fma() { Chain.run::<true>(x) } else { Chain.run::<false>(x) };
        assert_eq!(dispatch(true, &mut Chain, x).to_bits(), fma.to_bits());
    }
}
