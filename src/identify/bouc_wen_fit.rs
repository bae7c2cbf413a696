//! Bouc–Wen shape constants α, β, γ by particle swarm optimisation (physics spec §12).
//!
//! With d_p known (from [`crate::identify::dp`]) the swarm minimises the normalised squared
//! error between the measured stroke and the model's periodic stroke over one cycle:
//!
//! ```text
//! J(α, β, γ) = Σ (x_meas,i − x_sim,i)² / Σ (x_meas,i − mean(x_meas))²
//! ```
//!
//! (a blocked-force record is turned into a stroke by dividing by the given k_p; J is
//! unchanged by that scaling). √J is reported as the normalised RMS error.
//!
//! * **Class-I constraints by construction.** The swarm searches over
//!   `(α, log₁₀β, r = γ/β)` in a box with `α ≥ α_min > 0`, `β ≥ β_min > 0`, `r ∈ [−1, 1]`;
//!   then α > 0, β − γ = β(1 − r) ≥ 0 and β + γ = β(1 + r) ≥ 0, and the feasibility hook
//!   rejects the one face where β + γ = 0 (r = −1). Every evaluated candidate is
//!   class I (each evaluation re-checks and counts violations: the count is reported and is
//!   0), and so is the result, which is also passed through [`BoucWen::validate`].
//! * **Simulated stroke.** The voltage is known only at the samples, so it is taken as
//!   piecewise linear between them (each piece is monotone, so [`BoucWen::advance`] is exact
//!   on it) and the cycle wraps from the last sample to the first. Starting from h = 0 the
//!   cycle is run at least twice, then the periodic state (the fixed point h* of the
//!   cycle map G: h(start) ↦ h(end)) is found by safeguarded secant steps on G(h) − h,
//!   until |G(h) − h| ≤ 1e-10 × min(α·d_p/(β+γ), α·d_p·(V_max − V_min)) (at most 60
//!   cycles). The secant step matters for
//!   weakly hysteretic candidates (small β), whose memory fades too slowly for plain
//!   repetition.
//! * **Data.** [`CycleData::from_measurement`] takes the last `cycles` whole periods of a
//!   record (default 1). The period is given, or estimated from the voltage's upward
//!   crossings of its mean (with a ±10 % amplitude hysteresis against noise); the cycle is
//!   `round(T/dt)` samples. The voltage is used as measured: noise on it would create
//!   spurious minor loops, so use the commanded or a clean voltage.
//! * **Seeds.** [`fit_multi_seed`] repeats the fit with several seeds and reports the best
//!   fit and the mean and standard deviation of α, β, γ over the seeds (a spread much larger
//!   than the parameters' precision means they are poorly determined by the data).

use crate::actuator::bouc_wen::BoucWen;
use crate::error::{Error, Result};
use crate::identify::pso::{self, PsoOptions, StopReason};
use crate::identify::toml_float;
use crate::io::measurement::{Measurement, Quantity};

/// What the record's response column is.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum FitTarget {
    /// Free stroke (displacement column, m).
    Stroke,
    /// Blocked force (force column, N) = k_p · stroke.
    BlockedForce { k_p: f64 },
}

/// How a cycle is cut from a record.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CycleOptions {
    /// Period (s); None: estimated from the voltage.
    pub period: Option<f64>,
    /// Number of whole periods taken from the end of the record (default 1).
    pub cycles: usize,
}

impl Default for CycleOptions {
    fn default() -> Self {
        CycleOptions { period: None, cycles: 1 }
    }
}

/// One periodic stretch of samples: the sample after the last is the first again.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CycleData {
    /// Where the data came from (messages).
    pub file: String,
    /// Voltage samples (V).
    pub voltage: Vec<f64>,
    /// Measured stroke (m) at the same samples.
    pub stroke: Vec<f64>,
    /// Period (s) of one cycle (informative).
    pub period: f64,
}

