//! The frequency-domain periodic steady state (hysteresis on) against the Newmark steady
//! state of the same case, with the Δt trend.

mod common;
use beamflow::analysis::steady_state;
use beamflow::analysis::transient::{self, TransientSettings};
use beamflow::assembly::System;
use beamflow::case::build_model;
use common::*;

#[test]
fn periodic_steady_state_matches_the_transient_as_dt_shrinks() {
    let lc = case(
        "[[actuator]]\ntype = \"frame\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n",
    );
    let model = build_model(&lc).unwrap().model;
    let sys = System::assemble(&model).unwrap();
    let fd = steady_state::run(&model, &sys, 31, 2048).unwrap();
    assert!(fd.balance_error < 1e-9, "frequency-domain energy balance {}", fd.balance_error);
    let mut errs = Vec::new();
    for n in [200, 400, 800] {
        let s = TransientSettings {
            dt: Some(1.0 / 60.0 / n as f64),
            harmonics: 9,
            tolerance: 1e-7,
            max_periods: 2000,
            ..Default::default()
        };
        let tr = transient::run(&model, &sys, &s).unwrap();
        assert!(tr.converged);
        let err = tr.mean_power.iter().zip(&fd.mean_power).map(|(a, b)| (a - b).abs() / b.abs()).fold(0.0f64, f64::max);
        errs.push(err);
    }
    // The Δt trend: second order down to the 1e-4 level.
    assert!(errs[2] < 1e-4, "point powers differ by {:e} at Δt = T/800 (trend {errs:?})", errs[2]);
    assert!(errs[0] / errs[1] > 3.0 && errs[1] / errs[2] > 3.0, "error must fall ~4× per halving: {errs:?}");
}
