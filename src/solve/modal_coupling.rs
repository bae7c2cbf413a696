//! The harmonic solve of a placement's reduced system by receptance coupling, without a
//! dense factor of its dynamic stiffness.
//!
//! On a shared modal basis ([`super::shared_basis`]) the reduced coordinates are the
//! retained modes, the placement's residual vectors and the actuators' bodies. On the modes
//! the bare structure is diagonal (mass-normalised modes: ΦᵀMΦ = I, ΦᵀKΦ = Ω², ΦᵀCΦ
//! diagonal for Rayleigh or modal damping), and the actuators reach them only through their
//! feet: a link adds k·g·gᵀ and c·g·gᵀ on its stretch g = top − foot and its foot mass
//! m_f·f·fᵀ, and on the modes g = −f. So there the dynamic stiffness is
//!
//! ```text
//!     D_dd(ω) = Λ(ω) + Fᵀ·W(ω)·F,    Λ = Ω² − ω²·I + iω·ΦᵀCΦ,    W = diag(k_l − ω²m_f,l + iωc_l),
//! ```
//!
//! F the links' feet on the modes (rows of T at the feet), and the rest r (residual vectors
//! and bodies, a few coordinates) couples to the modes through a dense N = D_dr. With
//! u = F·x_d, the feet's motion carried by the modes, x_d = Λ⁻¹·(b_d − Fᵀ·W·u − N·x_r), and
//! what is left is a dense system of (links + rest) unknowns:
//!
//! ```text
//!     ⎡ I + F·Λ⁻¹·Fᵀ·W     F·Λ⁻¹·N         ⎤ ⎡ u   ⎤   ⎡ F·Λ⁻¹·b_d         ⎤
//!     ⎣ −Nᵀ·Λ⁻¹·Fᵀ·W       D_rr − Nᵀ·Λ⁻¹·N ⎦ ⎣ x_r ⎦ = ⎣ b_r − Nᵀ·Λ⁻¹·b_d ⎦
//! ```
//!
//! (F·Λ⁻¹·Fᵀ is the modes' receptance at the feet: Woodbury's identity). A frequency costs
//! O(modes·(links + rest)²) instead of a dense factor's O(n³)/6.
//!
//! The modes are M-orthogonal only to the eigensolver's accuracy (ΦᵀMΦ's off-diagonal
//! entries reach ≈ 2e-8 on the example plate), and the system solved is the reduced one as
//! assembled, those entries included. So the form above is the preconditioner, and each
//! solve is refined against the system's own dense K − ω²M + iωC until the correction is
//! round-off: the left-out entries contract it by their size over the modes' damping
//! (≈ 1e-6 per step at 1 % damping), and two or three steps leave the factor's accuracy.
//!
//! [`ModalCoupling::of`] takes the form only where it holds: a reduced system on a shared
//! modal basis whose modal block is the structure's diagonal and the links' feet, up to
//! entries below [`LEFT_OUT`] of their diagonal (not a grounded damper on the structure,
//! hysteretic damping, a basis reduced from one assembled system or a full system: those
//! keep the dense factor). A solve whose refinement does not settle says so, and its
//! caller takes the dense factor.

use crate::assembly::System;
use crate::error::{Error, Result};
use crate::linalg::Csr;
use crate::simd::complex_rows::kmc_row;
use num_complex::Complex64;
use std::sync::Arc;

/// What an entry of the modal block may differ from the form by, relative to the geometric
/// mean of its diagonal entries (the modes' M-orthogonality, the round-off of projecting the
/// actuators' springs): the refinement contracts by about this over the damping ratio.
const LEFT_OUT: f64 = 1e-6;

/// A solve has settled when its last correction is below this fraction of the solution,
/// or stops contracting below [`NOISE`]: then the correction is the rounding of the
/// residual itself carried through the solve (≈ ε·cond, as a factor's own error is).
const SETTLED: f64 = 1e-14;
const NOISE: f64 = 1e-10;
const MAX_STEPS: usize = 8;

