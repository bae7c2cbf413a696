//! Standard figures of a case run, and the building blocks the paper figures reuse.
//! Every figure is written as SVG, and as PNG and PDF as `--formats` asks.

use super::palette;
pub use super::plot::figure::{save, Dest, Drawing, Drawings, Figure};
use super::plot::text::si;
use super::plot::{BarChart, LinePlot, MultiPanel, Series, SeriesStyle};
use crate::actuator::Actuator;
use crate::analysis::case_run::{AnalysisResult, CaseRun};
use crate::analysis::harmonic::HarmonicResult;
use crate::analysis::modes::ModesResult;
use crate::analysis::series::{BodySeries, DriveSeries, LinkSeries, LinkSpectrum};
use crate::analysis::steady_state::SteadyStateResult;
use crate::error::Result;
use crate::power::modal::ModalDecomposition;
use crate::power::spectra::db;
use plotters::style::RGBColor;
use std::path::{Path, PathBuf};

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

/// Transmitted force(s) of one actuator over time, each point in its colour.
pub fn forces_panel(title: &str, t: &[f64], links: &[&LinkSeries], actuators: &[Actuator]) -> LinePlot {
    let x = ms_axis(t);
    let mut p = LinePlot::new(title, "time (ms)", "transmitted force (N)");
    for l in links {
        let s = Series::line(link_label(l), x.clone(), l.transmitted.clone());
        p.series.push(s.coloured(palette::link(actuators, l)));
    }
    p
}

/// Stiffness, damping and PZT components of a stack's transmitted force (the total is
/// drawn on its own axis by [`total_panel`]: where the components nearly cancel it would
/// be a flat line at their scale).
pub fn components_panel(title: &str, t: &[f64], l: &LinkSeries) -> LinePlot {
    let x = ms_axis(t);
    let mut p = LinePlot::new(title, "time (ms)", "force (N)");
    p.series.push(Series::line("stiffness k·u", x.clone(), l.f_stiffness.clone()).coloured(palette::part(0)));
    // Dashed: where the damping part matches the stiffness part it would hide it.
    let damping = Series::line("damping c·du/dt", x.clone(), l.f_damping.clone()).with_style(SeriesStyle::Dashed);
    p.series.push(damping.coloured(palette::part(1)));
    p.series.push(Series::line("PZT −F_{p}", x, l.f_pzt.clone()).coloured(palette::part(2)));
    p
}

/// A stack's total transmitted force `symbol` (e.g. `F_{T}`), titled with its size
/// against the largest component: how far the components cancel.
pub fn total_panel(who: &str, symbol: &str, t: &[f64], l: &LinkSeries, actuators: &[Actuator]) -> LinePlot {
    let peak = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let largest = peak(&l.f_stiffness).max(peak(&l.f_damping)).max(peak(&l.f_pzt));
    let share = if largest > 0.0 { peak(&l.transmitted) / largest } else { f64::NAN };
    let mut p = LinePlot::new(
        format!("{who}: total {symbol}, {} of the largest component", percent(share)),
        "time (ms)",
        "force (N)",
    );
    let total = Series::line(format!("total {symbol}"), ms_axis(t), l.transmitted.clone());
    p.series.push(total.coloured(palette::link(actuators, l)));
    p
}

/// A ratio as a percentage with two significant digits (`0.014 %`, `100 %`).
fn percent(r: f64) -> String {
    let v = 100.0 * r;
    if !v.is_finite() {
        return "–".into();
    }
    let decimals = if v >= 10.0 { 0 } else { (1 - v.log10().floor() as i32).max(0) as usize };
    format!("{v:.decimals$} %")
}

/// A body DOF over time, in µm (or µrad).
pub fn body_panel(title: &str, t: &[f64], b: &BodySeries) -> LinePlot {
    let x = ms_axis(t);
    // A DOF name `z_t` is z with subscript t: the figures' markup for that is `z_{t}`.
    let label = match b.dof.split_once('_') {
        _ if b.dof == "phi" => "rotation φ".to_string(),
        Some((name, sub)) if !sub.starts_with('{') => format!("{name}_{{{sub}}}"),
        _ => b.dof.clone(),
    };
    let unit = if b.dof == "phi" { "µrad" } else { "µm" };
    let mut p = LinePlot::new(title, "time (ms)", format!("{label} ({unit})"));
    p.series.push(Series::line(&label, x, b.q.iter().map(|v| v * 1e6).collect()));
    p
}

