//! The coupled system's figures: its transfer functions (magnitude and phase of the
//! velocity at each response point per unit input) and its mode shapes beside the bare
//! beam's.

use super::plot::{save, Dest};
use super::plot::{LinePlot, MultiPanel, Series};
use crate::analysis::harmonic::HarmonicResult;
use crate::analysis::modes::ModesResult;
use crate::assembly::Model;
use crate::error::Result;
use std::path::PathBuf;

/// Coupled modes drawn, one panel each.
const SHAPES: usize = 6;
/// Below this shape correlation a coupled mode has no bare-beam counterpart worth drawing
/// beside it (it lives mostly in the actuators).
const PAIR_MAC: f64 = 0.5;

/// What a transfer input is, in words: a unit force at a link's foot, or an actuator's
/// unit stack force F_p (`<actuator>_drive`).
fn input_text(input: &str) -> String {
    match input.strip_suffix("_drive") {
        Some(actuator) => format!("unit stack force F_{{p}} of {actuator}"),
        None => format!("unit force at the foot of {input}"),
    }
}

/// `<tag>_transfer`: one row per input, |V/F| on log axes beside its phase, a line per
/// response point.
pub fn transfer_figure(dir: Dest, tag: &str, h: &HarmonicResult, model: &Model) -> Result<Vec<PathBuf>> {
    let actuators = &model.actuators;
    if h.transfer_inputs.is_empty() {
        return Ok(Vec::new());
    }
    let mut panels = Vec::new();
    for (j, input) in h.transfer_inputs.iter().enumerate() {
        let what = input_text(input);
        let mut mag = LinePlot::new(format!("velocity per {what}"), "frequency (Hz)", "|V/F| (m/(N·s))");
        mag.log_x = true;
        mag.log_y = true;
        let mut phase = LinePlot::new(format!("phase of V/F, {what}"), "frequency (Hz)", "phase (°)");
        phase.log_x = true;
        phase.y_range = Some((-180.0, 180.0));
        for (i, p) in h.point_names.iter().enumerate() {
            let y: Vec<num_complex::Complex64> = h.transfer_velocity.iter().map(|m| m[i][j]).collect();
            let f = h.frequency_hz.clone();
            let mine = |s: Series| super::palette::point_series(actuators, p, s);
            mag.series.push(mine(Series::line(p.clone(), f.clone(), y.iter().map(|c| c.norm().max(1e-300)).collect())));
            let deg = y.iter().map(|c| c.arg().to_degrees()).collect();
            phase.series.push(mine(Series::line(p.clone(), f, deg).wrapped(360.0)));
        }
        panels.push(mag);
        panels.push(phase);
    }
    let structure = super::figures::structure_name(model);
    let fig = MultiPanel::new(format!("Transfer functions of the {structure} with its actuators attached"), panels)
        .with_columns(2);
    save(&fig, dir, &format!("{tag}_transfer"))
}

/// The modal assurance criterion of two shapes: (a·b)²/((a·a)(b·b)), 1 for the same shape.
fn mac(a: &[f64], b: &[f64]) -> f64 {
    let dot = |u: &[f64], v: &[f64]| u.iter().zip(v).map(|(x, y)| x * y).sum::<f64>();
    let (ab, aa, bb) = (dot(a, b), dot(a, a), dot(b, b));
    if aa > 0.0 && bb > 0.0 {
        ab * ab / (aa * bb)
    } else {
        0.0
    }
}

/// The bare-beam mode a coupled shape `w` resembles most, with their MAC (None when no
/// bare mode reaches [`PAIR_MAC`]).
pub fn counterpart(m: &ModesResult, w: &[f64]) -> Option<(usize, f64)> {
    m.shapes_w
        .iter()
        .enumerate()
        .map(|(b, wb)| (b, mac(w, wb)))
        .max_by(|x, y| x.1.total_cmp(&y.1))
        .filter(|(_, v)| *v >= PAIR_MAC)
}

/// `<tag>_coupled`: a panel per coupled mode, its shape on the beam beside the bare-beam
/// mode it resembles most (largest MAC of w at the nodes, sign matched).
pub fn modes_figure(dir: Dest, tag: &str, m: &ModesResult) -> Result<Vec<PathBuf>> {
    let Some(c) = &m.coupled else { return Ok(Vec::new()) };
    let mut panels = Vec::new();
    for (r, w) in c.shapes_w.iter().enumerate().take(SHAPES) {
        let best = counterpart(m, w);
        let title = match best {
            Some((b, v)) => format!(
                "mode {}: {:.2} Hz; bare mode {}: {:.2} Hz (MAC {v:.2})",
                r + 1,
                c.frequencies_hz[r],
                b + 1,
                m.frequencies_hz[b]
            ),
            None => format!("mode {}: {:.2} Hz, mostly the actuators", r + 1, c.frequencies_hz[r]),
        };
        let mut p = LinePlot::new(title, "x (m)", "w (m/√kg)");
        p.series.push(Series::line("with the actuators", m.node_x.clone(), w.clone()));
        if let Some((b, _)) = best {
            let wb = &m.shapes_w[b];
            let sign = if w.iter().zip(wb).map(|(x, y)| x * y).sum::<f64>() < 0.0 { -1.0 } else { 1.0 };
            p.series.push(Series::line("bare beam", m.node_x.clone(), wb.iter().map(|v| sign * v).collect()));
        }
        panels.push(p);
    }
    let title = "Modes of the beam with its actuators attached, beside the bare beam's";
    save(&MultiPanel::new(title, panels).with_columns(2), dir, &format!("{tag}_coupled"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mac_is_one_for_a_shape_and_its_multiple_and_zero_for_orthogonal_shapes() {
        let a = [0.0, 1.0, 2.0, 1.0, 0.0];
        assert!((mac(&a, &a.map(|v| -3.0 * v)) - 1.0).abs() < 1e-15);
        assert_eq!(mac(&a, &[0.0, 1.0, 0.0, -1.0, 0.0]), 0.0);
        assert_eq!(mac(&a, &[0.0; 5]), 0.0);
    }

    #[test]
    fn inputs_are_named_by_what_drives_them() {
        assert_eq!(input_text("frame_left_leg"), "unit force at the foot of frame_left_leg");
        assert_eq!(input_text("inertial_drive"), "unit stack force F_{p} of inertial");
    }
}