/// The dynamic stiffness of a reduced system in the coupled form (see the module's doc
/// comment), factorised per frequency.
pub struct ModalCoupling {
    /// Modal coordinates 0..nd; the rest nd..n.
    nd: usize,
    nr: usize,
    /// K, M, C of the modal coordinates, the structure's alone (diagonal).
    diag: [Vec<f64>; 3],
    /// The links' feet on the modes (links × nd, row-major) and each link's k, m_f, c.
    feet: Vec<f64>,
    weights: Vec<[f64; 3]>,
    /// K, M, C of modes × rest (nd × nr) and rest × rest (nr × nr), row-major.
    coupling: [Vec<f64>; 3],
    rest: [Vec<f64>; 3],
    /// The system's K, M, C (n × n, row-major), which the solves are refined against.
    totals: Arc<[Vec<f64>; 3]>,
    factor: Factor,
}

/// One frequency's factorisation.
#[derive(Default)]
struct Factor {
    omega: f64,
    lambda_inv: Vec<Complex64>,
    w: Vec<Complex64>,
    /// N(ω) and Λ⁻¹·N(ω) (nd × nr).
    n: Vec<Complex64>,
    scaled_n: Vec<Complex64>,
    /// Nᵀ·Λ⁻¹·N (nr × nr).
    schur: Vec<Complex64>,
    /// The coupled system's LU (s × s, row-major, unit L below the diagonal) and row order.
    lu: Vec<Complex64>,
    pivots: Vec<usize>,
}

/// k + c_m·m + c_c·c.
fn combine([k, m, c]: [f64; 3], c_m: f64, c_c: Complex64) -> Complex64 {
    Complex64::new(k + c_m * m, 0.0) + c_c * c
}

impl ModalCoupling {
    /// The coupled form of `sys`, where it holds (a reduced system on a shared modal basis
    /// whose modal block is the structure's diagonal plus the links' feet, up to entries
    /// below [`LEFT_OUT`] of their diagonal); None elsewhere.
    pub fn of(sys: &System) -> Option<Self> {
        let nd = sys.projection.as_ref()?.shared_modes()?;
        let n = sys.n();
        if sys.k_loss.is_some() || nd == 0 || nd > n {
            return None;
        }
        let links: Vec<_> = sys.links.iter().filter(|l| l.foot.iter().any(|&(d, _)| d < nd)).collect();
        let mut rows = vec![0.0; links.len() * nd];
        for (l, link) in links.iter().enumerate() {
            for &(d, c) in link.foot.iter().filter(|&&(d, _)| d < nd) {
                rows[l * nd + d] += c;
            }
        }
        let weights: Vec<[f64; 3]> = links.iter().map(|l| [l.k, l.foot_mass, l.c]).collect();
        let totals = match &sys.dense {
            Some(dense) => Arc::clone(dense),
            None => Arc::new([&sys.k, &sys.m, &sys.c].map(Csr::to_dense)),
        };
        let diag = [&sys.k_beam, &sys.m_beam, &sys.c_beam].map(|a| (0..nd).map(|i| a.get(i, i)).collect::<Vec<f64>>());
        // Σ_l w_l·f_l,i·f_l,j of the links' rank-one terms, a row at a time.
        let mut link = vec![0.0; nd];
        for (a, total) in totals.iter().enumerate() {
            let root: Vec<f64> = (0..nd).map(|i| total[i * n + i].abs().sqrt()).collect();
            for i in 0..nd {
                link[..=i].iter_mut().for_each(|x| *x = 0.0);
                for (l, w) in weights.iter().enumerate() {
                    let scale = w[a] * rows[l * nd + i];
                    link[..=i].iter_mut().zip(&rows[l * nd..=l * nd + i]).for_each(|(x, f)| *x += scale * f);
                }
                // Every entry compared, no branch per entry (a NaN fails its comparison).
                let bound = LEFT_OUT * root[i];
                let row = &total[i * n..i * n + i];
                let off_diagonal = row.iter().zip(&link[..i]).zip(&root[..i]);
                let within = off_diagonal.fold(true, |ok, ((t, l), r)| ok & ((t - l).abs() <= bound * r));
                let on_diagonal = (total[i * n + i] - diag[a][i] - link[i]).abs() <= bound * root[i];
                if !(within & on_diagonal) {
                    return None;
                }
            }
        }
        let nr = n - nd;
        let block = |t: &[f64], rows: std::ops::Range<usize>, from: usize| -> Vec<f64> {
            rows.flat_map(|i| t[i * n + from..(i + 1) * n].to_vec()).collect()
        };
        Some(ModalCoupling {
            nd,
            nr,
            diag,
            feet: rows,
            weights,
            coupling: totals.each_ref().map(|t| block(t, 0..nd, nd)),
            rest: totals.each_ref().map(|t| block(t, nd..n, nd)),
            totals,
            factor: Factor::default(),
        })
    }

