//! The band step's right-hand side and its row-by-row sweeps.

use super::{BandNewmark, Width};
use crate::simd::band::{dissipation_lanes, dissipation_rows, rhs_band, BandRhs, PeriodicRun, RhsForm};
use crate::simd::madd;
use crate::simd::update::{fill_history, update_row, StepCoeffs};

impl BandNewmark {
    /// z = load + M·w₁ + C·w₂ − K·u (in the proportional form M·w₁' − K·w₂' + R·w₂), by
    /// diagonals, and the last step's dissipation where it is pending.
    #[inline(always)]
    pub(super) fn rhs<W: Width, const FMA: bool>(&mut self, w: W, k: StepCoeffs) {
        let (n, b) = (self.n, w.b());
        if !self.w_ready {
            let (u, v, a) = (&self.u[b..b + n], &self.v[..n], &self.a[..n]);
            fill_history::<FMA>(k, u, v, a, &mut self.w1[b..b + n], &mut self.w2[b..b + n]);
        }
        let ray = self.proportional.is_some();
        // The last step's dissipation: folded into this pass in the AVX2 build (it reads C's
        // lower diagonals anyway, and v̄ is not overwritten before the backward sweep), a pass
        // of its own in the baseline build.
        let fold = self.diss_pending && FMA && cfg!(target_arch = "x86_64");
        if self.diss_pending && !fold {
            self.diss_sum += self.band_dissipation_from::<FMA>((0, [0.0; 4]));
            self.diss_pending = false;
        }
        let (w1, w2) = (&self.w1[..n + 2 * b], &self.w2[..n + 2 * b]);
        // In the proportional form w₂ holds w₂' = u − a₁·w₂ and takes u's place against K.
        let up = if ray { w2 } else { &self.u[..n + 2 * b] };
        let none: &[PeriodicRun] = &[];
        let use_runs = self.use_runs;
        let r = BandRhs {
            n,
            b,
            mck: [&self.band.m, &self.band.c, &self.band.k],
            ws: [w1, w2, up],
            vbar: &self.x[..n + 2 * b],
            runs4: if use_runs { &self.runs4 } else { none },
            runs8: if use_runs { &self.runs8 } else { none },
        };
        let z = &mut self.z[b..b + n];
        let lanes = rhs_band::<FMA>(&r, z, RhsForm { proportional: ray, dissipation: fold, wide: self.avx512 });
        // The load touches a handful of DOFs: added here rather than streamed in the loop.
        for &d in &self.touched {
            z[d] += std::mem::take(&mut self.load[d]);
        }
        // Out of the band as in it: K against `up`, and C only in the three-product form
        // (in the proportional one C's part is in the residual).
        for e in &self.band.extra {
            let (i, j, c) = (e.i, e.j, if ray { 0.0 } else { e.c });
            z[i] += e.m * w1[j + b] + c * w2[j + b] - e.k * up[j + b];
            z[j] += e.m * w1[i + b] + c * w2[i + b] - e.k * up[i + b];
        }
        if let Some(p) = &self.proportional {
            // R·w₂ with w₂ = e_v·v + e_a·a of the scheme, from v and a of the DOFs R touches.
            let w2 = |d: usize| madd::<FMA>(p.ev, self.v[d], p.ea * self.a[d]);
            for &(i, j, r) in &p.residual {
                z[i] += r * w2(j);
                if i != j {
                    z[j] += r * w2(i);
                }
            }
        }
        if fold {
            self.diss_sum += self.band_dissipation_from::<FMA>(lanes);
            self.diss_pending = false;
        }
    }

    /// L·y = z in place in z, and x = y/d. The newest unknown enters each row last and
    /// is carried in a register, so a row's critical path is one multiply–add rather than a
    /// store, a reload and a multiply–add.
    #[inline(always)]
    pub(super) fn forward<W: Width, const FMA: bool>(&mut self, w: W) {
        let (n, b) = (self.n, w.b());
        let l = &self.factor.l[..n * b];
        let d_inv = &self.factor.d_inv[..n];
        let z = &mut self.z[..n + b];
        let x = &mut self.x[..n + b];
        let mut lp = 0;
        let mut prev = 0.0; // y_{i−1}
        for i in 0..n {
            // Padded index of column i − B + s is i + s.
            let mut y = z[i + b];
            if lp < self.factor.long.len() && self.factor.long[lp].row == i {
                y -= self.factor.long[lp].dot::<FMA>(&self.factor.l_tail, b, z);
                lp += 1;
            }
            if b > 0 {
                for (&lt, &zt) in l[i * b..i * b + b - 1].iter().zip(&z[i..i + b - 1]) {
                    y = madd::<FMA>(-lt, zt, y);
                }
                y = madd::<FMA>(-l[i * b + b - 1], prev, y);
            }
            z[i + b] = y;
            x[i + b] = y * d_inv[i];
            prev = y;
        }
    }

