//! The drive as the analyses see it: its timing (the period it repeats with and how a run
//! samples it) and the stacks' active forces over one period of their periodic state.
//!
//! F_p = k_p·(d_p·V − h) depends on the voltage alone (physics spec §4), so a stack's force
//! over a period of its periodic state is a property of the stack and its drive, not of
//! the structure it stands on: [`stack_cycle`] computes it with the one periodic hysteresis
//! cycle of the crate ([`BoucWen::periodic_cycle_from`]), and [`StackForceCache`] keeps its
//! harmonics for the many cases of a sweep that share a drive.
//!
//! [`BoucWen::periodic_cycle_from`]: crate::actuator::bouc_wen::BoucWen::periodic_cycle_from
//! [`BoucWen::bound`]: crate::actuator::bouc_wen::BoucWen::bound

use crate::actuator::Stack;
use crate::assembly::Model;
use crate::error::{Error, Result};
use crate::power::spectra::harmonics;
use crate::signal::VoltageInput;
use num_complex::Complex64;
use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// The time step a case asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Step {
    /// Δt (s), used as given.
    Dt(f64),
    /// Steps per drive period: Δt = period / n.
    PerPeriod(usize),
    /// The default: 200 steps per period, or finer where the harmonics need it.
    Default,
}

impl Step {
    /// From a case's `dt` and `steps_per_period` (at most one of them).
    pub fn of(dt: Option<f64>, steps_per_period: Option<usize>) -> Self {
        match (dt, steps_per_period) {
            (Some(dt), _) => Step::Dt(dt),
            (None, Some(n)) => Step::PerPeriod(n),
            (None, None) => Step::Default,
        }
    }
}

/// How an analysis samples the drive in time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DriveTiming {
    /// The period T the drive repeats with (s). A non-periodic drive is run once over the
    /// requested duration, which then stands in for the period: the run is one "period".
    pub period: f64,
    /// Time step Δt = T / steps_per_period (s).
    pub dt: f64,
    /// Steps (samples) per period.
    pub steps_per_period: usize,
    /// Whether the drive repeats with `period` (false: `period` is the run's duration).
    pub periodic: bool,
}