    /// Links whose feet reach the modes.
    fn links(&self) -> usize {
        self.weights.len()
    }

    /// Factorises at circular frequency ω (rad/s). Fails where a mode's own dynamic
    /// stiffness or the coupled system is singular (an undamped resonance).
    pub fn factorize(&mut self, omega: f64) -> Result<()> {
        let mut f = std::mem::take(&mut self.factor);
        let done = self.factor_at(omega, &mut f);
        self.factor = f;
        done
    }

    /// [`ModalCoupling::factorize`] into `f`.
    fn factor_at(&self, omega: f64, f: &mut Factor) -> Result<()> {
        let (nd, nr, p) = (self.nd, self.nr, self.links());
        let (c_m, c_c) = (-omega * omega, Complex64::new(0.0, omega));
        f.omega = omega;
        f.lambda_inv.clear();
        for i in 0..nd {
            let kmc = [0, 1, 2].map(|a| self.diag[a][i]);
            let lambda = combine(kmc, c_m, c_c);
            let scale = kmc[0].abs() + omega * omega * kmc[1].abs() + omega * kmc[2].abs();
            if !(lambda.norm() > 1e-13 * scale) || !lambda.re.is_finite() || !lambda.im.is_finite() {
                return Err(Error::Singular {
                    row: i,
                    detail: format!("mode {i}'s dynamic stiffness {lambda:?} at {omega} rad/s: undamped at resonance"),
                });
            }
            f.lambda_inv.push(1.0 / lambda);
        }
        f.w = self.weights.iter().map(|&w| combine(w, c_m, c_c)).collect();
        let at = |blocks: &[Vec<f64>; 3], x: usize| combine([blocks[0][x], blocks[1][x], blocks[2][x]], c_m, c_c);
        f.n = (0..nd * nr).map(|x| at(&self.coupling, x)).collect();
        f.scaled_n = f.n.iter().enumerate().map(|(x, v)| v * f.lambda_inv[x / nr.max(1)]).collect();
        // G = F·Λ⁻¹·N (links × rest).
        let mut g = vec![Complex64::default(); p * nr];
        for l in 0..p {
            for i in 0..nd {
                let fl = self.feet[l * nd + i];
                if fl != 0.0 {
                    let row = &f.scaled_n[i * nr..(i + 1) * nr];
                    g[l * nr..(l + 1) * nr].iter_mut().zip(row).for_each(|(x, y)| *x += fl * y);
                }
            }
        }
        let s = p + nr;
        let z = &mut f.lu;
        z.clear();
        z.resize(s * s, Complex64::default());
        for l in 0..p {
            for m in 0..p {
                let h: Complex64 =
                    (0..nd).map(|i| self.feet[l * nd + i] * self.feet[m * nd + i] * f.lambda_inv[i]).sum();
                z[l * s + m] = h * f.w[m] + if l == m { 1.0 } else { 0.0 };
            }
            for c in 0..nr {
                z[l * s + p + c] = g[l * nr + c];
                z[(p + c) * s + l] = -g[l * nr + c] * f.w[l];
            }
        }
        // Nᵀ·Λ⁻¹·N as outer products of N's rows: each entry summed over i in the order a
        // dot product takes (the same bits), N's rows read contiguously.
        let schur = &mut f.schur;
        schur.clear();
        schur.resize(nr * nr, Complex64::default());
        if nr > 0 {
            for (n_i, sn_i) in f.n.chunks_exact(nr).zip(f.scaled_n.chunks_exact(nr)) {
                for (row, &n_ic) in schur.chunks_exact_mut(nr).zip(n_i) {
                    row.iter_mut().zip(sn_i).for_each(|(x, &sn_ie)| *x += n_ic * sn_ie);
                }
            }
        }
        for c in 0..nr {
            for e in 0..nr {
                z[(p + c) * s + p + e] = at(&self.rest, c * nr + e) - schur[c * nr + e];
            }
        }
        lu_in_place(z, s, &mut f.pivots)
    }

