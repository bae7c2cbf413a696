//! The coupled harmonic solve of a placement's reduced system (`solve::modal_coupling`)
//! against the dense factor of the same system, and where it declines.

use beamflow::analysis::plan::calibrated_model;
use beamflow::analysis::reduction::{self, Cutoff, ReductionSettings, SharedReduction};
use beamflow::analysis::steady_state;
use beamflow::assembly::{Model, System};
use beamflow::case::LoadedCase;
use beamflow::solve::dynamic_stiffness::DynamicStiffness;
use beamflow::solve::modal_coupling::ModalCoupling;
use num_complex::Complex64;
use std::f64::consts::PI;
use std::path::PathBuf;

fn model(text: &str) -> Model {
    calibrated_model(&LoadedCase::from_str(text, "plate.toml", PathBuf::from(".")).unwrap()).unwrap()
}

fn shipped(name: &str) -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases").join(name);
    std::fs::read_to_string(path).unwrap()
}

/// The two frames of the shipped placement study at new positions (feet between nodes),
/// the second turned 40°.
fn two_frames() -> Model {
    let text = shipped("plate-two-frames.toml")
        .replace("at = [0.15, 0.20]", "at = [0.137, 0.213]")
        .replace("at = [0.35, 0.20]\ndirection = 90.0", "at = [0.341, 0.166]\ndirection = 40.0");
    model(&text)
}

/// The shipped inertial actuator on the plate's uniform grid.
fn inertial() -> Model {
    // Without its sensor: the dense reference below solves the system without its basis.
    let text = shipped("plate-inertial.toml")
        .replace("elements = [20, 16]\n", "elements = [20, 16]\nthrough_points = false\n")
        .replace("[[sensor]]\nname = \"probe\"\nat = [0.31, 0.27]\n", "");
    model(&text)
}

/// The case's system on a shared basis built for it, as a placement study builds it.
fn reduced(m: &Model) -> System {
    let settings = ReductionSettings {
        cutoff: Cutoff::HarmonicFactor(reduction::AUTO_FACTOR),
        static_correction: true,
        error_estimate: false,
        modal_damping: None,
    };
    let cutoff = reduction::cutoff_hz(m, &settings, 9).unwrap();
    SharedReduction::new(m, &settings, cutoff).unwrap().system(m).unwrap().0
}

fn norm(x: &[Complex64]) -> f64 {
    x.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt()
}

/// A right-hand side on every coordinate, the drives' patterns among them.
fn load(sys: &System) -> Vec<Complex64> {
    let mut b: Vec<Complex64> = (0..sys.n())
        .map(|i| Complex64::new(((i * 7 + 3) % 11) as f64 - 5.0, ((i * 5 + 1) % 13) as f64 - 6.0))
        .collect();
    for (a, d) in sys.drives.iter().enumerate() {
        for &(i, c) in d {
            b[i] += Complex64::new(100.0 * c, -40.0 * c * a as f64);
        }
    }
    b
}

/// At the drive's odd harmonics, at retained modes' own frequencies (where a mode's
/// dynamic stiffness is its damping alone) and between them, the coupled solve agrees
/// with the dense factor's to 1e-10 of the solution.
fn agrees_with_the_dense_factor(m: &Model, drive_hz: f64) {
    let sys = reduced(m);
    let mut coupled = ModalCoupling::of(&sys).expect("a placement on a shared modal basis takes the coupled form");
    let mut dense = DynamicStiffness::of(&sys);
    let mut omegas: Vec<f64> = (1..=9).step_by(2).map(|k| 2.0 * PI * drive_hz * k as f64).collect();
    omegas.extend((0..6).map(|r| (sys.k_beam.get(r, r) / sys.m_beam.get(r, r)).sqrt()));
    omegas.extend([0.0, 2.0 * PI * 0.77 * drive_hz]);
    let b = load(&sys);
    // All frequencies at once (their residuals in one pass over the matrices) solve as one
    // at a time does, bit for bit.
    let mut together: Vec<Vec<Complex64>> = omegas.iter().map(|_| b.clone()).collect();
    let mut views: Vec<&mut [Complex64]> = together.iter_mut().map(|x| &mut x[..]).collect();
    let settled = coupled.solve_at(&omegas, &mut views).unwrap();
    for ((&w, x), settled) in omegas.iter().zip(&together).zip(settled) {
        coupled.factorize(w).unwrap();
        let mut alone = b.clone();
        assert_eq!(coupled.solve_in_place(&mut alone), settled, "ω = {w} rad/s settles alike");
        assert!(alone == *x, "ω = {w} rad/s: solved together, the solution's bits differ");
    }
    for w in omegas {
        dense.factorize(w).unwrap();
        coupled.factorize(w).unwrap();
        let (mut xd, mut xc) = (b.clone(), b.clone());
        dense.solve_in_place(&mut xd);
        assert!(coupled.solve_in_place(&mut xc), "the refinement settles at ω = {w} rad/s");
        let diff: Vec<Complex64> = xd.iter().zip(&xc).map(|(a, b)| a - b).collect();
        let e = norm(&diff) / norm(&xd);
        assert!(e < 1e-10, "ω = {w} rad/s: the coupled solve is {e:e} off the dense factor's");
    }
    // And a whole steady state: the same powers (the system without its basis takes the
    // dense factor).
    let solved = |sys: &System| steady_state::run(m, sys, 9, 256).unwrap();
    let fast = solved(&sys);
    let mut dense_sys = sys.clone();
    dense_sys.projection = None;
    let slow = solved(&dense_sys);
    for (a, b) in fast.mean_power.iter().zip(&slow.mean_power) {
        assert!((a - b).abs() <= 1e-10 * b.abs().max(1e-30), "point power {a} against {b}");
    }
}

#[test]
fn two_frames_on_a_reduced_plate_solve_as_the_dense_factor_does() {
    agrees_with_the_dense_factor(&two_frames(), 140.0);
}

#[test]
fn an_inertial_actuator_on_a_reduced_plate_solves_as_the_dense_factor_does() {
    agrees_with_the_dense_factor(&inertial(), 83.0);
}

/// Only a placement on a shared modal basis takes the coupled form: a full system does
/// not, nor a structure whose damping the modes do not diagonalise (a grounded damper).
#[test]
fn other_systems_keep_the_dense_factor() {
    let m = two_frames();
    assert!(ModalCoupling::of(&System::assemble(&m).unwrap()).is_none(), "a full system");
    let beam = model(&shipped("beam-frame-12V-60Hz.toml"));
    assert!(ModalCoupling::of(&System::assemble(&beam).unwrap()).is_none(), "the beam");
    let damper = shipped("plate-two-frames.toml").replacen(
        "[[actuator]]",
        "[[plate.spring]]\nat = [0.2, 0.15]\nstiffness = 0.0\ndamping = 5.0\n\n[[actuator]]",
        1,
    );
    let sys = reduced(&model(&damper));
    assert!(ModalCoupling::of(&sys).is_none(), "a grounded damper couples the modes");
}
