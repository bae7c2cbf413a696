//! Prescribed point forces (`[[load]]`) in steady-state and transient analyses, alone or
//! beside actuators, against independent references: the exact continuous beam, the
//! harmonic analysis at the Newmark-shifted frequency (the exact periodic state of the
//! stepped system), superposition, and the static solution under a slow ramp.

use beamflow::analysis::case_run::{AnalysisResult, CaseRun};
use beamflow::analysis::steady_state::SteadyStateResult;
use beamflow::analysis::transient::TransientResult;
use beamflow::app::runner::run_case;
use beamflow::beam::analytic::clamped_point_receptance;
use beamflow::case::LoadedCase;
use beamflow::power::spectra::harmonics;
use num_complex::Complex64;
use std::f64::consts::PI;
use std::path::PathBuf;

fn case(text: &str) -> LoadedCase {
    LoadedCase::from_str(text, "loads.toml", PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases")).unwrap()
}

fn run(text: &str) -> CaseRun {
    run_case(&case(text)).unwrap()
}

fn steady(r: &CaseRun) -> &SteadyStateResult {
    r.results.iter().find_map(|a| if let AnalysisResult::SteadyState(s) = a { Some(s) } else { None }).unwrap()
}

fn transient(r: &CaseRun) -> &TransientResult {
    r.results.iter().find_map(|a| if let AnalysisResult::Transient(t) = a { Some(t) } else { None }).unwrap()
}

const EI: f64 = 210e9 * 0.05 * 0.005 * 0.005 * 0.005 / 12.0;
const RHO_A: f64 = 7850.0 * 0.05 * 0.005;
const RAYLEIGH: &str = "[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n";

/// The point mobility V/F (m/(N·s)) of the exact continuous paper beam with Rayleigh damping
/// a₀ = 5 /s, a₁ = 1e-5 s at x under a force at x.
fn exact_mobility(f: f64, x: f64) -> Complex64 {
    let w = 2.0 * PI * f;
    // EI* = EI(1 + iωa₁), ρA* = ρA(1 − ia₀/ω); dividing by ρA*/ρA leaves a real ρA.
    let mass = Complex64::new(1.0, -5.0 / w);
    let ei = Complex64::new(EI, EI * w * 1e-5) / mass;
    Complex64::new(0.0, w) * clamped_point_receptance(0.73, ei, RHO_A, w, x, x) / mass
}

#[test]
fn a_steady_point_force_puts_in_what_the_exact_beam_takes() {
    // Two harmonics of one force: 1 N at 60 Hz and 0.5 N at 180 Hz. Each puts ½|F|²·Re Y
    // into the beam; the beam is linear, so they add.
    let r = run(&format!(
        "[beam.mesh]\nelements = 146\n{RAYLEIGH}[[load]]\nx = 0.15\n[load.force]\nkind = \"sines\"\n\
         components = [{{ amplitude = 1.0, frequency = 60.0 }}, {{ amplitude = 0.5, frequency = 180.0, phase = 0.7 }}]\n\
         [[analysis]]\ntype = \"steady_state\"\n[output]\nhdf5 = false\nplots = false\n"
    ));
    let s = steady(&r);
    let exact = 0.5 * exact_mobility(60.0, 0.15).re + 0.5 * 0.25 * exact_mobility(180.0, 0.15).re;
    let p = s.load_spectra[0].power_total;
    assert!((p - exact).abs() < 1e-6 * exact, "{p:e} W vs exact beam {exact:e} W");
    // The powers per harmonic, where they belong.
    let sp = &s.load_spectra[0];
    let p3 = 0.5 * 0.25 * exact_mobility(180.0, 0.15).re;
    assert!((sp.power[3] - p3).abs() < 1e-6 * p3, "{} vs {p3:e}", sp.power[3]);
    assert!(sp.power[2].abs() < 1e-12 * exact, "nothing at 120 Hz");
    // The beam dissipates what the force puts in.
    assert!(s.balance_error < 1e-9, "balance {:e}", s.balance_error);
    let m = s.modal.as_ref().unwrap();
    // Thirty modes carry the point force's power but for the slowly converging rest of the
    // modal sum (a point force excites every mode).
    assert!(m.load_residual[0].abs() < 1e-4 * p, "modal residual {:e}", m.load_residual[0]);
}

/// The frequency (Hz) average acceleration responds at when it steps a drive of `f` (Hz) by
/// `dt` (s): the continuous system at ω' = (2/Δt)·tan(ωΔt/2).
fn newmark_shifted(f: f64, dt: f64) -> f64 {
    (2.0 / dt) * (PI * f * dt).tan() / (2.0 * PI)
}

#[test]
fn a_transient_point_force_settles_to_the_newmark_shifted_solve() {
    // The beat case: 1 N at 60 Hz on the paper beam, mode 1 at 49.9 Hz lightly damped.
    // The stepped system's periodic state is the continuous one at the shifted frequency,
    // which the harmonic analysis (a separate solver) gives.
    let dt = 1.0 / 60.0 / 200.0;
    let shifted = newmark_shifted(60.0, dt);
    let text = |tolerance: &str| {
        format!(
            "[[load]]\nname = \"shaker\"\nx = 0.2\n[load.force]\nkind = \"sine\"\namplitude = 1.0\nfrequency = 60.0\n\
             [[analysis]]\ntype = \"transient\"\nsteps_per_period = 200\nmax_periods = 2000\n{tolerance}\
             [[analysis]]\ntype = \"harmonic\"\n[analysis.frequencies]\nvalues = [{shifted:?}, 60.0]\n[[analysis.force]]\nx = 0.2\n\
             [output]\nhdf5 = false\nplots = false\n"
        )
    };
    let r = run(&text(""));
    let t = transient(&r);
    let h = r.results.iter().find_map(|a| if let AnalysisResult::Harmonic(h) = a { Some(h) } else { None }).unwrap();
    let (reference, unshifted) = (h.input_power[0][0], h.input_power[1][0]);
    let p = t.load_spectra[0].power_total;
    assert!(t.converged && t.settling_estimate < 1e-4, "{} periods, estimate {:e}", t.periods_run, t.settling_estimate);
    assert!(t.periods_run > 100, "{} periods: mode 1 beats against the drive for longer", t.periods_run);
    assert!((p - reference).abs() < 1e-4 * reference, "{p:e} W vs {reference:e} W at {shifted} Hz");
    // Settled further, the run is the shifted solve to round-off, and the shift matters:
    // 60 Hz itself is 7e-4 away.
    let tight = run(&text("tolerance = 1e-8\n"));
    let p = transient(&tight).load_spectra[0].power_total;
    assert!((p - reference).abs() < 1e-7 * reference, "{p:e} W vs {reference:e} W at {shifted} Hz");
    assert!((p - unshifted).abs() > 1e-4 * reference, "{p:e} W, 60 Hz gives {unshifted:e} W");
    // Energy: what the force brings in over the run is dissipated or stored (to the
    // round-off summed over 40,000 steps).
    assert!(t.energy_run.beam.relative_error() < 1e-7, "{:e}", t.energy_run.beam.relative_error());
}

#[test]
fn transient_harmonics_of_a_multi_sine_force_each_take_their_own_shift() {
    let dt = 1.0 / 60.0 / 400.0;
    let r = run(&format!(
        "{RAYLEIGH}[[load]]\nx = 0.3\n[load.force]\nkind = \"sines\"\n\
         components = [{{ amplitude = 2.0, frequency = 60.0 }}, {{ amplitude = 1.0, frequency = 180.0 }}]\n\
         [[analysis]]\ntype = \"transient\"\nsteps_per_period = 400\ntolerance = 1e-6\nmax_periods = 2000\n\
         [output]\nhdf5 = false\nplots = false\n"
    ));
    let t = transient(&r);
    let p_exact: f64 = [(2.0, 60.0), (1.0, 180.0)]
        .iter()
        .map(|&(a, f)| 0.5 * a * a * exact_mobility(newmark_shifted(f, dt), 0.3).re)
        .sum();
    let p = t.load_spectra[0].power_total;
    assert!(t.converged, "{} periods", t.periods_run);
    // The default mesh's discretisation error adds ~1e-8; the settling tolerance 1e-6.
    assert!((p - p_exact).abs() < 2e-6 * p_exact, "{p:e} W vs {p_exact:e} W");
}

#[test]
fn a_load_beside_an_actuator_superposes() {
    let act = "[[actuator]]\ntype = \"frame\"\nx_e = 0.3\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";
    let load = "[[load]]\nx = 0.5\n[load.force]\nkind = \"sine\"\namplitude = 0.3\nfrequency = 120.0\nphase = 0.4\n";
    let tail = "[[sensor]]\nname = \"at_load\"\nx = 0.5\n[[analysis]]\ntype = \"steady_state\"\nharmonics = 20\n\
                [output]\nhdf5 = false\nplots = false\n";
    // The frame stands on the beam in every run (at zero volts when only the load drives),
    // so each runs on the same structure.
    let idle = act.replace("amplitude = 12.0", "amplitude = 0.0");
    let both = run(&format!("{act}{load}{tail}"));
    let only_act = run(&format!("{act}{tail}"));
    let only_load = run(&format!("{idle}{load}{tail}"));
    let (b, a, l) = (steady(&both), steady(&only_act), steady(&only_load));
    // The load's period (1/120 s) divides the actuator's: the common period is 1/60 s.
    assert_eq!(b.period, 1.0 / 60.0);
    let v = |s: &SteadyStateResult| s.sensors[0].v.clone();
    let (vb, va, vl) = (v(b), v(a), v(l));
    let n = vb.len();
    let vmax = vb.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for j in 0..n {
        let sum = va[j] + vl[j];
        assert!((vb[j] - sum).abs() < 1e-9 * vmax, "sample {j}: {} vs {sum}", vb[j]);
    }
    // The load's power uses the velocity both cause; the frame's net power likewise.
    let fb = &b.loads[0].force;
    let p_direct: f64 = fb.iter().zip(&vb).map(|(f, v)| f * v).sum::<f64>() / n as f64;
    let p = b.load_spectra[0].power_total;
    assert!((p - p_direct).abs() < 1e-9 * p.abs().max(1e-30), "{p:e} vs {p_direct:e}");
    assert!(b.balance_error < 1e-9, "{:e}", b.balance_error);
    let fv = harmonics(&vb);
    assert!(fv[2].norm() > 0.0 && fv[1].norm() > 0.0, "both drives move the beam");
}

#[test]
fn a_slow_step_force_ends_at_the_static_deflection() {
    // A ramp to 10 N over 0.3 s, far slower than mode 1 (20 ms), then held: the beam ends
    // where statics puts it. Clamped–clamped beam, load at a: w(a) = F·a³·b³/(3·EI·L³).
    let r =
        run("[damping]\nkind = \"rayleigh_ratio\"\nzeta = 0.05\n[[load]]\nx = 0.2\n[load.force]\nkind = \"step\"\n\
         time = 0.0\nfrom = 0.0\nto = 10.0\nrise_time = 0.3\n[[sensor]]\nname = \"s\"\nx = 0.2\n\
         [[analysis]]\ntype = \"transient\"\ndt = 1e-4\nduration = 0.6\n[output]\nhdf5 = false\nplots = false\n");
    let t = transient(&r);
    let (a, b, l) = (0.2f64, 0.53f64, 0.73f64);
    let exact = 10.0 * a.powi(3) * b.powi(3) / (3.0 * EI * l.powi(3));
    let w_end = *t.loads[0].w.last().unwrap();
    assert!((w_end - exact).abs() < 1e-3 * exact, "{w_end:e} m vs static {exact:e} m");
    assert_eq!(t.loads[0].w, t.sensors[0].w, "the load's point is the sensor's");
    // Work done = strain energy stored + dissipated (the integrator's balance).
    assert!(t.energy_run.system.relative_error() < 1e-9, "{:e}", t.energy_run.system.relative_error());
    assert!(t.settling_estimate.is_nan(), "a non-periodic drive has no periodic state to settle to");
}

#[test]
fn chirp_and_series_forces_run_in_time() {
    let dir = tempfile::tempdir().unwrap();
    let csv: String = std::iter::once("time,force\n".to_string())
        .chain((0..=200).map(|j| format!("{},{}\n", j as f64 * 1e-3, (j as f64 * 0.05).sin())))
        .collect();
    std::fs::write(dir.path().join("f.csv"), csv).unwrap();
    for force in [
        "kind = \"chirp\"\namplitude = 1.0\nf_start = 20.0\nf_end = 200.0\nduration = 0.2\n",
        "kind = \"series\"\nfile = \"f.csv\"\nvoltage_column = \"force\"\n",
    ] {
        let text = format!(
            "[[load]]\nx = 0.25\n[load.force]\n{force}[[analysis]]\ntype = \"transient\"\ndt = 1e-4\nduration = 0.2\n\
             [output]\nhdf5 = false\nplots = false\n"
        );
        let lc = LoadedCase::from_str(&text, "c.toml", dir.path().to_path_buf()).unwrap();
        let r = run_case(&lc).unwrap();
        let t = transient(&r);
        assert_eq!(t.loads[0].force.len(), t.t.len());
        assert!(t.loads[0].v.iter().any(|v| v.abs() > 0.0), "{force}: the beam moves");
        assert!(t.energy_run.system.relative_error() < 1e-7, "{force}: {:e}", t.energy_run.system.relative_error());
    }
}

#[test]
fn loads_that_cannot_be_run_are_refused_before_any_solve() {
    let err = |text: &str| LoadedCase::from_str(text, "bad.toml", PathBuf::from(".")).err().map(|e| e.to_string());
    let sine = "[load.force]\nkind = \"sine\"\namplitude = 1.0\nfrequency = 60.0\n";
    let e = err(&format!("base = \"rigid\"\n[[load]]\nx = 0.2\n{sine}")).unwrap();
    assert!(e.contains("bad.toml") && e.contains("load[0]") && e.contains("rigid"), "{e}");
    let e = err(&format!("[[load]]\nx = 0.9\n{sine}")).unwrap();
    assert!(e.contains("load[0].x") && e.contains("outside the beam"), "{e}");
    let e = err("[[load]]\nx = 0.2\n[load.force]\nkind = \"sine\"\namplitude = 1.0\nfrequency = -1.0\n").unwrap();
    assert!(e.contains("load[0].force.frequency"), "{e}");
    let e = err(&format!("[[load]]\nname = \"a\"\nx = 0.2\n{sine}[[load]]\nname = \"a\"\nx = 0.3\n{sine}")).unwrap();
    assert!(e.contains("load[1].name") && e.contains("already"), "{e}");
    // Run-time refusals, caught by check's preflight too.
    let step = "[[load]]\nx = 0.2\n[load.force]\nkind = \"step\"\ntime = 0.0\nfrom = 0.0\nto = 1.0\n";
    let e = run_case(&case(&format!("{step}[[analysis]]\ntype = \"steady_state\"\n"))).unwrap_err().to_string();
    assert!(e.contains("non-periodic"), "{e}");
    let act =
        "[[actuator]]\ntype = \"frame\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";
    let odd = "[[load]]\nx = 0.2\n[load.force]\nkind = \"sine\"\namplitude = 1.0\nfrequency = 61.0\n";
    let e = run_case(&case(&format!("{act}{odd}[[analysis]]\ntype = \"steady_state\"\n"))).unwrap_err().to_string();
    assert!(e.contains("load[0].force") && e.contains("common period"), "{e}");
}

#[test]
fn a_reduced_model_carries_the_load() {
    let text = |reduction: &str| {
        format!(
            "[[load]]\nx = 0.2\n[load.force]\nkind = \"sine\"\namplitude = 1.0\nfrequency = 60.0\n\
             [[analysis]]\ntype = \"steady_state\"\nharmonics = 3\n{reduction}[output]\nhdf5 = false\nplots = false\n"
        )
    };
    let full = steady(&run(&text(""))).load_spectra[0].power_total;
    let red = steady(&run(&text("reduction = \"auto\"\n"))).load_spectra[0].power_total;
    assert!((red - full).abs() < 1e-4 * full, "reduced {red:e} W vs full {full:e} W");
}

#[test]
fn a_harmonic_analysis_applies_the_case_sine_loads() {
    // Two sine loads at 60 Hz with different phases: their relative phase decides how much
    // each puts in, so the harmonic analysis must take phases as the time domain does.
    let r = run("[[load]]\nx = 0.2\n[load.force]\nkind = \"sine\"\namplitude = 1.0\nfrequency = 60.0\nphase = 0.3\n\
         [[load]]\nx = 0.4\n[load.force]\nkind = \"sine\"\namplitude = 0.5\nfrequency = 60.0\nphase = 2.0\n\
         [[analysis]]\ntype = \"harmonic\"\n[analysis.frequencies]\nvalues = [60.0]\n\
         [[analysis]]\ntype = \"steady_state\"\n[output]\nhdf5 = false\nplots = false\n");
    let h = r.results.iter().find_map(|a| if let AnalysisResult::Harmonic(h) = a { Some(h) } else { None }).unwrap();
    let s = steady(&r);
    for j in 0..2 {
        // Equal within the round-off each states (a phase mistake would be of order one).
        let (ph, ps) = (h.input_power[0][j], s.load_spectra[j].power_total);
        let tol = (h.mesh_roundoff + s.mesh_roundoff).max(1e-12) * ph.abs().max(ps.abs());
        assert!((ph - ps).abs() <= tol, "load {j}: harmonic {ph:e} W, steady {ps:e} W, stated {tol:e}");
    }
    assert!(h.input_power[0][1] * h.input_power[0][0] != 0.0);
    let e = LoadedCase::from_str(
        "[[load]]\nx = 0.2\n[load.force]\nkind = \"step\"\ntime = 0.0\nfrom = 0.0\nto = 1.0\n\
         [[analysis]]\ntype = \"harmonic\"\n[analysis.frequencies]\nvalues = [60.0]\n",
        "h.toml",
        PathBuf::from("."),
    )
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("load[0].force.kind") && e.contains("sine"), "{e}");
}
