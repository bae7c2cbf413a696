//! The step on fine meshes: −K·u from a [`StiffnessProduct`] and the increment refined.
//!
//! The factor of K_eff = K + c_m·M + c_c·C rounds its entries, and a smooth increment
//! amplifies that rounding by K_eff's condition, ≈ β·Δt²·ω_max²: ε·elements⁴·Δt² of the
//! smooth modes' effective mass, a fixed error the step makes every time and the periodic
//! state inherits near a resonance (4.5e-7 of a point power on 1,000 beam elements, 6e-4 on
//! 5,000, at 100 steps a period). So the increment is refined: r = b − K_eff·Δu with
//! K_eff's stiffness from the product (and M, R from the band, which cancel little), and
//! Δu += F⁻¹·r until the correction is negligible. Each correction gains that error's
//! factor again. The state is then updated from the refined Δu, row by row as the fused
//! step does.

use super::sweeps::backward_row;
use super::{BandNewmark, StiffnessProduct, Width};
use crate::simd::update::{update_row, StepCoeffs};
use std::sync::Arc;

/// Corrections at most per step: each multiplies the error by ≈ ε·cond(K_eff) in the
/// smooth modes (below 1e-2 up to 20,000 beam elements at 100 steps a period).
const MAX_CORRECTIONS: usize = 4;

/// A correction below this fraction of the increment (largest entries) ends the
/// refinement: the next would be smaller by the error's factor (≈ ε·cond(K_eff), 2e-4 on
/// 20,000 beam elements at 100 steps a period), which leaves ~1e-11 of the increment; the
/// corrections level off at the residual's own rounding, ≈ 3e-11 of it there.
const NEGLIGIBLE: f64 = 1e-7;

/// The refined step's product, coefficients and work vectors.
#[derive(Clone)]
pub(super) struct Accurate {
    pub(super) product: Arc<dyn StiffnessProduct>,
    /// a₁ (s) of C = a₀·M + a₁·K + R: the dissipation's a₁·v̄ᵀ·K·v̄ comes from the product.
    pub(super) a1: f64,
    /// K_eff = k·K + m·M + r·R (R = C − a₀·M − a₁·K).
    k: f64,
    m: f64,
    r: f64,
    /// The right-hand side, the refined increment and a scaled copy of it.
    rhs: Vec<f64>,
    dx: Vec<f64>,
    scaled: Vec<f64>,
}

impl Accurate {
    /// For K_eff = w_K·K + w_C·C + w_M·M (the scheme's
    /// [`effective_weights`](crate::solve::newmark::Scheme::effective_weights)) with
    /// C = a₀·M + a₁·K + R.
    pub(super) fn new(
        product: Arc<dyn StiffnessProduct>,
        n: usize,
        [kf, c_c, c_m]: [f64; 3],
        a0: f64,
        a1: f64,
    ) -> Self {
        Accurate {
            product,
            a1,
            k: kf + c_c * a1,
            m: c_m + c_c * a0,
            r: c_c,
            rhs: vec![0.0; n],
            dx: vec![0.0; n],
            scaled: vec![0.0; n],
        }
    }
}

fn largest(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

impl BandNewmark {
    /// A step with the right-hand side's stiffness term from the product and the
    /// increment refined against K_eff.
    #[inline(always)]
    pub(super) fn accurate_step<W: Width, const FMA: bool>(&mut self, w: W, k: StepCoeffs) {
        let (n, b) = (self.n, w.b());
        self.rhs::<W, FMA>(w, k);
        let mut acc = self.accurate.take().expect("an accurate step");
        // w₂ holds w₂' = u − a₁·w₂ (the proportional form).
        acc.product.subtract(&self.w2[b..b + n], &mut self.z[b..b + n]);
        acc.rhs.copy_from_slice(&self.z[b..b + n]);
        self.forward::<W, FMA>(w);
        self.backward_solve::<W, FMA>(w);
        acc.dx.copy_from_slice(&self.x[b..b + n]);
        let mut last = f64::INFINITY;
        for _ in 0..MAX_CORRECTIONS {
            self.z[b..b + n].copy_from_slice(&acc.rhs);
            self.subtract_effective(&mut acc);
            self.forward::<W, FMA>(w);
            self.backward_solve::<W, FMA>(w);
            let c = largest(&self.x[b..b + n]);
            acc.dx.iter_mut().zip(&self.x[b..b + n]).for_each(|(d, x)| *d += x);
            if c <= NEGLIGIBLE * largest(&acc.dx) || c > 0.5 * last {
                break;
            }
            last = c;
        }
        let x = &mut self.x[b..b + n];
        let (u, v, a) = (&mut self.u[b..b + n], &mut self.v[..n], &mut self.a[..n]);
        let (w1, w2) = (&mut self.w1[b..b + n], &mut self.w2[b..b + n]);
        for (i, &d) in acc.dx.iter().enumerate() {
            if self.track_dissipation {
                update_row::<FMA, true>(k, i, d, u, v, a, x, w1, w2);
            } else {
                update_row::<FMA, false>(k, i, d, u, v, a, x, w1, w2);
            }
        }
        self.accurate = Some(acc);
        self.w_ready = true;
        self.diss_pending = self.track_dissipation;
    }

    /// z ← z − K_eff·Δu (z padded by B in front): the stiffness from the product, M and R
    /// from the band storage.
    fn subtract_effective(&mut self, acc: &mut Accurate) {
        let (n, b) = (self.n, self.b);
        let stride = n + b;
        let (m, x) = (&self.band.m, &acc.dx);
        let z = &mut self.z[b..b + n];
        // Diagonal t by slices: its lower half against x shifted by t, its upper half back.
        for t in 0..=b.min(n.saturating_sub(1)) {
            let mt = &m[t * stride + t..t * stride + n];
            for ((zi, &v), &xj) in z[t..].iter_mut().zip(mt).zip(&x[..n - t]) {
                *zi -= acc.m * v * xj;
            }
            if t > 0 {
                for ((zj, &v), &xi) in z[..n - t].iter_mut().zip(mt).zip(&x[t..]) {
                    *zj -= acc.m * v * xi;
                }
            }
        }
        for e in &self.band.extra {
            z[e.i] -= acc.m * e.m * x[e.j];
            z[e.j] -= acc.m * e.m * x[e.i];
        }
        if let Some(p) = &self.proportional {
            for &(i, j, r) in &p.residual {
                z[i] -= acc.r * r * x[j];
                if i != j {
                    z[j] -= acc.r * r * x[i];
                }
            }
        }
        acc.scaled.iter_mut().zip(x).for_each(|(s, &d)| *s = acc.k * d);
        acc.product.subtract(&acc.scaled, z);
    }

    /// Lᵀ·x = y/d in place in x (padded by B in front), without the update.
    #[inline(always)]
    fn backward_solve<W: Width, const FMA: bool>(&mut self, w: W) {
        let (n, b) = (self.n, w.b());
        let l = &self.factor.l[..(n + b) * b];
        let x = &mut self.x[b..b + n + b];
        let mut lp = self.factor.long.len();
        let mut prev = 0.0;
        for i in (0..n).rev() {
            let xi = backward_row::<FMA>(l, b, i, x, prev);
            prev = xi;
            x[i] = xi;
            if lp > 0 && self.factor.long[lp - 1].row == i {
                lp -= 1;
                self.factor.long[lp].scatter(&self.factor.l_tail, b, x, xi);
            }
        }
    }
}