/// Lines more than this far below the panel's largest (as an amplitude ratio, 120 dB) are
/// left out of a force spectrum: they are round-off, e.g. the exactly zero even harmonics
/// of a symmetric drive in the frequency domain, which would otherwise set the axis at
/// thousands of dB below the lines that matter.
const SPECTRUM_FLOOR: f64 = 1e-6;

/// The frequency axis of a line spectrum: from zero to just past the highest analysed
/// harmonic, so a missing line reads as absent, not as out of range.
fn harmonic_axis(p: &mut LinePlot, frequency: &[f64]) {
    if let Some(&f_max) = frequency.last().filter(|f| **f > 0.0) {
        p.x_range = Some((0.0, 1.03 * f_max));
    }
}

/// One point's force spectrum: its legend label, the spectrum and the point's colour.
pub type ForceLines<'a> = (&'a str, &'a LinkSpectrum, RGBColor);

/// Force spectrum in dB re 1 N at the harmonics, as stems up from the bottom of the axis
/// (lines within 120 dB of the largest), over every analysed harmonic.
pub fn spectrum_panel(title: &str, spectra: &[ForceLines]) -> LinePlot {
    let mut p = LinePlot::new(title, "frequency (Hz)", "force level (dB re 1 N)");
    p.stem_base = f64::NEG_INFINITY;
    let top = spectra.iter().flat_map(|(_, s, _)| s.transmitted[1..].iter()).fold(0.0f64, |m, c| m.max(c.norm()));
    for (label, s, colour) in spectra {
        let (f, l): (Vec<f64>, Vec<f64>) = s.frequency[1..]
            .iter()
            .zip(&s.transmitted[1..])
            .filter(|(_, c)| c.norm() > SPECTRUM_FLOOR * top)
            .map(|(&f, c)| (f, db(c.norm(), 1.0)))
            .unzip();
        p.series.push(Series::line(*label, f, l).with_style(SeriesStyle::Stems).coloured(*colour));
    }
    if let Some((_, s, _)) = spectra.first() {
        harmonic_axis(&mut p, &s.frequency);
    }
    p
}

/// One line spectrum of power: its legend label, the harmonic frequencies (Hz), the
/// power per harmonic (W), index 0 being the mean (not drawn), and its point's colour
/// (`None`: the colour cycle).
pub type PowerLines<'a> = (&'a str, &'a [f64], &'a [f64], Option<RGBColor>);

/// Most decades of power drawn on a logarithmic scale below the largest line (the lines
/// drawn reach 10⁻⁹ of it); below the smallest line drawn, the symmetric-log axis has its
/// linear band around zero, so every line drawn shows its sign.
const POWER_DECADES: i32 = 9;

/// What power goes into, in labels: the beam, the plate, an imported model, or (actuators
/// on a rigid base) the base.
pub fn into_word(model: &crate::assembly::Model) -> &'static str {
    match model.structure.as_ref().map(|s| s.kind()) {
        None => "base",
        Some("imported") => "model",
        Some(kind) => kind,
    }
}

/// The structure in figure titles and legends: `beam`, `plate`, `imported model`, or
/// `structure` where the actuators stand on a rigid base.
pub fn structure_name(model: &crate::assembly::Model) -> &'static str {
    match model.structure.as_ref().map(|s| s.kind()) {
        None => "structure",
        Some("imported") => "imported model",
        Some(kind) => kind,
    }
}

/// A mode of the structure without its actuators, as an axis names it: `bare-beam mode`,
/// `bare-plate mode`, `mode of the bare imported model`.
fn bare_mode(model: &crate::assembly::Model) -> String {
    match structure_name(model) {
        "imported model" => "mode of the bare imported model".into(),
        name => format!("bare-{name} mode"),
    }
}