impl DriveTiming {
    /// The time grid of a time-stepping run.
    ///
    /// A periodic drive without `duration` is stepped by `dt` exactly as given, which must
    /// divide the period into whole steps (to 1e-9; otherwise the error names the two nearest
    /// steps that do) and give at least 20 steps per period of the highest frequency to
    /// resolve: harmonic `harmonics` of the fastest drive's fundamental, or that fundamental
    /// itself. Without `dt` it takes 200 steps per period, or more where that resolution
    /// needs them. A non-periodic drive (or a periodic one given a `duration`) runs once,
    /// by whole steps of `dt` (the duration rounded up to them) or of 1/20 of the period of
    /// its highest frequency. Every drive counts, whatever the order of the actuators.
    pub fn stepped(model: &Model, step: Step, duration: Option<f64>, harmonics: Option<usize>) -> Result<Self> {
        let period = common_period(model)?;
        let dt = match step {
            Step::Dt(dt) => Some(dt),
            Step::PerPeriod(n) => {
                let p = period.filter(|_| duration.is_none()).ok_or_else(|| {
                    Error::analysis_setting(
                        "steps_per_period",
                        "steps per period need a periodic drive run by periods (no `duration`): give `dt`",
                    )
                })?;
                Some(p / n as f64)
            }
            Step::Default => None,
        };
        if let (Some(p), None) = (period, duration) {
            let fastest = model.drive_signals().filter_map(|s| s.fundamental_frequency()).fold(1.0 / p, f64::max);
            let resolve_hz = fastest * harmonics.unwrap_or(1) as f64;
            let what = match harmonics {
                Some(h) => format!("harmonic {h} of the drive ({resolve_hz:.6e} Hz)"),
                None => format!("the drive frequency ({resolve_hz:.6e} Hz)"),
            };
            let n_min = countable(20.0 * resolve_hz * p * (1.0 - 1e-12)).ok_or_else(|| {
                Error::analysis_setting(
                    if harmonics.is_some() { "harmonics" } else { "dt" },
                    format!(
                        "resolving {what} over the drive period {p:e} s takes {:.3e} steps per period, more \
                         than can be counted ({MAX_STEPS:.1e}): analyse fewer harmonics",
                        20.0 * resolve_hz * p
                    ),
                )
            })?;
            return match dt {
                Some(dt) => {
                    let steps = p / dt;
                    if countable(steps).is_none() {
                        return Err(uncountable("dt", format!("Δt = {dt:e} s divides the drive period {p:e} s")));
                    }
                    let n = steps.round();
                    if (steps - n).abs() > 1e-9 * steps || n < 1.0 {
                        let (lo, hi) = (steps.floor().max(1.0), steps.ceil().max(1.0));
                        return Err(Error::analysis_setting("dt", format!(
                                "Δt = {dt:e} s does not divide the drive period {p:e} s into whole steps ({steps:.6} steps): \
                                 give `steps_per_period` = {hi} (Δt = {:.9e} s) or {lo} (Δt = {:.9e} s)",
                                p / hi,
                                p / lo
                            ),
                        ));
                    }
                    let n = n as usize;
                    let dt = if let Step::PerPeriod(_) = step { p / n as f64 } else { dt };
                    if n < n_min {
                        return Err(Error::analysis_setting(
                            "dt",
                            format!(
                                "Δt = {dt:e} s is too coarse for {what}: at least 20 steps per period of it are \
                                 needed, i.e. `steps_per_period` ≥ {n_min} (Δt ≤ {:.9e} s)",
                                p / n_min as f64
                            ),
                        ));
                    }
                    Ok(DriveTiming { period: p, dt, steps_per_period: n, periodic: true })
                }
                None => {
                    let n = n_min.max(200);
                    Ok(DriveTiming { period: p, dt: p / n as f64, steps_per_period: n, periodic: true })
                }
            };
        }
        let d = match duration {
            Some(d) => d,
            None => default_record(model)?,
        };
        let hf = model.drive_signals().filter_map(|s| s.highest_frequency()).fold(0.0, f64::max);
        match (dt, hf > 0.0) {
            (Some(dt), _) => {
                let n = countable(d / dt - 1e-9)
                    .ok_or_else(|| uncountable("dt", format!("Δt = {dt:e} s divides the duration {d:e} s")))?;
                Ok(DriveTiming { period: n as f64 * dt, dt, steps_per_period: n, periodic: false })
            }
            (None, true) => {
                let n = countable(d * 20.0 * hf - 1e-9).ok_or_else(|| {
                    uncountable(
                        "duration",
                        format!("20 steps per period of the drive's highest frequency ({hf:e} Hz) divide {d:e} s"),
                    )
                })?;
                Ok(DriveTiming { period: d, dt: d / n as f64, steps_per_period: n, periodic: false })
            }
            (None, false) => {
                Err(Error::analysis_setting("dt", "the drive has no frequency to derive a time step from: give `dt`"))
            }
        }
    }

    /// The harmonics of 1/period a run analyses: `requested`, or as many as its time step
    /// resolves at 20 steps per harmonic period (spec §8).
    pub fn analysed_harmonics(&self, requested: Option<usize>) -> usize {
        requested.unwrap_or((self.steps_per_period / 20).max(1))
    }

    /// One period of a periodic drive sampled `samples` times, as the frequency-domain
    /// steady state takes it. Errors if the drive does not repeat.
    pub fn sampled(model: &Model, samples: usize) -> Result<Self> {
        let period = common_period(model)?.ok_or_else(|| {
            Error::analysis_setting("type", "a frequency-domain steady state needs a periodic drive, and this is a non-periodic drive (chirp, step or series): use a transient analysis")
        })?;
        Ok(DriveTiming { period, dt: period / samples as f64, steps_per_period: samples, periodic: true })
    }
}

/// Time constants of the slowest decay in the band a record runs past a drive that holds
/// still at its end (a step, a series): the response then decays to e^−15 ≈ 3e-7 of its
/// peak, far below [`crate::power::record::DECAYED`], so one segment holds it and the
/// FRFs stay exact even well below the first mode, where the accelerance is small beside
/// what remains.
pub const HELD_TIME_CONSTANTS: f64 = 15.0;

