//! Runs every analysis a case asks for. Pure computation: writing is in [`crate::io`].

use crate::analysis::budget::Budget;
use crate::analysis::case_run::{AnalysisResult, CaseRun, BALANCE_TOLERANCE};
use crate::analysis::cost;
use crate::analysis::drive::{DriveTiming, Step};
use crate::analysis::harmonic::{self, PointForce};
use crate::analysis::mesh_estimate::{self, MeshCheck, MeshEstimate, PointPowers};
use crate::analysis::modes;
use crate::analysis::plan;
use crate::analysis::reduction::{self, ReductionReport, ReductionSettings};
use crate::analysis::roundoff;
use crate::analysis::steady_state::{self, HarmonicCount};
use crate::analysis::transient::{self, TransientSettings};
use crate::assembly::{DofMap, Model, System};
use crate::case::measured::Measured;
use crate::case::{AnalysisSpec, HarmonicSystem, LoadedCase, ReductionSpec, SchemeKind};
use crate::error::{Error, Result};
use crate::power::modal::ModalDamping;
use crate::signal::sampling::samples_for_harmonics;
use crate::solve::newmark::Scheme;
use crate::structure::Structure;
use std::cell::OnceCell;

/// Modes in the mode-resolved tables of a run (the residual of the truncated sum is reported).
pub const MODAL_TABLE_MODES: usize = 30;

/// The forces of a harmonic analysis: its own `[[analysis.force]]`, or else the case's
/// sine loads, each at its amplitude and phase. A load A·sin(ωt + φ) is the phasor
/// A·e^{i(φ − π/2)} of the analysis's convention F(t) = Re(F̂·e^{iωt}).
fn harmonic_forces(force: &[crate::case::ForceSpec], model: &crate::assembly::Model) -> Vec<PointForce> {
    let loads = &model.loads;
    if !force.is_empty() {
        let resolve = |at| model.structure.as_ref().map_or(at, |s| s.resolve(at));
        return force
            .iter()
            .map(|f| PointForce { at: resolve(f.location()), amplitude: f.amplitude, phase: f.phase })
            .collect();
    }
    loads
        .iter()
        .filter_map(|l| match l.force {
            crate::signal::voltage::VoltageInput::Sine { amplitude, phase, .. } => {
                Some(PointForce { at: l.at, amplitude, phase: phase - std::f64::consts::FRAC_PI_2 })
            }
            _ => None,
        })
        .collect()
}

/// The transient settings a case's analysis entry describes (`history`: the case's
/// `[output] full_history` and `history_every`; None keeps the last three periods only).
pub fn transient_settings(spec: &AnalysisSpec, history: Option<usize>) -> Option<TransientSettings> {
    if let AnalysisSpec::Transient {
        dt,
        steps_per_period,
        periods,
        duration,
        scheme,
        alpha,
        rho_inf,
        steady_state,
        tolerance,
        max_periods,
        harmonics,
        segment,
        reduction: _,
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
            steps_per_period: *steps_per_period,
            periods: *periods,
            duration: *duration,
            scheme,
            steady_state: *steady_state,
            tolerance: *tolerance,
            max_periods: *max_periods,
            harmonics: *harmonics,
            segment: *segment,
            record_periods: 3,
            full_history: history.is_some(),
            history_every: history.unwrap_or(1),
        })
    } else {
        None
    }
}

