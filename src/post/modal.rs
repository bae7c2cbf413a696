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

use crate::analysis::modes::bare_modes;
use crate::assembly::{Model, System};
use crate::error::Result;
use crate::solve::eigen::ratio_of;
use num_complex::Complex64;
use serde::Serialize;

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
    /// Modal dissipated power, summed over harmonics (W), [r].
    pub dissipation: Vec<f64>,
    /// Time-averaged kinetic and strain energy per mode, summed over harmonics (J), [r].
    pub kinetic_energy: Vec<f64>,
    pub strain_energy: Vec<f64>,
    /// Share of the net input power carried by each mode (Σ over links of P_{i,r} / Σ P_i).
    pub power_participation: Vec<f64>,
    /// Share of the response: Σ_k |η_r,k|² ω_k² normalised (kinetic-energy share).
    pub response_participation: Vec<f64>,
}

/// Decomposes harmonic amplitudes `q[k]` at frequencies `k·omega0` with `count` modes.
/// `interface[l][k]` are the links' interface-force amplitudes (N); `modal_ratios` the
/// case's modal damping ratios, if it has modal rather than Rayleigh damping.
pub fn decompose(
    model: &Model,
    sys: &System,
    q: &[Vec<Complex64>],
    omega0: f64,
    interface: &[Vec<Complex64>],
    count: usize,
    modal_ratios: Option<&[f64]>,
) -> Result<Option<ModalDecomposition>> {
    let Some(beam) = model.beam.as_ref() else { return Ok(None) };
    let modes = bare_modes(beam, count)?;
    // The bare system numbers DOFs differently (no actuator DOFs): map node by node.
    let bare = System::assemble(&Model {
        beam: Some(beam.clone()),
        rayleigh: Default::default(),
        actuators: vec![],
        sensors: vec![],
    })?;
    let mut to_coupled = vec![usize::MAX; bare.n()];
    for node in 0..beam.mesh.n_nodes() {
        if let (Some(b), Some(c)) = (bare.dofs.w[node], sys.dofs.w[node]) {
            to_coupled[b] = c;
        }
        if let (Some(b), Some(c)) = (bare.dofs.theta[node], sys.dofs.theta[node]) {
            to_coupled[b] = c;
        }
    }
    let n = sys.n();
    let nm = modes.count();
    let phi: Vec<Vec<f64>> = (0..nm)
        .map(|r| {
            let mut v = vec![0.0; n];
            for (row, &d) in modes.dofs.iter().enumerate() {
                v[to_coupled[d]] = modes.shapes[(row, r)];
            }
            v
        })
        .collect();
    let nl = sys.links.len();
    let mut out = ModalDecomposition {
        mode_frequency_hz: modes.frequencies_hz(),
        frequency: (0..q.len()).map(|k| k as f64 * omega0 / (2.0 * std::f64::consts::PI)).collect(),
        point_power: vec![vec![0.0; nm]; nl],
        dissipation: vec![0.0; nm],
        kinetic_energy: vec![0.0; nm],
        strain_energy: vec![0.0; nm],
        generalised_force_abs: vec![vec![]; model.actuators.len()],
        ..Default::default()
    };
    let (a0, a1) = (model.rayleigh.a0, model.rayleigh.a1);
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
                            .map(|(l, lk)| lk.foot_dof.map_or(Complex64::default(), |d| interface[l][k] * phi[r][d]))
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
            if let Some(d) = lk.foot_dof {
                for r in 0..nm {
                    out.point_power[l][r] += 0.5 * (interface[l][k] * (iw * phi[r][d] * eta[r]).conj()).re;
                }
            }
        }
        for (r, (&wr, eta_r)) in modes.omega.iter().zip(&eta).enumerate().take(nm) {
            let e2 = eta_r.norm_sqr();
            let c_r = match modal_ratios {
                Some(z) => 2.0 * ratio_of(z, r) * wr,
                None => a0 + a1 * wr * wr,
            };
            out.dissipation[r] += 0.5 * w * w * c_r * e2;
            out.kinetic_energy[r] += 0.25 * w * w * e2;
            out.strain_energy[r] += 0.25 * wr * wr * e2;
        }
    }
    for (l, lk) in sys.links.iter().enumerate() {
        let full: f64 = (1..q.len())
            .map(|k| {
                let w = k as f64 * omega0;
                lk.foot_dof.map_or(0.0, |d| 0.5 * (interface[l][k] * (Complex64::new(0.0, w) * q[k][d]).conj()).re)
            })
            .sum();
        out.point_residual.push(full - out.point_power[l].iter().sum::<f64>());
    }
    let total_in: f64 = out.point_power.iter().flatten().sum();
    out.power_participation = (0..nm)
        .map(|r| out.point_power.iter().map(|p| p[r]).sum::<f64>() / if total_in != 0.0 { total_in } else { 1.0 })
        .collect();
    let ke: f64 = out.kinetic_energy.iter().sum();
    out.response_participation = out.kinetic_energy.iter().map(|e| e / if ke != 0.0 { ke } else { 1.0 }).collect();
    Ok(Some(out))
}
