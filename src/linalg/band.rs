//! Band storage of a symmetric system whose rows, all but a few, stay within a half-width
//! B of the diagonal (a beam's Hermite elements give B = 3; an actuator's body rows reach
//! back to its feet): the matrices by diagonals, the entries beyond the band in a short
//! side list, and an LDLᵀ factor by rows of width B with its few long rows kept apart.
//!
//! This is the storage the fast Newmark step ([`crate::solve::band_newmark`]) streams: a
//! row of the band is then contiguous data with no column indices.

use super::{Csr, SkylineLdlt};
use crate::simd::lanes::dot_lanes_cold;

/// An entry of M, C, K outside the band (lower triangle, i > j); applied symmetrically.
#[derive(Clone, Copy, Debug)]
pub struct Extra {
    pub i: usize,
    pub j: usize,
    pub m: f64,
    pub c: f64,
    pub k: f64,
}

/// M, C and K of n rows by diagonals: diagonal t ∈ 0..=B of M at `m[t·(n + B) + i]` =
/// M(i, i − t) (zero where i < t and for the B padding entries past n); the upper half is
/// the same numbers. Entries further out are in `extra`.
#[derive(Clone, Debug)]
pub struct BandMatrices {
    pub m: Vec<f64>,
    pub c: Vec<f64>,
    pub k: Vec<f64>,
    /// Sorted by (i, j).
    pub extra: Vec<Extra>,
}

impl BandMatrices {
    /// The band storage of half-width `b` of M, C, K (n rows each).
    pub fn new(m: &Csr, c: &Csr, k: &Csr, b: usize) -> Self {
        let n = m.dim();
        let mut extra: Vec<Extra> = Vec::new();
        let mut diagonals = |a: &Csr, which: usize| {
            let mut out = vec![0.0; (b + 1) * (n + b)];
            for (i, j, v) in a.triplets() {
                if j <= i && i - j <= b {
                    out[(i - j) * (n + b) + i] = v;
                } else if i > j + b {
                    let e = match extra.iter().position(|e| e.i == i && e.j == j) {
                        Some(p) => &mut extra[p],
                        None => {
                            extra.push(Extra { i, j, m: 0.0, c: 0.0, k: 0.0 });
                            extra.last_mut().expect("just pushed")
                        }
                    };
                    *[&mut e.m, &mut e.c, &mut e.k][which] = v;
                }
            }
            out
        };
        let (m, c, k) = (diagonals(m, 0), diagonals(c, 1), diagonals(k, 2));
        extra.sort_by_key(|e| (e.i, e.j));
        BandMatrices { m, c, k, extra }
    }
}

/// A row of the factor that reaches back beyond the band: its columns `first..row − B`
/// are `tail[offset..]`.
#[derive(Clone, Copy, Debug)]
pub struct LongRow {
    pub row: usize,
    pub first: usize,
    pub offset: usize,
}

impl LongRow {
    /// Its entries in the columns `first..row − B`, from the side list `l_tail`.
    #[inline(always)]
    pub fn tail<'a>(&self, l_tail: &'a [f64], b: usize) -> &'a [f64] {
        &l_tail[self.offset..self.offset + (self.row - b - self.first)]
    }

    /// Σ_j L(row, j)·y_j over those columns, for the forward sweep (`y` padded by B in
    /// front), in four partial sums: one running sum would make the row a chain of dependent
    /// multiply–adds (a frame's leg-to-body rows span ≈ 45 columns). Out of line: it runs
    /// for a handful of rows a step, from every row of every sweep.
    #[inline(always)]
    pub fn dot<const FMA: bool>(&self, l_tail: &[f64], b: usize, y: &[f64]) -> f64 {
        let tail = self.tail(l_tail, b);
        dot_lanes_cold::<FMA>(tail, &y[self.first + b..self.first + b + tail.len()])
    }

    /// x_j −= L(row, j)·x_row over those columns, for the backward sweep as soon as x_row
    /// is known (`x` unpadded). No fused multiply–add here, so one build serves both.
    #[cold]
    #[inline(never)]
    pub fn scatter(&self, l_tail: &[f64], b: usize, x: &mut [f64], x_row: f64) {
        for (t, &lv) in self.tail(l_tail, b).iter().enumerate() {
            x[self.first + t] -= lv * x_row;
        }
    }
}

