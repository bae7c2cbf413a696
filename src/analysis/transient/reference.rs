//! The exact periodic state of the discrete system a transient steps.
//!
//! The stack force depends on the voltage alone (spec §9), so the stepped system is linear
//! with a periodic load, and the Newmark-family recurrence has one periodic solution. At
//! z = e^{iω_kΔt} the recurrence's updates give V = σ(z)·U and A = α(z)·U with
//!
//! g = (1−γ) + γz, b = (½−β) + βz, σ = g(z−1)/(Δt·(g + b(z−1))), α = (z−1)²/(Δt²·(g + b(z−1))),
//!
//! and the generalised-α balance weights M by (1−α_m)z + α_m and C, K and the load by
//! (1−α_f)z + α_f, so each harmonic k of the sampled load solves
//! (K + c_m·M + σ·C)·U_k = F̂_k with c_m = α·((1−α_m)z + α_m)/((1−α_f)z + α_f). For average
//! acceleration σ = i·(2/Δt)·tan(ω_kΔt/2): the continuous dynamic stiffness at the warped
//! frequency. The run's periods converge to this state; their distance from it is the
//! start-up transient that remains, which no comparison of neighbouring periods can see
//! while a lightly damped mode beats against the drive.

use super::record::PeriodRecord;
use super::settle::{period_metrics, Metrics};
use crate::analysis::drive::{load_cycles, stack_cycle, DriveTiming};
use crate::analysis::roundoff::MeshRefinement;
use crate::analysis::steady_state::{PeriodSynthesis, NEGLIGIBLE_HARMONIC};
use crate::assembly::{Model, System};
use crate::error::Result;
use crate::power::link::{interface_amplitude, link_power_error};
use crate::power::point::{mean_power_error, own_scales};
use crate::power::spectra::harmonics;
use crate::solve::dynamic_stiffness::DynamicStiffness;
use crate::solve::newmark::Scheme;
use crate::solve::refine::Refined;
use num_complex::Complex64;
use std::f64::consts::PI;

/// The coefficients (c_m, σ, α) of harmonic k of N at step `dt`; None where the scheme's
/// response to that harmonic vanishes (average acceleration at the Nyquist frequency).
fn coefficients(scheme: &Scheme, dt: f64, k: usize, n: usize) -> Option<(Complex64, Complex64, Complex64)> {
    let z = Complex64::from_polar(1.0, 2.0 * PI * k as f64 / n as f64);
    let one = Complex64::new(1.0, 0.0);
    let g = (1.0 - scheme.gamma) * one + scheme.gamma * z;
    let b = (0.5 - scheme.beta) * one + scheme.beta * z;
    let den = g + b * (z - 1.0);
    if den.norm() <= 1e-12 * (g.norm() + b.norm()) {
        return None;
    }
    let sigma = g * (z - 1.0) / (dt * den);
    let alpha = (z - 1.0) * (z - 1.0) / (dt * dt * den);
    let c_m = alpha * ((1.0 - scheme.alpha_m) * z + scheme.alpha_m) / ((1.0 - scheme.alpha_f) * z + scheme.alpha_f);
    let finite = |c: Complex64| c.re.is_finite() && c.im.is_finite();
    (finite(c_m) && finite(sigma) && finite(alpha)).then_some((c_m, sigma, alpha))
}

/// The periodic state's metrics and, where its solves are refined, a bound of their
/// round-off: the largest over the metrics, each relative to its own size as the settling
/// check takes it (0 where not refined).
pub(super) struct Reference {
    pub metrics: Metrics,
    pub bound: f64,
}

/// Each metric's round-off bound (W, N), summed over the harmonics.
#[derive(Default)]
struct Bounds {
    powers: Vec<f64>,
    /// Squares of the transmitted forces' amplitude errors, summed.
    forces: Vec<f64>,
}

impl Bounds {
    fn new(links: usize, loads: usize) -> Self {
        Bounds { powers: vec![0.0; links + loads], forces: vec![0.0; links] }
    }

    /// The largest relative bound against `m`'s own scales. An RMS force's error is at most
    /// the RMS of the error, ≤ √(Σ_k |δF_k|²).
    fn relative_to(&self, m: &Metrics) -> f64 {
        let rel = |b: &[f64], v: &[f64]| {
            b.iter().zip(own_scales(v)).fold(0.0f64, |acc, (e, s)| acc.max(if *e == 0.0 { 0.0 } else { e / s }))
        };
        let forces: Vec<f64> = self.forces.iter().map(|f| f.sqrt()).collect();
        rel(&self.powers, &m.powers).max(rel(&forces, &m.forces))
    }
}

