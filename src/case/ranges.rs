//! The admissible ranges of a case's physical numbers.
//!
//! A finite, positive number can still be many orders of magnitude from anything a beam
//! and a piezo stack can be, and there the arithmetic of the analyses no longer holds:
//! E = 1e-300 Pa gives an energy balance off by 1e136, a 1e-12 Hz drive puts in less
//! power than the round-off of its own balance, a 1e300 V drive overflows. Each range
//! below spans every real material and drive by orders of magnitude either way (steel is
//! 2.1e11 Pa, the shipped drives are 12–48 V at 30–60 Hz) and keeps the analyses in the
//! range double precision carries; a value outside is refused with the range.

use super::schema::{AnalysisSpec, BeamSpec, BodySpec, Case};
use super::signal::SignalSpec;
use crate::error::{Error, Result};

/// Young's modulus (Pa): soft elastomers to beyond diamond.
pub const YOUNGS_MODULUS: (f64, f64) = (1e3, 1e13);
/// Density (kg/m³): foams to beyond osmium.
pub const DENSITY: (f64, f64) = (1.0, 1e5);
/// Poisson's ratio of an isotropic solid, bounds excluded (–).
pub const POISSON_RATIO: (f64, f64) = (-1.0, 0.5);
/// Beam length, width and thickness, plate thickness (m).
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
/// The stack's d_p (m/V): PZT stacks are 1e-10 to 1e-6 m/V; beyond these no stack is made,
/// and d_p·V at the largest drive would leave double precision.
pub const D_P: (f64, f64) = (1e-15, 1e-3);

/// Largest ratio of anything attached to the beam (a stiffness, mass, rotary inertia or
/// damper, at a point) to the beam's own scale of the same kind. The force through a
/// stiff element is its stiffness times the difference of two nearly equal motions, so it
/// carries a relative round-off of about 2.2e-16 × (its stiffness / the beam's): at 1e10
/// that is 2e-6, the least accuracy the results state. A mass ω²·m stands to the beam's
/// stiffness as m to the beam's mass at the beam's own frequencies, so masses, inertias
/// and dampers are held to the same ratio of the beam's mass, rotary inertia and
/// damping scale. The shipped cases stay below 1e7.
pub const BEAM_RATIO: f64 = 1e10;

/// The smallest element of a mesh file as a fraction of the mean element length: an
/// element's stiffness grows as 1/ℓ³, so one shorter than this is more than 1e9 times as
/// stiff as its neighbours and the factorisation loses the beam's motion to round-off.
pub const ELEMENT_FRACTION: f64 = 1e-3;

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

/// Refuses `x` outside [lo, hi] (in `unit`), naming `field` and the range.
pub fn within(file: &str, field: &str, x: f64, (lo, hi): (f64, f64), unit: &str) -> Result<()> {
    if (lo..=hi).contains(&x) {
        return Ok(());
    }
    Err(Error::input(file, field, outside(x, (lo, hi), unit)))
}

/// Why `x` is refused: it and the range [lo, hi], in `unit`.
fn outside(x: f64, (lo, hi): (f64, f64), unit: &str) -> String {
    format!("{} is outside the admissible range, {} to {}", num(x, unit), num(lo, ""), num(hi, unit))
}

fn magnitude(file: &str, field: &str, x: f64, max: f64, unit: &str) -> Result<()> {
    if x.abs() <= max {
        return Ok(());
    }
    Err(Error::input(file, field, outside(x, (-max, max), unit)))
}

/// The beam's own scales that what is attached to it is measured against, each with its
/// unit and what it is: bending stiffness EI/L³, rotational stiffness EI/L, mass ρAL,
/// rotary inertia ρAL·L² and the damping √(EI/L³ · ρAL).
struct BeamScales {
    stiffness: f64,
    rotational: f64,
    mass: f64,
    rotary: f64,
    damping: f64,
}

#[derive(Clone, Copy)]
enum Kind {
    Stiffness,
    Rotational,
    Mass,
    Rotary,
    Damping,
}

impl BeamScales {
    fn of(b: &BeamSpec) -> BeamScales {
        let ei = b.youngs_modulus * b.width * b.thickness.powi(3) / 12.0;
        let mass = b.density * b.width * b.thickness * b.length;
        let stiffness = ei / b.length.powi(3);
        BeamScales {
            stiffness,
            rotational: ei / b.length,
            mass,
            rotary: mass * b.length * b.length,
            damping: (stiffness * mass).sqrt(),
        }
    }

