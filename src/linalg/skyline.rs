//! Symmetric matrices in profile (skyline) storage and their LDLᵀ factorisation.
//!
//! Why a profile solver: the beam's Hermite elements give a band of half-width 3, and each
//! actuator adds a few rows that reach back to the beam nodes its feet stand on. A profile
//! stores row *i* from its first non-zero column to the diagonal, and LDLᵀ creates no fill
//! outside that envelope, so factorisation and solves cost O(profile) — linear in the number
//! of beam DOFs — with no pivoting, no symbolic phase and no indirection in the inner loops.
//!
//! The same code factorises real SPD matrices (Newmark effective stiffness) and complex
//! symmetric ones (`K − ω²M + iωC`, which is symmetric but not Hermitian). Without pivoting
//! a complex symmetric LDLᵀ can meet a tiny pivot; we detect that and report it rather than
//! return garbage (damping keeps the pivots of physical problems away from zero).

use super::scalar::Scalar;
use crate::error::{Error, Result};

/// A symmetric matrix stored by rows of its lower triangle, each from `first[i]` to `i`.
#[derive(Clone, Debug)]
pub struct Skyline<T: Scalar> {
    /// First stored column of each row.
    first: Vec<usize>,
    /// Offset of row i's first stored entry in `values`; row i occupies
    /// `start[i] .. start[i] + (i - first[i] + 1)` and ends with the diagonal.
    start: Vec<usize>,
    values: Vec<T>,
}

impl<T: Scalar> Skyline<T> {
    /// An all-zero matrix with the given envelope (`first[i] <= i`).
    pub fn zeros(first: Vec<usize>) -> Self {
        let mut start = Vec::with_capacity(first.len() + 1);
        let mut off = 0;
        for (i, &f) in first.iter().enumerate() {
            debug_assert!(f <= i);
            start.push(off);
            off += i - f + 1;
        }
        start.push(off);
        Skyline { first, start, values: vec![T::zero(); off] }
    }

    /// The envelope that holds every (i, j) pair of the given symmetric pattern.
    pub fn envelope_of(n: usize, pairs: impl IntoIterator<Item = (usize, usize)>) -> Vec<usize> {
        let mut first: Vec<usize> = (0..n).collect();
        for (i, j) in pairs {
            let (r, c) = if i >= j { (i, j) } else { (j, i) };
            if c < first[r] {
                first[r] = c;
            }
        }
        first
    }

    pub fn dim(&self) -> usize {
        self.first.len()
    }

    /// Number of stored entries (the profile).
    pub fn profile(&self) -> usize {
        self.values.len()
    }

    pub fn first(&self) -> &[usize] {
        &self.first
    }

    #[inline]
    fn index(&self, i: usize, j: usize) -> Option<usize> {
        let (r, c) = if i >= j { (i, j) } else { (j, i) };
        if c < self.first[r] {
            None
        } else {
            Some(self.start[r] + (c - self.first[r]))
        }
    }

    /// Entry (i, j) (symmetric), zero outside the envelope.
    pub fn get(&self, i: usize, j: usize) -> T {
        self.index(i, j).map_or(T::zero(), |k| self.values[k])
    }

    /// Adds `v` to entry (i, j) (and so to (j, i)). Panics if outside the envelope: that is
    /// a programming error in assembly, not a user error.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: T) {
        let k = self.index(i, j).expect("skyline: entry outside the envelope");
        self.values[k] += v;
    }

    /// Sets every entry to zero, keeping the envelope (reuse between frequencies).
    pub fn clear(&mut self) {
        self.values.iter_mut().for_each(|v| *v = T::zero());
    }

    /// y = A·x.
    pub fn mul_vec(&self, x: &[T], y: &mut [T]) {
        let n = self.dim();
        y.iter_mut().for_each(|v| *v = T::zero());
        for i in 0..n {
            let f = self.first[i];
            let row = &self.values[self.start[i]..self.start[i + 1]];
            let (off, diag) = row.split_at(row.len() - 1);
            let mut acc = diag[0] * x[i];
            for (k, &a) in off.iter().enumerate() {
                let j = f + k;
                acc += a * x[j];
                y[j] += a * x[i];
            }
            y[i] += acc;
        }
    }

    /// The stored entries, row by row from `first[i]` to the diagonal.
    pub fn into_values(self) -> Vec<T> {
        self.values
    }

    /// Factorises A = L·D·Lᵀ in a copy of the storage. Fails on a zero, tiny or non-finite
    /// pivot, naming the row: that means a singular (e.g. unsupported) or ill-posed system.
    pub fn factorize(&self) -> Result<SkylineLdlt<T>> {
        let mut f = SkylineLdlt {
            first: self.first.clone(),
            start: self.start.clone(),
            values: self.values.clone(),
            diag: Vec::new(),
        };
        f.refactor_in_place()?;
        Ok(f)
    }
}

