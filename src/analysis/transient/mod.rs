//! Time integration of the coupled system driven by the stacks' voltages.
//!
//! The run advances whole drive periods. Because F_p depends on the voltage alone, each
//! period's stack forces are computed up front (h exact in voltage space), then the
//! Newmark loop steps through the period ([`step`]), and the read-outs the integrator
//! evaluates after every step ([`readout`]) are sorted into the period's record
//! ([`record`]). At each period end the steady-state check ([`settle`]) compares the period
//! with the exact periodic state; the run stops when every point is within the tolerance
//! of its own power there.

mod readout;
mod record;
mod records;
mod reference;
mod settle;
pub use settle::DECAY_PERIODS;
mod stability;
mod step;

use self::readout::Readout;
use self::record::{PeriodRecord, Window};
use self::settle::SettleCheck;
use self::step::{EnergyLedger, StackHistories, Stepper};
use super::drive::{DriveTiming, Step};
use super::series::{
    Balances, BodySeries, DriveSeries, LinkSeries, LinkSpectrum, LoadSeries, LoadSpectrum, SensorSeries,
};
use crate::analysis::roundoff;
use crate::assembly::rows::StiffnessRows;
use crate::assembly::{Model, System};
use crate::error::Result;
use crate::power::energy::StrainEnergy;
use crate::power::point::{mean_product, net_power};
use crate::power::record::{RecordAnalysis, RecordPlan, Welch};
use crate::power::spectra::harmonics;
use crate::progress::Task;
use crate::solve::band_newmark::{BandNewmark, StepOptions};
use crate::solve::newmark::{consistent_acceleration, Scheme};
use serde::Serialize;
use std::sync::Arc;

/// How to run.
#[derive(Clone, Debug)]
pub struct TransientSettings {
    pub dt: Option<f64>,
    /// Steps per drive period instead of `dt`.
    pub steps_per_period: Option<usize>,
    pub periods: Option<usize>,
    pub duration: Option<f64>,
    pub scheme: Scheme,
    pub steady_state: bool,
    pub tolerance: f64,
    pub max_periods: usize,
    /// Highest harmonic of the drive analysed (sets the Δt limit and the spectra length);
    /// None: as many as the time step resolves ([`DriveTiming::analysed_harmonics`]).
    pub harmonics: Option<usize>,
    /// A non-periodic record's Welch segment (s); None: the estimator the record supports
    /// ([`crate::power::record::choose`]).
    pub segment: Option<f64>,
    /// Periods kept at the end of the run for output (and run at least before the
    /// steady-state criterion may stop it).
    pub record_periods: usize,
    /// Keep every period of the run for output instead (`[output] full_history`).
    pub full_history: bool,
    /// With `full_history`, the periods before the last `record_periods` keep every this
    /// many-th step only (`[output] history_every`; 1 keeps every step).
    pub history_every: usize,
}

impl Default for TransientSettings {
    fn default() -> Self {
        TransientSettings {
            dt: None,
            steps_per_period: None,
            periods: None,
            duration: None,
            scheme: Scheme::average_acceleration(),
            steady_state: true,
            tolerance: 1e-4,
            max_periods: 400,
            harmonics: None,
            segment: None,
            record_periods: 3,
            full_history: false,
            history_every: 1,
        }
    }
}

