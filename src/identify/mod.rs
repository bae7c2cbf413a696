//! Parameter identification from measurements (physics spec §12).
//!
//! The chain the paper uses, one module per step:
//!
//! | step | module | gives |
//! |---|---|---|
//! | load and validate measurement CSVs | [`crate::io::measurement`] | [`crate::io::measurement::Measurement`] |
//! | d_p from two records with a constant voltage offset | [`dp`] | [`dp::DpEstimate`] |
//! | α, β, γ by particle swarm inside the class-I constraints | [`bouc_wen_fit`] (on [`pso`]) | [`bouc_wen_fit::BoucWenFit`] |
//! | impact test → H1 frequency response and coherence | [`frf`] | [`frf::Frf`] |
//! | modal fit (single mode, or rational-fraction polynomial) | [`modal_fit`] | [`modal_fit::Mode`] |
//! | k = m·ω_n², c = 2ζ·m·ω_n | [`modal_fit::dynamic_parameters`] | [`modal_fit::DynamicParameters`] |
//!
//! Every result type renders a case-file TOML fragment ready to paste with
//! `to_case_fragment()`; the field names are those of the case file (`k_p`, `c_p`, `m_p`,
//! `d_p`, `alpha`, `beta`, `gamma` in `[actuator.stack]` for the stack; `k_l`, `c_l` or
//! `k_l_right`, `c_l_right` as bare keys of the frame's `[[actuator]]` table for a leg).
//!
//! [`synth`] makes synthetic measurements from a case with the simulator's own models, and
//! [`commands`] runs each identification end to end (load, fit, fragment, plots), as the
//! `beamflow identify` and `beamflow synth` commands do.
//!
//! The methods, conventions and tolerances are described in `docs/identification.md`.

pub mod bouc_wen_fit;
pub mod dp;
pub mod frf;
pub mod modal_fit;
pub mod pso;
pub mod synth;

/// Case-file table that holds the stack's parameters.
pub const STACK_TABLE: &str = "actuator.stack";
/// Frame legs have no table of their own: `k_l`, `c_l` (and `k_l_right`, `c_l_right`) are
/// fields of the frame's `[[actuator]]` table itself.
pub const LEG_FIELDS: [&str; 4] = ["k_l", "c_l", "k_l_right", "c_l_right"];

/// Formats a value for a TOML fragment: six significant digits, shortest form that
/// round-trips that rounding, always a valid TOML float (`0.3`, `1.3e-7`, `30000000.0`).
pub(crate) fn toml_float(x: f64) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "nan".into()
        } else if x > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        };
    }
    let rounded: f64 = format!("{x:.5e}").parse().unwrap_or(x);
    let s = format!("{rounded:?}");
    // `{:?}` gives e.g. "0.3", "1.3e-7", "3e20", "30000000.0": all valid TOML floats.
    s
}

impl crate::io::measurement::Measurement {
    /// A comment block describing the record (no case fields: measurements are inputs).
    pub fn to_case_fragment(&self) -> String {
        format!(
            "# measurement {}: {} samples, dt = {} s, columns: {}\n",
            self.file,
            self.len(),
            toml_float(self.dt),
            self.quantities().iter().map(|q| q.name()).collect::<Vec<_>>().join(", ")
        )
    }
}

/// Serialises complex numbers as `[re, im]` pairs (num-complex is built without serde).
pub(crate) mod complex_serde {
    use num_complex::Complex64;
    use serde::ser::{SerializeSeq, Serializer};

    pub fn one<S: Serializer>(z: &Complex64, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(2))?;
        seq.serialize_element(&z.re)?;
        seq.serialize_element(&z.im)?;
        seq.end()
    }

    pub fn many<S: Serializer>(v: &[Complex64], s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(v.len()))?;
        for z in v {
            seq.serialize_element(&[z.re, z.im])?;
        }
        seq.end()
    }
}

/// Mean of a slice (0 for an empty one).
pub(crate) fn mean(x: &[f64]) -> f64 {
    if x.is_empty() {
        0.0
    } else {
        x.iter().sum::<f64>() / x.len() as f64
    }
}

/// Population standard deviation of a slice.
pub(crate) fn std_dev(x: &[f64]) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    let m = mean(x);
    (x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / x.len() as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn toml_float_is_valid_toml_and_rounds_to_six_digits() {
        for (x, want) in [(0.3, "0.3"), (1.3e-7, "1.3e-7"), (3.0e7, "30000000.0"), (0.02, "0.02")] {
            assert_eq!(toml_float(x), want);
        }
        for x in [1.2345678e-9, 0.30000000001, 3.0e7, -4.5e12, 1.0, 7.25e-3, 1e300] {
            let frag = format!("v = {}\n", toml_float(x));
            let t: toml::Table = toml::from_str(&frag).unwrap();
            let back = t["v"].as_float().unwrap();
            assert!(((back - x) / x).abs() < 1e-5, "{x} -> {frag}");
        }
    }

    #[test]
    fn a_measurement_fragment_is_a_comment() {
        use crate::io::measurement::{Measurement, Quantity};
        let m = Measurement::new("m", vec![0.0, 1e-3], vec![(Quantity::Force, vec![1.0, 2.0])]).unwrap();
        let frag = m.to_case_fragment();
        assert!(frag.starts_with('#') && frag.contains("dt = 0.001 s"), "{frag}");
    }

    #[test]
    fn mean_and_std() {
        assert_eq!(mean(&[1.0, 2.0, 3.0]), 2.0);
        assert!((std_dev(&[1.0, 3.0]) - 1.0).abs() < 1e-15);
    }
}