    /// The scale of `kind`, its unit and its name in messages.
    fn scale(&self, kind: Kind) -> (f64, &'static str, &'static str) {
        match kind {
            Kind::Stiffness => (self.stiffness, "N/m", "bending stiffness EI/L³"),
            Kind::Rotational => (self.rotational, "N·m/rad", "rotational stiffness EI/L"),
            Kind::Mass => (self.mass, "kg", "mass ρAL"),
            Kind::Rotary => (self.rotary, "kg·m²", "rotary inertia ρAL·L²"),
            Kind::Damping => (self.damping, "N·s/m", "damping scale √(EI/L³·ρAL)"),
        }
    }

    /// Refuses `x` beyond [`BEAM_RATIO`] times the beam's scale of its kind.
    fn attached(&self, file: &str, field: &str, x: f64, kind: Kind) -> Result<()> {
        self.ratio(file, field, x, kind, 0.0)
    }

    /// Refuses a stiffness that carries an actuator's force (its stack, its legs) beyond
    /// [`BEAM_RATIO`] times the beam's scale either way: a far softer one carries a force
    /// below the round-off of the beam's.
    fn carrier(&self, file: &str, field: &str, x: f64, kind: Kind) -> Result<()> {
        self.ratio(file, field, x, kind, 1.0 / BEAM_RATIO)
    }

    fn ratio(&self, file: &str, field: &str, x: f64, kind: Kind, floor: f64) -> Result<()> {
        let (scale, unit, what) = self.scale(kind);
        let (lo, hi) = (floor * scale, BEAM_RATIO * scale);
        if (lo..=hi).contains(&x) {
            return Ok(());
        }
        let side = if x > hi {
            format!("beyond {} times", num(BEAM_RATIO, ""))
        } else {
            format!("below {} times", num(floor, ""))
        };
        Err(Error::input(
            file,
            field,
            format!(
                "{}: {side} the beam's {what} ({}), the forces through it are lost to round-off beside the \
                 beam's and the results would not be accurate",
                outside(x, (rounded(lo), rounded(hi)), unit),
                num(rounded(scale), unit)
            ),
        ))
    }
}

/// `x` to four significant digits, for a limit derived from the case's numbers.
fn rounded(x: f64) -> f64 {
    format!("{x:.3e}").parse().unwrap_or(x)
}

/// Checks what the beam carries (point masses, springs, supports) and what each actuator
/// puts on it (stack, body, legs) against the beam's own scales ([`BEAM_RATIO`]).
fn attachments(case: &Case, file: &str) -> Result<()> {
    let s = BeamScales::of(&case.beam);
    let b = &case.beam;
    for (i, p) in b.point_mass.iter().enumerate() {
        s.attached(file, &format!("beam.point_mass[{i}].mass"), p.mass, Kind::Mass)?;
        s.attached(file, &format!("beam.point_mass[{i}].rotary_inertia"), p.rotary_inertia, Kind::Rotary)?;
    }
    for (i, k) in b.spring.iter().enumerate() {
        s.attached(file, &format!("beam.spring[{i}].stiffness"), k.stiffness, Kind::Stiffness)?;
        s.attached(file, &format!("beam.spring[{i}].damping"), k.damping, Kind::Damping)?;
    }
    for (i, sup) in b.support.iter().enumerate() {
        s.attached(file, &format!("beam.support[{i}].k_w"), sup.k_w.unwrap_or(0.0), Kind::Stiffness)?;
        s.attached(file, &format!("beam.support[{i}].k_theta"), sup.k_theta.unwrap_or(0.0), Kind::Rotational)?;
    }
    for (i, a) in case.actuator.iter().enumerate() {
        let f = |name: &str| format!("actuator[{i}].{name}");
        let st = &a.stack;
        s.carrier(file, &f("stack.k_p"), st.k_p, Kind::Stiffness)?;
        s.attached(file, &f("stack.c_p"), st.c_p, Kind::Damping)?;
        s.attached(file, &f("stack.m_p"), st.m_p, Kind::Mass)?;
        match &a.body {
            BodySpec::Inertial { m_t } => s.attached(file, &f("m_t"), *m_t, Kind::Mass)?,
            BodySpec::Frame(fr) => {
                s.attached(file, &f("m_b"), fr.m_b, Kind::Mass)?;
                s.attached(file, &f("j_b"), fr.j_b, Kind::Rotary)?;
                for (side, leg) in [("", fr.left), ("_right", fr.right)] {
                    s.carrier(file, &f(&format!("k_l{side}")), leg.k_l, Kind::Stiffness)?;
                    s.attached(file, &f(&format!("c_l{side}")), leg.c_l, Kind::Damping)?;
                }
            }
        }
    }
    Ok(())
}

