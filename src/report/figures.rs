//! Standard figures of a case run, and the building blocks the paper figures reuse.
//! Every figure is written as PNG and SVG.

use super::plot::{BarChart, LinePlot, MultiPanel, Series, SeriesStyle};
use crate::analysis::case_run::{AnalysisResult, CaseRun};
use crate::analysis::harmonic::HarmonicResult;
use crate::analysis::modes::ModesResult;
use crate::analysis::series::{BodySeries, DriveSeries, LinkSeries, LinkSpectrum};
use crate::error::Result;
use crate::power::spectra::db;
use std::path::{Path, PathBuf};

/// Something that can be rendered to a path.
pub trait Figure {
    fn render_to(&self, path: &Path) -> Result<()>;
}

impl Figure for LinePlot {
    fn render_to(&self, path: &Path) -> Result<()> {
        self.render(path)
    }
}
impl Figure for MultiPanel {
    fn render_to(&self, path: &Path) -> Result<()> {
        self.render(path)
    }
}
impl Figure for BarChart {
    fn render_to(&self, path: &Path) -> Result<()> {
        self.render(path)
    }
}

/// Writes `dir/name.png` and `dir/name.svg`; returns both paths.
pub fn save(fig: &dyn Figure, dir: &Path, name: &str) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for ext in ["png", "svg"] {
        let p = crate::io::paths::output_file(dir, &format!("{name}.{ext}"))?;
        fig.render_to(&p)?;
        out.push(p);
    }
    Ok(out)
}

/// Time axis in ms from the start of the window.
pub fn ms_axis(t: &[f64]) -> Vec<f64> {
    let t0 = t.first().copied().unwrap_or(0.0);
    t.iter().map(|x| (x - t0) * 1e3).collect()
}

/// A readable name for a link: "stack foot", "left leg", "right leg".
pub fn link_label(l: &LinkSeries) -> String {
    match l.name.as_str() {
        "stack" => "stack foot".to_string(),
        n => n.replace('_', " "),
    }
}

/// Transmitted force(s) of one actuator over time.
pub fn forces_panel(title: &str, t: &[f64], links: &[&LinkSeries]) -> LinePlot {
    let x = ms_axis(t);
    let mut p = LinePlot::new(title, "time (ms)", "transmitted force (N)");
    for l in links {
        p.series.push(Series::line(link_label(l), x.clone(), l.transmitted.clone()));
    }
    p
}

/// Stiffness, damping and PZT components of a stack's transmitted force.
pub fn components_panel(title: &str, t: &[f64], l: &LinkSeries) -> LinePlot {
    let x = ms_axis(t);
    let mut p = LinePlot::new(title, "time (ms)", "force (N)");
    p.series.push(Series::line("total F", x.clone(), l.transmitted.clone()));
    p.series.push(Series::line("stiffness k·u", x.clone(), l.f_stiffness.clone()));
    p.series.push(Series::line("damping c·du/dt", x.clone(), l.f_damping.clone()));
    p.series.push(Series::line("PZT −F_p", x, l.f_pzt.clone()));
    p
}

/// A body DOF over time, in µm (or µrad).
pub fn body_panel(title: &str, t: &[f64], b: &BodySeries) -> LinePlot {
    let x = ms_axis(t);
    let (label, unit) = if b.dof == "phi" { ("rotation φ", "µrad") } else { (b.dof.as_str(), "µm") };
    let mut p = LinePlot::new(title, "time (ms)", format!("{label} ({unit})"));
    p.series.push(Series::line(label, x, b.q.iter().map(|v| v * 1e6).collect()));
    p
}

/// Lines more than this far below the panel's largest (as an amplitude ratio, 120 dB) are
/// left out of a force spectrum: they are round-off, e.g. the exactly zero even harmonics
/// of a symmetric drive in the frequency domain, which would otherwise set the axis at
/// thousands of dB below the lines that matter.
const SPECTRUM_FLOOR: f64 = 1e-6;

