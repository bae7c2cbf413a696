//! The frequency-domain periodic steady state (hysteresis on) against the Newmark steady
//! state of the same case, with the Δt trend.

mod common;
use beamflow::analysis::plan::calibrated_model;
use beamflow::analysis::steady_state;
use beamflow::analysis::transient::{self, TransientSettings};
use beamflow::assembly::System;
use beamflow::case::LoadedCase;
use common::*;

#[test]
fn periodic_steady_state_matches_the_transient_as_dt_shrinks() {
    let lc = case(
        "[[actuator]]\ntype = \"frame\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n",
    );
    let model = calibrated_model(&lc).unwrap();
    let sys = System::assemble(&model).unwrap();
    let fd = steady_state::run(&model, &sys, 31, 2048).unwrap();
    assert!(fd.balance_error < 1e-9, "frequency-domain energy balance {}", fd.balance_error);
    let mut errs = Vec::new();
    for n in [200, 400, 800] {
        let s = TransientSettings {
            dt: Some(1.0 / 60.0 / n as f64),
            harmonics: Some(9),
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

/// Harmonics with no stack force are skipped, and only those: a sine drive through the
/// symmetric hysteresis excites odd harmonics only (even ones are left at exactly zero),
/// while a drive with a second harmonic and an offset gets its even harmonics and mean
/// solved, and each of them matches a linear single-harmonic solve of the same system.
#[test]
fn only_harmonics_without_force_are_skipped() {
    let sine = case(
        "[[actuator]]\ntype = \"inertial\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n",
    );
    let model = calibrated_model(&sine).unwrap();
    let sys = System::assemble(&model).unwrap();
    let r = steady_state::run(&model, &sys, 9, 512).unwrap();
    for k in 0..=9 {
        let qmax = r.q[k].iter().fold(0.0f64, |m, z| m.max(z.norm()));
        if k % 2 == 0 {
            assert_eq!(qmax, 0.0, "harmonic {k} of a sine drive should be skipped");
        } else {
            assert!(qmax > 0.0, "harmonic {k} must be solved");
        }
    }
    let mixed = case(
        "[[actuator]]\ntype = \"inertial\"\n[actuator.stack]\nhysteresis = false\n[actuator.voltage]\nkind = \"sines\"\n\
         offset = 3.0\ncomponents = [{ amplitude = 12.0, frequency = 60.0, phase = 0.0 }, \
         { amplitude = 4.0, frequency = 120.0, phase = 0.3 }]\n",
    );
    let model = calibrated_model(&mixed).unwrap();
    let sys = System::assemble(&model).unwrap();
    let r = steady_state::run(&model, &sys, 4, 256).unwrap();
    for k in [0usize, 1, 2] {
        let qmax = r.q[k].iter().fold(0.0f64, |m, z| m.max(z.norm()));
        assert!(qmax > 0.0, "harmonic {k} of the two-tone drive with offset must be solved");
    }
    // Linear stack: Q_k is the solve of the dynamic stiffness against b·F̂_p,k.
    let w0 = 2.0 * std::f64::consts::PI * 60.0;
    for k in [0usize, 2] {
        let (q, _) =
            steady_state::solve_harmonics(&sys, |_, j| if j == k { r.f_p[0][k] } else { Default::default() }, k, w0)
                .unwrap();
        let err = q[k].iter().zip(&r.q[k]).fold(0.0f64, |m, (a, b)| m.max((a - b).norm()));
        let scale = r.q[k].iter().fold(0.0f64, |m, z| m.max(z.norm()));
        assert!(err <= 1e-9 * scale, "harmonic {k}: {err:e} of {scale:e}");
    }
    assert_eq!(r.q[3].iter().fold(0.0f64, |m, z| m.max(z.norm())), 0.0, "no third harmonic in a linear two-tone drive");
}

/// Chosen harmonic count: every point's power with the chosen count is within the
/// tolerance of its own value in the exact periodic state (511 harmonics of forces sampled
/// eight times as finely, so that neither the harmonics left out nor the folding of the
/// higher ones onto the kept ones is in it), the reported estimate bounds that error at
/// every point, and a fixed count of 9 reports the ≈ 1e-3 it leaves out on the inertial
/// case.
#[test]
fn the_harmonic_count_meets_its_tolerance_against_511_harmonics() {
    use beamflow::analysis::steady_state::{run_counted, HarmonicCount};
    use beamflow::power::point::own_scales;
    for file in ["beam-inertial-12V-60Hz.toml", "beam-frame-12V-60Hz.toml"] {
        let lc = LoadedCase::load(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases").join(file)).unwrap();
        let model = calibrated_model(&lc).unwrap();
        let sys = System::assemble(&model).unwrap();
        let reference = steady_state::run(&model, &sys, 511, 8192).unwrap();
        let scales = own_scales(&reference.mean_power);
        let diff = |r: &steady_state::SteadyStateResult| {
            let points = r.mean_power.iter().zip(&reference.mean_power).zip(&scales);
            points.fold(0.0f64, |m, ((a, b), s)| m.max((a - b).abs() / s))
        };
        let chosen = run_counted(&model, &sys, HarmonicCount::Tolerance(1e-6), 1024).unwrap();
        let (d, est) = (diff(&chosen), chosen.truncation_estimate);
        eprintln!("{file}: {} harmonics, off by {d:.3e}, estimate {est:.3e}", chosen.harmonics);
        assert!(est <= 1e-6 && d <= est, "{file}: {d:e} with the estimate {est:e}");
        assert!(chosen.harmonics < 511);
        let nine = run_counted(&model, &sys, HarmonicCount::Fixed(9), 1024).unwrap();
        let (d9, est9) = (diff(&nine), nine.truncation_estimate);
        eprintln!("{file}: 9 harmonics, off by {d9:.3e}, estimate {est9:.3e}");
        assert!(d9 <= est9, "{file}: nine harmonics off by {d9:e}, estimate {est9:e}");
        if file.contains("inertial") {
            assert!(d9 > 1e-4, "the 11th, 19th, … harmonics matter near the beam's modes: {d9:e}");
        }
        // All 511 from 1024 samples: what is left is the folding of the harmonics beyond
        // 511, and the estimate bounds it too.
        let all = run_counted(&model, &sys, HarmonicCount::Fixed(511), 1024).unwrap();
        let (da, esta) = (diff(&all), all.truncation_estimate);
        eprintln!("{file}: 511 harmonics from 1024 samples, off by {da:.3e}, estimate {esta:.3e}");
        assert!(da <= esta, "{file}: all harmonics off by {da:e}, estimate {esta:e}");
    }
}
