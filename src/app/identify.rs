//! The identification commands end to end, as library functions: load the measurement
//! files, identify, write the case fragment (`.toml`), the numbers (`.json`) and the
//! figures (`.png` and `.svg`), and return the result with a printable report. The CLI
//! (`beamflow identify …`, `beamflow synth`) only parses arguments and prints.
//!
//! | function | writes in the output directory |
//! |---|---|
//! | [`identify_dp`] | `dp.toml`, `dp.json`, `dp-difference.{png,svg}` |
//! | [`identify_bouc_wen`] | `bouc-wen.toml`, `bouc-wen.json`, `bouc-wen-loop.{png,svg}`, `bouc-wen-convergence.{png,svg}` |
//! | [`identify_modal`] | `modal.toml`, `modal.json`, `modal-frf.{png,svg}` |
//! | [`synth`] | the CSV file(s) |
//!
//! Measurement sources are CSV files, or beamflow results files (`FILE.h5[:SELECTOR]`, see
//! [`measurement::load_hdf5`]).

use std::path::{Path, PathBuf};

use crate::case::LoadedCase;
use crate::error::{Error, Result};
use crate::identify::bouc_wen_fit::{self, CycleData, CycleOptions, FitOptions, FitTarget, MultiSeedFit};
use crate::identify::dp::{self, DpEstimate, DpOptions};
use crate::identify::frf::{self, Frf, FrfOptions, Segmentation};
use crate::identify::modal_fit::{self, DynamicParameters, IdentifiedElement, ModalFit, RfpOptions, SdofOptions};
use crate::identify::synth::{self, SynthKind, SynthOptions, Truth};
use crate::io::atomic::write_atomic_string;
use crate::io::lock::OutputLock;
use crate::io::measurement::{self, LoadOptions, Quantity};
use crate::io::paths::{output_file, refuse_input, refuse_output, Input};
use crate::report::identify as plots;

/// Names the measurement file in an identification step's errors: the settings it could
/// not accept, and any numerical failure.
fn attribute(e: Error, file: &str) -> Error {
    match e {
        Error::Numerical(m) => Error::Numerical(format!("{file}: {m}")),
        other => other.in_file(file),
    }
}

/// An option given on the command line (or as a Python argument) that cannot be used,
/// named by its flag: the measurement file is not at fault.
fn flag_error(flag: &str, reason: impl Into<String>) -> Error {
    Error::input("<cli>", flag, reason)
}

fn positive_flag(flag: &str, x: f64, unit: &str) -> Result<()> {
    if x > 0.0 && x.is_finite() {
        return Ok(());
    }
    Err(flag_error(flag, format!("must be a positive, finite number ({unit}), got {x}")))
}

fn at_least(flag: &str, n: usize, min: usize, what: &str) -> Result<()> {
    if n >= min {
        return Ok(());
    }
    Err(flag_error(flag, format!("must be at least {min} ({what}), got {n}")))
}

/// Checks the options every identification reads its files with.
fn check_load(load: &LoadOptions) -> Result<()> {
    let t = load.uniform_tolerance;
    if t > 0.0 && t < 1.0 {
        return Ok(());
    }
    Err(flag_error("--uniform-tolerance", format!("must lie in (0, 1) (a relative jitter of the time step), got {t}")))
}

/// Refuses an output folder `dir` where one of the files an identification writes
/// (`names`, figures as `.png` and `.svg`) would replace one of its measurement `sources`
/// (CSV files, or `FILE.h5[:ACTUATOR]`).
fn refuse_over_sources(dir: Option<&Path>, names: &[&str], sources: &[&Path]) -> Result<()> {
    let Some(dir) = dir else { return Ok(()) };
    let inputs: Vec<Input> = sources
        .iter()
        .map(|s| {
            let text = s.to_string_lossy();
            let file = measurement::split_hdf5_source(&text).map_or_else(|| s.to_path_buf(), |(f, _)| PathBuf::from(f));
            Input::new(file, "a measurement file")
        })
        .collect();
    for name in names {
        let exts: &[&str] = if name.contains('.') { &[""] } else { &[".png", ".svg"] };
        for ext in exts {
            refuse_input("--out", &output_file(dir, &format!("{name}{ext}"))?, &inputs)?;
        }
    }
    Ok(())
}

