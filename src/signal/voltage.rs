//! Voltage inputs `V(t)` for the stacks.
//!
//! A [`VoltageInput`] is the signal as physics sees it: a function of time, complete when
//! built (a case file's `kind` tables and CSV files become one in
//! [`crate::case::signal::SignalSpec::build`]). Units are volts, hertz, seconds and radians
//! throughout.
//!
//! Besides the value, every input gives its exact time derivative ([`VoltageInput::rate`])
//! and the times where the voltage reverses direction ([`VoltageInput::turning_points`]):
//! the hysteresis model integrates exactly in voltage space and needs monotone pieces.

use num_complex::Complex64;
use std::f64::consts::{PI, TAU};

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::signal::csv::check_time_axis;

/// Largest denominator tried when looking for a common period of several sines (see
/// [`VoltageInput::period`]).
pub const MAX_PERIOD_RATIO: u32 = 1000;

/// Relative tolerance to which frequencies must be integer multiples of a common fundamental.
pub const COMMENSURATE_TOL: f64 = 1e-9;

/// Samples per period of the highest frequency when turning points are searched numerically.
const SEARCH_PER_PERIOD: f64 = 32.0;

/// Bisection stops when the bracket is this short (s).
const BISECT_TOL: f64 = 1e-14;

/// One component of a [`VoltageInput::Sines`] sum: `amplitude·sin(2π·frequency·t + phase)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SineComponent {
    /// V
    pub amplitude: f64,
    /// Hz, > 0
    pub frequency: f64,
    /// rad
    #[serde(default)]
    pub phase: f64,
}

/// Frequency law of a [`VoltageInput::Chirp`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ChirpLaw {
    /// f(t) = f_start + (f_end − f_start)·t/duration
    #[default]
    Linear,
    /// f(t) = f_start·(f_end/f_start)^(t/duration)
    Log,
}

/// Tabulated voltage of a [`VoltageInput::Series`] (see [`VoltageInput::from_samples`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Samples {
    t: Vec<f64>,
    v: Vec<f64>,
}

impl Samples {
    /// Sample times (s), strictly increasing, at least two.
    pub fn times(&self) -> &[f64] {
        &self.t
    }
    /// Sample voltages (V).
    pub fn values(&self) -> &[f64] {
        &self.v
    }
    /// Index `i` of the segment `[t_i, t_{i+1})` holding `t`; `None` outside `[t_0, t_last)`.
    fn segment(&self, t: f64) -> Option<usize> {
        let n = self.t.len();
        if !(t >= self.t[0] && t < self.t[n - 1]) {
            return None;
        }
        Some(self.t.partition_point(|&x| x <= t) - 1)
    }
    fn slope(&self, i: usize) -> f64 {
        (self.v[i + 1] - self.v[i]) / (self.t[i + 1] - self.t[i])
    }
}

/// The voltage applied to a stack, as a function of time.
#[derive(Debug, Clone, PartialEq)]
pub enum VoltageInput {
    /// `V = offset + amplitude·sin(2π·frequency·t + phase)`.
    Sine { amplitude: f64, frequency: f64, offset: f64, phase: f64 },
    /// `V = offset + Σ amplitude_k·sin(2π·frequency_k·t + phase_k)`.
    Sines { offset: f64, components: Vec<SineComponent> },
    /// `V = offset + amplitude·sin φ(t)`, with the instantaneous frequency `φ'/2π` sweeping
    /// from `f_start` at t = 0 to `f_end` at t = `duration` (linearly or geometrically).
    ///
    /// The phase is continuous everywhere: before t = 0 the frequency is `f_start`, after
    /// `duration` the signal **continues at `f_end`** (it does not stop or restart).
    Chirp { amplitude: f64, f_start: f64, f_end: f64, duration: f64, sweep: ChirpLaw, offset: f64 },
    /// `from` before `time`, `to` after; with `rise_time > 0` a linear ramp over
    /// `[time, time + rise_time]`. With `rise_time = 0` the jump is at `time` and
    /// `V(time) = to` (right-continuous).
    Step { time: f64, from: f64, to: f64, rise_time: f64 },
    /// Tabulated voltage, linearly interpolated, held at the first/last value outside the
    /// table (built by [`VoltageInput::from_samples`], or from a case's CSV file).
    Series { samples: Samples },
}

