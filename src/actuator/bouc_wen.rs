//! Bouc–Wen hysteresis of a piezo stack (spec §4), integrated exactly in voltage space.
//!
//! The free stroke of the stack is `δ = d_p·V − h`, with the hysteretic displacement `h`
//! obeying (n = 1)
//!
//! ```text
//! ḣ = α·d_p·V̇ − β·|V̇|·h − γ·V̇·|h|
//! ```
//!
//! Every term is proportional to `V̇` or `|V̇|`, so `h` is a function of the voltage *path*,
//! not of time: dividing by `V̇` on a stretch where the voltage moves in one direction
//! (`s = sign V̇` fixed) gives
//!
//! ```text
//! dh/dV = a − β·s·h − γ·|h|,        a = α·d_p.
//! ```
//!
//! While in addition the sign `σ` of `h` is fixed, `|h| = σ·h` and this is the *linear*
//! equation `dh/dV = a − κ·h` with `κ = β·s + γ·σ`, solved in closed form:
//!
//! ```text
//! h(V₀ + ΔV) = h₀ + (a − κ·h₀)·φ(κ, ΔV),     φ(κ, ΔV) = (1 − e^(−κ·ΔV))/κ   (= ΔV if κ = 0)
//! ```
//!
//! `φ` is evaluated as `−expm1(−κ·ΔV)/κ`, which has no cancellation when `κ·ΔV` is tiny.
//! For class-I parameters `κ·ΔV ≥ 0` on every piece, so the exponential never grows.
//! At `h = 0` the slope is `a > 0`, so `h` can change sign only in the direction of the
//! voltage move and at most once per monotone move; [`BoucWen::advance`] finds that voltage
//! in closed form (`ΔV_c = −ln1p(−κ·q)/κ`, `q = −h₀/(a − κ·h₀)`) and continues from `h = 0`
//! with `κ = (β + γ)·s`.
//!
//! A whole history is then exact up to rounding: split the time axis at the turning points
//! of the input ([`VoltageInput::turning_points`]) so every piece is monotone in V, and
//! apply the closed form from the voltage at one end to the voltage at the other. The
//! result does not depend on the time step nor on how fast the voltage moves
//! (rate independence), and a jump in V is handled like any other monotone move.
//!
//! [`BoucWen::rk4_reference`] integrates the time ODE instead, with classic RK4, as an
//! independent check for the tests.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::signal::voltage::VoltageInput;

/// Bouc–Wen parameters of a stack (n = 1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoucWen {
    /// Effective piezo coefficient d_p (m/V), > 0.
    pub d_p: f64,
    /// Shape constant α (–), > 0.
    pub alpha: f64,
    /// Shape constant β (1/V).
    pub beta: f64,
    /// Shape constant γ (1/V).
    pub gamma: f64,
}

impl Default for BoucWen {
    /// The spec §13 defaults for a 7×7×20 mm PZT-5 stack.
    fn default() -> Self {
        BoucWen { d_p: 1.3e-7, alpha: 0.3, beta: 0.02, gamma: 0.005 }
    }
}

/// One period of the periodic state, from [`BoucWen::periodic_cycle_from`].
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicCycle {
    /// The period the cycle repeats with (s).
    pub period: f64,
    /// `samples_per_period + 1` times covering the last period computed, both ends included
    /// (`t[N] = t[0] + period`).
    pub t: Vec<f64>,
    /// Voltage at `t` (V).
    pub v: Vec<f64>,
    /// Hysteretic displacement at `t` (m).
    pub h: Vec<f64>,
    /// Free stroke `δ = d_p·V − h` at `t` (m).
    pub stroke: Vec<f64>,
    /// How many periods were run, counting the returned one.
    pub periods: usize,
    /// `|h(end) − h(start)|` of the returned period, relative to the bound on |h|
    /// ([`BoucWen::bound`] of the starting h).
    pub change: f64,
    /// Whether `change ≤ tol`.
    pub converged: bool,
}

/// The hysteresis loop of a cycle: voltage (V) and free stroke δ (m) at the cycle's samples.
pub fn loop_points(cycle: &PeriodicCycle) -> (Vec<f64>, Vec<f64>) {
    (cycle.v.clone(), cycle.stroke.clone())
}