impl CycleData {
    /// Checks and wraps voltage/stroke samples covering whole periods.
    pub fn new(file: impl Into<String>, voltage: Vec<f64>, stroke: Vec<f64>, period: f64) -> Result<Self> {
        let file = file.into();
        if voltage.len() != stroke.len() {
            return Err(Error::input(
                &file,
                "displacement",
                format!("{} stroke samples for {} voltage samples", stroke.len(), voltage.len()),
            ));
        }
        if voltage.len() < 8 {
            return Err(Error::input(&file, "voltage", "a cycle needs at least 8 samples"));
        }
        for (name, x) in [("voltage", &voltage), ("displacement", &stroke)] {
            if let Some(i) = x.iter().position(|v| !v.is_finite()) {
                return Err(Error::input(&file, name, format!("sample {i} is not finite")));
            }
        }
        let m = crate::identify::mean(&stroke);
        if stroke.iter().all(|x| (x - m).abs() == 0.0) {
            return Err(Error::input(&file, "displacement", "the stroke is constant: nothing to fit"));
        }
        Ok(CycleData { file, voltage, stroke, period })
    }

    /// The last `opts.cycles` periods of a record with voltage and displacement (or force,
    /// for [`FitTarget::BlockedForce`]).
    pub fn from_measurement(m: &Measurement, target: FitTarget, opts: &CycleOptions) -> Result<Self> {
        let v = m.column(Quantity::Voltage)?;
        let x: Vec<f64> = match target {
            FitTarget::Stroke => m.column(Quantity::Displacement)?.to_vec(),
            FitTarget::BlockedForce { k_p } => {
                if !(k_p > 0.0 && k_p.is_finite()) {
                    return Err(Error::input(&m.file, "k_p", format!("must be positive, got {k_p}")));
                }
                m.column(Quantity::Force)?.iter().map(|f| f / k_p).collect()
            }
        };
        let period = match opts.period {
            Some(p) if p > 0.0 && p.is_finite() => p,
            Some(p) => return Err(Error::input(&m.file, "period", format!("must be positive, got {p}"))),
            None => estimate_period(&m.file, v, m.dt)?,
        };
        let n = (period / m.dt).round() as usize;
        if n < 8 {
            return Err(Error::input(
                &m.file,
                "time",
                format!("only {n} samples per period ({period:e} s at dt = {:e} s); at least 8 are needed", m.dt),
            ));
        }
        let cycles = opts.cycles.max(1);
        let len = n * cycles;
        if len > v.len() {
            return Err(Error::input(
                &m.file,
                "time",
                format!("the record ({} samples) is shorter than {cycles} period(s) of {n} samples", v.len()),
            ));
        }
        let s = v.len() - len;
        CycleData::new(m.file.clone(), v[s..].to_vec(), x[s..].to_vec(), period * cycles as f64)
    }
}

/// Period of a voltage record from its upward crossings of the mean (±10 % hysteresis).
pub fn estimate_period(file: &str, v: &[f64], dt: f64) -> Result<f64> {
    let c = crate::identify::mean(v);
    let (lo, hi) = v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(*x), b.max(*x)));
    let amp = 0.5 * (hi - lo);
    let mut crossings = Vec::new();
    let mut armed = false; // true once the signal was below c − 0.1·amp
    let mut last_cross = None;
    for i in 1..v.len() {
        if v[i] < c - 0.1 * amp {
            armed = true;
        }
        if v[i - 1] < c && v[i] >= c {
            last_cross = Some((i - 1) as f64 + (c - v[i - 1]) / (v[i] - v[i - 1]));
        }
        if armed && v[i] > c + 0.1 * amp {
            if let Some(tc) = last_cross {
                crossings.push(tc * dt);
            }
            armed = false;
        }
    }
    if amp <= 0.0 || crossings.len() < 2 {
        return Err(Error::input(
            file,
            "voltage",
            "cannot estimate the period: the record holds less than one whole cycle of an oscillating voltage; give the period",
        ));
    }
    Ok((crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64)
}

/// Settings of [`fit`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FitOptions {
    /// The known d_p (m/V).
    pub d_p: f64,
    /// Search range of α (default [1e-3, 1]); the lower end must be > 0.
    #[serde(default = "default_alpha")]
    pub alpha_range: (f64, f64),
    /// Search range of β in 1/V, searched on a log scale (default [1e-5, 1]); lower end > 0.
    #[serde(default = "default_beta")]
    pub beta_range: (f64, f64),
    /// Swarm settings (the seed is taken from here by [`fit`]).
    #[serde(default)]
    pub pso: PsoOptions,
    /// What the fits may take (`--max-memory`, `--max-steps`), held before the swarm starts.
    #[serde(skip)]
    pub budget: crate::analysis::budget::Budget,
}

