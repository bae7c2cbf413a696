//! Linear algebra kernels the solvers need and the general crates do not provide in the
//! form we want: a profile (skyline) LDLᵀ that is fast for the banded-with-a-few-long-rows
//! matrices a beam with actuators produces, for real and complex symmetric matrices alike.

pub mod scalar;
pub mod skyline;
pub mod sparse;

pub use scalar::Scalar;
pub use skyline::{Skyline, SkylineLdlt};
pub use sparse::Csr;

/// Σ aᵢ·bᵢ, summed in order (the Krylov and reduction bases' inner products).
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
