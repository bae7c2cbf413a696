//! Shared helpers for the integration tests.
#![allow(dead_code)]

use beamflow::case::LoadedCase;
use std::path::PathBuf;

/// Parses case text as if it were a file named `name` in the repository's `cases/`.
pub fn case(text: &str) -> LoadedCase {
    LoadedCase::from_str(text, "test.toml", PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases"))
        .expect("test case must be valid")
}

/// The default (paper) beam, clamped at both ends, in `elements` equal elements with
/// Rayleigh damping C = a₀·M + a₁·K given outright, so no modal analysis is run to set it.
pub fn bare_beam(elements: usize, [a0, a1]: [f64; 2]) -> LoadedCase {
    case(&format!("[beam.mesh]\nelements = {elements}\n[damping]\nkind = \"rayleigh\"\na0 = {a0}\na1 = {a1}\n"))
}

/// The error message a bad case text produces.
pub fn case_error(text: &str) -> String {
    match LoadedCase::from_str(text, "bad.toml", PathBuf::from(".")) {
        Ok(lc) => match beamflow::analysis::plan::calibrated_model(&lc) {
            Ok(_) => panic!("case was accepted but should be rejected:\n{text}"),
            Err(e) => e.to_string(),
        },
        Err(e) => e.to_string(),
    }
}

/// Relative difference.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The paper beam's length (m), bending stiffness EI (N·m²) and mass per length ρA (kg/m).
pub const L: f64 = 0.73;
pub const EI: f64 = 210e9 * 0.05 * 0.005 * 0.005 * 0.005 / 12.0;
pub const RHO_A: f64 = 7850.0 * 0.05 * 0.005;

/// Mass-normalised clamped–clamped mode with root βL = `bl` at x, evaluated without the
/// cancellation of cosh − sinh for high modes:
/// W = [e^{−z}(1+σ)/2 + e^{z}(1−σ)/2 − cos z + σ·sin z]/√(ρA·L), z = βx.
pub fn cc_mode(bl: f64, x: f64) -> f64 {
    let z = bl * x / L;
    let em = (-bl).exp();
    let denom = 1.0 - em * em - 2.0 * bl.sin() * em; // 2(sinh βL − sin βL)·e^{−βL}
    let sigma = 1.0 - 2.0 * (bl.cos() - bl.sin() - em) * em / denom;
    let grow = (bl.cos() - bl.sin() - em) * (z - bl).exp() / denom; // e^{z}(1−σ)/2
    ((-z).exp() * (1.0 + sigma) / 2.0 + grow - z.cos() + sigma * z.sin()) / (RHO_A * L).sqrt()
}

/// The error message `run` gives for case text that loads but cannot run.
pub fn case_error_run(text: &str) -> String {
    let lc = LoadedCase::from_str(text, "bad.toml", PathBuf::from(".")).expect("the case loads");
    match beamflow::app::runner::run_case(&lc) {
        Ok(_) => panic!("case ran but should be refused:\n{text}"),
        Err(e) => e.to_string(),
    }
}
