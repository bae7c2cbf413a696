//! Modal reduction (bare-beam modes + residual-flexibility correction + actuator bodies)
//! against the full model, on the paper's beam cases.

mod common;
use beamflow::analysis::case_run::{AnalysisResult, CaseRun};
use beamflow::analysis::plan::calibrated_model;
use beamflow::analysis::reduction::{self, Cutoff, ReductionSettings};
use beamflow::app::runner::run_case;
use beamflow::assembly::{Model, System};
use beamflow::case::{AnalysisSpec, LoadedCase, ReductionSpec};
use common::*;
use std::path::PathBuf;

const PAPER_CASES: [&str; 2] = ["beam-inertial-12V-60Hz.toml", "beam-frame-12V-60Hz.toml"];

fn cases_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases")
}

fn paper_text(name: &str) -> String {
    std::fs::read_to_string(cases_dir().join(name)).unwrap()
}

/// The paper case with `reduction = …` added to every analysis.
fn with_reduction(text: &str, reduction: &str) -> String {
    let out = text
        .replace("type = \"steady_state\"\n", &format!("type = \"steady_state\"\nreduction = {reduction}\n"))
        .replace("type = \"transient\"\n", &format!("type = \"transient\"\nreduction = {reduction}\n"));
    assert_eq!(out.matches("reduction =").count(), 2, "both analyses of the paper case get the option");
    out
}

fn run_text(text: &str, name: &str) -> CaseRun {
    let lc = LoadedCase::from_str(text, name, cases_dir()).unwrap();
    run_case(&lc).unwrap()
}

fn model_and_system(name: &str) -> (Model, System) {
    let lc = LoadedCase::load(&cases_dir().join(name)).unwrap();
    let model = calibrated_model(&lc).unwrap();
    let sys = System::assemble(&model).unwrap();
    (model, sys)
}

/// Max relative error of the point powers (frequency-domain steady state, 9 harmonics)
/// of a reduction with the given cut-off.
fn error_at(model: &Model, full: &System, hz: f64, static_correction: bool) -> f64 {
    let rs = ReductionSettings { cutoff: Cutoff::Hz(hz), static_correction, error_estimate: true, modal_damping: None };
    let (red, _) = reduction::reduce(model, full, &rs, hz).unwrap();
    beamflow::analysis::steady_state::estimate_reduction_error(model, full, &red, 9, 1024).unwrap().max_relative_error
}

fn sci(v: &[f64]) -> String {
    v.iter().map(|x| format!("{x:.2e}")).collect::<Vec<_>>().join(", ")
}

fn max_rel(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| rel(*x, *y)).fold(0.0, f64::max)
}

