//! The coupled system's figures: its transfer functions (magnitude and phase of the
//! velocity at each response point per unit input) and its mode shapes beside the bare
//! beam's.

use super::figures::save;
use super::plot::{LinePlot, MultiPanel, Series};
use crate::analysis::harmonic::HarmonicResult;
use crate::analysis::modes::ModesResult;
use crate::error::Result;
use std::path::{Path, PathBuf};

/// Mode shapes drawn per panel.
const SHAPES: usize = 6;

/// `<tag>_transfer`: per input, |V/F| on log axes and its phase, at every response point.
pub fn transfer_figure(dir: &Path, tag: &str, h: &HarmonicResult) -> Result<Vec<PathBuf>> {
    if h.transfer_inputs.is_empty() {
        return Ok(Vec::new());
    }
    let mut panels = Vec::new();
    for (j, input) in h.transfer_inputs.iter().enumerate() {
        let mut mag = LinePlot::new(format!("velocity per unit {input}"), "frequency (Hz)", "|V/F| (m/(N·s))");
        mag.log_x = true;
        mag.log_y = true;
        let mut phase = LinePlot::new(format!("phase, per unit {input}"), "frequency (Hz)", "phase (°)");
        phase.log_x = true;
        for (i, p) in h.point_names.iter().enumerate() {
            let y: Vec<num_complex::Complex64> = h.transfer_velocity.iter().map(|m| m[i][j]).collect();
            let f = h.frequency_hz.clone();
            mag.series.push(Series::line(p.clone(), f.clone(), y.iter().map(|c| c.norm().max(1e-300)).collect()));
            phase.series.push(Series::line(p.clone(), f, y.iter().map(|c| c.arg().to_degrees()).collect()));
        }
        panels.push(mag);
        panels.push(phase);
    }
    save(&MultiPanel::new("Transfer functions of the beam with its actuators", panels), dir, &format!("{tag}_transfer"))
}

/// `<tag>_coupled_modes`: the bare beam's mode shapes and the coupled system's, one panel
/// each.
pub fn modes_figure(dir: &Path, tag: &str, m: &ModesResult) -> Result<Vec<PathBuf>> {
    let Some(c) = &m.coupled else { return Ok(Vec::new()) };
    let panel = |title: &str, f: &[f64], w: &[Vec<f64>]| {
        let mut p = LinePlot::new(title, "x (m)", "w (1/√kg)");
        for (r, w) in w.iter().enumerate().take(SHAPES) {
            p.series.push(Series::line(format!("mode {}: {:.2} Hz", r + 1, f[r]), m.node_x.clone(), w.clone()));
        }
        p
    };
    let panels = vec![
        panel("bare beam", &m.frequencies_hz, &m.shapes_w),
        panel(&format!("with the actuators ({})", c.body_names.join(", ")), &c.frequencies_hz, &c.shapes_w),
    ];
    save(&MultiPanel::new("Mode shapes: bare beam and coupled system", panels), dir, &format!("{tag}_coupled_modes"))
}
