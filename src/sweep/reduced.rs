//! The system a study (a sweep or an optimisation) solves a case's steady state on: the
//! case's assembled system, or — when the base case's steady state asks for a modal
//! `reduction` and every case has the base's structure — one reduction shared by them all.
//!
//! Every case has the base's structure when it is a plate or an imported model that the
//! study does not vary ([`BaseCase::share_structure`]). Then one [`SharedReduction`] serves
//! all of them: the bare structure's modes are computed once, for the first case that needs
//! them, and each case adds its own static correction and actuators. Its cut-off covers
//! every case: an explicit `modes_up_to_hz`, or the `factor` times the highest analysed
//! harmonic over the base case and the study's extremes (each varied field at its least and
//! greatest value); a case whose own cut-off would lie above it is refused, naming the
//! setting to give. Otherwise (a beam, whose mesh follows the feet and whose banded solve
//! is faster than any reduction, or a varied structure) every case is solved on its full
//! system, as before.

use super::base::BaseCase;
use super::field::Field;
use crate::analysis::reduction::{self, ReductionReport, ReductionSettings, SharedReduction};
use crate::assembly::{Model, System};
use crate::case::ReductionSpec;
use crate::error::{Error, Result};
use rayon::prelude::*;
use std::sync::Arc;

/// How a study's cases get their systems.
#[derive(Debug)]
pub struct StudySystems {
    harmonics: usize,
    /// What the shared reduction is built from (None: every case on its full system). It
    /// is built by the first case that needs it and kept in the base's
    /// [`BaseCase::shared_reduction`]; a failed build, e.g. a cancelled one, is not kept:
    /// its error goes to that case as it is.
    shared_from: Option<SharedFrom>,
}

#[derive(Debug)]
struct SharedFrom {
    spec: ReductionSpec,
    study: String,
    base: BaseCase,
    extremes: Vec<(String, Field, toml::Value)>,
}

impl StudySystems {
    /// The systems of the cases of a study on `base` (its file `study`), solved with
    /// `harmonics` harmonics; `extremes` are its varied fields at their least and greatest
    /// values.
    pub fn new(study: &str, base: &BaseCase, harmonics: usize, extremes: Vec<(String, &Field, toml::Value)>) -> Self {
        let shared_from = base.reduction.clone().filter(|_| base.shared_structure).map(|spec| SharedFrom {
            spec,
            study: study.to_string(),
            base: base.clone(),
            extremes: extremes.into_iter().map(|(n, f, v)| (n, f.clone(), v)).collect(),
        });
        StudySystems { harmonics, shared_from }
    }

    /// Every case on its full assembled system, whatever the base case asks (a study's
    /// figures that decompose the power into the structure's modes, which need its DOFs).
    pub fn full(harmonics: usize) -> Self {
        StudySystems { harmonics, shared_from: None }
    }

    /// The shared reduction, once built (None before the first case, or without one).
    pub fn shared(&self) -> Option<Arc<SharedReduction>> {
        self.shared_from.as_ref()?.base.shared_reduction.lock().ok()?.clone()
    }

    /// The system of the case `model` (read from `file`), and its reduction's report.
    pub fn system(&self, model: &Model, file: &str) -> Result<(System, Option<ReductionReport>)> {
        let Some(from) = &self.shared_from else {
            let sys = super::exec::frequency_domain_system(model, file, super::SweepAnalysis::SteadyState)?;
            return Ok((sys, None));
        };
        let settings = &ReductionSettings::of_spec(&from.spec, model.modal_ratios());
        let case_cutoff = reduction::cutoff_hz(model, settings, self.harmonics).map_err(|e| e.in_file(file))?;
        let shared = from.shared(settings, self.harmonics)?;
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

    /// Solves up front, a block of right-hand sides per pass over the factor of K, the
    /// static shapes of the `count` cases `case` builds (a study that knows its
    /// candidates: the nodes of a node sweep, its positions; only where their actuators
    /// and loads stand is read), so that each case then reads them instead of solving its
    /// own. Builds the shared reduction if no case has yet, with the settings of `first`
    /// (a case's calibrated model). Without one, or where it or a case cannot be built,
    /// nothing is done: the cases' own evaluations report their errors. Returns the
    /// shapes solved.
    pub fn prefetch(&self, first: &Model, count: usize, case: impl Fn(usize) -> Result<Model> + Sync) -> usize {
        let Some(from) = &self.shared_from else { return 0 };
        let settings = &ReductionSettings::of_spec(&from.spec, first.modal_ratios());
        let Ok(shared) = from.shared(settings, self.harmonics) else { return 0 };
        let patterns: Vec<_> = (0..count)
            .into_par_iter()
            .filter_map(|i| case(i).ok().and_then(|m| shared.attachment_patterns(&m).ok()))
            .flatten()
            .collect();
        shared.prefetch(&patterns)
    }
}

impl SharedFrom {
    /// The study's shared reduction, built by the first case that asks for it.
    fn shared(&self, settings: &ReductionSettings, harmonics: usize) -> Result<Arc<SharedReduction>> {
        let cell = &self.base.shared_reduction;
        let mut slot = cell.lock().map_err(|_| Error::Numerical("a study thread panicked".into()))?;
        match slot.as_ref() {
            Some(s) => Ok(Arc::clone(s)),
            None => Ok(Arc::clone(slot.insert(Arc::new(self.build(settings, harmonics)?)))),
        }
    }

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