#[test]
fn auto_reduction_matches_the_full_model_in_both_domains_on_the_paper_cases() {
    for name in PAPER_CASES {
        // A reduced steady state keeps 9 harmonics; the full one is asked for the same.
        let text = paper_text(name).replace("type = \"steady_state\"\n", "type = \"steady_state\"\nharmonics = 9\n");
        let full = run_text(&text, name);
        let red = run_text(&with_reduction(&text, "\"auto\""), name);
        let [AnalysisResult::SteadyState(fs), AnalysisResult::Transient(ft)] = &full.results[..] else {
            panic!("paper case runs steady_state then transient")
        };
        let [AnalysisResult::SteadyState(rs), AnalysisResult::Transient(rt)] = &red.results[..] else {
            panic!("paper case runs steady_state then transient")
        };
        assert!(fs.reduction.is_none() && ft.reduction.is_none());
        // Frequency domain.
        let e_ss = max_rel(&rs.mean_power, &fs.mean_power);
        let e_net = max_rel(&rs.net_power, &fs.net_power);
        // Time domain, same Δt and steady-state criterion.
        let e_tr = max_rel(&rt.mean_power, &ft.mean_power);
        let e_tr_net = max_rel(&rt.net_power, &ft.net_power);
        eprintln!("{name}: steady state {e_ss:.2e} (net {e_net:.2e}), transient {e_tr:.2e} (net {e_tr_net:.2e})");
        assert!(e_ss < 1e-3 && e_net < 1e-3, "{name}: steady-state point powers off by {e_ss:e}");
        assert!(e_tr < 1e-3 && e_tr_net < 1e-3, "{name}: transient point powers off by {e_tr:e}");
        assert_eq!(rt.periods_run, ft.periods_run, "{name}: same settling");

        // The result carries its basis and error estimate.
        // The steady state analyses its 9 harmonics, the transient the 10 its step resolves.
        for (rep, h) in [(rs.reduction.as_ref().unwrap(), rs.harmonics), (rt.reduction.as_ref().unwrap(), rt.harmonics)]
        {
            let cutoff = 5.0 * h as f64 * 60.0;
            assert!((rep.cutoff_hz - cutoff).abs() < 1e-9, "auto = 5 × the highest analysed harmonic of 60 Hz");
            // Clamped–clamped modes: 10 below 2700 Hz, 11 below 3000 Hz (f₁₁ ≈ 2910 Hz).
            assert_eq!(rep.modes_kept, if h == 9 { 10 } else { 11 }, "modes below {cutoff} Hz");
            assert!(rep.mode_frequencies_hz.iter().all(|&f| f <= cutoff));
            assert!(rep.first_discarded_mode_hz.unwrap() > cutoff);
            let feet = red.system.links.iter().filter(|l| l.foot_dof.is_some()).count();
            assert_eq!(rep.residual_vectors, feet, "one residual vector per foot");
            assert_eq!(rep.reduced_dofs, rep.modes_kept + feet + red.system.dofs.bodies.iter().flatten().count());
            let err = rep.error.as_ref().expect("error estimate is on by default");
            assert!(err.max_relative_error < 1e-3);
            assert_eq!(err.full_mean_power.len(), fs.mean_power.len());
        }
        // In the frequency domain the estimate is the actual difference.
        let est = rs.reduction.as_ref().unwrap().error.as_ref().unwrap().max_relative_error;
        assert!((est - e_ss).abs() <= 1e-12 * e_ss.max(1e-300) + 1e-15, "estimate {est:e} vs actual {e_ss:e}");
    }
}

#[test]
fn static_correction_matters_and_the_error_falls_as_the_cutoff_rises() {
    for name in PAPER_CASES {
        let (model, full) = model_and_system(name);
        let with: Vec<f64> =
            [300.0, 600.0, 1000.0, 2700.0].iter().map(|&hz| error_at(&model, &full, hz, true)).collect();
        let without: Vec<f64> =
            [600.0, 2700.0, 6000.0, 20000.0].iter().map(|&hz| error_at(&model, &full, hz, false)).collect();
        eprintln!("{name}: with correction (300, 600, 1000, 2700 Hz) {}", sci(&with));
        eprintln!("{name}: without (600, 2700, 6000, 20000 Hz) {}", sci(&without));
        for w in with.windows(2).chain(without.windows(2)) {
            assert!(w[1] < 0.5 * w[0], "{name}: error must fall as the cut-off rises: {w:?}");
        }
        // At the automatic cut-off (2700 Hz) the correction is worth orders of magnitude.
        assert!(with[3] < 1e-6, "{name}: corrected error {:e}", with[3]);
        assert!(without[1] > 100.0 * with[3], "{name}: {:e} without vs {:e} with", without[1], with[3]);
    }
    // The frame's stiff legs on a beam whose local flexibility the modes miss: without the
    // correction the point powers are simply wrong at 5× the highest harmonic.
    let (model, full) = model_and_system("beam-frame-12V-60Hz.toml");
    assert!(error_at(&model, &full, 2700.0, false) > 0.1);
}

