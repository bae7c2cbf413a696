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

/// [`dot`] of `a` with each of `bs`, the same bits: four of them at a time, each still
/// summed in order. One dot product is a chain of dependent additions; four independent
/// chains fill the time each addition waits for the last.
pub fn dots(a: &[f64], bs: &[&[f64]]) -> Vec<f64> {
    debug_assert!(bs.iter().all(|b| b.len() == a.len()), "dots of vectors of one length");
    let mut out = Vec::with_capacity(bs.len());
    let mut groups = bs.chunks_exact(4);
    for g in &mut groups {
        let (b0, b1, b2, b3) = (&g[0][..a.len()], &g[1][..a.len()], &g[2][..a.len()], &g[3][..a.len()]);
        let mut s = [-0.0f64; 4];
        for (i, x) in a.iter().enumerate() {
            s[0] += x * b0[i];
            s[1] += x * b1[i];
            s[2] += x * b2[i];
            s[3] += x * b3[i];
        }
        out.extend_from_slice(&s);
    }
    out.extend(groups.remainder().iter().map(|b| dot(a, b)));
    out
}

#[cfg(test)]
mod dot_tests {
    use super::*;

    /// Interleaving the chains changes no bit of any dot product.
    #[test]
    fn dots_are_the_dot_products_bit_for_bit() {
        let v = |seed: f64, n: usize| -> Vec<f64> {
            (0..n).map(|i| (seed * (i as f64 + 0.3)).sin() * 1e3f64.powf((i % 7) as f64 - 3.0)).collect()
        };
        let a = v(1.7, 1281);
        let bs: Vec<Vec<f64>> = (0..7).map(|k| v(0.3 + k as f64, 1281)).collect();
        let refs: Vec<&[f64]> = bs.iter().map(Vec::as_slice).collect();
        let got = dots(&a, &refs);
        assert_eq!(got.len(), 7);
        for (g, b) in got.iter().zip(&bs) {
            assert_eq!(g.to_bits(), dot(&a, b).to_bits());
        }
    }
}