/// Everything about a case's analyses that can be refused without solving them: beams they
/// need, points on nodes, time steps (as given, resolving the drive, stable for the
/// scheme), periodic drives where the analysis needs one, damping the analysis can apply.
/// Each analysis's memory and steps are estimated and held to `budget` first.
/// `beamflow check` runs it, and [`run_case`] before its first analysis, so both refuse the
/// same cases with the same messages. Returns the case's measurements (`[[measurement]]`),
/// read and checked against the model.
pub fn preflight(lc: &LoadedCase, model: &Model, system: &System, budget: &Budget) -> Result<Vec<Measured>> {
    for (i, spec) in lc.case.analysis.iter().enumerate() {
        let field = format!("analysis[{i}]");
        let need_beam =
            || {
                model.structure.as_ref().map(|_| ()).ok_or_else(|| {
                    Error::input(&lc.file, &field, "this analysis needs a structure, but base = \"rigid\"")
                })
            };
        let check = || -> Result<()> {
            match spec {
                AnalysisSpec::Modes { count } => {
                    need_beam()?;
                    budget.admit(&cost::modes(model, *count))
                }
                AnalysisSpec::Harmonic { force, system: kind, frequencies } => {
                    need_beam()?;
                    if *kind == HarmonicSystem::Coupled && model.modal_ratios().is_some() {
                        return Err(Error::analysis_setting(
                            "system",
                            "the coupled system has no damping matrix with modal damping (its ratios belong to the \
                             bare beam's modes): give the beam Rayleigh or hysteretic damping, or analyse the bare \
                             beam",
                        ));
                    }
                    let f = cost::frequency_count(frequencies).unwrap_or(u64::MAX);
                    let forces = if force.is_empty() { model.loads.len() } else { force.len() };
                    let modal = model.modal_ratios().is_some();
                    budget.admit(&cost::harmonic(system, f, forces, model.sensors.len(), modal))?;
                    let structure = model.structure.as_ref().expect("checked");
                    for (j, f) in force.iter().enumerate() {
                        let at = f.location();
                        let refuse =
                            |why| Err(Error::input(&lc.file, format!("{field}.force[{j}].{}", at.field()), why));
                        match structure.attach(&at) {
                            Err(why) => return refuse(why),
                            Ok(a) if crate::structure::single_node(&a).is_none() => {
                                return refuse(format!("{at} is not on a mesh node"))
                            }
                            Ok(_) => {}
                        }
                    }
                    Ok(())
                }
                AnalysisSpec::Transient { reduction, .. } => {
                    if model.loss_factor() > 0.0 {
                        return Err(Error::case_field("damping.kind", transient::HYSTERETIC_IN_TIME));
                    }
                    let s = transient_settings(spec, None).expect("transient");
                    let timing =
                        DriveTiming::stepped(model, Step::of(s.dt, s.steps_per_period), s.duration, s.harmonics)?;
                    let stepping = cost::transient(model, system, &s, &timing);
                    budget.admit(&stepping)?;
                    let steps = stepping.steps.unwrap_or(u64::MAX);
                    if let Some(search) = cost::drive_search(model, steps as f64 * timing.dt, steps) {
                        budget.admit(&search)?;
                    }
                    transient::record_plan(model, &timing, s.segment)?;
                    match reduction {
                        // Modal damping is a matrix only in modal coordinates.
                        None => {
                            plan::require_viscous_damping(model, "transient analysis without `reduction`")?;
                            transient::check_time_step(system, s.scheme, &timing)
                        }
                        Some(r) if r.modes_up_to_hz.is_none() && !timing.periodic => {
                            reduction::highest_harmonic_hz(model, 1).map(|_| ())
                        }
                        Some(_) => Ok(()),
                    }
                }
                AnalysisSpec::SteadyState { samples_per_period, reduction, .. } => {
                    budget.admit(&cost::steady_state(model, system, *samples_per_period))?;
                    let timing = DriveTiming::sampled(model, *samples_per_period)?;
                    if let Some(search) = cost::cycle_search(model, &timing) {
                        budget.admit(&search)?;
                    }
                    if model.loss_factor() > 0.0 && reduction.is_some() {
                        return Err(Error::analysis_setting(
                            "reduction",
                            "a modal reduction is not available with hysteretic damping: run the full model",
                        ));
                    }
                    let beam_dofs = system.dofs.structure_dofs().len();
                    if model.modal_ratios().is_some()
                        && reduction.is_none()
                        && beam_dofs > reduction::COMPLETE_BASIS_LIMIT
                    {
                        return Err(Error::analysis_setting(
                            "reduction",
                            format!(
                                "modal damping without a reduction needs all {beam_dofs} modes of the beam (dense, \
                                 above the {} this computes); give `reduction = \"auto\"` or a cut-off",
                                reduction::COMPLETE_BASIS_LIMIT
                            ),
                        ));
                    }
                    Ok(())
                }
            }
        };
        check().map_err(|e| e.in_analysis(&lc.file, &field))?;
    }
    let measured = crate::case::measured::load_measurements(lc)?;
    let periodic = lc
        .case
        .analysis
        .iter()
        .filter(|a| matches!(a, AnalysisSpec::Transient { .. } | AnalysisSpec::SteadyState { .. }))
        .count();
    crate::analysis::measured::check(&measured, model, system, periodic).map_err(|e| e.in_file(&lc.file))?;
    Ok(measured)
}