/// Power per harmonic into `into` (the beam, the plate, …). All into it: stems on a
/// logarithmic axis. With lines of both
/// signs: a symmetric-log axis, into the beam up, out of it down, each decade the same
/// height. `stems` stand at their harmonics (one colour and marker each: one legend entry
/// per point, not per sign; the longest drawn first); `markers` are a second estimate of
/// the same lines, in their own colours and shapes. Lines below 10⁻⁹ of the largest are
/// left out: round-off, or unsettled transient (even harmonics of a symmetric drive).
pub fn power_spectrum_panel(title: &str, into: &str, stems: &[PowerLines], markers: &[PowerLines]) -> LinePlot {
    let mut p = LinePlot::new(title, "frequency (Hz)", format!("power into the {into} (W)"));
    let top =
        stems.iter().chain(markers).flat_map(|(_, _, pw, _)| pw.iter().skip(1)).fold(0.0f64, |m, x| m.max(x.abs()));
    let kept = |(_, f, pw, _): &PowerLines| -> (Vec<f64>, Vec<f64>) {
        f.iter().zip(pw.iter()).skip(1).filter(|(_, pw)| pw.abs() > 1e-9 * top).map(|(&f, &pw)| (f, pw)).unzip()
    };
    for (style, set) in [(SeriesStyle::Stems, stems), (SeriesStyle::Markers, markers)] {
        for lines in set {
            let (f, pw) = kept(lines);
            let s = Series::line(lines.0, f, pw).with_style(style);
            p.series.push(match lines.3 {
                Some(c) => s.coloured(c),
                None => s,
            });
        }
    }
    if p.series.iter().all(|s| s.y.iter().all(|&v| v > 0.0)) {
        p.log_y = true;
    } else if top > 0.0 {
        let smallest = p.series.iter().flat_map(|s| s.y.iter()).fold(top, |m, v| m.min(v.abs()));
        let floor = top.log10().floor() as i32 - POWER_DECADES;
        p.symlog_y = Some(10f64.powi((smallest.log10().floor() as i32).max(floor)));
    }
    if let Some((_, f, _, _)) = stems.first() {
        harmonic_axis(&mut p, f);
    }
    p
}

/// Stroke against voltage over the recorded window (the hysteresis loop), closed: the
/// window holds whole periods sampled at t₀ + j·Δt, j < N, so the sample after the last is
/// the first one a period on, and without it the loop would have a gap of one step where
/// the window starts (at V = 0 for a sine).
pub fn loop_panel(title: &str, d: &DriveSeries) -> LinePlot {
    let mut p = LinePlot::new(title, "voltage (V)", "free stroke δ (µm)");
    let closed = |v: &[f64]| v.iter().chain(v.first()).copied().collect::<Vec<f64>>();
    let stroke: Vec<f64> = closed(&d.stroke).iter().map(|s| s * 1e6).collect();
    p.series.push(Series::line("Bouc–Wen", closed(&d.voltage), stroke));
    p
}

fn modes_figure(m: &ModesResult) -> LinePlot {
    let mut p = LinePlot::new("Mode shapes of the bare beam (mass-normalised)", "x (m)", "w (m/√kg)");
    for (r, w) in m.shapes_w.iter().enumerate().take(6) {
        p.series.push(Series::line(
            format!("mode {}: {:.2} Hz", r + 1, m.frequencies_hz[r]),
            m.node_x.clone(),
            w.clone(),
        ));
    }
    p
}

/// None when the analysis applies no force (transfer functions of the coupled system
/// only, drawn by [`super::coupled`]).
fn harmonic_figure(h: &HarmonicResult, model: &crate::assembly::Model) -> Option<MultiPanel> {
    let structure = structure_name(model);
    let mut mob = LinePlot::new("Driving-point mobility", "frequency (Hz)", "|Y| (m/(N·s))");
    mob.log_x = true;
    mob.log_y = true;
    let mut pw = LinePlot::new("Input power", "frequency (Hz)", "power (W)");
    pw.log_x = true;
    pw.log_y = true;
    let nforce = h.input_power.first().map_or(0, Vec::len);
    if nforce == 0 {
        return None;
    }
    for j in 0..nforce {
        let y: Vec<f64> = h.mobility.iter().map(|m| m[j][j].norm().max(1e-300)).collect();
        let at = h.point_at.get(j).map_or_else(|| format!("x = {} m", h.point_x[j]), |at| at.to_string());
        let s = Series::line(format!("{} at {at}", h.point_names[j]), h.frequency_hz.clone(), y);
        mob.series.push(palette::point_series(&model.actuators, &h.point_names[j], s));
    }
    pw.series.push(Series::line(
        "input ½Re(F·V*)",
        h.frequency_hz.clone(),
        h.total_power.iter().map(|p| p.abs().max(1e-300)).collect(),
    ));
    pw.series.push(
        Series::line(
            format!("{structure} dissipation"),
            h.frequency_hz.clone(),
            h.dissipated_power.iter().map(|p| p.abs().max(1e-300)).collect(),
        )
        .with_style(SeriesStyle::Markers),
    );
    Some(MultiPanel::new(format!("Harmonic response of the {structure}"), vec![mob, pw]))
}

