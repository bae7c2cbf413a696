//! Runs every analysis a case asks for. Pure computation: writing is in [`crate::io`].

use crate::analysis::harmonic::{self, HarmonicResult, PointForce};
use crate::analysis::modes::{self, ModesResult};
use crate::analysis::transient::{self, TransientResult, TransientSettings};
use crate::assembly::{Model, System};
use crate::case::{build_model, AnalysisSpec, LoadedCase, SchemeKind};
use crate::error::{Error, Result};
use crate::solve::newmark::Scheme;

/// Modes in the mode-resolved tables of a run (the residual of the truncated sum is reported).
pub const MODAL_TABLE_MODES: usize = 30;

/// One analysis' result, in case order.
#[derive(Clone, Debug)]
pub enum AnalysisResult {
    Modes(ModesResult),
    Harmonic(HarmonicResult),
    Transient(Box<TransientResult>),
    SteadyState(Box<crate::analysis::steady_state::SteadyStateResult>),
}

/// Everything a case run produced.
#[derive(Clone, Debug)]
pub struct CaseRun {
    pub model: Model,
    pub system: System,
    pub results: Vec<AnalysisResult>,
}

/// The transient settings a case's analysis entry describes.
pub fn transient_settings(spec: &AnalysisSpec) -> Option<TransientSettings> {
    if let AnalysisSpec::Transient {
        dt,
        periods,
        duration,
        scheme,
        alpha,
        rho_inf,
        steady_state,
        tolerance,
        max_periods,
        harmonics,
    } = spec
    {
        let scheme = match scheme {
            SchemeKind::AverageAcceleration => Scheme::average_acceleration(),
            SchemeKind::LinearAcceleration => Scheme::linear_acceleration(),
            SchemeKind::Hht => Scheme::hht(alpha.unwrap_or(0.1)),
            SchemeKind::GeneralizedAlpha => Scheme::generalized_alpha(rho_inf.unwrap_or(0.9)),
        };
        Some(TransientSettings {
            dt: *dt,
            periods: *periods,
            duration: *duration,
            scheme,
            steady_state: *steady_state,
            tolerance: *tolerance,
            max_periods: *max_periods,
            harmonics: *harmonics,
            record_periods: 3,
        })
    } else {
        None
    }
}

/// Builds the model and runs the case's analyses in order.
pub fn run_case(lc: &LoadedCase) -> Result<CaseRun> {
    let built = build_model(lc)?;
    let model = built.model;
    let system = System::assemble(&model)?;
    let mut results = Vec::new();
    for (i, spec) in lc.case.analysis.iter().enumerate() {
        let field = format!("analysis[{i}]");
        let need_beam = || {
            model
                .beam
                .as_ref()
                .ok_or_else(|| Error::input(&lc.file, &field, "this analysis needs a beam, but base = \"rigid\""))
        };
        let r = match spec {
            AnalysisSpec::Modes { count } => AnalysisResult::Modes(modes::run(need_beam()?, *count)?),
            AnalysisSpec::Harmonic { frequencies, force } => {
                let beam = need_beam()?;
                let bare = Model {
                    beam: Some(beam.clone()),
                    rayleigh: model.rayleigh,
                    actuators: Vec::new(),
                    sensors: model.sensors.clone(),
                };
                let sys = System::assemble(&bare)?;
                let forces: Vec<PointForce> =
                    force.iter().map(|f| PointForce { x: f.x, amplitude: f.amplitude, phase: f.phase }).collect();
                let modal = match &built.modal_ratios {
                    Some(r) => Some((crate::case::build::bare_modes(beam, usize::MAX)?, r.clone())),
                    None => None,
                };
                AnalysisResult::Harmonic(harmonic::run(
                    &bare,
                    &sys,
                    &frequencies.list(),
                    &forces,
                    modal.as_ref().map(|(m, r)| (m, r.as_slice())),
                )?)
            }
            AnalysisSpec::Transient { .. } => {
                let s = transient_settings(spec).expect("transient");
                AnalysisResult::Transient(Box::new(
                    transient::run(&model, &system, &s).map_err(|e| relabel(e, &lc.file, &field))?,
                ))
            }
            AnalysisSpec::SteadyState { harmonics, samples_per_period } => {
                let mut s = crate::analysis::steady_state::run(&model, &system, *harmonics, *samples_per_period)
                    .map_err(|e| relabel(e, &lc.file, &field))?;
                s.decompose_modes(&model, &system, MODAL_TABLE_MODES)?;
                AnalysisResult::SteadyState(Box::new(s))
            }
        };
        results.push(r);
    }
    Ok(CaseRun { model, system, results })
}

/// Analyses report input problems against `<case>`/`analysis`; name the real file and entry.
fn relabel(e: Error, file: &str, field: &str) -> Error {
    match e {
        Error::Input { file: f, field: fl, reason } if f == "<case>" => {
            let fl = fl.strip_prefix("analysis.").map(|s| format!("{field}.{s}")).unwrap_or(fl);
            Error::Input { file: file.to_string(), field: fl, reason }
        }
        e => e,
    }
}
