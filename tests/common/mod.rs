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

/// The cells of one CSV line (RFC 4180 quotes, no line breaks inside a cell).
pub fn csv_cells(line: &str) -> Vec<String> {
    let (mut cells, mut cell, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cell.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => cells.push(std::mem::take(&mut cell)),
            _ => cell.push(c),
        }
    }
    cells.push(cell);
    cells
}

/// Checks a CSV text against the one header convention of every CSV file beamflow writes:
/// `name [unit]`, no unit for a text, count or index column, and a unit on every column
/// of real numbers. Returns what breaks it.
pub fn csv_header_convention(file: &str, text: &str) -> Result<(), String> {
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header = csv_cells(lines.next().ok_or(format!("{file}: empty"))?);
    let first = lines.next().map(csv_cells).unwrap_or_default();
    for (k, h) in header.iter().enumerate() {
        let unit = h.strip_suffix(']').and_then(|s| s.rsplit_once(" [")).map(|(name, unit)| (name, unit));
        match unit {
            Some((name, unit)) if !name.is_empty() && !unit.is_empty() && !name.contains('[') => {}
            Some(_) => return Err(format!("{file}: column `{h}` is not `name [unit]`")),
            None if h.contains('[') || h.contains(']') || h.trim_end().ends_with(')') => {
                return Err(format!("{file}: column `{h}` is not `name [unit]`"))
            }
            None => {
                let cell = first.get(k).map_or("", String::as_str);
                if cell.parse::<i64>().is_err() && cell.parse::<f64>().is_ok() {
                    return Err(format!("{file}: column `{h}` holds real numbers ({cell}) but names no unit"));
                }
            }
        }
    }
    Ok(())
}

/// The example plate of spec §16: aluminium 0.500 × 0.400 × 0.003 m.
pub mod example_plate {
    pub const LX: f64 = 0.5;
    pub const LY: f64 = 0.4;
    pub const H: f64 = 0.003;
    pub const E: f64 = 70e9;
    pub const NU: f64 = 0.33;
    pub const RHO: f64 = 2700.0;

    /// Its bending stiffness D = E·h³/(12(1 − ν²)) (N·m).
    pub fn d() -> f64 {
        E * H * H * H / (12.0 * (1.0 - NU * NU))
    }
}
