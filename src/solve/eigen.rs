//! Undamped natural modes: K·φ = ω²·M·φ.
//!
//! faer has no generalised symmetric eigensolver, so we reduce the problem with a
//! Cholesky factor to a standard symmetric one (see `modes` for which factor and why). Dense, so meant for models up to a few
//! thousand DOFs; that covers every beam mesh a power-flow study needs.

use crate::error::{Error, Result};
use crate::linalg::{BandedR, Csr};
use faer::linalg::triangular_solve::{solve_lower_triangular_in_place, solve_upper_triangular_in_place};
use faer::{Mat, MatRef, Par, Side};

/// Natural modes of a system over a subset of its DOFs.
#[derive(Clone, Debug)]
pub struct Modes {
    /// Circular natural frequencies ω_r (rad/s), ascending.
    pub omega: Vec<f64>,
    /// Mode shapes, column r over the selected DOFs (mass-normalised).
    pub shapes: Mat<f64>,
    /// The global DOF index of each row of `shapes`.
    pub dofs: Vec<usize>,
    /// Whether K entered through its square-root factor from the element rows (relative
    /// round-off in ω_r ~ε·ω_max/ω_r) rather than as assembled (~ε·(ω_max/ω_r)²); see
    /// `analysis::modes::ModesResult::roundoff_bound`.
    pub from_root: bool,
}

impl Modes {
    pub fn count(&self) -> usize {
        self.omega.len()
    }

    /// Natural frequencies in Hz.
    pub fn frequencies_hz(&self) -> Vec<f64> {
        self.omega.iter().map(|w| w / (2.0 * std::f64::consts::PI)).collect()
    }

    /// Mode r over the whole system's DOFs (zero outside the selected DOFs).
    pub fn shape_global(&self, r: usize, n: usize) -> Vec<f64> {
        let mut v = vec![0.0; n];
        for (row, &d) in self.dofs.iter().enumerate() {
            v[d] = self.shapes[(row, r)];
        }
        v
    }
}

/// The lowest `count` modes of (K, M) restricted to `dofs` (all if `count` exceeds them).
pub fn modes(k: &Csr, m: &Csr, dofs: &[usize], count: usize) -> Result<Modes> {
    let n = dofs.len();
    if n == 0 {
        return Err(Error::Numerical("modal analysis of a system with no free DOFs".into()));
    }
    let mut pos = vec![usize::MAX; k.dim()];
    for (r, &d) in dofs.iter().enumerate() {
        pos[d] = r;
    }
    let mut kd = Mat::<f64>::zeros(n, n);
    let mut md = Mat::<f64>::zeros(n, n);
    for (i, j, v) in k.triplets() {
        if pos[i] != usize::MAX && pos[j] != usize::MAX {
            kd[(pos[i], pos[j])] += v;
        }
    }
    for (i, j, v) in m.triplets() {
        if pos[i] != usize::MAX && pos[j] != usize::MAX {
            md[(pos[i], pos[j])] += v;
        }
    }
    // Invert the problem, M·x = μ·K·x with μ = 1/λ, so that the lowest modes are the
    // *largest* eigenvalues of B = L⁻¹·M·L⁻ᵀ (K = L·Lᵀ) and come out with full relative
    // accuracy. Reducing with M's factor instead computes them to ε·λ_max absolute, and
    // λ_max of a fine mesh (rotations carry little mass) is 10⁹ times λ₁: that costs five
    // digits at 200 elements. A free structure has a singular K; shift it by σ·M then.
    let mut shift = 0.0;
    let llt = match kd.llt(Side::Lower).ok().filter(|f| !rigid_pivot(f.L(), &kd)) {
        Some(f) => f,
        None => {
            let tk: f64 = (0..n).map(|i| kd[(i, i)]).sum();
            let tm: f64 = (0..n).map(|i| md[(i, i)]).sum();
            shift = super::lanczos::free_shift_size(tk, tm);
            let shifted = Mat::from_fn(n, n, |i, j| kd[(i, j)] + shift * md[(i, j)]);
            shifted.llt(Side::Lower).map_err(|_| {
                Error::Numerical(
                    "the stiffness matrix is not positive semi-definite, even shifted by its mass: some \
                         stiffness is negative or not a number (springs, supports, material constants)"
                        .into(),
                )
            })?
        }
    };
    reduce(llt.L(), md, shift, dofs, count, false)
}

/// Whether the Cholesky factor L of K has a pivot L_ii² below
/// [`super::lanczos::RIGID_PIVOT`] of K_ii: a free structure's K is singular, but round-off
/// can leave its factor positive, with pivots of ~10⁻¹³ of the diagonal on the rigid-body
/// motions. Reducing with that factor carries the round-off into every mode (residuals of
/// 10⁻⁵ on a free plate's elastic modes); shifted by a little of M it does not.
fn rigid_pivot(l: MatRef<'_, f64>, k: &Mat<f64>) -> bool {
    (0..k.nrows()).any(|i| l[(i, i)] * l[(i, i)] < super::lanczos::RIGID_PIVOT * k[(i, i)])
}

