//! The lowest modes of large models: shift-invert Lanczos, solving with K's banded
//! square-root factor from the element rows (σ = 0, supported structures: accurate on very
//! fine meshes), with the profile LDLᵀ of K − σM as assembled (beams with actuators), or
//! with its sparse LDLᵀ under a fill-reducing ordering (plates, imported models).
//!
//! The operator x ↦ (K − σM)⁻¹·M·x has eigenvalues θ = 1/(λ − σ), so the modes nearest the
//! shift come first and are well separated (for a beam 1/λ falls as r⁻⁴). Lanczos runs in
//! the M-inner product with full reorthogonalisation (twice, which is enough in floating
//! point), so the Ritz vectors come out mass-normalised. Cost: one banded or profile solve and one
//! sparse product per Lanczos vector plus O(n·m²) for the orthogonalisation — linear in the
//! number of DOFs for a fixed number of modes, with no dense n×n matrix anywhere.

use super::eigen::Modes;
use crate::error::{Error, Result};
use crate::linalg::{dot, BandedR, Csr, Skyline, SparsePattern};
use faer::{Mat, Side};

/// The `count` modes of (K, M) nearest above the shift σ (rad²/s²; 0 for the lowest modes,
/// a free structure's rigid-body modes among them). All of the system's DOFs take part.
///
/// Factorises K − σM as assembled: for σ = 0 on a very fine mesh that loses ~ε·(elements)⁴
/// of the lowest eigenvalues; [`lowest_modes_from_root`] keeps ~ε·(elements)².
pub fn modes_shift_invert(k: &Csr, m: &Csr, envelope: &[usize], count: usize, sigma: f64) -> Result<Modes> {
    // The argument error first: with count 0 and a singular K − σM the user would otherwise
    // see the factorisation's error instead.
    check_sizes(m, count)?;
    let factor = |sigma: f64| {
        let mut a = Skyline::zeros(envelope.to_vec());
        k.add_into_skyline(1.0, &mut a);
        m.add_into_skyline(-sigma, &mut a);
        let f = a.factorize()?;
        let ratio =
            f.pivots().iter().enumerate().map(|(i, d)| d.abs() / a.get(i, i).abs()).fold(f64::INFINITY, f64::min);
        Ok((f, ratio))
    };
    let (fac, sigma) = lowest_or_free(k, m, sigma, factor)?;
    run(m, count, sigma, &|x| fac.solve_in_place(x), Start::Plain, false)
}

/// The factor of K − σM, or for the lowest modes (σ = 0) of a free structure, whose K is
/// singular, of K − σ_f·M at the shift σ_f of [`free_shift`]: the rigid-body modes then come
/// first, at ω ≈ 0, as the dense solver finds them. K counts as singular where its
/// factorisation fails or leaves a pivot below [`RIGID_PIVOT`] of its diagonal entry
/// (round-off can leave a free plate's factor positive; a factor that near singular would
/// carry its round-off into every mode). `factor` returns the factor and its smallest pivot
/// ratio. Any other failure is the first factorisation's error.
fn lowest_or_free<F>(k: &Csr, m: &Csr, sigma: f64, factor: impl Fn(f64) -> Result<(F, f64)>) -> Result<(F, f64)> {
    // The first factor is dropped before the shifted one is built: a large model's factor
    // is the memory the budget counts once.
    let first_error = match factor(sigma) {
        Ok((f, ratio)) if sigma != 0.0 || ratio >= RIGID_PIVOT => return Ok((f, sigma)),
        Ok(_) => None,
        Err(e) if sigma != 0.0 => return Err(e),
        Err(e) => Some(e),
    };
    let shift = free_shift(k, m);
    match (factor(shift), first_error) {
        (Ok((f, _)), _) => Ok((f, shift)),
        (Err(e), None) => factor(sigma).map(|(f, _)| (f, sigma)).map_err(|_| e),
        (Err(_), Some(e)) => Err(e),
    }
}