/// The model, system and measurements of a case whose every analysis passed [`preflight`]
/// within `budget`: what `beamflow check` and [`run_case_within`] do before any analysis
/// runs.
pub fn planned(lc: &LoadedCase, budget: &Budget) -> Result<(Model, System, Vec<Measured>)> {
    let (model, system) = plan::model_and_system_within(lc, budget)?;
    let measured = preflight(lc, &model, &system, budget)?;
    Ok((model, system, measured))
}

/// [`run_case_within`] the machine's default [`Budget`].
pub fn run_case(lc: &LoadedCase) -> Result<CaseRun> {
    run_case_within(lc, &Budget::default())
}

/// The DOF numbering of a structure without actuators (bare modes and harmonic analyses).
fn structure_only(structure: &Structure) -> DofMap {
    DofMap::number(Some(structure), &[], &[])
}

/// Builds the model and runs the case's analyses in order, after [`planned`] held them to
/// `budget`.
pub fn run_case_within(lc: &LoadedCase, budget: &Budget) -> Result<CaseRun> {
    let (model, system, measured) = planned(lc, budget)?;
    let results = run_analyses(lc, &model, &system, None)?;
    let mesh = mesh_checks(lc, &model, &results, budget);
    let link_name =
        |l: &crate::analysis::series::LinkSeries| crate::actuator::link_id(model.actuators[l.actuator].name(), &l.name);
    let measured =
        crate::analysis::measured::compare_all(&results, &measured, &link_name).map_err(|e| e.in_file(&lc.file))?;
    Ok(CaseRun { model, system, results, measured, mesh })
}