/// Width of the outer hysteresis loop (m): the largest difference of the free stroke between
/// the rising branch (from the sample of lowest voltage to that of highest voltage) and the
/// falling branch (back), at equal voltage, over 1000 voltage levels. On each branch the
/// stroke at a level is interpolated on the first sample segment that reaches the level, so
/// this is meant for inputs with one minimum and one maximum per period. 0 for a constant
/// voltage.
pub fn loop_width(cycle: &PeriodicCycle) -> f64 {
    let n = cycle.v.len().saturating_sub(1); // the last sample repeats the first
    if n < 2 {
        return 0.0;
    }
    let v = &cycle.v[..n];
    let d = &cycle.stroke[..n];
    let argmin = (0..n).min_by(|&i, &j| v[i].total_cmp(&v[j])).unwrap_or(0);
    let argmax = (0..n).max_by(|&i, &j| v[i].total_cmp(&v[j])).unwrap_or(0);
    let (vmin, vmax) = (v[argmin], v[argmax]);
    if vmax <= vmin {
        return 0.0;
    }
    let branch = |from: usize, to: usize| -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        let mut i = from;
        loop {
            out.push((v[i], d[i]));
            if i == to {
                break;
            }
            i = (i + 1) % n;
        }
        out
    };
    let at = |b: &[(f64, f64)], level: f64| -> Option<f64> {
        b.windows(2).find_map(|w| {
            let ((v0, d0), (v1, d1)) = (w[0], w[1]);
            let (lo, hi) = if v0 <= v1 { (v0, v1) } else { (v1, v0) };
            (lo <= level && level <= hi && hi > lo).then(|| d0 + (d1 - d0) * (level - v0) / (v1 - v0))
        })
    };
    let up = branch(argmin, argmax);
    let down = branch(argmax, argmin);
    let levels = 1000;
    (1..levels)
        .map(|k| vmin + (vmax - vmin) * (k as f64 / levels as f64))
        .filter_map(|level| Some((at(&down, level)? - at(&up, level)?).abs()))
        .fold(0.0, f64::max)
}

/// Compensated (Neumaier) running sum for `h`: a long history adds thousands of small
/// increments, and plain summation would let rounding errors grow with their number.
struct Accumulator {
    sum: f64,
    comp: f64,
}

impl Accumulator {
    fn new(h: f64) -> Self {
        Accumulator { sum: h, comp: 0.0 }
    }
    fn add(&mut self, x: f64) {
        let t = self.sum + x;
        if self.sum.abs() >= x.abs() {
            self.comp += (self.sum - t) + x;
        } else {
            self.comp += (x - t) + self.sum;
        }
        self.sum = t;
    }
    fn value(&self) -> f64 {
        self.sum + self.comp
    }
}

/// `φ(κ, Δ) = (1 − e^(−κΔ))/κ`, `Δ` when `κ = 0`, without cancellation for small `κΔ`.
fn phi(kappa: f64, dv: f64) -> f64 {
    if kappa == 0.0 {
        dv
    } else {
        -(-kappa * dv).exp_m1() / kappa
    }
}

impl BoucWen {
    /// Checks the class-I constraints (bounded, passive hysteresis; Ikhouane–Rodellar):
    /// all finite, `d_p > 0`, `α > 0`, `β + γ > 0`, `β − γ ≥ 0`. The error names the
    /// parameter and the violated constraint; the caller names the file and table
    /// ([`Error::in_table`]). A violation of `β + γ > 0` names `beta` when `β ≤ 0` (the two constraints
    /// together need `β > 0`), otherwise `gamma`; a violation of `β − γ ≥ 0` names `gamma`.
    pub fn validate(&self) -> Result<()> {
        let f = |name: &str| name.to_string();
        for (name, x) in [("d_p", self.d_p), ("alpha", self.alpha), ("beta", self.beta), ("gamma", self.gamma)] {
            if !x.is_finite() {
                return Err(Error::argument(f(name), format!("must be a finite number, got {x}")));
            }
        }
        if self.d_p <= 0.0 {
            return Err(Error::argument(
                f("d_p"),
                format!("violates d_p > 0 (Bouc–Wen class I; m/V): got {}", self.d_p),
            ));
        }
        if self.alpha <= 0.0 {
            return Err(Error::argument(
                f("alpha"),
                format!("violates alpha > 0 (Bouc–Wen class I): got {}", self.alpha),
            ));
        }
        if self.beta + self.gamma <= 0.0 {
            let name = if self.beta <= 0.0 { "beta" } else { "gamma" };
            return Err(Error::argument(
                f(name),
                format!(
                    "violates beta + gamma > 0 (Bouc–Wen class I, bounded hysteresis): beta = {}, gamma = {}",
                    self.beta, self.gamma
                ),
            ));
        }
        if self.beta - self.gamma < 0.0 {
            return Err(Error::argument(
                f("gamma"),
                format!(
                    "violates beta - gamma >= 0 (Bouc–Wen class I, passive hysteresis): beta = {}, gamma = {}",
                    self.beta, self.gamma
                ),
            ));
        }
        Ok(())
    }

    /// The class-I bound on |h| for a history starting at `h0`: `max(|h0|, α·d_p/(β + γ))` (m).
    pub fn bound(&self, h0: f64) -> f64 {
        h0.abs().max(self.alpha * self.d_p / (self.beta + self.gamma))
    }

    /// Free stroke `δ = d_p·V − h` (m).
    pub fn stroke(&self, v: f64, h: f64) -> f64 {
        self.d_p * v - h
    }

