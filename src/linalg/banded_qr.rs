//! A banded upper-triangular square-root factor R of K = GᵀG, from G's rows by Givens QR.
//!
//! Why not Cholesky of the assembled K: for a beam of n elements K's entries are ~EI/h³,
//! and a smooth mode's strain energy uᵀKu is a cancellation of them by a factor ~n⁴, so
//! the mere rounding of K's entries costs the lowest eigenvalue ~ε·n⁴ of relative accuracy
//! (28 % at 50,000 elements), whatever factorisation follows. G (one row per quadrature
//! point and per spring, K = GᵀG) holds entries ~√(EI·h)/h², and Gu cancels only by ~n²;
//! an orthogonal reduction of G has backward error ε on G's rows, so λ₁ keeps ~ε·n².
//!
//! Rows are folded in one at a time, in order of their first column: each is rotated
//! against R's rows from its first column on until it is zero (the rotated-away remainder
//! is Q's business, and Q is never kept). With that order every row of R so far ends at or
//! before column f + b when a row spanning f … f + b arrives, so the row touches only R's
//! rows f … f + b and fills nothing past column f + b: R keeps the rows' bandwidth b, and
//! the cost is O(rows·b²), linear in the number of DOFs. (Out of order, a row could drag
//! earlier rows' columns back into R's rows before them and leave the band.)

use crate::error::{Error, Result};

/// Upper-triangular R with R[i, j] = 0 unless i ≤ j ≤ i + b (b the bandwidth), stored by
/// rows, each as b + 1 values from the diagonal on. Its diagonal is kept non-negative, so
/// RᵀR = GᵀG makes R the Cholesky factor (transposed) of GᵀG.
#[derive(Clone, Debug)]
pub struct BandedR {
    n: usize,
    bandwidth: usize,
    /// Row i at `i·(b+1) .. (i+1)·(b+1)`; entry k of a row is R[i, i + k].
    values: Vec<f64>,
    /// Σ over the rows folded in of G[·, j]²: the diagonal of GᵀG, the scale a pivot
    /// R[j, j]² is judged against.
    gram_diagonal: Vec<f64>,
    /// 1/R[i, i], set by [`BandedR::check`] (the solves multiply: a division in the
    /// back-substitution's dependency chain costs more than the extra rounding is worth).
    inv_diag: Vec<f64>,
    /// First column of the last row folded in.
    last_first: usize,
}

impl BandedR {
    /// R = 0 for n columns and bandwidth b (G's rows may span at most b + 1 columns).
    pub fn new(n: usize, bandwidth: usize) -> Self {
        BandedR {
            n,
            bandwidth,
            values: vec![0.0; n * (bandwidth + 1)],
            gram_diagonal: vec![0.0; n],
            inv_diag: Vec::new(),
            last_first: 0,
        }
    }