fn sgn(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// Bisection for a sign change of `f` in `[a, b]`, `fa = f(a)`, to [`BISECT_TOL`].
fn bisect(f: &impl Fn(f64) -> f64, mut a: f64, mut b: f64, mut fa: f64) -> f64 {
    loop {
        // Written so that a NaN bracket ends the search too.
        if !(b - a > BISECT_TOL) {
            break;
        }
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        let fm = f(m);
        if fm == 0.0 {
            return m;
        }
        if (fm < 0.0) != (fa < 0.0) {
            b = m;
        } else {
            a = m;
            fa = fm;
        }
    }
    0.5 * (a + b)
}

/// Intervals the turning-point search cuts (t0, t1) into for a signal whose highest
/// frequency is `fmax`: [`SEARCH_PER_PERIOD`] a period, at least one (None: not finite or
/// beyond 2⁶³).
fn search_intervals(t0: f64, t1: f64, fmax: f64) -> Option<u64> {
    let n = (t1 - t0) * fmax * SEARCH_PER_PERIOD;
    // Written so that NaN gives None too.
    (n < 9.2e18).then(|| n.ceil().max(1.0) as u64)
}

/// Node `j` of the search grid of (t0, t1) in `n` intervals (exactly t1 at j = n).
fn grid_node(t0: f64, t1: f64, n: usize, j: usize) -> f64 {
    if j == n {
        t1
    } else {
        t0 + (t1 - t0) * (j as f64 / n as f64)
    }
}

/// Nodes between which the sum of sines is turned by rotation, not evaluated afresh: the
/// rotations' round-off stays within a few hundred ulps of the rate.
const RESEED_NODES: usize = 64;

/// The rate V̇ and its derivative of the sum of `components` at the nodes of a uniform grid
/// of (t0, t1) in `n` intervals, in order: each component's phasor e^{i(ωt + φ)} is turned
/// by its step e^{iωΔt} from node to node (four products instead of a sine and a cosine),
/// evaluated afresh every [`RESEED_NODES`] nodes and at t1.
fn sines_grid(components: &[SineComponent], t0: f64, t1: f64, n: usize) -> impl Iterator<Item = (f64, f64)> + '_ {
    let h = (t1 - t0) / n as f64;
    let omega: Vec<f64> = components.iter().map(|c| TAU * c.frequency).collect();
    let step: Vec<Complex64> = omega.iter().map(|w| Complex64::from_polar(1.0, w * h)).collect();
    let mut z = vec![Complex64::new(0.0, 0.0); components.len()];
    (0..=n).map(move |j| {
        let fresh = j % RESEED_NODES == 0 || j == n;
        let t = grid_node(t0, t1, n, j);
        let (mut rate, mut accel) = (0.0, 0.0);
        for (k, c) in components.iter().enumerate() {
            z[k] = if fresh { Complex64::from_polar(1.0, omega[k] * t + c.phase) } else { z[k] * step[k] };
            rate += c.amplitude * omega[k] * z[k].re;
            accel -= c.amplitude * omega[k] * omega[k] * z[k].im;
        }
        (rate, accel)
    })
}

/// Times in (t0, t1) where `rate` changes sign, for a smooth signal whose highest frequency
/// is `fmax`: dense sampling of the rate (`grid`: the rate and its derivative at the
/// [`search_intervals`] + 1 nodes of a uniform grid, in order), bisection of every sign
/// change, and — so that two close roots inside one sampling interval are not missed — a
/// check of the rate at every extremum of the rate (a sign change of `accel`) inside an
/// interval without a sign change.
fn rate_sign_changes<G: Iterator<Item = (f64, f64)>>(
    (t0, t1, n): (f64, f64, usize),
    rate: impl Fn(f64) -> f64,
    accel: impl Fn(f64) -> f64,
    grid: G,
) -> Vec<f64> {
    let node = |j: usize| grid_node(t0, t1, n, j);
    let mut out = Vec::new();
    let mut grid = grid;
    let Some((mut ra, mut aa)) = grid.next() else { return out };
    let mut a = t0;
    for (j, (rb, ab)) in (1..=n).zip(grid) {
        let b = node(j);
        if ra == 0.0 && j > 1 {
            out.push(a);
        }
        let (sa, sb) = (sgn(ra), sgn(rb));
        if sa * sb < 0 {
            out.push(bisect(&rate, a, b, ra));
        } else if sa * sb > 0 && sgn(aa) * sgn(ab) < 0 {
            let m = bisect(&accel, a, b, aa);
            let rm = rate(m);
            if sgn(rm) * sa < 0 {
                out.push(bisect(&rate, a, m, ra));
                out.push(bisect(&rate, m, b, rm));
            }
        }
        a = b;
        ra = rb;
        aa = ab;
    }
    out.retain(|&t| t > t0 && t < t1);
    out
}

fn sort_dedup(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}

impl VoltageInput {
    /// A pure sine `amplitude·sin(2π·frequency·t)`.
    pub fn sine(amplitude: f64, frequency: f64) -> Self {
        VoltageInput::Sine { amplitude, frequency, offset: 0.0, phase: 0.0 }
    }

