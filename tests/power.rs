//! Coupled beam–actuator power flow: against an independent continuous-beam model, against
//! the foundation's harmonic analysis, time domain against frequency domain, convergence
//! orders, energy balance, and the paper's claims.

mod common;
use beamflow::analysis::harmonic::{self, PointForce};
use beamflow::analysis::plan::calibrated_model;
use beamflow::analysis::steady_state::{self, solve_at};
use beamflow::analysis::transient::{self, TransientSettings};
use beamflow::assembly::{Model, System};
use beamflow::beam::analytic::{beta_l_roots, End};
use beamflow::case::LoadedCase;
use beamflow::power::link::link_harmonic;
use common::*;
use num_complex::Complex64;
use std::f64::consts::PI;

/// Rayleigh coefficients for ζ = 1 % at the analytic modes 1 and 3.
fn rayleigh() -> (f64, f64) {
    let r = beta_l_roots(End::Clamped, End::Clamped, 3).unwrap();
    let c = (EI / RHO_A).sqrt() / (L * L);
    let (w1, w3) = (r[0] * r[0] * c, r[2] * r[2] * c);
    let a1 = 2.0 * 0.01 / (w1 + w3);
    (a1 * w1 * w3, a1)
}

fn dense_solve(mut a: Vec<Vec<Complex64>>, mut b: Vec<Complex64>) -> Vec<Complex64> {
    let n = b.len();
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| a[i][c].norm().partial_cmp(&a[j][c].norm()).unwrap()).unwrap();
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..n {
            let f = a[r][c] / a[c][c];
            if f.norm() == 0.0 {
                continue;
            }
            let (upper, lower) = a.split_at_mut(r);
            for (ark, &v) in lower[0][c..n].iter_mut().zip(&upper[c][c..n]) {
                *ark -= f * v;
            }
            let v = b[c];
            b[r] -= f * v;
        }
    }
    for c in (0..n).rev() {
        let mut s = b[c];
        for k in c + 1..n {
            s -= a[c][k] * b[k];
        }
        b[c] = s / a[c][c];
    }
    b
}

/// Independent reference: the continuous clamped–clamped beam in `nm` modal coordinates,
/// coupled to the actuator's bodies and links (taken from the model's component
/// description), with a linear stack force F_p at ω. Returns the power per link (W).
fn continuous_reference(model: &Model, w: f64, fp: f64, nm: usize) -> Vec<f64> {
    let (a0, a1) = rayleigh();
    let roots = beta_l_roots(End::Clamped, End::Clamped, nm).unwrap();
    let c = (EI / RHO_A).sqrt() / (L * L);
    let comp = model.actuators[0].component();
    let nb = comp.dof_names.len();
    let n = nm + nb;
    let mut a = vec![vec![Complex64::default(); n]; n];
    for (r, bl) in roots.iter().enumerate() {
        let wr = bl * bl * c;
        a[r][r] += Complex64::new(wr * wr - w * w, w * (a0 + a1 * wr * wr));
    }
    for i in 0..nb {
        for j in 0..nb {
            a[nm + i][nm + j] -= w * w * comp.mass[(i, j)];
        }
    }
    let mut f = vec![Complex64::default(); n];
    let mut links = Vec::new();
    for lk in &comp.links {
        let x = match lk.foot {
            beamflow::actuator::FootBase::On(at) => at.x(),
            _ => unreachable!(),
        };
        let phi: Vec<f64> = roots.iter().map(|&bl| cc_mode(bl, x)).collect();
        let mut g = vec![0.0; n];
        for &(d, co) in &lk.top {
            g[nm + d] += co;
        }
        for r in 0..nm {
            g[r] -= phi[r];
        }
        let z = Complex64::new(lk.k, w * lk.c);
        for i in 0..n {
            for j in 0..n {
                a[i][j] += z * g[i] * g[j];
            }
        }
        for i in 0..nm {
            for j in 0..nm {
                a[i][j] -= w * w * lk.foot_mass * phi[i] * phi[j];
            }
        }
        if lk.active {
            for i in 0..n {
                f[i] += fp * g[i];
            }
        }
        links.push((g, phi, z, lk.foot_mass, lk.active));
    }
    let q = dense_solve(a, f);
    links
        .iter()
        .map(|(g, phi, z, mf, active)| {
            let u: Complex64 = g.iter().zip(&q).map(|(gi, qi)| qi * gi).sum();
            let wf: Complex64 = phi.iter().zip(&q).map(|(p, qi)| qi * p).sum();
            let fi = z * u - if *active { fp } else { 0.0 } + mf * w * w * wf;
            0.5 * (fi * (Complex64::new(0.0, w) * wf).conj()).re
        })
        .collect()
}

