//! Read-outs gᵀ·(u, v, a) of the integrator's state, evaluated after every step.

use crate::simd::lanes::gemv3;
use crate::simd::madd;

/// Read-outs gᵀ·(u, v, a) of the state evaluated after every step, while the state is in
/// cache: the analyses' links, feet, drives and sensors. A row with many entries (every row
/// of a modal-reduced model) is kept dense and read over lanes; short rows stay pairs.
#[derive(Clone, Debug, Default)]
pub(super) struct Observations {
    /// Dense rows, `stride` (n rounded up to four) numbers each, zero rows up to a multiple
    /// of four, and the observation each belongs to.
    dense: Vec<f64>,
    stride: usize,
    dense_index: Vec<usize>,
    /// The dense rows' products with u, v and a.
    products: Vec<[f64; 3]>,
    /// Short rows as (observation, pairs).
    sparse: Vec<(usize, Vec<(usize, f64)>)>,
    /// (gᵀu, gᵀv, gᵀa) per observation.
    values: Vec<[f64; 3]>,
}

/// Rows with at least this many entries are read densely.
const DENSE_OBSERVATION: usize = 8;

impl Observations {
    /// Read-outs of a system of n DOFs: row r is gᵣ as sparse pairs (duplicates summed).
    pub(super) fn new(n: usize, rows: &[Vec<(usize, f64)>]) -> Self {
        let stride = n.next_multiple_of(4);
        let mut o = Observations { values: vec![[0.0; 3]; rows.len()], stride, ..Default::default() };
        for (r, g) in rows.iter().enumerate() {
            if g.len() >= DENSE_OBSERVATION {
                let mut row = vec![0.0; stride];
                for &(d, c) in g {
                    row[d] += c;
                }
                o.dense.extend(row);
                o.dense_index.push(r);
            } else {
                o.sparse.push((r, g.clone()));
            }
        }
        o.dense.resize(o.dense_index.len().next_multiple_of(4) * stride, 0.0);
        o.products = vec![[0.0; 3]; o.dense_index.len()];
        o
    }

    /// (gᵣᵀu, gᵣᵀv, gᵣᵀa) of each read-out.
    pub(super) fn values(&self) -> &[[f64; 3]] {
        &self.values
    }

    /// Evaluates every read-out at u, v, a (n numbers each, zero-padded up to a multiple of
    /// four, which the dense rows read).
    #[inline(always)]
    pub(super) fn observe<const FMA: bool>(&mut self, n: usize, [u, v, a]: [&[f64]; 3]) {
        if self.values.is_empty() {
            return;
        }
        if !self.dense_index.is_empty() {
            gemv3::<FMA>(&self.dense, self.stride, u, v, a, &mut self.products);
            for (&r, &p) in self.dense_index.iter().zip(&self.products) {
                self.values[r] = p;
            }
        }
        let (u, v, a) = (&u[..n], &v[..n], &a[..n]);
        for (r, g) in &self.sparse {
            let mut val = [0.0; 3];
            for &(d, c) in g {
                val = [madd::<FMA>(c, u[d], val[0]), madd::<FMA>(c, v[d], val[1]), madd::<FMA>(c, a[d], val[2])];
            }
            self.values[*r] = val;
        }
    }
}
