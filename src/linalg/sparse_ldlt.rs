//! Sparse symmetric LDLᵀ of combinations Σ cᵢ·Aᵢ of assembled matrices (K − σM), for
//! models whose sparsity a profile cannot follow: 2-D meshes and imported FE models.
//!
//! Built on faer's sparse Cholesky: an approximate-minimum-degree ordering and the
//! symbolic factor (supernodal where that pays) are computed once for the union of the
//! matrices' patterns ([`SparsePattern`]); each shift is then a numeric factorisation on
//! that pattern ([`SparsePattern::factorize`]). The LDLᵀ has no pivoting, like the
//! profile solver: fine for K − σM with σ away from an eigenvalue (the pivots are then of
//! the order of the diagonal), and it gives D, whose negative entries count the
//! eigenvalues below σ (Sylvester's law of inertia). A zero, tiny or non-finite pivot —
//! a singular K at σ = 0, σ on an eigenvalue — is an error naming the DOF, never a
//! garbage solve. (faer's pivoted LBLᵀ pivots only inside supernodes, so it neither
//! guarantees stability nor gives the inertia as directly; it is not used.)

use super::sparse::Csr;
use crate::error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::{LdltError, LdltRegularization};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, supernodal::SupernodalLdltRef, LdltRef, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// A pivot below this fraction of its row's diagonal means a singular matrix (as in the
/// profile LDLᵀ).
const TINY_PIVOT: f64 = 1e-13;

/// The lower triangle of the union of the patterns of symmetric matrices, column by column,
/// with its fill-reducing ordering and symbolic factor.
#[derive(Debug)]
pub struct SparsePattern {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
}

/// Factor entries above which a factorisation shows progress (about 0.05 s of work).
const SHOWN_ABOVE: usize = 1_000_000;

impl SparsePattern {
    /// Orders and analyses the union of the patterns of `matrices` (symmetric, of one
    /// dimension; only the upper triangle of each row is read).
    pub fn analyse(matrices: &[&Csr]) -> Result<Self> {
        let n = matrices.first().map_or(0, |a| a.dim());
        if n == 0 || matrices.iter().any(|a| a.dim() != n) {
            return Err(Error::Numerical("sparse LDLᵀ needs square matrices of one non-zero dimension".into()));
        }
        // Row i's upper triangle of a symmetric matrix is column i of its lower triangle.
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        let mut column = Vec::new();
        for i in 0..n {
            column.clear();
            for a in matrices {
                column.extend(a.row(i).0.iter().copied().filter(|&j| j >= i));
            }
            column.push(i);
            column.sort_unstable();
            column.dedup();
            row_idx.extend_from_slice(&column);
            col_ptr.push(row_idx.len());
        }
        let lower = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let symbolic = factorize_symbolic_cholesky(lower, Side::Lower, SymmetricOrdering::Amd, Default::default())
            .map_err(|e| Error::Numerical(format!("sparse LDLᵀ analysis failed: {e:?}")))?;
        Ok(SparsePattern { col_ptr, row_idx, symbolic })
    }

    pub fn dim(&self) -> usize {
        self.col_ptr.len() - 1
    }

    /// Stored entries of the factor L (and D) after fill.
    pub fn factor_entries(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Bytes a numeric factorisation holds at its peak: the factor's values, the matrix in
    /// the factor's order and faer's workspace (the pattern itself is already held).
    pub fn factor_bytes(&self) -> u64 {
        let values = std::mem::size_of::<f64>() * self.factor_entries();
        let scratch = self.numeric_scratch().size_bytes();
        (values + scratch + std::mem::size_of::<f64>() * self.row_idx.len()) as u64
    }

    fn numeric_scratch(&self) -> StackReq {
        self.symbolic.factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default())
    }

