//! A sparse matrix as fixed-width rows, for products streamed many times.
//!
//! A refinement applies the same mass matrices in every residual and every GMRES
//! iteration. Walked as compressed rows, a finite-element row's few entries cost a loop of
//! unknown length, a bounds check per entry and 16 bytes per entry of index and value.
//! Here each non-empty row keeps its first [`WIDTH`] entries in a fixed-size array (u32
//! columns, zero-padded), so the product's inner loop is unrolled; entries beyond the
//! width (a row that couples many DOFs) follow in a list of their own. The sums run in the
//! compressed rows' order, so the products are those of [`Csr::mul_vec_add`] bit for bit
//! (a padded entry adds x·0, which changes no sum of finite terms).

use super::scalar::Scalar;
use super::sparse::Csr;

/// Entries kept in each row's fixed part: a beam's consistent mass couples a node's two
/// DOFs with its neighbours', six a row.
pub const WIDTH: usize = 6;

/// One non-empty row: its index, its first [`WIDTH`] entries, and how many more follow
/// in [`PackedRows::more`].
#[derive(Clone, Debug)]
struct Row {
    index: u32,
    columns: [u32; WIDTH],
    values: [f64; WIDTH],
    more: u32,
}

/// A square sparse matrix's non-empty rows, packed.
#[derive(Clone, Debug)]
pub struct PackedRows {
    rows: Vec<Row>,
    /// The entries beyond [`WIDTH`] of each row that has them, row after row.
    more: Vec<(u32, f64)>,
}

impl PackedRows {
    /// The rows of `a` (whose dimension must fit a u32).
    pub fn of(a: &Csr) -> Self {
        let mut rows = Vec::new();
        let mut more = Vec::new();
        for i in 0..a.dim() {
            let (cols, vals) = a.row(i);
            if cols.is_empty() {
                continue;
            }
            let mut row = Row { index: i as u32, columns: [0; WIDTH], values: [0.0; WIDTH], more: 0 };
            for (e, (&j, &v)) in cols.iter().zip(vals).enumerate() {
                if e < WIDTH {
                    (row.columns[e], row.values[e]) = (j as u32, v);
                } else {
                    more.push((j as u32, v));
                    row.more += 1;
                }
            }
            rows.push(row);
        }
        PackedRows { rows, more }
    }

    /// y += α·A·x, as [`Csr::mul_vec_add`]. No allocation.
    pub fn mul_vec_add<T: Scalar>(&self, alpha: T, x: &[T], y: &mut [T]) {
        let mut next = 0;
        for row in &self.rows {
            let mut s = T::zero();
            for e in 0..WIDTH {
                s += x[row.columns[e] as usize].times_real(row.values[e]);
            }
            if row.more > 0 {
                let end = next + row.more as usize;
                for &(j, v) in &self.more[next..end] {
                    s += x[j as usize].times_real(v);
                }
                next = end;
            }
            y[row.index as usize] += alpha * s;
        }
    }

    /// Whether the matrix has no stored entry.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_complex::Complex64;

    /// The packed product gives the compressed rows' bits, for short, empty and long rows.
    #[test]
    fn gives_the_bits_of_the_compressed_rows() {
        let n = 40;
        let mut trip = Vec::new();
        for i in 0..n {
            if i % 7 == 3 {
                continue;
            }
            let width = if i == 11 { 25 } else { 1 + i % 6 };
            for k in 0..width {
                let j = (i + 3 * k) % n;
                trip.push((i, j, ((i * 31 + j * 17) as f64).sin() * 1e3 + 0.1));
            }
        }
        let a = Csr::from_triplets(n, &trip);
        let packed = PackedRows::of(&a);
        let x: Vec<Complex64> =
            (0..n).map(|i| Complex64::new((i as f64 * 0.7).cos(), (i as f64 * 1.3).sin())).collect();
        let alpha = Complex64::new(-3.7e4, 12.5);
        let (mut y1, mut y2): (Vec<Complex64>, Vec<Complex64>) =
            (0..n).map(|i| (Complex64::new(i as f64, 1.0), Complex64::new(i as f64, 1.0))).unzip();
        a.mul_vec_add(alpha, &x, &mut y1);
        packed.mul_vec_add(alpha, &x, &mut y2);
        assert_eq!(y1, y2);
        assert!(!packed.is_empty());
    }
}
