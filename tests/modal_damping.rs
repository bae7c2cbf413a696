//! Modal damping (ζ_r per bare-beam mode) outside the harmonic analysis: the periodic
//! steady state runs it in the complete modal basis, a transient on its modal reduction.
//!
//! The independent check is Rayleigh damping, which *is* modal damping with
//! ζ_r = a₀/(2ω_r) + a₁ω_r/2: the same ratios given as a modal list must reproduce the
//! Rayleigh results, which come from the assembled C = a₀M + a₁K on the physical DOFs.

mod common;
use beamflow::analysis::case_run::{AnalysisResult, CaseRun};
use beamflow::analysis::plan::calibrated_model;
use beamflow::analysis::reduction::{self, Cutoff, ReductionSettings};
use beamflow::app::runner::run_case;
use beamflow::assembly::System;
use beamflow::case::LoadedCase;
use common::*;
use std::path::PathBuf;

fn cases_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases")
}

/// The paper's frame case (Fig. 15) without its analyses, then `analyses`.
fn frame_case(damping: &str, analyses: &str) -> String {
    let text = std::fs::read_to_string(cases_dir().join("beam-frame-12V-60Hz.toml")).unwrap();
    let head = &text[..text.find("[[analysis]]").expect("paper case has analyses")];
    format!("{head}{damping}\n{analyses}")
}

fn run_text(text: &str) -> CaseRun {
    run_case(&LoadedCase::from_str(text, "modal.toml", cases_dir()).unwrap()).unwrap()
}

fn list(v: &[f64]) -> String {
    format!("[{}]", v.iter().map(|x| format!("{x:e}")).collect::<Vec<_>>().join(", "))
}

fn max_rel(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter().zip(b).map(|(x, y)| (x - y).abs() / scale).fold(0.0, f64::max)
}

const STEADY: &str = "[[analysis]]\ntype = \"steady_state\"\nharmonics = 9\n";

#[test]
fn modal_ratios_equal_to_rayleigh_reproduce_the_rayleigh_steady_state() {
    let rayleigh = run_text(&frame_case("", STEADY));
    let (a0, a1) = (rayleigh.model.rayleigh().a0, rayleigh.model.rayleigh().a1);
    assert!(a0 > 0.0 && a1 > 0.0, "the paper case is Rayleigh-damped");
    // Every bare-beam mode gets its Rayleigh-equivalent ratio.
    let modes = beamflow::analysis::modes::bare_modes(
        &beamflow::structure::Structure::from(rayleigh.model.beam().unwrap()),
        usize::MAX,
    )
    .unwrap();
    let ratios: Vec<f64> = modes.omega.iter().map(|w| a0 / (2.0 * w) + a1 * w / 2.0).collect();
    let modal = run_text(&frame_case(&format!("[damping]\nkind = \"modal\"\nratios = {}\n", list(&ratios)), STEADY));
    let [AnalysisResult::SteadyState(r)] = &rayleigh.results[..] else { panic!("one steady state") };
    let [AnalysisResult::SteadyState(m)] = &modal.results[..] else { panic!("one steady state") };

    let e_point = max_rel(&m.mean_power, &r.mean_power);
    let e_net = max_rel(&m.net_power, &r.net_power);
    let e_diss = rel(m.beam_dissipation, r.beam_dissipation);
    eprintln!("point powers {e_point:.2e}, net {e_net:.2e}, beam dissipation {e_diss:.2e}");
    // The reduced model's floor with every mode kept is ~1e-8 (solve::modal_basis).
    assert!(e_point < 1e-6 && e_net < 1e-6 && e_diss < 1e-6, "{e_point:e} {e_net:e} {e_diss:e}");
    assert!(m.balance_error < 1e-8, "power in = beam dissipation: {:e}", m.balance_error);
    assert!(m.reduction.is_none(), "the complete modal basis is the full model, not a reduction");

    // The mode-resolved tables split the same dissipation the same way.
    let (tm, tr) = (m.modal.as_ref().unwrap(), r.modal.as_ref().unwrap());
    let e_modal = max_rel(&tm.dissipation, &tr.dissipation);
    let e_point_modal = max_rel(&tm.point_power.concat(), &tr.point_power.concat());
    eprintln!("modal dissipation {e_modal:.2e}, modal point powers {e_point_modal:.2e}");
    assert!(e_modal < 1e-6 && e_point_modal < 1e-6);
}

