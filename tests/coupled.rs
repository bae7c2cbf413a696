//! The coupled system's frequency response (beam with passive actuators): its transfer
//! functions against the steady state under the same unit harmonic force and drive, its
//! point mobility against the exact beam with the actuator's impedance added, and its
//! natural frequencies against the peaks of its FRFs.

mod common;

use beamflow::analysis::case_run::{AnalysisResult, CaseRun};
use beamflow::analysis::harmonic::HarmonicResult;
use beamflow::app::runner::run_case;
use beamflow::beam::analytic::clamped_point_receptance;
use common::{case, EI, L, RHO_A};
use num_complex::Complex64;
use std::f64::consts::PI;

const A0: f64 = 5.0;
const A1: f64 = 1e-5;

/// An inertial actuator (top mass m_t + m_p/2, foot mass m_p/2, stack k_p, c_p) at
/// x = 0.146 m of a 100-element beam with Rayleigh damping, a sensor at mid-span, and the
/// analyses given.
fn text(voltage: &str, stack: &str, analyses: &str) -> String {
    format!(
        "[beam.mesh]\nelements = 100\n[damping]\nkind = \"rayleigh\"\na0 = {A0}\na1 = {A1}\n\
         [[actuator]]\ntype = \"inertial\"\nname = \"shaker\"\nx_e = 0.146\nm_t = 0.1\n\
         [actuator.stack]\nk_p = 3e7\nc_p = 200.0\nm_p = 0.03\n{stack}\n\
         [actuator.voltage]\nkind = \"sine\"\n{voltage}\nfrequency = 60.0\n\
         [[sensor]]\nname = \"mid\"\nx = 0.365\n{analyses}"
    )
}

fn run(text: &str) -> CaseRun {
    run_case(&case(text)).unwrap()
}

fn harmonic(r: &CaseRun) -> &HarmonicResult {
    r.results.iter().find_map(|a| if let AnalysisResult::Harmonic(h) = a { Some(h) } else { None }).unwrap()
}

fn rel(a: Complex64, b: Complex64) -> f64 {
    (a - b).norm() / b.norm()
}

/// The exact clamped–clamped beam's point mobility V/F (m/(N·s)) at x with Rayleigh damping
/// C = a₀M + a₁K: EI* = EI(1 + iωa₁), ρA* = ρA(1 − ia₀/ω).
fn exact_mobility(w: f64, x: f64) -> Complex64 {
    let mass = Complex64::new(1.0, -A0 / w);
    let ei = Complex64::new(EI, EI * w * A1) / mass;
    Complex64::new(0.0, w) * clamped_point_receptance(L, ei, RHO_A, w, x, x) / mass
}

#[test]
fn coupled_frfs_are_the_steady_state_under_a_unit_force_and_a_unit_drive() {
    // A sine load of 1 N at the foot, the actuator passive (0 V: no stack force).
    let load =
        "[[load]]\nname = \"tap\"\nx = 0.146\n[load.force]\nkind = \"sine\"\namplitude = 1.0\nfrequency = 60.0\n";
    let steady = "[[analysis]]\ntype = \"steady_state\"\nharmonics = 3\nsamples_per_period = 64\n";
    let frf = "[[analysis]]\ntype = \"harmonic\"\nsystem = \"coupled\"\n[analysis.frequencies]\nvalues = [60.0]\n";
    let r = run(&format!("{}{load}{steady}{frf}", text("amplitude = 0.0", "", "")));
    let AnalysisResult::SteadyState(s) = &r.results[0] else { panic!("steady state first") };
    let h = harmonic(&r);
    // The load's phasor: 1·sin(ωt) = Re(−i·e^{iωt}).
    let f_hat = Complex64::new(0.0, -1.0);
    let at = |name: &str| h.point_names.iter().position(|p| p == name).unwrap();
    let foot_in = h.transfer_inputs.iter().position(|p| p == "shaker_stack").unwrap();
    // Foot velocity and interface force of the steady state, harmonic 1.
    let (v_ss, fi_ss) = (s.spectra[0].velocity[1], s.spectra[0].interface[1]);
    assert!(rel(h.velocity[0][at("force_0")], v_ss) < 1e-9, "{} vs {v_ss}", h.velocity[0][at("force_0")]);
    assert!(rel(h.transfer_velocity[0][at("shaker_stack")][foot_in] * f_hat, v_ss) < 1e-9);
    assert!(rel(h.transfer_interface[0][0][foot_in] * f_hat, fi_ss) < 1e-9, "interface");
    // The sensor: its velocity over the period, harmonic 1.
    let v_mid = beamflow::power::spectra::harmonics(&s.sensors[0].v)[1];
    assert!(rel(h.transfer_velocity[0][at("mid")][foot_in] * f_hat, v_mid) < 1e-9, "sensor");

    // A linear stack (no hysteresis) driven at 12 V: F_p = k_p·d_p·V.
    let r = run(&format!("{}{steady}{frf}", text("amplitude = 12.0", "hysteresis = false", "")));
    let AnalysisResult::SteadyState(s) = &r.results[0] else { panic!("steady state first") };
    let h = harmonic(&r);
    let drive = h.transfer_inputs.iter().position(|p| p == "shaker_drive").unwrap();
    let fp_hat = 3e7 * 1.3e-7 * Complex64::new(0.0, -12.0);
    let v_mid = beamflow::power::spectra::harmonics(&s.sensors[0].v)[1];
    let mid = h.point_names.iter().position(|p| p == "mid").unwrap();
    assert!(rel(h.transfer_velocity[0][mid][drive] * fp_hat, v_mid) < 1e-9, "drive to sensor");
    assert!(rel(h.transfer_interface[0][0][drive] * fp_hat, s.spectra[0].interface[1]) < 1e-9, "drive to foot force");
}