fn write_text(dir: &Path, name: &str, text: &str, written: &mut Vec<PathBuf>) -> Result<()> {
    let p = output_file(dir, name)?;
    write_atomic_string(&p, text)?;
    written.push(p);
    Ok(())
}

fn write_json<T: serde::Serialize>(dir: &Path, name: &str, value: &T, written: &mut Vec<PathBuf>) -> Result<()> {
    let text = serde_json::to_string_pretty(value).expect("plain data serialises");
    write_text(dir, name, &text, written)
}

fn written_list(written: &[PathBuf]) -> String {
    if written.is_empty() {
        return String::new();
    }
    let mut s = String::from("wrote:\n");
    for p in written {
        s += &format!("  {}\n", p.display());
    }
    s
}

// ---------------------------------------------------------------------------------------
// d_p
// ---------------------------------------------------------------------------------------

/// What [`identify_dp`] does.
#[derive(Clone, Debug)]
pub struct DpRequest {
    pub first: PathBuf,
    pub second: PathBuf,
    pub options: DpOptions,
    pub load: LoadOptions,
    /// Output directory (None: write nothing).
    pub out: Option<PathBuf>,
    pub plots: bool,
}

/// Result of [`identify_dp`].
#[derive(Clone, Debug)]
pub struct DpOutcome {
    pub estimate: DpEstimate,
    pub fragment: String,
    pub written: Vec<PathBuf>,
}

impl DpOutcome {
    /// What the CLI prints.
    pub fn report(&self) -> String {
        let e = &self.estimate;
        format!(
            "d_p from {} and {}\n  d_p        = {:.6e} m/V\n  delta_V    = {:.6} V (std-dev of V2 - V1: {:.3e} V)\n  \
             residual   = {:.3e} m RMS over {} sample pairs (alignment shift {})\n  std error  = {:.3e} m/V ({:.3} %)\n\n\
             case fragment:\n{}\n{}",
            e.files.0,
            e.files.1,
            e.d_p,
            e.delta_v,
            e.offset_std,
            e.residual_rms,
            e.pairs,
            e.shift,
            e.std_error,
            100.0 * e.std_error / e.d_p,
            self.fragment,
            written_list(&self.written)
        )
    }
}

/// d_p from two records whose voltages differ by a constant offset.
pub fn identify_dp(req: &DpRequest) -> Result<DpOutcome> {
    check_load(&req.load)?;
    if let Some(k) = req.options.k_p {
        positive_flag("--k-p", k, "N/m")?;
    }
    positive_flag("--offset-tolerance", req.options.offset_tolerance, "a fraction of |ΔV|")?;
    let need: &[Quantity] =
        if req.options.k_p.is_some() { &[Quantity::Voltage] } else { &[Quantity::Voltage, Quantity::Displacement] };
    refuse_over_sources(req.out.as_deref(), &["dp.toml", "dp.json", "dp-difference"], &[&req.first, &req.second])?;
    let a = measurement::load_source(&req.first, need, &req.load)?;
    let b = measurement::load_source(&req.second, need, &req.load)?;
    let estimate = dp::estimate_dp(&a, &b, &req.options)?;
    let fragment = estimate.to_case_fragment();
    let mut written = Vec::new();
    if let Some(dir) = &req.out {
        let _lock = OutputLock::folder(dir)?;
        write_text(dir, "dp.toml", &fragment, &mut written)?;
        write_json(dir, "dp.json", &estimate, &mut written)?;
        if req.plots {
            // The aligned stroke differences.
            let stroke = |m: &measurement::Measurement| -> Vec<f64> {
                match (&m.displacement, &m.force, req.options.k_p) {
                    (Some(x), _, _) => x.clone(),
                    (None, Some(f), Some(k)) => f.iter().map(|f| f / k).collect(),
                    _ => vec![0.0; m.len()],
                }
            };
            let (x1, x2) = (stroke(&a), stroke(&b));
            let s = estimate.shift;
            let lo = 0isize.max(-s) as usize;
            let hi = (x1.len() as isize).min(x2.len() as isize - s).max(lo as isize) as usize;
            let t: Vec<f64> = a.time[lo..hi].to_vec();
            let d: Vec<f64> = (lo..hi).map(|i| x2[(i as isize + s) as usize] - x1[i]).collect();
            let fig = plots::dp_difference((&a.file, &b.file), &t, &d, estimate.d_p, estimate.delta_v);
            written.extend(plots::render_both(&fig, dir, "dp-difference")?);
        }
    }
    Ok(DpOutcome { estimate, fragment, written })
}

