//! The global search over the unit box [0, 1]^d and its local polish, on library
//! optimisers: CMA-ES (`cmaes`) from seeded random starts, then Nelder–Mead (`argmin`)
//! from the best point. The cost is evaluated in parallel over each generation's
//! candidates (rayon, on the caller's pool); every random number comes from the seed, and a
//! candidate's cost depends on nothing else, so the result does not depend on the thread
//! count.

use argmin::core::{CostFunction, Executor, State};
use argmin::solver::neldermead::NelderMead;

/// How hard to search.
#[derive(Clone, Debug)]
pub struct Options {
    pub seed: u64,
    /// Independent starts.
    pub starts: usize,
    /// Cost evaluations of the global search, all starts together.
    pub evaluations: usize,
    /// Evaluations of the Nelder–Mead polish (0: none).
    pub polish: usize,
}

/// The best point of one start.
#[derive(Clone, Debug)]
pub struct Point {
    pub u: Vec<f64>,
    pub cost: f64,
}

/// What the search found.
#[derive(Clone, Debug)]
pub struct Found {
    /// The best point overall (after the polish).
    pub best: Point,
    /// The best point of each start, in start order.
    pub starts: Vec<Point>,
}

/// The costs the search asks for: `cost` of one point (called from several threads),
/// and `generation` before each batch of points (for bookkeeping: the calls of one batch
/// may come in any order).
pub trait Cost: Sync {
    fn cost(&self, u: &[f64]) -> f64;
    fn generation(&self, start: usize) {
        let _ = start;
    }
}

/// Folds a point into the box by reflection at its faces: x ↦ the triangle wave of
/// period 2, so the box's cost extends to all of ℝ^d without a kink in its level sets
/// (CMA-ES samples freely).
pub fn reflect(x: f64) -> f64 {
    let t = x.rem_euclid(2.0);
    if t > 1.0 {
        2.0 - t
    } else {
        t
    }
}

fn folded(x: &[f64]) -> Vec<f64> {
    x.iter().map(|&v| reflect(v)).collect()
}

/// A reproducible stream of start points: splitmix64 of the seed and start number.
fn start_point(seed: u64, start: usize, d: usize) -> Vec<f64> {
    let mut rng = crate::identify::pso::Rng::new(seed.wrapping_mul(0x9E37_79B9).wrapping_add(start as u64));
    (0..d).map(|_| rng.uniform()).collect()
}

/// Minimises `f` over [0, 1]^d: `opts.starts` CMA-ES runs, each from a seeded random mean
/// with step 0.3 and its share of the evaluations (it stops early when its step falls
/// below 1e-4 of the box or its costs stop changing), then Nelder–Mead from the best.
pub fn minimize(d: usize, f: &dyn Cost, opts: &Options) -> Found {
    let per_start = opts.evaluations / opts.starts.max(1);
    let mut starts = Vec::with_capacity(opts.starts);
    for s in 0..opts.starts {
        starts.push(cmaes_start(d, f, opts.seed, s, per_start));
    }
    let mut best = starts.iter().min_by(|a, b| a.cost.total_cmp(&b.cost)).cloned().expect("at least one start");
    if opts.polish > 0 {
        f.generation(opts.starts);
        if let Some(p) = polish(&best, f, opts.polish) {
            if p.cost < best.cost {
                best = p;
            }
        }
    }
    Found { best, starts }
}

fn cmaes_start(d: usize, f: &dyn Cost, seed: u64, s: usize, budget: usize) -> Point {
    use cmaes::{CMAESOptions, DVector};
    let mean = start_point(seed, s, d);
    let objective = |x: &DVector<f64>| f.cost(&folded(x.as_slice()));
    let mut cma = CMAESOptions::new(mean.clone(), 0.3)
        .seed(seed.wrapping_add(s as u64))
        .max_function_evals(budget)
        .tol_x(1e-4)
        .tol_fun(0.0)
        .build(objective)
        .expect("valid CMA-ES options");
    loop {
        f.generation(s);
        if cma.next_parallel().is_some() {
            break;
        }
    }
    match cma.overall_best_individual() {
        Some(b) => Point { u: folded(b.point.as_slice()), cost: b.value },
        None => Point { u: mean, cost: f64::INFINITY },
    }
}

/// Nelder–Mead in the box (reflected) from `start`, with a simplex of 2 % of the box.
fn polish(start: &Point, f: &dyn Cost, budget: usize) -> Option<Point> {
    struct Folded<'a>(&'a dyn Cost);
    impl CostFunction for Folded<'_> {
        type Param = Vec<f64>;
        type Output = f64;
        fn cost(&self, x: &Vec<f64>) -> Result<f64, argmin::core::Error> {
            Ok(self.0.cost(&folded(x)))
        }
    }
    let d = start.u.len();
    let mut simplex = vec![start.u.clone()];
    for i in 0..d {
        let mut p = start.u.clone();
        p[i] += if p[i] > 0.5 { -0.02 } else { 0.02 };
        simplex.push(p);
    }
    let nm = NelderMead::new(simplex).with_sd_tolerance(1e-12).ok()?;
    // Each iteration costs one to d + 2 evaluations; stop on the budget of iterations.
    let iters = (budget / 2).max(1) as u64;
    let res = Executor::new(Folded(f), nm).configure(|s| s.max_iters(iters)).run().ok()?;
    let st = res.state();
    let u = folded(st.get_best_param()?);
    Some(Point { u, cost: st.get_best_cost() })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    struct Fun<F: Fn(&[f64]) -> f64 + Sync>(F, AtomicUsize);
    impl<F: Fn(&[f64]) -> f64 + Sync> Cost for Fun<F> {
        fn cost(&self, u: &[f64]) -> f64 {
            self.1.fetch_add(1, Ordering::Relaxed);
            (self.0)(u)
        }
    }

    #[test]
    fn reflection_folds_onto_the_box() {
        for (x, y) in [(0.3, 0.3), (1.2, 0.8), (-0.25, 0.25), (2.5, 0.5), (-1.5, 0.5), (1.0, 1.0)] {
            assert!((reflect(x) - y).abs() < 1e-12, "{x} -> {}", reflect(x));
        }
    }

    #[test]
    fn finds_a_corner_and_an_interior_minimum_within_budget() {
        let f = Fun(
            |u: &[f64]| (u[0] - 0.3).powi(2) + (u[1] - 0.9).powi(2) + 10.0 * (u[2] - 0.0).powi(2),
            AtomicUsize::new(0),
        );
        let o = Options { seed: 3, starts: 2, evaluations: 800, polish: 100 };
        let r = minimize(3, &f, &o);
        assert!(
            (r.best.u[0] - 0.3).abs() < 1e-3 && (r.best.u[1] - 0.9).abs() < 1e-3 && r.best.u[2] < 1e-3,
            "{:?}",
            r.best
        );
        assert!(f.1.load(Ordering::Relaxed) <= 800 + 2 * 100 + 20);
        // Same seed, same answer.
        let again = minimize(3, &f, &o);
        assert_eq!(again.best.u, r.best.u);
    }
}