#[test]
fn reduced_model_is_exact_in_statics_only_with_the_correction() {
    // The feet carry all actuator forces, so span(Φ_r, Ψ) holds the exact static response.
    let (model, full) = model_and_system("beam-frame-12V-60Hz.toml");
    let static_stretches = |sys: &System| -> Vec<f64> {
        let mut f = vec![0.0; sys.n()];
        for &(d, c) in &sys.drives[0] {
            f[d] += 100.0 * c;
        }
        let q = sys.static_solve(&f).unwrap();
        sys.links.iter().map(|l| l.stretch.iter().map(|&(d, c)| c * q[d]).sum()).collect()
    };
    let exact = static_stretches(&full);
    for (sc, bound_ok) in [(true, true), (false, false)] {
        let rs = ReductionSettings {
            cutoff: Cutoff::Hz(2700.0),
            static_correction: sc,
            error_estimate: false,
            modal_damping: None,
        };
        let (red, _) = reduction::reduce(&model, &full, &rs, 2700.0).unwrap();
        let e = max_rel(&static_stretches(&red), &exact);
        eprintln!("static stretches, static_correction = {sc}: {e:.2e}");
        assert_eq!(e < 1e-7, bound_ok, "static_correction = {sc}: relative error {e:e}");
        // Bare-beam blocks are diagonal: M_beam = I, K_beam = diag(ω²).
        let nb = red.n() - red.dofs.bodies.iter().flatten().count();
        for i in 0..nb {
            assert!((red.m_beam.get(i, i) - 1.0).abs() < 1e-9);
            for j in 0..nb {
                if i != j {
                    assert!(red.m_beam.get(i, j).abs() < 1e-9 && red.k_beam.get(i, j) == 0.0);
                }
            }
        }
    }
    // In the full model a foot is one DOF, as before.
    for l in &full.links {
        assert_eq!(l.foot, l.foot_dof.map(|d| vec![(d, 1.0)]).unwrap_or_default());
    }
}

#[test]
fn sensors_and_bodies_come_out_of_a_reduced_run() {
    let text = "[beam]\n[[sensor]]\nname = \"mid\"\nx = 0.365\n[[actuator]]\ntype = \"frame\"\nx_e = 0.150\n\
                [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n\
                [[analysis]]\ntype = \"steady_state\"\nharmonics = 5\n";
    let full = run_text(text, "sensor.toml");
    let red = run_text(&text.replace("harmonics = 5\n", "harmonics = 5\nreduction = \"auto\"\n"), "sensor.toml");
    let (AnalysisResult::SteadyState(f), AnalysisResult::SteadyState(r)) = (&full.results[0], &red.results[0]) else {
        panic!()
    };
    let amp = |x: &[f64]| x.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    assert!(rel(amp(&r.sensors[0].a), amp(&f.sensors[0].a)) < 1e-4, "mid-span acceleration");
    for (rb, fb) in r.bodies.iter().zip(&f.bodies) {
        assert_eq!(rb.dof, fb.dof);
        assert!(rel(amp(&rb.q), amp(&fb.q)) < 1e-4, "body {}", rb.dof);
    }
    assert!(r.balance_error < 1e-8, "energy balance of the reduced model: {:e}", r.balance_error);
}

#[test]
fn cutoff_below_the_first_mode_is_an_error_naming_file_and_field() {
    let text = with_reduction(&paper_text("beam-frame-12V-60Hz.toml"), "{ modes_up_to_hz = 30.0 }");
    let lc = LoadedCase::from_str(&text, "bad.toml", cases_dir()).unwrap();
    let msg = run_case(&lc).unwrap_err().to_string();
    eprintln!("{msg}");
    assert!(msg.contains("bad.toml"), "{msg}");
    assert!(msg.contains("analysis[0].reduction.modes_up_to_hz"), "{msg}");
    assert!(msg.contains("first natural frequency") && msg.contains("49.88 Hz"), "{msg}");

    // A factor that lands below the first mode: 0.05 × 540 Hz = 27 Hz.
    let text = with_reduction(&paper_text("beam-frame-12V-60Hz.toml"), "{ factor = 0.05 }");
    let lc = LoadedCase::from_str(&text, "bad.toml", cases_dir()).unwrap();
    let msg = run_case(&lc).unwrap_err().to_string();
    assert!(msg.contains("bad.toml") && msg.contains("analysis[0].reduction.factor"), "{msg}");
}