/// A pivot below this fraction of its diagonal entry is a rigid-body motion up to round-off
/// (a free plate's: 10⁻¹⁵ to 10⁻¹³), not a stiff part of a held structure (a held plate's
/// smallest is ≈ 0.4; a link 10⁹ times stiffer than the elements beside it leaves ≈ 10⁻⁹).
pub const RIGID_PIVOT: f64 = 1e-11;

/// How far below zero a free structure's lowest modes are sought, from the traces of K and
/// M: 10⁻⁶ of tr K / tr M (rad²/s²), far below the lowest elastic eigenvalue of any mesh
/// the solvers take (their ratio to the stiffest DOF's is ≳ 10⁻¹²), yet K + s·M keeps
/// pivots of ~10⁻⁶ of its diagonal on the rigid-body motions, which a positive definite
/// factorisation resolves to round-off. The dense solver ([`super::eigen::modes`]) and
/// this one both shift by it.
pub fn free_shift_size(trace_k: f64, trace_m: f64) -> f64 {
    1e-6 * trace_k / trace_m
}

/// The shift σ_f = −[`free_shift_size`] of the sparse factor K − σ_f·M.
fn free_shift(k: &Csr, m: &Csr) -> f64 {
    let trace = |a: &Csr| (0..a.dim()).map(|i| a.get(i, i)).sum::<f64>();
    -free_shift_size(trace(k), trace(m))
}

/// The `count` modes of (K, M) nearest above the shift σ, factorising K − σM with the
/// sparse LDLᵀ (see [`crate::linalg::sparse_ldlt`]): for meshes whose profile is wide
/// (plates) and imported models of any sparsity. Progress and cancellation go through the
/// thread's [`crate::progress`] task, one step per Lanczos vector.
///
/// M may be singular (no rotary inertia lumped): the start vector is (K − σM)⁻¹·M·r, which
/// has no component that M does not see, and every later vector stays in that range.
/// A singular M's infinite eigenvalues are not found: at most M's rank modes come back.
pub fn modes_sparse(k: &Csr, m: &Csr, count: usize, sigma: f64) -> Result<Modes> {
    check_sizes(m, count)?;
    if k.dim() != m.dim() {
        return Err(Error::Numerical(format!("K has {} DOFs, M {}", k.dim(), m.dim())));
    }
    modes_on_pattern(&SparsePattern::analyse(&[k, m])?, k, m, count, sigma)
}

/// [`modes_sparse`] on a `pattern` already analysed from K and M (a caller that factorises
/// them at another shift too orders them once).
pub fn modes_on_pattern(pattern: &SparsePattern, k: &Csr, m: &Csr, count: usize, sigma: f64) -> Result<Modes> {
    check_sizes(m, count)?;
    let factor = |sigma: f64| {
        let f = pattern.factorize(&[(1.0, k), (-sigma, m)])?;
        let ratio = f.smallest_pivot_ratio();
        Ok((f, ratio))
    };
    let (fac, sigma) = lowest_or_free(k, m, sigma, factor)?;
    run(m, count, sigma, &|x| fac.solve_in_place(x), Start::Purified, false)
}

/// How the Lanczos start vector is made from a fixed pseudo-random one r.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Start {
    /// r itself (M positive definite).
    Plain,
    /// The operator applied once, (K − σM)⁻¹·M·r: free of M's null space.
    Purified,
}

/// The `count` lowest modes of (K, M) with K = RᵀR given by its square-root factor (see
/// [`crate::assembly::system::structure_stiffness_root`]): shift-invert Lanczos at σ = 0,
/// each step solving RᵀR·x = M·q with two banded triangular solves. R must have passed
/// [`BandedR::check`].
pub fn lowest_modes_from_root(root: &BandedR, m: &Csr, count: usize) -> Result<Modes> {
    if root.dim() != m.dim() {
        return Err(Error::Numerical(format!("stiffness factor has {} DOFs, M {}", root.dim(), m.dim())));
    }
    check_sizes(m, count)?;
    run(m, count, 0.0, &|x| root.solve_normal_in_place(x), Start::Plain, true)
}

