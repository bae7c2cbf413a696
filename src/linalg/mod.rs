//! Linear algebra kernels the solvers need and the general crates do not provide in the
//! form we want: a profile (skyline) LDLᵀ that is fast for the banded-with-a-few-long-rows
//! matrices a beam with actuators produces, for real and complex symmetric matrices alike;
//! and a banded square-root factor of the stiffness built from its element rows without
//! forming K (see [`banded_qr`]), for modes of very fine meshes; and a sparse LDLᵀ with a
//! fill-reducing ordering for 2-D meshes and imported models (see [`sparse_ldlt`]).

pub mod band;
pub mod banded_qr;
pub mod packed;
pub mod scalar;
pub mod skyline;
pub mod sparse;
pub mod sparse_ldlt;

pub use banded_qr::BandedR;
pub use packed::PackedRows;
pub use scalar::Scalar;
pub use skyline::{Skyline, SkylineLdlt};
pub use sparse::Csr;
pub use sparse_ldlt::{SparseLdlt, SparsePattern};

/// Replaces a square row-major `n × n` matrix by its symmetric part, (A + Aᵀ)/2.
pub fn symmetrise(a: &mut [f64], n: usize) {
    for i in 0..n {
        for j in 0..i {
            let s = 0.5 * (a[i * n + j] + a[j * n + i]);
            a[i * n + j] = s;
            a[j * n + i] = s;
        }
    }
}

/// Σ aᵢ·bᵢ, summed in order (the Krylov and reduction bases' inner products).
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