/// When a drive stops changing (s), and whether it then holds still: a step after its
/// ramp, a series after its last sample; a chirp keeps running at `f_end` after its sweep
/// and a sine never stops.
fn drive_span(s: &VoltageInput) -> (f64, bool) {
    match s {
        VoltageInput::Chirp { duration, .. } => (*duration, false),
        VoltageInput::Step { time, rise_time, .. } => (time + rise_time, true),
        VoltageInput::Series { samples } => (samples.times().last().copied().unwrap_or(0.0), true),
        VoltageInput::Sine { .. } | VoltageInput::Sines { .. } => (0.0, false),
    }
}

/// The band a record's drives excite (Hz): from the lowest frequency any of them names (a
/// chirp's sweep start, a sine's frequency; 0 for a step or a series) up to the highest,
/// or to `resolved` (what the time step resolves) for a jump.
pub fn drive_band(model: &Model, resolved: f64) -> (f64, f64) {
    let low = |s: &VoltageInput| match s {
        VoltageInput::Chirp { f_start, f_end, .. } => f_start.min(*f_end),
        VoltageInput::Sine { frequency, .. } => *frequency,
        VoltageInput::Sines { components, .. } => components.iter().map(|c| c.frequency).fold(f64::INFINITY, f64::min),
        VoltageInput::Step { .. } | VoltageInput::Series { .. } => 0.0,
    };
    let lo = model.drive_signals().map(low).fold(f64::INFINITY, f64::min);
    let hi = model.drive_signals().map(|s| s.highest_frequency().unwrap_or(resolved)).fold(0.0, f64::max);
    (lo.min(hi), hi.min(resolved))
}

/// The slowest decay rate σ (1/s) of the structure's modes in a record's band: Rayleigh
/// damping decays a mode at ω by (a₀ + a₁ω²)/2, slowest at the band's low edge (the
/// actuators' own dampers only add to it).
pub fn slowest_decay(model: &Model) -> f64 {
    let (lo, _) = drive_band(model, f64::INFINITY);
    model.damping.slowest_decay(2.0 * std::f64::consts::PI * lo)
}

/// A non-periodic run's length without `duration`: the drives' span, then
/// [`HELD_TIME_CONSTANTS`] of the slowest decay in the band when every drive holds still
/// afterwards (one exact segment), else a Welch segment of
/// [`crate::power::record::SEGMENT_TIME_CONSTANTS`] of them after the sweep.
pub fn default_record(model: &Model) -> Result<f64> {
    let sigma = slowest_decay(model);
    if !(sigma > 0.0 && sigma.is_finite()) {
        return Err(Error::analysis_setting(
            "duration",
            "a non-periodic drive needs `duration` here: the structure has no damping at the low edge of the \
             drive's band, so no record length lets its response decay",
        ));
    }
    let spans: Vec<(f64, bool)> = model.drive_signals().map(drive_span).collect();
    let span = spans.iter().map(|s| s.0).fold(0.0, f64::max);
    let held = spans.iter().all(|s| s.1);
    let taus = if held { HELD_TIME_CONSTANTS } else { crate::power::record::SEGMENT_TIME_CONSTANTS };
    Ok(span + taus / sigma)
}

/// The most steps one period (or one non-periodic run) may be divided into: the largest
/// count every smaller count of which f64 holds exactly (2⁵³), far above any step budget.
pub const MAX_STEPS: f64 = 9_007_199_254_740_992.0;

/// `x` rounded up to a whole count ≥ 1, None when it is not finite or above [`MAX_STEPS`].
fn countable(x: f64) -> Option<usize> {
    if x.is_nan() {
        return None;
    }
    let n = x.ceil().max(1.0);
    (n <= MAX_STEPS).then(|| usize::try_from(n as u64).ok()).flatten()
}

/// The error of a step count beyond [`MAX_STEPS`]: `what` divides something into it.
fn uncountable(field: &str, what: String) -> Error {
    Error::analysis_setting(
        field,
        format!("{what} into more steps than can be counted ({MAX_STEPS:.1e}): give a larger `dt` or a shorter run"),
    )
}

