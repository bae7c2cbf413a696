//! The step's coefficients for a scheme and Δt, and the proportional form of the
//! right-hand side.

use super::super::newmark::Scheme;
use crate::linalg::band::BandMatrices;
use crate::simd::update::StepCoeffs;

/// The coefficients of scheme `s` (α_m, α_f, γ, β) at step Δt (s): the history terms
/// w₁ = c_v·v + c_a·a and w₂ = e_v·v + e_a·a of the increment's right-hand side
/// M·w₁ + C·w₂ − K·u, and the update a_new = (Δu − Δt·v)/(βΔt²) − (1/(2β) − 1)·a,
/// v_new = v + Δt·((1 − γ)·a + γ·a_new).
pub(super) fn step_coeffs(s: Scheme, dt: f64) -> StepCoeffs {
    let (am, af, g, b) = (s.alpha_m, s.alpha_f, s.gamma, s.beta);
    let cu = (1.0 - am) / (b * dt * dt);
    StepCoeffs {
        cv: cu * dt,
        ca: (1.0 - am) * (0.5 / b - 1.0) - am,
        ev: -(1.0 - af) * (1.0 - g / b) - af,
        ea: -(1.0 - af) * dt * (1.0 - 0.5 * g / b),
        eu: 0.0,
        dt,
        ab: 1.0 / (b * dt * dt),
        a_old: 0.5 / b - 1.0,
        va_old: dt * (1.0 - g),
        va_new: dt * g,
    }
}

/// C = a₀·M + a₁·K + R with R sparse: Rayleigh damping of the structure, plus the dashpots,
/// masses and springs it does not cover (an actuator's links and body, point masses,
/// supports). Then M·w₁ + C·w₂ − K·u = M·(w₁ + a₀·w₂) − K·(u − a₁·w₂) + R·w₂: the update
/// writes the two combined vectors instead of w₁ and w₂ (`Proportional::detect`), and the
/// band right-hand side has two products instead of three, with R's few entries added
/// after it. C's diagonals are then read only for the dissipation, which keeps using C
/// itself.
#[derive(Clone, Debug)]
pub(super) struct Proportional {
    /// R's entries (i ≥ j; applied symmetrically).
    pub(super) residual: Vec<(usize, usize, f64)>,
    /// The scheme's w₂ = e_v·v + e_a·a, which R multiplies.
    pub(super) ev: f64,
    pub(super) ea: f64,
    /// a₀ (1/s) and a₁ (s) of C = a₀·M + a₁·K + R.
    pub(super) a0: f64,
    pub(super) a1: f64,
}

/// An entry of C − a₀·M − a₁·K below this fraction of |C| + |a₀·M| + |a₁·K| (a few
/// units of round-off) counts as zero. With the coefficients the damping was assembled
/// from, the structure's entries come out exactly zero (measured on the paper beam, the
/// frame and inertial cases, 1,000 elements and an irregular 333-element mesh), so this
/// only allows for another assembly order. It must stay that tight: C's entries are
/// dominated by a₁·K, so a coefficient a₀ off by δ leaves entries of only ≈ 1e-7·δ of |C|
/// on the paper beam, yet it is a mass-proportional change that the lowest modes feel in
/// full; such a remainder must be kept (and then declines the form), not dropped.
const PROPORTIONAL_ROUND_OFF: f64 = 1e-15;

impl Proportional {
    /// The form for C = a₀·M + a₁·K + R with a₀ (1/s) and a₁ (s), and the step's
    /// coefficients in it (from `k`, the plain ones): none where R would be more than a few
    /// entries a row (the three products are then kept) or a coefficient is not finite.
    pub(super) fn detect(
        band: &BandMatrices,
        n: usize,
        b: usize,
        a0: f64,
        a1: f64,
        k: StepCoeffs,
    ) -> Option<(Self, StepCoeffs)> {
        if !(a0.is_finite() && a1.is_finite()) {
            return None;
        }
        let stride = n + b;
        let mut residual = Vec::new();
        let mut keep = |i: usize, j: usize, m: f64, c: f64, k: f64| {
            let r = c - a0 * m - a1 * k;
            if r.abs() > PROPORTIONAL_ROUND_OFF * (c.abs() + (a0 * m).abs() + (a1 * k).abs()) {
                residual.push((i, j, r));
            }
        };
        for t in 0..=b {
            for i in t..n {
                let o = t * stride + i;
                keep(i, i - t, band.m[o], band.c[o], band.k[o]);
            }
        }
        for e in &band.extra {
            keep(e.i, e.j, e.m, e.c, e.k);
        }
        if residual.len() > n / 8 + 64 {
            return None;
        }
        // M·w₁ + C·w₂ − K·u = M·(w₁ + a₀·w₂) − K·(u − a₁·w₂) + R·w₂: the update writes
        // w₁' = w₁ + a₀·w₂ and w₂' = u − a₁·w₂, and the band sees no C.
        let coeffs =
            StepCoeffs { cv: k.cv + a0 * k.ev, ca: k.ca + a0 * k.ea, ev: -a1 * k.ev, ea: -a1 * k.ea, eu: 1.0, ..k };
        Some((Proportional { residual, ev: k.ev, ea: k.ea, a0, a1 }, coeffs))
    }
}
