//! The two scalar fields the solvers run on: `f64` (transient, statics) and `Complex64`
//! (harmonic and periodic steady-state solves).

use num_complex::Complex64;
use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

/// A field element: what LDLᵀ and matrix–vector products need.
pub trait Scalar:
    Copy
    + Send
    + Sync
    + std::fmt::Debug
    + PartialEq
    + Default
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + 'static
{
    fn zero() -> Self;
    fn from_real(x: f64) -> Self;
    /// Modulus, used for pivot checks.
    fn modulus(self) -> f64;
    fn is_finite(self) -> bool;
    /// self·r for a real r: two products for a complex number where self·from_real(r)
    /// takes four (the same value; only the sign of a zero part can differ).
    #[inline]
    fn times_real(self, r: f64) -> Self {
        self * Self::from_real(r)
    }
}

impl Scalar for f64 {
    #[inline]
    fn zero() -> Self {
        0.0
    }
    #[inline]
    fn from_real(x: f64) -> Self {
        x
    }
    #[inline]
    fn modulus(self) -> f64 {
        self.abs()
    }
    #[inline]
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
}

impl Scalar for Complex64 {
    #[inline]
    fn zero() -> Self {
        Complex64::new(0.0, 0.0)
    }
    #[inline]
    fn from_real(x: f64) -> Self {
        Complex64::new(x, 0.0)
    }
    #[inline]
    fn modulus(self) -> f64 {
        self.norm()
    }
    #[inline]
    fn is_finite(self) -> bool {
        self.re.is_finite() && self.im.is_finite()
    }
    #[inline]
    fn times_real(self, r: f64) -> Self {
        Complex64::new(self.re * r, self.im * r)
    }
}