    /// `h` after the voltage moves monotonically from `v_from` to `v_to`, starting at `h`:
    /// the exact solution of `dh/dV = α·d_p − β·s·h − γ·|h|`, `s = sign(v_to − v_from)`
    /// (see the module docs). Exact up to rounding and independent of how fast the move is,
    /// so it also serves a voltage jump. `advance(advance(h, a, b), b, c) = advance(h, a, c)`
    /// whenever `a ≤ b ≤ c` or `a ≥ b ≥ c`.
    ///
    /// Assumes class-I parameters ([`validate`](Self::validate)); otherwise the exponential
    /// may overflow.
    pub fn advance(&self, h: f64, v_from: f64, v_to: f64) -> f64 {
        h + self.increment(h, v_from, v_to)
    }

    /// The change of `h` over the monotone move (what [`advance`](Self::advance) adds to `h`),
    /// kept separate so that long histories can sum the increments with compensation.
    fn increment(&self, h: f64, v_from: f64, v_to: f64) -> f64 {
        let dv = v_to - v_from;
        if dv == 0.0 {
            return 0.0;
        }
        let a = self.alpha * self.d_p;
        let s = dv.signum();
        // At h = 0 the slope dh/dV is a > 0: h leaves zero in the direction of the move.
        let sigma = if h != 0.0 { h.signum() } else { s };
        let kappa = self.beta * s + self.gamma * sigma;
        if sigma == s {
            // h moves away from zero or relaxes towards a/κ on its own side: no sign change.
            return (a - kappa * h) * phi(kappa, dv);
        }
        // h has the sign opposite to the move and heads for zero; a − κh > 0 here.
        let q = -h / (a - kappa * h);
        let dv_zero = if kappa == 0.0 { q } else { -(-kappa * q).ln_1p() / kappa };
        if dv_zero.abs() >= dv.abs() {
            return (a - kappa * h) * phi(kappa, dv);
        }
        // Reaches zero at v_from + dv_zero, then grows on the other side.
        a * phi((self.beta + self.gamma) * s, dv - dv_zero) - h
    }

    /// `h` at `t1` from `h` at `t0` (t0 ≤ t1) under `input`: [`advance`](Self::advance) over
    /// the monotone pieces between the input's turning points. What a time stepper calls once
    /// per step.
    pub fn advance_time(&self, input: &VoltageInput, h: f64, t0: f64, t1: f64) -> f64 {
        let turns: Vec<f64> = input.turning_points(t0, t1).into_iter().map(|t| input.value(t)).collect();
        self.advance_through(h, input.value(t0), &turns, input.value(t1))
    }

    /// `h` after the voltage runs from `v0` through `turns` (its values at its turning
    /// points, in order) to `v1`: [`advance`](Self::advance) over each monotone piece.
    fn advance_through(&self, h: f64, v0: f64, turns: &[f64], v1: f64) -> f64 {
        let mut acc = Accumulator::new(h);
        let mut v = v0;
        for &vt in turns.iter().chain(std::iter::once(&v1)) {
            acc.add(self.increment(acc.value(), v, vt));
            v = vt;
        }
        acc.value()
    }

    /// `h` at each of `times` (nondecreasing), starting from `h0` at `times[0]`: every
    /// interval is split at the input's turning points and each monotone piece is advanced
    /// exactly. The time grid only chooses where `h` is reported; it has no effect on the
    /// accuracy.
    ///
    /// # Panics
    /// If `times` decreases somewhere.
    pub fn history(&self, input: &VoltageInput, times: &[f64], h0: f64) -> Vec<f64> {
        let (mut h, mut v) = (Vec::new(), Vec::new());
        self.history_into(input, times, h0, &mut h, &mut v);
        h
    }

    /// [`history`](Self::history) into `h`, and the input voltage at each of `times` into
    /// `v` (both cleared first): the voltages are evaluated anyway, and a transient run needs
    /// them too.
    ///
    /// # Panics
    /// If `times` decreases somewhere.
    pub fn history_into(&self, input: &VoltageInput, times: &[f64], h0: f64, h: &mut Vec<f64>, v: &mut Vec<f64>) {
        h.clear();
        v.clear();
        let Some((&first, rest)) = times.split_first() else {
            return;
        };
        assert!(times.windows(2).all(|w| w[0] <= w[1]), "BoucWen::history: times must be nondecreasing");
        let last = *times.last().unwrap_or(&first);
        let tps = input.turning_points(first, last);
        let mut acc = Accumulator::new(h0);
        let mut v_now = input.value(first);
        h.push(h0);
        v.push(v_now);
        let mut k = 0;
        for &t in rest {
            while k < tps.len() && tps[k] < t {
                let vt = input.value(tps[k]);
                acc.add(self.increment(acc.value(), v_now, vt));
                v_now = vt;
                k += 1;
            }
            let vt = input.value(t);
            acc.add(self.increment(acc.value(), v_now, vt));
            v_now = vt;
            h.push(acc.value());
            v.push(vt);
        }
    }

