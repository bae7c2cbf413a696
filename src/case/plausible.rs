//! Values that are admissible but unlikely to be meant: a slip of units (a 730 m beam where
//! 730 mm was meant, a modulus in GPa, a density in g/cm³). They are not refused — a user may
//! mean them — but `check`, `run` and the report say what looks wrong and the likely slip.
//!
//! The ranges span the structures and actuators this tool is for (laboratory beams of
//! centimetres to metres, metals and polymers, stacks at tens to hundreds of volts); a value
//! outside them by a factor is almost always a unit written in the wrong scale.

use super::schema::Case;
use super::signal::SignalSpec;
use crate::error::Error;

/// (low, high) of a plausible value, what it is, and the slip to suspect outside it.
struct Range {
    field: &'static str,
    low: f64,
    high: f64,
    hint: &'static str,
}

const BEAM: [Range; 5] = [
    Range { field: "beam.length", low: 0.01, high: 20.0, hint: "lengths are in metres (730 mm is 0.73)" },
    Range { field: "beam.width", low: 1e-4, high: 2.0, hint: "lengths are in metres (50 mm is 0.05)" },
    Range { field: "beam.thickness", low: 1e-5, high: 0.5, hint: "lengths are in metres (5 mm is 0.005)" },
    Range { field: "beam.youngs_modulus", low: 1e8, high: 1.5e12, hint: "moduli are in Pa (210 GPa is 2.1e11)" },
    Range { field: "beam.density", low: 100.0, high: 25_000.0, hint: "densities are in kg/m³ (steel is 7850)" },
];

/// Warnings for the values of `case` that look like a slip, each naming the field.
pub fn warnings(case: &Case) -> Vec<String> {
    let b = &case.beam;
    let mut w: Vec<String> = BEAM
        .iter()
        .zip([b.length, b.width, b.thickness, b.youngs_modulus, b.density])
        .filter(|(r, v)| !(r.low..=r.high).contains(v))
        .map(|(r, v)| format!("`{}` = {} lies outside {} to {}: {}", r.field, num(v), num(r.low), num(r.high), r.hint))
        .collect();
    if b.thickness > 0.1 * b.length {
        w.push(format!(
            "`beam.thickness` is {:.0} % of `beam.length`: Euler–Bernoulli beams are slender (thickness below a \
             tenth of the length); shear and rotary inertia, left out here, matter at this ratio",
            100.0 * b.thickness / b.length
        ));
    }
    for (i, a) in case.actuator.iter().enumerate() {
        w.extend(drive_warnings(&format!("actuator[{i}].voltage"), &a.voltage, "V", 1000.0));
    }
    w
}

/// `e` (a case refused) with the values of `case` that look like a slip of units named
/// beside it: a refusal often follows from one elsewhere (a 730 m beam makes every stack
/// too stiff for it).
pub fn blame_slips(e: Error, case: &Case) -> Error {
    let slips = warnings(case);
    match e {
        Error::Input { file, field, reason } if !slips.is_empty() => Error::Input {
            file,
            field,
            reason: format!("{reason}. This may follow from a slip of units elsewhere: {}", slips.join("; ")),
        },
        e => e,
    }
}

/// A number as a person writes it: plain where that is short, else with an exponent.
fn num(v: f64) -> String {
    if v == 0.0 || (1e-3..1e6).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Warnings for a drive: frequencies far outside the structural band, amplitudes above
/// `high` (in `unit`).
fn drive_warnings(field: &str, s: &SignalSpec, unit: &str, high: f64) -> Vec<String> {
    let mut w = Vec::new();
    let freq = |name: &str, f: f64, w: &mut Vec<String>| {
        if !(0.1..=1e5).contains(&f) {
            w.push(format!(
                "`{field}.{name}` = {} Hz lies outside 0.1 Hz to 100 kHz: frequencies are in Hz, not rad/s or kHz",
                num(f)
            ));
        }
    };
    let amp = |a: f64, w: &mut Vec<String>| {
        if a.abs() > high {
            w.push(format!(
                "`{field}.amplitude` = {} {unit} is above {} {unit}: piezo stacks take tens to hundreds of volts",
                num(a),
                num(high)
            ));
        }
    };
    match s {
        SignalSpec::Sine { amplitude, frequency, .. } => {
            freq("frequency", *frequency, &mut w);
            amp(*amplitude, &mut w);
        }
        SignalSpec::Chirp { amplitude, f_start, f_end, .. } => {
            freq("f_start", *f_start, &mut w);
            freq("f_end", *f_end, &mut w);
            amp(*amplitude, &mut w);
        }
        _ => {}
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case(text: &str) -> Case {
        toml::from_str(text).unwrap()
    }

    const SINE: &str = "[[actuator]]\ntype = \"inertial\"\n[actuator.voltage]\nkind = \"sine\"\n";

    #[test]
    fn the_shipped_defaults_raise_nothing() {
        assert!(warnings(&case(&format!("{SINE}amplitude = 12.0\nfrequency = 60.0\n"))).is_empty());
    }

    #[test]
    fn a_beam_in_millimetres_is_named_with_the_likely_slip() {
        let w = warnings(&case(&format!("[beam]\nlength = 730.0\n{SINE}amplitude = 12.0\nfrequency = 60.0\n")));
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("`beam.length` = 730 lies outside 0.01 to 20") && w[0].contains("metres"), "{w:?}");
    }

    #[test]
    fn moduli_densities_frequencies_and_voltages_out_of_scale() {
        let text = format!(
            "[beam]\nyoungs_modulus = 210.0\ndensity = 7.85\n{SINE}amplitude = 12000.0\nfrequency = 377000.0\n"
        );
        let w = warnings(&case(&text)).join("\n");
        for needle in ["youngs_modulus", "in Pa", "density", "kg/m³", "frequency", "in Hz", "amplitude", "volts"] {
            assert!(w.contains(needle), "{needle}: {w}");
        }
    }

    #[test]
    fn a_refusal_names_the_slip_that_may_cause_it() {
        let c = case(&format!("[beam]\nlength = 730.0\n{SINE}amplitude = 12.0\nfrequency = 60.0\n"));
        let e = blame_slips(Error::input("c.toml", "actuator[0].stack.k_p", "too stiff"), &c).to_string();
        assert!(e.contains("too stiff. This may follow from a slip of units") && e.contains("beam.length"), "{e}");
    }

    #[test]
    fn a_stubby_beam_is_outside_euler_bernoulli() {
        let w = warnings(&case(&format!("[beam]\nthickness = 0.2\n{SINE}amplitude = 12.0\nfrequency = 60.0\n")));
        assert!(w.iter().any(|s| s.contains("slender")), "{w:?}");
    }
}
