//! The global search over the unit box [0, 1]^d and its local polish, on library
//! optimisers: CMA-ES (`cmaes`) from seeded random starts, then Nelder–Mead (`argmin`)
//! from the best point. The cost is evaluated in parallel over each generation's
//! candidates (rayon, on the caller's pool); every random number comes from the seed, and a
//! candidate's cost depends on nothing else, so the result does not depend on the thread
//! count.

use argmin::core::{CostFunction, Executor};
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

/// A seeded Latin hypercube of `n` points in [0, 1]^d: each variable's range cut into n
/// equal cells, one point in each, the cells paired across variables at random.
fn latin_hypercube(seed: u64, n: usize, d: usize) -> Vec<Vec<f64>> {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut pts = vec![vec![0.0; d]; n];
    for j in 0..d {
        let mut cells: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            cells.swap(i, rng.random_range(0..=i));
        }
        for (p, c) in pts.iter_mut().zip(cells) {
            p[j] = (c as f64 + rng.random::<f64>()) / n as f64;
        }
    }
    pts
}

/// Minimises `f` over [0, 1]^d in three phases: a seeded Latin hypercube (a fifth of the
/// evaluations, at least four points per start) to see the whole box; CMA-ES from each of
/// the `starts` best sample points that lie at least 0.1 apart (step 0.1, its share of the
/// rest of the evaluations; it stops early when its step falls below 1e-4 of the box);
/// then Nelder–Mead from the two best points found.
pub fn minimize(d: usize, f: &dyn Cost, opts: &Options) -> Found {
    use rayon::prelude::*;
    let n0 = (opts.evaluations * 2 / 5).max(4 * opts.starts);
    let sample = latin_hypercube(opts.seed, n0, d);
    f.generation(0);
    let costs: Vec<f64> = sample.par_iter().map(|u| f.cost(u)).collect();
    let mut order: Vec<usize> = (0..n0).collect();
    order.sort_by(|&a, &b| costs[a].total_cmp(&costs[b]));
    let mut means: Vec<usize> = Vec::new();
    for &i in &order {
        if means.len() < opts.starts && means.iter().all(|&j| super::local::distance(&sample[i], &sample[j]) >= 0.1) {
            means.push(i);
        }
    }
    // Too few distinct points (a tiny box sample): the next best ones.
    for &i in &order {
        if means.len() < opts.starts && !means.contains(&i) {
            means.push(i);
        }
    }
    let per_start = opts.evaluations.saturating_sub(n0) / opts.starts.max(1);
    let mut starts = Vec::with_capacity(opts.starts);
    for (s, &i) in means.iter().enumerate() {
        let p = cmaes_start(f, &sample[i], opts.seed, s, per_start);
        starts.push(if p.cost <= costs[i] { p } else { Point { u: sample[i].clone(), cost: costs[i] } });
    }
    // Near-equal optima in different places are told apart only once both are converged:
    // the two best starts are polished (half the budget each).
    let mut ranked: Vec<&Point> = starts.iter().collect();
    ranked.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    let mut best = ranked[0].clone();
    if opts.polish > 0 {
        let n = ranked.len().min(2);
        for (k, p) in ranked.iter().take(n).enumerate() {
            f.generation(opts.starts + 1 + k);
            if let Some(q) = polish(p, f, opts.polish / n) {
                if q.cost < best.cost {
                    best = q;
                }
            }
        }
    }
    Found { best, starts }
}

fn cmaes_start(f: &dyn Cost, mean: &[f64], seed: u64, s: usize, budget: usize) -> Point {
    use cmaes::{CMAESOptions, DVector};
    let mean = mean.to_vec();
    let objective = |x: &DVector<f64>| f.cost(&folded(x.as_slice()));
    let mut cma = CMAESOptions::new(mean.clone(), 0.1)
        .seed(seed.wrapping_add(s as u64))
        .max_function_evals(budget)
        .tol_x(1e-4)
        .tol_fun(0.0)
        .build(objective)
        .expect("valid CMA-ES options");
    loop {
        f.generation(s + 1);
        if cma.next_parallel().is_some() {
            break;
        }
    }
    match cma.overall_best_individual() {
        Some(b) => Point { u: folded(b.point.as_slice()), cost: b.value },
        None => Point { u: mean, cost: f64::INFINITY },
    }
}

/// Nelder–Mead in the box (reflected) from `start`, with a simplex of 2 % of the box, for
/// at most `budget` evaluations (the cost refuses more, which ends the run; the best point
/// seen is kept here, not taken from the solver).
pub fn polish(start: &Point, f: &dyn Cost, budget: usize) -> Option<Point> {
    struct Budgeted<'a> {
        f: &'a dyn Cost,
        left: &'a std::sync::atomic::AtomicUsize,
        best: &'a std::sync::Mutex<Option<Point>>,
    }
    impl CostFunction for Budgeted<'_> {
        type Param = Vec<f64>;
        type Output = f64;
        fn cost(&self, x: &Vec<f64>) -> Result<f64, argmin::core::Error> {
            use std::sync::atomic::Ordering;
            if self.left.fetch_update(Ordering::SeqCst, Ordering::SeqCst, |n| n.checked_sub(1)).is_err() {
                return Err(argmin::core::Error::msg("evaluation budget spent"));
            }
            let u = folded(x);
            let c = self.f.cost(&u);
            let mut b = self.best.lock().expect("not poisoned");
            if b.as_ref().is_none_or(|p| c < p.cost) {
                *b = Some(Point { u, cost: c });
            }
            Ok(c)
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
    let (left, best) = (budget.into(), None.into());
    let problem = Budgeted { f, left: &left, best: &best };
    // The run ends on the budget (an error by design) or on convergence: either way the
    // best point is the one kept above.
    let _ = Executor::new(problem, nm).configure(|s| s.max_iters(budget as u64)).run();
    best.into_inner().expect("not poisoned")
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