fn default_alpha() -> (f64, f64) {
    (1e-3, 1.0)
}
fn default_beta() -> (f64, f64) {
    (1e-5, 1.0)
}

impl FitOptions {
    /// Defaults with the given d_p.
    pub fn new(d_p: f64) -> Self {
        FitOptions {
            d_p,
            alpha_range: default_alpha(),
            beta_range: default_beta(),
            pso: PsoOptions::default(),
            budget: Default::default(),
        }
    }

    fn validate(&self, file: &str) -> Result<()> {
        if !(self.d_p > 0.0 && self.d_p.is_finite()) {
            return Err(Error::input(file, "d_p", format!("must be positive (class I), got {}", self.d_p)));
        }
        let (a0, a1) = self.alpha_range;
        if !(a0 > 0.0 && a1 >= a0 && a1.is_finite()) {
            return Err(Error::input(file, "alpha_range", format!("need 0 < lower ≤ upper, got ({a0}, {a1})")));
        }
        let (b0, b1) = self.beta_range;
        if !(b0 > 0.0 && b1 >= b0 && b1.is_finite()) {
            return Err(Error::input(file, "beta_range", format!("need 0 < lower ≤ upper, got ({b0}, {b1})")));
        }
        self.pso.validate().map_err(|e| e.in_file(file))
    }
}

/// The class-I constraints d_p > 0, α > 0, β + γ > 0, β − γ ≥ 0.
pub fn is_class_one(m: &BoucWen) -> bool {
    m.d_p > 0.0 && m.alpha > 0.0 && m.beta + m.gamma > 0.0 && m.beta - m.gamma >= 0.0
}

/// Parameters of a search point (α, log₁₀β, r).
pub fn candidate(d_p: f64, x: &[f64]) -> BoucWen {
    let beta = 10f64.powf(x[1]);
    BoucWen { d_p, alpha: x[0], beta, gamma: x[2] * beta }
}

/// Periodic stroke of `model` for the cyclic voltage samples (see the module docs).
pub fn simulate_cycle(model: &BoucWen, voltage: &[f64]) -> Vec<f64> {
    let n = voltage.len();
    let cycle = |h0: f64, out: Option<&mut Vec<f64>>| -> f64 {
        let mut h = h0;
        match out {
            Some(o) => {
                o.clear();
                for i in 0..n {
                    o.push(model.stroke(voltage[i], h));
                    h = model.advance(h, voltage[i], voltage[(i + 1) % n]);
                }
            }
            None => {
                for i in 0..n {
                    h = model.advance(h, voltage[i], voltage[(i + 1) % n]);
                }
            }
        }
        h
    };
    let bound = model.bound(0.0);
    // |h| ≤ bound, and h cannot move by more than α·d_p·(V range) over a cycle: the
    // smaller of the two scales the tolerance.
    let (vlo, vhi) = voltage.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
    let tol = 1e-10 * bound.min(model.alpha * model.d_p * (vhi - vlo)).max(f64::MIN_POSITIVE);
    // Two plain cycles, then safeguarded secant on g(h) = G(h) − h (G increasing, with
    // slope in [0, 1] for class I, so g is decreasing and the root is bracketed by the
    // iterates' signs).
    let mut h0 = 0.0;
    let mut h1 = cycle(h0, None);
    let mut g0 = h1 - h0;
    let mut h = h1;
    let mut g = cycle(h1, None) - h1;
    let (mut lo, mut hi) = (-bound, bound);
    for _ in 0..60 {
        if g.abs() <= tol {
            break;
        }
        if g > 0.0 {
            lo = lo.max(h);
        } else {
            hi = hi.min(h);
        }
        let mut next = if g != g0 { h - g * (h - h0) / (g - g0) } else { h + g };
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        h0 = h;
        g0 = g;
        h = next;
        h1 = cycle(h, None);
        g = h1 - h;
    }
    let mut out = Vec::with_capacity(n);
    cycle(h, Some(&mut out));
    out
}