    /// Solves at the last factorised frequency, in place, refined against the system's own
    /// matrices (see the module's doc comment). False where the refinement did not settle:
    /// `x` is then not the solution.
    pub fn solve_in_place(&self, x: &mut [Complex64]) -> bool {
        self.refine(&[&self.factor], &mut [x])[0]
    }

    /// Solves at each circular frequency of `omegas` (rad/s) the right-hand side in the same
    /// place of `xs`, in place, as [`ModalCoupling::factorize`] and
    /// [`ModalCoupling::solve_in_place`] would one at a time (the same bits); per frequency,
    /// whether its refinement settled. The refinement's residuals of every frequency are
    /// formed in one pass over the system's matrices, which would otherwise be read from
    /// memory once per frequency and step.
    pub fn solve_at(&self, omegas: &[f64], xs: &mut [&mut [Complex64]]) -> Result<Vec<bool>> {
        let mut factors: Vec<Factor> = omegas.iter().map(|_| Factor::default()).collect();
        for (&omega, f) in omegas.iter().zip(&mut factors) {
            self.factor_at(omega, f)?;
        }
        Ok(self.refine(&factors.iter().collect::<Vec<_>>(), xs))
    }

    /// The preconditioned refinement of each right-hand side `xs[j]` at the frequency of
    /// `factors[j]`, in place; per right-hand side, whether it settled.
    fn refine(&self, factors: &[&Factor], xs: &mut [&mut [Complex64]]) -> Vec<bool> {
        let b: Vec<Vec<Complex64>> = xs.iter().map(|x| x.to_vec()).collect();
        for (f, x) in factors.iter().zip(xs.iter_mut()) {
            self.precondition(f, x);
        }
        let mut last = vec![f64::INFINITY; xs.len()];
        let mut settled: Vec<Option<bool>> = vec![None; xs.len()];
        for _ in 0..MAX_STEPS {
            let open: Vec<usize> = (0..xs.len()).filter(|&j| settled[j].is_none()).collect();
            if open.is_empty() {
                break;
            }
            let at: Vec<(f64, &[Complex64], &[Complex64])> =
                open.iter().map(|&j| (factors[j].omega, &b[j][..], &xs[j][..])).collect();
            for (mut r, &j) in self.residuals(&at).into_iter().zip(&open) {
                self.precondition(factors[j], &mut r);
                let (step, size) = (norm(&r), norm(xs[j]));
                xs[j].iter_mut().zip(&r).for_each(|(x, d)| *x += d);
                // The next correction is this one contracted as the last was: settled when
                // that is below SETTLED too.
                let next = if last[j].is_finite() { step * (step / last[j]) } else { step };
                if step <= SETTLED * size || (next <= SETTLED * size && step <= NOISE * size) {
                    settled[j] = Some(true);
                } else if step > 0.5 * last[j] {
                    settled[j] = Some(step <= NOISE * size);
                }
                last[j] = step;
            }
        }
        settled.into_iter().map(|s| s == Some(true)).collect()
    }

    /// b − (K − ω²M + iωC)·x of each (ω, b, x) in `at`, row by row: a row of K, M and C is
    /// read once for all of them.
    fn residuals(&self, at: &[(f64, &[Complex64], &[Complex64])]) -> Vec<Vec<Complex64>> {
        let n = self.nd + self.nr;
        let [k, m, c] = &*self.totals;
        let parts: Vec<(Vec<f64>, Vec<f64>)> =
            at.iter().map(|(_, _, x)| x.iter().map(|z| (z.re, z.im)).unzip()).collect();
        let mut out: Vec<Vec<Complex64>> = at.iter().map(|_| Vec::with_capacity(n)).collect();
        for i in 0..n {
            let row = i * n..(i + 1) * n;
            let (k, m, c) = (&k[row.clone()], &m[row.clone()], &c[row]);
            for ((r, &(omega, b, _)), (re, im)) in out.iter_mut().zip(at).zip(&parts) {
                let [real_re, real_im, damped_re, damped_im] = kmc_row(k, m, c, -omega * omega, re, im);
                r.push(b[i] - Complex64::new(real_re - omega * damped_im, real_im + omega * damped_re));
            }
        }
        out
    }