#[test]
fn malformed_reduction_entries_are_rejected_when_the_case_loads() {
    let base = "[[actuator]]\ntype = \"inertial\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\n\
                frequency = 60.0\n[[analysis]]\ntype = \"transient\"\n";
    for (entry, field, words) in [
        ("reduction = { modes_up_to_hz = -5.0 }", "analysis[0].reduction.modes_up_to_hz", "positive"),
        ("reduction = { factor = 0.0 }", "analysis[0].reduction.factor", "positive"),
        ("reduction = { modes_up_to_hz = 2000.0, factor = 5.0 }", "analysis[0].reduction", "not both"),
    ] {
        let msg = case_error(&format!("{base}{entry}\n"));
        assert!(msg.contains("bad.toml") && msg.contains(field) && msg.contains(words), "{entry}: {msg}");
    }
    let msg = case_error(&format!("{base}reduction = \"fast\"\n"));
    assert!(msg.contains("bad.toml") && msg.contains("reduction") && msg.contains("\"auto\""), "{msg}");
    let msg = case_error(&format!("{base}reduction = {{ modes_to = 2000.0 }}\n"));
    assert!(msg.contains("bad.toml") && msg.contains("modes_to"), "{msg}");
    let msg = case_error(&format!("base = \"rigid\"\n{base}reduction = \"auto\"\n"));
    assert!(msg.contains("analysis[0].reduction") && msg.contains("rigid"), "{msg}");
}

#[test]
fn reduction_field_survives_a_toml_round_trip() {
    // Sweeps build cases in code and serialise them back to TOML.
    for entry in ["\"auto\"", "{ modes_up_to_hz = 2500.0 }", "{ factor = 8.0, static_correction = false }"] {
        let text = with_reduction(&paper_text("beam-inertial-12V-60Hz.toml"), entry);
        let lc = LoadedCase::from_str(&text, "a.toml", cases_dir()).unwrap();
        let again = LoadedCase::from_case(lc.case.clone(), "b.toml", cases_dir()).unwrap();
        let spec = |c: &beamflow::case::Case| -> Vec<Option<ReductionSpec>> {
            c.analysis
                .iter()
                .map(|a| match a {
                    AnalysisSpec::Transient { reduction, .. } | AnalysisSpec::SteadyState { reduction, .. } => {
                        reduction.clone()
                    }
                    _ => None,
                })
                .collect()
        };
        assert_eq!(spec(&again.case), spec(&lc.case), "{entry} → {}", again.text);
        assert!(spec(&lc.case).iter().all(Option::is_some));
    }
}