/// Runs the case's analyses in order on its planned model and system: every one, a
/// round-off bound above the tolerance said (or refused, if the case is strict); or for a
/// plate's coarser grid `only` those by index, round-off left to the case's own run.
fn run_analyses(
    lc: &LoadedCase,
    model: &Model,
    system: &System,
    only: Option<&[usize]>,
) -> Result<Vec<AnalysisResult>> {
    let mut run = Runner { model, system, reduced: ReducedCache::default(), complete: OnceCell::new() };
    let mut results = Vec::new();
    let structure = model.structure.as_ref();
    let wanted = |i: usize| only.is_none_or(|o| o.contains(&i));
    for (i, spec) in lc.case.analysis.iter().enumerate().filter(|(i, _)| wanted(*i)) {
        let field = format!("analysis[{i}]");
        let need_beam = || {
            structure
                .ok_or_else(|| Error::input(&lc.file, &field, "this analysis needs a structure, but base = \"rigid\""))
        };
        // Which DOF numbering a failed factorisation's row refers to.
        let (r, numbering) = match spec {
            AnalysisSpec::Modes { count } => {
                let s = need_beam()?;
                let r = modes::run(s, *count).map_err(|e| structure_only(s).locate(e, structure)).and_then(|mut r| {
                    r.coupled = modes::coupled_modes(model, system, *count)?;
                    Ok(AnalysisResult::Modes(r))
                });
                (r, Some(&system.dofs))
            }
            AnalysisSpec::Harmonic { frequencies, force, system: HarmonicSystem::Coupled } => {
                need_beam()?;
                let forces = harmonic_forces(force, model);
                let r = harmonic::run(model, system, &frequencies.list(), &forces, None);
                (r.map(AnalysisResult::Harmonic), Some(&system.dofs))
            }
            AnalysisSpec::Harmonic { frequencies, force, system: HarmonicSystem::Bare } => {
                let s = need_beam()?;
                let r = run.harmonic(s, &frequencies.list(), force);
                (r.map(AnalysisResult::Harmonic).map_err(|e| structure_only(s).locate(e, structure)), None)
            }
            AnalysisSpec::Transient { reduction, .. } => {
                let s = transient_settings(spec, lc.case.output.history()).expect("transient");
                let r = run.transient(&s, reduction.as_ref());
                (r.map(|r| AnalysisResult::Transient(Box::new(r))), reduction.is_none().then_some(&system.dofs))
            }
            AnalysisSpec::SteadyState { harmonics, harmonic_tolerance, samples_per_period, reduction } => {
                let count = match harmonics {
                    Some(h) => HarmonicCount::Fixed(*h),
                    None => HarmonicCount::Tolerance(*harmonic_tolerance),
                };
                let r = run.steady_state(count, *samples_per_period, reduction.as_ref());
                (r.map(|r| AnalysisResult::SteadyState(Box::new(r))), reduction.is_none().then_some(&system.dofs))
            }
        };
        let located = |e: Error| match numbering {
            Some(d) => d.locate(e, structure),
            None => e,
        };
        let r = r.map_err(|e| located(e).in_analysis(&lc.file, &field))?;
        refuse_unsound(&lc.file, i, spec, &r, if only.is_none() { "; nothing was written" } else { "" })?;
        if only.is_none() {
            hold_roundoff(lc, model, &field, &r)?;
        }
        results.push(r);
    }
    Ok(results)
}

/// The point powers of a result whose grid error a coarser plate grid estimates: a steady
/// state, or a transient of a periodic drive (a non-periodic record: Err, why not).
fn periodic_powers(r: &AnalysisResult) -> Option<std::result::Result<PointPowers, &'static str>> {
    let loads = |l: &[crate::analysis::series::LoadSpectrum]| l.iter().map(|s| s.power_total).collect();
    match r {
        AnalysisResult::SteadyState(s) => Some(Ok(PointPowers {
            links: s.mean_power.clone(),
            net: s.net_power.clone(),
            loads: loads(&s.load_spectra),
        })),
        AnalysisResult::Transient(t) if t.record.is_none() => Some(Ok(PointPowers {
            links: t.mean_power.clone(),
            net: t.net_power.clone(),
            loads: loads(&t.load_spectra),
        })),
        AnalysisResult::Transient(_) => {
            Some(Err("a non-periodic record's energies and spectra are not compared between grids: compare two \
                      grids' runs yourself"))
        }
        _ => None,
    }
}

/// The elements of a plate model's grid along x and y, as built.
fn built_grid(model: &Model) -> Option<[usize; 2]> {
    match model.structure.as_ref()? {
        Structure::Plate(p) => Some([p.grid.nx(), p.grid.ny()]),
        _ => None,
    }
}

