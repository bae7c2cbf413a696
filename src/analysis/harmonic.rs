//! Harmonic response of the beam, bare or coupled with its actuators, to point forces:
//! mobilities, input power and the coupled system's transfer functions.

use super::roundoff::{self, MeshRefinement};
use crate::assembly::{Model, System};
use crate::error::{Error, Result};
use crate::power::balance::balance_error;
use crate::power::modal::{modal_dissipated_power, ModalDamping};
use crate::power::point::{beam_dissipation, mean_power, mean_power_error};
use crate::solve::dynamic_stiffness::DynamicStiffness;
use crate::solve::eigen::{ratio_of, Modes};
use crate::solve::refine::Refined;
use crate::structure::Location;
use num_complex::Complex64;
use serde::Serialize;
use std::f64::consts::PI;

/// A point force: amplitude (N) and phase (rad) at x (m).
#[derive(Clone, Copy, Debug)]
pub struct PointForce {
    pub at: Location,
    pub amplitude: f64,
    pub phase: f64,
}

/// Result over a list of frequencies. Complex amplitudes follow q(t) = Re(Q·e^{iωt}).
#[derive(Clone, Debug, Default, Serialize)]
pub struct HarmonicResult {
    pub frequency_hz: Vec<f64>,
    /// Bound on the relative round-off of every input power and mobility, the largest
    /// over points and frequencies ([`crate::analysis::roundoff`]).
    pub mesh_roundoff: f64,
    /// Positions (m) of the response points: the force points, then the sensors.
    pub point_x: Vec<f64>,
    /// The points' y (m) on a plate; empty on a beam.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub point_y: Vec<f64>,
    /// The response points as located on the structure (x, (x, y), or a node and its
    /// component): the figures name them, the results write their y, z, node and component.
    #[serde(skip)]
    pub point_at: Vec<Location>,
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
    /// The coupled system's transfer functions (a model with actuators; empty for the bare
    /// beam): the inputs are a unit force at each attachment point on the beam (the link
    /// feet, named as the links), then each actuator's unit stack force F_p (named
    /// `<actuator>_drive`).
    pub transfer_inputs: Vec<String>,
    /// Velocity at each response point per unit input, [f][point][input] (m/(N·s)).
    #[serde(skip)]
    pub transfer_velocity: Vec<Vec<Vec<Complex64>>>,
    /// The links (`<actuator>_<link>`) whose interface forces [`transfer_interface`]
    /// holds.
    ///
    /// [`transfer_interface`]: HarmonicResult::transfer_interface
    pub link_names: Vec<String>,
    /// Interface force under each link's foot per unit input, [f][link][input] (N/N).
    #[serde(skip)]
    pub transfer_interface: Vec<Vec<Vec<Complex64>>>,
}

impl HarmonicResult {
    /// Whether the analysis applied a force: without one (transfer functions only) no power
    /// goes in and there is no energy balance to state.
    pub fn forced(&self) -> bool {
        self.input_power.first().is_some_and(|p| !p.is_empty())
    }
}

/// An input of the coupled system's transfer functions: its load pattern and the stack
/// force it stands for (actuator, for a drive).
struct TransferInput {
    name: String,
    pattern: Vec<(usize, f64)>,
    drive: Option<usize>,
}

/// The coupled system's transfer inputs: a unit force at each link foot on the beam, then
/// each actuator's unit stack force.
fn transfer_inputs(model: &Model, sys: &System) -> Vec<TransferInput> {
    let link_name =
        |l: &crate::assembly::system::LinkDofs| format!("{}_{}", model.actuators[l.actuator].name(), l.name);
    let feet = sys
        .links
        .iter()
        .filter_map(|l| l.foot_dof.map(|d| TransferInput { name: link_name(l), pattern: vec![(d, 1.0)], drive: None }));
    let drives = sys.drives.iter().enumerate().map(|(a, b)| TransferInput {
        name: format!("{}_drive", model.actuators[a].name()),
        pattern: b.clone(),
        drive: Some(a),
    });
    feet.chain(drives).collect()
}