/// Refuses a Poisson's ratio outside [`POISSON_RATIO`] (bounds excluded), naming `field`.
pub fn poisson_ratio(file: &str, field: &str, nu: f64) -> Result<()> {
    let (lo, hi) = POISSON_RATIO;
    if nu > lo && nu < hi {
        return Ok(());
    }
    Err(Error::input(file, field, format!("{nu}: an isotropic solid has −1 < ν < 0.5")))
}

/// Checks a mesh file's node coordinates or grid lines (`x`, m, the array `field`): no
/// element shorter than [`ELEMENT_FRACTION`] of the mean element length, naming the
/// entry that ends it.
pub fn mesh_lines(file: &str, field: &str, x: &[f64]) -> Result<()> {
    let n = x.len().saturating_sub(1);
    if n == 0 {
        return Ok(());
    }
    let mean = (x[n] - x[0]) / n as f64;
    let min = ELEMENT_FRACTION * mean;
    match x.windows(2).position(|w| w[1] - w[0] < min) {
        None => Ok(()),
        Some(i) => Err(Error::input(
            file,
            format!("{field}[{}]", i + 1),
            format!(
                "{} m is {} from the one before it; elements shorter than {} of the mean element length \
                 ({}), i.e. {}, are more than 1e9 times as stiff as their neighbours and the solve loses the \
                 structure's motion to round-off: merge or move the {}",
                x[i + 1],
                num(rounded(x[i + 1] - x[i]), "m"),
                num(ELEMENT_FRACTION, ""),
                num(rounded(mean), "m"),
                num(rounded(min), "m"),
                if field == "nodes" { "node" } else { "line" }
            ),
        )),
    }
}

/// Checks the values of a tabulated drive (`column` of the CSV `file`; `unit` V or N):
/// each within ±[`AMPLITUDE`], naming its row.
pub fn series_values(file: &str, column: &str, values: &[f64], unit: &str) -> Result<()> {
    match values.iter().position(|v| v.abs() > AMPLITUDE) {
        None => Ok(()),
        Some(i) => Err(Error::input(
            file,
            column,
            format!("row {}: {}", i + 1, outside(values[i], (-AMPLITUDE, AMPLITUDE), unit)),
        )),
    }
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
        within(file, &f("d_p"), s.d_p, D_P, "m/V")?;
        signal(file, &format!("actuator[{i}].voltage"), &a.voltage, "V")?;
    }
    attachments(case, file)?;
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

#[cfg(test)]
mod tests {
    use super::*;

    fn case(text: &str) -> Case {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn attachments_are_held_to_the_beams_own_scales() {
        let s = BeamScales::of(&BeamSpec::default());
        // The paper beam: EI/L³ ≈ 281 N/m, ρAL ≈ 1.43 kg.
        assert!((s.stiffness - 281.157).abs() < 0.01 && (s.mass - 1.4326).abs() < 1e-3);
        let with = |table: &str| {
            check(&case(&format!("[[actuator]]\ntype = \"frame\"\n{table}\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n")), "c.toml")
        };
        assert!(with("").is_ok(), "the defaults are far inside");
        assert!(with("k_l = 2.8e12").is_ok());
        let e = with("k_l = 2.9e12").unwrap_err().to_string();
        assert!(e.contains("actuator[0].k_l") && e.contains("2.812e12 N/m") && e.contains("EI/L³"), "{e}");
        let e = with("k_l = 2.7e-8").unwrap_err().to_string();
        assert!(e.contains("below 1e-10 times"), "{e}");
        let e = with("m_b = 2e10").unwrap_err().to_string();
        assert!(e.contains("actuator[0].m_b") && e.contains("1.433e10 kg"), "{e}");
    }

    #[test]
    fn mesh_elements_far_shorter_than_the_mean_are_refused() {
        assert!(mesh_lines("m.toml", "nodes", &[0.0, 0.5, 1.0]).is_ok());
        assert!(mesh_lines("m.toml", "nodes", &[0.0, 0.0006, 1.0]).is_ok(), "just above 1e-3 of the mean 0.5 m");
        let e = mesh_lines("m.toml", "nodes", &[0.0, 0.5, 0.5 + 1e-15, 1.0]).unwrap_err().to_string();
        assert!(e.contains("nodes[2]") && e.contains("m.toml") && e.contains("3.333e-4 m"), "{e}");
    }

    #[test]
    fn series_values_name_their_row() {
        assert!(series_values("v.csv", "voltage", &[0.0, -1e9, 1e9], "V").is_ok());
        let e = series_values("v.csv", "voltage", &[0.0, 1.0, -2e9], "V").unwrap_err().to_string();
        assert!(e.contains("row 3") && e.contains("-2e9 V") && e.contains("-1e9 to 1e9 V"), "{e}");
    }
}