    /// Factorises Σ cᵢ·Aᵢ (each Aᵢ's pattern within the analysed one) as L·D·Lᵀ. Fails,
    /// naming the DOF, on a zero, tiny or non-finite pivot.
    pub fn factorize(&self, terms: &[(f64, &Csr)]) -> Result<SparseLdlt<'_>> {
        // A factorisation long enough to notice gets a bar (faer reports nothing inside
        // one, so it shows the factorisation begun and done, and lets Ctrl-C stop after it).
        let task = (self.factor_entries() > SHOWN_ABOVE).then(|| {
            let label = format!("LDLᵀ of {} DOFs, {} factor entries", self.dim(), self.factor_entries());
            crate::progress::Task::start(&label, Some(1), "factorisations")
        });
        let a = self.values(terms)?;
        let lower = SymbolicSparseColMatRef::new_checked(self.dim(), self.dim(), &self.col_ptr, None, &self.row_idx);
        let mut l = vec![0.0; self.factor_entries()];
        let mut buf = MemBuffer::try_new(self.numeric_scratch())
            .map_err(|_| Error::Numerical("out of memory for the sparse LDLᵀ workspace".into()))?;
        self.symbolic
            .factorize_numeric_ldlt(
                &mut l,
                SparseColMatRef::new(lower, &a),
                Side::Lower,
                LdltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut buf),
                Default::default(),
            )
            .map_err(|LdltError::ZeroPivot { index }| self.singular(self.zero_pivot(index), 0.0, &a))?;
        let pivots = self.pivots(&l);
        let mut smallest = f64::INFINITY;
        for (k, &d) in pivots.iter().enumerate() {
            let dof = self.original(k);
            let scale = self.diagonal(&a, dof).abs().max(f64::MIN_POSITIVE);
            if !d.is_finite() || d.abs() <= TINY_PIVOT * scale {
                return Err(self.singular(k, d, &a));
            }
            smallest = smallest.min(d.abs() / scale);
        }
        if let Some(t) = task {
            t.set(1)?;
        }
        let negative = pivots.iter().filter(|&&d| d < 0.0).count();
        Ok(SparseLdlt { pattern: self, negative, smallest, values: l })
    }

    /// The values of Σ cᵢ·Aᵢ on the analysed lower triangle.
    fn values(&self, terms: &[(f64, &Csr)]) -> Result<Vec<f64>> {
        let mut v = vec![0.0; self.row_idx.len()];
        for &(c, a) in terms {
            if a.dim() != self.dim() {
                return Err(Error::Numerical(format!("matrix of {} DOFs on a pattern of {}", a.dim(), self.dim())));
            }
            for i in 0..self.dim() {
                let (cols, vals) = a.row(i);
                let column = &self.row_idx[self.col_ptr[i]..self.col_ptr[i + 1]];
                for (&j, &x) in cols.iter().zip(vals).filter(|(&j, _)| j >= i) {
                    let p = column.binary_search(&j).map_err(|_| {
                        Error::Numerical(format!("entry ({i}, {j}) lies outside the analysed sparse pattern"))
                    })?;
                    v[self.col_ptr[i] + p] += c * x;
                }
            }
        }
        Ok(v)
    }

    /// The diagonal entry of DOF `dof` in `a` (values on this pattern; it is stored first).
    fn diagonal(&self, a: &[f64], dof: usize) -> f64 {
        a[self.col_ptr[dof]]
    }

    /// The elimination step of faer's zero-pivot index: one-based from the simplicial
    /// factor, zero-based from the supernodal one.
    fn zero_pivot(&self, index: usize) -> usize {
        let k = match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => index.saturating_sub(1),
            SymbolicCholeskyRaw::Supernodal(_) => index,
        };
        k.min(self.dim() - 1)
    }

    /// The DOF eliminated `k`-th.
    fn original(&self, k: usize) -> usize {
        self.symbolic.perm().map_or(k, |p| p.arrays().0[k])
    }

    /// D in elimination order: the first entry of each simplicial column, the diagonal of
    /// each supernode's leading block.
    fn pivots(&self, l: &[f64]) -> Vec<f64> {
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => s.col_ptr()[..self.dim()].iter().map(|&p| l[p]).collect(),
            SymbolicCholeskyRaw::Supernodal(s) => {
                let f = SupernodalLdltRef::new(s, l);
                let mut d = Vec::with_capacity(self.dim());
                for node in 0..s.n_supernodes() {
                    let block = f.supernode(node).val();
                    d.extend((0..block.ncols()).map(|c| block[(c, c)]));
                }
                d
            }
        }
    }

    fn singular(&self, k: usize, pivot: f64, a: &[f64]) -> Error {
        let dof = self.original(k);
        Error::Singular {
            row: dof,
            detail: format!(
                "sparse LDLᵀ pivot {pivot:e} against the diagonal {:e}: the system is singular or nearly so \
                 (an unsupported structure at zero shift, or a shift on an eigenvalue)",
                self.diagonal(a, dof)
            ),
        }
    }
}

