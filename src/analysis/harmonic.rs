//! Harmonic response of the beam to point forces: mobilities and input power.

use crate::assembly::{Model, System};
use crate::error::{Error, Result};
use crate::power::balance::balance_error;
use crate::power::modal::{modal_dissipated_power, ModalDamping};
use crate::power::point::{beam_dissipation, mean_power};
use crate::solve::dynamic_stiffness::DynamicStiffness;
use crate::solve::eigen::{ratio_of, Modes};
use num_complex::Complex64;
use serde::Serialize;
use std::f64::consts::PI;

/// A point force: amplitude (N) and phase (rad) at x (m).
#[derive(Clone, Copy, Debug)]
pub struct PointForce {
    pub x: f64,
    pub amplitude: f64,
    pub phase: f64,
}

/// Result over a list of frequencies. Complex amplitudes follow q(t) = Re(Q·e^{iωt}).
#[derive(Clone, Debug, Default, Serialize)]
pub struct HarmonicResult {
    pub frequency_hz: Vec<f64>,
    /// Estimated relative round-off of the mobilities and powers from the mesh
    /// ([`crate::analysis::roundoff::mesh_roundoff`]).
    pub mesh_roundoff: f64,
    /// Positions (m) of the response points: the force points, then the sensors.
    pub point_x: Vec<f64>,
    pub point_names: Vec<String>,
    /// Mobility Y[f][i][j] = V_i/F_j (m/(N·s)) for response point i and unit force j.
    #[serde(skip)]
    pub mobility: Vec<Vec<Vec<Complex64>>>,
    /// Velocity at each response point under all forces together (m/s).
    #[serde(skip)]
    pub velocity: Vec<Vec<Complex64>>,
    /// Time-averaged input power per force point ½Re(F·conj(V)) (W), [f][j].
    pub input_power: Vec<Vec<f64>>,
    /// Σ over force points (W).
    pub total_power: Vec<f64>,
    /// Power dissipated in the beam, computed independently from ½ω²·Qᴴ·C·Q (W).
    pub dissipated_power: Vec<f64>,
    /// |total − dissipated| / dissipated.
    pub balance_error: Vec<f64>,
}