#[test]
fn point_mobilities_are_the_exact_beam_bare_and_with_the_actuator_impedance() {
    let freqs = [20.0, 60.0, 150.0, 400.0, 900.0];
    let list = freqs.map(|f| f.to_string()).join(", ");
    let analyses = format!(
        "[[analysis]]\ntype = \"harmonic\"\n[analysis.frequencies]\nvalues = [{list}]\n\
         [[analysis.force]]\nx = 0.146\n\
         [[analysis]]\ntype = \"harmonic\"\nsystem = \"coupled\"\n[analysis.frequencies]\nvalues = [{list}]\n"
    );
    let r = run(&text("amplitude = 12.0", "", &analyses));
    let (AnalysisResult::Harmonic(bare), AnalysisResult::Harmonic(coupled)) = (&r.results[0], &r.results[1]) else {
        panic!("two harmonic analyses")
    };
    let foot = coupled.point_names.iter().position(|p| p == "shaker_stack").unwrap();
    let (k, c, m_top, m_foot) = (3e7, 200.0, 0.1 + 0.015, 0.015);
    for (i, &f) in freqs.iter().enumerate() {
        let w = 2.0 * PI * f;
        let y_beam = exact_mobility(w, 0.146);
        assert!(rel(bare.mobility[i][0][0], y_beam) < 1e-4, "{f} Hz bare: {} vs {y_beam}", bare.mobility[i][0][0]);
        // The actuator's impedance at its foot: foot mass, and the top mass on the stack.
        let iw = Complex64::new(0.0, w);
        let ks = Complex64::new(k, w * c);
        let z = iw * m_foot + iw * m_top * ks / (ks - w * w * m_top);
        let y_coupled = y_beam / (1.0 + z * y_beam);
        let y = coupled.transfer_velocity[i][foot][0];
        assert!(rel(y, y_coupled) < 1e-4, "{f} Hz coupled: {y} vs {y_coupled} (bare {y_beam})");
        assert!(rel(y, y_beam) > 1e-3, "{f} Hz: the actuator changes the mobility");
    }
}

#[test]
fn coupled_natural_frequencies_are_the_peaks_of_the_frfs() {
    let modes = run(&text("amplitude = 12.0", "", "[[analysis]]\ntype = \"modes\"\ncount = 4\n"));
    let AnalysisResult::Modes(m) = &modes.results[0] else { panic!("modes") };
    let coupled = m.coupled.as_ref().expect("coupled modes beside the bare ones");
    assert_eq!(coupled.body_names, ["shaker_z_t"]);
    // Light damping: each peak of the mid-span velocity per unit foot force within one step
    // of a 1e-4 grid around the natural frequency.
    let light = |t: String| t.replace(&format!("a0 = {A0}"), "a0 = 0.05").replace(&format!("a1 = {A1}"), "a1 = 1e-8");
    for (r, &fr) in coupled.frequencies_hz.iter().enumerate() {
        assert!((fr - m.frequencies_hz[r]).abs() > 1e-3 * fr, "mode {}: the actuator shifts it", r + 1);
        let grid: Vec<f64> = (-100..=100).map(|j| fr * (1.0 + 1e-4 * j as f64)).collect();
        let list = grid.iter().map(|f| format!("{f:e}")).collect::<Vec<_>>().join(", ");
        let run = run(&light(text(
            "amplitude = 12.0",
            "",
            &format!(
                "[[analysis]]\ntype = \"harmonic\"\nsystem = \"coupled\"\n[analysis.frequencies]\nvalues = [{list}]\n"
            ),
        )));
        let h = harmonic(&run);
        let mid = h.point_names.iter().position(|p| p == "mid").unwrap();
        let y: Vec<f64> = h.transfer_velocity.iter().map(|t| t[mid][0].norm()).collect();
        let peak = (0..y.len()).max_by(|&a, &b| y[a].total_cmp(&y[b])).unwrap();
        assert!((grid[peak] / fr - 1.0).abs() <= 1.01e-4, "mode {}: peak at {} Hz, natural {fr} Hz", r + 1, grid[peak]);
        assert!(peak > 0 && peak < grid.len() - 1, "mode {}: a peak inside the grid", r + 1);
    }
}