/// The analysis types of a run as file-name parts, `transient` or, when a case has several
/// of one type, `transient_1`, `transient_2`, … in the case's order.
pub fn analysis_tags(run: &CaseRun) -> Vec<String> {
    let kind = |r: &AnalysisResult| match r {
        AnalysisResult::Modes(_) => "modes",
        AnalysisResult::Harmonic(_) => "harmonic",
        AnalysisResult::Transient(_) => "transient",
        AnalysisResult::SteadyState(_) => "steady_state",
    };
    let kinds: Vec<&str> = run.results.iter().map(kind).collect();
    kinds
        .iter()
        .enumerate()
        .map(|(i, k)| {
            if kinds.iter().filter(|o| *o == k).count() == 1 {
                k.to_string()
            } else {
                format!("{k}_{}", kinds[..=i].iter().filter(|o| *o == k).count())
            }
        })
        .collect()
}

/// The standard figures of `run`: one set per analysis, named `<stem>_<analysis type>…`.
pub fn plot_run(dir: &Path, stem: &str, run: &CaseRun) -> Result<Vec<PathBuf>> {
    draw_run(Dest::Folder(dir), stem, run)
}

/// The figures [`plot_run`] writes, as drawings named as their files without the stem
/// (`steady_state_frame_time`, …).
pub fn run_drawings(run: &CaseRun) -> Result<Vec<(String, Drawing)>> {
    let kept = Drawings::default();
    draw_run(Dest::Keep(&kept), "", run)?;
    Ok(kept.into_inner().into_iter().map(|(name, d)| (name.trim_start_matches('_').to_string(), d)).collect())
}

fn draw_run(dir: Dest, stem: &str, run: &CaseRun) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    let plate = run.model.structure.as_ref().and_then(|s| s.plate());
    if let Some(p) = plate {
        out.extend(super::plate::layout_figure(dir, stem, p, run)?);
    }
    for (r, kind) in run.results.iter().zip(analysis_tags(run)) {
        let tag = format!("{stem}_{kind}");
        match r {
            AnalysisResult::Modes(m) => match plate {
                Some(p) => out.extend(super::plate::modes_figure(dir, &tag, p, m)?),
                // An imported model's shapes have no line or plane to be drawn over (its
                // frequencies are in the report's table and the results files).
                None if run.model.structure.as_ref().is_some_and(|s| s.imported().is_some()) => {}
                None => {
                    out.extend(save(&modes_figure(m), dir, &tag)?);
                    out.extend(super::coupled::modes_figure(dir, &tag, m)?);
                }
            },
            AnalysisResult::Harmonic(h) => {
                if let Some(fig) = harmonic_figure(h, &run.model) {
                    out.extend(save(&fig, dir, &tag)?);
                }
                out.extend(super::coupled::transfer_figure(dir, &tag, h, &run.model)?);
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
                        let acts = &run.model.actuators;
                        out.extend(record_figures(dir, &tag, time, &links, acts, rec, 1.2 * rec.band.1)?)
                    }
                }
                out.extend(load_figures(dir, &tag, into_word(&run.model), time, &t.loads, &t.load_spectra)?);
                if t.record.is_none() && t.t.len() > n {
                    out.extend(history_figures(dir, &tag, run, t)?);
                }
            }
            AnalysisResult::SteadyState(s) => {
                out.extend(periodic_figures(dir, &tag, run, &s.t, &s.links, &s.spectra, &s.mean_power, &s.drives)?);
                out.extend(load_figures(dir, &tag, into_word(&run.model), &s.t, &s.loads, &s.load_spectra)?);
                if let Some(m) = &s.modal {
                    out.extend(save(&modal_power_figure(m, run, s), dir, &format!("{tag}_power_by_mode"))?);
                }
            }
        }
    }
    out.extend(super::measured::figures(dir, stem, &analysis_tags(run), &run.measured)?);
    Ok(out)
}