/// Runs the analysis on the bare beam `sys` (no actuators). With `modal` (modes and their
/// damping ratios) the response is the modal sum over those modes instead of the direct
/// solve with the Rayleigh matrix.
pub fn run(
    model: &Model,
    sys: &System,
    frequencies: &[f64],
    forces: &[PointForce],
    modal: Option<(&Modes, &[f64])>,
) -> Result<HarmonicResult> {
    let n = sys.n();
    let mut points: Vec<(f64, String, Option<usize>)> = Vec::new();
    for (j, f) in forces.iter().enumerate() {
        points.push((f.x, format!("force_{j}"), sys.w_dof_at(model, f.x, &format!("analysis.force[{j}].x"))?));
    }
    for s in &model.sensors {
        points.push((s.x, s.name.clone(), sys.w_dof_at(model, s.x, "sensor.x")?));
    }
    let fdofs: Vec<Option<usize>> = points[..forces.len()].iter().map(|p| p.2).collect();
    let amps: Vec<Complex64> = forces.iter().map(|f| Complex64::from_polar(f.amplitude, f.phase)).collect();
    let mut res = HarmonicResult {
        frequency_hz: frequencies.to_vec(),
        point_x: points.iter().map(|p| p.0).collect(),
        point_names: points.iter().map(|p| p.1.clone()).collect(),
        mesh_roundoff: super::roundoff::mesh_roundoff(model),
        ..Default::default()
    };
    let mut dynk = match modal {
        None => Some(DynamicStiffness::of(sys)),
        Some(_) => None,
    };
    let mut cols: Vec<Vec<Complex64>> = vec![vec![Complex64::default(); n]; forces.len()];
    let task = crate::progress::Task::start("harmonic analysis", Some(frequencies.len() as u64), "frequencies");
    for (done, &fhz) in frequencies.iter().enumerate() {
        task.set(done as u64);
        if !(fhz > 0.0) {
            return Err(Error::analysis_setting("frequencies", format!("frequencies must be positive, got {fhz} Hz")));
        }
        let w = 2.0 * PI * fhz;
        for (j, col) in cols.iter_mut().enumerate() {
            col.iter_mut().for_each(|x| *x = Complex64::default());
            if let Some(d) = fdofs[j] {
                col[d] = Complex64::new(1.0, 0.0);
            }
        }
        match (&mut dynk, modal) {
            (Some(dk), _) => {
                dk.factorize(w)?;
                for col in cols.iter_mut() {
                    dk.solve_in_place(col);
                }
            }
            (None, Some((modes, ratios))) => {
                for col in cols.iter_mut() {
                    *col = modal_response(modes, ratios, col, w, n);
                }
            }
            _ => unreachable!(),
        }
        // Displacement under all forces, for the dissipation check.
        let mut q = vec![Complex64::default(); n];
        for (j, col) in cols.iter().enumerate() {
            for i in 0..n {
                q[i] += col[i] * amps[j];
            }
        }
        let iw = Complex64::new(0.0, w);
        let vel = |d: Option<usize>, v: &[Complex64]| d.map_or(Complex64::default(), |d| iw * v[d]);
        let mob: Vec<Vec<Complex64>> = points.iter().map(|p| cols.iter().map(|c| vel(p.2, c)).collect()).collect();
        let v_all: Vec<Complex64> = points.iter().map(|p| vel(p.2, &q)).collect();
        let pin: Vec<f64> = (0..forces.len()).map(|j| mean_power(amps[j], v_all[j])).collect();
        let total: f64 = pin.iter().sum();
        let diss = match modal {
            None => beam_dissipation(sys, &q, w),
            Some((modes, ratios)) => modal_dissipation(modes, ratios, &sys.m_beam, &q, w),
        };
        res.balance_error.push(balance_error(total, diss));
        res.mobility.push(mob);
        res.velocity.push(v_all);
        res.input_power.push(pin);
        res.total_power.push(total);
        res.dissipated_power.push(diss);
    }
    Ok(res)
}

/// Q = Σ_r φ_r·(φ_rᵀF)/(ω_r² − ω² + 2iζ_r·ω_r·ω).
fn modal_response(modes: &Modes, ratios: &[f64], f: &[Complex64], w: f64, n: usize) -> Vec<Complex64> {
    let mut q = vec![Complex64::default(); n];
    for r in 0..modes.count() {
        let wr = modes.omega[r];
        let mut gf = Complex64::default();
        for (row, &d) in modes.dofs.iter().enumerate() {
            gf += f[d] * modes.shapes[(row, r)];
        }
        let eta = gf / Complex64::new(wr * wr - w * w, 2.0 * ratio_of(ratios, r) * wr * w);
        for (row, &d) in modes.dofs.iter().enumerate() {
            q[d] += eta * modes.shapes[(row, r)];
        }
    }
    q
}

/// Dissipation of modal damping: Σ_r ½ω²·2ζ_r·ω_r·|η_r|², with η_r = φ_rᵀ·M·Q.
fn modal_dissipation(modes: &Modes, ratios: &[f64], m: &crate::linalg::Csr, q: &[Complex64], w: f64) -> f64 {
    let mut mq = vec![Complex64::default(); q.len()];
    m.mul_vec(q, &mut mq);
    let damping = ModalDamping::Ratios(ratios);
    (0..modes.count())
        .map(|r| {
            let mut eta = Complex64::default();
            for (row, &d) in modes.dofs.iter().enumerate() {
                eta += mq[d] * modes.shapes[(row, r)];
            }
            modal_dissipated_power(w, damping.coefficient(r, modes.omega[r]), eta)
        })
        .sum()
}
