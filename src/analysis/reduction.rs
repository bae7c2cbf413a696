//! Modal reduction as a solver option of the transient and steady-state analyses.
//!
//! [`reduce`] builds the reduced [`System`] (see [`crate::solve::modal_basis`] for the basis:
//! bare-beam modes up to a cut-off, residual-flexibility vectors at the feet, actuator
//! bodies physical); the analyses then run on it unchanged. [`super::steady_state::estimate_reduction_error`] compares
//! the frequency-domain periodic steady state (§9) of the reduced and the full model at the
//! drive harmonics — a few complex solves each — and reports how far the point powers
//! differ. The estimate is the same whichever domain the reduced run itself was in: the
//! reduction error is a property of the model pair, and the frequency domain isolates it
//! from the time-step error of a transient.

use super::drive::common_period;
use crate::assembly::{Model, System};
use crate::error::{Error, Result};
use crate::power::point::relative_to_own;
use crate::solve::eigen::Modes;
use crate::solve::modal_basis::{self as red, ReductionOptions};
use crate::solve::shared_basis::{Pattern, SharedBasis};
use serde::Serialize;
use std::f64::consts::PI;

/// The multiple of the highest analysed harmonic that `reduction = "auto"` keeps modes up to.
pub const AUTO_FACTOR: f64 = 5.0;

/// Where the modal cut-off lies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cutoff {
    /// An explicit frequency (Hz).
    Hz(f64),
    /// This multiple of the highest analysed harmonic of the drive (k_max·f₀).
    HarmonicFactor(f64),
}

/// A reduction request, with the case field it came from (for messages).
#[derive(Clone, Debug, PartialEq)]
pub struct ReductionSettings {
    pub cutoff: Cutoff,
    pub static_correction: bool,
    /// Compare with the full model (frequency domain) and report the difference.
    pub error_estimate: bool,
    /// The case's modal damping ratios per bare-beam mode (the last repeats), if it asked
    /// for modal damping: the reduced model applies them in its modal coordinates.
    pub modal_damping: Option<Vec<f64>>,
}

impl ReductionSettings {
    /// The solver-side settings of a case's `reduction` entry, for a case with the given
    /// modal damping ratios (None: Rayleigh or no damping).
    pub fn of_spec(spec: &crate::case::ReductionSpec, modal_damping: Option<&[f64]>) -> Self {
        ReductionSettings {
            cutoff: match (spec.modes_up_to_hz, spec.factor) {
                (Some(f), _) => Cutoff::Hz(f),
                (None, k) => Cutoff::HarmonicFactor(k.unwrap_or(AUTO_FACTOR)),
            },
            static_correction: spec.static_correction,
            error_estimate: spec.error_estimate,
            modal_damping: modal_damping.map(<[f64]>::to_vec),
        }
    }
}

/// The difference between reduced and full model, from the frequency-domain steady state.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ReductionError {
    /// Harmonics of the drive compared (besides the mean).
    pub harmonics: usize,
    /// Mean power into the base per link (W), full and reduced model.
    pub full_mean_power: Vec<f64>,
    pub reduced_mean_power: Vec<f64>,
    /// |P_red − P_full| / |P_full| per link. A point whose |P_full| is below 1e-6 of the
    /// largest point power is measured against that largest instead.
    pub relative_error: Vec<f64>,
    /// The largest of `relative_error`: the headline estimate.
    pub max_relative_error: f64,
    /// Net power per actuator, relative difference.
    pub net_power_relative_error: Vec<f64>,
}

impl ReductionError {
    /// The difference of the point powers (W, per link) and net powers (W, per actuator)
    /// of a reduced model from the full model's, at `harmonics` harmonics.
    pub fn between(harmonics: usize, full: (&[f64], &[f64]), reduced: (&[f64], &[f64])) -> Self {
        let relative_error = relative_to_own(full.0, reduced.0);
        ReductionError {
            harmonics,
            full_mean_power: full.0.to_vec(),
            reduced_mean_power: reduced.0.to_vec(),
            max_relative_error: relative_error.iter().fold(0.0f64, |a, &b| a.max(b)),
            relative_error,
            net_power_relative_error: relative_to_own(full.1, reduced.1),
        }
    }

    /// The largest relative difference, point or net power.
    pub fn largest(&self) -> f64 {
        self.net_power_relative_error.iter().fold(self.max_relative_error, |a, &b| a.max(b))
    }
}

/// What a reduced run reports with its result.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ReductionReport {
    /// The cut-off used (Hz).
    pub cutoff_hz: f64,
    pub static_correction: bool,
    /// Bare-beam modes kept and their frequencies (Hz).
    pub modes_kept: usize,
    pub mode_frequencies_hz: Vec<f64>,
    /// The lowest discarded mode (Hz), if any.
    pub first_discarded_mode_hz: Option<f64>,
    /// Residual-flexibility vectors (static correction) kept, and their
    /// pseudo-frequencies (Hz).
    pub residual_vectors: usize,
    pub residual_frequencies_hz: Vec<f64>,
    /// DOFs of the full and the reduced system.
    pub full_dofs: usize,
    pub reduced_dofs: usize,
    /// Against the full model, if asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<ReductionError>,
}