/// Runs the analysis on `sys`: the bare beam (a model without actuators), or the coupled
/// system of beam and passive actuators (stacks as their spring and damper, F_p the
/// input), which adds the link feet as response points and the transfer functions from a
/// unit force at each foot and each unit stack force. With `modal` (modes and their
/// damping ratios; bare beam only) the response is the modal sum over those modes instead
/// of the direct solve with the Rayleigh matrix.
pub fn run(
    model: &Model,
    sys: &System,
    frequencies: &[f64],
    forces: &[PointForce],
    modal: Option<(&Modes, &[f64])>,
) -> Result<HarmonicResult> {
    let n = sys.n();
    let mut points: Vec<(Location, String, Option<usize>)> = Vec::new();
    for (j, f) in forces.iter().enumerate() {
        let field = format!("analysis.force[{j}].{}", f.at.field());
        points.push((f.at, format!("force_{j}"), sys.w_dof_at(model, &f.at, &field)?));
    }
    for s in &model.sensors {
        points.push((s.at, s.name.clone(), sys.w_dof_at(model, &s.at, &format!("sensor.{}", s.at.field()))?));
    }
    // The coupled system's attachment points: each link's foot on the structure.
    for l in sys.links.iter().filter(|l| l.foot_dof.is_some()) {
        let name = format!("{}_{}", model.actuators[l.actuator].name(), l.name);
        points.push((l.foot_at.unwrap_or(Location::Beam { x: f64::NAN }), name, l.foot_dof));
    }
    let inputs = transfer_inputs(model, sys);
    let fdofs: Vec<Option<usize>> = points[..forces.len()].iter().map(|p| p.2).collect();
    let amps: Vec<Complex64> = forces.iter().map(|f| Complex64::from_polar(f.amplitude, f.phase)).collect();
    let mut res = HarmonicResult {
        frequency_hz: frequencies.to_vec(),
        point_x: points.iter().map(|p| p.0.x()).collect(),
        point_y: points.iter().filter_map(|p| p.0.y()).collect(),
        point_at: points.iter().map(|p| p.0).collect(),
        point_names: points.iter().map(|p| p.1.clone()).collect(),
        mesh_roundoff: 0.0,
        transfer_inputs: inputs.iter().map(|t| t.name.clone()).collect(),
        link_names: if inputs.is_empty() {
            Vec::new()
        } else {
            sys.links.iter().map(|l| format!("{}_{}", model.actuators[l.actuator].name(), l.name)).collect()
        },
        ..Default::default()
    };
    let mut tcols: Vec<Vec<Complex64>> = vec![vec![Complex64::default(); n]; inputs.len()];
    let mut dynk = match modal {
        None => Some((DynamicStiffness::of(sys), MeshRefinement::new(model, sys)?)),
        Some(_) => None,
    };
    // Per force column, the bound on each DOF's error (zero for the modal sum, whose modes
    // come from the stiffness's square root and need no refinement).
    let mut col_errors: Vec<Refined> = vec![Refined::default(); forces.len()];
    let mut cols: Vec<Vec<Complex64>> = vec![vec![Complex64::default(); n]; forces.len()];
    let task = crate::progress::Task::start("harmonic analysis", Some(frequencies.len() as u64), "frequencies");
    for (done, &fhz) in frequencies.iter().enumerate() {
        task.set(done as u64)?;
        if !(fhz > 0.0) {
            return Err(Error::analysis_setting("frequencies", format!("frequencies must be positive, got {fhz} Hz")));
        }
        let w = 2.0 * PI * fhz;
        let mut always = false;
        let (q, mob, v_all, pin) = loop {
            for (j, col) in cols.iter_mut().enumerate() {
                col.iter_mut().for_each(|x| *x = Complex64::default());
                if let Some(d) = fdofs[j] {
                    col[d] = Complex64::new(1.0, 0.0);
                }
            }
            for (t, col) in inputs.iter().zip(tcols.iter_mut()) {
                col.iter_mut().for_each(|x| *x = Complex64::default());
                for &(d, c) in &t.pattern {
                    col[d] += c;
                }
            }
            match (&mut dynk, modal) {
                (Some((dk, refinement)), _) => {
                    // A retry refines against the factorisation it already has.
                    if !always {
                        dk.factorize(w)?;
                    }
                    for (j, col) in cols.iter_mut().chain(tcols.iter_mut()).enumerate() {
                        let b = col.clone();
                        dk.solve_in_place(col);
                        let e = refinement.refine_if(dk, 0, &b, col, always);
                        if j < forces.len() {
                            col_errors[j] = e;
                        }
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
            let bound = roundoff_bound(&points, &cols, &col_errors, &amps, &pin, w);
            // A point's own bound above the tolerance where the whole solution's estimate let
            // the factor's solution stand: solved again, refined.
            let again = !always && dynk.as_ref().is_some_and(|(_, r)| r.can_refine() && bound > r.tolerance());
            if again {
                always = true;
                continue;
            }
            res.mesh_roundoff = res.mesh_roundoff.max(bound);
            break (q, mob, v_all, pin);
        };
        let iw = Complex64::new(0.0, w);
        let vel = |d: Option<usize>, v: &[Complex64]| d.map_or(Complex64::default(), |d| iw * v[d]);
        let total: f64 = pin.iter().sum();
        let diss = match modal {
            // The structure's, and on a coupled system the links' dampers' ½ω²·c·|u|².
            None => {
                let structure = match &dynk {
                    Some((_, refinement)) => refinement.dissipation(sys, &q, w),
                    None => beam_dissipation(sys, &q, w),
                };
                structure + links_dissipation(sys, &q, w)
            }
            Some((modes, ratios)) => modal_dissipation(modes, ratios, &sys.m_beam, &q, w),
        };
        if !inputs.is_empty() {
            res.transfer_velocity.push(points.iter().map(|p| tcols.iter().map(|c| vel(p.2, c)).collect()).collect());
            res.transfer_interface.push(
                sys.links
                    .iter()
                    .map(|lk| {
                        inputs
                            .iter()
                            .zip(&tcols)
                            .map(|(t, c)| {
                                let mut fp = vec![Complex64::default(); model.actuators.len()];
                                if let Some(a) = t.drive {
                                    fp[a] = Complex64::new(1.0, 0.0);
                                }
                                crate::power::link::link_harmonic(lk, c, w, &fp).interface
                            })
                            .collect()
                    })
                    .collect(),
            );
        }
        res.balance_error.push(balance_error(total, diss));
        res.mobility.push(mob);
        res.velocity.push(v_all);
        res.input_power.push(pin);
        res.total_power.push(total);
        res.dissipated_power.push(diss);
    }
    Ok(res)
}

/// The largest relative round-off bound at frequency ω of the input powers `pin` (forces
/// `amps` on the first points) and of the mobilities of the force columns `cols`, from each
/// column's DOF error bounds (see [`crate::analysis::roundoff`]).
fn roundoff_bound(
    points: &[(Location, String, Option<usize>)],
    cols: &[Vec<Complex64>],
    errors: &[Refined],
    amps: &[Complex64],
    pin: &[f64],
    w: f64,
) -> f64 {
    let mut worst = 0.0f64;
    for (p, (_, _, dof)) in points.iter().enumerate() {
        let Some(d) = *dof else { continue };
        for (col, e) in cols.iter().zip(errors) {
            worst = worst.max(roundoff::relative(e.bound(&[(d, 1.0)]), col[d].norm()));
        }
        if let (Some(&f), Some(&power)) = (amps.get(p), pin.get(p)) {
            let q: Complex64 = cols.iter().zip(amps).map(|(c, a)| c[d] * a).sum();
            let dq: f64 = errors.iter().zip(amps).map(|(e, a)| e.bound(&[(d, 1.0)]) * a.norm()).sum();
            let bound = mean_power_error(f, 0.0, Complex64::new(0.0, w) * q, w * dq);
            worst = worst.max(roundoff::relative(bound, power));
        }
    }
    worst
}

/// Power the links' dampers dissipate in harmonic motion Q at ω: Σ_l ½ω²·c_l·|u_l|², u_l
/// the link's stretch (zero without actuators).
fn links_dissipation(sys: &System, q: &[Complex64], w: f64) -> f64 {
    sys.links
        .iter()
        .map(|l| {
            let u: Complex64 = l.stretch.iter().map(|&(d, c)| q[d] * c).sum();
            0.5 * w * w * l.c * u.norm_sqr()
        })
        .sum()
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
            modal_dissipated_power(w, damping.coefficient(r, modes.omega[r], &[]), eta)
        })
        .sum()
}
