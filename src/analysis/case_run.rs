//! What a case run produced: each analysis' result in case order, with the model and the
//! assembled system they ran on. Output and figures read this; the application layer's runner
//! fills it.

use crate::analysis::harmonic::HarmonicResult;
use crate::analysis::modes::ModesResult;
use crate::analysis::steady_state::SteadyStateResult;
use crate::analysis::transient::TransientResult;
use crate::assembly::{Model, System};
use crate::case::measured::MeasuredQuantity;
use num_complex::Complex64;

/// One analysis' result, in case order.
#[derive(Clone, Debug)]
pub enum AnalysisResult {
    Modes(ModesResult),
    Harmonic(HarmonicResult),
    Transient(Box<TransientResult>),
    SteadyState(Box<SteadyStateResult>),
}

/// Everything a case run produced.
#[derive(Clone, Debug)]
pub struct CaseRun {
    pub model: Model,
    pub system: System,
    pub results: Vec<AnalysisResult>,
    /// The case's measurements against each periodic analysis' prediction.
    pub measured: Vec<Comparison>,
    /// Per result, in case order: its plate grid's error estimate, or why it has none
    /// (None: not a plate's point powers).
    pub mesh: Vec<Option<crate::analysis::mesh_estimate::MeshCheck>>,
}

/// The largest energy-balance error a result may have (relative): the analyses balance to
/// 1e-6 or better on every shipped and tested case (exactly, up to round-off, for the
/// frequency-domain ones and average acceleration), so an error this large means the
/// numbers describe no motion of the model and are refused.
pub const BALANCE_TOLERANCE: f64 = 1e-3;

impl AnalysisResult {
    /// The result's energy-balance error (relative) and what it balances: power in against
    /// power dissipated (harmonic: the largest over the frequencies; steady state), or the
    /// work put in against dissipation and stored energy over the run (transient). None for
    /// modes.
    pub fn balance(&self) -> Option<(&'static str, f64)> {
        match self {
            AnalysisResult::Modes(_) => None,
            AnalysisResult::Harmonic(h) => Some((
                "power in − dissipated, largest over the frequencies",
                h.balance_error.iter().fold(0.0, |a, &b| a.max(b)),
            )),
            AnalysisResult::Transient(t) => {
                Some(("work in − dissipated − Δ stored over the run", t.energy_run.system.relative_error()))
            }
            AnalysisResult::SteadyState(s) => Some(("power in − dissipated", s.balance_error)),
        }
    }

    /// The result's bound on the relative round-off of its point powers and mobilities
    /// ([`crate::analysis::roundoff`]); None for modes.
    pub fn mesh_roundoff(&self) -> Option<f64> {
        match self {
            AnalysisResult::Modes(_) => None,
            AnalysisResult::Harmonic(h) => Some(h.mesh_roundoff),
            AnalysisResult::Transient(t) => Some(t.mesh_roundoff),
            AnalysisResult::SteadyState(s) => Some(s.mesh_roundoff),
        }
    }

    /// The first reported quantity that is not a finite number (NaN or ±∞), named: such a
    /// result is never reported as a success. Series are checked whole, headline numbers
    /// one by one.
    pub fn non_finite(&self) -> Option<String> {
        let bad = |x: &f64| !x.is_finite();
        let first = |name: &str, v: &[f64]| v.iter().position(bad).map(|i| format!("{name}[{i}] = {}", v[i]));
        let one = |name: &str, x: f64| bad(&x).then(|| format!("{name} = {x}"));
        match self {
            AnalysisResult::Modes(m) => first("frequencies_hz", &m.frequencies_hz),
            AnalysisResult::Harmonic(h) => h
                .input_power
                .iter()
                .enumerate()
                .find_map(|(f, p)| first(&format!("input_power at frequency {f}"), p))
                .or_else(|| first("dissipated_power", &h.dissipated_power)),
            AnalysisResult::Transient(t) => first("mean_power", &t.mean_power)
                .or_else(|| first("net_power", &t.net_power))
                .or_else(|| one("beam_dissipation", t.beam_dissipation))
                .or_else(|| t.links.iter().find_map(|l| first(&format!("links.{}.interface", l.name), &l.interface)))
                .or_else(|| {
                    t.load_spectra.iter().find_map(|l| one(&format!("loads.{}.mean_power", l.name), l.power_total))
                })
                .or_else(|| t.loads.iter().find_map(|l| first(&format!("loads.{}.v", l.name), &l.v)))
                .or_else(|| {
                    t.record
                        .as_ref()
                        .and_then(|r| r.points.iter().find_map(|p| one(&format!("record.{}.energy", p.name), p.energy)))
                }),
            AnalysisResult::SteadyState(s) => first("mean_power", &s.mean_power)
                .or_else(|| first("net_power", &s.net_power))
                .or_else(|| one("beam_dissipation", s.beam_dissipation))
                .or_else(|| {
                    s.load_spectra.iter().find_map(|l| one(&format!("loads.{}.mean_power", l.name), l.power_total))
                })
                .or_else(|| s.links.iter().find_map(|l| first(&format!("links.{}.interface", l.name), &l.interface))),
        }
    }
}

/// One measured quantity against one analysis' prediction.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// The analysis (case order) the prediction is from.
    pub analysis: usize,
    pub name: String,
    pub point: String,
    pub quantity: MeasuredQuantity,
    /// The measurement's source, as read.
    pub file: String,
    /// The harmonics compared (k ≥ 1) and their frequencies (Hz).
    pub harmonic: Vec<usize>,
    pub frequency: Vec<f64>,
    /// Complex amplitudes (N or m/s²) at those harmonics; for power, the power per
    /// harmonic (W) as a real number.
    pub measured: Vec<Complex64>,
    pub predicted: Vec<Complex64>,
    /// Level error (dB) and phase error (rad, in (−π, π]; for power 0 or π: the sign).
    pub error_db: Vec<f64>,
    pub phase_error: Vec<f64>,
    /// RMS of measured minus predicted over the record (unit of the quantity), and that
    /// relative to the prediction's RMS over the same times; NaN for power.
    pub rms_error: f64,
    pub relative_rms_error: f64,
    pub tolerance_db: Option<f64>,
}

impl Comparison {
    /// The largest |level error| over the compared harmonics (NaN if none).
    pub fn max_abs_error_db(&self) -> f64 {
        self.error_db.iter().map(|e| e.abs()).reduce(f64::max).unwrap_or(f64::NAN)
    }

    /// The level error at the drive frequency (harmonic 1), if compared.
    pub fn drive_error_db(&self) -> Option<f64> {
        self.harmonic.iter().position(|&k| k == 1).map(|i| self.error_db[i])
    }

    /// Whether every compared harmonic is within the tolerance (None without one).
    pub fn agrees(&self) -> Option<bool> {
        self.tolerance_db.map(|t| !self.harmonic.is_empty() && self.max_abs_error_db() <= t)
    }

    /// The SI unit of the amplitudes.
    pub fn unit(&self) -> &'static str {
        match self.quantity {
            MeasuredQuantity::Force => "N",
            MeasuredQuantity::Acceleration => "m/s^2",
            MeasuredQuantity::Power => "W",
        }
    }
}