#[test]
fn reduced_modal_damping_is_the_rayleigh_matrix_in_modal_coordinates() {
    let lc = LoadedCase::load(&cases_dir().join("beam-frame-12V-60Hz.toml")).unwrap();
    let model = calibrated_model(&lc).unwrap();
    let (a0, a1) = (model.rayleigh().a0, model.rayleigh().a1);
    let full = System::assemble(&model).unwrap();
    let settings = |modal_damping| ReductionSettings {
        cutoff: Cutoff::HarmonicFactor(5.0),
        static_correction: true,
        error_estimate: false,
        modal_damping,
    };
    let hz = reduction::cutoff_hz(&model, &settings(None), 9).unwrap();
    let (with_rayleigh, report) = reduction::reduce(&model, &full, &settings(None), hz).unwrap();
    assert!(report.residual_vectors > 0, "the check covers the residual vectors too");

    // The same beam without Rayleigh damping, given as modal ratios at the reduced
    // coordinates' frequencies (modes, then the residual vectors in order).
    let mut undamped = model.clone();
    undamped.damping = beamflow::assembly::Damping::None;
    let bare_c = System::assemble(&undamped).unwrap();
    let omegas: Vec<f64> = report
        .mode_frequencies_hz
        .iter()
        .chain(&report.residual_frequencies_hz)
        .map(|f| 2.0 * std::f64::consts::PI * f)
        .collect();
    let ratios: Vec<f64> = omegas.iter().map(|w| a0 / (2.0 * w) + a1 * w / 2.0).collect();
    let (with_modal, _) = reduction::reduce(&undamped, &bare_c, &settings(Some(ratios)), hz).unwrap();

    let n = with_rayleigh.n();
    assert_eq!(with_modal.n(), n);
    // The Rayleigh side is projected, a₁·Tᵀ·K·T, and for the residual vectors K·ψ is a
    // difference of large numbers (the reason the reduction takes K_beam from the formula):
    // its round-off shows there at a few cond(K)·ε (cond(K) ≈ 2e9 for 200 elements, so
    // ≈ 1e-6 of the diagonal: 2e-7 and 1.1e-6 for two meshes that differ only in the last
    // bit of the element lengths); in the modes' block only the eigenvectors'
    // orthogonality round-off is left, relative to the small damping of the lowest modes
    // (1e-11 to 6e-10 for those two meshes).
    let modes = report.modes_kept;
    for (name, a, b) in [("C", &with_modal.c, &with_rayleigh.c), ("C_beam", &with_modal.c_beam, &with_rayleigh.c_beam)]
    {
        let (mut worst_modes, mut worst) = (0.0f64, 0.0f64);
        for i in 0..n {
            for j in 0..n {
                let scale = (b.get(i, i) * b.get(j, j)).abs().sqrt();
                let d = (a.get(i, j) - b.get(i, j)).abs() / scale;
                worst = worst.max(d);
                if i < modes && j < modes {
                    worst_modes = worst_modes.max(d);
                }
            }
        }
        eprintln!("{name}: largest difference {worst:.2e} (modes' block {worst_modes:.2e}) of the diagonal");
        assert!(worst_modes <= 1e-8 && worst <= 1e-5, "{name} differs by {worst:e} ({worst_modes:e} in the modes)");
    }
    // A ratio list that differs changes the damping: the comparison can fail.
    let (other, _) = reduction::reduce(&undamped, &bare_c, &settings(Some(vec![0.02])), hz).unwrap();
    assert!((other.c.get(0, 0) - with_rayleigh.c.get(0, 0)).abs() > 1e-3 * with_rayleigh.c.get(0, 0));
}