    /// A tabulated input built in code (e.g. a measured voltage). `label` names the source in
    /// error messages. Checks equal lengths, finite values and a strictly increasing time
    /// axis with at least two samples.
    pub fn from_samples(label: &str, t: Vec<f64>, v: Vec<f64>) -> Result<Self> {
        if t.len() != v.len() {
            return Err(Error::input(
                label,
                "voltage",
                format!("{} voltages for {} times; the columns must have equal length", v.len(), t.len()),
            ));
        }
        check_time_axis(label, "time", &t, false)?;
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(Error::input(label, "voltage", format!("row {}: value {} is not finite", i + 1, v[i])));
        }
        Ok(VoltageInput::Series { samples: Samples { t, v } })
    }

    /// Evaluations (of one component at one time) that finding the turning points over
    /// `span` seconds, cut into `intervals` searched one by one, takes: the rate and its
    /// derivative at [`SEARCH_PER_PERIOD`] points per period of the highest frequency, and
    /// at both ends of every interval. Zero for drives whose turning points need no search;
    /// None beyond 64 bits. Bisection adds about fifty evaluations per turning point found,
    /// fewer than the search samples.
    pub fn search_evaluations(&self, span: f64, intervals: u64) -> Option<u64> {
        let (components, fmax) = match self {
            VoltageInput::Sines { components, .. } => {
                (components.len(), components.iter().map(|c| c.frequency).fold(0.0, f64::max))
            }
            VoltageInput::Chirp { f_start, f_end, .. } => (1, f_start.max(*f_end)),
            _ => return Some(0),
        };
        search_intervals(0.0, span, fmax)?.checked_add(intervals)?.checked_mul(2 * components as u64)
    }

    /// The tabulated samples of a series; `None` for the other kinds.
    pub fn samples(&self) -> Option<&Samples> {
        match self {
            VoltageInput::Series { samples } => Some(samples),
            _ => None,
        }
    }

    /// Chirp phase φ(t) and its first two derivatives.
    fn chirp_phase(f0: f64, f1: f64, duration: f64, sweep: ChirpLaw, t: f64) -> (f64, f64, f64) {
        if t <= 0.0 {
            return (TAU * f0 * t, TAU * f0, 0.0);
        }
        let tt = t.min(duration);
        let (phi, f, fdot) = match sweep {
            ChirpLaw::Linear => {
                let k = (f1 - f0) / duration;
                (TAU * (f0 * tt + 0.5 * k * tt * tt), f0 + k * tt, k)
            }
            ChirpLaw::Log => {
                let l = (f1 / f0).ln();
                if l == 0.0 {
                    (TAU * f0 * tt, f0, 0.0)
                } else {
                    let x = l * tt / duration;
                    let f = f0 * x.exp();
                    (TAU * f0 * duration * x.exp_m1() / l, f, f * l / duration)
                }
            }
        };
        if t <= duration {
            (phi, TAU * f, TAU * fdot)
        } else {
            (phi + TAU * f1 * (t - duration), TAU * f1, 0.0)
        }
    }

    /// The voltage V(t) (V).
    ///
    /// # Panics
    /// For a `series` whose samples were not read yet ([`VoltageInput::load`]).
    pub fn value(&self, t: f64) -> f64 {
        match self {
            VoltageInput::Sine { amplitude, frequency, offset, phase } => {
                offset + amplitude * (TAU * frequency * t + phase).sin()
            }
            VoltageInput::Sines { offset, components } => {
                offset + components.iter().map(|c| c.amplitude * (TAU * c.frequency * t + c.phase).sin()).sum::<f64>()
            }
            VoltageInput::Chirp { amplitude, f_start, f_end, duration, sweep, offset } => {
                let (phi, _, _) = Self::chirp_phase(*f_start, *f_end, *duration, *sweep, t);
                offset + amplitude * phi.sin()
            }
            VoltageInput::Step { time, from, to, rise_time } => {
                if t < *time {
                    *from
                } else if *rise_time > 0.0 && t < time + rise_time {
                    from + (to - from) * ((t - time) / rise_time)
                } else {
                    *to
                }
            }
            VoltageInput::Series { samples } => {
                let s = samples;
                match s.segment(t) {
                    Some(i) => {
                        let w = (t - s.t[i]) / (s.t[i + 1] - s.t[i]);
                        s.v[i] + w * (s.v[i + 1] - s.v[i])
                    }
                    None if t < s.t[0] => s.v[0],
                    None => s.v[s.v.len() - 1],
                }
            }
        }
    }

    /// The left limit V(t⁻). Equal to [`value`](Self::value) except at the jump of a step
    /// with `rise_time = 0`, where it is `from`.
    pub fn value_left(&self, t: f64) -> f64 {
        match self {
            VoltageInput::Step { time, from, rise_time, .. } if *rise_time == 0.0 && t <= *time => *from,
            _ => self.value(t),
        }
    }

    /// The exact time derivative dV/dt (V/s). At a jump it is 0; at a kink (series knot,
    /// ramp end) it is the slope to the right.
    pub fn rate(&self, t: f64) -> f64 {
        match self {
            VoltageInput::Sine { amplitude, frequency, phase, .. } => {
                amplitude * TAU * frequency * (TAU * frequency * t + phase).cos()
            }
            VoltageInput::Sines { components, .. } => components
                .iter()
                .map(|c| c.amplitude * TAU * c.frequency * (TAU * c.frequency * t + c.phase).cos())
                .sum(),
            VoltageInput::Chirp { amplitude, f_start, f_end, duration, sweep, .. } => {
                let (phi, w, _) = Self::chirp_phase(*f_start, *f_end, *duration, *sweep, t);
                amplitude * w * phi.cos()
            }
            VoltageInput::Step { time, from, to, rise_time } => {
                if *rise_time > 0.0 && t >= *time && t < time + rise_time {
                    (to - from) / rise_time
                } else {
                    0.0
                }
            }
            VoltageInput::Series { samples } => {
                let s = samples;
                s.segment(t).map_or(0.0, |i| s.slope(i))
            }
        }
    }

    /// The left limit of dV/dt: equal to [`rate`](Self::rate) except at the kinks of a
    /// piecewise-linear input (series knot, ramp end), where it is the slope to the left.
    pub fn rate_left(&self, t: f64) -> f64 {
        match self {
            VoltageInput::Step { time, from, to, rise_time } => {
                if *rise_time > 0.0 && t > *time && t <= time + rise_time {
                    (to - from) / rise_time
                } else {
                    0.0
                }
            }
            VoltageInput::Series { samples } => {
                let s = samples;
                let n = s.t.len();
                if t > s.t[0] && t <= s.t[n - 1] {
                    s.slope(s.t.partition_point(|&x| x < t) - 1)
                } else {
                    0.0
                }
            }
            _ => self.rate(t),
        }
    }

    /// d²V/dt² for the smooth kinds (used by the turning-point search).
    fn accel(&self, t: f64) -> f64 {
        match self {
            VoltageInput::Sine { amplitude, frequency, phase, .. } => {
                let w = TAU * frequency;
                -amplitude * w * w * (w * t + phase).sin()
            }
            VoltageInput::Sines { components, .. } => components
                .iter()
                .map(|c| {
                    let w = TAU * c.frequency;
                    -c.amplitude * w * w * (w * t + c.phase).sin()
                })
                .sum(),
            VoltageInput::Chirp { amplitude, f_start, f_end, duration, sweep, .. } => {
                let (phi, w, wdot) = Self::chirp_phase(*f_start, *f_end, *duration, *sweep, t);
                amplitude * (wdot * phi.cos() - w * w * phi.sin())
            }
            _ => 0.0,
        }
    }

    /// The exact common period (s): `1/f` for a sine; for `sines`, the period of the common
    /// fundamental when every frequency is an integer multiple of `f_min/q` to
    /// [`COMMENSURATE_TOL`] relative, for the smallest `q ≤` [`MAX_PERIOD_RATIO`]. `None`
    /// otherwise and for the other kinds.
    pub fn period(&self) -> Option<f64> {
        self.fundamental_frequency().map(|f| 1.0 / f)
    }

    /// The fundamental frequency (Hz) of a periodic input, see [`period`](Self::period).
    pub fn fundamental_frequency(&self) -> Option<f64> {
        match self {
            VoltageInput::Sine { frequency, .. } => Some(*frequency),
            VoltageInput::Sines { components, .. } => {
                let freqs: Vec<f64> = components.iter().map(|c| c.frequency).collect();
                let fmin = freqs.iter().copied().fold(f64::INFINITY, f64::min);
                if freqs.is_empty() || !(fmin > 0.0 && fmin.is_finite()) {
                    return None;
                }
                (1..=MAX_PERIOD_RATIO).map(|q| fmin / q as f64).find(|&f0| {
                    freqs.iter().all(|&f| {
                        let n = (f / f0).round();
                        n >= 1.0 && (n * f0 - f).abs() <= COMMENSURATE_TOL * f
                    })
                })
            }
            _ => None,
        }
    }

    /// The highest frequency (Hz) a time step must resolve: the frequency of a sine, the
    /// largest component frequency, `max(f_start, f_end)` for a chirp, half the mean sampling
    /// rate of a loaded series, `1/(2·rise_time)` for a ramped step (a half period spans the
    /// ramp). `None` for a jump (no finite frequency: the jump is a turning point instead)
    /// and for a series not loaded yet.
    pub fn highest_frequency(&self) -> Option<f64> {
        match self {
            VoltageInput::Sine { frequency, .. } => Some(*frequency),
            VoltageInput::Sines { components, .. } => components.iter().map(|c| c.frequency).reduce(f64::max),
            VoltageInput::Chirp { f_start, f_end, .. } => Some(f_start.max(*f_end)),
            VoltageInput::Step { rise_time, .. } => (*rise_time > 0.0).then(|| 0.5 / rise_time),
            VoltageInput::Series { samples: s } => Some({
                let n = s.t.len();
                0.5 * (n - 1) as f64 / (s.t[n - 1] - s.t[0])
            }),
        }
    }

    /// Times in the open interval (t0, t1) where V̇ changes sign (the extrema of V), plus the
    /// jump of a step with `rise_time = 0`; sorted. Between two consecutive returned times
    /// (and t0, t1) the voltage is monotone.
    ///
    /// - sine: analytically, `2πf·t + phase = π/2 + kπ`;
    /// - series: the sample knots where the slope sign changes (a flat segment counts as its
    ///   own sign, so both of its ends may be returned);
    /// - step: the jump time (a ramp is monotone and has none);
    /// - sines and chirp: V̇ sampled 32 times per period of the highest frequency, each sign
    ///   change bisected to 1e-14 s; inside a sampling interval without a sign change the
    ///   extremum of V̇ is located too (bisection of V̈) and checked, so a close pair of
    ///   extrema is not missed. An exact zero of V̇ at a sampling node is returned even if V̇
    ///   only touches zero there (harmless for splitting: both sides stay monotone).
    pub fn turning_points(&self, t0: f64, t1: f64) -> Vec<f64> {
        // Written so that a NaN bound also gives no points.
        if t1.partial_cmp(&t0) != Some(std::cmp::Ordering::Greater) {
            return Vec::new();
        }
        match self {
            VoltageInput::Sine { amplitude, frequency, phase, .. } => {
                if *amplitude == 0.0 {
                    return Vec::new();
                }
                // V̇ = 0 where ωt + φ = (k + ½)π. The phase counts modulo 2π only, and
                // reduced it keeps k small enough for f64 to count in steps of one; the
                // count of k in (t0, t1) is taken up front, so the loop ends whatever the
                // numbers (a frequency or phase beyond double precision gives no points).
                let w = TAU * frequency;
                let phase = phase.rem_euclid(TAU);
                let k0 = ((w * t0 + phase) / PI - 0.5).floor();
                let span = ((w * t1 + phase) / PI - 0.5).floor() - k0;
                if !(k0.is_finite() && span.is_finite() && span >= 0.0 && k0.abs() < 1e15 && span < 1e15) {
                    return Vec::new();
                }
                (0..=span as u64)
                    .map(|j| ((k0 + j as f64 + 0.5) * PI - phase) / w)
                    .filter(|&t| t > t0 && t < t1)
                    .collect()
            }
            VoltageInput::Sines { components, .. } => {
                let fmax = components.iter().map(|c| c.frequency).fold(0.0, f64::max);
                let Some(n) = search_intervals(t0, t1, fmax).filter(|_| fmax > 0.0) else {
                    return Vec::new();
                };
                let n = n as usize;
                let grid = sines_grid(components, t0, t1, n);
                sort_dedup(rate_sign_changes((t0, t1, n), |t| self.rate(t), |t| self.accel(t), grid))
            }
            VoltageInput::Chirp { amplitude, f_start, f_end, .. } => {
                let Some(n) = search_intervals(t0, t1, f_start.max(*f_end)).filter(|_| *amplitude != 0.0) else {
                    return Vec::new();
                };
                let n = n as usize;
                let grid = (0..=n).map(|j| grid_node(t0, t1, n, j)).map(|t| (self.rate(t), self.accel(t)));
                sort_dedup(rate_sign_changes((t0, t1, n), |t| self.rate(t), |t| self.accel(t), grid))
            }
            VoltageInput::Step { time, from, to, rise_time } => {
                if *rise_time == 0.0 && from != to && *time > t0 && *time < t1 {
                    vec![*time]
                } else {
                    Vec::new()
                }
            }
            VoltageInput::Series { samples } => {
                let s = samples;
                let n = s.t.len();
                let slope_sign = |i: isize| -> i8 {
                    if i < 0 || i as usize >= n - 1 {
                        0
                    } else {
                        sgn(s.slope(i as usize))
                    }
                };
                (0..n)
                    .filter(|&k| s.t[k] > t0 && s.t[k] < t1)
                    .filter(|&k| slope_sign(k as isize - 1) != slope_sign(k as isize))
                    .map(|k| s.t[k])
                    .collect()
            }
        }
    }

    /// [`turning_points`](Self::turning_points) plus every other time in (t0, t1) where V is
    /// not smooth: the ends of a step's ramp, every sample knot of a series, t = 0 and
    /// t = `duration` of a chirp. Between two consecutive points V is monotone and C^∞, so a
    /// time integrator that steps exactly onto them keeps its full order.
    pub fn breakpoints(&self, t0: f64, t1: f64) -> Vec<f64> {
        if t1.partial_cmp(&t0) != Some(std::cmp::Ordering::Greater) {
            return Vec::new();
        }
        let mut out = self.turning_points(t0, t1);
        match self {
            VoltageInput::Chirp { duration, .. } => out.extend([0.0, *duration]),
            VoltageInput::Step { time, rise_time, .. } => out.extend([*time, time + rise_time]),
            VoltageInput::Series { samples } => out.extend_from_slice(&samples.t),
            _ => {}
        }
        out.retain(|&t| t > t0 && t < t1);
        sort_dedup(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `count` components at incommensurate frequencies up to about `fmax`, seeded phases.
    fn many_sines(count: usize, fmax: f64) -> Vec<SineComponent> {
        (0..count)
            .map(|k| SineComponent {
                amplitude: 1.0 / (k + 1) as f64,
                frequency: fmax * (0.1 + 0.9 * ((k as f64 * 0.618_033_988_75).fract())),
                phase: (k as f64 * 2.399_963).rem_euclid(TAU),
            })
            .collect()
    }

    #[test]
    fn the_rotated_grid_matches_the_sum_evaluated_afresh() {
        let components = many_sines(200, 1000.0);
        let input = VoltageInput::Sines { offset: 0.0, components: components.clone() };
        let (t0, t1, n) = (0.3, 1.7, 20_000);
        let scale: f64 = components.iter().map(|c| c.amplitude * TAU * c.frequency).sum();
        let worst = sines_grid(&components, t0, t1, n)
            .enumerate()
            .map(|(j, (r, a))| {
                let t = grid_node(t0, t1, n, j);
                let w = TAU * 1000.0;
                ((r - input.rate(t)) / scale).abs().max(((a - input.accel(t)) / (scale * w)).abs())
            })
            .fold(0.0, f64::max);
        assert!(worst < 1e-12, "relative error {worst:e}");
        // Its turning points split the signal into monotone pieces, as the search promises.
        let tps = input.turning_points(t0, t0 + 0.05);
        assert!(tps.len() > 10);
        assert_monotone_pieces(&input, t0, t0 + 0.05, &tps);
    }

    #[test]
    fn the_search_counts_its_evaluations_before_it_runs() {
        let three = VoltageInput::Sines { offset: 0.0, components: many_sines(3, 100.0) };
        let fmax = many_sines(3, 100.0).iter().map(|c| c.frequency).fold(0.0, f64::max);
        let samples = (fmax * SEARCH_PER_PERIOD).ceil() as u64;
        assert_eq!(three.search_evaluations(1.0, 10), Some((samples + 10) * 2 * 3));
        assert_eq!(VoltageInput::sine(1.0, 50.0).search_evaluations(1e300, 10), Some(0));
        assert_eq!(three.search_evaluations(1e300, 10), None);
        assert_eq!(three.search_evaluations(f64::NAN, 10), None);
    }

    fn all_smooth_inputs() -> Vec<VoltageInput> {
        vec![
            VoltageInput::Sine { amplitude: 48.0, frequency: 30.0, offset: 5.0, phase: 0.3 },
            VoltageInput::Sines {
                offset: 1.0,
                components: vec![
                    SineComponent { amplitude: 10.0, frequency: 60.0, phase: 0.0 },
                    SineComponent { amplitude: 4.0, frequency: 180.0, phase: 1.0 },
                    SineComponent { amplitude: 2.0, frequency: 300.0, phase: -0.4 },
                ],
            },
            VoltageInput::Chirp {
                amplitude: 20.0,
                f_start: 5.0,
                f_end: 80.0,
                duration: 0.5,
                sweep: ChirpLaw::Linear,
                offset: 0.0,
            },
            VoltageInput::Chirp {
                amplitude: 20.0,
                f_start: 80.0,
                f_end: 5.0,
                duration: 0.5,
                sweep: ChirpLaw::Log,
                offset: -3.0,
            },
        ]
    }

    #[test]
    fn rate_is_the_derivative_of_value() {
        let mut inputs = all_smooth_inputs();
        inputs.push(VoltageInput::Step { time: 0.1, from: 1.0, to: 5.0, rise_time: 0.05 });
        inputs.push(VoltageInput::from_samples("mem", vec![0.0, 0.1, 0.3], vec![0.0, 2.0, -1.0]).unwrap());
        for input in &inputs {
            let grid: Vec<f64> = (1..200).map(|k| k as f64 * 0.00371 + 0.0001).collect();
            let rate_scale = grid.iter().map(|&t| input.rate(t).abs()).fold(1.0, f64::max);
            let accel_scale = grid.iter().map(|&t| input.accel(t).abs()).fold(1.0, f64::max);
            let h = 1e-7;
            for &t in &grid {
                // Skip the few points within h of a kink of a piecewise-linear input.
                let kink = input.breakpoints(t - h, t + h).iter().any(|&b| {
                    !matches!(input, VoltageInput::Sine { .. } | VoltageInput::Sines { .. }) && (b - t).abs() < h
                });
                if kink {
                    continue;
                }
                let fd = (input.value(t + h) - input.value(t - h)) / (2.0 * h);
                let r = input.rate(t);
                assert!((fd - r).abs() <= 1e-6 * rate_scale, "{input:?} t={t}: {fd} vs {r}");
                assert_eq!(input.rate_left(t), r);
                if !matches!(input, VoltageInput::Step { .. } | VoltageInput::Series { .. }) {
                    let fa = (input.rate(t + h) - input.rate(t - h)) / (2.0 * h);
                    let a = input.accel(t);
                    assert!((fa - a).abs() <= 1e-6 * accel_scale, "{input:?} t={t}: {fa} vs {a}");
                }
            }
        }
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-12 * y.abs();
        let ser = &inputs[inputs.len() - 1];
        assert!(close(ser.rate_left(0.1), 20.0) && close(ser.rate(0.1), -15.0));
        let ramp = &inputs[inputs.len() - 2];
        let end = 0.1 + 0.05;
        assert!(close(ramp.rate_left(end), 80.0) && ramp.rate(end) == 0.0);
        assert!(ramp.rate_left(0.1) == 0.0 && close(ramp.rate(0.1), 80.0));
    }

    #[test]
    fn chirp_frequency_law_and_continuation() {
        for sweep in [ChirpLaw::Linear, ChirpLaw::Log] {
            let c =
                VoltageInput::Chirp { amplitude: 1.0, f_start: 10.0, f_end: 40.0, duration: 2.0, sweep, offset: 0.0 };
            let (_, w0, _) = VoltageInput::chirp_phase(10.0, 40.0, 2.0, sweep, 1e-12);
            let (_, w1, _) = VoltageInput::chirp_phase(10.0, 40.0, 2.0, sweep, 2.0);
            let (_, w2, _) = VoltageInput::chirp_phase(10.0, 40.0, 2.0, sweep, 7.0);
            assert!(
                (w0 / TAU - 10.0).abs() < 1e-9 && (w1 / TAU - 40.0).abs() < 1e-9 && (w2 / TAU - 40.0).abs() < 1e-12
            );
            let mid = VoltageInput::chirp_phase(10.0, 40.0, 2.0, sweep, 1.0).1 / TAU;
            let expect = if sweep == ChirpLaw::Linear { 25.0 } else { 20.0 };
            assert!((mid - expect).abs() < 1e-9, "{mid}");
            // phase continuity across t = duration and t = 0
            for tk in [0.0, 2.0] {
                let d = c.value(tk + 1e-9) - c.value(tk - 1e-9);
                assert!(d.abs() < 1e-6, "{d}");
            }
        }
    }

    #[test]
    fn periods_and_frequencies() {
        let s = |fs: &[f64]| VoltageInput::Sines {
            offset: 0.0,
            components: fs.iter().map(|&f| SineComponent { amplitude: 1.0, frequency: f, phase: 0.0 }).collect(),
        };
        assert_eq!(VoltageInput::sine(1.0, 30.0).period(), Some(1.0 / 30.0));
        assert_eq!(s(&[60.0, 180.0]).fundamental_frequency(), Some(60.0));
        assert_eq!(s(&[180.0, 60.0, 300.0]).fundamental_frequency(), Some(60.0));
        assert_eq!(s(&[30.0, 45.0]).fundamental_frequency(), Some(15.0));
        assert_eq!(s(&[6.0, 10.0]).fundamental_frequency(), Some(2.0));
        let f = s(&[0.1, 0.3, 0.7]).fundamental_frequency().unwrap();
        assert!((f - 0.1).abs() < 1e-15);
        assert_eq!(s(&[1.0, 2f64.sqrt()]).period(), None);
        assert_eq!(s(&[1.0, 1.0 + 3e-9]).period(), None);
        assert!(s(&[1.0, 1.0 + 1e-10]).period().is_some());
        assert_eq!(s(&[60.0, 180.0]).highest_frequency(), Some(180.0));
        let chirp = &all_smooth_inputs()[2];
        assert_eq!(chirp.period(), None);
        assert_eq!(chirp.highest_frequency(), Some(80.0));
        assert_eq!(VoltageInput::Step { time: 0.0, from: 0.0, to: 1.0, rise_time: 0.0 }.highest_frequency(), None);
        assert_eq!(
            VoltageInput::Step { time: 0.0, from: 0.0, to: 1.0, rise_time: 0.01 }.highest_frequency(),
            Some(50.0)
        );
        let series = VoltageInput::from_samples("mem", vec![0.0, 0.001, 0.002, 0.003], vec![0.0; 4]).unwrap();
        assert!((series.highest_frequency().unwrap() - 500.0).abs() < 1e-9);
        // a sum of sines is periodic with the period found
        let x = s(&[30.0, 45.0, 75.0]);
        let p = x.period().unwrap();
        for k in 0..50 {
            let t = 0.0123 * k as f64;
            assert!((x.value(t + p) - x.value(t)).abs() < 1e-9);
        }
    }

    /// Checks that `tps` are exactly the direction changes: V̇ ≈ 0 there, and V is monotone
    /// between consecutive points (dense check).
    fn assert_monotone_pieces(input: &VoltageInput, t0: f64, t1: f64, tps: &[f64]) {
        let mut edges = vec![t0];
        edges.extend_from_slice(tps);
        edges.push(t1);
        for w in edges.windows(2) {
            let (a, b) = (w[0], w[1]);
            let n = 400;
            let mut dir = 0i8;
            let mut prev = input.value(a);
            for k in 1..=n {
                let v = input.value(a + (b - a) * k as f64 / n as f64);
                let s = sgn(v - prev);
                // tolerate rounding-level wiggles
                if (v - prev).abs() > 1e-9 {
                    assert!(dir == 0 || s == dir, "{input:?}: not monotone in [{a}, {b}]");
                    dir = s;
                }
                prev = v;
            }
        }
        for &t in tps {
            let scale = (0..1000).map(|k| input.rate(t0 + (t1 - t0) * k as f64 / 1000.0).abs()).fold(1.0, f64::max);
            assert!(input.rate(t).abs() <= 1e-10 * scale, "{input:?} at {t}: rate {}", input.rate(t));
        }
    }

    #[test]
    fn turning_points_split_into_monotone_pieces() {
        // sine: analytic, count per period = 2
        let s = VoltageInput::Sine { amplitude: 3.0, frequency: 7.0, offset: 0.0, phase: 0.4 };
        let tps = s.turning_points(0.0, 1.0);
        assert_eq!(tps.len(), 14);
        assert_monotone_pieces(&s, 0.0, 1.0, &tps);
        for &t in &tps {
            assert!((s.value(t).abs() - 3.0).abs() < 1e-13);
        }
        // open interval: an endpoint on a turning point is not returned
        let t_first = tps[0];
        assert_eq!(s.turning_points(t_first, tps[1] + 1e-9).len(), 1);
        for input in all_smooth_inputs().iter().skip(1) {
            let tps = input.turning_points(0.0, 0.8);
            assert!(tps.windows(2).all(|w| w[0] < w[1]));
            assert_monotone_pieces(input, 0.0, 0.8, &tps);
        }
        // two close extrema inside one sampling interval: V̇ = cos(ωt) + c near its minimum.
        // With c slightly below 1, V̇ dips below zero only briefly around t = 1/(2f).
        let f = 1.0;
        let c = 1.0 - 1e-4;
        let slow = 1e-3;
        let comps = vec![
            SineComponent { amplitude: 1.0 / (TAU * f), frequency: f, phase: 0.0 },
            // rate of this one ≈ c around t = 0.5
            SineComponent { amplitude: c / (TAU * slow), frequency: slow, phase: -TAU * slow * 0.5 },
        ];
        let pair = VoltageInput::Sines { offset: 0.0, components: comps };
        let tps = pair.turning_points(0.4, 0.6);
        assert_eq!(tps.len(), 2, "{tps:?}");
        assert!(tps[1] - tps[0] < 1.0 / 32.0, "the pair lies inside one sampling interval");
        assert_monotone_pieces(&pair, 0.4, 0.6, &tps);
        // step jump and series knots
        let st = VoltageInput::Step { time: 0.5, from: 0.0, to: 2.0, rise_time: 0.0 };
        assert_eq!(st.turning_points(0.0, 1.0), vec![0.5]);
        assert!(st.turning_points(0.5, 1.0).is_empty());
        assert_eq!(st.value(0.5), 2.0);
        assert_eq!(st.value_left(0.5), 0.0);
        let ramp = VoltageInput::Step { time: 0.5, from: 0.0, to: 2.0, rise_time: 0.1 };
        assert!(ramp.turning_points(0.0, 1.0).is_empty());
        assert_eq!(ramp.breakpoints(0.0, 1.0), vec![0.5, 0.6]);
        let ser =
            VoltageInput::from_samples("mem", vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0], vec![0.0, 1.0, 3.0, 3.0, -1.0, 0.0])
                .unwrap();
        assert_eq!(ser.turning_points(-1.0, 10.0), vec![0.0, 2.0, 3.0, 4.0, 5.0]);
        assert_eq!(ser.breakpoints(0.5, 4.5), vec![1.0, 2.0, 3.0, 4.0]);
        assert_eq!(ser.value(2.5), 3.0);
        assert_eq!(ser.value(3.5), 1.0);
        assert_eq!(ser.value(-1.0), 0.0);
        assert_eq!(ser.value(9.0), 0.0);
        assert_eq!(ser.rate(4.2), 1.0);
    }
}