    /// The coupled form's solve (the preconditioner), in place.
    fn precondition(&self, f: &Factor, x: &mut [Complex64]) {
        let (nd, nr, p) = (self.nd, self.nr, self.links());
        let b_scaled: Vec<Complex64> = (0..nd).map(|i| x[i] * f.lambda_inv[i]).collect();
        let mut y: Vec<Complex64> = (0..p)
            .map(|l| (0..nd).map(|i| self.feet[l * nd + i] * b_scaled[i]).sum())
            .chain((0..nr).map(|c| x[nd + c] - (0..nd).map(|i| f.n[i * nr + c] * b_scaled[i]).sum::<Complex64>()))
            .collect();
        lu_solve(&f.lu, &f.pivots, &mut y);
        let (u, x_r) = y.split_at(p);
        let wu: Vec<Complex64> = u.iter().zip(&f.w).map(|(u, w)| u * w).collect();
        for i in 0..nd {
            let from_feet: Complex64 = wu.iter().enumerate().map(|(l, z)| z * self.feet[l * nd + i]).sum();
            let from_rest: Complex64 = x_r.iter().zip(&f.n[i * nr..(i + 1) * nr]).map(|(a, b)| a * b).sum();
            x[i] = (x[i] - from_feet - from_rest) * f.lambda_inv[i];
        }
        x[nd..].copy_from_slice(x_r);
    }
}

fn norm(x: &[Complex64]) -> f64 {
    x.iter().map(Complex64::norm_sqr).sum::<f64>().sqrt()
}

/// LU with partial pivoting of the row-major s × s `a`, in place; the row order into
/// `pivots`. Fails on a pivot that vanishes beside its column.
fn lu_in_place(a: &mut [Complex64], s: usize, pivots: &mut Vec<usize>) -> Result<()> {
    pivots.clear();
    for k in 0..s {
        // Sizes compared squared (the moduli's order up to rounding in near-ties), without
        // a hypot each.
        let size = |i: usize| a[i * s + k].norm_sqr();
        let p = (k..s).max_by(|&i, &j| size(i).total_cmp(&size(j))).unwrap_or(k);
        let pivot = a[p * s + k];
        if !(size(p) > 0.0) || !pivot.re.is_finite() || !pivot.im.is_finite() {
            return Err(Error::Singular {
                row: k,
                detail: "the actuators coupled to the modes at their feet: the system is singular".into(),
            });
        }
        pivots.push(p);
        if p != k {
            for j in 0..s {
                a.swap(k * s + j, p * s + j);
            }
        }
        let inv = 1.0 / a[k * s + k];
        for i in k + 1..s {
            let l = a[i * s + k] * inv;
            a[i * s + k] = l;
            if l != Complex64::default() {
                for j in k + 1..s {
                    let t = a[k * s + j];
                    a[i * s + j] -= l * t;
                }
            }
        }
    }
    Ok(())
}

/// Solves with [`lu_in_place`]'s factor, in place.
fn lu_solve(lu: &[Complex64], pivots: &[usize], x: &mut [Complex64]) {
    let s = x.len();
    for (k, &p) in pivots.iter().enumerate() {
        x.swap(k, p);
    }
    for i in 0..s {
        let sum: Complex64 = (0..i).map(|j| lu[i * s + j] * x[j]).sum();
        x[i] -= sum;
    }
    for i in (0..s).rev() {
        let sum: Complex64 = (i + 1..s).map(|j| lu[i * s + j] * x[j]).sum();
        x[i] = (x[i] - sum) / lu[i * s + i];
    }
}