/// At least one mode and one DOF: each entry point checks before any factorisation.
fn check_sizes(m: &Csr, count: usize) -> Result<()> {
    if count == 0 || m.dim() == 0 {
        return Err(Error::Numerical("shift-invert Lanczos needs at least one mode and one DOF".into()));
    }
    Ok(())
}

/// Lanczos on x ↦ (K − σM)⁻¹·M·x, `solve` applying (K − σM)⁻¹ in place, with more vectors
/// until the wanted Ritz pairs converge (sizes already checked by `check_sizes`).
/// `from_root` only labels the result (see [`Modes::from_root`]).
fn run(m: &Csr, count: usize, sigma: f64, solve: &dyn Fn(&mut [f64]), start: Start, from_root: bool) -> Result<Modes> {
    let n = m.dim();
    let count = count.min(n);
    let mut steps = (2 * count + 20).max(40).min(n);
    loop {
        let task =
            crate::progress::Task::start(&format!("{count} modes of {n} DOFs"), Some(steps as u64), "Lanczos vectors");
        let (omega, shapes, converged) = lanczos(m, solve, start, (steps, from_root), count, sigma, &task)?;
        if converged || steps == n {
            if !converged {
                return Err(Error::Numerical(format!(
                    "shift-invert Lanczos did not converge for {count} modes with {steps} vectors"
                )));
            }
            return Ok(Modes { omega, shapes, dofs: (0..n).collect(), from_root });
        }
        steps = (steps * 2).min(n);
    }
}

/// `steps`: the vectors at most, and whether K enters through a beam's stiffness root
/// (which [`checked`] takes).
fn lanczos(
    m: &Csr,
    solve: &dyn Fn(&mut [f64]),
    start: Start,
    (steps, from_root): (usize, bool),
    count: usize,
    sigma: f64,
    task: &crate::progress::Task,
) -> Result<(Vec<f64>, Mat<f64>, bool)> {
    let n = m.dim();
    let mut q: Vec<Vec<f64>> = Vec::with_capacity(steps + 1);
    let mut mq: Vec<Vec<f64>> = Vec::with_capacity(steps + 1);
    // A deterministic start vector with all modes present.
    let mut v: Vec<f64> = (0..n).map(|i| 1.0 + 0.37 * ((i as f64 * 0.618_033_988_75).fract() - 0.5)).collect();
    let mut mv = vec![0.0; n];
    if start == Start::Purified {
        m.mul_vec(&v, &mut mv);
        v.copy_from_slice(&mv);
        solve(&mut v);
    }
    m.mul_vec(&v, &mut mv);
    let norm = dot(&v, &mv).sqrt();
    if !(norm > 0.0 && norm.is_finite()) {
        return Err(Error::Numerical(format!(
            "shift-invert Lanczos: the start vector has M-norm {norm:e} (is M zero?)"
        )));
    }
    v.iter_mut().for_each(|x| *x /= norm);
    mv.iter_mut().for_each(|x| *x /= norm);
    q.push(v);
    mq.push(mv);
    let mut alpha = Vec::with_capacity(steps);
    let mut beta: Vec<f64> = Vec::with_capacity(steps);
    for j in 0..steps {
        task.set(j as u64)?;
        let mut w = mq[j].clone();
        solve(&mut w);
        let aj = dot(&w, &mq[j]);
        alpha.push(aj);
        for _ in 0..2 {
            for i in 0..=j {
                let c = dot(&w, &mq[i]);
                for (wx, qx) in w.iter_mut().zip(&q[i]) {
                    *wx -= c * qx;
                }
            }
        }
        let mut mw = vec![0.0; n];
        m.mul_vec(&w, &mut mw);
        let b = dot(&w, &mw).max(0.0).sqrt();
        beta.push(b);
        if j + 1 == steps
            || b <= 1e-14 * aj.abs()
            || (checked(j + 1, count, from_root) && ritz(&alpha, &beta, count).is_ok_and(|r| r.2))
        {
            break;
        }
        w.iter_mut().for_each(|x| *x /= b);
        mw.iter_mut().for_each(|x| *x /= b);
        q.push(w);
        mq.push(mw);
    }
    let mdim = alpha.len();
    let (theta, s, converged) = ritz(&alpha, &beta, count)?;
    let take = count.min(mdim);
    let mut omega = Vec::with_capacity(take);
    let mut shapes = Mat::<f64>::zeros(n, take);
    for r in 0..take {
        // Largest θ first.
        let c = mdim - 1 - r;
        let th = theta[c];
        let lam = sigma + 1.0 / th;
        omega.push(lam.max(0.0).sqrt());
        // On the column's slice: indexing the matrix entry by entry costs as much as the
        // sums on a large model.
        let shape = shapes.col_mut(r).try_as_col_major_mut().expect("a fresh matrix is column-major").as_slice_mut();
        for (k, qk) in q.iter().take(mdim).enumerate() {
            let coef = s[(k, c)];
            for (x, qx) in shape.iter_mut().zip(qk) {
                *x += coef * qx;
            }
        }
        // Sign convention as in the dense solver: largest entry positive.
        let mut big = 0.0f64;
        for &x in shape.iter() {
            if x.abs() > big.abs() {
                big = x;
            }
        }
        if big < 0.0 {
            shape.iter_mut().for_each(|x| *x = -*x);
        }
    }
    Ok((omega, shapes, converged))
}

