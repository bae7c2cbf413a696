//! Figures of the identification steps: measured against identified.
//!
//! * d_p: the stroke difference x₂ − x₁ of the aligned records against time, with the
//!   fitted constant d_p·ΔV.
//! * Bouc–Wen: the hysteresis loop (stroke against voltage), measured points and the
//!   identified model's periodic loop; and the swarm's convergence history (best
//!   normalised RMS error per iteration, one line per seed).
//! * Modal: the FRF (accelerance) magnitude in dB and phase, measured and fitted (single
//!   mode, and the multi-mode fit when there is one), and the coherence.
//!
//! Each figure is written as PNG and SVG by [`render_both`].

use std::path::Path;

use num_complex::Complex64;

use crate::identify::bouc_wen_fit::{CycleData, FitTarget, MultiSeedFit};
use crate::identify::frf::Frf;
use crate::identify::modal_fit::ModalFit;
use crate::report::plot::{LinePlot, MultiPanel, Series, SeriesStyle};

// Figures are written through the run figures' helpers: PNG and SVG side by side.
pub use crate::report::plot::{save as render_both, Figure};

/// Short file name for titles.
fn short(file: &str) -> String {
    Path::new(file).file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| file.to_string())
}

/// The stroke difference of the aligned pair and the fitted d_p·ΔV.
pub fn dp_difference(files: (&str, &str), t: &[f64], diff: &[f64], d_p: f64, delta_v: f64) -> LinePlot {
    let ms: Vec<f64> = t.iter().map(|t| 1e3 * t).collect();
    let um: Vec<f64> = diff.iter().map(|x| 1e6 * x).collect();
    let level = 1e6 * d_p * delta_v;
    let mut p = LinePlot::new(
        format!(
            "d_{{p}} from {} and {}: d_{{p}} = {:.4e} m/V, ΔV = {:.4} V",
            short(files.0),
            short(files.1),
            d_p,
            delta_v
        ),
        "time in the first record (ms)",
        "stroke difference x₂ − x₁ (µm)",
    );
    let (t0, t1) = (ms.first().copied().unwrap_or(0.0), ms.last().copied().unwrap_or(1.0));
    p.series.push(Series::line("measured x₂ − x₁", ms, um).with_style(SeriesStyle::Markers));
    p.series.push(Series::line("fitted d_{p}·ΔV", vec![t0, t1], vec![level, level]));
    p
}

/// Measured against identified hysteresis loop (stroke against voltage).
pub fn hysteresis_loop(data: &CycleData, simulated: &[f64], fit: &MultiSeedFit, target: FitTarget) -> LinePlot {
    let close = |x: &[f64]| -> Vec<f64> {
        let mut v = x.to_vec();
        if let Some(f) = x.first() {
            v.push(*f);
        }
        v
    };
    let v = close(&data.voltage);
    let meas: Vec<f64> = close(&data.stroke).iter().map(|x| 1e6 * x).collect();
    let sim: Vec<f64> = close(simulated).iter().map(|x| 1e6 * x).collect();
    let b = &fit.best.params;
    let y_label = match target {
        FitTarget::Stroke => "free stroke δ (µm)".to_string(),
        FitTarget::BlockedForce { k_p } => format!("stroke F/k_{{p}} (µm), k_{{p}} = {k_p:.4e} N/m"),
    };
    let mut p = LinePlot::new(
        format!("Hysteresis loop of {}: measured and identified", short(&data.file)),
        "voltage (V)",
        y_label,
    );
    p.series.push(Series::line("measured", v.clone(), meas).with_style(SeriesStyle::Markers));
    p.series.push(Series::line(
        format!(
            "identified: α = {:.4}, β = {:.4e} 1/V, γ = {:.4e} 1/V (NRMSE {:.2} %, seed {})",
            b.alpha,
            b.beta,
            b.gamma,
            100.0 * fit.best.nrmse,
            fit.best.seed
        ),
        v,
        sim,
    ));
    p
}