/// L and D of one combination on a [`SparsePattern`].
#[derive(Debug)]
pub struct SparseLdlt<'p> {
    pattern: &'p SparsePattern,
    values: Vec<f64>,
    negative: usize,
    /// The smallest |pivot| over its row's diagonal entry.
    smallest: f64,
}

impl SparseLdlt<'_> {
    pub fn dim(&self) -> usize {
        self.pattern.dim()
    }

    /// Number of negative pivots: by Sylvester's law of inertia the number of eigenvalues of
    /// (K, M) below σ when this is K − σM (M positive definite), or of negative eigenvalues
    /// of the matrix itself.
    pub fn negative_pivots(&self) -> usize {
        self.negative
    }

    /// The smallest |pivot| relative to its row's diagonal entry: near round-off where the
    /// matrix is singular up to round-off (a free structure's K).
    pub fn smallest_pivot_ratio(&self) -> f64 {
        self.smallest
    }

    /// Bytes of the factor's values.
    pub fn bytes(&self) -> u64 {
        (std::mem::size_of::<f64>() * self.values.len()) as u64
    }

    /// Solves A·x = b in place (`x` holds b on entry).
    pub fn solve_in_place(&self, x: &mut [f64]) {
        solve_with(self.pattern, &self.values, x);
    }
}

/// A factor that owns its pattern, kept for many solves (a study's static shapes).
#[derive(Debug)]
pub struct OwnedLdlt {
    pattern: SparsePattern,
    values: Vec<f64>,
}

impl OwnedLdlt {
    /// Analyses and factors one symmetric matrix `a`.
    pub fn of(a: &Csr) -> Result<Self> {
        let pattern = SparsePattern::analyse(&[a])?;
        let values = pattern.factorize(&[(1.0, a)])?.values;
        Ok(OwnedLdlt { pattern, values })
    }

    pub fn dim(&self) -> usize {
        self.pattern.dim()
    }

    /// Solves A·x = b in place (`x` holds b on entry).
    pub fn solve_in_place(&self, x: &mut [f64]) {
        solve_with(&self.pattern, &self.values, x);
    }

    /// Solves A·X = B in place for the columns of B, stored one after the other in `x`
    /// (column-major, `dim()` rows): one pass over the factor for them all.
    pub fn solve_columns_in_place(&self, x: &mut [f64]) {
        solve_with(&self.pattern, &self.values, x);
    }
}

/// Solves with the factor `values` on `pattern`, in place, for the columns of `x`
/// (column-major, `pattern.dim()` rows).
fn solve_with(pattern: &SparsePattern, values: &[f64], x: &mut [f64]) {
    let n = pattern.dim();
    assert!(n > 0 && x.len() % n == 0);
    let columns = x.len() / n;
    let symbolic = &pattern.symbolic;
    let mut buf = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(columns, Par::Seq));
    let rhs = MatMut::from_column_major_slice_mut(x, n, columns);
    LdltRef::new(symbolic, values).solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(&mut buf));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inertia_counts_negative_diagonal_entries() {
        let d =
            Csr::from_triplets(4, &[(0, 0, 1.0), (1, 1, -2.0), (2, 2, 3.0), (3, 3, -0.5), (0, 3, 0.1), (3, 0, 0.1)]);
        let p = SparsePattern::analyse(&[&d]).unwrap();
        assert_eq!(p.factorize(&[(1.0, &d)]).unwrap().negative_pivots(), 2);
    }

    #[test]
    fn matrices_off_the_pattern_are_errors() {
        let a = Csr::from_triplets(3, &[(0, 0, 1.0), (1, 1, 1.0), (2, 2, 1.0)]);
        let b = Csr::from_triplets(3, &[(0, 2, 1.0), (2, 0, 1.0)]);
        assert!(SparsePattern::analyse(&[&a, &Csr::zeros(2)]).is_err());
        assert!(SparsePattern::analyse(&[]).is_err());
        let p = SparsePattern::analyse(&[&a]).unwrap();
        let err = p.factorize(&[(1.0, &b)]).unwrap_err().to_string();
        assert!(err.contains("outside the analysed sparse pattern"), "{err}");
    }

    #[test]
    fn singular_matrix_is_reported_not_solved() {
        let a = Csr::from_triplets(2, &[(0, 0, 1.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 1.0)]);
        let p = SparsePattern::analyse(&[&a]).unwrap();
        let err = p.factorize(&[(1.0, &a)]).unwrap_err().to_string();
        assert!(err.contains("singular"), "{err}");
    }
}