/// The highest analysed harmonic frequency k_max·f₀ (Hz) of a periodic drive.
pub fn highest_harmonic_hz(model: &Model, harmonics: usize) -> Result<f64> {
    let period = common_period(model)?.ok_or_else(|| {
        Error::analysis_setting(
            "reduction",
            "a cut-off relative to the drive's harmonics needs a periodic drive: give `modes_up_to_hz`",
        )
    })?;
    Ok(harmonics as f64 / period)
}

/// The cut-off (Hz) a setting means for a model analysed up to harmonic `harmonics`.
pub fn cutoff_hz(model: &Model, settings: &ReductionSettings, harmonics: usize) -> Result<f64> {
    match settings.cutoff {
        Cutoff::Hz(f) => Ok(f),
        Cutoff::HarmonicFactor(k) => Ok(k * highest_harmonic_hz(model, harmonics)?),
    }
}

/// Builds the reduced system of `full` for a cut-off of `cutoff_hz`. Errors (against the
/// field `analysis.reduction…`, which the runner relabels with the file and entry) if
/// the cut-off keeps no mode. A plate or an imported model is reduced as a placement
/// study reduces each of its cases ([`SharedReduction`]), so that a case run alone gives
/// the study's numbers; a beam keeps its own path, bit for bit.
pub fn reduce(
    model: &Model,
    full: &System,
    settings: &ReductionSettings,
    cutoff_hz: f64,
) -> Result<(System, ReductionReport)> {
    if model.beam().is_none() && model.structure.is_some() {
        return SharedReduction::new(model, settings, cutoff_hz)?.system(model);
    }
    let (modes, sparse) = modes_to(model, full, settings, cutoff_hz)?;
    let opts = options(settings, cutoff_hz, sparse);
    let r = red::reduce(full, &modes, &opts)?;
    let report = report_of(&r, settings, cutoff_hz, full.n());
    Ok((r.system, report))
}

/// The bare structure's modes a reduction of `full` at `cutoff_hz` keeps (and the first
/// above), and whether they came from the sparse path. A beam keeps its dense (or root)
/// path, bit for bit; a large plate or imported model computes only the modes the
/// cut-off keeps, on its sparse factor. Errors if the cut-off keeps no mode.
fn modes_to(model: &Model, full: &System, settings: &ReductionSettings, cutoff_hz: f64) -> Result<(Modes, bool)> {
    let field = match settings.cutoff {
        Cutoff::Hz(_) => "reduction.modes_up_to_hz",
        Cutoff::HarmonicFactor(_) => "reduction.factor",
    };
    if model.structure.is_none() {
        return Err(Error::analysis_setting("reduction", "a modal reduction needs a structure (base = \"beam\")"));
    }
    let large = full.dofs.structure_dofs().len() > crate::analysis::modes::DENSE_EIGEN_LIMIT;
    let is_beam = model.structure.as_ref().and_then(|s| s.beam()).is_some();
    let sparse = large && !is_beam && cutoff_hz.is_finite() && cutoff_hz > 0.0;
    let modes = match sparse {
        true => red::structure_modes_to(full, 2.0 * PI * cutoff_hz)?,
        false => red::beam_modes(full)?,
    };
    let f1 = modes.omega.first().map_or(f64::INFINITY, |w| w / (2.0 * PI));
    if cutoff_hz.is_nan() || cutoff_hz < f1 {
        return Err(Error::analysis_setting(
            field,
            format!(
                "the cut-off {cutoff_hz:.1} Hz is below the structure's first natural frequency {f1:.2} Hz, so no mode \
                 would be kept; raise it (\"auto\" keeps the modes up to 5× the highest analysed harmonic)"
            ),
        ));
    }
    Ok((modes, sparse))
}

fn options(settings: &ReductionSettings, cutoff_hz: f64, sparse: bool) -> ReductionOptions {
    ReductionOptions {
        cutoff: 2.0 * PI * cutoff_hz,
        static_correction: settings.static_correction,
        modal_damping: settings.modal_damping.clone(),
        sparse_factor: sparse,
    }
}

/// What a reduction `r` of a `full_dofs` system reports.
fn report_of(r: &red::Reduction, settings: &ReductionSettings, cutoff_hz: f64, full_dofs: usize) -> ReductionReport {
    let hz = |w: &f64| w / (2.0 * PI);
    ReductionReport {
        cutoff_hz,
        static_correction: settings.static_correction,
        modes_kept: r.mode_omega.len(),
        mode_frequencies_hz: r.mode_omega.iter().map(hz).collect(),
        first_discarded_mode_hz: r.first_discarded_omega.as_ref().map(hz),
        residual_vectors: r.residual_omega.len(),
        residual_frequencies_hz: r.residual_omega.iter().map(hz).collect(),
        full_dofs,
        reduced_dofs: r.system.n(),
        error: None,
    }
}