/// Result of a transient run.
#[derive(Clone, Debug, Default, Serialize)]
pub struct TransientResult {
    /// Time step used (s) and drive period (s).
    pub dt: f64,
    pub period: f64,
    pub steps_per_period: usize,
    pub periods_run: usize,
    pub steps_run: usize,
    /// Harmonics of 1/period in the spectra: as asked, or as many as Δt resolves.
    pub harmonics: usize,
    /// Whether the steady-state criterion was met, and the last relative change between
    /// neighbouring periods.
    pub converged: bool,
    pub final_change: f64,
    /// The start-up transient left in the last period: an upper bound of every point's
    /// mean-power and RMS-force error, each relative to its own, against the exact periodic
    /// state of the same discrete system (the measured distance plus a margin for round-off;
    /// see [`settle`]; NaN for a non-periodic drive).
    pub settling_estimate: f64,
    /// A run that did not settle: about how many periods in all it would need, from the
    /// decay of its start-up transient over its last periods (None where that does not
    /// decay, or fewer than 20 periods ran).
    pub periods_needed: Option<usize>,
    /// Whether the case fixed the periods (`periods`) rather than a most (`max_periods`).
    pub periods_given: bool,
    /// The relative round-off of the point powers that `settling_estimate` does not
    /// measure: on a fine mesh whose steps use the element rows, the bound of the refined
    /// periodic state it is measured against; else the measured envelope of the step's
    /// round-off ([`crate::analysis::roundoff`]).
    pub mesh_roundoff: f64,
    /// Times of the recorded window (s).
    pub t: Vec<f64>,
    pub links: Vec<LinkSeries>,
    pub bodies: Vec<BodySeries>,
    pub drives: Vec<DriveSeries>,
    pub sensors: Vec<SensorSeries>,
    pub loads: Vec<LoadSeries>,
    /// Per point load, its mean power into the beam over the last period and its harmonics.
    pub load_spectra: Vec<LoadSpectrum>,
    /// Mean power into the base at each link's foot over the last period (W).
    pub mean_power: Vec<f64>,
    /// Net mean power into the base per actuator (W).
    pub net_power: Vec<f64>,
    pub spectra: Vec<LinkSpectrum>,
    /// Over the whole run, and over the last period.
    pub energy_run: Balances,
    pub energy_last_period: Balances,
    /// Mean power dissipated in the beam over the last period (W).
    pub beam_dissipation: f64,
    /// Mean power into the beam over the last period by the same (midpoint) quadrature as
    /// the dissipation, so the two balance to round-off in steady state (W). The per-point
    /// `mean_power` are sample means, consistent with the spectra; both converge at O(Δt²).
    pub beam_input_power: f64,
    /// Set when the run used a modal reduction: its basis and error estimate.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reduction: Option<crate::analysis::reduction::ReductionReport>,
    /// A non-periodic drive's record: energies, PSDs and FRFs instead of harmonics (whose
    /// fields then stay empty).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub record: Option<RecordAnalysis>,
}

/// How many periods a run takes and keeps.
struct PeriodPlan {
    /// Periods to run at most.
    total: usize,
    /// Periods to run at least before the steady-state check may stop the run.
    min: usize,
    /// Periods kept for output.
    keep: usize,
}

impl PeriodPlan {
    fn new(timing: &DriveTiming, s: &TransientSettings) -> Self {
        let total = match (timing.periodic, s.periods) {
            (false, _) => 1,
            (true, Some(p)) => p,
            (true, None) if s.steady_state => s.max_periods,
            (true, None) => 1,
        };
        let min = if timing.periodic { s.record_periods.max(1) } else { 1 };
        PeriodPlan { total, min, keep: if s.full_history { total.max(1) } else { min } }
    }
}

/// The integrator of a run, built and set up in one place, and the element rows' strain
/// energy where the step uses them.
fn integrator(
    model: &Model,
    sys: &System,
    scheme: Scheme,
    dt: f64,
) -> Result<(BandNewmark, Option<Arc<dyn StrainEnergy>>)> {
    // The structure's Rayleigh damping lets the band step drop its C product (a reduced,
    // dense system declines: its C is no longer banded).
    let options = StepOptions {
        rayleigh: Some((model.rayleigh().a0, model.rayleigh().a1)),
        track_dissipation: true,
        ..StepOptions::default()
    };
    let mut nm = BandNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, scheme, dt, options)?;
    // A mesh too fine for the envelope's bound steps with the element rows' stiffness and
    // refines its increments (`band_newmark::accurate`); its energies come from the rows.
    if roundoff::coarse_bound(model).is_none() {
        if let Some(rows) = StiffnessRows::of(model, sys)? {
            let rows = Arc::new(roundoff::RowStiffness(rows));
            if nm.use_stiffness_product(rows.clone()) {
                return Ok((nm, Some(rows)));
            }
        }
    }
    Ok((nm, None))
}

/// Starts the integrator at rest under the forces `w0` at t = 0 (N: each stack's F_p,
/// then each point load), with the consistent initial acceleration, and registers their
/// load patterns.
fn start_at_rest(nm: &mut BandNewmark, sys: &System, w0: &[f64]) -> Result<()> {
    let patterns: Vec<Vec<(usize, f64)>> = sys.drives.iter().chain(&sys.loads).cloned().collect();
    // F₀ = Σ_j b_j·w_j(0) as sparse pairs.
    let loads: Vec<(usize, f64)> =
        patterns.iter().zip(w0).flat_map(|(b, &w)| b.iter().map(move |&(d, c)| (d, c * w))).collect();
    let zeros = vec![0.0; sys.n()];
    let a0 = consistent_acceleration(&sys.m, &sys.c, &sys.k, &sys.envelope, &zeros, &zeros, &loads)?;
    nm.set_state(&zeros, &zeros, &a0, &loads);
    nm.set_load_patterns(patterns);
    nm.set_previous_weights(w0);
    Ok(())
}