/// L (unit lower, in the envelope) and D of A = L·D·Lᵀ.
#[derive(Clone, Debug)]
pub struct SkylineLdlt<T: Scalar> {
    first: Vec<usize>,
    start: Vec<usize>,
    /// Strictly-lower entries are L; the diagonal slot holds D.
    values: Vec<T>,
    diag: Vec<T>,
}

impl<T: Scalar> SkylineLdlt<T> {
    fn refactor_in_place(&mut self) -> Result<()> {
        let n = self.first.len();
        self.diag.clear();
        self.diag.reserve(n);
        for i in 0..n {
            let fi = self.first[i];
            let si = self.start[i];
            let a_ii = self.values[si + i - fi];
            // Row i holds a_ij; turn it into g_ij = l_ij·d_j, column by column.
            for j in fi..i {
                let fj = self.first[j];
                let sj = self.start[j];
                let lo = fi.max(fj);
                let mut s = T::zero();
                for k in lo..j {
                    s += self.values[si + k - fi] * self.values[sj + k - fj];
                }
                self.values[si + j - fi] -= s;
            }
            // d_i = a_ii − Σ g_ij²/d_j, and l_ij = g_ij/d_j.
            let mut d = a_ii;
            for j in fi..i {
                let g = self.values[si + j - fi];
                let l = g / self.diag[j];
                d -= g * l;
                self.values[si + j - fi] = l;
            }
            let scale = a_ii.modulus().max(f64::MIN_POSITIVE);
            if !d.is_finite() || d.modulus() <= 1e-13 * scale {
                return Err(Error::Singular {
                    row: i,
                    detail: format!(
                        "LDLᵀ pivot {d:?} against the diagonal {a_ii:?}: the system is singular or nearly so"
                    ),
                });
            }
            self.values[si + i - fi] = d;
            self.diag.push(d);
        }
        Ok(())
    }

    pub fn dim(&self) -> usize {
        self.first.len()
    }

    /// The pivots D.
    pub fn pivots(&self) -> &[T] {
        &self.diag
    }

    /// The factor's storage: envelope `first`, row offsets `start` (n + 1 of them), the
    /// values (L strictly below the diagonal, D in the diagonal slot) and D.
    pub fn into_parts(self) -> (Vec<usize>, Vec<usize>, Vec<T>, Vec<T>) {
        (self.first, self.start, self.values, self.diag)
    }

    /// Solves A·x = b in place (`x` holds b on entry).
    pub fn solve_in_place(&self, x: &mut [T]) {
        let n = self.dim();
        assert_eq!(x.len(), n);
        // L·y = b (row-oriented: each row is contiguous).
        for i in 0..n {
            let fi = self.first[i];
            let row = &self.values[self.start[i]..self.start[i] + (i - fi)];
            let mut s = T::zero();
            for (k, &l) in row.iter().enumerate() {
                s += l * x[fi + k];
            }
            x[i] -= s;
        }
        for (xi, &d) in x[..n].iter_mut().zip(&self.diag[..n]) {
            *xi = *xi / d;
        }
        // Lᵀ·x = z (column-oriented sweep over the same rows).
        for i in (0..n).rev() {
            let fi = self.first[i];
            let xi = x[i];
            let row = &self.values[self.start[i]..self.start[i] + (i - fi)];
            for (k, &l) in row.iter().enumerate() {
                x[fi + k] -= l * xi;
            }
        }
    }