    /// The periodic state under a periodic input, from `h = 0` at t = 0 over the input's own
    /// period: [`periodic_cycle_from`](Self::periodic_cycle_from) with `h0 = 0` and
    /// `period` = [`VoltageInput::period`].
    ///
    /// Errors ([`Error::Input`], file `<case>`) if the input has no period or the arguments
    /// are out of range.
    pub fn periodic_cycle(
        &self,
        input: &VoltageInput,
        samples_per_period: usize,
        tol: f64,
        max_periods: usize,
    ) -> Result<PeriodicCycle> {
        let Some(period) = input.period() else {
            return Err(Error::argument(
                "voltage",
                "a periodic cycle needs a periodic voltage (a sine, or sines with commensurate frequencies)",
            ));
        };
        self.periodic_cycle_from(input, 0.0, period, samples_per_period, tol, max_periods)
    }

    /// The periodic state under `input`, which repeats with `period` (s; the input's own
    /// period or a multiple of it, such as the common period of several drives), starting
    /// from `h0` at t = 0: the one periodic cycle every analysis and the identification use.
    ///
    /// Whole periods are run until `h` at the end of a period repeats its start to `tol`
    /// relative to [`bound`](Self::bound)`(h0)`, or `max_periods` have run; that last period
    /// is sampled `samples_per_period` (≥ 2) times and returned (see [`PeriodicCycle`]; check
    /// `converged`). `h` at the end of a period does not depend on samples in between (the
    /// solution is exact over every monotone piece of the voltage), so the settling periods
    /// advance from turning point to turning point, a few closed-form steps each, and only
    /// the returned period is split at its samples as well (which gives the same `h` up to
    /// rounding).
    pub fn periodic_cycle_from(
        &self,
        input: &VoltageInput,
        h0: f64,
        period: f64,
        samples_per_period: usize,
        tol: f64,
        max_periods: usize,
    ) -> Result<PeriodicCycle> {
        if samples_per_period < 2 {
            return Err(Error::argument("samples_per_period", format!("must be ≥ 2, got {samples_per_period}")));
        }
        if max_periods == 0 {
            return Err(Error::argument("max_periods", "must be ≥ 1"));
        }
        if !(tol.is_finite() && tol >= 0.0) {
            return Err(Error::argument("tol", format!("must be a finite number ≥ 0, got {tol}")));
        }
        let scale = self.bound(h0).max(f64::MIN_POSITIVE);
        // The input repeats with `period`: the turning points of one period serve every
        // settling period, so the search over the input runs once, not once a period.
        let turns: Vec<f64> = input.turning_points(0.0, period).into_iter().map(|t| input.value(t)).collect();
        let (v_start, v_end) = (input.value(0.0), input.value(period));
        // Period p runs from p·T to (p + 1)·T, starting at h_start.
        let (mut p, mut h_start) = (0, h0);
        let change = loop {
            let h_end = self.advance_through(h_start, v_start, &turns, v_end);
            let change = (h_end - h_start).abs() / scale;
            if change <= tol || p + 1 == max_periods {
                break change;
            }
            h_start = h_end;
            p += 1;
        };
        let n = samples_per_period;
        let t: Vec<f64> = (0..=n).map(|j| (p as f64 + j as f64 / n as f64) * period).collect();
        let (mut h, mut v) = (Vec::new(), Vec::new());
        self.history_into(input, &t, h_start, &mut h, &mut v);
        let stroke = v.iter().zip(&h).map(|(&vi, &hi)| self.stroke(vi, hi)).collect();
        Ok(PeriodicCycle { period, t, v, h, stroke, periods: p + 1, change, converged: change <= tol })
    }

