//! Iterative refinement of a solve whose factor is less accurate than its residual.
//!
//! A = F + E: F is a factorised approximation of A (on a fine mesh, the LDLᵀ of the
//! assembled dynamic stiffness, whose error grows as elements⁴) while A·x can be applied
//! accurately (from element rows). Each step computes the residual r = b − A·x and solves
//! A·d = r by GMRES on the left-preconditioned system F⁻¹A·d = F⁻¹r (Carson–Higham
//! GMRES-IR): F⁻¹A is the identity but in the few directions where F is wrong (the smooth,
//! low modes, where the assembled entries cancel most), so GMRES needs few iterations even
//! where F alone would make plain refinement diverge (ε·cond(A) ≳ 1).
//!
//! The estimate of the error left, as a vector ([`Refined`]): twice the last correction d
//! (x_{k+1} = x_k + d with d ≈ the error of x_k; GMRES solves for it to
//! [`GMRES_REDUCTION`] and the steps stop on stagnation, so x_{k+1} keeps well under d of
//! it), plus what can still separate the residual from the exact one carried through the
//! solve, A⁻¹Σρ_j over the vectors ρ_j the operator gives for it ([`Refinable::rounding`]:
//! roundings with independent signs, whose image is the random walk they make; a factor
//! [`FLOOR_MARGIN`] covers the walk's spread; A⁻¹ is linear, so the sum takes one GMRES
//! solve). The residual itself must be accurate ([`Refinable::residual`]: on a fine mesh,
//! compensated sums): a residual in doubles would be mostly its own rounding once the
//! solution is good, and the floor would be all the estimate could say. Without
//! refinement ([`estimate`]: the factor already holds the tolerance) the estimate is
//! 2·F⁻¹r — the first-order error of x — plus the same floor, and x is left bit for bit as
//! the factor gave it. Refinement shrinks the correction, never the floor, so the floor is
//! added once, at the x finally kept ([`Refined::with_floor`]).

use num_complex::Complex64;

/// GMRES stops when the preconditioned residual has fallen by this factor: a refinement
/// step then leaves ~1e-6 of the error it corrects, so two steps take a solution from the
/// factor's to the residual's accuracy.
pub const GMRES_REDUCTION: f64 = 1e-6;
/// Krylov vectors kept before a restart, and restarts at most.
const KRYLOV: usize = 30;
const RESTARTS: usize = 4;
/// Refinement steps at most.
const STEPS: usize = 8;
/// The margin on the rounding floor carried through A⁻¹: over one realisation of the
/// random walk of roundings, each at its worst-case size γ·|…| (a typical rounding is a
/// fraction of that).
pub const FLOOR_MARGIN: f64 = 4.0;

/// How a solution was refined, and the estimate of the error left in it.
#[derive(Clone, Debug, Default)]
pub struct Refined {
    /// The error's estimate as a vector (signed, so that a quantity formed from several
    /// DOFs — a link's stretch, top minus foot — gets its own error, not the sum of theirs):
    /// 2·the last correction, or 2·F⁻¹r unrefined. Empty where nothing was estimated.
    pub correction: Vec<Complex64>,
    /// The residual's rounding carried through the solve, Σ_j F⁻¹ρ_j.
    pub floor: Vec<Complex64>,
    /// Refinement steps taken (0: the factor's solution kept).
    pub steps: usize,
    /// GMRES iterations over all steps.
    pub iterations: usize,
}

impl Refined {
    /// The bound on the error of Σ c·x[dof] over `functional`'s (dof, c):
    /// |Σ c·correction| + [`FLOOR_MARGIN`]·|Σ c·floor| (the first term alone while the floor
    /// is not yet added).
    pub fn bound(&self, functional: &[(usize, f64)]) -> f64 {
        let at = |v: &[Complex64]| functional.iter().map(|&(d, c)| v[d] * c).sum::<Complex64>().norm();
        match (self.correction.is_empty(), self.floor.is_empty()) {
            (true, _) => 0.0,
            (false, true) => at(&self.correction),
            (false, false) => at(&self.correction) + FLOOR_MARGIN * at(&self.floor),
        }
    }

    /// Adds the floor at `x`, the solution kept: the residual's rounding there carried
    /// through the solve, A⁻¹Σ_jρ_j. Through A, not the factor F: where F is off by O(1) in
    /// the smooth modes (a fine mesh), F⁻¹ could shrink the very part a smooth response
    /// amplifies. GMRES solves it to [`GMRES_REDUCTION`], which the margin covers.
    pub fn with_floor(mut self, op: &impl Refinable, x: &[Complex64]) -> Self {
        let mut parts = op.rounding(x).into_iter();
        let mut floor = parts.next().unwrap_or_else(|| vec![Complex64::default(); x.len()]);
        for v in parts {
            floor.iter_mut().zip(&v).for_each(|(f, v)| *f += v);
        }
        let (floor, iterations) = gmres(op, &floor);
        self.floor = floor;
        self.iterations += iterations;
        self
    }
}