/// Best normalised RMS error (%) per iteration, one line per seed, log scale.
pub fn convergence(fit: &MultiSeedFit) -> LinePlot {
    let mut p = LinePlot::new(
        format!("PSO convergence, Bouc–Wen fit to {}", short(&fit.best.file)),
        "iteration",
        "best normalised RMS error √J (%)",
    );
    p.log_y = true;
    for f in &fit.fits {
        let (x, y): (Vec<f64>, Vec<f64>) = f
            .history
            .iter()
            .enumerate()
            .filter(|(_, c)| c.is_finite() && **c > 0.0)
            .map(|(i, c)| (i as f64, 100.0 * c.sqrt()))
            .unzip();
        p.series.push(Series::line(format!("seed {} ({}, {} iterations)", f.seed, short_stop(f), f.iterations), x, y));
    }
    p
}

fn short_stop(f: &crate::identify::bouc_wen_fit::BoucWenFit) -> &'static str {
    match f.stop {
        crate::identify::pso::StopReason::Converged { .. } => "converged",
        crate::identify::pso::StopReason::MaxIterations => "iteration limit",
    }
}

/// Phase in degrees wrapped to [−90, 270): a driving-point accelerance lies in [0, 180].
fn phase_deg(h: Complex64) -> f64 {
    let mut d = h.arg().to_degrees();
    if d < -90.0 {
        d += 360.0;
    }
    d
}

/// FRF magnitude (dB re 1 (m/s²)/N) and phase, measured against fitted, and the coherence.
pub fn frf_figure(file: &str, frf: &Frf, fits: &[(&str, &ModalFit)]) -> MultiPanel {
    let nyq = frf.freq.last().copied().unwrap_or(1.0);
    // Up to 2.5 × the highest identified mode (and at least the single-mode band).
    let top = fits
        .iter()
        .map(|(_, f)| (2.5 * f.modes.iter().map(|m| m.freq_hz()).fold(0.0, f64::max)).max(f.band.1.min(f.band.0 * 4.0)))
        .fold(0.0f64, f64::max);
    let x_max = if top > 0.0 { top.min(nyq) } else { nyq };
    let bins: Vec<usize> = (1..frf.freq.len()).filter(|&k| frf.freq[k] <= x_max && frf.h1[k].norm() > 0.0).collect();
    let f: Vec<f64> = bins.iter().map(|&k| frf.freq[k]).collect();
    let mag: Vec<f64> = bins.iter().map(|&k| 20.0 * frf.h1[k].norm().log10()).collect();
    let ph: Vec<f64> = bins.iter().map(|&k| phase_deg(frf.h1[k])).collect();
    let coh: Vec<f64> = bins.iter().map(|&k| frf.coherence[k]).collect();
    let mut pm = LinePlot::new("", "frequency (Hz)", "|H_{1}| (dB re 1 (m/s²)/N)");
    let mut pp = LinePlot::new("", "frequency (Hz)", "phase (°)");
    let mut pc = LinePlot::new("", "frequency (Hz)", "coherence γ² (–)");
    for p in [&mut pm, &mut pp, &mut pc] {
        p.x_range = Some((0.0, x_max));
    }
    pp.y_range = Some((-90.0, 270.0));
    pc.y_range = Some((0.0, 1.1));
    pm.series.push(Series::line(format!("measured H_{{1}} ({} hits)", frf.segments), f.clone(), mag));
    pp.series.push(Series::line("measured H_{1}", f.clone(), ph));
    pc.series.push(Series::line("coherence", f, coh));
    for (label, fit) in fits {
        let (lo, hi) = fit.band;
        let n = 400;
        let fx: Vec<f64> = (0..=n).map(|i| lo + (hi - lo) * i as f64 / n as f64).collect();
        let h: Vec<Complex64> =
            fx.iter().map(|&fr| fit.windowed_accelerance(2.0 * std::f64::consts::PI * fr)).collect();
        let modes: Vec<String> =
            fit.modes.iter().map(|m| format!("f_{{n}} = {:.2} Hz, ζ = {:.4}", m.freq_hz(), m.zeta)).collect();
        let name = format!("{label}: {}", modes.join("; "));
        pm.series.push(Series::line(name.clone(), fx.clone(), h.iter().map(|h| 20.0 * h.norm().log10()).collect()));
        pp.series.push(Series::line(name, fx, h.iter().map(|h| phase_deg(*h)).collect()));
    }
    let mut m =
        MultiPanel::new(format!("Impact test {}: accelerance, measured and fitted", short(file)), vec![pm, pp, pc]);
    m.size = Some((1000, 1000));
    m
}
