//! Compressed sparse rows for the assembled M, C and K.
//!
//! Assembly collects (row, col, value) triplets (duplicates summed), and the matrices are
//! `sprs` matrices for interchange (Matrix Market). `Csr` wraps one with the allocation-free
//! products the time-step loop needs.

use super::scalar::Scalar;
use super::skyline::Skyline;
use sprs::CsMat;

/// A square sparse matrix in CSR form.
#[derive(Clone, Debug)]
pub struct Csr {
    mat: CsMat<f64>,
}

impl Csr {
    /// Builds from (row, col, value) triplets; duplicates are summed.
    ///
    /// A counting sort by row and a small sort within each row: finite-element rows hold a
    /// handful of entries, so this is linear in the number of triplets, where a general
    /// triplet sort (what `sprs` does) is n·log n and dominated assembly of large meshes.
    pub fn from_triplets(n: usize, triplets: &[(usize, usize, f64)]) -> Self {
        let mut start = vec![0usize; n + 1];
        for &(i, _, _) in triplets {
            start[i + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut bucket = vec![(0usize, 0.0f64); triplets.len()];
        for &(i, j, v) in triplets {
            bucket[fill[i]] = (j, v);
            fill[i] += 1;
        }
        let mut indptr = Vec::with_capacity(n + 1);
        let mut indices = Vec::with_capacity(triplets.len());
        let mut data = Vec::with_capacity(triplets.len());
        indptr.push(0);
        for i in 0..n {
            // Most rows of an actuators-only system are empty: they cost one push.
            let row = &mut bucket[start[i]..start[i + 1]];
            if row.len() > 1 {
                row.sort_unstable_by_key(|&(j, _)| j);
            }
            for &(j, v) in row.iter() {
                if indices.len() > indptr[i] && *indices.last().unwrap() == j {
                    *data.last_mut().unwrap() += v;
                } else {
                    indices.push(j);
                    data.push(v);
                }
            }
            indptr.push(indices.len());
        }
        Csr { mat: CsMat::new((n, n), indptr, indices, data) }
    }

    /// Builds from rows already in compressed form: row i's column indices (ascending,
    /// distinct) and values at `indptr[i]..indptr[i + 1]`.
    pub fn from_sorted_rows(n: usize, indptr: Vec<usize>, indices: Vec<usize>, data: Vec<f64>) -> Self {
        Csr { mat: CsMat::new((n, n), indptr, indices, data) }
    }

    /// This matrix times `factor`.
    pub fn scaled(&self, factor: f64) -> Self {
        let n = self.dim();
        let trip: Vec<(usize, usize, f64)> = self.triplets().map(|(i, j, v)| (i, j, v * factor)).collect();
        Csr::from_triplets(n, &trip)
    }

    pub fn zeros(n: usize) -> Self {
        Csr { mat: CsMat::zero((n, n)).to_csr() }
    }

    pub fn dim(&self) -> usize {
        self.mat.rows()
    }

    pub fn nnz(&self) -> usize {
        self.mat.nnz()
    }

    pub fn as_sprs(&self) -> &CsMat<f64> {
        &self.mat
    }

    /// Entry (i, j), zero if not stored.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.mat.get(i, j).copied().unwrap_or(0.0)
    }

    /// Row i's stored columns (ascending) and values.
    pub fn row(&self, i: usize) -> (&[usize], &[f64]) {
        let ip: &[usize] = self.mat.indptr().into_raw_storage();
        let range = ip[i]..ip[i + 1];
        (&self.mat.indices()[range.clone()], &self.mat.data()[range])
    }

    /// Iterates the stored entries as (row, col, value).
    pub fn triplets(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        let ip: &[usize] = self.mat.indptr().into_raw_storage();
        let (idx, val) = (self.mat.indices(), self.mat.data());
        (0..self.dim()).flat_map(move |i| (ip[i]..ip[i + 1]).map(move |k| (i, idx[k], val[k])))
    }

    /// y = A·x (overwrites y). No allocation.
    #[inline]
    pub fn mul_vec<T: Scalar>(&self, x: &[T], y: &mut [T]) {
        let ip = self.mat.indptr();
        let ip = ip.raw_storage();
        let idx = self.mat.indices();
        let val = self.mat.data();
        for i in 0..self.dim() {
            let mut s = T::zero();
            for k in ip[i]..ip[i + 1] {
                s += x[idx[k]].times_real(val[k]);
            }
            y[i] = s;
        }
    }

    /// y += α·A·x. No allocation.
    #[inline]
    /// Y = A·X for the columns of X stored one after the other (column-major, `dim()`
    /// rows): each row of A read once for all of them, each column summed in the order
    /// [`Csr::mul_vec`] sums it (so bit for bit its product), the columns side by side.
    pub fn mul_columns(&self, x: &[f64], y: &mut [f64]) {
        let n = self.dim();
        assert!(x.len() == y.len() && (n == 0 || x.len() % n == 0));
        let Some(k) = x.len().checked_div(n).filter(|&k| k > 0) else { return };
        // X by rows, so that one entry of A scales a contiguous row of k values.
        let mut by_row = vec![0.0; n * k];
        for (c, xc) in x.chunks_exact(n).enumerate() {
            xc.iter().enumerate().for_each(|(j, &v)| by_row[j * k + c] = v);
        }
        let mut s = vec![0.0; k];
        for i in 0..n {
            let (cols, vals) = self.row(i);
            s.iter_mut().for_each(|v| *v = 0.0);
            for (&j, &v) in cols.iter().zip(vals) {
                s.iter_mut().zip(&by_row[j * k..(j + 1) * k]).for_each(|(acc, &xj)| *acc += v * xj);
            }
            s.iter().enumerate().for_each(|(c, &v)| y[c * n + i] = v);
        }
    }

    pub fn mul_vec_add<T: Scalar>(&self, alpha: T, x: &[T], y: &mut [T]) {
        let ip = self.mat.indptr();
        let ip = ip.raw_storage();
        let idx = self.mat.indices();
        let val = self.mat.data();
        for i in 0..self.dim() {
            let mut s = T::zero();
            for k in ip[i]..ip[i + 1] {
                s += x[idx[k]].times_real(val[k]);
            }
            y[i] += alpha * s;
        }
    }

    /// xᵀ·A·y, row by row without storing A·y. (Transient runs evaluate their stored
    /// energies through `power::energy::StoredEnergy` instead, whose flat lists avoid the branch
    /// miss per short row that this loop pays.)
    pub fn bilinear(&self, x: &[f64], y: &[f64]) -> f64 {
        let ip = self.mat.indptr();
        let ip = ip.raw_storage();
        let idx = self.mat.indices();
        let val = self.mat.data();
        let mut sum = 0.0;
        for (i, xi) in x.iter().enumerate().take(self.dim()) {
            let mut s = 0.0;
            for k in ip[i]..ip[i + 1] {
                s += val[k] * y[idx[k]];
            }
            sum += xi * s;
        }
        sum
    }

    /// Hermitian form x̄ᵀ·A·x of a complex vector (A real symmetric): real by symmetry.
    /// Row by row, without storing A·x: harmonic solves call it once per frequency.
    pub fn hermitian_form(&self, x: &[num_complex::Complex64]) -> f64 {
        let ip = self.mat.indptr();
        let ip = ip.raw_storage();
        let idx = self.mat.indices();
        let val = self.mat.data();
        let mut sum = -0.0;
        for (i, xi) in x.iter().enumerate().take(self.dim()) {
            let mut s = num_complex::Complex64::default();
            for k in ip[i]..ip[i + 1] {
                s += x[idx[k]] * val[k];
            }
            sum += (xi.conj() * s).re;
        }
        sum
    }

    /// Dense copy (row-major), for small problems and tests.
    pub fn to_dense(&self) -> Vec<f64> {
        let n = self.dim();
        let mut d = vec![0.0; n * n];
        for i in 0..n {
            let (idx, val) = self.row(i);
            idx.iter().zip(val).for_each(|(&j, &v)| d[i * n + j] += v);
        }
        d
    }

    /// Adds `scale·A` into a skyline matrix whose envelope covers A's pattern.
    pub fn add_into_skyline<T: Scalar>(&self, scale: T, s: &mut Skyline<T>) {
        for (i, j, v) in self.triplets() {
            if j <= i {
                s.add(i, j, scale * T::from_real(v));
            }
        }
    }

    /// Linear combination Σ cᵢ·Aᵢ of matrices of one dimension (terms with cᵢ = 0 left
    /// out, their pattern too; two terms otherwise as [`Csr::sum_of`]).
    pub fn combine(terms: &[(f64, &Csr)]) -> Csr {
        let n = terms.first().map_or(0, |t| t.1.dim());
        if let [(ca, a), (cb, b)] = terms {
            if *ca != 0.0 && *cb != 0.0 {
                return Csr::sum_of((*ca, a), (*cb, b));
            }
        }
        let mut trip = Vec::new();
        for (c, a) in terms {
            if *c != 0.0 {
                trip.extend(a.triplets().map(|(i, j, v)| (i, j, c * v)));
            }
        }
        Csr::from_triplets(n, &trip)
    }

    /// The skyline envelope (each row's first column) that holds the symmetric patterns
    /// of `matrices`, each n × n: every entry (i, j) and (j, i).
    pub fn envelope_of(n: usize, matrices: &[&Csr]) -> Vec<usize> {
        let mut first: Vec<usize> = (0..n).collect();
        matrices.iter().for_each(|a| a.widen_envelope(&mut first));
        first
    }

    /// Lowers each row's first column in `first` (initially the row itself) so that the
    /// envelope holds this matrix's pattern. A row's columns ascend, so its first is its
    /// lowest, and those above the diagonal follow the first one past it.
    fn widen_envelope(&self, first: &mut [usize]) {
        for i in 0..self.dim() {
            let columns = self.row(i).0;
            if let Some(&j) = columns.first() {
                first[i] = first[i].min(j);
            }
            for &j in &columns[columns.partition_point(|&j| j <= i)..] {
                first[j] = first[j].min(i);
            }
        }
    }

    /// a·A + b·B of matrices of one dimension, on the union of their patterns (an entry
    /// of one only is its own product; zero coefficients keep their pattern). Their rows
    /// merged in column order: the same entries and bits as the triplets of both summed.
    pub fn sum_of((ca, a): (f64, &Csr), (cb, b): (f64, &Csr)) -> Csr {
        let n = a.dim();
        assert_eq!(n, b.dim(), "a sum of matrices of one dimension");
        let mut indptr = Vec::with_capacity(n + 1);
        let mut indices = Vec::with_capacity(a.nnz().max(b.nnz()));
        let mut data = Vec::with_capacity(a.nnz().max(b.nnz()));
        indptr.push(0);
        for i in 0..n {
            let ((ja, va), (jb, vb)) = (a.row(i), b.row(i));
            let (mut p, mut q) = (0, 0);
            while p < ja.len() || q < jb.len() {
                let (col_a, col_b) =
                    (ja.get(p).copied().unwrap_or(usize::MAX), jb.get(q).copied().unwrap_or(usize::MAX));
                let col = col_a.min(col_b);
                let value = match (col_a == col, col_b == col) {
                    (true, true) => ca * va[p] + cb * vb[q],
                    (true, false) => ca * va[p],
                    _ => cb * vb[q],
                };
                p += usize::from(col_a == col);
                q += usize::from(col_b == col);
                indices.push(col);
                data.push(value);
            }
            indptr.push(indices.len());
        }
        Csr::from_sorted_rows(n, indptr, indices, data)
    }

    /// The matrix on the rows and columns `keep` only, renumbered 0..keep.len() in their order.
    pub fn restricted(&self, keep: &[usize]) -> Csr {
        let mut local = vec![usize::MAX; self.dim()];
        for (i, &r) in keep.iter().enumerate() {
            local[r] = i;
        }
        let t: Vec<_> = self
            .triplets()
            .filter(|t| local[t.0] != usize::MAX && local[t.1] != usize::MAX)
            .map(|(i, j, v)| (local[i], local[j], v))
            .collect();
        Csr::from_triplets(keep.len(), &t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// a·A + b·B by merged rows gives the entries and bits of both matrices' triplets
    /// summed: on patterns that overlap in part, with an empty row, and with a zero
    /// coefficient (whose pattern stays).
    #[test]
    fn sum_of_matches_the_summed_triplets() {
        let a = Csr::from_triplets(5, &[(0, 0, 1.5), (0, 2, -0.3), (2, 2, 0.7), (4, 1, 2.2), (4, 4, 0.1)]);
        let b = Csr::from_triplets(5, &[(0, 0, 0.3), (0, 1, 1.1), (2, 2, -0.9), (3, 3, 4.0), (4, 4, 0.2)]);
        for (ca, cb) in [(0.37, 1.9), (1.0, 0.0), (0.0, -2.5)] {
            let merged = Csr::sum_of((ca, &a), (cb, &b));
            let both: Vec<_> = a
                .triplets()
                .map(|(i, j, v)| (i, j, ca * v))
                .chain(b.triplets().map(|(i, j, v)| (i, j, cb * v)))
                .collect();
            let want = Csr::from_triplets(5, &both);
            let bits = |a: &Csr| a.triplets().map(|(i, j, v)| (i, j, v.to_bits())).collect::<Vec<_>>();
            assert_eq!(bits(&merged), bits(&want), "{ca}, {cb}");
        }
    }

    /// The envelope widened row by row is the one of every (i, j) pair, on a pattern that
    /// is not symmetric.
    #[test]
    fn widened_envelope_matches_the_pairs() {
        let a = Csr::from_triplets(6, &[(0, 4, 1.0), (1, 1, 1.0), (2, 0, 1.0), (3, 5, 1.0), (5, 2, 1.0), (4, 4, 1.0)]);
        let first = Csr::envelope_of(6, &[&a]);
        assert_eq!(first, Skyline::<f64>::envelope_of(6, a.triplets().map(|(i, j, _)| (i, j))));
        assert_eq!(first, [0, 1, 0, 3, 0, 2]);
    }

    /// xᵀ·A·y against the dense sum, on an unsymmetric pattern with a duplicate triplet and
    /// an empty row.
    #[test]
    fn bilinear_matches_the_dense_sum() {
        let trip = [(0, 0, 2.0), (0, 3, -1.5), (1, 2, 0.25), (3, 0, 4.0), (3, 3, 1.0), (3, 3, 0.5), (2, 1, -3.0)];
        let a = Csr::from_triplets(4, &trip);
        let x = [0.3, -1.2, 2.5, 0.7];
        let y = [1.1, 0.4, -0.9, 2.0];
        let mut want = 0.0;
        for &(i, j, v) in &trip {
            want += x[i] * v * y[j];
        }
        assert!((a.bilinear(&x, &y) - want).abs() < 1e-14 * 20.0, "{} vs {want}", a.bilinear(&x, &y));
    }

    /// A block of columns times A is each column's own product, bit for bit.
    #[test]
    fn columns_are_multiplied_as_single_vectors() {
        let trip = [(0, 0, 2.0), (0, 3, -1.5), (1, 2, 0.25), (3, 0, 4.0), (3, 3, 1.0), (2, 1, -3.0), (2, 2, 0.1)];
        let a = Csr::from_triplets(4, &trip);
        let x: Vec<f64> = (0..12).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut y = vec![f64::NAN; 12];
        a.mul_columns(&x, &mut y);
        for (xc, yc) in x.chunks_exact(4).zip(y.chunks_exact(4)) {
            let mut want = vec![0.0; 4];
            a.mul_vec(xc, &mut want);
            assert_eq!(yc, &want[..]);
        }
    }
}
