//! Harmonic analysis of the paper beam against an independent continuous-beam solution.

mod common;
use beamflow::analysis::harmonic::{self, PointForce};
use beamflow::analysis::plan::calibrated_model;
use beamflow::assembly::System;
use beamflow::beam::analytic::{beta_l_roots, End};
use common::*;
use num_complex::Complex64;
use std::f64::consts::PI;

/// Driving-point mobility of the continuous clamped–clamped beam with proportional damping
/// C = a₀M + a₁K, by the modal sum over `modes` modes.
fn continuous_mobility(x: f64, f_hz: f64, a0: f64, a1: f64, modes: usize) -> Complex64 {
    let w = 2.0 * PI * f_hz;
    let c = (EI / RHO_A).sqrt() / (L * L);
    let mut h = Complex64::default();
    for bl in beta_l_roots(End::Clamped, End::Clamped, modes).unwrap() {
        let wr = bl * bl * c;
        let phi = cc_mode(bl, x);
        h += phi * phi / Complex64::new(wr * wr - w * w, w * (a0 + a1 * wr * wr));
    }
    Complex64::new(0.0, w) * h
}

#[test]
fn mode_functions_are_mass_normalised() {
    // ∫ρA·W² dx = 1 by Simpson's rule, for a low and a high mode.
    let roots = beta_l_roots(End::Clamped, End::Clamped, 150).unwrap();
    for &bl in [roots[0], roots[149]].iter() {
        let n = 20000;
        let hstep = L / n as f64;
        let s: f64 = (0..=n)
            .map(|i| {
                let w = if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                w * cc_mode(bl, i as f64 * hstep).powi(2)
            })
            .sum::<f64>()
            * hstep
            / 3.0;
        assert!((RHO_A * s - 1.0).abs() < 1e-8, "βL = {bl}: {}", RHO_A * s);
        assert!(cc_mode(bl, L).abs() < 1e-8 * cc_mode(bl, 0.37 * L).abs().max(1e-3));
    }
}

#[test]
fn driving_point_power_matches_the_continuous_beam() {
    let (a0, a1) = (3.0, 2.0e-6);
    let lc = case(&format!(
        "[damping]\nkind = \"rayleigh\"\na0 = {a0}\na1 = {a1}\n[[sensor]]\nname = \"drive\"\nx = 0.150\n"
    ));
    let model = calibrated_model(&lc).unwrap();
    let sys = System::assemble(&model).unwrap();
    let freqs = [30.0, 60.0, 100.0, 180.0, 400.0];
    let res = harmonic::run(
        &model,
        &sys,
        &freqs,
        &[PointForce { at: beamflow::structure::Location::Beam { x: 0.150 }, amplitude: 1.0, phase: 0.0 }],
        None,
    )
    .unwrap();
    for (k, &f) in freqs.iter().enumerate() {
        let y = continuous_mobility(0.150, f, a0, a1, 400);
        let p_exact = 0.5 * y.re;
        let p = res.input_power[k][0];
        assert!(rel(p, p_exact) < 1e-4, "{f} Hz: FE {p:.9e} W vs continuous {p_exact:.9e} W ({:.2e})", rel(p, p_exact));
        let y_fe = res.mobility[k][0][0];
        assert!((y_fe - y).norm() < 1e-4 * y.norm(), "{f} Hz mobility {y_fe} vs {y}");
        // Energy balance: input = dissipation computed from ½ω²QᴴCQ.
        assert!(res.balance_error[k] < 1e-9, "{f} Hz balance error {}", res.balance_error[k]);
    }
}

#[test]
fn modal_damping_path_balances_and_agrees_with_rayleigh_equivalent() {
    // Modal ratios chosen equal to what Rayleigh gives at each mode: both paths must agree.
    let lc_r = case("[damping]\nkind = \"rayleigh\"\na0 = 3.0\na1 = 2.0e-6\n[beam.mesh]\nelements = 40\n");
    let model = calibrated_model(&lc_r).unwrap();
    let sys = System::assemble(&model).unwrap();
    let beam = model.beam().unwrap();
    let modes = beamflow::analysis::modes::bare_modes(&beamflow::structure::Structure::from(beam), 1000).unwrap();
    let ratios: Vec<f64> = modes.omega.iter().map(|w| model.rayleigh().ratio_at(*w)).collect();
    let forces = [PointForce { at: beamflow::structure::Location::Beam { x: 0.146 }, amplitude: 2.0, phase: 0.3 }];
    let direct = harmonic::run(&model, &sys, &[55.0, 170.0], &forces, None);
    let direct = direct.unwrap();
    let modal = harmonic::run(&model, &sys, &[55.0, 170.0], &forces, Some((&modes, &ratios))).unwrap();
    for k in 0..2 {
        assert!(
            rel(modal.total_power[k], direct.total_power[k]) < 1e-9,
            "{} vs {}",
            modal.total_power[k],
            direct.total_power[k]
        );
        assert!(modal.balance_error[k] < 1e-9);
    }
}