    /// The factor of GᵀG for G's rows given as sparse (column, value) lists, in any order
    /// (they are folded in by first column; a stable sort, linear for rows that come
    /// nearly sorted as a beam's do). Bandwidth: the widest row's column span.
    pub fn from_rows<'a>(n: usize, rows: impl Iterator<Item = &'a [(usize, f64)]>) -> Self {
        let mut rows: Vec<(usize, &[(usize, f64)])> = rows.filter(|r| !r.is_empty()).map(|r| (span(r).0, r)).collect();
        rows.sort_by_key(|&(first, _)| first);
        let bandwidth = rows.iter().map(|&(first, r)| span(r).1 - first).max().unwrap_or(0);
        let mut f = BandedR::new(n, bandwidth);
        let mut window = vec![0.0; bandwidth + 1];
        for (first, row) in rows {
            window.iter_mut().for_each(|x| *x = 0.0);
            for &(j, v) in row {
                window[j - first] += v;
            }
            f.add_row(first, &mut window);
        }
        f
    }

    pub fn dim(&self) -> usize {
        self.n
    }

    pub fn bandwidth(&self) -> usize {
        self.bandwidth
    }

    /// R[i, j] (zero outside the band).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        if j < i || j > i + self.bandwidth {
            0.0
        } else {
            self.values[i * (self.bandwidth + 1) + (j - i)]
        }
    }

    /// Folds one row of G into R: `x[k]` is G's entry in column `first + k` (x has b + 1
    /// slots; it is left zero). Rows must come in non-decreasing order of `first` (see the
    /// module notes); panics otherwise, or if the row reaches past the last column.
    pub fn add_row(&mut self, first: usize, x: &mut [f64]) {
        let w = self.bandwidth + 1;
        assert_eq!(x.len(), w, "a row of G needs bandwidth + 1 slots");
        assert!(first >= self.last_first, "rows of G out of order: column {first} after {}", self.last_first);
        self.last_first = first;
        let last = x.iter().rposition(|&v| v != 0.0).map_or(first, |k| first + k);
        assert!(last < self.n, "row of G reaches column {last} of {}", self.n);
        // Rotations fill the row up to column first + b, never beyond (rows in order).
        let end = (first + self.bandwidth).min(self.n - 1);
        for (k, &v) in x.iter().enumerate() {
            if v != 0.0 {
                self.gram_diagonal[first + k] += v * v;
            }
        }
        self.inv_diag.clear();
        // x holds the remaining row over columns j … j + b.
        for j in first..=end {
            let xj = x[0];
            if xj != 0.0 {
                let row = &mut self.values[j * w..(j + 1) * w];
                let rjj = row[0];
                if rjj == 0.0 {
                    // Row j of R is still empty (diagonals only become zero that way): the
                    // remaining row becomes it, sign chosen to keep the diagonal positive.
                    let sign = xj.signum();
                    for (r, v) in row.iter_mut().zip(x.iter_mut()) {
                        *r = sign * *v;
                        *v = 0.0;
                    }
                    return;
                }
                // The rotation that zeroes x_j against R[j, j]. Entries are far from
                // overflow (|G| ≲ 10⁸ for any sensible beam), so no hypot.
                let r = (rjj * rjj + xj * xj).sqrt();
                let (c, s) = (rjj / r, xj / r);
                row[0] = r;
                for k in 1..w {
                    let (a, b) = (row[k], x[k]);
                    row[k] = c * a + s * b;
                    x[k] = c * b - s * a;
                }
            }
            // Slide the window one column right.
            x.copy_within(1.., 0);
            x[w - 1] = 0.0;
        }
        x.iter_mut().for_each(|v| *v = 0.0);
    }

    /// Checks that RᵀR is positive definite with the same test the profile LDLᵀ applies to
    /// its pivots (d_j = R[j, j]² against the diagonal (GᵀG)_jj, ratio 1e-13), and prepares
    /// the solves. Errors name the first failing column.
    pub fn check(&mut self) -> Result<()> {
        let w = self.bandwidth + 1;
        let mut inv = Vec::with_capacity(self.n);
        for j in 0..self.n {
            let d = self.values[j * w];
            let scale = self.gram_diagonal[j].max(f64::MIN_POSITIVE);
            if !d.is_finite() || d * d <= 1e-13 * scale {
                return Err(Error::Singular {
                    row: j,
                    detail: format!(
                        "square-root factor: pivot {d:e} against the column scale {:e}: the stiffness is singular \
                         or nearly so",
                        scale.sqrt()
                    ),
                });
            }
            inv.push(1.0 / d);
        }
        self.inv_diag = inv;
        Ok(())
    }

    /// Solves RᵀR·x = b in place (`x` holds b on entry): Rᵀy = b forward, R·x = y backward.
    /// Panics unless [`BandedR::check`] has passed since the last row was added.
    pub fn solve_normal_in_place(&self, x: &mut [f64]) {
        let n = self.n;
        let w = self.bandwidth + 1;
        assert_eq!(x.len(), n);
        assert_eq!(self.inv_diag.len(), n, "BandedR::check must pass before solving");
        // Rᵀ·y = b, by columns of Rᵀ (= rows of R, contiguous).
        for i in 0..n {
            let row = &self.values[i * w..(i + 1) * w];
            let yi = x[i] * self.inv_diag[i];
            x[i] = yi;
            let end = w.min(n - i);
            for k in 1..end {
                x[i + k] -= row[k] * yi;
            }
        }
        // R·x = y, by rows.
        for i in (0..n).rev() {
            let row = &self.values[i * w..(i + 1) * w];
            let end = w.min(n - i);
            let mut s = x[i];
            for k in 1..end {
                s -= row[k] * x[i + k];
            }
            x[i] = s * self.inv_diag[i];
        }
    }
}