/// The lowest `count` modes of (K, M) over all of M's DOFs, with K = RᵀR given by its
/// banded square-root factor (see [`crate::assembly::system::structure_stiffness_root`]):
/// the same reduction as [`modes`] with L = Rᵀ, whose round-off is that of K's element
/// rows rather than of K's assembled entries. R must have passed [`BandedR::check`].
pub fn modes_from_root(root: &BandedR, m: &Csr, count: usize) -> Result<Modes> {
    let n = root.dim();
    if n == 0 || m.dim() != n {
        return Err(Error::Numerical(format!(
            "modal analysis with a {n}-DOF stiffness factor and a {}-DOF M",
            m.dim()
        )));
    }
    let l = Mat::<f64>::from_fn(n, n, |i, j| root.get(j, i));
    let mut md = Mat::<f64>::zeros(n, n);
    for (i, j, v) in m.triplets() {
        md[(i, j)] += v;
    }
    let dofs: Vec<usize> = (0..n).collect();
    reduce(l.as_ref(), md, 0.0, &dofs, count, true)
}

/// Modes from K + shift·M = L·Lᵀ and M (dense, over `dofs`): the largest eigenvalues μ of
/// L⁻¹·M·L⁻ᵀ are 1/(λ + shift) of the lowest modes.
fn reduce(
    l: MatRef<'_, f64>,
    mut md: Mat<f64>,
    shift: f64,
    dofs: &[usize],
    count: usize,
    from_root: bool,
) -> Result<Modes> {
    let n = dofs.len();
    // B = L⁻¹·M·L⁻ᵀ: X = L⁻¹M, then B = L⁻¹·Xᵀ.
    solve_lower_triangular_in_place(l, md.as_mut(), Par::Seq);
    let mut b = md.transpose().to_owned();
    solve_lower_triangular_in_place(l, b.as_mut(), Par::Seq);
    let b = Mat::from_fn(n, n, |i, j| 0.5 * (b[(i, j)] + b[(j, i)]));
    let evd = b.self_adjoint_eigen(Side::Lower).map_err(|e| not_converged("eigensolver", e))?;
    let take = count.min(n);
    let mu = evd.S().column_vector();
    // Eigenvalues come ascending: the largest μ (lowest λ) are last.
    let mut x = Mat::<f64>::from_fn(n, take, |i, j| evd.U()[(i, n - 1 - j)]);
    solve_upper_triangular_in_place(l.transpose(), x.as_mut(), Par::Seq);
    let mut omega = Vec::with_capacity(take);
    for r in 0..take {
        let m = mu[n - 1 - r];
        if !(m > 0.0) {
            return Err(Error::Numerical(format!("mode {} has a non-positive inverse eigenvalue {m}: the mass matrix is not positive definite (a DOF without mass?)", r + 1)));
        }
        // xᵀ·M·x = μ for y of unit length, so φ = x/√μ is mass-normalised.
        let scale = 1.0 / m.sqrt();
        for i in 0..n {
            x[(i, r)] *= scale;
        }
        let lam = 1.0 / m - shift;
        // Round-off can make a rigid-body eigenvalue slightly negative.
        omega.push(if lam > 0.0 { lam.sqrt() } else { 0.0 });
    }
    // Sign convention: the largest-magnitude entry of each mode is positive.
    for r in 0..take {
        let mut big = 0.0f64;
        for i in 0..n {
            if x[(i, r)].abs() > big.abs() {
                big = x[(i, r)];
            }
        }
        if big < 0.0 {
            for i in 0..n {
                x[(i, r)] = -x[(i, r)];
            }
        }
    }
    Ok(Modes { omega, shapes: x, dofs: dofs.to_vec(), from_root })
}

/// A dense eigensolver that did not converge (`solver` names it), with the likely cause:
/// matrix entries spread beyond what double precision resolves.
pub(crate) fn not_converged(solver: &str, e: impl std::fmt::Debug) -> Error {
    Error::Numerical(format!(
        "the {solver} did not converge ({e:?}): the stiffness and mass values span more than double \
         precision carries; bring material constants, masses and springs nearer physical values"
    ))
}

/// Damping ratio ζ of mode r (0-based) from a case's modal damping list, whose last entry
/// repeats for every higher mode.
pub fn ratio_of(ratios: &[f64], r: usize) -> f64 {
    ratios.get(r).or(ratios.last()).copied().unwrap_or(0.0)
}
