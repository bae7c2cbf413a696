//! Seeded random numbers for identification and synthetic data ([`Rng`]), and the
//! particle swarm that fits the Bouc–Wen parameters: `argmin`'s `ParticleSwarm`, seeded and
//! run one iteration at a time here for its history and stop criterion, with a
//! feasibility hook.
//!
//! Update rule (global-best PSO; argmin's implementation):
//!
//! ```text
//! v ← w·v + c₁·r₁·(p_best − x) + c₂·r₂·(g_best − x)      (r₁, r₂ ~ U(0, 1) per component)
//! x ← x + v                                              (then clamped to the box)
//! ```
//!
//! * `w` (inertia) = 0.7298, `c₁` (cognitive) = `c₂` (social) = 1.49618 by default: the
//!   Clerc–Kennedy constriction values written in inertia form.
//! * Feasibility: a candidate for which `feasible(x)` is false is **never evaluated**: its
//!   cost is +∞, so it never becomes a particle's or the swarm's best.
//! * Convergence criterion: after at least `window` iterations, stop when the best cost
//!   improved by no more than `tol_abs + tol_rel·|best|` over the last `window` iterations;
//!   otherwise stop at `max_iterations`. The reason is reported in [`StopReason`].
//!
//! The swarm's random numbers come from xoshiro256++ seeded by the seed (`rand_xoshiro`);
//! [`Rng`] is xoshiro256** (`rand_xoshiro`) seeded through splitmix64. The same seed gives bit-identical
//! results on every platform and thread count.

use crate::error::{Error, Result};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Pseudo-random generator: xoshiro256** (Blackman & Vigna, `rand_xoshiro`), seeded by
/// splitmix64, with uniform and normal deviates.
#[derive(Clone, Debug)]
pub struct Rng {
    bits: rand_xoshiro::Xoshiro256StarStar,
    spare_normal: Option<f64>,
}

impl Rng {
    /// A generator whose whole stream is determined by `seed`.
    pub fn new(seed: u64) -> Self {
        use rand::SeedableRng;
        Rng { bits: rand_xoshiro::Xoshiro256StarStar::seed_from_u64(seed), spare_normal: None }
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        rand::RngCore::next_u64(&mut self.bits)
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [lo, hi).
    pub fn uniform_in(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// Standard normal deviate (Box–Muller; the second value of each pair is kept).
    pub fn normal(&mut self) -> f64 {
        if let Some(z) = self.spare_normal.take() {
            return z;
        }
        // u1 in (0, 1] so that ln(u1) is finite.
        let u1 = 1.0 - self.uniform();
        let u2 = self.uniform();
        let r = (-2.0 * u1.ln()).sqrt();
        let (s, c) = (2.0 * std::f64::consts::PI * u2).sin_cos();
        self.spare_normal = Some(r * s);
        r * c
    }
}

/// Settings of the swarm; `Default` gives the documented constants.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PsoOptions {
    /// Number of particles (default 30).
    pub particles: usize,
    /// Iteration limit (default 400).
    pub max_iterations: usize,
    /// Inertia weight w (default 0.7298).
    pub inertia: f64,
    /// Cognitive constant c₁: pull towards the particle's own best (default 1.49618).
    pub cognitive: f64,
    /// Social constant c₂: pull towards the swarm's best (default 1.49618).
    pub social: f64,
    /// Convergence window in iterations (default 40).
    pub window: usize,
    /// Absolute cost-change tolerance over the window (default 0).
    pub tol_abs: f64,
    /// Relative cost-change tolerance over the window (default 1e-6).
    pub tol_rel: f64,
    /// Seed of the random stream (default 1).
    pub seed: u64,
}

impl Default for PsoOptions {
    fn default() -> Self {
        PsoOptions {
            particles: 30,
            max_iterations: 400,
            inertia: 0.7298,
            cognitive: 1.49618,
            social: 1.49618,
            window: 40,
            tol_abs: 0.0,
            tol_rel: 1e-6,
            seed: 1,
        }
    }
}

impl PsoOptions {
    /// Checks the settings (errors name the setting; the caller names the file).
    pub fn validate(&self) -> Result<()> {
        let bad = |field: &str, reason: &str| Err(Error::argument(format!("pso.{field}"), reason));
        if self.particles < 2 {
            return bad("particles", "must be at least 2");
        }
        if self.max_iterations < 1 {
            return bad("max_iterations", "must be at least 1");
        }
        if self.window < 1 {
            return bad("window", "must be at least 1");
        }
        for (name, v) in [("inertia", self.inertia), ("cognitive", self.cognitive), ("social", self.social)] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(name, "must be finite and non-negative");
            }
        }
        if !(self.tol_abs >= 0.0 && self.tol_rel >= 0.0) {
            return bad("tol_abs/tol_rel", "must be non-negative");
        }
        Ok(())
    }
}