/// Each result's mesh estimate (None where it has no point powers on a plate): the same
/// analyses run again on a generated plate grid of half the elements each way
/// ([`crate::analysis::mesh_estimate`]). A coarser grid that cannot run them, or is no
/// coarser, leaves the results as they are, with the reason.
fn mesh_checks(lc: &LoadedCase, model: &Model, results: &[AnalysisResult], budget: &Budget) -> Vec<Option<MeshCheck>> {
    let mut checks = vec![None; results.len()];
    let (Some(plate), Some(fine_grid)) = (lc.case.plate.as_ref(), built_grid(model)) else { return checks };
    if plate.mesh.error_estimate == Some(false) {
        return checks;
    }
    let mut wanted = Vec::new();
    for (i, r) in results.iter().enumerate() {
        match periodic_powers(r) {
            Some(Ok(p)) if !(p.links.is_empty() && p.loads.is_empty()) => wanted.push((i, p)),
            Some(Err(why)) => checks[i] = Some(MeshCheck::NotEstimated(why.into())),
            _ => {}
        }
    }
    if wanted.is_empty() {
        return checks;
    }
    let coarse = if plate.mesh.file.is_some() {
        Err("a mesh file's grid is as written, with no coarser grid to compare it with".to_string())
    } else {
        coarse_run(lc, fine_grid, &wanted.iter().map(|w| w.0).collect::<Vec<_>>(), budget)
    };
    for (k, (i, fine)) in wanted.iter().enumerate() {
        checks[*i] = Some(match &coarse {
            Ok((grid, c)) => match periodic_powers(&c[k]) {
                Some(Ok(cp)) => MeshCheck::Estimate(MeshEstimate::between((fine_grid, *grid), fine, &cp)),
                _ => MeshCheck::NotEstimated("the coarser grid's run has no point powers".into()),
            },
            Err(why) => MeshCheck::NotEstimated(why.clone()),
        });
    }
    checks
}

/// The analyses `wanted` (by index) of the case on a generated plate grid of half the
/// elements each way, and that grid as built; or why there is none: a grid that halving
/// leaves as it was along a side, or a coarser grid that refused or failed (its reason,
/// which names the case's own field and analysis).
fn coarse_run(
    lc: &LoadedCase,
    fine_grid: [usize; 2],
    wanted: &[usize],
    budget: &Budget,
) -> std::result::Result<([usize; 2], Vec<AnalysisResult>), String> {
    let c = coarse_case(lc);
    let asked = c.case.plate.as_ref().map_or([0, 0], |p| p.mesh.elements());
    let failed =
        |e: Error| format!("the coarser grid ({} × {} elements asked) could not run it: {e}", asked[0], asked[1]);
    let (model, system) = match planned(&c, budget) {
        Ok((model, system, _)) => (model, system),
        Err(e) => return Err(failed(e)),
    };
    let grid = built_grid(&model).unwrap_or(fine_grid);
    if let Some(why) = mesh_estimate::not_coarser(fine_grid, grid) {
        return Err(why);
    }
    run_analyses(&c, &model, &system, Some(wanted)).map(|r| (grid, r)).map_err(failed)
}

/// The case on a generated plate grid of half the elements each way, every analysis kept
/// (their force points keep their grid lines, their indices the case's), no measurements,
/// no history, and no estimates of its own.
fn coarse_case(lc: &LoadedCase) -> LoadedCase {
    let mut c = lc.clone();
    let plate = c.case.plate.as_mut().expect("a plate case");
    plate.mesh.elements = Some(mesh_estimate::coarser(plate.mesh.elements()));
    plate.mesh.error_estimate = Some(false);
    c.case.measurement.clear();
    c.case.output.full_history = false;
    c.case.output.history_every = 1;
    for a in &mut c.case.analysis {
        if let AnalysisSpec::SteadyState { reduction: Some(r), .. }
        | AnalysisSpec::Transient { reduction: Some(r), .. } = a
        {
            r.error_estimate = false;
        }
    }
    c
}