fn linear_case(actuator: &str, extra: &str) -> LoadedCase {
    let (a0, a1) = rayleigh();
    case(&format!(
        "[damping]\nkind = \"rayleigh\"\na0 = {a0}\na1 = {a1}\n{extra}\n[[actuator]]\ntype = \"{actuator}\"\n[actuator.stack]\nhysteresis = false\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n"
    ))
}

#[test]
fn coupled_powers_match_an_independent_continuous_beam_model() {
    for kind in ["inertial", "frame"] {
        let lc = linear_case(kind, "");
        let model = calibrated_model(&lc).unwrap();
        let sys = System::assemble(&model).unwrap();
        let ss = steady_state::run(&model, &sys, 3, 64).unwrap();
        let fp = 3.0e7 * 1.3e-7 * 12.0;
        let reference = continuous_reference(&model, 2.0 * PI * 60.0, fp, 400);
        let scale = reference.iter().fold(0.0f64, |m, p| m.max(p.abs()));
        for (l, p) in reference.iter().enumerate() {
            let fe = ss.spectra[l].power[1];
            assert!((fe - p).abs() < 1e-4 * scale, "{kind} link {l}: FE {fe:.8e} W vs continuous {p:.8e} W");
        }
    }
}

#[test]
fn actuator_replaced_by_its_force_pair_reproduces_the_harmonic_analysis() {
    let lc = linear_case("frame", "");
    let model = calibrated_model(&lc).unwrap();
    let sys = System::assemble(&model).unwrap();
    let w = 2.0 * PI * 60.0;
    let fp = Complex64::new(0.0, -3.0e7 * 1.3e-7 * 12.0); // sin → −i in e^{iωt} amplitudes
    let q = solve_at(&sys, w, &[fp]).unwrap();
    let h: Vec<_> = sys.links.iter().map(|lk| link_harmonic(lk, &q, w, &[fp])).collect();
    // The interface forces act on the beam: apply them as prescribed point forces.
    let forces: Vec<PointForce> = sys
        .links
        .iter()
        .zip(&h)
        .map(|(lk, h)| PointForce { at: lk.foot_at.unwrap(), amplitude: h.interface.norm(), phase: h.interface.arg() })
        .collect();
    let bare = Model {
        structure: model.structure.clone(),
        damping: model.damping.clone(),
        actuators: vec![],
        sensors: vec![],
        loads: vec![],
        roundoff_tolerance: model.roundoff_tolerance,
    };
    let bsys = System::assemble(&bare).unwrap();
    let r = harmonic::run(&bare, &bsys, &[60.0], &forces, None).unwrap();
    for (j, hj) in h.iter().enumerate() {
        assert!((r.velocity[0][j] - hj.velocity).norm() < 1e-9 * hj.velocity.norm(), "velocity at foot {j}");
        assert!(
            (r.input_power[0][j] - hj.power).abs() < 1e-8 * hj.power.abs(),
            "power at foot {j}: {} vs {}",
            r.input_power[0][j],
            hj.power
        );
    }
}

fn newmark_steady(
    lc: &LoadedCase,
    steps_per_period: usize,
    periods: usize,
) -> (Model, System, transient::TransientResult) {
    let model = calibrated_model(lc).unwrap();
    let sys = System::assemble(&model).unwrap();
    let s = TransientSettings {
        dt: Some(1.0 / 60.0 / steps_per_period as f64),
        periods: Some(periods),
        harmonics: Some(2),
        ..Default::default()
    };
    let r = transient::run(&model, &sys, &s).unwrap();
    (model, sys, r)
}