/// A non-periodic run's figures: the transmitted forces over the record, and per point its
/// accelerance FRF from the drive, the power density into the structure and (with Welch
/// segments) the coherence.
#[allow(clippy::too_many_arguments)]
fn record_figures(
    dir: Dest,
    tag: &str,
    t: &[f64],
    links: &[LinkSeries],
    actuators: &[Actuator],
    rec: &crate::power::record::RecordAnalysis,
    f_max: f64,
) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    if !links.is_empty() {
        let refs: Vec<&LinkSeries> = links.iter().collect();
        out.extend(save(
            &forces_panel("transmitted forces over the record", t, &refs, actuators),
            dir,
            &format!("{tag}_record_time"),
        )?);
    }
    let f = &rec.frequency;
    // The band on a log axis: from the first bin (or a little below the band) to a little
    // above it; beyond it the FRFs divide noise by noise.
    let lo = (0.8 * rec.band.0).max(f.get(1).copied().unwrap_or(1.0));
    let hi = if f_max > lo { f_max } else { f.last().copied().unwrap_or(1.0) };
    let bins: Vec<usize> = (1..f.len()).filter(|&k| (lo..=hi).contains(&f[k])).collect();
    let pick = |y: &[f64], keep: &dyn Fn(usize) -> bool| -> (Vec<f64>, Vec<f64>) {
        bins.iter().filter(|&&k| keep(k)).map(|&k| (f[k], y[k])).unzip()
    };
    let log_plot = |title: &str, y_label: &str, log_y: bool| {
        let mut p = LinePlot::new(title, "frequency (Hz)", y_label);
        p.log_x = true;
        p.log_y = log_y;
        p.x_range = Some((lo, hi));
        p
    };
    let mut frf = log_plot("accelerance from the drive: magnitude", "|H_{1}| ((m/s²) per V or N)", true);
    let mut phase = log_plot("accelerance from the drive: phase", "phase (°)", false);
    let mut pd = log_plot("power into the structure per hertz", "Re G_{Fv} (W/Hz)", false);
    let mut force = log_plot("force PSD at each point", "G_{FF} (N²/Hz)", true);
    let mut coh = log_plot("coherence of the accelerance", "γ²", false);
    let trusted = crate::power::record::COHERENCE_TRUSTED;
    // Bins where some FRF's coherence says it is not to be trusted: shaded behind them.
    let mut low = std::collections::BTreeSet::new();
    let mut frf_of = |name: &str, h: &[num_complex::Complex64], c: &[f64]| {
        let mag: Vec<f64> = h.iter().map(|h| h.norm().max(1e-300)).collect();
        let deg: Vec<f64> = h.iter().map(|h| h.arg().to_degrees()).collect();
        let mine = |s: Series| palette::point_series(actuators, name, s);
        let (x, y) = pick(&mag, &|_| true);
        frf.series.push(mine(Series::line(name, x, y)));
        let (x, y) = pick(&deg, &|_| true);
        phase.series.push(mine(Series::line(name, x, y).wrapped(360.0)));
        if !c.is_empty() {
            low.extend(bins.iter().filter(|&&k| c[k] < trusted));
            let (x, y) = pick(c, &|_| true);
            coh.series.push(mine(Series::line(name, x, y)));
        }
    };
    for p in &rec.points {
        frf_of(&p.name, &p.acceleration_frf, &p.acceleration_coherence);
    }
    for sr in &rec.sensors {
        frf_of(&format!("sensor {}", sr.name), &sr.acceleration_frf, &sr.acceleration_coherence);
    }
    for p in &rec.points {
        let mine = |s: Series| palette::point_series(actuators, &p.name, s);
        let (x, y) = pick(&p.power_density, &|_| true);
        pd.series.push(mine(Series::line(p.name.clone(), x, y)));
        let psd: Vec<f64> = p.force_psd.iter().map(|v| v.max(1e-300)).collect();
        let (x, y) = pick(&psd, &|_| true);
        force.series.push(mine(Series::line(p.name.clone(), x, y)));
    }
    let bands = bands_of(f, &low);
    for p in [&mut frf, &mut phase, &mut coh] {
        p.shaded = bands.clone();
        p.shaded_label = format!("γ² < {trusted}");
    }
    let mut panels = vec![frf, phase, pd, force];
    if !coh.series.is_empty() {
        panels.push(coh);
    }
    let kind = if rec.estimate.reason == "decayed" { "one segment, response decayed" } else { "Welch, Hann" };
    let title =
        format!("record of {:.3} s: {kind}, {} segment(s) of {:.3} s", rec.duration, rec.segments, rec.segment_s);
    out.extend(save(&MultiPanel::new(title, panels), dir, &format!("{tag}_record_spectra"))?);
    Ok(out)
}