/// The period the model's drives — actuators' voltages and point loads' forces — repeat
/// with together (s): the longest of their periods, each commensurate with the first's;
/// None when any of them does not repeat. Errors without any drive or with incommensurate
/// periods.
pub fn common_period(model: &Model) -> Result<Option<f64>> {
    let fields: Vec<String> = (0..model.actuators.len())
        .map(|i| format!("actuator[{i}].voltage"))
        .chain((0..model.loads.len()).map(|i| format!("load[{i}].force")))
        .collect();
    let periods: Vec<Option<f64>> = model.drive_signals().map(|s| s.period()).collect();
    let Some(&period) = periods.first() else {
        return Err(Error::case_field(
            "actuator",
            "the analysis needs at least one actuator or [[load]] to drive the system",
        ));
    };
    for (i, p) in periods.iter().enumerate().skip(1) {
        if let (Some(p0), Some(pi)) = (period, *p) {
            let ratio = p0.max(pi) / p0.min(pi);
            // Written so that a ratio that is not a finite number (a period of 0 or ∞)
            // is refused too.
            if !((ratio - ratio.round()).abs() <= 1e-9) {
                return Err(Error::case_field(
                    &fields[i],
                    format!(
                        "its period {pi:e} s and the first drive's {p0:e} s have no common period: \
                         every periodic drive must repeat with a whole multiple of the others"
                    ),
                ));
            }
        }
    }
    if periods.iter().any(Option::is_none) {
        return Ok(None);
    }
    Ok(period.map(|p| periods.iter().flatten().fold(p, |a, &b| a.max(b))))
}

/// The hysteresis cycle has settled when h at the end of a period repeats its start to
/// this fraction of the bound on |h| ([`BoucWen::bound`]).
pub const CYCLE_TOLERANCE: f64 = 1e-13;

/// Periods the hysteresis cycle may take to settle before the analysis gives up.
pub const CYCLE_MAX_PERIODS: usize = 10_000;

/// One period of a stack's periodic state: voltage V (V), hysteretic displacement h (m) and
/// active force F_p (N) at t_j = (p + j/N)·T, j < N, p the period it settled in.
#[derive(Clone, Debug, Default)]
pub struct StackCycle {
    pub voltage: Vec<f64>,
    pub h: Vec<f64>,
    pub f_p: Vec<f64>,
    /// Periods it took h to settle into its cycle, the sampled one included (1 without
    /// hysteresis).
    pub periods: usize,
}

/// A stack's force over one period `period` (s) of its periodic state, `samples` samples:
/// the Bouc–Wen cycle from the stack's h₀ at t = 0, settled to [`CYCLE_TOLERANCE`]; without
/// hysteresis the linear stack, h = 0.
pub fn stack_cycle(stack: &Stack, period: f64, samples: usize) -> Result<StackCycle> {
    let n = samples;
    let (voltage, h, periods) = if stack.hysteresis_on {
        let c = stack.hysteresis.periodic_cycle_from(
            &stack.voltage,
            stack.h0,
            period,
            samples,
            CYCLE_TOLERANCE,
            CYCLE_MAX_PERIODS,
        )?;
        if !c.converged {
            return Err(Error::Numerical(format!(
                "the hysteresis cycle did not repeat within {CYCLE_MAX_PERIODS} periods"
            )));
        }
        let (mut v, mut h) = (c.v, c.h);
        v.truncate(n);
        h.truncate(n);
        (v, h, c.periods)
    } else {
        let v = (0..n).map(|j| stack.voltage.value(j as f64 / n as f64 * period)).collect();
        (v, vec![0.0; n], 1)
    };
    let f_p = voltage.iter().zip(&h).map(|(&v, &h)| stack.active_force(v, h)).collect();
    Ok(StackCycle { voltage, h, f_p, periods })
}

/// One period of each point load's force (N) at the samples of `timing`, t_j = j·Δt.
pub fn load_cycles(model: &Model, timing: &DriveTiming) -> Vec<Vec<f64>> {
    let n = timing.steps_per_period;
    model.loads.iter().map(|l| (0..n).map(|j| l.force.value(j as f64 * timing.dt)).collect()).collect()
}