/// Force spectrum in dB re 1 N at the harmonics (lines within 120 dB of the largest).
pub fn spectrum_panel(title: &str, spectra: &[(&str, &LinkSpectrum)]) -> LinePlot {
    let mut p = LinePlot::new(title, "frequency (Hz)", "force level (dB re 1 N)");
    let top = spectra.iter().flat_map(|(_, s)| s.transmitted[1..].iter()).fold(0.0f64, |m, c| m.max(c.norm()));
    for (label, s) in spectra {
        let (f, l): (Vec<f64>, Vec<f64>) = s.frequency[1..]
            .iter()
            .zip(&s.transmitted[1..])
            .filter(|(_, c)| c.norm() > SPECTRUM_FLOOR * top)
            .map(|(&f, c)| (f, db(c.norm(), 1.0)))
            .unzip();
        p.series.push(Series::line(*label, f, l).with_style(SeriesStyle::LineMarkers));
    }
    p
}

/// Power per harmonic as a level in dB re 1 pW (10·log₁₀|P|/1 pW), positive (into the
/// base) and negative (out of it) lines as separate series (stems for the first spectrum,
/// markers for the others); lines below 10⁻⁹ of the largest are left out, since they are
/// round-off or unsettled transient (even harmonics of a symmetric drive).
pub fn power_spectrum_panel(title: &str, spectra: &[(&str, &LinkSpectrum)]) -> LinePlot {
    let mut p = LinePlot::new(title, "frequency (Hz)", "|power| level (dB re 1 pW)");
    let top = spectra.iter().flat_map(|(_, s)| s.power[1..].iter()).fold(0.0f64, |m, x| m.max(x.abs()));
    for (i, (label, s)) in spectra.iter().enumerate() {
        let style = if i == 0 { SeriesStyle::Stems } else { SeriesStyle::Markers };
        for (sign, name) in [(1.0, "into the beam"), (-1.0, "out of the beam")] {
            let (f, l): (Vec<f64>, Vec<f64>) = s.frequency[1..]
                .iter()
                .zip(&s.power[1..])
                .filter(|(_, &pw)| pw * sign > 1e-9 * top)
                .map(|(&f, &pw)| (f, 10.0 * (pw.abs() / 1e-12).log10()))
                .unzip();
            if !f.is_empty() {
                p.series.push(Series::line(format!("{label}, {name}"), f, l).with_style(style));
            }
        }
    }
    p
}

/// Stroke against voltage over the recorded window (the hysteresis loop).
pub fn loop_panel(title: &str, d: &DriveSeries) -> LinePlot {
    let mut p = LinePlot::new(title, "voltage (V)", "free stroke δ (µm)");
    p.series.push(Series::line("Bouc–Wen", d.voltage.clone(), d.stroke.iter().map(|s| s * 1e6).collect()));
    p
}

fn modes_figure(m: &ModesResult) -> LinePlot {
    let mut p = LinePlot::new("Mode shapes of the bare beam (mass-normalised)", "x (m)", "w (1/√kg)");
    for (r, w) in m.shapes_w.iter().enumerate().take(6) {
        p.series.push(Series::line(
            format!("mode {}: {:.2} Hz", r + 1, m.frequencies_hz[r]),
            m.node_x.clone(),
            w.clone(),
        ));
    }
    p
}