    /// Number of negative pivots of a real factorisation: by Sylvester's law of inertia the
    /// number of eigenvalues below the shift, used to count modes in a band.
    pub fn negative_pivots(&self) -> usize
    where
        T: Into<f64>,
    {
        self.diag.iter().filter(|&&d| d.into() < 0.0).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_complex::Complex64;

    /// Dense reference: solve by Gaussian elimination with partial pivoting.
    fn dense_solve(a: &[Vec<Complex64>], b: &[Complex64]) -> Vec<Complex64> {
        let n = b.len();
        let mut m: Vec<Vec<Complex64>> = a.to_vec();
        let mut x = b.to_vec();
        for c in 0..n {
            let p = (c..n).max_by(|&i, &j| m[i][c].norm().partial_cmp(&m[j][c].norm()).unwrap()).unwrap();
            m.swap(c, p);
            x.swap(c, p);
            for r in c + 1..n {
                let f = m[r][c] / m[c][c];
                let (upper, lower) = m.split_at_mut(r);
                for (mrk, &v) in lower[0][c..n].iter_mut().zip(&upper[c][c..n]) {
                    *mrk -= f * v;
                }
                let v = x[c];
                x[r] -= f * v;
            }
        }
        for c in (0..n).rev() {
            let mut s = x[c];
            for k in c + 1..n {
                s -= m[c][k] * x[k];
            }
            x[c] = s / m[c][c];
        }
        x
    }

    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64) / ((1u64 << 53) as f64) - 0.5
    }

    #[test]
    // Both triangles of `dense` are filled from one (i, j) loop.
    #[allow(clippy::needless_range_loop)]
    fn complex_symmetric_solve_matches_dense_elimination() {
        let n: usize = 30;
        let mut seed = 7;
        // A ragged envelope with a few long rows, like actuator rows.
        let first: Vec<usize> =
            (0..n).map(|i| if i % 7 == 6 { i.saturating_sub(12) } else { i.saturating_sub(3) }).collect();
        let mut a = Skyline::<Complex64>::zeros(first.clone());
        let mut dense = vec![vec![Complex64::default(); n]; n];
        for i in 0..n {
            for j in first[i]..=i {
                let mut v = Complex64::new(lcg(&mut seed), lcg(&mut seed));
                if i == j {
                    v += Complex64::new(8.0, 1.0);
                }
                a.add(i, j, v);
                dense[i][j] = v;
                dense[j][i] = v;
            }
        }
        let b: Vec<Complex64> = (0..n).map(|_| Complex64::new(lcg(&mut seed), lcg(&mut seed))).collect();
        let xref = dense_solve(&dense, &b);
        let f = a.factorize().unwrap();
        let mut x = b.clone();
        f.solve_in_place(&mut x);
        for i in 0..n {
            assert!((x[i] - xref[i]).norm() < 1e-12 * xref[i].norm().max(1.0), "row {i}");
        }
        // And A·x reproduces b through the skyline product.
        let mut ax = vec![Complex64::default(); n];
        a.mul_vec(&x, &mut ax);
        for i in 0..n {
            assert!((ax[i] - b[i]).norm() < 1e-12);
        }
    }

    #[test]
    fn singular_matrix_is_reported_not_solved() {
        let mut a = Skyline::<f64>::zeros(vec![0, 0]);
        a.add(0, 0, 1.0);
        a.add(1, 0, 1.0);
        a.add(1, 1, 1.0);
        let err = a.factorize().unwrap_err().to_string();
        assert!(err.contains("singular"), "{err}");
    }

    #[test]
    fn inertia_counts_negative_eigenvalues() {
        // diag(1, 2, 3) − 2.5·I has two negative eigenvalues.
        let mut a = Skyline::<f64>::zeros(vec![0, 0, 1]);
        for (i, v) in [1.0, 2.0, 3.0].iter().enumerate() {
            a.add(i, i, v - 2.5);
        }
        assert_eq!(a.factorize().unwrap().negative_pivots(), 2);
    }
}