/// Why a transient refuses hysteretic damping.
pub const HYSTERETIC_IN_TIME: &str = "hysteretic damping (stiffness K·(1 + iη) at every frequency) has no causal \
     time-domain form: its response would begin before its cause, so no time integration can use it. Use it in \
     harmonic and steady-state analyses, or give the transient viscous damping (kind = \"rayleigh_ratio\" with \
     zeta ≈ η/2 matches it at the calibration modes)";

/// Refuses a time step the scheme cannot run stably on `sys` (see [`stability`]).
pub fn check_time_step(sys: &System, scheme: Scheme, timing: &DriveTiming) -> Result<()> {
    stability::check_step(sys, scheme, timing)
}

/// Runs the transient.
pub fn run(model: &Model, sys: &System, s: &TransientSettings) -> Result<TransientResult> {
    if sys.k_loss.is_some() {
        return Err(crate::error::Error::case_field("damping.kind", HYSTERETIC_IN_TIME));
    }
    let timing = DriveTiming::stepped(model, Step::of(s.dt, s.steps_per_period), s.duration, s.harmonics)?;
    stability::check_step(sys, s.scheme, &timing)?;
    integrate(model, sys, s, timing)
}

/// Refuses a run that diverges, after `period` periods of `steps` steps: a displacement or
/// velocity that is no longer a finite number, or more energy stored than the start held
/// and the drives ever put in (see [`EnergyLedger::runaway`]). Names the DOF that moves
/// most (by its share of the kinetic energy).
fn check_bounded(nm: &BandNewmark, sys: &System, ledger: &EnergyLedger, period: usize, steps: usize) -> Result<()> {
    let n = sys.n();
    let at =
        |what: &str| format!("the time integration diverged in period {period} (by step {})", period * steps) + what;
    let advice = "a smaller `dt`, an unconditionally stable scheme (average_acceleration) or inputs nearer \
                  physical values are needed";
    if let Some(d) = nm.u().iter().chain(nm.v()).position(|x| !x.is_finite()) {
        let q = if d < n { "displacement" } else { "velocity" };
        let what = format!(": the {q} of {} is no longer a finite number; {advice}", sys.dofs.describe(d % n));
        return Err(crate::error::Error::analysis_setting("dt", at(&what)));
    }
    if let Some((stored, supplied)) = ledger.runaway() {
        let kinetic = |d: usize| sys.m.get(d, d) * nm.v()[d].powi(2);
        let d = (0..n).max_by(|&a, &b| kinetic(a).total_cmp(&kinetic(b))).unwrap_or(0);
        let what = format!(
            ": the structure stores {stored:.3e} J, {:.1e} times the {supplied:.3e} J the start held and the \
             drives put in (it cannot store more), moving most at {}; {advice}",
            stored / supplied,
            sys.dofs.describe(d)
        );
        return Err(crate::error::Error::analysis_setting("dt", at(&what)));
    }
    Ok(())
}