/// The frequency intervals covered by `bins` (indices into the uniform grid `f`), each bin
/// from halfway to its neighbours below to halfway to those above, adjacent bins merged.
fn bands_of(f: &[f64], bins: &std::collections::BTreeSet<usize>) -> Vec<(f64, f64)> {
    let df = if f.len() > 1 { f[1] - f[0] } else { 0.0 };
    let mut out: Vec<(f64, f64)> = Vec::new();
    for &k in bins {
        let (lo, hi) = (f[k] - 0.5 * df, f[k] + 0.5 * df);
        match out.last_mut() {
            Some(last) if lo <= last.1 + 1e-9 * df => last.1 = hi,
            _ => out.push((lo, hi)),
        }
    }
    out
}

/// Buckets of a whole history drawn (each its least and largest value, in time order): the
/// start-up's envelope stays exact however long the run.
const HISTORY_BUCKETS: usize = 2000;

/// `v` over `t` reduced to [`HISTORY_BUCKETS`] buckets of consecutive samples, each as its
/// smallest and largest value in the order they occur.
fn envelope(t: &[f64], v: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let per = t.len().div_ceil(HISTORY_BUCKETS).max(1);
    if per == 1 {
        return (t.to_vec(), v.to_vec());
    }
    let (mut x, mut y) = (Vec::new(), Vec::new());
    for (tc, vc) in t.chunks(per).zip(v.chunks(per)) {
        let lo = (0..vc.len()).min_by(|&a, &b| vc[a].total_cmp(&vc[b])).unwrap_or(0);
        let hi = (0..vc.len()).max_by(|&a, &b| vc[a].total_cmp(&vc[b])).unwrap_or(0);
        for k in if lo <= hi { [lo, hi] } else { [hi, lo] } {
            x.push(tc[k]);
            y.push(vc[k]);
        }
    }
    (x, y)
}

/// A transient that kept its whole history (`[output] full_history`): each actuator's
/// transmitted forces from t = 0, so the start-up shows, as an envelope of
/// [`HISTORY_BUCKETS`] buckets.
fn history_figures(
    dir: Dest,
    tag: &str,
    run: &CaseRun,
    t: &crate::analysis::transient::TransientResult,
) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for (a, act) in run.model.actuators.iter().enumerate() {
        let name = act.name();
        let mut p = LinePlot::new(
            format!("{name}: transmitted forces from the start, {} periods", t.periods_run),
            "time (s)",
            "transmitted force (N)",
        );
        for l in t.links.iter().filter(|l| l.actuator == a) {
            let (x, y) = envelope(&t.t, &l.transmitted);
            p.series.push(Series::line(link_label(l), x, y).coloured(palette::link(&run.model.actuators, l)));
        }
        p.notes = vec![format!("{} samples,", t.t.len()), format!("≤ {} buckets drawn", HISTORY_BUCKETS)];
        // A thinned history (`history_every`) says so: its first step is k·Δt.
        let every = t.t.get(1).map_or(1.0, |t1| ((t1 - t.t[0]) / t.dt).round());
        if every > 1.0 {
            p.notes.push(format!("every {every}th step before the last 3 periods"));
        }
        out.extend(save(&p, dir, &format!("{tag}_{name}_history"))?);
    }
    Ok(out)
}