/// Refuses a result that holds a non-finite number or misses its energy balance by more
/// than [`BALANCE_TOLERANCE`]: such numbers describe no motion of the model, so they are
/// never reported as a success. The message names the setting that closes the gap, and
/// `outcome` what became of the run (the case's own: nothing was written).
fn refuse_unsound(file: &str, i: usize, spec: &AnalysisSpec, r: &AnalysisResult, outcome: &str) -> Result<()> {
    if let Some(q) = r.non_finite() {
        return Err(Error::input(
            file,
            format!("analysis[{i}]"),
            format!(
                "the result is not a finite number ({q}): the inputs are out of the range double precision \
                 can carry (amplitudes, material constants or frequencies many orders of magnitude from \
                 physical values) or the solution diverged{outcome}"
            ),
        ));
    }
    let Some((what, e)) = r.balance().filter(|(_, e)| !(*e <= BALANCE_TOLERANCE)) else { return Ok(()) };
    let (field, advice) = match spec {
        AnalysisSpec::Transient { .. } => (
            format!("analysis[{i}].dt"),
            "a finer `dt` (a numerically dissipative `scheme` — hht, generalized_alpha — loses energy the \
             model does not, the more the coarser the step) or inputs nearer physical values",
        ),
        AnalysisSpec::SteadyState { .. } => (
            format!("analysis[{i}]"),
            "more `harmonics` (a smaller `harmonic_tolerance`) or inputs nearer physical values",
        ),
        _ => (format!("analysis[{i}]"), "inputs nearer physical values"),
    };
    Err(Error::input(
        file,
        field,
        format!(
            "the energy balance ({what}) is off by {e:.3e} of its terms, above the tolerance \
             {BALANCE_TOLERANCE:e}: the result is not a solution of the model; {advice} are needed{outcome}"
        ),
    ))
}

/// Says on standard error where a result's round-off bound exceeds the case's tolerance,
/// or refuses it if the case is strict (`beam.mesh.strict_roundoff`).
fn hold_roundoff(lc: &LoadedCase, model: &Model, field: &str, r: &AnalysisResult) -> Result<()> {
    let Some(bound) = r.mesh_roundoff() else { return Ok(()) };
    let strict = lc.case.beam.mesh.strict_roundoff;
    match crate::analysis::roundoff::check(model, strict, field, bound).map_err(|e| e.in_file(&lc.file))? {
        Some(text) => crate::app::console::note_line(format_args!("warning: {}: {text}", lc.file)),
        None => {}
    }
    Ok(())
}

/// A case's analyses against one model and its assembled system, sharing what they build.
struct Runner<'a> {
    model: &'a Model,
    system: &'a System,
    reduced: ReducedCache,
    /// The model in the bare beam's complete modal basis, where modal damping is a matrix:
    /// built at most once per case run (an eigen-analysis and a dense basis).
    complete: OnceCell<System>,
}