    /// Independent reference for the tests: classic RK4 on the time ODE
    /// `ḣ = α·d_p·V̇ − β·|V̇|·h − γ·V̇·|h|` with the exact V̇ of the input.
    ///
    /// Each interval between samples is cut at the input's [`breakpoints`](VoltageInput::breakpoints)
    /// (turning points and kinks, where the right-hand side is not smooth in t) and each
    /// piece gets `substeps` equal RK4 steps. Inside a piece the smooth branch of `|h|` for the
    /// current sign is used; a step that changes the sign of `h` is redone up to the zero of
    /// `h` (found by bisection on the step length) and continued from `h = 0` on the other
    /// branch. With that the method keeps its 4th order. A voltage jump (step with
    /// `rise_time = 0`) is crossed by the same RK4 in voltage (`dh/dV`, `substeps` steps).
    pub fn rk4_reference(&self, input: &VoltageInput, times: &[f64], h0: f64, substeps: usize) -> Vec<f64> {
        let n = substeps.max(1);
        let mut out = Vec::with_capacity(times.len());
        if times.is_empty() {
            return out;
        }
        let mut h = h0;
        out.push(h);
        for w in times.windows(2) {
            let (ta, tb) = (w[0], w[1]);
            let mut edges = vec![ta];
            edges.extend(input.breakpoints(ta, tb));
            edges.push(tb);
            for e in edges.windows(2) {
                let (x0, x1) = (e[0], e[1]);
                if x1 > x0 {
                    let s = input.rate(0.5 * (x0 + x1)).signum();
                    if input.rate(0.5 * (x0 + x1)) != 0.0 {
                        // At the piece's right end use the left limit of V̇ (a series knot
                        // or a ramp end is a kink).
                        let rate = |t: f64| if t >= x1 { input.rate_left(x1) } else { input.rate(t) };
                        h = self.rk4_piece(h, x0, x1, n, s, rate);
                    }
                }
                let (vl, vr) = (input.value_left(x1), input.value(x1));
                if vl != vr {
                    h = self.rk4_piece(h, vl, vr, n, (vr - vl).signum(), |_| 1.0);
                }
            }
            out.push(h);
        }
        out
    }