fn harmonic_figure(h: &HarmonicResult) -> MultiPanel {
    let mut mob = LinePlot::new("Driving-point mobility", "frequency (Hz)", "|Y| (m/(N·s))");
    mob.log_x = true;
    mob.log_y = true;
    let mut pw = LinePlot::new("Input power", "frequency (Hz)", "power (W)");
    pw.log_x = true;
    pw.log_y = true;
    let nforce = h.input_power.first().map_or(0, Vec::len);
    for j in 0..nforce {
        let y: Vec<f64> = h.mobility.iter().map(|m| m[j][j].norm().max(1e-300)).collect();
        mob.series.push(Series::line(
            format!("{} at x = {} m", h.point_names[j], h.point_x[j]),
            h.frequency_hz.clone(),
            y,
        ));
    }
    pw.series.push(Series::line(
        "input ½Re(F·V*)",
        h.frequency_hz.clone(),
        h.total_power.iter().map(|p| p.abs().max(1e-300)).collect(),
    ));
    pw.series.push(
        Series::line(
            "beam dissipation",
            h.frequency_hz.clone(),
            h.dissipated_power.iter().map(|p| p.abs().max(1e-300)).collect(),
        )
        .with_style(SeriesStyle::Markers),
    );
    MultiPanel::new("Harmonic response of the beam", vec![mob, pw])
}

/// The standard figures of `run`: one set per analysis.
pub fn plot_run(dir: &Path, stem: &str, run: &CaseRun) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for (i, r) in run.results.iter().enumerate() {
        let tag = format!("{stem}_{i}");
        match r {
            AnalysisResult::Modes(m) => {
                out.extend(save(&modes_figure(m), dir, &format!("{tag}_modes"))?);
                out.extend(super::coupled::modes_figure(dir, &tag, m)?);
            }
            AnalysisResult::Harmonic(h) => {
                out.extend(save(&harmonic_figure(h), dir, &format!("{tag}_harmonic"))?);
                out.extend(super::coupled::transfer_figure(dir, &tag, h)?);
            }
            AnalysisResult::Transient(t) => {
                // Figures show the last periods (a whole history, `[output] full_history`,
                // is in the HDF5 file; drawn it would be hundreds of periods per panel).
                let n = (PLOTTED_PERIODS * t.steps_per_period).min(t.t.len());
                let links: Vec<LinkSeries> = t.links.iter().map(|l| l.tail(n)).collect();
                let drives: Vec<DriveSeries> = t.drives.iter().map(|d| d.tail(n)).collect();
                let time = &t.t[t.t.len() - n..];
                match &t.record {
                    None => {
                        out.extend(periodic_figures(dir, &tag, run, time, &links, &t.spectra, &t.mean_power, &drives)?)
                    }
                    Some(rec) => {
                        // The drives' band, with a margin: beyond it the FRFs divide noise by noise.
                        let band = run.model.drive_signals().filter_map(|s| s.highest_frequency()).fold(0.0, f64::max);
                        out.extend(record_figures(dir, &tag, time, &links, rec, 1.25 * band)?)
                    }
                }
                out.extend(load_figures(dir, &tag, time, &t.loads, &t.load_spectra)?);
            }
            AnalysisResult::SteadyState(s) => {
                out.extend(periodic_figures(dir, &tag, run, &s.t, &s.links, &s.spectra, &s.mean_power, &s.drives)?);
                out.extend(load_figures(dir, &tag, &s.t, &s.loads, &s.load_spectra)?);
                if let Some(m) = &s.modal {
                    out.extend(save(&modal_power_figure(m, run), dir, &format!("{tag}_power_by_mode"))?);
                }
            }
        }
    }
    out.extend(super::measured::figures(dir, stem, &run.measured)?);
    Ok(out)
}