/// The time stepping of [`run`] on `timing`, whose step [`run`] checked.
fn integrate(model: &Model, sys: &System, s: &TransientSettings, timing: DriveTiming) -> Result<TransientResult> {
    let record_plan = record_plan(model, &timing, s.segment)?;
    let layout = Readout::new(model, sys)?;
    let (mut nm, strain) = integrator(model, sys, s.scheme, timing.dt)?;
    let accurate = strain.is_some();
    let mut stacks = StackHistories::new(model, &timing);
    let f_p0 = stacks.initial_forces();
    start_at_rest(&mut nm, sys, &stacks.initial_weights())?;
    let plan = PeriodPlan::new(&timing, s);
    let thin = s.history_every.max(1);
    let mut window = Window::new(plan.keep, timing.steps_per_period, (plan.min, thin));
    let mut ledger = EnergyLedger::new(sys, &nm, strain);
    nm.set_observations(layout.rows());
    let mut stepper = Stepper::new(&nm, sys, &layout, &f_p0, &timing);
    let reference = if timing.periodic && s.steady_state {
        Some(reference::periodic_metrics(model, sys, &s.scheme, &timing, accurate)?)
    } else {
        None
    };
    // The period means of N products carry up to N·ε each (a sum's worst case): the run's
    // and the reference's.
    let summed = timing.steps_per_period as f64 * f64::EPSILON;
    let (roundoff, margin) = match &reference {
        // A refined reference's bound is all the measured distance cannot see: the run's own
        // round-off is part of that distance.
        Some(r) if accurate => (r.bound, r.bound + 2.0 * summed),
        // Otherwise the reference and the run each carry the mesh's measured envelope.
        _ => {
            let envelope = if accurate { roundoff::refined_step_envelope(model) } else { roundoff::envelope(model) };
            (envelope, 2.0 * (envelope + summed))
        }
    };
    let mut settle = SettleCheck::new(s.tolerance, reference.map(|r| r.metrics), margin);
    let (mut converged, mut periods_run, mut settled_run) = (false, 0, 0);
    // A periodic run counts periods; a record, its steps.
    let task = if timing.periodic {
        Task::start("transient", Some(plan.total as u64), "periods")
    } else {
        Task::start("transient record", Some(timing.steps_per_period as u64), "steps")
    };
    for p in 0..plan.total {
        stacks.advance(p, &timing);
        let mut rec = window.next_record(&layout);
        ledger.open_period(&nm);
        let pb = stepper.period(&mut nm, sys, &layout, &stacks, (!timing.periodic).then_some(&task))?;
        ledger.close_period(&nm, pb);
        check_bounded(&nm, sys, &ledger, p + 1, timing.steps_per_period)?;
        let n = timing.steps_per_period;
        rec.store_drives(&stacks.times[..n], &stacks.v, &stacks.h, &stepper.f_p, &stacks.load_f);
        rec.store_readouts(&layout, &stepper.observed);
        periods_run = p + 1;
        // Every period kept for output must be settled, not only the last.
        settled_run = if settle.settled_after(&sys.links, &rec) { settled_run + 1 } else { 0 };
        if timing.periodic {
            task.set_with(periods_run as u64, || settling_message(&settle, s.tolerance))?;
        }
        window.push(rec);
        if timing.periodic && s.steady_state && settled_run >= plan.min {
            converged = true;
            if s.periods.is_none() {
                break;
            }
        }
    }
    let mut result = TransientResult {
        dt: timing.dt,
        period: timing.period,
        steps_per_period: timing.steps_per_period,
        periods_run,
        steps_run: periods_run * timing.steps_per_period,
        converged,
        final_change: settle.change(),
        settling_estimate: settle.remaining(),
        periods_needed: if converged { None } else { settle.periods_needed() },
        periods_given: s.periods.is_some(),
        mesh_roundoff: roundoff,
        energy_run: ledger.run,
        energy_last_period: ledger.last_period,
        beam_dissipation: ledger.last_period.beam.dissipated / timing.period,
        beam_input_power: ledger.last_period.beam.input / timing.period,
        ..Default::default()
    };
    let all = window.joined(&layout);
    match record_plan {
        None => {
            let harmonics = timing.analysed_harmonics(s.harmonics);
            result.harmonics = harmonics;
            add_links(&mut result, sys, &all, harmonics);
            add_loads(&mut result, model, &all, harmonics);
            result.net_power = net_power(&sys.links, &result.mean_power, model.actuators.len());
        }
        Some(plan) => {
            result.links = sys.links.iter().enumerate().map(|(l, lk)| all.link_series(l, lk)).collect();
            result.record = Some(records::analyse(model, sys, &result.links, &all, &plan));
        }
    }
    result.t = all.t.clone();
    (result.bodies, result.drives, result.sensors, result.loads) = all.into_series(model, &layout, &stacks.stacks);
    Ok(result)
}

/// How far a periodic run has settled, for its progress bar.
fn settling_message(settle: &SettleCheck, tolerance: f64) -> String {
    let (left, change) = (settle.remaining(), settle.change());
    if left.is_finite() {
        format!("start-up transient left {left:.1e} (target {tolerance:.0e})")
    } else if change.is_finite() {
        format!("change over the last period {change:.1e}")
    } else {
        String::new()
    }
}

/// How a non-periodic run's record is to be analysed (None for a periodic drive): the
/// case's `segment` (s), refused before the run when the record cannot hold it, or the
/// segment the slowest decay in the drive's band asks for
/// ([`crate::power::record::choose`] settles the estimator once the record is in).
pub fn record_plan(model: &Model, timing: &DriveTiming, segment: Option<f64>) -> Result<Option<RecordPlan>> {
    if timing.periodic {
        return Ok(None);
    }
    let samples = timing.steps_per_period;
    let given = segment.map(|seg| Welch::hann((seg / timing.dt).round() as usize));
    if let Some(w) = &given {
        w.check(samples).map_err(|r| crate::error::Error::analysis_setting("segment", r))?;
    }
    let decay_rate = super::drive::slowest_decay(model);
    Ok(Some(RecordPlan {
        samples,
        dt: timing.dt,
        given,
        decay_rate,
        needed_segment_s: crate::power::record::SEGMENT_TIME_CONSTANTS / decay_rate,
        band: super::drive::drive_band(model, 1.0 / (20.0 * timing.dt)),
    }))
}