#[test]
fn a_modal_damped_reduced_transient_settles_onto_its_steady_state_and_balances() {
    // Ratios that no Rayleigh pair gives (ζ up, down, up again with frequency).
    let damping = "[damping]\nkind = \"modal\"\nratios = [0.02, 0.04, 0.01, 0.02]\n";
    let dt = 1.0 / 60.0 / 400.0;
    let analyses =
        format!("{STEADY}\n[[analysis]]\ntype = \"transient\"\nharmonics = 9\ndt = {dt:e}\ntolerance = 1e-8\nreduction = \"auto\"\n");
    let run = run_text(&frame_case(damping, &analyses));
    let [AnalysisResult::SteadyState(ss), AnalysisResult::Transient(tr)] = &run.results[..] else {
        panic!("steady state then transient")
    };
    let e = max_rel(&tr.mean_power, &ss.mean_power);
    // The frame's net power is a small difference of its points' powers: measure it against
    // those.
    let scale = ss.mean_power.iter().fold(0.0f64, |m, p| m.max(p.abs()));
    let e_net = (tr.net_power[0] - ss.net_power[0]).abs() / scale;
    eprintln!("transient vs steady state: point powers {e:.2e}, net {e_net:.2e} ({} periods)", tr.periods_run);
    // Settled far enough that what is left of the start-up (mode 1 decays over ≈ 8 periods)
    // is below the Δt² error of average acceleration at Δt = T/400.
    assert!(tr.converged, "settled in {} periods", tr.periods_run);
    assert!(e < 1e-3 && e_net < 1e-3, "{e:e} {e_net:e}");
    // The beam's energy balance over the run, its dissipation being the modal damping's
    // (system dissipation minus the links' dampers).
    let balance = tr.energy_run.beam.relative_error();
    eprintln!("beam energy balance over the run {balance:.2e}");
    assert!(balance < 1e-9, "energy balance of the damped beam: {balance:e}");
    assert!(tr.energy_run.beam.dissipated > 0.0);
    let last = tr.energy_last_period.beam.relative_error();
    assert!(last < 1e-9, "energy balance over the last period: {last:e}");
    let e_diss = rel(tr.beam_dissipation, tr.beam_input_power);
    assert!(e_diss < 1e-3, "settled: dissipation {:e} against input {:e}", tr.beam_dissipation, tr.beam_input_power);
    // The error estimate compares with the same modal damping on the complete basis.
    let est = tr.reduction.as_ref().unwrap().error.as_ref().unwrap();
    assert!(est.max_relative_error < 1e-3, "{:e}", est.max_relative_error);

    // With another ratio for mode 2 the powers move: the damping reaches the run.
    let other = run_text(&frame_case("[damping]\nkind = \"modal\"\nratios = [0.02, 0.01]\n", STEADY));
    let [AnalysisResult::SteadyState(o)] = &other.results[..] else { panic!("one steady state") };
    assert!(max_rel(&o.mean_power, &ss.mean_power) > 1e-3);
}

/// A steady-state sweep of a modal-damped case runs in the complete modal basis, grouped or
/// case by case, and with Rayleigh-equivalent ratios it reproduces the Rayleigh sweep.
#[test]
fn a_steady_state_sweep_applies_modal_damping() {
    use beamflow::sweep::{self, RunOptions};
    let dir = tempfile::tempdir().unwrap();
    let rayleigh_text = frame_case("", STEADY);
    let rayleigh = run_text(&rayleigh_text);
    let (a0, a1) = (rayleigh.model.rayleigh().a0, rayleigh.model.rayleigh().a1);
    let modes = beamflow::analysis::modes::bare_modes(
        &beamflow::structure::Structure::from(rayleigh.model.beam().unwrap()),
        usize::MAX,
    )
    .unwrap();
    let ratios: Vec<f64> = modes.omega.iter().map(|w| a0 / (2.0 * w) + a1 * w / 2.0).collect();
    let modal_text = frame_case(&format!("[damping]\nkind = \"modal\"\nratios = {}\n", list(&ratios)), STEADY);
    std::fs::write(dir.path().join("rayleigh.toml"), &rayleigh_text).unwrap();
    std::fs::write(dir.path().join("modal.toml"), &modal_text).unwrap();
    // One placement (the mesh, hence the modes, stays that of the ratios), two frequencies.
    let spec = |base: &str| {
        format!("base = \"{base}\"\n[[parameter]]\npath = \"actuator[0].voltage.frequency\"\nvalues = [45.0, 60.0]\n")
    };
    let load = |name: &str, base: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, spec(base)).unwrap();
        sweep::load(&path).unwrap()
    };
    let opts = RunOptions { threads: Some(1), ..Default::default() };
    let r = sweep::run(&load("r.sweep.toml", "rayleigh.toml"), &opts).unwrap();
    let m = sweep::run(&load("m.sweep.toml", "modal.toml"), &opts).unwrap();
    let m_ref = sweep::run(&load("m.sweep.toml", "modal.toml"), &RunOptions { reference: true, ..opts }).unwrap();
    for ((a, b), c) in m.rows.iter().zip(&r.rows).zip(&m_ref.rows) {
        let e = max_rel(&a.mean_power, &b.mean_power);
        eprintln!("{} Hz: modal vs Rayleigh sweep, point powers {e:.2e}", a.inputs[0]);
        assert!(e < 1e-6, "{e:e}");
        assert!(rel(a.beam_dissipation, b.beam_dissipation) < 1e-6);
        // The grouped fast path and steady_state::run on the same basis agree.
        assert!(max_rel(&a.mean_power, &c.mean_power) < 1e-12);
    }
    // The 60 Hz row is the case run directly.
    let [AnalysisResult::SteadyState(direct)] = &run_text(&modal_text).results[..] else { panic!("one steady state") };
    assert!(max_rel(&m.rows[1].mean_power, &direct.mean_power) < 1e-12);
}