/// A reduction shared by the cases of a placement study on one structure
/// ([`SharedBasis`]): the bare structure's modes up to the cut-off, computed once; each
/// case's static correction and actuators added per case.
#[derive(Debug)]
pub struct SharedReduction {
    basis: SharedBasis,
    settings: ReductionSettings,
    cutoff_hz: f64,
}

impl SharedReduction {
    /// The shared reduction of the structure (and its damping) of `model`, keeping the
    /// modes up to `cutoff_hz`. Refuses hysteretic damping, as a case's reduction does.
    pub fn new(model: &Model, settings: &ReductionSettings, cutoff_hz: f64) -> Result<Self> {
        if model.loss_factor() > 0.0 {
            return Err(Error::analysis_setting(
                "reduction",
                "a modal reduction is not available with hysteretic damping: run the full model",
            ));
        }
        let Some(structure) = model.structure.clone() else {
            return Err(Error::analysis_setting("reduction", "a modal reduction needs a structure (base = \"beam\")"));
        };
        let bare = Model {
            damping: model.damping.clone(),
            roundoff_tolerance: model.roundoff_tolerance,
            ..Model::bare(structure)
        };
        let bare_sys = System::assemble(&bare)?;
        let (modes, sparse) = modes_to(&bare, &bare_sys, settings, cutoff_hz)?;
        let basis = SharedBasis::new(&bare_sys, &modes, &options(settings, cutoff_hz, sparse))?;
        Ok(SharedReduction { basis, settings: settings.clone(), cutoff_hz })
    }

    /// The cut-off (Hz).
    pub fn cutoff_hz(&self) -> f64 {
        self.cutoff_hz
    }

    /// The structure's modes kept.
    pub fn modes_kept(&self) -> usize {
        self.basis.modes()
    }

    /// The patterns along which the actuators and loads of `model` (a case on the same
    /// structure) act on it: what [`SharedReduction::prefetch`] takes.
    pub fn attachment_patterns(&self, model: &Model) -> Result<Vec<Pattern>> {
        Ok(self.basis.attachment_patterns(&System::assemble_attachments_on(model, self.basis.structure_dofs())?))
    }

    /// Solves the static shapes of `patterns` up front ([`SharedBasis::prefetch`]).
    pub fn prefetch(&self, patterns: &[Pattern]) -> usize {
        self.basis.prefetch(patterns)
    }

    /// The same reduction keeping at most `bytes` of static shapes (0: every case solves
    /// its own).
    pub fn with_shape_cache(mut self, bytes: u64) -> Self {
        self.basis.set_shape_cache(bytes);
        self
    }

    /// The reduced system of `model` (a case on the same structure) and its report.
    pub fn system(&self, model: &Model) -> Result<(System, ReductionReport)> {
        let attached = System::assemble_attachments_on(model, self.basis.structure_dofs())?;
        let r = self.basis.reduce(&attached)?;
        let report = report_of(&r, &self.settings, self.cutoff_hz, attached.n());
        Ok((r.system, report))
    }
}

/// Beam DOFs up to which [`complete_modal_basis`] computes every mode. The paper beam
/// (398) takes 0.35 s for a whole steady-state run; at this limit (≈ 500 elements) about
/// 5 s, mostly the dense complex factorisation per harmonic of a system that is then
/// dense. Beyond ≈ 1300 DOFs the dense eigensolver also loses the highest modes to
/// round-off (K's condition number grows as the fourth power of the element count).
pub const COMPLETE_BASIS_LIMIT: usize = 1000;

/// The full model in the complete modal basis of the bare beam (every mode kept, the
/// actuator bodies physical) with modal damping `ratios` applied: the same model as `full`
/// in other coordinates, and the only form in which modal damping is a matrix of the size
/// of the model rather than dense over all beam DOFs. The frequency-domain analyses run a
/// modal-damped case on it, and a reduced model's error estimate compares against it.
pub fn complete_modal_basis(full: &System, ratios: &[f64]) -> Result<System> {
    let beam_dofs = full.dofs.structure_dofs().len();
    if beam_dofs > COMPLETE_BASIS_LIMIT {
        return Err(Error::analysis_setting(
            "reduction",
            format!(
                "modal damping without a reduction needs all {beam_dofs} modes of the beam (dense, above the \
                 {COMPLETE_BASIS_LIMIT} this computes); give `reduction = \"auto\"` or a cut-off"
            ),
        ));
    }
    let modes = red::beam_modes(full)?;
    let opts = ReductionOptions {
        cutoff: f64::INFINITY,
        static_correction: false,
        modal_damping: Some(ratios.to_vec()),
        sparse_factor: false,
    };
    Ok(red::reduce(full, &modes, &opts)?.system)
}