/// The stack forces' harmonics F̂_p,k (N), k = 0..=n_harm, of a cycle (single-sided, see
/// [`crate::power::spectra`]).
pub fn force_harmonics(cycle: &StackCycle, n_harm: usize) -> Vec<Complex64> {
    harmonics(&cycle.f_p)[..=n_harm].to_vec()
}

/// A stack's force harmonics over one period of its periodic state.
#[derive(Clone, Debug, Default)]
pub struct StackHarmonics {
    /// F̂_p,k (N), k = 0..=n_harm.
    pub f_p: Vec<Complex64>,
    /// Periods the hysteresis took to settle (see [`StackCycle::periods`]).
    pub periods: usize,
}

/// Stack-force harmonics shared by the cases of a sweep. F_p depends on the stack and its
/// voltage alone, not on where the stack stands, so a placement sweep settles the Bouc–Wen
/// cycle once per drive instead of once per case. A cached value is a pure function of its
/// key, so which thread fills it changes no bit.
#[derive(Debug, Default)]
pub struct StackForceCache {
    map: Mutex<HashMap<String, Arc<StackHarmonics>>>,
    /// Hysteresis cycles settled (cache misses).
    pub computed: AtomicUsize,
}

impl StackForceCache {
    /// F̂_p,k, k = 0..=n_harm, of `stack` over `period` (s) from `samples` samples: what
    /// [`force_harmonics`] of [`stack_cycle`] gives.
    pub fn get(&self, stack: &Stack, period: f64, samples: usize, n_harm: usize) -> Result<Arc<StackHarmonics>> {
        // Debug formatting of f64 round-trips exactly, so equal keys mean equal inputs.
        let key = format!("{stack:?}|{period:?}|{samples}|{n_harm}");
        if let Some(v) = self.map.lock().expect("cache lock").get(&key) {
            return Ok(v.clone());
        }
        let cycle = stack_cycle(stack, period, samples)?;
        let h = Arc::new(StackHarmonics { f_p: force_harmonics(&cycle, n_harm), periods: cycle.periods });
        self.computed.fetch_add(1, Ordering::Relaxed);
        self.map.lock().expect("cache lock").entry(key).or_insert(h.clone());
        Ok(h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::plan::calibrated_model;
    use crate::case::LoadedCase;
    use std::path::PathBuf;

    fn model(voltage: &str) -> Model {
        let text = format!("base = \"rigid\"\n[[actuator]]\ntype = \"inertial\"\n[actuator.voltage]\n{voltage}\n");
        let lc = LoadedCase::from_str(&text, "d.toml", PathBuf::from(".")).unwrap();
        calibrated_model(&lc).unwrap()
    }

    const SINE: &str = "kind = \"sine\"\namplitude = 48.0\nfrequency = 30.0";

    /// Over twice its period the cycle is the same cycle twice: a 2T-cycle of 2N samples is
    /// the T-cycle of N samples, twice, and the 2T grid's harmonic 2 is the T grid's
    /// harmonic 1.
    #[test]
    fn a_cycle_over_a_multiple_of_the_period_repeats_the_cycle() {
        let m = model(SINE);
        let stack = m.actuators[0].stack();
        let (t, n) = (1.0 / 30.0, 200);
        let one = stack_cycle(stack, t, n).unwrap();
        let two = stack_cycle(stack, 2.0 * t, 2 * n).unwrap();
        let scale = stack.hysteresis.bound(0.0);
        for j in 0..n {
            for half in [j, n + j] {
                assert!((two.h[half] - one.h[j]).abs() < 1e-12 * scale, "h at sample {half}");
                assert!((two.voltage[half] - one.voltage[j]).abs() < 1e-12 * 48.0, "V at sample {half}");
            }
        }
        assert!(one.periods > 1, "hysteresis settles over several periods");
        let (h1, h2) = (force_harmonics(&one, 3), force_harmonics(&two, 6));
        assert!((h2[2] - h1[1]).norm() < 1e-9 * h1[1].norm(), "{} vs {}", h2[2], h1[1]);
        assert!(h2[1].norm() < 1e-9 * h1[1].norm(), "no subharmonic");
    }

    #[test]
    fn the_cache_gives_the_bits_of_the_cycle_and_settles_it_once() {
        let m = model(SINE);
        let stack = m.actuators[0].stack();
        let cache = StackForceCache::default();
        let a = cache.get(stack, 1.0 / 30.0, 256, 5).unwrap();
        let b = cache.get(stack, 1.0 / 30.0, 256, 5).unwrap();
        let direct = force_harmonics(&stack_cycle(stack, 1.0 / 30.0, 256).unwrap(), 5);
        assert_eq!(cache.computed.load(Ordering::Relaxed), 1);
        assert_eq!(a.f_p, direct);
        assert_eq!(b.f_p, direct);
        // Another timing is another entry.
        cache.get(stack, 2.0 / 30.0, 256, 5).unwrap();
        assert_eq!(cache.computed.load(Ordering::Relaxed), 2);
    }

    #[test]
    fn timing_follows_the_drive_and_refuses_what_it_cannot_sample() {
        let m = model(SINE);
        // A given dt is used as given, when it divides the period.
        let s = DriveTiming::stepped(&m, Step::Dt(1.0 / 30.0 / 250.0), None, Some(9)).unwrap();
        assert!(s.periodic && s.steps_per_period == 250 && s.dt == 1.0 / 30.0 / 250.0);
        // One that does not is refused, with the two nearest steps that do.
        let e = DriveTiming::stepped(&m, Step::Dt(1e-4), None, None).unwrap_err().to_string();
        assert!(e.contains("`dt`") && e.contains("whole steps"), "{e}");
        assert!(e.contains("`steps_per_period` = 334") && e.contains("or 333"), "{e}");
        assert!(
            e.contains(&format!("{:.9e}", 1.0 / 30.0 / 334.0)) && e.contains(&format!("{:.9e}", 1.0 / 30.0 / 333.0)),
            "{e}"
        );
        // Default: 200 steps per period, more where harmonic 20 needs 20 steps each.
        assert_eq!(DriveTiming::stepped(&m, Step::Default, None, Some(9)).unwrap().steps_per_period, 200);
        assert_eq!(DriveTiming::stepped(&m, Step::Default, None, Some(20)).unwrap().steps_per_period, 400);
        let d = DriveTiming::stepped(&m, Step::Default, None, None).unwrap();
        assert_eq!((d.steps_per_period, d.analysed_harmonics(None), d.analysed_harmonics(Some(3))), (200, 10, 3));
        let e = DriveTiming::stepped(&m, Step::PerPeriod(100), None, Some(9)).unwrap_err().to_string();
        assert!(e.contains("`dt`") && e.contains("too coarse") && e.contains("`steps_per_period` ≥ 180"), "{e}");
        let exact = DriveTiming::stepped(&m, Step::PerPeriod(6667), None, None).unwrap();
        assert_eq!((exact.steps_per_period, exact.dt), (6667, 1.0 / 30.0 / 6667.0));
        // A duration runs once, by whole steps of the given dt.
        let once = DriveTiming::stepped(&m, Step::Dt(1e-4), Some(0.05), Some(9)).unwrap();
        assert!(!once.periodic && once.steps_per_period == 500 && once.dt == 1e-4);
        let longer = DriveTiming::stepped(&m, Step::Dt(3e-4), Some(0.05), None).unwrap();
        assert!(longer.steps_per_period == 167 && longer.dt == 3e-4 && longer.period >= 0.05);
        assert_eq!(DriveTiming::sampled(&m, 64).unwrap().period, 1.0 / 30.0);
        let chirp = model(
            "kind = \"chirp\"\namplitude = 10.0\nf_start = 5.0\nf_end = 50.0\nduration = 1.0\nsweep = \"linear\"",
        );
        let e = DriveTiming::sampled(&chirp, 64).unwrap_err().to_string();
        assert!(e.contains("needs a periodic drive"), "{e}");
        // On a rigid base nothing decays to size a record by: it needs `duration`.
        let e = DriveTiming::stepped(&chirp, Step::Default, None, None).unwrap_err().to_string();
        assert!(e.contains("`duration`") && e.contains("no damping"), "{e}");
    }
}