#[test]
fn newmark_steady_state_equals_the_frequency_domain_solve_at_the_shifted_frequency() {
    // The trapezoidal rule's periodic response to a sampled sine at ω is the exact response
    // at Ω = (2/Δt)·tan(ωΔt/2), and sample means of products equal ½Re(F·conj(V)).
    let lc = linear_case("frame", "");
    let n = 200;
    let (_, sys, r) = newmark_steady(&lc, n, 700);
    let dt = 1.0 / 60.0 / n as f64;
    let w = 2.0 * PI * 60.0;
    let big_w = 2.0 / dt * (w * dt / 2.0).tan();
    let fp = Complex64::new(0.0, -3.0e7 * 1.3e-7 * 12.0);
    let q = solve_at(&sys, big_w, &[fp]).unwrap();
    for (l, lk) in sys.links.iter().enumerate() {
        let p = link_harmonic(lk, &q, big_w, &[fp]).power;
        assert!(
            (r.mean_power[l] - p).abs() < 1e-5 * p.abs(),
            "link {l}: Newmark {:.9e} W vs shifted FD {p:.9e} W",
            r.mean_power[l]
        );
        // Σ over harmonics of the spectrum equals the time average.
        assert!((r.spectra[l].power_total - r.mean_power[l]).abs() < 1e-9 * p.abs());
        // Measured-style power from acceleration agrees with that from velocity at the drive.
        let (pv, pa) = (r.spectra[l].power[1], r.spectra[l].power_from_acceleration[1]);
        assert!((pv - pa).abs() < 1e-3 * pv.abs(), "from acceleration {pa} vs velocity {pv}");
    }
    // Energy balance: exact for the trapezoidal rule over the run and the last period.
    assert!(r.energy_run.beam.relative_error() < 1e-8, "{}", r.energy_run.beam.relative_error());
    assert!(r.energy_last_period.beam.relative_error() < 1e-6);
    let input = r.beam_input_power;
    assert!(
        (input - r.beam_dissipation).abs() < 1e-6 * input.abs(),
        "steady state: input {input} vs dissipated {}",
        r.beam_dissipation
    );
    let sampled: f64 = r.mean_power.iter().sum();
    assert!((sampled - input).abs() < 1e-3 * input.abs(), "sample-mean and midpoint powers agree to O(Δt²)");
}

#[test]
fn time_step_convergence_is_second_order() {
    let lc = linear_case("inertial", "");
    let model = calibrated_model(&lc).unwrap();
    let sys = System::assemble(&model).unwrap();
    let exact = steady_state::run(&model, &sys, 3, 64).unwrap().mean_power[0];
    let errs: Vec<f64> = [50, 100, 200]
        .iter()
        .map(|&n| (newmark_steady(&lc, n, 700).2.mean_power[0] - exact).abs() / exact.abs())
        .collect();
    for w in errs.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!((1.8..2.2).contains(&order), "observed order {order:.3}, errors {errs:?}");
    }
}

#[test]
fn point_powers_converge_under_mesh_refinement() {
    let powers: Vec<Vec<f64>> = [25, 50, 100, 200]
        .iter()
        .map(|&ne| {
            let lc = linear_case("frame", &format!("[beam.mesh]\nelements = {ne}\n"));
            let model = calibrated_model(&lc).unwrap();
            let sys = System::assemble(&model).unwrap();
            steady_state::run(&model, &sys, 3, 64).unwrap().mean_power
        })
        .collect();
    let diff =
        |a: &Vec<f64>, b: &Vec<f64>| a.iter().zip(b).map(|(x, y)| (x - y).abs() / y.abs()).fold(0.0f64, f64::max);
    let d: Vec<f64> = powers.windows(2).map(|w| diff(&w[0], &w[1])).collect();
    assert!(d[0] > d[1] && d[1] > d[2], "changes must shrink: {d:?}");
    assert!(d[2] < 1e-5, "200-element powers settled to {:e}", d[2]);
}