/// The operators a refinement needs: A·x (for GMRES, to working precision), the residual
/// b − A·x (accurately: [`Refinable::residual`]), what can still separate that residual
/// from the exact one at x, as vectors whose images under A⁻¹ bound its effect on the
/// solution (magnitudes, or signed where the product's structure cancels them), and F⁻¹ in
/// place.
pub trait Refinable {
    fn apply(&self, x: &[Complex64], y: &mut [Complex64]);
    /// r = b − A·x; by default from [`Refinable::apply`] ([`working_residual`]).
    fn residual(&self, b: &[Complex64], x: &[Complex64], r: &mut [Complex64]) {
        working_residual(self, b, x, r);
    }
    fn rounding(&self, x: &[Complex64]) -> Vec<Vec<Complex64>>;
    fn precondition(&self, x: &mut [Complex64]);
}

/// r = b − A·x from [`Refinable::apply`], to working precision.
pub fn working_residual(op: &(impl Refinable + ?Sized), b: &[Complex64], x: &[Complex64], r: &mut [Complex64]) {
    op.apply(x, r);
    r.iter_mut().zip(b).for_each(|(r, b)| *r = b - *r);
}

fn norm(x: &[Complex64]) -> f64 {
    x.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt()
}

/// The first-order error estimate of `x` (F⁻¹b) without refining it: 2·F⁻¹r, r = b − A·x
/// (no floor yet: [`Refined::with_floor`]).
pub fn estimate(op: &impl Refinable, b: &[Complex64], x: &[Complex64]) -> Refined {
    let mut r = vec![Complex64::default(); x.len()];
    op.residual(b, x, &mut r);
    op.precondition(&mut r);
    r.iter_mut().for_each(|d| *d *= 2.0);
    Refined { correction: r, ..Default::default() }
}

/// Refines `x` (F⁻¹b on entry) until the correction falls below `step_tolerance`·|x|
/// (relative, Euclidean), or stagnates; the estimate is twice the last correction (no floor
/// yet: [`Refined::with_floor`]).
pub fn refine(op: &impl Refinable, b: &[Complex64], x: &mut [Complex64], step_tolerance: f64) -> Refined {
    let mut r = vec![Complex64::default(); x.len()];
    let mut out = Refined::default();
    let mut last = f64::INFINITY;
    loop {
        op.residual(b, x, &mut r);
        let (d, its) = gmres(op, &r);
        out.iterations += its;
        out.steps += 1;
        x.iter_mut().zip(&d).for_each(|(x, d)| *x += d);
        let size = norm(&d);
        if size <= step_tolerance * norm(x) || size > 0.5 * last || out.steps == STEPS {
            out.correction = d.iter().map(|d| 2.0 * d).collect();
            return out;
        }
        last = size;
    }
}