/// Why the swarm stopped.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum StopReason {
    /// The best cost changed by no more than the tolerance over `window` iterations.
    Converged { window: usize, change: f64 },
    /// `max_iterations` was reached first.
    MaxIterations,
}

impl std::fmt::Display for StopReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StopReason::Converged { window, change } => {
                write!(f, "converged: best cost changed by {change:.3e} over the last {window} iterations")
            }
            StopReason::MaxIterations => write!(f, "reached the iteration limit"),
        }
    }
}

/// Outcome of [`minimize`].
#[derive(Clone, Debug, serde::Serialize)]
pub struct PsoResult {
    /// Best point found.
    pub best: Vec<f64>,
    /// Its cost.
    pub cost: f64,
    /// Best cost after each iteration (entry 0: after the initial swarm).
    pub history: Vec<f64>,
    /// Iterations performed (not counting the initial swarm).
    pub iterations: usize,
    /// Cost evaluations performed (all of them at feasible points).
    pub evaluations: usize,
    /// Why it stopped.
    pub stop: StopReason,
}

/// Minimises `cost` over the box `lower ≤ x ≤ upper` with `argmin`'s particle swarm,
/// driven one iteration at a time for the history and the stop criterion. A point for
/// which `feasible` is false is not evaluated (its cost is +∞, so it is never a best); a
/// non-finite cost counts as +∞. The swarm's costs are evaluated in parallel on the
/// current rayon pool; each depends on its point alone, so the result does not depend on
/// the thread count.
///
/// Errors: inconsistent bounds, invalid options, or no feasible point in the initial swarm.
pub fn minimize<F, C>(lower: &[f64], upper: &[f64], opts: &PsoOptions, feasible: C, cost: F) -> Result<PsoResult>
where
    F: Fn(&[f64]) -> f64 + Sync,
    C: Fn(&[f64]) -> bool + Sync,
{
    use argmin::core::{PopulationState, Problem, Solver, State};
    use argmin::solver::particleswarm::ParticleSwarm;
    use rand::SeedableRng;

    opts.validate()?;
    let d = lower.len();
    if d == 0 || upper.len() != d {
        return Err(Error::argument("bounds", "lower and upper bounds must be non-empty and of equal length"));
    }
    for i in 0..d {
        if !(lower[i].is_finite() && upper[i].is_finite() && lower[i] <= upper[i]) {
            return Err(Error::argument(
                format!("bounds[{i}]"),
                format!("need finite lower ≤ upper, got [{}, {}]", lower[i], upper[i]),
            ));
        }
    }
    let evaluations = AtomicUsize::new(0);
    let mut problem = Problem::new(Swarmed { cost: &cost, feasible: &feasible, evaluations: &evaluations });
    let numerical = |e: argmin::core::Error| Error::Numerical(format!("particle swarm: {e}"));
    let mut swarm = ParticleSwarm::new((lower.to_vec(), upper.to_vec()), opts.particles)
        .with_inertia_factor(opts.inertia)
        .and_then(|s| s.with_cognitive_factor(opts.cognitive))
        .and_then(|s| s.with_social_factor(opts.social))
        .map_err(numerical)?
        .with_rng_generator(rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(opts.seed));
    let (mut state, _) = swarm.init(&mut problem, PopulationState::new()).map_err(numerical)?;
    if !state.cost.is_finite() {
        return Err(Error::Numerical("PSO: no feasible point in the initial swarm".into()));
    }
    let mut history = vec![state.cost];
    let mut stop = StopReason::MaxIterations;
    let mut iterations = 0;
    for it in 1..=opts.max_iterations {
        iterations = it;
        state = swarm.next_iter(&mut problem, state).map_err(numerical)?.0;
        history.push(state.cost);
        if it >= opts.window {
            let change = history[it - opts.window] - state.cost;
            if change.is_finite() && change <= opts.tol_abs + opts.tol_rel * state.cost.abs() {
                stop = StopReason::Converged { window: opts.window, change };
                break;
            }
        }
    }
    let best = state.individual.map(|p| p.position).ok_or_else(|| Error::Numerical("PSO: no best particle".into()))?;
    Ok(PsoResult { best, cost: state.cost, history, iterations, evaluations: evaluations.into_inner(), stop })
}