/// Each point load's figure: its force and the beam's velocity at its point, and (periodic
/// runs) its power per harmonic.
fn load_figures(
    dir: Dest,
    tag: &str,
    into: &str,
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
        let mut vel = LinePlot::new(format!("{}: {into} velocity at the load", l.name), "time (ms)", "velocity (m/s)");
        vel.series.push(Series::line("v", x.clone(), tail(&l.v)));
        let mut panels = vec![force, vel];
        if let Some(sp) = spectra.get(j) {
            let title = format!("{}: power per harmonic, {} in total", l.name, si(sp.power_total, "W", 4));
            panels.push(power_spectrum_panel(&title, into, &[("P_{k}", &sp.frequency, &sp.power, None)], &[]));
        }
        out.extend(save(
            &MultiPanel::new(format!("point load {}", l.name), panels),
            dir,
            &format!("{tag}_{}_load", l.name),
        )?);
    }
    Ok(out)
}

/// An actuator's name with its kind, `top (inertial)`, or the name alone when it is the
/// kind (`frame`, not `frame (frame)`).
fn named_with_kind(name: &str, kind: &str) -> String {
    if name.eq_ignore_ascii_case(kind) {
        name.to_string()
    } else {
        format!("{name} ({kind})")
    }
}

/// Periods of a transient's time histories drawn in its figures (the last ones).
const PLOTTED_PERIODS: usize = 3;