/// The per-period metrics (as [`period_metrics`] takes them from a run) of the periodic
/// state of `sys` stepped by `scheme` at `timing`. With `refined`, each harmonic's solve
/// is refined against the model's element rows ([`MeshRefinement`]) and its bound stated:
/// the periodic state of a fine mesh, whose run steps with the rows too.
pub(super) fn periodic_metrics(
    model: &Model,
    sys: &System,
    scheme: &Scheme,
    timing: &DriveTiming,
    refined: bool,
) -> Result<Reference> {
    let n = timing.steps_per_period;
    let mut rec = PeriodRecord::default();
    // Every forcing's harmonics: the stacks' F_p, then the point loads'.
    let mut loads = Vec::with_capacity(model.actuators.len() + model.loads.len());
    for a in &model.actuators {
        let cycle = stack_cycle(a.stack(), timing.period, n)?;
        loads.push(harmonics(&cycle.f_p));
        rec.fp.push(cycle.f_p);
    }
    for f in load_cycles(model, timing) {
        loads.push(harmonics(&f));
        rec.lf.push(f);
    }
    let kmax = n / 2;
    let size = |k: usize| loads.iter().map(|f| f[k].norm()).fold(0.0f64, f64::max);
    let largest = (0..=kmax).map(size).fold(0.0f64, f64::max);
    let mut dk = DynamicStiffness::of(sys);
    let refinement = if refined { Some(MeshRefinement::new(model, sys)?) } else { None };
    let nl = sys.links.len();
    let mut bounds = Bounds::new(nl, sys.loads.len());
    let zero = vec![Complex64::default(); kmax + 1];
    let (mut u, mut ud, mut fv, mut fa) =
        (vec![zero.clone(); nl], vec![zero.clone(); nl], vec![zero.clone(); nl], vec![zero.clone(); nl]);
    let mut lv = vec![zero; sys.loads.len()];
    for k in 0..=kmax {
        let Some((c_m, sigma, alpha)) = coefficients(scheme, timing.dt, k, n) else { continue };
        if size(k) <= NEGLIGIBLE_HARMONIC * largest {
            continue;
        }
        let mut q = vec![Complex64::default(); sys.n()];
        for (b, f) in sys.drives.iter().chain(&sys.loads).zip(&loads) {
            for &(d, c) in b {
                q[d] += f[k] * c;
            }
        }
        dk.factorize_general(c_m, sigma)?;
        let b = refinement.as_ref().map(|_| q.clone());
        dk.solve_in_place(&mut q);
        let e = match (&refinement, b) {
            (Some(r), Some(b)) => r.refine_if(&dk, 0, &b, &mut q, true),
            _ => Refined::default(),
        };
        // The rates' magnitudes: |σ| = ω̃ and |α| = ω̃² for average acceleration, and the
        // larger of the two stands for both in the other schemes' bound.
        let omega = sigma.norm().max(alpha.norm().sqrt());
        for (l, lk) in sys.links.iter().enumerate() {
            let stretch: Complex64 = lk.stretch.iter().map(|&(d, c)| q[d] * c).sum();
            let foot: Complex64 = lk.foot.iter().map(|&(d, c)| q[d] * c).sum();
            (u[l][k], ud[l][k], fv[l][k], fa[l][k]) = (stretch, sigma * stretch, sigma * foot, alpha * foot);
            if refinement.is_some() {
                // F_T = k·u + c·u̇ − F_p (the stack's only where active), at the rates of the
                // recurrence.
                let f_p = if lk.active { loads[lk.actuator][k] } else { Complex64::default() };
                let ft = stretch * lk.k + ud[l][k] * lk.c - f_p;
                let fi = interface_amplitude(lk, ft, fa[l][k]);
                let du = e.bound(&lk.stretch);
                bounds.powers[l] += link_power_error(lk, du, e.bound(&lk.foot), omega, fi, fv[l][k]);
                bounds.forces[l] += (du * Complex64::new(lk.k, omega * lk.c).norm()).powi(2);
            }
        }
        for (j, pattern) in sys.loads.iter().enumerate() {
            lv[j][k] = sigma * pattern.iter().map(|&(d, c)| q[d] * c).sum::<Complex64>();
            if refinement.is_some() {
                let f = loads[model.actuators.len() + j][k];
                bounds.powers[nl + j] += mean_power_error(f, 0.0, lv[j][k], omega * e.bound(pattern));
            }
        }
    }
    // x_j = Re Σ_k X̂_k·e^{i2πkj/N}: one inverse FFT per signal (the time derivative is
    // not asked of it, so its frequency is irrelevant).
    let mut synth = PeriodSynthesis::new(n, 0.0);
    for l in 0..nl {
        rec.u.push(synth.series(&u[l]));
        rec.ud.push(synth.series(&ud[l]));
        rec.fv.push(synth.series(&fv[l]));
        rec.fa.push(synth.series(&fa[l]));
    }
    rec.lv = lv.iter().map(|v| synth.series(v)).collect();
    let metrics = period_metrics(&sys.links, &rec);
    Ok(Reference { bound: bounds.relative_to(&metrics), metrics })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn average_acceleration_is_the_continuous_system_at_the_warped_frequency() {
        let (dt, n) = (1e-4, 200);
        for k in [1, 3, 37, 99] {
            let (c_m, sigma, alpha) = coefficients(&Scheme::average_acceleration(), dt, k, n).unwrap();
            let w = 2.0 * PI * k as f64 / (n as f64 * dt);
            let warped = 2.0 / dt * (w * dt / 2.0).tan();
            assert!((sigma - Complex64::new(0.0, warped)).norm() < 1e-9 * warped, "{sigma} vs i·{warped}");
            assert!((c_m + warped * warped).norm() < 1e-9 * warped * warped);
            assert!((alpha - sigma * sigma).norm() < 1e-9 * warped * warped);
        }
        assert!(coefficients(&Scheme::average_acceleration(), dt, 100, 200).is_none(), "no response at Nyquist");
        // The static load (k = 0) sees K alone.
        let (c_m, sigma, _) = coefficients(&Scheme::hht(0.1), dt, 0, n).unwrap();
        assert!(c_m.norm() == 0.0 && sigma.norm() == 0.0);
    }
}