/// The cost as the swarm sees it: +∞ at infeasible points, which are not evaluated.
struct Swarmed<'a, F, C> {
    cost: &'a F,
    feasible: &'a C,
    evaluations: &'a AtomicUsize,
}

impl<F: Fn(&[f64]) -> f64 + Sync, C: Fn(&[f64]) -> bool + Sync> argmin::core::CostFunction for Swarmed<'_, F, C> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, x: &Vec<f64>) -> std::result::Result<f64, argmin::core::Error> {
        if !(self.feasible)(x) {
            return Ok(f64::INFINITY);
        }
        self.evaluations.fetch_add(1, Ordering::Relaxed);
        let c = (self.cost)(x);
        Ok(if c.is_finite() { c } else { f64::INFINITY })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rng_is_reproducible_and_roughly_uniform_and_normal() {
        let mut a = Rng::new(42);
        let mut b = Rng::new(42);
        let mut c = Rng::new(43);
        let xa: Vec<u64> = (0..10).map(|_| a.next_u64()).collect();
        let xb: Vec<u64> = (0..10).map(|_| b.next_u64()).collect();
        let xc: Vec<u64> = (0..10).map(|_| c.next_u64()).collect();
        assert_eq!(xa, xb);
        assert_ne!(xa, xc);
        let mut r = Rng::new(7);
        let n = 200_000;
        let u: Vec<f64> = (0..n).map(|_| r.uniform()).collect();
        assert!(u.iter().all(|&x| (0.0..1.0).contains(&x)));
        assert!((crate::identify::mean(&u) - 0.5).abs() < 0.005);
        let z: Vec<f64> = (0..n).map(|_| r.normal()).collect();
        assert!(crate::identify::mean(&z).abs() < 0.01);
        assert!((crate::identify::std_dev(&z) - 1.0).abs() < 0.01);
    }

    fn rosenbrock(x: &[f64]) -> f64 {
        (1.0 - x[0]).powi(2) + 100.0 * (x[1] - x[0] * x[0]).powi(2)
    }

    #[test]
    fn finds_minimum_of_sphere_and_rosenbrock() {
        let opts = PsoOptions { seed: 3, ..Default::default() };
        let r = minimize(
            &[-5.0; 3],
            &[5.0; 3],
            &opts,
            |_| true,
            |x| x.iter().enumerate().map(|(i, v)| (v - i as f64).powi(2)).sum(),
        )
        .unwrap();
        for (i, v) in r.best.iter().enumerate() {
            assert!((v - i as f64).abs() < 1e-3, "{:?}", r.best);
        }
        let opts = PsoOptions {
            seed: 5,
            max_iterations: 2000,
            tol_rel: 0.0,
            tol_abs: 1e-14,
            window: 100,
            ..Default::default()
        };
        let r = minimize(&[-2.0, -2.0], &[2.0, 2.0], &opts, |_| true, rosenbrock).unwrap();
        assert!((r.best[0] - 1.0).abs() < 1e-2 && (r.best[1] - 1.0).abs() < 2e-2, "{:?} {}", r.best, r.cost);
        // History is the best cost per iteration: non-increasing, one entry per iteration + initial.
        assert_eq!(r.history.len(), r.iterations + 1);
        assert!(r.history.windows(2).all(|w| w[1] <= w[0]));
        assert_eq!(*r.history.last().unwrap(), r.cost);
    }

    #[test]
    fn same_seed_same_answer_other_seed_other_path() {
        let f = |x: &[f64]| (x[0] - 0.3).powi(2) + (x[1] + 0.1).powi(2) + 0.1 * (5.0 * x[0]).sin().powi(2);
        let o = PsoOptions { seed: 11, ..Default::default() };
        let a = minimize(&[-1.0, -1.0], &[1.0, 1.0], &o, |_| true, f).unwrap();
        let b = minimize(&[-1.0, -1.0], &[1.0, 1.0], &o, |_| true, f).unwrap();
        assert_eq!(a.best, b.best);
        assert_eq!(a.history, b.history);
        let c = minimize(&[-1.0, -1.0], &[1.0, 1.0], &PsoOptions { seed: 12, ..o }, |_| true, f).unwrap();
        assert_ne!(a.history, c.history);
    }

    #[test]
    fn infeasible_points_are_never_evaluated_and_constrained_optimum_is_found() {
        // Minimise (x-2)² + (y-2)² subject to x + y ≤ 2: optimum (1, 1).
        let feasible = |x: &[f64]| x[0] + x[1] <= 2.0;
        let violations = AtomicUsize::new(0);
        let opts = PsoOptions { max_iterations: 1000, window: 100, tol_rel: 1e-12, ..Default::default() };
        let r = minimize(&[-3.0, -3.0], &[3.0, 3.0], &opts, feasible, |x| {
            if x[0] + x[1] > 2.0 {
                violations.fetch_add(1, Ordering::Relaxed);
            }
            (x[0] - 2.0).powi(2) + (x[1] - 2.0).powi(2)
        })
        .unwrap();
        assert_eq!(violations.into_inner(), 0);
        assert!(feasible(&r.best));
        assert!((r.best[0] - 1.0).abs() < 1e-2 && (r.best[1] - 1.0).abs() < 1e-2, "{:?}", r.best);
    }

    #[test]
    fn stops_by_the_stated_criterion() {
        let o = PsoOptions { window: 10, tol_rel: 1e-3, ..Default::default() };
        let r = minimize(&[-1.0], &[1.0], &o, |_| true, |x| x[0] * x[0] + 1.0).unwrap();
        match r.stop {
            StopReason::Converged { window, change } => {
                assert_eq!(window, 10);
                assert!(change <= 1e-3 * r.cost);
                let n = r.history.len();
                assert!(r.history[n - 11] - r.history[n - 1] <= 1e-3 * r.cost);
            }
            _ => panic!("expected convergence, got {:?}", r.stop),
        }
        let o = PsoOptions { max_iterations: 5, tol_rel: 0.0, window: 10, ..Default::default() };
        let r = minimize(&[-1.0], &[1.0], &o, |_| true, |x| x[0] * x[0]).unwrap();
        assert_eq!(r.stop, StopReason::MaxIterations);
        assert_eq!(r.iterations, 5);
    }

    #[test]
    fn bad_bounds_and_impossible_feasibility_are_errors() {
        let o = PsoOptions::default();
        assert!(minimize(&[1.0], &[0.0], &o, |_| true, |x| x[0]).is_err());
        assert!(minimize(&[0.0, 0.0], &[1.0], &o, |_| true, |x| x[0]).is_err());
        assert!(minimize(&[0.0], &[1.0], &o, |_| false, |x| x[0]).is_err());
        let bad = PsoOptions { particles: 1, ..Default::default() };
        let e = minimize(&[0.0], &[1.0], &bad, |_| true, |x| x[0]).unwrap_err().to_string();
        assert!(e.contains("particles"), "{e}");
    }
}