/// A non-periodic run's figures: the transmitted forces over the record, and per point its
/// accelerance FRF from the drive, the power density into the structure and (with Welch
/// segments) the coherence.
fn record_figures(
    dir: &Path,
    tag: &str,
    t: &[f64],
    links: &[LinkSeries],
    rec: &crate::power::record::RecordAnalysis,
    f_max: f64,
) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    if !links.is_empty() {
        let refs: Vec<&LinkSeries> = links.iter().collect();
        out.extend(save(
            &forces_panel("transmitted forces over the record", t, &refs),
            dir,
            &format!("{tag}_record_time"),
        )?);
    }
    let f = &rec.frequency;
    let shown = |&(a, _): &(f64, f64)| f_max <= 0.0 || a <= f_max;
    let band =
        |y: &[f64]| -> (Vec<f64>, Vec<f64>) { f.iter().zip(y).skip(1).map(|(&a, &b)| (a, b)).filter(shown).unzip() };
    let mut frf = LinePlot::new("accelerance from the drive", "frequency (Hz)", "|H1| ((m/s²) per V or N)");
    frf.log_y = true;
    let mut pd = LinePlot::new("power into the structure per hertz", "frequency (Hz)", "Re G_Fv (W/Hz)");
    let mut coh = LinePlot::new("coherence of the accelerance", "frequency (Hz)", "γ²");
    for p in &rec.points {
        let mag: Vec<f64> = p.acceleration_frf.iter().map(|h| h.norm().max(1e-300)).collect();
        let (x, y) = band(&mag);
        frf.series.push(Series::line(p.name.clone(), x, y));
        let (x, y) = band(&p.power_density);
        pd.series.push(Series::line(p.name.clone(), x, y));
        if !p.acceleration_coherence.is_empty() {
            let (x, y) = band(&p.acceleration_coherence);
            coh.series.push(Series::line(p.name.clone(), x, y));
        }
    }
    let mut panels = vec![frf, pd];
    if !coh.series.is_empty() {
        panels.push(coh);
    }
    let title =
        format!("non-periodic record of {:.3} s: {} segment(s) of {:.3} s", rec.duration, rec.segments, rec.segment_s);
    out.extend(save(&MultiPanel::new(title, panels), dir, &format!("{tag}_record_spectra"))?);
    Ok(out)
}

/// Each point load's figure: its force and the beam's velocity at its point, and (periodic
/// runs) its power per harmonic.
fn load_figures(
    dir: &Path,
    tag: &str,
    t: &[f64],
    loads: &[crate::analysis::series::LoadSeries],
    spectra: &[crate::analysis::series::LoadSpectrum],
) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    let x = ms_axis(t);
    for (j, l) in loads.iter().enumerate() {
        let tail = |v: &[f64]| v[v.len() - t.len()..].to_vec();
        let mut force = LinePlot::new(format!("{}: force at x = {} m", l.name, l.x), "time (ms)", "force (N)");
        force.series.push(Series::line("F", x.clone(), tail(&l.force)));
        let mut vel = LinePlot::new(format!("{}: beam velocity at the load", l.name), "time (ms)", "velocity (m/s)");
        vel.series.push(Series::line("v", x.clone(), tail(&l.v)));
        let mut panels = vec![force, vel];
        if let Some(sp) = spectra.get(j) {
            let mut pp = LinePlot::new(
                format!("{}: power per harmonic, {:.4e} W in total", l.name, sp.power_total),
                "frequency (Hz)",
                "power (W)",
            );
            pp.series.push(
                Series::line("P_k", sp.frequency[1..].to_vec(), sp.power[1..].to_vec())
                    .with_style(crate::report::plot::SeriesStyle::Stems),
            );
            panels.push(pp);
        }
        out.extend(save(
            &MultiPanel::new(format!("point load {}", l.name), panels),
            dir,
            &format!("{tag}_{}_load", l.name),
        )?);
    }
    Ok(out)
}

/// Periods of a transient's time histories drawn in its figures (the last ones).
const PLOTTED_PERIODS: usize = 3;

