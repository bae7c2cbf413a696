//! Values that are admissible but unlikely to be meant: a slip of units (a 730 m beam where
//! 730 mm was meant, a modulus in GPa, a density in g/cm³), an actuator's foot where the
//! plate is held. They are not refused — a user may
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

const PLATE: [Range; 5] = [
    Range { field: "plate.length_x", low: 0.01, high: 20.0, hint: "lengths are in metres (600 mm is 0.6)" },
    Range { field: "plate.length_y", low: 0.01, high: 20.0, hint: "lengths are in metres (400 mm is 0.4)" },
    Range { field: "plate.thickness", low: 1e-5, high: 0.5, hint: "lengths are in metres (2 mm is 0.002)" },
    Range { field: "plate.youngs_modulus", low: 1e8, high: 1.5e12, hint: "moduli are in Pa (70 GPa is 7e10)" },
    Range { field: "plate.density", low: 100.0, high: 25_000.0, hint: "densities are in kg/m³ (aluminium is 2700)" },
];

/// Warnings for the values of `case` that look like a slip, each naming the field, and
/// for actuator feet where a plate is held.
pub fn warnings(case: &Case) -> Vec<String> {
    let mut w = slips(case);
    if let Some(p) = &case.plate {
        w.extend(held_feet(case, p));
    }
    w
}

/// The values of `case` that look like a slip of units, each naming the field.
fn slips(case: &Case) -> Vec<String> {
    let mut w = match (&case.plate, &case.imported) {
        (Some(p), _) => outside(&PLATE, [p.length_x, p.length_y, p.thickness, p.youngs_modulus, p.density]),
        // An imported model's matrices carry their own units.
        (None, Some(_)) => Vec::new(),
        (None, None) => beam_warnings(&case.beam),
    };
    for (i, a) in case.actuator.iter().enumerate() {
        w.extend(drive_warnings(&format!("actuator[{i}].voltage"), &a.voltage, "V", 1000.0));
    }
    w
}

/// The values outside their plausible `ranges`, each with its likely slip.
fn outside(ranges: &[Range], values: [f64; 5]) -> Vec<String> {
    ranges
        .iter()
        .zip(values)
        .filter(|(r, v)| !(r.low..=r.high).contains(v))
        .map(|(r, v)| format!("`{}` = {} lies outside {} to {}: {}", r.field, num(v), num(r.low), num(r.high), r.hint))
        .collect()
}

/// Actuator feet where the plate cannot move — on a clamped or simply supported edge, or on
/// a pinned or clamped point support — so that no power enters there: admissible (a leg
/// may stand on a support), but seldom meant for the stack.
fn held_feet(case: &Case, p: &super::schema::PlateSpec) -> Vec<String> {
    use super::schema::{EdgeSpec, PlateSupportKindSpec};
    let tol = 1e-9 * p.length_x.max(p.length_y);
    let near = |a: f64, b: f64| (a - b).abs() <= tol;
    let e = &p.edges;
    let edges = [
        ("x0", e.x0, 0.0, true),
        ("x1", e.x1, p.length_x, true),
        ("y0", e.y0, 0.0, false),
        ("y1", e.y1, p.length_y, false),
    ];
    let mut w = Vec::new();
    for (i, a) in case.actuator.iter().enumerate() {
        for (foot, at) in a.feet() {
            let crate::structure::Location::Plate { x, y } = at else { continue };
            let on_edge = edges
                .iter()
                .find(|(_, kind, c, along_x)| *kind != EdgeSpec::Free && near(if *along_x { x } else { y }, *c));
            let on_support = p
                .support
                .iter()
                .find(|s| s.kind != PlateSupportKindSpec::Spring && near(s.at[0], x) && near(s.at[1], y));
            let what = match (on_edge, on_support) {
                (Some((name, kind, ..)), _) => {
                    let kind = if *kind == EdgeSpec::Clamped { "clamped" } else { "simply supported" };
                    format!("on the {kind} edge `plate.edges.{name}`")
                }
                (None, Some(_)) => "on a point support (`plate.support`)".to_string(),
                (None, None) => continue,
            };
            w.push(format!(
                "`actuator[{i}]`: the {foot} foot at ({}, {}) m is {what}: the plate does not move there, so no \
                 power enters at it",
                num(round_to_9(x)),
                num(round_to_9(y))
            ));
        }
    }
    w
}

/// A beam's slips of units, and a beam too thick for Euler–Bernoulli theory.
fn beam_warnings(b: &super::schema::BeamSpec) -> Vec<String> {
    let mut w = outside(&BEAM, [b.length, b.width, b.thickness, b.youngs_modulus, b.density]);
    if b.thickness > 0.1 * b.length {
        w.push(format!(
            "`beam.thickness` is {:.0} % of `beam.length`: Euler–Bernoulli beams are slender (thickness below a \
             tenth of the length); shear and rotary inertia, left out here, matter at this ratio",
            100.0 * b.thickness / b.length
        ));
    }
    w
}

/// `e` (a case refused) with the values of `case` that look like a slip of units named
/// beside it: a refusal often follows from one elsewhere (a 730 m beam makes every stack
/// too stiff for it).
pub fn blame_slips(e: Error, case: &Case) -> Error {
    let slips = slips(case);
    match e {
        Error::Input { file, field, reason } if !slips.is_empty() => Error::Input {
            file,
            field,
            reason: format!("{reason}. This may follow from a slip of units elsewhere: {}", slips.join("; ")),
        },
        e => e,
    }
}

/// `v` to 9 significant digits: a foot's position computed from the stack's and the
/// direction carries round-off a reader need not see.
fn round_to_9(v: f64) -> f64 {
    format!("{v:.8e}").parse().unwrap_or(v)
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