/// J = Σ(meas − sim)² / Σ(meas − mean)².
pub fn normalised_squared_error(measured: &[f64], simulated: &[f64]) -> f64 {
    let m = crate::identify::mean(measured);
    let num: f64 = measured.iter().zip(simulated).map(|(a, b)| (a - b).powi(2)).sum();
    let den: f64 = measured.iter().map(|a| (a - m).powi(2)).sum();
    num / den
}

/// Result of one swarm run.
#[derive(Clone, Debug, serde::Serialize)]
pub struct BoucWenFit {
    /// Identified parameters (d_p as given).
    pub params: BoucWen,
    /// Final cost J.
    pub cost: f64,
    /// √J: normalised RMS error of the stroke.
    pub nrmse: f64,
    /// Best cost per iteration.
    pub history: Vec<f64>,
    pub iterations: usize,
    pub evaluations: usize,
    pub stop: StopReason,
    pub seed: u64,
    /// Evaluated candidates that violated class I (0 by construction; reported as a check).
    pub infeasible_candidates: usize,
    /// Data source.
    pub file: String,
}

impl BoucWenFit {
    /// `[actuator.stack]` with `d_p`, `alpha`, `beta`, `gamma`.
    pub fn to_case_fragment(&self) -> String {
        format!(
            "# Bouc-Wen fit to {}: normalised RMS error {} %, PSO seed {}, {} iterations ({})\n{}",
            self.file,
            toml_float(100.0 * self.nrmse),
            self.seed,
            self.iterations,
            self.stop,
            stack_fields(&self.params)
        )
    }
}

fn stack_fields(p: &BoucWen) -> String {
    format!(
        "[{}]\nd_p = {}\nalpha = {}\nbeta = {}\ngamma = {}\n",
        crate::identify::STACK_TABLE,
        toml_float(p.d_p),
        toml_float(p.alpha),
        toml_float(p.beta),
        toml_float(p.gamma)
    )
}

/// Fits α, β, γ to one cycle (seed from `opts.pso.seed`).
pub fn fit(data: &CycleData, opts: &FitOptions) -> Result<BoucWenFit> {
    opts.validate(&data.file)?;
    let lower = [opts.alpha_range.0, opts.beta_range.0.log10(), -1.0];
    let upper = [opts.alpha_range.1, opts.beta_range.1.log10(), 1.0];
    let d_p = opts.d_p;
    let feasible = |x: &[f64]| is_class_one(&candidate(d_p, x));
    let violations = std::sync::atomic::AtomicUsize::new(0);
    let res = pso::minimize(&lower, &upper, &opts.pso, feasible, |x| {
        let model = candidate(d_p, x);
        if !is_class_one(&model) {
            violations.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            return f64::INFINITY;
        }
        normalised_squared_error(&data.stroke, &simulate_cycle(&model, &data.voltage))
    })?;
    let params = candidate(d_p, &res.best);
    params.validate().map_err(|e| e.in_table(&data.file, crate::identify::STACK_TABLE))?;
    Ok(BoucWenFit {
        params,
        cost: res.cost,
        nrmse: res.cost.sqrt(),
        history: res.history,
        iterations: res.iterations,
        evaluations: res.evaluations,
        stop: res.stop,
        seed: opts.pso.seed,
        infeasible_candidates: violations.into_inner(),
        file: data.file.clone(),
    })
}

/// Fits with each seed; reports the best and the spread.
#[derive(Clone, Debug, serde::Serialize)]
pub struct MultiSeedFit {
    /// The fit with the lowest cost.
    pub best: BoucWenFit,
    /// All fits, in seed order.
    pub fits: Vec<BoucWenFit>,
    /// Mean of (α, β, γ) over the seeds.
    pub mean: [f64; 3],
    /// Standard deviation (population) of (α, β, γ) over the seeds.
    pub std: [f64; 3],
}

impl MultiSeedFit {
    /// The best fit's fragment with the spread over the seeds as comments.
    pub fn to_case_fragment(&self) -> String {
        let seeds: Vec<String> = self.fits.iter().map(|f| f.seed.to_string()).collect();
        format!(
            "# Bouc-Wen fit to {}: best of seeds [{}], normalised RMS error {} %\n\
             # spread over seeds (mean +- std): alpha {} +- {}, beta {} +- {}, gamma {} +- {}\n{}",
            self.best.file,
            seeds.join(", "),
            toml_float(100.0 * self.best.nrmse),
            toml_float(self.mean[0]),
            toml_float(self.std[0]),
            toml_float(self.mean[1]),
            toml_float(self.std[1]),
            toml_float(self.mean[2]),
            toml_float(self.std[2]),
            stack_fields(&self.best.params)
        )
    }
}