    /// RK4 over `[x0, x1]` in `n` steps for `dh/dx = rate(x)·(a − (β·s + γ·σ)·h)`, `s` the
    /// sign of the voltage motion on the piece, `σ` the sign of `h` (with zero crossings
    /// located, see [`rk4_reference`](Self::rk4_reference)).
    fn rk4_piece(&self, h: f64, x0: f64, x1: f64, n: usize, s: f64, rate: impl Fn(f64) -> f64) -> f64 {
        let a = self.alpha * self.d_p;
        let f = |x: f64, h: f64, sigma: f64| rate(x) * (a - (self.beta * s + self.gamma * sigma) * h);
        let step = |x: f64, h: f64, dx: f64, sigma: f64| {
            let k1 = f(x, h, sigma);
            let k2 = f(x + 0.5 * dx, h + 0.5 * dx * k1, sigma);
            let k3 = f(x + 0.5 * dx, h + 0.5 * dx * k2, sigma);
            let k4 = f(x + dx, h + dx * k3, sigma);
            h + dx / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        };
        let mut h = h;
        // h = 0 leaves zero in the direction of the motion, so it takes the branch σ = s.
        let mut sigma = if h != 0.0 { h.signum() } else { s };
        let node = |i: usize| if i == n { x1 } else { x0 + (x1 - x0) * (i as f64 / n as f64) };
        for i in 0..n {
            let (xa, xb) = (node(i), node(i + 1));
            let hn = step(xa, h, xb - xa, sigma);
            if hn * sigma < 0.0 {
                // Zero of h inside the step: bisect the step fraction θ with h(θ) = 0.
                let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    if step(xa, h, mid * (xb - xa), sigma) * sigma > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let xc = xa + 0.5 * (lo + hi) * (xb - xa);
                sigma = s;
                h = step(xc, 0.0, xb - xc, sigma);
            } else {
                h = hn;
            }
        }
        h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signal::voltage::{ChirpLaw, SineComponent};
    use std::f64::consts::TAU;

    /// Deterministic 64-bit LCG (Knuth's MMIX constants); `next` gives a uniform in [0, 1).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.next()
        }
    }

    fn linspace(t0: f64, t1: f64, n: usize) -> Vec<f64> {
        (0..=n).map(|i| t0 + (t1 - t0) * (i as f64 / n as f64)).collect()
    }

    fn max_rel_diff(x: &[f64], y: &[f64], scale: f64) -> f64 {
        assert_eq!(x.len(), y.len());
        x.iter().zip(y).map(|(a, b)| (a - b).abs() / scale).fold(0.0, f64::max)
    }

    fn sine(amplitude: f64, frequency: f64, offset: f64) -> VoltageInput {
        VoltageInput::Sine { amplitude, frequency, offset, phase: 0.0 }
    }

    fn chirp(sweep: ChirpLaw) -> VoltageInput {
        VoltageInput::Chirp { amplitude: 30.0, f_start: 5.0, f_end: 60.0, duration: 0.4, sweep, offset: 3.0 }
    }

    fn sines() -> VoltageInput {
        VoltageInput::Sines {
            offset: 2.0,
            components: vec![
                SineComponent { amplitude: 40.0, frequency: 30.0, phase: 0.0 },
                SineComponent { amplitude: 15.0, frequency: 90.0, phase: 0.7 },
                SineComponent { amplitude: 6.0, frequency: 150.0, phase: -1.1 },
            ],
        }
    }

    #[test]
    fn linear_limit_is_exact() {
        let bw = BoucWen { d_p: 1.3e-7, alpha: 0.3, beta: 0.0, gamma: 0.0 };
        let a = bw.alpha * bw.d_p;
        let times = linspace(0.0, 0.6, 600);
        for input in [sine(48.0, 30.0, 4.0), chirp(ChirpLaw::Linear), chirp(ChirpLaw::Log)] {
            let h = bw.history(&input, &times, 0.0);
            let v0 = input.value(0.0);
            let exact: Vec<f64> = times.iter().map(|&t| a * (input.value(t) - v0)).collect();
            let scale = exact.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            let err = max_rel_diff(&h, &exact, scale);
            println!("beta = gamma = 0, {input:?}: max error {err:.2e} of max |h|");
            assert!(err <= 1e-15, "{err:e}");
        }
    }

    #[test]
    fn advance_composes_and_matches_closed_forms() {
        let bw = BoucWen::default();
        let a = bw.alpha * bw.d_p;
        let hb = bw.bound(0.0);
        // from h = 0 going up: h = a/(β+γ)·(1 − e^{−(β+γ)ΔV})
        let k = bw.beta + bw.gamma;
        let h = bw.advance(0.0, -3.0, 50.0);
        let exact = a / k * (1.0 - (-k * 53.0f64).exp());
        assert!((h - exact).abs() <= 1e-15 * hb, "{h} vs {exact}");
        // splitting a monotone move anywhere changes nothing (includes the zero crossing)
        let mut rng = Lcg(7);
        for _ in 0..2000 {
            let h0 = rng.range(-2.0, 2.0) * hb;
            let (v0, v1, v2) = (rng.range(-60.0, 60.0), rng.range(-60.0, 60.0), rng.range(-60.0, 60.0));
            let mut v = [v0, v1, v2];
            v.sort_by(f64::total_cmp);
            if rng.next() < 0.5 {
                v.reverse();
            }
            let two = bw.advance(bw.advance(h0, v[0], v[1]), v[1], v[2]);
            let one = bw.advance(h0, v[0], v[2]);
            assert!((two - one).abs() <= 4e-15 * bw.bound(h0), "{h0} {v:?}: {two} vs {one}");
        }
        // tiny moves: first order, no cancellation
        let dv = 1e-12;
        let h0 = 0.3 * hb;
        let dh = bw.advance(h0, 1.0, 1.0 + dv) - h0;
        let slope = a - bw.beta * h0 - bw.gamma * h0.abs();
        assert!((dh / dv - slope).abs() <= 1e-3 * slope);
    }

    /// Exact vs RK4 for a list of inputs, and the convergence order of RK4.
    #[test]
    fn history_matches_rk4_at_fourth_order() {
        let bw = BoucWen::default();
        let scale = bw.bound(0.0);
        let series = {
            let t = linspace(0.0, 0.3, 37);
            let mut rng = Lcg(3);
            let v = t.iter().map(|_| rng.range(-40.0, 40.0)).collect();
            VoltageInput::from_samples("mem", t, v).unwrap()
        };
        let ramp = VoltageInput::Step { time: 0.05, from: -20.0, to: 45.0, rise_time: 0.02 };
        let jump = VoltageInput::Step { time: 0.05, from: -20.0, to: 45.0, rise_time: 0.0 };
        let cases = [
            ("sine", sine(48.0, 30.0, 0.0)),
            ("sines", sines()),
            ("chirp linear", chirp(ChirpLaw::Linear)),
            ("chirp log", chirp(ChirpLaw::Log)),
            ("series", series),
            ("ramp", ramp),
            ("jump", jump),
        ];
        for (name, input) in &cases {
            let times = linspace(0.0, 0.3, 60);
            let h0 = -0.4 * scale;
            let exact = bw.history(input, &times, h0);
            // The buffered form gives the same h and the input at each time (buffers reused).
            let (mut h, mut v) = (vec![9.0; 3], vec![9.0; 100]);
            bw.history_into(input, &times, h0, &mut h, &mut v);
            assert_eq!(h, exact, "{name}: history_into");
            assert!(v.len() == times.len() && times.iter().zip(&v).all(|(&t, &x)| x == input.value(t)), "{name}: v");
            let fine = bw.rk4_reference(input, &times, h0, 400);
            let err_fine = max_rel_diff(&exact, &fine, scale);
            let errs: Vec<f64> = [2usize, 4, 8, 16]
                .iter()
                .map(|&n| max_rel_diff(&exact, &bw.rk4_reference(input, &times, h0, n), scale))
                .collect();
            let orders: Vec<f64> = errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
            let errs_s: Vec<String> = errs.iter().map(|e| format!("{e:.2e}")).collect();
            println!("{name:13}: |exact - rk4(400)| = {err_fine:.1e}; rk4 errors (2,4,8,16 substeps) {errs_s:?}; orders {orders:.2?}");
            assert!(err_fine <= 1e-9, "{name}: {err_fine:e}");
            // The two finer doublings (4 -> 8 -> 16 substeps), errors far above rounding.
            assert!(errs[3] > 1e-11, "{name}: errors too small to measure an order: {errs:?}");
            for &order in &orders[1..] {
                assert!((3.5..=4.5).contains(&order), "{name}: order {order} from {errs:?}");
            }
        }
    }

    #[test]
    fn never_exceeds_the_class_one_bound() {
        let mut rng = Lcg(12345);
        let mut worst = 0.0_f64;
        for trial in 0..200 {
            let beta = rng.range(0.001, 0.1);
            let gamma = rng.range(-0.99, 1.0) * beta;
            let bw = BoucWen { d_p: rng.range(1e-8, 1e-6), alpha: rng.range(0.05, 1.5), beta, gamma };
            bw.validate().unwrap();
            let hb = bw.bound(0.0);
            // start inside, at the bound, or beyond it (either sign)
            let h0 = match trial % 4 {
                0 => 0.0,
                1 => rng.range(-1.0, 1.0) * hb,
                2 => rng.range(1.0, 5.0) * hb,
                _ => -rng.range(1.0, 5.0) * hb,
            };
            let bound = bw.bound(h0);
            // a random voltage walk with random jumps, through advance directly
            let mut h = h0;
            let mut v = 0.0;
            for _ in 0..300 {
                let v1 = v + rng.range(-1.0, 1.0) * 10f64.powf(rng.range(-3.0, 3.0));
                h = bw.advance(h, v, v1);
                v = v1;
                worst = worst.max(h.abs() / bound - 1.0);
                assert!(h.abs() <= bound * (1.0 + 1e-14), "trial {trial}: |h| = {h} > {bound}");
            }
            // a random sum of sines through history
            let input = VoltageInput::Sines {
                offset: rng.range(-20.0, 20.0),
                components: (0..3)
                    .map(|_| SineComponent {
                        amplitude: rng.range(0.0, 80.0),
                        frequency: rng.range(1.0, 200.0),
                        phase: rng.range(0.0, TAU),
                    })
                    .collect(),
            };
            let times = linspace(0.0, 0.5, 500);
            for &h in &bw.history(&input, &times, h0) {
                worst = worst.max(h.abs() / bound - 1.0);
                assert!(h.abs() <= bound * (1.0 + 1e-14), "trial {trial}: |h| = {h} > {bound}");
            }
        }
        println!("largest |h|/bound - 1 over all trials: {worst:.1e}");
    }

    #[test]
    fn periodic_loop_is_rate_independent() {
        let bw = BoucWen::default();
        let slow = bw.periodic_cycle(&sine(48.0, 1.0, 0.0), 400, 1e-13, 200).unwrap();
        let fast = bw.periodic_cycle(&sine(48.0, 100.0, 0.0), 400, 1e-13, 200).unwrap();
        assert!(slow.converged && fast.converged);
        assert_eq!(slow.periods, fast.periods);
        let d = max_rel_diff(&slow.h, &fast.h, bw.bound(0.0));
        println!("1 Hz vs 100 Hz: max |Δh| = {d:.1e} of the bound, {} periods", slow.periods);
        assert!(d <= 1e-12, "{d:e}");
        // the loop closes
        assert!((slow.h[400] - slow.h[0]).abs() <= 1e-13 * bw.bound(0.0));
    }

    #[test]
    fn offset_does_not_change_the_periodic_h() {
        let bw = BoucWen::default();
        let base = bw.periodic_cycle(&sine(20.0, 30.0, 0.0), 300, 1e-13, 500).unwrap();
        let shifted = bw.periodic_cycle(&sine(20.0, 30.0, 35.0), 300, 1e-13, 500).unwrap();
        let scale = base.h.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let d = max_rel_diff(&base.h, &shifted.h, scale);
        println!("offset 35 V: max |Δh| = {d:.1e} of max |h|");
        assert!(d <= 1e-10, "{d:e}");
        // ... and shifts the stroke by d_p·ΔV
        for (a, b) in base.stroke.iter().zip(&shifted.stroke) {
            assert!((b - a - bw.d_p * 35.0).abs() <= 1e-10 * bw.d_p * 35.0);
        }
    }

    #[test]
    fn jumps_are_exact_monotone_moves() {
        let bw = BoucWen::default();
        let h0 = 0.3 * bw.bound(0.0);
        for (from, to) in [(1.0, 40.0), (40.0, -25.0)] {
            let input = VoltageInput::Step { time: 0.3, from, to, rise_time: 0.0 };
            let expect = bw.advance(h0, from, to);
            // jump strictly inside an interval, and exactly on a sample time
            for times in [linspace(0.0, 1.0, 7), linspace(0.0, 1.0, 10)] {
                let h = bw.history(&input, &times, h0);
                for (&t, &hi) in times.iter().zip(&h) {
                    let want = if t < 0.3 { h0 } else { expect };
                    assert_eq!(hi, want, "t = {t}");
                }
            }
            assert_eq!(bw.advance_time(&input, h0, 0.0, 1.0), expect);
            assert_ne!(expect, h0);
        }
    }

    #[test]
    fn class_one_violations_name_the_parameter() {
        let ok = BoucWen::default();
        ok.validate().unwrap();
        let cases = [
            (BoucWen { d_p: 0.0, ..ok }, "d_p", "d_p > 0"),
            (BoucWen { d_p: -1e-7, ..ok }, "d_p", "d_p > 0"),
            (BoucWen { alpha: 0.0, ..ok }, "alpha", "alpha > 0"),
            (BoucWen { beta: 0.0, gamma: 0.0, ..ok }, "beta", "beta + gamma > 0"),
            (BoucWen { beta: 0.01, gamma: -0.02, ..ok }, "gamma", "beta + gamma > 0"),
            (BoucWen { beta: 0.01, gamma: 0.02, ..ok }, "gamma", "beta - gamma >= 0"),
            (BoucWen { beta: f64::NAN, ..ok }, "beta", "finite"),
            (BoucWen { alpha: f64::INFINITY, ..ok }, "alpha", "finite"),
        ];
        for (bw, name, constraint) in cases {
            let e = bw.validate().unwrap_err().in_table("case.toml", "actuator[0].stack").to_string();
            assert!(
                e.starts_with(&format!("case.toml: field `actuator[0].stack.{name}`")) && e.contains(constraint),
                "{e}"
            );
        }
        // β = γ is allowed (β − γ ≥ 0)
        BoucWen { beta: 0.01, gamma: 0.01, ..ok }.validate().unwrap();
    }

    #[test]
    fn parses_with_unknown_fields_rejected() {
        let bw: BoucWen = toml::from_str("d_p = 1.3e-7\nalpha = 0.3\nbeta = 0.02\ngamma = 0.005\n").unwrap();
        assert_eq!(bw, BoucWen::default());
        let e =
            toml::from_str::<BoucWen>("d_p = 1.3e-7\nalpha = 0.3\nbeta = 0.02\ngamma = 0.005\nn = 1\n").unwrap_err();
        assert!(e.to_string().contains("unknown field `n`"), "{e}");
    }

    #[test]
    fn periodic_cycle_needs_a_period() {
        let bw = BoucWen::default();
        let e = bw.periodic_cycle(&chirp(ChirpLaw::Linear), 100, 1e-10, 10).unwrap_err().to_string();
        assert!(e.contains("periodic"), "{e}");
        assert!(bw.periodic_cycle(&sine(1.0, 1.0, 0.0), 1, 1e-10, 10).is_err());
        // not converged within the allowed periods: reported, not hidden
        let c = bw.periodic_cycle(&sine(1.0, 1.0, 0.0), 50, 0.0, 2).unwrap();
        assert!(!c.converged && c.periods == 2 && c.change > 0.0);
    }

    #[test]
    fn default_stack_loop_at_48_volts() {
        let bw = BoucWen::default();
        let input = sine(48.0, 30.0, 0.0);
        let cycle = bw.periodic_cycle(&input, 2000, 1e-12, 100).unwrap();
        assert!(cycle.converged);
        let (v, d) = loop_points(&cycle);
        let pp = |x: &[f64]| x.iter().copied().fold(f64::MIN, f64::max) - x.iter().copied().fold(f64::MAX, f64::min);
        let stroke_pp = pp(&d);
        let h_pp = pp(&cycle.h);
        let width = loop_width(&cycle);
        // loop area ∮ δ dV (trapezoid), V·m
        let area: f64 = v.windows(2).zip(d.windows(2)).map(|(vv, dd)| 0.5 * (dd[0] + dd[1]) * (vv[1] - vv[0])).sum();
        println!(
            "default stack, 48 V sine at 30 Hz: stroke p-p {:.3} um (linear d_p*96 V = {:.3} um), h p-p {:.3} um, \
             loop width {:.3} um = {:.1} % of the stroke, loop area {:.3e} V*m, {} periods to converge",
            stroke_pp * 1e6,
            bw.d_p * 96.0 * 1e6,
            h_pp * 1e6,
            width * 1e6,
            100.0 * width / stroke_pp,
            area.abs(),
            cycle.periods
        );
        assert!(stroke_pp > 0.5 * bw.d_p * 96.0 && stroke_pp < bw.d_p * 96.0);
        assert!(area.abs() > 0.01 * stroke_pp * 96.0, "degenerate loop");
        let ratio = width / stroke_pp;
        assert!((0.01..=0.30).contains(&ratio), "width/stroke = {ratio}");
        // the maximum width sits near V = 0 for a symmetric loop; δ at V = 0 on the two branches
        let mid_up = cycle.h[0]; // t = 0: V = 0, rising
        let mid_down = cycle.h[1000]; // half period: V = 0, falling
        assert!(((mid_up - mid_down).abs() - width).abs() <= 0.01 * width);
    }
}