/// Solves A·d = r approximately: restarted GMRES on F⁻¹A·d = F⁻¹r from d = 0, until the
/// preconditioned residual falls by [`GMRES_REDUCTION`]. Returns d and the iterations.
fn gmres(op: &impl Refinable, r: &[Complex64]) -> (Vec<Complex64>, usize) {
    let n = r.len();
    let mut d = vec![Complex64::default(); n];
    let mut z = r.to_vec();
    op.precondition(&mut z);
    let beta0 = norm(&z);
    let mut iterations = 0;
    if beta0 == 0.0 {
        return (d, 0);
    }
    let mut w = vec![Complex64::default(); n];
    for restart in 0..RESTARTS {
        if restart > 0 {
            // Restarts need only working precision: the outer residual is the accurate one.
            working_residual(op, r, &d, &mut z);
            op.precondition(&mut z);
        }
        let beta = norm(&z);
        if beta <= GMRES_REDUCTION * beta0 {
            break;
        }
        let mut v: Vec<Vec<Complex64>> = vec![z.iter().map(|x| x / beta).collect()];
        let mut h = vec![vec![Complex64::default(); KRYLOV]; KRYLOV + 1];
        let (mut cs, mut sn) = (vec![0.0; KRYLOV], vec![Complex64::default(); KRYLOV]);
        let mut g = vec![Complex64::default(); KRYLOV + 1];
        g[0] = Complex64::new(beta, 0.0);
        let mut k = 0;
        for j in 0..KRYLOV {
            iterations += 1;
            op.apply(&v[j], &mut w);
            op.precondition(&mut w);
            for (i, vi) in v.iter().enumerate() {
                let hij: Complex64 = vi.iter().zip(&w).map(|(a, b)| a.conj() * b).sum();
                h[i][j] = hij;
                w.iter_mut().zip(vi).for_each(|(w, a)| *w -= hij * a);
            }
            let hn = norm(&w);
            h[j + 1][j] = Complex64::new(hn, 0.0);
            for i in 0..j {
                let (a, b) = (h[i][j], h[i + 1][j]);
                h[i][j] = cs[i] * a + sn[i] * b;
                h[i + 1][j] = -sn[i].conj() * a + cs[i] * b;
            }
            let (a, b) = (h[j][j], h[j + 1][j]);
            let t = (a.norm_sqr() + b.norm_sqr()).sqrt();
            let (c, s) = if a.norm() == 0.0 {
                (0.0, Complex64::new(1.0, 0.0))
            } else {
                (a.norm() / t, a / a.norm() * b.conj() / t)
            };
            cs[j] = c;
            sn[j] = s;
            h[j][j] = c * a + s * b;
            h[j + 1][j] = Complex64::default();
            g[j + 1] = -s.conj() * g[j];
            g[j] *= c;
            k = j + 1;
            if g[j + 1].norm() <= GMRES_REDUCTION * beta0 || hn == 0.0 {
                break;
            }
            v.push(w.iter().map(|x| x / hn).collect());
        }
        // H·y = g (upper triangular, k × k), d += V·y.
        let mut y = vec![Complex64::default(); k];
        for i in (0..k).rev() {
            let s: Complex64 = (i + 1..k).map(|l| h[i][l] * y[l]).sum();
            y[i] = (g[i] - s) / h[i][i];
        }
        for (yi, vi) in y.iter().zip(&v) {
            d.iter_mut().zip(vi).for_each(|(d, v)| *d += yi * v);
        }
        if g[k].norm() <= GMRES_REDUCTION * beta0 {
            break;
        }
    }
    (d, iterations)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A diagonal A with a deliberately wrong "factor" in a few entries: GMRES-IR must still
    /// converge to A⁻¹b, and the estimate must bound the error.
    struct Diag {
        a: Vec<Complex64>,
        f: Vec<Complex64>,
    }

    impl Refinable for Diag {
        fn apply(&self, x: &[Complex64], y: &mut [Complex64]) {
            y.iter_mut().zip(x).zip(&self.a).for_each(|((y, x), a)| *y = a * x);
        }
        fn rounding(&self, x: &[Complex64]) -> Vec<Vec<Complex64>> {
            vec![x.iter().zip(&self.a).map(|(x, a)| Complex64::new(f64::EPSILON * (a * x).norm(), 0.0)).collect()]
        }
        fn precondition(&self, x: &mut [Complex64]) {
            x.iter_mut().zip(&self.f).for_each(|(x, f)| *x /= f);
        }
    }

    #[test]
    fn a_factor_wrong_by_order_one_in_a_few_directions_is_refined_to_round_off() {
        let n = 50;
        let a: Vec<Complex64> = (0..n).map(|i| Complex64::new(1.0 + i as f64, 0.1)).collect();
        // Three entries off by 80 % to 300 %, the rest by 1e-9.
        let f: Vec<Complex64> =
            a.iter().enumerate().map(|(i, a)| a * [1.8, 0.25, 4.0].get(i).copied().unwrap_or(1.0 + 1e-9)).collect();
        let op = Diag { a: a.clone(), f };
        let b: Vec<Complex64> = (0..n).map(|i| Complex64::new((i as f64).cos(), 1.0)).collect();
        let exact: Vec<Complex64> = b.iter().zip(&a).map(|(b, a)| b / a).collect();
        let mut x = b.clone();
        op.precondition(&mut x);
        let first = estimate(&op, &b, &x).with_floor(&op, &x);
        for i in 0..3 {
            // Unrefined, the estimate sees the wrong directions.
            assert!(first.bound(&[(i, 1.0)]) > 0.1 * exact[i].norm());
        }
        let out = refine(&op, &b, &mut x, 1e-14);
        let out = out.with_floor(&op, &x);
        assert!(out.steps >= 1 && out.iterations <= 30, "{out:?}");
        for i in 0..n {
            let (err, bound) = ((x[i] - exact[i]).norm(), out.bound(&[(i, 1.0)]));
            assert!(err < 1e-14 * exact[i].norm(), "{i}: {err:e}");
            assert!(err <= bound.max(2.0 * f64::EPSILON * exact[i].norm()), "{i}: {err:e} vs {bound:e}");
        }
    }
}