/// What the swarms of `seeds` fits take: each particle simulates the cycle once an
/// iteration (and once at the start), and holds its position, velocity and best.
fn swarm_cost(data: &CycleData, opts: &FitOptions, seeds: usize) -> crate::analysis::budget::Cost {
    use crate::analysis::budget::{count, product, sum};
    let (particles, iterations) = (count(opts.pso.particles), count(opts.pso.max_iterations));
    let samples = count(data.voltage.len());
    let steps = product(&[count(seeds), particles, iterations.saturating_add(1), samples]);
    let bytes = sum(&[product(&[particles, 3 * 8 * 4]), product(&[samples, 8 * 8])]);
    // The argument furthest above its default drives the estimate.
    let defaults = PsoOptions::default();
    let flag = if particles * count(defaults.max_iterations) >= iterations * count(defaults.particles) {
        "--particles"
    } else {
        "--max-iterations"
    };
    crate::analysis::cost::of_arguments(
        "this identification",
        (bytes, steps),
        "cycle samples simulated",
        format!("{seeds} seeds × {particles} particles × {iterations} iterations × {samples} samples per cycle"),
        flag,
        "use fewer --particles, --max-iterations or --seeds",
    )
}

/// [`fit`] once per seed (the seeds replace `opts.pso.seed`).
pub fn fit_multi_seed(data: &CycleData, opts: &FitOptions, seeds: &[u64]) -> Result<MultiSeedFit> {
    if seeds.is_empty() {
        return Err(Error::input(&data.file, "seeds", "give at least one seed"));
    }
    opts.budget.admit(&swarm_cost(data, opts, seeds.len())).map_err(|e| e.in_file("<cli>"))?;
    let mut fits = Vec::with_capacity(seeds.len());
    for &seed in seeds {
        let mut o = opts.clone();
        o.pso.seed = seed;
        fits.push(fit(data, &o)?);
    }
    let col =
        |k: usize| -> Vec<f64> { fits.iter().map(|f| [f.params.alpha, f.params.beta, f.params.gamma][k]).collect() };
    let mean = [0, 1, 2].map(|k| crate::identify::mean(&col(k)));
    let std = [0, 1, 2].map(|k| crate::identify::std_dev(&col(k)));
    let best = fits.iter().min_by(|a, b| a.cost.total_cmp(&b.cost)).cloned().expect("non-empty");
    Ok(MultiSeedFit { best, fits, mean, std })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::identify::frf::tests::add_noise;
    use crate::identify::pso::Rng;
    use crate::io::measurement::{self, LoadOptions};
    use crate::signal::voltage::VoltageInput;

    const TRUE: BoucWen = BoucWen { d_p: 1.3e-7, alpha: 0.3, beta: 0.02, gamma: 0.005 };
    const SPP: usize = 200; // samples per period
    const FREQ: f64 = 30.0;

    /// A 3-period record of the true model's periodic state under 48 V at 30 Hz, computed by
    /// the exact sine history (not the piecewise-linear path the fit uses), 1 % noise on
    /// the stroke.
    fn record(noise: f64, seed: u64) -> Measurement {
        let input = VoltageInput::sine(48.0, FREQ);
        let cyc = TRUE.periodic_cycle(&input, SPP, 1e-13, 200).unwrap();
        assert!(cyc.converged);
        let periods = 3;
        let dt = 1.0 / (FREQ * SPP as f64);
        let n = periods * SPP;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
        let v: Vec<f64> = (0..n).map(|i| cyc.v[i % SPP]).collect();
        let mut x: Vec<f64> = (0..n).map(|i| cyc.stroke[i % SPP]).collect();
        add_noise(&mut x, noise, &mut Rng::new(seed));
        Measurement::new("loop.csv", t, vec![(Quantity::Voltage, v), (Quantity::Displacement, x)]).unwrap()
    }

    /// NRMSE of the identified model's periodic loop against the true one (exact sine).
    fn loop_error(p: &BoucWen) -> f64 {
        let input = VoltageInput::sine(48.0, FREQ);
        let a = TRUE.periodic_cycle(&input, 400, 1e-12, 500).unwrap();
        let b = p.periodic_cycle(&input, 400, 1e-12, 500).unwrap();
        normalised_squared_error(&a.stroke, &b.stroke).sqrt()
    }

    fn quick_pso() -> PsoOptions {
        PsoOptions { particles: 24, max_iterations: 250, window: 30, tol_rel: 1e-7, ..Default::default() }
    }

    #[test]
    fn simulate_cycle_matches_the_exact_periodic_state() {
        let input = VoltageInput::sine(48.0, FREQ);
        let cyc = TRUE.periodic_cycle(&input, 400, 1e-13, 500).unwrap();
        let sim = simulate_cycle(&TRUE, &cyc.v[..400]);
        let e = normalised_squared_error(&cyc.stroke[..400], &sim).sqrt();
        assert!(e < 1e-4, "{e}");
        // A weakly hysteretic candidate (tiny β, memory fading by ~0.1 % per cycle): the
        // returned cycle is periodic, h(end) = h(start).
        let weak = BoucWen { d_p: 1.3e-7, alpha: 0.5, beta: 1e-5, gamma: -0.9e-5 };
        let v = &cyc.v[..400];
        let sim = simulate_cycle(&weak, v);
        let h0 = weak.d_p * v[0] - sim[0];
        let mut h = h0;
        for i in 0..400 {
            h = weak.advance(h, v[i], v[(i + 1) % 400]);
        }
        let h_range = weak.alpha * weak.d_p * 96.0;
        assert!((h - h0).abs() <= 1e-9 * h_range, "{h} vs {h0}");
        // Plain repetition from another start is still far from it after 20 cycles.
        let mut hp = 1e-6;
        for _ in 0..20 {
            for i in 0..400 {
                hp = weak.advance(hp, v[i], v[(i + 1) % 400]);
            }
        }
        assert!((hp - h0).abs() > 0.5e-6, "{hp} vs {h0}");
    }

    #[test]
    fn period_estimate_and_cycle_cut() {
        let m = record(0.01, 3);
        let p = estimate_period("loop.csv", m.voltage.as_ref().unwrap(), m.dt).unwrap();
        assert!((p * FREQ - 1.0).abs() < 1e-3, "{p}");
        let c = CycleData::from_measurement(&m, FitTarget::Stroke, &CycleOptions::default()).unwrap();
        assert_eq!(c.voltage.len(), SPP);
        let c = CycleData::from_measurement(&m, FitTarget::Stroke, &CycleOptions { period: None, cycles: 2 }).unwrap();
        assert_eq!(c.voltage.len(), 2 * SPP);
        let e =
            CycleData::from_measurement(&m, FitTarget::Stroke, &CycleOptions { period: None, cycles: 9 }).unwrap_err();
        assert!(e.to_string().contains("loop.csv") && e.to_string().contains("shorter"), "{e}");
        let flat = Measurement::new("flat.csv", m.time.clone(), vec![(Quantity::Voltage, vec![1.0; m.len()])]).unwrap();
        let e = estimate_period("flat.csv", flat.voltage.as_ref().unwrap(), m.dt).unwrap_err().to_string();
        assert!(e.contains("flat.csv") && e.contains("period"), "{e}");
    }

    #[test]
    fn round_trip_through_a_file_reproduces_the_loop() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("loop.csv");
        measurement::write(&path, &record(0.01, 42)).unwrap();
        let m =
            measurement::load(&path, &[Quantity::Voltage, Quantity::Displacement], &LoadOptions::default()).unwrap();
        let data = CycleData::from_measurement(&m, FitTarget::Stroke, &CycleOptions::default()).unwrap();
        let opts = FitOptions { pso: quick_pso(), ..FitOptions::new(1.3e-7) };
        let multi = fit_multi_seed(&data, &opts, &[1, 2, 3]).unwrap();
        for f in &multi.fits {
            assert_eq!(f.infeasible_candidates, 0);
            assert!(is_class_one(&f.params));
            f.params.validate().unwrap();
            assert!(f.history.windows(2).all(|w| w[1] <= w[0]));
        }
        let best = &multi.best;
        let le = loop_error(&best.params);
        eprintln!(
            "Bouc-Wen fit: alpha {:.4} beta {:.5} gamma {:.5}; data NRMSE {:.4e}; loop NRMSE vs truth {le:.2e}; \
             spread std {:?}; iterations {:?}",
            best.params.alpha,
            best.params.beta,
            best.params.gamma,
            best.nrmse,
            multi.std,
            multi.fits.iter().map(|f| f.iterations).collect::<Vec<_>>()
        );
        assert!(le < 0.01, "loop error {le}");
        // The noise floor: 1 % noise on the stroke cannot be fitted away.
        assert!(best.nrmse > 0.005 && best.nrmse < 0.02, "{}", best.nrmse);
        let frag = multi.to_case_fragment();
        let t: toml::Table = toml::from_str(&frag).unwrap();
        let st = t["actuator"]["stack"].as_table().unwrap();
        for k in ["d_p", "alpha", "beta", "gamma"] {
            assert!(st[k].as_float().is_some(), "{k} missing in\n{frag}");
        }
        assert!((st["alpha"].as_float().unwrap() / best.params.alpha - 1.0).abs() < 1e-5);
    }

    #[test]
    fn blocked_force_fit_and_reproducibility() {
        let m = record(0.01, 7);
        let kp = 3.0e7;
        let f: Vec<f64> = m.displacement.as_ref().unwrap().iter().map(|x| kp * x).collect();
        let mf = Measurement::new(
            "blocked.csv",
            m.time.clone(),
            vec![(Quantity::Voltage, m.voltage.clone().unwrap()), (Quantity::Force, f)],
        )
        .unwrap();
        let data =
            CycleData::from_measurement(&mf, FitTarget::BlockedForce { k_p: kp }, &CycleOptions::default()).unwrap();
        let opts = FitOptions { pso: PsoOptions { seed: 5, ..quick_pso() }, ..FitOptions::new(1.3e-7) };
        let a = fit(&data, &opts).unwrap();
        let b = fit(&data, &opts).unwrap();
        assert_eq!(a.params, b.params);
        assert_eq!(a.history, b.history);
        assert_eq!(a.infeasible_candidates, 0);
        assert!(loop_error(&a.params) < 0.01);
        // Missing force column with a blocked-force target.
        let e =
            CycleData::from_measurement(&m, FitTarget::BlockedForce { k_p: kp }, &CycleOptions::default()).unwrap_err();
        assert!(e.to_string().contains("loop.csv") && e.to_string().contains("force"), "{e}");
    }

    #[test]
    fn candidates_are_class_one_over_the_whole_box() {
        let mut rng = Rng::new(1);
        let o = FitOptions::new(1.3e-7);
        for _ in 0..100_000 {
            let x = [
                rng.uniform_in(o.alpha_range.0, o.alpha_range.1),
                rng.uniform_in(o.beta_range.0.log10(), o.beta_range.1.log10()),
                rng.uniform_in(-1.0, 1.0),
            ];
            assert!(is_class_one(&candidate(1.3e-7, &x)), "{x:?}");
        }
        // The box's corners except the r = −1 face (rejected by the hook).
        assert!(is_class_one(&candidate(1.3e-7, &[1e-3, -5.0, 1.0])));
        assert!(!is_class_one(&candidate(1.3e-7, &[1e-3, -5.0, -1.0])));
    }

    #[test]
    fn bad_options_are_errors() {
        let data =
            CycleData::new("c.csv", (0..16).map(|i| i as f64).collect(), (0..16).map(|i| i as f64).collect(), 1.0)
                .unwrap();
        let e = fit(&data, &FitOptions::new(-1.0)).unwrap_err().to_string();
        assert!(e.contains("c.csv") && e.contains("d_p"), "{e}");
        let e = fit(&data, &FitOptions { alpha_range: (0.0, 1.0), ..FitOptions::new(1e-7) }).unwrap_err().to_string();
        assert!(e.contains("alpha_range"), "{e}");
        let e = CycleData::new("c.csv", vec![1.0; 16], vec![2.0; 16], 1.0).unwrap_err().to_string();
        assert!(e.contains("constant"), "{e}");
    }
}