#[allow(clippy::too_many_arguments)]
fn periodic_figures(
    dir: Dest,
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
            forces_panel(&format!("{name}: transmitted forces"), t, &refs, &run.model.actuators),
            components_panel(&format!("{name}: components of the stack-foot force"), t, &links[stack]),
        ];
        if refs.iter().any(|l| l.foot_x.is_some()) {
            let x = ms_axis(t);
            let into = into_word(&run.model);
            let mut pp =
                LinePlot::new(format!("{name}: instantaneous power into the {into}"), "time (ms)", "power (W)");
            for l in &refs {
                let s = Series::line(link_label(l), x.clone(), l.power.clone());
                pp.series.push(s.coloured(palette::link(&run.model.actuators, l)));
            }
            panels.push(pp);
        }
        // A transient's figures show its last periods: their time axis starts at t₀.
        let from = t
            .first()
            .filter(|&&t0| t0 > 0.0)
            .map_or(String::new(), |&t0| format!(", time from t₀ = {}", si(t0, "s", 4)));
        out.extend(save(
            &MultiPanel::new(format!("{}{from}", named_with_kind(name, act.kind())), panels),
            dir,
            &format!("{tag}_{name}_time"),
        )?);
        let labels: Vec<String> = mine.iter().map(|&l| link_label(&links[l])).collect();
        let colours: Vec<RGBColor> = mine.iter().map(|&l| palette::link(&run.model.actuators, &links[l])).collect();
        let specs: Vec<ForceLines> =
            mine.iter().zip(&labels).zip(&colours).map(|((&l, s), &c)| (s.as_str(), &spectra[l], c)).collect();
        out.extend(save(
            &spectrum_panel(&format!("{name}: transmitted-force spectrum"), &specs),
            dir,
            &format!("{tag}_{name}_spectrum"),
        )?);
        if refs.iter().any(|l| l.foot_x.is_some()) {
            let lines: Vec<PowerLines> = specs
                .iter()
                .map(|(label, s, c)| (*label, s.frequency.as_slice(), s.power.as_slice(), Some(*c)))
                .collect();
            out.extend(save(
                &power_spectrum_panel(&format!("{name}: power per harmonic"), into_word(&run.model), &lines, &[]),
                dir,
                &format!("{tag}_{name}_power_spectrum"),
            )?);
            let mut bar = BarChart::new(
                format!("{name}: time-averaged power into the {}", into_word(&run.model)),
                "interface point",
                "power (W)",
            );
            bar.categories = labels.clone();
            bar.category_colours = colours.clone();
            bar.groups.push((String::new(), mine.iter().map(|&l| mean[l]).collect()));
            bar.show_values = true;
            bar.notes = vec![format!("net: {}", si(mine.iter().map(|&l| mean[l]).sum(), "W", 4))];
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

/// A mode is drawn on its own when it carries at least this share of some source's
/// power (of the sum of the magnitudes over modes).
const MODE_SHARE: f64 = 0.01;
/// At most this many modes get their own bar.
const MODE_BARS: usize = 16;

/// Net power into the structure by bare-structure mode, one group per actuator and point load: a bar
/// for each mode that matters ([`MODE_SHARE`], at most [`MODE_BARS`], in mode order) and a
/// last bar `rest` with the other modes and what the truncated modal sum misses, so that
/// each group's bars add up to its net power.
pub fn modal_power_figure(m: &ModalDecomposition, run: &CaseRun, s: &SteadyStateResult) -> BarChart {
    // (name, power per mode, net power) of each source.
    let mut sources: Vec<(String, Vec<f64>, f64)> = Vec::new();
    for (a, act) in run.model.actuators.iter().enumerate() {
        let mine: Vec<usize> = (0..run.system.links.len()).filter(|&l| run.system.links[l].actuator == a).collect();
        let per_mode =
            (0..m.mode_frequency_hz.len()).map(|r| mine.iter().map(|&l| m.point_power[l][r]).sum()).collect();
        sources.push((act.name().to_string(), per_mode, s.net_power[a]));
    }
    for ((load, p), sp) in run.model.loads.iter().zip(&m.load_power).zip(&s.load_spectra) {
        sources.push((load.name.clone(), p.clone(), sp.power_total));
    }
    let shown = modes_that_matter(sources.iter().map(|(_, p, _)| p.as_slice()));
    let mut bar = BarChart::new(
        format!("Net power into the {} by mode", into_word(&run.model)),
        format!("{} (number, natural frequency)", bare_mode(&run.model)),
        "power (W)",
    );
    bar.categories = shown.iter().map(|&r| format!("{}\n{:.0} Hz", r + 1, m.mode_frequency_hz[r])).collect();
    bar.categories.push("rest".into());
    bar.group_colours = (0..run.model.actuators.len()).map(palette::actuator).collect();
    for (name, per_mode, total) in sources {
        let mut v: Vec<f64> = shown.iter().map(|&r| per_mode[r]).collect();
        v.push(total - v.iter().sum::<f64>());
        bar.groups.push((name, v));
    }
    bar.notes = vec![
        format!("{} of {} modes drawn;", shown.len(), m.mode_frequency_hz.len()),
        "rest: the others and the".into(),
        "modal truncation".into(),
    ];
    // Room for each category's two-line name.
    bar.size = ((300 + 75 * bar.categories.len() as u32).max(1000), 600);
    bar
}

/// Modes (indices, ascending) carrying at least [`MODE_SHARE`] of some source's power,
/// the [`MODE_BARS`] largest of them.
fn modes_that_matter<'a>(sources: impl Iterator<Item = &'a [f64]>) -> Vec<usize> {
    let mut share: Vec<f64> = Vec::new();
    for p in sources {
        let sum: f64 = p.iter().map(|x| x.abs()).sum();
        share.resize(share.len().max(p.len()), 0.0);
        for (r, x) in p.iter().enumerate() {
            if sum > 0.0 {
                share[r] = share[r].max(x.abs() / sum);
            }
        }
    }
    let mut r: Vec<usize> = (0..share.len()).filter(|&r| share[r] >= MODE_SHARE).collect();
    r.sort_by(|&a, &b| share[b].total_cmp(&share[a]));
    r.truncate(MODE_BARS);
    r.sort_unstable();
    r
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
        let p = spectrum_panel("t", &[("stack", &s, palette::point("frame", "stack"))]);
        let series = &p.series[0];
        // 60 Hz at 20 dB, 180 Hz at −40 dB; the zero and the 1e-300 line are not drawn.
        assert_eq!(series.x, vec![60.0, 180.0]);
        assert!((series.y[0] - 20.0).abs() < 1e-12 && (series.y[1] + 40.0).abs() < 1e-12, "{:?}", series.y);
    }
}
