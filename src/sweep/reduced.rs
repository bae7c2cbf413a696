//! The system a study (a sweep or an optimisation) solves a case's steady state on: the
//! case's assembled system, or — when the base case's steady state asks for a modal
//! `reduction` — a reduction of it.
//!
//! Where every case has the base's structure (a plate or an imported model that the study
//! does not vary, [`BaseCase::share_structure`]), one [`SharedReduction`] serves them all:
//! the bare structure's modes are computed once, for the first case that needs them, and
//! each case adds its own static correction and actuators. Its cut-off covers every case:
//! an explicit `modes_up_to_hz`, or the `factor` times the highest analysed harmonic over
//! the base case and the study's extremes (each varied field at its least and greatest
//! value); a case whose own cut-off would lie above it is refused, naming the setting to
//! give. Otherwise (a beam, whose mesh follows the feet, or a varied structure) each case
//! is reduced on its own, as its own run would.

use super::base::BaseCase;
use super::field::Field;
use crate::analysis::reduction::{self, ReductionReport, ReductionSettings, SharedReduction};
use crate::assembly::{Model, System};
use crate::case::ReductionSpec;
use crate::error::{Error, Result};
use std::sync::{Arc, OnceLock};

/// How a study's cases get their systems.
#[derive(Debug)]
pub struct StudySystems {
    /// The reduction the base case asks for (None: the full system).
    spec: Option<ReductionSpec>,
    harmonics: usize,
    /// What the shared basis is built from: the base case and the study's extremes
    /// (None: each case is reduced on its own).
    shared_from: Option<SharedFrom>,
    shared: OnceLock<std::result::Result<Arc<SharedReduction>, String>>,
}

#[derive(Debug)]
struct SharedFrom {
    study: String,
    base: BaseCase,
    extremes: Vec<(String, Field, toml::Value)>,
}

impl StudySystems {
    /// The systems of the cases of a study on `base` (its file `study`), solved with
    /// `harmonics` harmonics; `extremes` are its varied fields at their least and greatest
    /// values.
    pub fn new(study: &str, base: &BaseCase, harmonics: usize, extremes: Vec<(String, &Field, toml::Value)>) -> Self {
        let spec = base.reduction.clone();
        let shared_from = (spec.is_some() && base.shared_structure).then(|| SharedFrom {
            study: study.to_string(),
            base: base.clone(),
            extremes: extremes.into_iter().map(|(n, f, v)| (n, f.clone(), v)).collect(),
        });
        StudySystems { spec, harmonics, shared_from, shared: OnceLock::new() }
    }

    /// Every case on its full assembled system, whatever the base case asks (a study's
    /// figures that decompose the power into the structure's modes, which need its DOFs).
    pub fn full(harmonics: usize) -> Self {
        StudySystems { spec: None, harmonics, shared_from: None, shared: OnceLock::new() }
    }

    /// Whether the cases are solved on a reduction.
    pub fn reduced(&self) -> bool {
        self.spec.is_some()
    }

    /// The shared reduction, once built (None before the first case, or without one).
    pub fn shared(&self) -> Option<&SharedReduction> {
        self.shared.get().and_then(|r| r.as_ref().ok()).map(Arc::as_ref)
    }

    /// The system of the case `model` (read from `file`), and its reduction's report.
    pub fn system(&self, model: &Model, file: &str) -> Result<(System, Option<ReductionReport>)> {
        let Some(spec) = &self.spec else {
            let sys = super::exec::frequency_domain_system(model, file, super::SweepAnalysis::SteadyState)?;
            return Ok((sys, None));
        };
        let settings = &ReductionSettings::of_spec(spec, model.modal_ratios());
        let case_cutoff = reduction::cutoff_hz(model, settings, self.harmonics).map_err(|e| e.in_file(file))?;
        let Some(from) = &self.shared_from else {
            let full = System::assemble(model).map_err(|e| e.in_file(file))?;
            let (sys, report) = reduction::reduce(model, &full, settings, case_cutoff).map_err(|e| e.in_file(file))?;
            return Ok((sys, Some(report)));
        };
        let shared = self
            .shared
            .get_or_init(|| from.build(settings, self.harmonics).map(Arc::new).map_err(|e| e.to_string()))
            .as_ref()
            .map_err(|e| Error::Numerical(e.clone()))?;
        if case_cutoff > shared.cutoff_hz() * (1.0 + 1e-12) {
            return Err(Error::input(
                file,
                "analysis.reduction",
                format!(
                    "this case's cut-off {case_cutoff:.1} Hz is above the {:.1} Hz the study's shared modes reach (from \
                     the base case and each varied field at its bounds); give `reduction = {{ modes_up_to_hz = \
                     {case_cutoff:.0} }}` or more in the base case's steady state",
                    shared.cutoff_hz()
                ),
            ));
        }
        let (sys, report) = shared.system(model).map_err(|e| e.in_file(file))?;
        Ok((sys, Some(report)))
    }
}

impl SharedFrom {
    /// The shared reduction: on the base case's structure, up to the highest cut-off the
    /// base case and the extremes ask for.
    fn build(&self, settings: &ReductionSettings, harmonics: usize) -> Result<SharedReduction> {
        let base = &self.base;
        let model_of = |set: Option<(&Field, toml::Value)>, name: &str| -> Result<Model> {
            let lc = base.case_with(set, &base.file).map_err(|r| Error::input(&self.study, name, r))?;
            crate::analysis::plan::calibrated_model(&lc)
        };
        let model = model_of(None, "base")?;
        let mut cutoff = reduction::cutoff_hz(&model, settings, harmonics).map_err(|e| e.in_file(&base.file))?;
        if let reduction::Cutoff::HarmonicFactor(_) = settings.cutoff {
            for (name, field, value) in &self.extremes {
                let m = model_of(Some((field, value.clone())), name)?;
                let c = reduction::cutoff_hz(&m, settings, harmonics).map_err(|e| e.in_file(&self.study))?;
                cutoff = cutoff.max(c);
            }
        }
        SharedReduction::new(&model, settings, cutoff).map_err(|e| e.in_file(&base.file))
    }
}