    /// Lᵀ·x = y/d. Band entries are gathered down column i (entry l_{i+s,i} sits in row i+s
    /// at slot B−s) from u, where each finished row's displacement already is, the newest
    /// xᵢ₊₁ last and from a register; the entries of long rows, which reach far back, are
    /// scattered into x as soon as their xₖ is known. x keeps only what the dissipation
    /// needs (v̄, with `VBAR`): one stream fewer than keeping the solution there too.
    #[inline(always)]
    pub(super) fn backward<W: Width, const FMA: bool, const VBAR: bool>(&mut self, w: W, k: StepCoeffs) {
        let (n, b) = (self.n, w.b());
        let l = &self.factor.l[..(n + b) * b];
        // Δu of rows i + 1..=i + B, read by row i, stays in x (zero past row n − 1) until
        // no later row reads it: row i + B is updated (and its v̄ stored over its Δu) only
        // once row i is done.
        let x = &mut self.x[b..b + n + b];
        let (u, v, a) = (&mut self.u[b..b + n], &mut self.v[..n], &mut self.a[..n]);
        let (w1, w2) = (&mut self.w1[b..b + n], &mut self.w2[b..b + n]);
        let mut lp = self.factor.long.len();
        let mut prev = 0.0; // x_{i+1}
        for i in (0..n).rev() {
            let xi = backward_row::<FMA>(l, b, i, x, prev);
            prev = xi;
            x[i] = xi;
            if i + b < n {
                update_row::<FMA, VBAR>(k, i + b, x[i + b], u, v, a, x, w1, w2);
            }
            if lp > 0 && self.factor.long[lp - 1].row == i {
                lp -= 1;
                self.factor.long[lp].scatter(&self.factor.l_tail, b, x, xi);
            }
        }
        for i in 0..b.min(n) {
            update_row::<FMA, VBAR>(k, i, x[i], u, v, a, x, w1, w2);
        }
    }

    /// The banded v̄ᵀ·C·v̄ of the v̄ in `x`, with the entries outside the band.
    pub(super) fn band_dissipation<const FMA: bool>(&self) -> f64 {
        let (n, b) = (self.n, self.b);
        self.band_dissipation_from::<FMA>(dissipation_lanes::<FMA>(n, b, &self.band.c, &self.x))
    }

    /// `band_dissipation` from the vector pass's (first row left, lane sums).
    fn band_dissipation_from<const FMA: bool>(&self, lanes: (usize, [f64; 4])) -> f64 {
        let (n, b) = (self.n, self.b);
        let vb = &self.x[..n + 2 * b];
        let mut diss = dissipation_rows::<FMA>(n, b, &self.band.c, vb, lanes);
        for e in &self.band.extra {
            diss += 2.0 * e.c * vb[e.i + b] * vb[e.j + b];
        }
        if let Some(acc) = &self.accurate {
            diss += acc.a1 * acc.product.quadratic(&vb[b..b + n]);
        }
        diss
    }
}

/// Row i of the backward sweep Lᵀ·x = y/d: x[i] (holding y/d) less the band entries of
/// column i against the rows below, the newest (`prev`, x_{i+1}) last and from a register.
#[inline(always)]
pub(super) fn backward_row<const FMA: bool>(l: &[f64], b: usize, i: usize, x: &[f64], prev: f64) -> f64 {
    let mut xi = x[i];
    if b > 0 {
        for s in (2..=b).rev() {
            xi = madd::<FMA>(-l[(i + s) * b + b - s], x[i + s], xi);
        }
        xi = madd::<FMA>(-l[(i + 1) * b + b - 1], prev, xi);
    }
    xi
}