/// Adds each point load's mean power and spectrum over the last period.
fn add_loads(result: &mut TransientResult, model: &Model, all: &PeriodRecord, harmonics_kept: usize) {
    let n = result.steps_per_period;
    for (j, l) in model.loads.iter().enumerate() {
        let start = all.lf[j].len() - n;
        let (f, v) = (&all.lf[j][start..], &all.lv[j][start..]);
        let fh = harmonics(f);
        let hmax = harmonics_kept.min(fh.len() - 1);
        let mut sp = LoadSpectrum::new(&l.name, l.at.x(), (result.period, n, hmax), fh, harmonics(v));
        // The sample mean, as the links' mean powers are taken.
        sp.power_total = mean_product(f, v);
        result.load_spectra.push(sp);
    }
}

/// Adds each link's series over the recorded window, and its mean power and spectrum
/// (up to harmonic `harmonics_kept`) over the last period.
fn add_links(result: &mut TransientResult, sys: &System, all: &PeriodRecord, harmonics_kept: usize) {
    let n = result.steps_per_period;
    for (l, lk) in sys.links.iter().enumerate() {
        let ls = all.link_series(l, lk);
        let start = ls.interface.len() - n;
        let (interface, velocity) = (&ls.interface[start..], &ls.base_velocity[start..]);
        result.mean_power.push(mean_product(interface, velocity));
        let fh = harmonics(&ls.transmitted[start..]);
        let hmax = harmonics_kept.min(fh.len() - 1);
        let (ih, vh, ah) = (harmonics(interface), harmonics(velocity), harmonics(&ls.base_acceleration[start..]));
        result.spectra.push(LinkSpectrum::new(result.period, n, hmax, fh, ih, vh, ah));
        result.links.push(ls);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::LoadedCase;

    /// A coarse beam driven by an inertial actuator, integrated by linear acceleration
    /// (stable for ω_max·Δt < 2√3), with the step `factor` times that limit: the model,
    /// its system, the settings and the timing, bypassing the check before the run.
    fn linear_acceleration_at(factor: f64) -> Result<TransientResult> {
        let text = "[beam.mesh]\nelements = 6\n[[actuator]]\ntype = \"inertial\"\nx_e = 0.2\n\
                    [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n\
                    [[analysis]]\ntype = \"transient\"\nscheme = \"linear_acceleration\"\nperiods = 3\n";
        let lc = LoadedCase::from_str(text, "t.toml", ".".into()).unwrap();
        let (model, sys) = crate::analysis::plan::model_and_system(&lc).unwrap();
        let all: Vec<usize> = (0..sys.n()).collect();
        let omega_max = *crate::solve::eigen::modes(&sys.k, &sys.m, &all, sys.n()).unwrap().omega.last().unwrap();
        let limit = 2.0 * 3f64.sqrt() / omega_max;
        let mut s = crate::app::runner::transient_settings(&lc.case.analysis[0], None).unwrap();
        let steps = ((1.0 / 60.0) / (factor * limit)).round() as usize;
        s.steps_per_period = Some(steps);
        let timing = DriveTiming::stepped(&model, Step::of(None, Some(steps)), None, None).unwrap();
        assert!((timing.dt / limit - factor).abs() < 0.05 * factor, "Δt/limit = {}", timing.dt / limit);
        integrate(&model, &sys, &s, timing)
    }

    #[test]
    fn a_run_beyond_the_stability_limit_is_stopped_by_the_energy_no_drive_supplied() {
        // Just beyond the limit the highest mode grows slowly: caught by its energy, long
        // before its numbers overflow, with the period and the place named.
        let e = linear_acceleration_at(1.05).unwrap_err().to_string();
        assert!(e.contains("diverged in period") && e.contains("times the") && e.contains("beam node"), "{e}");
        // Within the limit the same run completes, and its balance closes.
        let r = linear_acceleration_at(0.9).unwrap();
        assert!(r.energy_run.system.relative_error() < 1e-2, "{}", r.energy_run.system.relative_error());
        assert!(r.net_power.iter().all(|p| p.is_finite() && *p > 0.0), "{:?}", r.net_power);
    }
}