#[allow(clippy::too_many_arguments)]
fn periodic_figures(
    dir: &Path,
    tag: &str,
    run: &CaseRun,
    t: &[f64],
    links: &[LinkSeries],
    spectra: &[LinkSpectrum],
    mean: &[f64],
    drives: &[DriveSeries],
) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for (a, act) in run.model.actuators.iter().enumerate() {
        let mine: Vec<usize> = (0..links.len()).filter(|&l| links[l].actuator == a).collect();
        let refs: Vec<&LinkSeries> = mine.iter().map(|&l| &links[l]).collect();
        let name = act.name();
        let stack = mine.iter().copied().find(|&l| links[l].name == "stack").expect("every actuator has a stack");
        let mut panels = vec![
            forces_panel(&format!("{name}: transmitted forces"), t, &refs),
            components_panel(&format!("{name}: components of the stack-foot force"), t, &links[stack]),
        ];
        if refs.iter().any(|l| l.foot_x.is_some()) {
            let x = ms_axis(t);
            let mut pp = LinePlot::new(format!("{name}: instantaneous power into the beam"), "time (ms)", "power (W)");
            for l in &refs {
                pp.series.push(Series::line(link_label(l), x.clone(), l.power.clone()));
            }
            panels.push(pp);
        }
        out.extend(save(
            &MultiPanel::new(format!("{name} ({})", act.kind()), panels),
            dir,
            &format!("{tag}_{name}_time"),
        )?);
        let labels: Vec<String> = mine.iter().map(|&l| link_label(&links[l])).collect();
        let specs: Vec<(&str, &LinkSpectrum)> =
            mine.iter().zip(&labels).map(|(&l, s)| (s.as_str(), &spectra[l])).collect();
        out.extend(save(
            &spectrum_panel(&format!("{name}: transmitted-force spectrum"), &specs),
            dir,
            &format!("{tag}_{name}_spectrum"),
        )?);
        if refs.iter().any(|l| l.foot_x.is_some()) {
            out.extend(save(
                &power_spectrum_panel(&format!("{name}: power per harmonic"), &specs),
                dir,
                &format!("{tag}_{name}_power_spectrum"),
            )?);
            let mut bar =
                BarChart::new(format!("{name}: time-averaged power into the beam"), "interface point", "power (W)");
            bar.categories = labels.clone();
            bar.groups.push(("mean power".into(), mine.iter().map(|&l| mean[l]).collect()));
            out.extend(save(&bar, dir, &format!("{tag}_{name}_power_points"))?);
        }
        if let Some(d) = drives.get(a) {
            out.extend(save(
                &loop_panel(&format!("{name}: stack hysteresis loop"), d),
                dir,
                &format!("{tag}_{name}_loop"),
            )?);
        }
    }
    Ok(out)
}

/// Net input power by bare-beam mode (first 12), one group per actuator.
pub fn modal_power_figure(m: &crate::power::modal::ModalDecomposition, run: &CaseRun) -> BarChart {
    let nm = m.mode_frequency_hz.len().min(12);
    let mut bar = BarChart::new("Net power into the beam by mode", "bare-beam mode (natural frequency)", "power (W)");
    bar.categories = (0..nm).map(|r| format!("{:.0} Hz", m.mode_frequency_hz[r])).collect();
    for (a, act) in run.model.actuators.iter().enumerate() {
        let v: Vec<f64> = (0..nm)
            .map(|r| {
                run.system
                    .links
                    .iter()
                    .enumerate()
                    .filter(|(_, l)| l.actuator == a)
                    .map(|(l, _)| m.point_power[l][r])
                    .sum()
            })
            .collect();
        bar.groups.push((act.name().to_string(), v));
    }
    for (load, p) in run.model.loads.iter().zip(&m.load_power) {
        bar.groups.push((load.name.clone(), p[..nm].to_vec()));
    }
    bar
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_complex::Complex64;

    #[test]
    fn force_spectra_leave_out_round_off_lines() {
        let c = |re: f64| Complex64::new(re, 0.0);
        let s = LinkSpectrum {
            frequency: vec![0.0, 60.0, 120.0, 180.0, 240.0],
            transmitted: vec![c(1.0), c(10.0), c(0.0), c(0.01), c(1e-300)],
            ..Default::default()
        };
        let p = spectrum_panel("t", &[("stack", &s)]);
        let series = &p.series[0];
        // 60 Hz at 20 dB, 180 Hz at −40 dB; the zero and the 1e-300 line are not drawn.
        assert_eq!(series.x, vec![60.0, 180.0]);
        assert!((series.y[0] - 20.0).abs() < 1e-12 && (series.y[1] + 40.0).abs() < 1e-12, "{:?}", series.y);
    }
}
