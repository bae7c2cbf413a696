//! The admissible ranges of a case's physical numbers.
//!
//! A finite, positive number can still be many orders of magnitude from anything a beam
//! and a piezo stack can be, and there the arithmetic of the analyses no longer holds:
//! E = 1e-300 Pa gives an energy balance off by 1e136, a 1e-12 Hz drive puts in less
//! power than the round-off of its own balance, a 1e300 V drive overflows. Each range
//! below spans every real material and drive by orders of magnitude either way (steel is
//! 2.1e11 Pa, the shipped drives are 12–48 V at 30–60 Hz) and keeps the analyses in the
//! range double precision carries; a value outside is refused with the range.

use super::schema::{AnalysisSpec, Case};
use super::signal::SignalSpec;
use crate::error::{Error, Result};

/// Young's modulus (Pa): soft elastomers to beyond diamond.
pub const YOUNGS_MODULUS: (f64, f64) = (1e3, 1e13);
/// Density (kg/m³): foams to beyond osmium.
pub const DENSITY: (f64, f64) = (1.0, 1e5);
/// Beam length, width and thickness (m).
pub const DIMENSION: (f64, f64) = (1e-6, 1e3);
/// Drive and analysis frequencies (Hz): below, a drive is quasi-static and the power it
/// puts in is below the round-off of its own balance; above, Euler–Bernoulli theory and
/// the time step both stop meaning anything.
pub const FREQUENCY: (f64, f64) = (1e-3, 1e8);
/// |amplitude| and |offset| of a drive (V for a voltage, N for a force).
pub const AMPLITUDE: f64 = 1e9;
/// |phase| of a drive (rad): it counts modulo 2π, and beyond this its last digit is
/// below 1e-10 rad no longer.
pub const PHASE: f64 = 1e6;
/// |h0|, the stack's initial hysteretic displacement (m).
pub const H0: f64 = 1.0;
/// Bouc–Wen α (–) and |β|, |γ| (1/V).
pub const BOUC_WEN: f64 = 1e6;

/// A number as a reader writes it: plain near 1, in powers of ten far from it; with its
/// unit, if it has one.
fn num(x: f64, unit: &str) -> String {
    let n = if x == 0.0 || (1e-3..1e6).contains(&x.abs()) { format!("{x}") } else { format!("{x:e}") };
    if unit.is_empty() {
        n
    } else {
        format!("{n} {unit}")
    }
}

fn within(file: &str, field: &str, x: f64, (lo, hi): (f64, f64), unit: &str) -> Result<()> {
    if (lo..=hi).contains(&x) {
        return Ok(());
    }
    let range = format!("{} to {}", num(lo, ""), num(hi, unit));
    Err(Error::input(file, field, format!("{} is outside the admissible range, {range}", num(x, unit))))
}

fn magnitude(file: &str, field: &str, x: f64, max: f64, unit: &str) -> Result<()> {
    if x.abs() <= max {
        return Ok(());
    }
    let range = format!("{} to {}", num(-max, ""), num(max, unit));
    Err(Error::input(file, field, format!("{} is outside the admissible range, {range}", num(x, unit))))
}

/// Checks a drive's amplitudes, offsets, phases and frequencies (`unit` of its amplitude).
pub fn signal(file: &str, field: &str, s: &SignalSpec, unit: &str) -> Result<()> {
    let f = |name: &str| format!("{field}.{name}");
    match s {
        SignalSpec::Sine { amplitude, frequency, offset, phase } => {
            magnitude(file, &f("amplitude"), *amplitude, AMPLITUDE, unit)?;
            magnitude(file, &f("offset"), *offset, AMPLITUDE, unit)?;
            magnitude(file, &f("phase"), *phase, PHASE, "rad")?;
            within(file, &f("frequency"), *frequency, FREQUENCY, "Hz")
        }
        SignalSpec::Sines { offset, components } => {
            magnitude(file, &f("offset"), *offset, AMPLITUDE, unit)?;
            for (i, c) in components.iter().enumerate() {
                let g = |name: &str| format!("{field}.components[{i}].{name}");
                magnitude(file, &g("amplitude"), c.amplitude, AMPLITUDE, unit)?;
                magnitude(file, &g("phase"), c.phase, PHASE, "rad")?;
                within(file, &g("frequency"), c.frequency, FREQUENCY, "Hz")?;
            }
            Ok(())
        }
        SignalSpec::Chirp { amplitude, f_start, f_end, offset, .. } => {
            magnitude(file, &f("amplitude"), *amplitude, AMPLITUDE, unit)?;
            magnitude(file, &f("offset"), *offset, AMPLITUDE, unit)?;
            within(file, &f("f_start"), *f_start, FREQUENCY, "Hz")?;
            within(file, &f("f_end"), *f_end, FREQUENCY, "Hz")
        }
        SignalSpec::Step { from, to, .. } => {
            magnitude(file, &f("from"), *from, AMPLITUDE, unit)?;
            magnitude(file, &f("to"), *to, AMPLITUDE, unit)
        }
        SignalSpec::Series { .. } => Ok(()),
    }
}

/// Checks every range of `case` (its other constraints are [`Case::validate`]'s).
pub fn check(case: &Case, file: &str) -> Result<()> {
    let b = &case.beam;
    within(file, "beam.youngs_modulus", b.youngs_modulus, YOUNGS_MODULUS, "Pa")?;
    within(file, "beam.density", b.density, DENSITY, "kg/m³")?;
    for (name, x) in [("length", b.length), ("width", b.width), ("thickness", b.thickness)] {
        within(file, &format!("beam.{name}"), x, DIMENSION, "m")?;
    }
    for (i, a) in case.actuator.iter().enumerate() {
        let s = &a.stack;
        let f = |name: &str| format!("actuator[{i}].stack.{name}");
        magnitude(file, &f("h0"), s.h0, H0, "m")?;
        within(file, &f("alpha"), s.alpha, (0.0, BOUC_WEN), "")?;
        magnitude(file, &f("beta"), s.beta, BOUC_WEN, "1/V")?;
        magnitude(file, &f("gamma"), s.gamma, BOUC_WEN, "1/V")?;
        signal(file, &format!("actuator[{i}].voltage"), &a.voltage, "V")?;
    }
    for (i, l) in case.load.iter().enumerate() {
        signal(file, &format!("load[{i}].force"), &l.force, "N")?;
    }
    for (i, an) in case.analysis.iter().enumerate() {
        if let AnalysisSpec::Harmonic { frequencies, force, .. } = an {
            let f = format!("analysis[{i}].frequencies");
            for (k, &v) in frequencies.values.iter().enumerate() {
                within(file, &format!("{f}.values[{k}]"), v, FREQUENCY, "Hz")?;
            }
            for (name, v) in [("start", frequencies.start), ("stop", frequencies.stop)] {
                if let Some(v) = v {
                    within(file, &format!("{f}.{name}"), v, FREQUENCY, "Hz")?;
                }
            }
            for (j, p) in force.iter().enumerate() {
                magnitude(file, &format!("analysis[{i}].force[{j}].amplitude"), p.amplitude, AMPLITUDE, "N")?;
                magnitude(file, &format!("analysis[{i}].force[{j}].phase"), p.phase, PHASE, "rad")?;
            }
        }
    }
    Ok(())
}