impl Runner<'_> {
    /// The full-order system the frequency-domain analyses solve: the assembled one, or
    /// with modal damping its complete modal basis.
    fn reference(&self) -> Result<&System> {
        match self.model.modal_ratios() {
            None => Ok(self.system),
            Some(r) => {
                if self.complete.get().is_none() {
                    let _ = self.complete.set(reduction::complete_modal_basis(self.system, r)?);
                }
                Ok(self.complete.get().expect("set above"))
            }
        }
    }

    /// The bare beam (with the case's sensors and damping) under the harmonic analysis's
    /// forces, or the case's sine loads.
    fn harmonic(
        &self,
        structure: &Structure,
        hz: &[f64],
        force: &[crate::case::ForceSpec],
    ) -> Result<harmonic::HarmonicResult> {
        let model = self.model;
        let bare = Model {
            structure: Some(structure.clone()),
            damping: model.damping.clone(),
            actuators: Vec::new(),
            sensors: model.sensors.clone(),
            loads: Vec::new(),
            roundoff_tolerance: model.roundoff_tolerance,
        };
        let sys = System::assemble(&bare)?;
        let forces = harmonic_forces(force, &model);
        let modal = match model.modal_ratios() {
            Some(r) => Some((modes::bare_modes(structure, usize::MAX)?, r)),
            None => None,
        };
        let modal = modal.as_ref().map(|(m, r)| (m, *r));
        harmonic::run(&bare, &sys, hz, &forces, modal)
    }

    fn transient(
        &mut self,
        s: &TransientSettings,
        reduction: Option<&ReductionSpec>,
    ) -> Result<transient::TransientResult> {
        let model = self.model;
        let Some(rs) = reduction else { return transient::run(model, self.system, s) };
        let rs = ReductionSettings::of_spec(rs, model.modal_ratios());
        let timing = DriveTiming::stepped(model, Step::of(s.dt, s.steps_per_period), s.duration, s.harmonics)?;
        let h = timing.analysed_harmonics(s.harmonics);
        let (red, mut report) = self.reduced.get(model, self.system, &rs, h)?;
        let mut r = transient::run(model, &red, s)?;
        if rs.error_estimate {
            let samples = ESTIMATE_SAMPLES.max(samples_for_harmonics(h).unwrap_or(usize::MAX));
            report.error = Some(steady_state::estimate_reduction_error(model, self.reference()?, &red, h, samples)?);
        }
        r.reduction = Some(report);
        Ok(r)
    }

    fn steady_state(
        &mut self,
        count: HarmonicCount,
        samples: usize,
        reduction: Option<&ReductionSpec>,
    ) -> Result<steady_state::SteadyStateResult> {
        let model = self.model;
        let Some(rs) = reduction else {
            let (fd, system) = (self.reference()?, self.system);
            // The mode-resolved view has viscous modal dampers only.
            let bare = || {
                if model.loss_factor() > 0.0 {
                    Ok(None)
                } else {
                    modes::bare_modes_on(model, system, MODAL_TABLE_MODES)
                }
            };
            let counted = || steady_state::run_counted(model, fd, count, samples);
            // A fine mesh's modes take a good part of its steady state's time: beside it.
            let (s, bare) = match roundoff::coarse_bound(model) {
                Some(_) => (counted(), bare()),
                None => crate::progress::side_by_side(counted, bare),
            };
            let mut s = s?;
            s.expand(fd);
            s.decompose_with(system, bare?.as_ref(), ModalDamping::of_model(model, system));
            return Ok(s);
        };
        // A reduced model's cut-off follows the harmonic count, so it needs one first: the
        // default count. Where the harmonics it leaves out carry more than the tolerance,
        // the count the reduced model's own spectrum asks for, on the same reduction: a
        // cut-off raised with the count would keep most of a plate's modes (a dense
        // reduced system far slower than the full model), and the error estimate below
        // states what the reduction costs the added harmonics.
        let h = match count {
            HarmonicCount::Fixed(h) => h,
            HarmonicCount::Tolerance(_) => crate::case::DEFAULT_HARMONICS,
        };
        let rs = ReductionSettings::of_spec(rs, model.modal_ratios());
        let (red, mut report) = self.reduced.get(model, self.system, &rs, h)?;
        let mut r = steady_state::run_counted(model, &red, HarmonicCount::Fixed(h), samples)?;
        // Where the samples cannot resolve the count the tolerance asks for, the default
        // count's result stands, its truncation estimate stated and warned of.
        if matches!(count, HarmonicCount::Tolerance(tol) if r.truncation_estimate > tol) {
            if let Ok(more) = steady_state::run_counted(model, &red, count, samples) {
                r = more;
            }
        }
        if rs.error_estimate {
            let full = steady_state::run(model, self.reference()?, r.harmonics, samples)?;
            report.error = Some(steady_state::reduction_error(&full, &r));
        }
        r.reduction = Some(report);
        Ok(r)
    }
}

/// Samples per period of the frequency-domain runs behind a reduction's error estimate.
const ESTIMATE_SAMPLES: usize = 1024;

/// Reduced systems built so far in a case run, so that analyses asking for the same basis
/// share it.
#[derive(Default)]
struct ReducedCache {
    built: Vec<((u64, bool), System, ReductionReport)>,
}

impl ReducedCache {
    fn get(
        &mut self,
        model: &Model,
        full: &System,
        rs: &ReductionSettings,
        harmonics: usize,
    ) -> Result<(System, ReductionReport)> {
        let hz = reduction::cutoff_hz(model, rs, harmonics)?;
        let key = (hz.to_bits(), rs.static_correction);
        if let Some((_, s, r)) = self.built.iter().find(|(k, _, _)| *k == key) {
            return Ok((s.clone(), r.clone()));
        }
        let (s, r) = reduction::reduce(model, full, rs, hz)?;
        self.built.push((key, s.clone(), r.clone()));
        Ok((s, r))
    }
}