// ---------------------------------------------------------------------------------------
// Bouc–Wen
// ---------------------------------------------------------------------------------------

/// What [`identify_bouc_wen`] does.
#[derive(Clone, Debug)]
pub struct BoucWenRequest {
    pub file: PathBuf,
    pub target: FitTarget,
    pub cycle: CycleOptions,
    /// d_p, search ranges and swarm settings (the seed is replaced by each of `seeds`).
    pub fit: FitOptions,
    pub seeds: Vec<u64>,
    pub load: LoadOptions,
    pub out: Option<PathBuf>,
    pub plots: bool,
}

/// Result of [`identify_bouc_wen`].
#[derive(Clone, Debug, serde::Serialize)]
pub struct BoucWenOutcome {
    pub fit: MultiSeedFit,
    /// The fitted cycle (voltage and measured stroke).
    pub data: CycleData,
    /// The identified model's periodic stroke at the cycle's voltage samples (m).
    pub simulated: Vec<f64>,
    #[serde(skip)]
    pub fragment: String,
    #[serde(skip)]
    pub written: Vec<PathBuf>,
}

impl BoucWenOutcome {
    /// What the CLI prints.
    pub fn report(&self) -> String {
        let f = &self.fit;
        let mut s = format!(
            "Bouc-Wen fit to {} ({} samples, period {:.6e} s), d_p = {:.6e} m/V held fixed\n\
             {:>6}  {:>10}  {:>12}  {:>12}  {:>9}  {:>10}  {:>11}  stop\n",
            self.data.file,
            self.data.voltage.len(),
            self.data.period,
            f.best.params.d_p,
            "seed",
            "alpha",
            "beta (1/V)",
            "gamma (1/V)",
            "NRMSE %",
            "iterations",
            "evaluations"
        );
        for r in &f.fits {
            s += &format!(
                "{:>6}  {:>10.6}  {:>12.6e}  {:>12.6e}  {:>9.4}  {:>10}  {:>11}  {}\n",
                r.seed,
                r.params.alpha,
                r.params.beta,
                r.params.gamma,
                100.0 * r.nrmse,
                r.iterations,
                r.evaluations,
                r.stop
            );
        }
        let b = &f.best;
        s += &format!(
            "best (seed {}): alpha = {:.6}, beta = {:.6e} 1/V, gamma = {:.6e} 1/V, cost J = {:.4e}, NRMSE {:.4} %\n\
             spread over {} seed(s), mean +- std: alpha {:.6} +- {:.2e}, beta {:.6e} +- {:.2e}, gamma {:.6e} +- {:.2e}\n\
             class I (d_p > 0, alpha > 0, beta + gamma > 0, beta - gamma >= 0): {}; infeasible candidates evaluated: {}\n\n\
             case fragment:\n{}\n{}",
            b.seed,
            b.params.alpha,
            b.params.beta,
            b.params.gamma,
            b.cost,
            100.0 * b.nrmse,
            f.fits.len(),
            f.mean[0],
            f.std[0],
            f.mean[1],
            f.std[1],
            f.mean[2],
            f.std[2],
            if bouc_wen_fit::is_class_one(&b.params) { "holds" } else { "VIOLATED" },
            f.fits.iter().map(|r| r.infeasible_candidates).sum::<usize>(),
            self.fragment,
            written_list(&self.written)
        );
        s
    }
}

/// Checks a Bouc–Wen request's options before any file is read, naming each flag.
fn check_bouc_wen(req: &BoucWenRequest) -> Result<()> {
    check_load(&req.load)?;
    crate::case::ranges::within("<cli>", "--d-p", req.fit.d_p, crate::case::ranges::D_P, "m/V")?;
    if let FitTarget::BlockedForce { k_p } = req.target {
        positive_flag("--k-p", k_p, "N/m")?;
    }
    if let Some(p) = req.cycle.period {
        positive_flag("--period", p, "s")?;
    }
    at_least("--cycles", req.cycle.cycles, 1, "whole periods fitted, from the end of the record")?;
    at_least("--particles", req.fit.pso.particles, 2, "a swarm needs two particles to move")?;
    at_least("--max-iterations", req.fit.pso.max_iterations, 1, "iterations of the swarm")?;
    if req.seeds.is_empty() {
        return Err(flag_error("--seeds", "give at least one seed"));
    }
    Ok(())
}