/// A plate above the dense eigensolver's limit reduces on its sparse factor: exactly the
/// modes below the cut-off (as many as a modes analysis finds there, at the same
/// frequencies) and the first above it, and the reduced steady state's point powers and
/// sensor response agree with the full model's.
#[test]
fn a_large_plate_reduces_on_its_modes_below_the_cutoff() {
    let text = std::fs::read_to_string(cases_dir().join("plate-inertial.toml")).unwrap();
    let base = text.split("[[analysis]]").next().unwrap().replace("elements = [20, 16]", "elements = [30, 24]");
    let cutoff = 2000.0;
    let reduced = run_text(
        &format!(
            "{base}[[analysis]]\ntype = \"steady_state\"\nharmonics = 9\n\
             reduction = {{ modes_up_to_hz = {cutoff}, error_estimate = false }}\n\
             [[analysis]]\ntype = \"steady_state\"\nharmonics = 9\n[[analysis]]\ntype = \"modes\"\ncount = 60\n"
        ),
        "plate.toml",
    );
    let [AnalysisResult::SteadyState(r), AnalysisResult::SteadyState(f), AnalysisResult::Modes(m)] =
        &reduced.results[..]
    else {
        panic!("two steady states and a modes analysis")
    };
    let report = r.reduction.as_ref().expect("a reduced run reports its basis");
    assert!(report.full_dofs > beamflow::analysis::modes::DENSE_EIGEN_LIMIT, "{}", report.full_dofs);
    let below: Vec<f64> = m.frequencies_hz.iter().copied().filter(|&f| f <= cutoff).collect();
    assert!(below.len() < m.frequencies_hz.len(), "the modes analysis reaches past the cut-off");
    assert_eq!(report.modes_kept, below.len());
    for (a, b) in report.mode_frequencies_hz.iter().zip(&below) {
        assert!((a - b).abs() <= 1e-9 * b, "{a} Hz against {b} Hz");
    }
    let next = report.first_discarded_mode_hz.expect("the first mode above the cut-off");
    assert!((next - m.frequencies_hz[below.len()]).abs() <= 1e-9 * next, "{next}");
    let d = max_rel(&r.mean_power, &f.mean_power);
    assert!(d <= 1e-6, "reduced against full: {d:e}");
}

/// A reduced steady state whose default nine harmonics leave more than the tolerance out
/// (a stiff corner takes little power, so harmonics far above the drive matter to it)
/// raises its count on the same reduction to the one the tolerance asks for, and agrees
/// with the full model's powers (its own automatic count) within the reduction's stated
/// error, where nine harmonics did not.
#[test]
fn a_reduced_steady_state_raises_its_harmonics_to_the_tolerance() {
    let plate = "[plate]\nlength_x = 0.6\nlength_y = 0.4\nthickness = 0.002\nyoungs_modulus = 70e9\n\
                 poisson_ratio = 0.33\ndensity = 2700.0\n[plate.mesh]\nelements = [12, 8]\n[plate.edges]\n\
                 x0 = \"clamped\"\nx1 = \"free\"\ny0 = \"simply_supported\"\ny1 = \"simply_supported\"\n\
                 [[actuator]]\ntype = \"frame\"\nname = \"frame\"\nat = [0.4, 0.25]\ndirection = 120.0\n\
                 [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 120.0\n\
                 [[actuator]]\ntype = \"inertial\"\nname = \"corner\"\nat = [0.01, 0.01]\n\
                 [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 120.0\n";
    let run = run_text(
        &format!(
            "{plate}[[analysis]]\ntype = \"steady_state\"\nreduction = \"auto\"\n\
             [[analysis]]\ntype = \"steady_state\"\n"
        ),
        "corner.toml",
    );
    let [AnalysisResult::SteadyState(r), AnalysisResult::SteadyState(f)] = &run.results[..] else {
        panic!("two steady states")
    };
    let nine = run_text(
        &format!("{plate}[[analysis]]\ntype = \"steady_state\"\nreduction = \"auto\"\nharmonics = 9\n"),
        "nine.toml",
    );
    let AnalysisResult::SteadyState(nine) = &nine.results[0] else { panic!("a steady state") };
    assert!(nine.truncation_estimate > 1e-6, "nine harmonics leave out only {:e}", nine.truncation_estimate);
    assert!(
        r.harmonics > 9 && r.truncation_estimate <= 1e-6,
        "{} harmonics leave {:e}",
        r.harmonics,
        r.truncation_estimate
    );
    let stated = r.reduction.as_ref().and_then(|rep| rep.error.as_ref()).expect("an error estimate").max_relative_error;
    let d = max_rel(&r.mean_power, &f.mean_power);
    assert!(d <= stated * 1.01 + 2e-6, "reduced against full: {d:e}, stated {stated:e}");
    assert!(max_rel(&nine.mean_power, &f.mean_power) > 10.0 * d, "nine harmonics were as close");
}
