//! The step of a small dense system (a modal-reduced model) as dense products.

use crate::linalg::{Csr, SkylineLdlt};
use crate::simd::lanes::gemv;
use crate::simd::madd;
use crate::simd::update::{fill_history, update_row, StepCoeffs};

/// Systems at most this large whose band covers half the matrix are stepped densely.
pub(super) const DENSE_LIMIT: usize = 48;

/// The step of a small dense system as Δu = x = K_eff⁻¹·F + (K_eff⁻¹M)·w₁ + (K_eff⁻¹C)·w₂ −
/// (K_eff⁻¹K)·u, each operator from solves with the factor. A modal-reduced model is
/// dense by construction, and for it independent multiply–adds beat two triangular sweeps
/// whose every row waits on the previous one. The operators are stored side by side by
/// rows, [K_eff⁻¹M | K_eff⁻¹C | K_eff⁻¹K], each row padded to a multiple of four, so that
/// row i of x is one dot product with w = [w₁ | w₂ | −u] over lanes of four and the n
/// rows are independent of each other.
#[derive(Clone, Debug)]
pub(super) struct DenseStep {
    n: usize,
    /// C by rows (padded like `ops`), for the dissipation.
    c: Vec<f64>,
    /// Padded length of a row of `c` (n rounded up to four).
    c_stride: usize,
    /// [K_eff⁻¹M | K_eff⁻¹C | K_eff⁻¹K] by rows, `stride` numbers per row.
    ops: Vec<f64>,
    stride: usize,
    /// w = [w₁ | w₂ | −u] of the step in progress, zero-padded to `stride`.
    w: Vec<f64>,
    /// K_eff⁻¹ column-major, for loads given as sparse pairs.
    a: Vec<f64>,
}

/// The loads of a dense step: registered patterns already solved (K_eff⁻¹·b_a) with their
/// weights, if the step is weighted, and a dense load vector nonzero only at `touched`
/// (consumed: those entries are zeroed).
pub(super) struct DenseLoads<'a> {
    pub(super) solved: Option<(&'a [Vec<f64>], &'a [f64])>,
    pub(super) touched: &'a [usize],
    pub(super) load: &'a mut [f64],
}

impl DenseStep {
    /// The operators of M, C, K (n rows) from the factor of K_eff.
    pub(super) fn new(m: &Csr, c: &Csr, k: &Csr, factor: &SkylineLdlt<f64>) -> Self {
        let n = m.dim();
        let column = |a: Option<&Csr>, j: usize| {
            let mut x = vec![0.0; n];
            match a {
                Some(a) => (0..n).for_each(|i| x[i] = a.get(i, j)),
                None => x[j] = 1.0,
            }
            factor.solve_in_place(&mut x);
            x
        };
        let blocks = [m, c, k];
        let stride = (blocks.len() * n).next_multiple_of(4);
        let rows = n.next_multiple_of(4);
        let mut ops = vec![0.0; rows * stride];
        for (q, a) in blocks.iter().enumerate() {
            for j in 0..n {
                for (i, x) in column(Some(a), j).into_iter().enumerate() {
                    ops[i * stride + q * n + j] = x;
                }
            }
        }
        let c_stride = n.next_multiple_of(4);
        let mut cr = vec![0.0; rows * c_stride];
        for i in 0..n {
            for j in 0..n {
                cr[i * c_stride + j] = c.get(i, j);
            }
        }
        DenseStep {
            n,
            c: cr,
            c_stride,
            ops,
            stride,
            w: vec![0.0; stride],
            a: (0..n).flat_map(|j| column(None, j)).collect(),
        }
    }

    /// K_eff⁻¹·b for a sparse load pattern b.
    pub(super) fn solve_pattern(&self, b: &[(usize, f64)]) -> Vec<f64> {
        let n = self.n;
        let mut x = vec![0.0; n];
        for &(d, c) in b {
            for i in 0..n {
                x[i] += self.a[d * n + i] * c;
            }
        }
        x
    }

    /// Δu = x = (K_eff⁻¹M)·w₁ + (K_eff⁻¹C)·w₂ − (K_eff⁻¹K)·u + K_eff⁻¹·load, row by row;
    /// w₁, w₂ from u, v, a unless the last `update` left them (`w_ready`).
    #[inline(always)]
    pub(super) fn solve<const FMA: bool>(
        &mut self,
        k: StepCoeffs,
        w_ready: bool,
        [u, v, a]: [&[f64]; 3],
        x: &mut [f64],
        loads: DenseLoads,
    ) {
        let n = self.n;
        let (w1, rest) = self.w.split_at_mut(n);
        let (w2, rest) = rest.split_at_mut(n);
        if !w_ready {
            fill_history::<FMA>(k, u, v, a, w1, w2);
        }
        for j in 0..n {
            rest[j] = -u[j];
        }
        gemv::<FMA>(&self.ops, self.stride, &self.w, x);
        if let Some((solved, weights)) = loads.solved {
            for (xa, &wa) in solved.iter().zip(weights) {
                for i in 0..n {
                    x[i] = madd::<FMA>(xa[i], wa, x[i]);
                }
            }
        }
        for &d in loads.touched {
            let f = std::mem::take(&mut loads.load[d]);
            if f != 0.0 {
                let col = &self.a[d * n..(d + 1) * n];
                for i in 0..n {
                    x[i] = madd::<FMA>(col[i], f, x[i]);
                }
            }
        }
    }

    /// New u, v, a and v̄ (stored over x) from x, and the next step's w₁, w₂ straight into
    /// the step's w.
    #[inline(always)]
    pub(super) fn update<const FMA: bool>(&mut self, k: StepCoeffs, x: &mut [f64], [u, v, a]: [&mut [f64]; 3]) {
        let n = self.n;
        let (w1, rest) = self.w.split_at_mut(n);
        let w2 = &mut rest[..n];
        for i in 0..n {
            update_row::<FMA, true>(k, i, x[i], u, v, a, x, w1, w2);
        }
    }

    /// v̄ᵀ·C·v̄ with C by rows; `vb` is v̄ with zeros up to the padded row length, `cv` n
    /// numbers of work space.
    #[inline(always)]
    pub(super) fn dissipation<const FMA: bool>(&self, vb: &[f64], cv: &mut [f64]) -> f64 {
        let vb = &vb[..self.c_stride];
        gemv::<FMA>(&self.c, self.c_stride, vb, cv);
        vb.iter().zip(cv.iter()).map(|(v, c)| v * c).sum()
    }
}