/// α, β, γ by particle swarm, once per seed.
pub fn identify_bouc_wen(req: &BoucWenRequest) -> Result<BoucWenOutcome> {
    check_bouc_wen(req)?;
    let need: &[Quantity] = match req.target {
        FitTarget::Stroke => &[Quantity::Voltage, Quantity::Displacement],
        FitTarget::BlockedForce { .. } => &[Quantity::Voltage, Quantity::Force],
    };
    refuse_over_sources(
        req.out.as_deref(),
        &["bouc-wen.toml", "bouc-wen.json", "bouc-wen-loop", "bouc-wen-convergence"],
        &[&req.file],
    )?;
    let m = measurement::load_source(&req.file, need, &req.load)?;
    let data = CycleData::from_measurement(&m, req.target, &req.cycle)?;
    let fit = bouc_wen_fit::fit_multi_seed(&data, &req.fit, &req.seeds).map_err(|e| attribute(e, &m.file))?;
    let simulated = bouc_wen_fit::simulate_cycle(&fit.best.params, &data.voltage);
    let fragment = fit.to_case_fragment();
    let mut out = BoucWenOutcome { fit, data, simulated, fragment, written: Vec::new() };
    if let Some(dir) = &req.out {
        let mut written = Vec::new();
        let _lock = OutputLock::folder(dir)?;
        write_text(dir, "bouc-wen.toml", &out.fragment, &mut written)?;
        write_json(dir, "bouc-wen.json", &out, &mut written)?;
        if req.plots {
            let lp = plots::hysteresis_loop(&out.data, &out.simulated, &out.fit, req.target);
            written.extend(plots::render_both(&lp, dir, "bouc-wen-loop")?);
            written.extend(plots::render_both(&plots::convergence(&out.fit), dir, "bouc-wen-convergence")?);
        }
        out.written = written;
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------
// Modal
// ---------------------------------------------------------------------------------------

/// What [`identify_modal`] does.
#[derive(Clone, Debug)]
pub struct ModalRequest {
    pub file: PathBuf,
    /// The known moving mass (kg).
    pub mass: f64,
    pub element: IdentifiedElement,
    /// Modes of the multi-mode (rational-fraction) fit (default 1).
    pub modes: usize,
    /// Band (Hz) of the multi-mode fit, also where the single-mode fit looks for its peak.
    /// None: the single-mode fit looks in the hammer's band (force auto-spectrum within 20 dB
    /// of its maximum); the multi-mode fit uses 0.5–1.5 × the single-mode frequency with one
    /// mode, the hammer's band with more.
    pub band: Option<(f64, f64)>,
    /// Mode (1-based, in increasing frequency) of the multi-mode fit that gives k and c when
    /// `modes > 1`. With `modes = 1` the single-mode fit gives them.
    pub use_mode: usize,
    /// Samples per hit segment (None: the shortest spacing between hits).
    pub segment: Option<usize>,
    /// Exponential window: its value at the segment's end, in (0, 1).
    pub exp_window: Option<f64>,
    /// Force window length (s).
    pub force_window: Option<f64>,
    /// Bins with coherence below this are left out of the fits (default 0.8).
    pub min_coherence: f64,
    pub load: LoadOptions,
    pub out: Option<PathBuf>,
    pub plots: bool,
}

impl ModalRequest {
    /// Defaults: one mode, the hammer's band, auto segments, no windows.
    pub fn new(file: impl Into<PathBuf>, mass: f64, element: IdentifiedElement) -> Self {
        ModalRequest {
            file: file.into(),
            mass,
            element,
            modes: 1,
            band: None,
            use_mode: 1,
            segment: None,
            exp_window: None,
            force_window: None,
            min_coherence: 0.8,
            load: LoadOptions::default(),
            out: None,
            plots: true,
        }
    }
}

/// Result of [`identify_modal`].
#[derive(Clone, Debug, serde::Serialize)]
pub struct ModalOutcome {
    pub file: String,
    #[serde(skip)]
    pub frf: Frf,
    pub segments: usize,
    pub segment_length: usize,
    /// Single-mode fit around the highest peak.
    pub single_mode: ModalFit,
    /// Multi-mode rational-fraction fit over the band.
    pub multi_mode: ModalFit,
    /// Which fit gave k and c: `single_mode` or `multi_mode`.
    pub used: String,
    pub parameters: DynamicParameters,
    /// Modal mass from the residue of the mode used (kg): a check on the given mass for a
    /// single-DOF test.
    pub modal_mass: f64,
    #[serde(skip)]
    pub fragment: String,
    #[serde(skip)]
    pub written: Vec<PathBuf>,
}

impl ModalOutcome {
    /// What the CLI prints.
    pub fn report(&self) -> String {
        let mode_line = |f: &ModalFit| -> String {
            f.modes
                .iter()
                .enumerate()
                .map(|(i, m)| format!("    mode {}: f_n = {:.6} Hz, zeta = {:.6}\n", i + 1, m.freq_hz(), m.zeta))
                .collect()
        };
        let p = &self.parameters;
        format!(
            "impact test {}: H1 from {} hit(s) of {} samples (df = {:.4} Hz)\n\
             single-mode fit over {:.2}..{:.2} Hz ({} bins, misfit {:.3e}):\n{}\
             multi-mode fit, {} mode(s) over {:.2}..{:.2} Hz ({} bins, misfit {:.3e}):\n{}\
             k and c from the {} fit ({}), mass {} kg:\n  f_n = {:.6} Hz, zeta = {:.6}\n  k = {:.6e} N/m\n  c = {:.6e} N s/m\n\
             modal mass from the residue: {:.4} kg (given {} kg)\n\ncase fragment:\n{}\n{}",
            self.file,
            self.segments,
            self.segment_length,
            self.frf.freq.get(1).copied().unwrap_or(0.0),
            self.single_mode.band.0,
            self.single_mode.band.1,
            self.single_mode.points,
            self.single_mode.fit_error,
            mode_line(&self.single_mode),
            self.multi_mode.modes.len(),
            self.multi_mode.band.0,
            self.multi_mode.band.1,
            self.multi_mode.points,
            self.multi_mode.fit_error,
            mode_line(&self.multi_mode),
            self.used.replace('_', "-"),
            synth::element_name(p.element),
            p.mass,
            p.omega_n / (2.0 * std::f64::consts::PI),
            p.zeta,
            p.k,
            p.c,
            self.modal_mass,
            p.mass,
            self.fragment,
            written_list(&self.written)
        )
    }
}

/// The hammer's band: bins 1.. where the mean force auto-spectrum is within 20 dB of its
/// largest value, up to the first bin that falls below.
fn hammer_band(frf: &Frf) -> (f64, f64) {
    let s = &frf.force_autospectrum;
    let peak = s.iter().skip(1).fold(0.0f64, |m, v| m.max(*v));
    let mut k_hi = s.len() - 1;
    for (k, v) in s.iter().enumerate().skip(1) {
        if *v < 0.01 * peak {
            k_hi = k.saturating_sub(1).max(1);
            break;
        }
    }
    (frf.freq[1], frf.freq[k_hi])
}

/// Checks the modal request's options besides mass, modes and band before any file is
/// read, naming each flag.
fn check_modal(req: &ModalRequest) -> Result<()> {
    check_load(&req.load)?;
    if req.use_mode < 1 || req.use_mode > req.modes {
        return Err(flag_error(
            "--use-mode",
            format!(
                "--use-mode {} picks a mode of the {}-mode fit (--modes {}): it must lie in 1..={}; raise --modes \
                 to fit more modes",
                req.use_mode, req.modes, req.modes, req.modes
            ),
        ));
    }
    if let Some(n) = req.segment {
        at_least("--segment", n, 8, "samples per hit")?;
    }
    if let Some(e) = req.exp_window {
        if !(e > 0.0 && e < 1.0) {
            return Err(flag_error(
                "--exp-window",
                format!("must lie in (0, 1) (the window's value at the end), got {e}"),
            ));
        }
    }
    if let Some(w) = req.force_window {
        positive_flag("--force-window", w, "s")?;
    }
    let c = req.min_coherence;
    if !(0.0..=1.0).contains(&c) {
        return Err(flag_error("--min-coherence", format!("must lie in [0, 1], got {c}")));
    }
    Ok(())
}

/// H1 with coherence, single- and multi-mode fits, and k = m·ω_n², c = 2ζ·m·ω_n.
pub fn identify_modal(req: &ModalRequest) -> Result<ModalOutcome> {
    if !(req.mass > 0.0 && req.mass.is_finite()) {
        return Err(Error::input("<cli>", "--mass", format!("must be a positive mass in kg, got {}", req.mass)));
    }
    if req.modes < 1 {
        return Err(Error::input("<cli>", "--modes", "must be at least 1"));
    }
    if let Some((lo, hi)) = req.band {
        if !(lo >= 0.0 && hi > lo && hi.is_finite()) {
            return Err(Error::input("<cli>", "--band", format!("need 0 <= F1 < F2, got {lo},{hi}")));
        }
    }
    check_modal(req)?;
    refuse_over_sources(req.out.as_deref(), &["modal.toml", "modal.json", "modal-frf"], &[&req.file])?;
    let m = measurement::load_source(&req.file, &[Quantity::Force, Quantity::Acceleration], &req.load)?;
    let file = m.file.clone();
    let force = m.column(Quantity::Force)?;
    let threshold = 0.1;
    let len = match req.segment {
        Some(n) => n,
        None => frf::auto_segment_length(&file, force, threshold)?,
    };
    let opts = FrfOptions {
        segmentation: Segmentation::Hits { length: len, pre_trigger: len / 20, threshold },
        force_window: req.force_window,
        exponential_window_end: req.exp_window,
        hann: false,
    };
    let frf = frf::h1_from_measurement(&m, &opts)?;
    let nyq = frf.freq.last().copied().unwrap_or(0.0);
    let band = match req.band {
        Some((lo, hi)) => {
            if lo > nyq {
                return Err(Error::input("<cli>", "--band", format!("starts above the Nyquist frequency {nyq} Hz")));
            }
            (lo.max(frf.freq[1]), hi.min(nyq))
        }
        None => hammer_band(&frf),
    };
    let single_mode = modal_fit::fit_sdof(
        &frf,
        &SdofOptions { search: Some(band), min_coherence: req.min_coherence, ..SdofOptions::default() },
    )
    .map_err(|e| attribute(e, &file))?;
    // One mode without a given band: half to one and a half times the single-mode fit's
    // frequency (a single-mode rational fraction over a very wide band is ill-conditioned).
    let rfp_band = match (req.band, req.modes) {
        (None, 1) => {
            let f = single_mode.modes[0].freq_hz();
            ((0.5 * f).max(band.0), (1.5 * f).min(band.1))
        }
        _ => band,
    };
    let multi_mode = modal_fit::fit_rfp(
        &frf,
        &RfpOptions { min_coherence: req.min_coherence, ..RfpOptions::new(req.modes, rfp_band) },
    )
    .map_err(|e| attribute(e, &file))?;
    let (used, mode) = if req.modes > 1 {
        let i = req.use_mode - 1;
        let mode = multi_mode.modes.get(i).ok_or_else(|| {
            Error::input(
                &file,
                "modes",
                format!(
                    "--use-mode {} requested but the multi-mode fit found {} mode(s) in {:.1}..{:.1} Hz",
                    req.use_mode,
                    multi_mode.modes.len(),
                    band.0,
                    band.1
                ),
            )
        })?;
        ("multi_mode", mode.clone())
    } else {
        ("single_mode", single_mode.modes[0].clone())
    };
    let parameters =
        DynamicParameters::new(req.element, req.mass, mode.omega_n, mode.zeta).map_err(|e| attribute(e, &file))?;
    let other = if used == "single_mode" { &multi_mode } else { &single_mode };
    let other_modes: Vec<String> =
        other.modes.iter().map(|m| format!("{:.6} Hz / {:.5}", m.freq_hz(), m.zeta)).collect();
    let fragment = format!(
        "# impact test {file} ({} hits), {} fit; other fit: {}\n{}",
        frf.segments,
        used.replace('_', "-"),
        other_modes.join(", "),
        parameters.to_case_fragment()
    );
    let mut out = ModalOutcome {
        file: file.clone(),
        segments: frf.segments,
        segment_length: len,
        modal_mass: mode.modal_mass(),
        frf,
        single_mode,
        multi_mode,
        used: used.to_string(),
        parameters,
        fragment,
        written: Vec::new(),
    };
    if let Some(dir) = &req.out {
        let mut written = Vec::new();
        let _lock = OutputLock::folder(dir)?;
        write_text(dir, "modal.toml", &out.fragment, &mut written)?;
        write_json(dir, "modal.json", &out, &mut written)?;
        if req.plots {
            let multi_label = format!("{}-mode RFP fit", req.modes);
            let fig = plots::frf_figure(
                &file,
                &out.frf,
                &[("single-mode fit", &out.single_mode), (multi_label.as_str(), &out.multi_mode)],
            );
            written.extend(plots::render_both(&fig, dir, "modal-frf")?);
        }
        out.written = written;
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------
// Synthetic measurements
// ---------------------------------------------------------------------------------------

/// What [`synth`] does.
#[derive(Clone, Debug)]
pub struct SynthRequest {
    pub case: PathBuf,
    /// The CSV file; a d_p pair writes `STEM_1.EXT` and `STEM_2.EXT` next to it.
    pub out: PathBuf,
    pub options: SynthOptions,
    /// Significant digits of the data columns (default 7: a 24-bit acquisition's
    /// resolution; None: shortest exact form).
    pub digits: Option<usize>,
}

/// Result of [`synth`].
#[derive(Clone, Debug)]
pub struct SynthOutcome {
    pub files: Vec<PathBuf>,
    pub truth: Truth,
    pub samples: Vec<usize>,
}

impl SynthOutcome {
    /// What the CLI prints.
    pub fn report(&self) -> String {
        let mut s: String = self.truth.comments().iter().map(|c| format!("{c}\n")).collect();
        for (f, n) in self.files.iter().zip(&self.samples) {
            s += &format!("wrote {} ({n} samples)\n", f.display());
        }
        s
    }
}

/// Output paths: `out` for one record; `STEM_1.EXT`, `STEM_2.EXT` for two.
fn record_paths(out: &Path, n: usize) -> Vec<PathBuf> {
    if n == 1 {
        return vec![out.to_path_buf()];
    }
    let stem = out.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "synth".into());
    let ext = out.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_else(|| "csv".into());
    (1..=n).map(|k| out.with_file_name(format!("{stem}_{k}.{ext}"))).collect()
}

/// Makes synthetic measurements of a case and writes them as CSV.
pub fn synth(req: &SynthRequest) -> Result<SynthOutcome> {
    if measurement::split_hdf5_source(&req.out.to_string_lossy()).is_some() {
        return Err(Error::input("<cli>", "--out", "synth writes CSV files; give a .csv name"));
    }
    let lc = LoadedCase::load(&req.case)?;
    let s = synth::synthesize(&lc, &req.options)?;
    let paths = record_paths(&req.out, s.records.len());
    let inputs = crate::app::case_inputs(&lc);
    for (k, p) in paths.iter().enumerate() {
        refuse_input("--out", p, &inputs)?;
        refuse_output("--out", p, &paths[..k])?;
    }
    let _lock = OutputLock::file(&req.out)?;
    let mut samples = Vec::new();
    for (k, (m, p)) in s.records.iter().zip(&paths).enumerate() {
        let mut comments = s.truth.comments();
        if s.records.len() > 1 {
            comments.push(format!(
                "record {} of {}{}",
                k + 1,
                s.records.len(),
                if req.options.kind == SynthKind::DpPair && k == 1 {
                    format!(
                        ", starting {} samples later in the cycle",
                        req.options.lag % req.options.samples_per_period
                    )
                } else {
                    String::new()
                }
            ));
        }
        write_atomic_string(p, &measurement::to_csv_with(m, &comments, req.digits))?;
        samples.push(m.len());
    }
    Ok(SynthOutcome { files: paths, truth: s.truth, samples })
}
