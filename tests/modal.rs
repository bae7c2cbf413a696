//! Mode-resolved power flow: exact with all modes, symmetry, truncation.

mod common;
use beamflow::analysis::plan::calibrated_model;
use beamflow::analysis::steady_state;
use beamflow::assembly::System;
use common::*;

const SINE: &str = "[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";

#[test]
fn modal_shares_sum_to_point_powers_and_dissipation_with_all_modes() {
    let lc = case(&format!("[beam.mesh]\nelements = 60\n[[actuator]]\ntype = \"frame\"\n{SINE}"));
    let model = calibrated_model(&lc).unwrap();
    let sys = System::assemble(&model).unwrap();
    let mut ss = steady_state::run(&model, &sys, 5, 256).unwrap();
    ss.decompose_modes(&model, &sys, usize::MAX).unwrap();
    let m = ss.modal.as_ref().unwrap();
    for (l, p) in ss.mean_power.iter().enumerate() {
        let sum: f64 = m.point_power[l].iter().sum();
        assert!((sum - p).abs() < 1e-8 * p.abs(), "link {l}: Σ_r P = {sum:e} vs P = {p:e}");
        assert!(m.point_residual[l].abs() < 1e-8 * p.abs());
    }
    let diss: f64 = m.dissipation.iter().sum();
    assert!((diss - ss.beam_dissipation).abs() < 1e-8 * ss.beam_dissipation, "{diss} vs {}", ss.beam_dissipation);
    // Truncation leaves a residual that shrinks as modes are added.
    let res = |count| {
        let mut s = ss.clone();
        s.decompose_modes(&model, &sys, count).unwrap();
        s.modal.unwrap().point_residual.iter().map(|r| r.abs()).fold(0.0f64, f64::max)
    };
    let (r3, r10, r30) = (res(3), res(10), res(30));
    assert!(r3 > r10 && r10 > r30, "residuals {r3:e} {r10:e} {r30:e}");
}

#[test]
fn symmetric_frame_on_symmetric_beam_does_not_drive_antisymmetric_modes() {
    // Stack centred (e = 0), legs equal, frame centred at midspan.
    let lc = case(&format!("[beam.mesh]\nelements = 80\n[[actuator]]\ntype = \"frame\"\ne = 0.0\nx_e = 0.365\n{SINE}"));
    let model = calibrated_model(&lc).unwrap();
    let sys = System::assemble(&model).unwrap();
    let mut ss = steady_state::run(&model, &sys, 3, 64).unwrap();
    ss.decompose_modes(&model, &sys, 8).unwrap();
    let gf = &ss.modal.as_ref().unwrap().generalised_force_abs[0][1];
    let sym = gf[0].max(gf[2]);
    for r in [1, 3, 5, 7] {
        assert!(gf[r] < 1e-9 * sym, "antisymmetric mode {}: {:e} vs symmetric {:e}", r + 1, gf[r], sym);
    }
    assert!(gf[2] > 0.0 && gf[4] > 0.0);
}