/// An LDLᵀ factor by rows of width B: row i of L at `l[i·B + s]` = L(i, i − B + s) (zero
/// before column 0; B zero rows follow the last, so the backward sweep's gathers need no
/// bounds), the entries of long rows beyond the band in `l_tail`, and 1/D.
#[derive(Clone, Debug)]
pub struct BandFactor {
    pub n: usize,
    pub b: usize,
    pub l: Vec<f64>,
    pub long: Vec<LongRow>,
    pub l_tail: Vec<f64>,
    pub d_inv: Vec<f64>,
}

impl BandFactor {
    /// The band form of a profile factor, with the half-width that covers nine rows in
    /// ten (the rest become long rows).
    pub fn new(factor: SkylineLdlt<f64>) -> Self {
        let (first, start, lv, d) = factor.into_parts();
        let n = d.len();
        let mut widths: Vec<usize> = first.iter().enumerate().map(|(i, &f)| i - f).collect();
        widths.sort_unstable();
        let b = widths.get((n * 9) / 10).copied().unwrap_or(0);
        let mut l = vec![0.0; (n + b) * b];
        let mut long = Vec::new();
        let mut l_tail = Vec::new();
        for i in 0..n {
            let row = &lv[start[i]..start[i + 1] - 1];
            for (t, &val) in row.iter().enumerate() {
                let j = first[i] + t;
                if j + b >= i {
                    l[i * b + (j + b - i)] = val;
                } else {
                    if long.last().map(|lr: &LongRow| lr.row) != Some(i) {
                        long.push(LongRow { row: i, first: j, offset: l_tail.len() });
                    }
                    l_tail.push(val);
                }
            }
        }
        let d_inv = d.iter().map(|x| 1.0 / x).collect();
        BandFactor { n, b, l, long, l_tail, d_inv }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::Skyline;

    /// A band matrix with one long row: the factor's band rows, long row and 1/D rebuild
    /// L·D·Lᵀ = A, and the matrices' diagonals and side list rebuild A.
    #[test]
    fn band_storage_rebuilds_the_matrix() {
        let n = 12;
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 10.0 + i as f64));
            for s in 1..=2 {
                if i >= s {
                    t.push((i, i - s, 1.0 / (s as f64 + i as f64)));
                    t.push((i - s, i, 1.0 / (s as f64 + i as f64)));
                }
            }
        }
        t.push((11, 3, 0.25));
        t.push((3, 11, 0.25));
        let a = Csr::from_triplets(n, &t);
        let mut envelope: Vec<usize> = (0..n).map(|i| i.saturating_sub(2)).collect();
        envelope[11] = 3;
        let mut sky = Skyline::<f64>::zeros(envelope);
        a.add_into_skyline(1.0, &mut sky);
        let f = BandFactor::new(sky.factorize().unwrap());
        assert_eq!((f.b, f.long.len()), (2, 1));
        let entry = |i: usize, j: usize| -> f64 {
            if i == j {
                1.0
            } else if j + f.b >= i && j < i {
                f.l[i * f.b + (j + f.b - i)]
            } else if let Some(lr) = f.long.iter().find(|lr| lr.row == i && j >= lr.first && j + f.b < i) {
                lr.tail(&f.l_tail, f.b)[j - lr.first]
            } else {
                0.0
            }
        };
        for i in 0..n {
            for j in 0..=i {
                let ldl: f64 = (0..=j).map(|q| entry(i, q) * entry(j, q) / f.d_inv[q]).sum();
                assert!((ldl - a.get(i, j)).abs() < 1e-12, "({i}, {j}): {ldl} vs {}", a.get(i, j));
            }
        }
        let band = BandMatrices::new(&a, &a, &a, f.b);
        assert_eq!(band.extra.len(), 1);
        for i in 0..n {
            for j in 0..=i {
                let got = if i - j <= f.b {
                    band.k[(i - j) * (n + f.b) + i]
                } else {
                    band.extra.iter().find(|e| e.i == i && e.j == j).map_or(0.0, |e| e.k)
                };
                assert_eq!(got, a.get(i, j), "({i}, {j})");
            }
        }
    }
}
