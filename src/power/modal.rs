//! Mode-resolved power flow: through which of the bare beam's modes the power enters and
//! where it is dissipated.
//!
//! With the bare beam's mass-normalised modes φ_r (ω_r), the beam part of a harmonic
//! response has modal coordinates η_r = φ_rᵀ·M_beam·Q, and the beam velocity at a point is
//! Σ_r iω·φ_r(x)·η_r. So the power at point i splits exactly into modal shares
//! P_{i,r} = ½·Re(F̂_i·conj(iω·φ_r(x_i)·η_r)), whose sum over all modes is P_i; a truncated
//! sum leaves a residual that is reported. With Rayleigh damping the modes also diagonalise
//! C_beam, so the beam dissipation splits into P_r = ½ω²·(a₀ + a₁ω_r²)·|η_r|²; with modal
//! damping (ratios ζ_r) into P_r = ½ω²·2ζ_r·ω_r·|η_r|².

use super::point::mean_power;
use crate::assembly::Damping;
use crate::assembly::System;
use crate::solve::eigen::{ratio_of, Modes};
use num_complex::Complex64;
use serde::Serialize;

/// How the structure's damping acts on its modes.
#[derive(Clone, Copy, Debug)]
pub enum ModalDamping<'a> {
    /// Rayleigh damping C = a₀·M + a₁·K: modal coefficient c_r = a₀ + a₁·ω_r² (1/s).
    Rayleigh { a0: f64, a1: f64 },
    /// Modal damping ratios ζ_r per mode (the last repeats): c_r = 2ζ_r·ω_r (1/s).
    Ratios(&'a [f64]),
    /// A damping matrix as given (an imported model's C, on the system's DOFs): c_r is its
    /// modal diagonal φ_rᵀ·C·φ_r; the coupling between modes it may hold is left in the
    /// residual the decomposition reports.
    Matrix(&'a crate::linalg::Csr),
}

impl<'a> ModalDamping<'a> {
    /// A model's viscous damping on its modes: its modal ratios if it has them, else its
    /// Rayleigh coefficients (zero for no damping; hysteretic damping has no modal dampers).
    pub fn of(damping: &'a Damping) -> Self {
        match damping.modal_ratios() {
            Some(z) => ModalDamping::Ratios(z),
            None => {
                let r = damping.rayleigh();
                ModalDamping::Rayleigh { a0: r.a0, a1: r.a1 }
            }
        }
    }

    /// The damping of `model` on the modes of its system `sys`: the given matrix of an
    /// imported model that has one, else [`ModalDamping::of`].
    pub fn of_model(model: &'a crate::assembly::Model, sys: &'a System) -> Self {
        match model.structure.as_ref().and_then(|s| s.imported()) {
            Some(m) if m.c.is_some() => ModalDamping::Matrix(&sys.c_beam),
            _ => ModalDamping::of(&model.damping),
        }
    }

    /// The modal damping coefficient c_r (1/s) of mode r (0-based) at ω_r (rad/s), its
    /// mass-normalised shape `phi` on the system's DOFs.
    pub fn coefficient(&self, r: usize, omega_r: f64, phi: &[f64]) -> f64 {
        match *self {
            ModalDamping::Rayleigh { a0, a1 } => a0 + a1 * omega_r * omega_r,
            ModalDamping::Ratios(z) => 2.0 * ratio_of(z, r) * omega_r,
            ModalDamping::Matrix(c) => c.bilinear(phi, phi),
        }
    }
}

/// Time-averaged power (W) a mode with damping coefficient c_r (1/s) dissipates when its
/// coordinate moves harmonically with amplitude η (√kg·m) at ω (rad/s): ½ω²·c_r·|η|².
#[inline]
pub fn modal_dissipated_power(omega: f64, c_r: f64, eta: Complex64) -> f64 {
    0.5 * omega * omega * c_r * eta.norm_sqr()
}

/// Mode-resolved view of a periodic steady state (per harmonic k and mode r).
#[derive(Clone, Debug, Default, Serialize)]
pub struct ModalDecomposition {
    /// Natural frequencies of the modes used (Hz).
    pub mode_frequency_hz: Vec<f64>,
    /// Harmonic frequencies (Hz).
    pub frequency: Vec<f64>,
    /// Modal coordinate amplitudes |η_r,k| (√kg·m), [k][r].
    pub eta_abs: Vec<Vec<f64>>,
    /// Modal generalised force of each actuator, |Q_r,k| = |Σ_i φ_r(x_i)·F̂_i,k| (N/√kg), [a][k][r].
    pub generalised_force_abs: Vec<Vec<Vec<f64>>>,
    /// Point power per mode, summed over harmonics (W), [link][r].
    pub point_power: Vec<Vec<f64>>,
    /// P_i − Σ_r P_{i,r} (W) per link: what the truncated modal sum misses.
    pub point_residual: Vec<f64>,
    /// Point-load power per mode, summed over harmonics (W), [load][r], and what the
    /// truncated sum misses per load (W).
    pub load_power: Vec<Vec<f64>>,
    pub load_residual: Vec<f64>,
    /// Modal dissipated power, summed over harmonics (W), [r].
    pub dissipation: Vec<f64>,
    /// Time-averaged kinetic and strain energy per mode, summed over harmonics (J), [r].
    pub kinetic_energy: Vec<f64>,
    pub strain_energy: Vec<f64>,
    /// Share of the net input power carried by each mode (Σ over links and loads of
    /// P_{i,r} / Σ P_i).
    pub power_participation: Vec<f64>,
    /// Share of the response: Σ_k |η_r,k|² ω_k² normalised (kinetic-energy share).
    pub response_participation: Vec<f64>,
}

/// Σ c·v[d] over a pattern of (DOF, coefficient).
fn pattern_value(pattern: &[(usize, f64)], v: &[f64]) -> f64 {
    pattern.iter().map(|&(d, c)| c * v[d]).sum()
}

/// Decomposes harmonic amplitudes `q[k]` at frequencies `k·omega0` (rad/s) of the system
/// `sys` with the bare structure's mass-normalised `modes`, their rows numbered on `sys`'s
/// DOFs (see `analysis::modes::bare_modes_on`). `interface[l][k]` are the links'
/// interface-force amplitudes (N), `loads[j][k]` the point loads' (N, at `sys.loads`);
/// `damping` how the structure's damping acts on the modes.
pub fn decompose(
    sys: &System,
    modes: &Modes,
    damping: ModalDamping,
    (q, omega0): (&[Vec<Complex64>], f64),
    interface: &[Vec<Complex64>],
    loads: &[Vec<Complex64>],
) -> ModalDecomposition {
    let n = sys.n();
    let nm = modes.count();
    let phi: Vec<Vec<f64>> = (0..nm).map(|r| modes.shape_global(r, n)).collect();
    let nl = sys.links.len();
    let mut out = ModalDecomposition {
        mode_frequency_hz: modes.frequencies_hz(),
        frequency: (0..q.len()).map(|k| k as f64 * omega0 / (2.0 * std::f64::consts::PI)).collect(),
        point_power: vec![vec![0.0; nm]; nl],
        load_power: vec![vec![0.0; nm]; loads.len()],
        dissipation: vec![0.0; nm],
        kinetic_energy: vec![0.0; nm],
        strain_energy: vec![0.0; nm],
        generalised_force_abs: vec![vec![]; sys.drives.len()],
        ..Default::default()
    };
    let mut mq = vec![Complex64::default(); n];
    for (k, qk) in q.iter().enumerate() {
        let w = k as f64 * omega0;
        sys.m_beam.mul_vec(qk, &mut mq);
        let eta: Vec<Complex64> = phi.iter().map(|p| p.iter().zip(&mq).map(|(a, b)| b * a).sum()).collect();
        out.eta_abs.push(eta.iter().map(|e| e.norm()).collect());
        for (a, gf) in out.generalised_force_abs.iter_mut().enumerate() {
            gf.push(
                (0..nm)
                    .map(|r| {
                        sys.links
                            .iter()
                            .enumerate()
                            .filter(|(_, lk)| lk.actuator == a)
                            .map(|(l, lk)| interface[l][k] * pattern_value(&lk.foot, &phi[r]))
                            .sum::<Complex64>()
                            .norm()
                    })
                    .collect(),
            );
        }
        if k == 0 {
            continue;
        }
        let iw = Complex64::new(0.0, w);
        for (l, lk) in sys.links.iter().enumerate() {
            for r in 0..nm {
                let phi_foot = pattern_value(&lk.foot, &phi[r]);
                out.point_power[l][r] += mean_power(interface[l][k], iw * phi_foot * eta[r]);
            }
        }
        for (j, pattern) in sys.loads.iter().enumerate() {
            for r in 0..nm {
                let phi_x: f64 = pattern.iter().map(|&(d, c)| c * phi[r][d]).sum();
                out.load_power[j][r] += mean_power(loads[j][k], iw * phi_x * eta[r]);
            }
        }
        for (r, (&wr, &eta_r)) in modes.omega.iter().zip(&eta).enumerate().take(nm) {
            let e2 = eta_r.norm_sqr();
            out.dissipation[r] += modal_dissipated_power(w, damping.coefficient(r, wr, &phi[r]), eta_r);
            out.kinetic_energy[r] += 0.25 * w * w * e2;
            out.strain_energy[r] += 0.25 * wr * wr * e2;
        }
    }
    for (l, lk) in sys.links.iter().enumerate() {
        let full: f64 = (1..q.len())
            .map(|k| {
                let w = k as f64 * omega0;
                let foot: Complex64 = lk.foot.iter().map(|&(d, c)| q[k][d] * c).sum();
                mean_power(interface[l][k], Complex64::new(0.0, w) * foot)
            })
            .sum();
        out.point_residual.push(full - out.point_power[l].iter().sum::<f64>());
    }
    for (j, pattern) in sys.loads.iter().enumerate() {
        let full: f64 = (1..q.len())
            .map(|k| {
                let w: Complex64 = pattern.iter().map(|&(d, c)| q[k][d] * c).sum();
                mean_power(loads[j][k], Complex64::new(0.0, k as f64 * omega0) * w)
            })
            .sum();
        out.load_residual.push(full - out.load_power[j].iter().sum::<f64>());
    }
    let points = || out.point_power.iter().chain(&out.load_power);
    let total_in: f64 = points().flatten().sum();
    out.power_participation =
        (0..nm).map(|r| points().map(|p| p[r]).sum::<f64>() / if total_in != 0.0 { total_in } else { 1.0 }).collect();
    let ke: f64 = out.kinetic_energy.iter().sum();
    out.response_participation = out.kinetic_energy.iter().map(|e| e / if ke != 0.0 { ke } else { 1.0 }).collect();
    out
}