/// First and last column of a sparse row.
fn span(row: &[(usize, f64)]) -> (usize, usize) {
    row.iter().fold((usize::MAX, 0), |(lo, hi), &(j, _)| (lo.min(j), hi.max(j)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic pseudo-random sequence in [−1, 1).
    fn rand(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    fn random_rows(n: usize, b: usize, count: usize, seed: &mut u64) -> Vec<Vec<(usize, f64)>> {
        let mut rows = Vec::new();
        for _ in 0..count {
            let first = ((rand(seed) + 1.0) * 0.5 * (n - b) as f64) as usize;
            let mut row = Vec::new();
            for j in first..=first + b {
                if rand(seed) > -0.6 {
                    // Magnitudes over two decades, as element and spring rows differ.
                    row.push((j, rand(seed) * 10f64.powf(rand(seed))));
                }
            }
            rows.push(row);
        }
        rows
    }

    #[test]
    fn rt_r_reproduces_the_gram_matrix_of_unordered_rows() {
        let mut seed = 7;
        let (n, b) = (23, 3);
        let mut rows = random_rows(n, b, 80, &mut seed);
        // Every column gets a diagonal row, so GᵀG is positive definite.
        rows.extend((0..n).map(|j| vec![(j, 0.5 + rand(&mut seed).abs())]));
        let mut r = BandedR::from_rows(n, rows.iter().map(|r| r.as_slice()));
        assert!(r.bandwidth() <= b);
        let mut gram = vec![0.0; n * n];
        for row in &rows {
            for &(i, a) in row {
                for &(j, c) in row {
                    gram[i * n + j] += a * c;
                }
            }
        }
        for i in 0..n {
            assert!(r.get(i, i) > 0.0);
            for j in 0..n {
                if j < i || j > i + r.bandwidth() {
                    assert_eq!(r.get(i, j), 0.0);
                }
                let rtr: f64 = (0..n).map(|k| r.get(k, i) * r.get(k, j)).sum();
                let scale = (gram[i * n + i] * gram[j * n + j]).sqrt();
                assert!((rtr - gram[i * n + j]).abs() < 1e-13 * scale, "({i},{j}): {rtr} vs {}", gram[i * n + j]);
            }
        }
        // The solve inverts RᵀR.
        r.check().unwrap();
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
        let mut y: Vec<f64> = (0..n).map(|i| (0..n).map(|j| gram[i * n + j] * x[j]).sum()).collect();
        r.solve_normal_in_place(&mut y);
        for (a, b) in x.iter().zip(&y) {
            assert!((a - b).abs() < 1e-10, "{a} vs {b}");
        }
    }

    #[test]
    fn a_rank_deficient_gram_matrix_is_reported() {
        // Differences of neighbours: the constant vector is in G's null space.
        let n = 12;
        let rows: Vec<Vec<(usize, f64)>> = (0..n - 1).map(|j| vec![(j, 1.0), (j + 1, -1.0)]).collect();
        let mut r = BandedR::from_rows(n, rows.iter().map(|r| r.as_slice()));
        let err = r.check().unwrap_err().to_string();
        assert!(err.contains("singular"), "{err}");
    }
}