/// Whether the Ritz pairs are checked after `steps` vectors (the tridiagonal eigenproblem
/// costs little beside the reorthogonalisation, which grows as the square of the vectors
/// kept: stopping once the wanted pairs converge saves most of it). For any structure every
/// ten from twenty beyond the modes wanted: a residual test cannot see a mode the vectors
/// have not yet reached, and the second of a repeated pair (a square plate's (1,2) and
/// (2,1)) emerges only from rounding, after more vectors. For a beam's stiffness root
/// (`from_root`) every five from ten beyond: a beam's bending modes are simple and the
/// lowest of a shift-invert at zero separate fast, so the three of a Rayleigh calibration
/// stop after a few more vectors than they are.
fn checked(steps: usize, count: usize, from_root: bool) -> bool {
    match from_root {
        true => steps >= count + 10 && (steps - count).is_multiple_of(5),
        false => steps >= count + 20 && steps.is_multiple_of(10),
    }
}

/// The Ritz values θ (ascending), the eigenvectors of the tridiagonal T (α on its diagonal,
/// β beside it) and whether the `count` largest have converged: residual |β_m·s_m| within
/// 1e-10·θ. A non-positive wanted θ is an error (the shift is above a mode).
fn ritz(alpha: &[f64], beta: &[f64], count: usize) -> Result<(Vec<f64>, Mat<f64>, bool)> {
    let mdim = alpha.len();
    let t = Mat::from_fn(mdim, mdim, |i, j| {
        if i == j {
            alpha[i]
        } else if i == j + 1 || j == i + 1 {
            beta[i.min(j)]
        } else {
            0.0
        }
    });
    let evd =
        t.self_adjoint_eigen(Side::Lower).map_err(|e| super::eigen::not_converged("tridiagonal eigensolver", e))?;
    let theta: Vec<f64> = (0..mdim).map(|i| evd.S().column_vector()[i]).collect();
    let s = evd.U().to_owned();
    let last_beta = *beta.last().unwrap_or(&0.0);
    let mut converged = true;
    for c in (mdim - count.min(mdim)..mdim).rev() {
        if !(theta[c] > 0.0) {
            return Err(Error::Numerical(
                "shift-invert Lanczos met a non-positive Ritz value: is the shift below the lowest mode?".into(),
            ));
        }
        if (last_beta * s[(mdim - 1, c)]).abs() > 1e-10 * theta[c] {
            converged = false;
        }
    }
    Ok((theta, s, converged))
}
