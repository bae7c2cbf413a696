//! Compares the two library optimisers beamflow could use for its placement search, on
//! the benchmark problems of tests/optimize.rs, at equal budgets over ten seeds:
//! `cmaes` (CMA-ES from the best points of a Latin hypercube, as `optimize::search` runs
//! it) and `argmin`'s particle swarm, both followed by the same Nelder–Mead polish. Prints the success rate (the
//! run reaches the grid optimum of the test) and the mean best value. docs/optimize.md
//! quotes the output.
//!
//! `cargo run --release --example optimiser_comparison`

use argmin::core::{CostFunction, Executor, State};
use argmin::solver::particleswarm::ParticleSwarm;
use beamflow::optimize::evaluate::Evaluator;
use beamflow::optimize::search::{self, Cost, Options};
use beamflow::optimize::Spec;
use rand::SeedableRng;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

struct Problem<'a> {
    ev: Evaluator<'a>,
    count: AtomicUsize,
}

impl Cost for Problem<'_> {
    fn cost(&self, u: &[f64]) -> f64 {
        self.count.fetch_add(1, Ordering::Relaxed);
        self.ev.evaluate(u).cost(self.ev.spec, 0)
    }
}

impl CostFunction for &Problem<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, u: &Vec<f64>) -> Result<f64, argmin::core::Error> {
        Ok(Cost::cost(*self, u))
    }
}

fn pso(p: &Problem, d: usize, seed: u64, budget: usize, polish: usize) -> f64 {
    let particles = if d == 1 { 10 } else { 20 };
    let solver = ParticleSwarm::new((vec![0.0; d], vec![1.0; d]), particles)
        .with_rng_generator(rand::rngs::StdRng::seed_from_u64(seed));
    let iters = (budget / particles).saturating_sub(1) as u64;
    let r = Executor::new(p, solver).configure(|s| s.max_iters(iters)).run().expect("PSO runs");
    let st = r.state();
    let best =
        search::Point { u: st.get_best_param().expect("a best point").position.clone(), cost: st.get_best_cost() };
    match search::polish(&best, p, polish) {
        Some(q) if q.cost < best.cost => q.cost,
        _ => best.cost,
    }
}

fn main() {
    let cases = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    let dir = tempfile::tempdir().expect("temp dir");
    let base = std::fs::read_to_string(cases.join("placement-frame.toml")).expect("shipped case");
    std::fs::write(dir.path().join("frame-440Hz.toml"), base.replace("frequency = 60.0", "frequency = 440.0")).unwrap();
    std::fs::copy(cases.join("two-frames.toml"), dir.path().join("two-frames.toml")).unwrap();
    let one = "base = \"frame-440Hz.toml\"\n[search]\nstarts = 3\n[[variable]]\npath = \"actuator[0].x_e\"\nmin = 0.05\nmax = 0.68\n\
               [[objective]]\nquantity = \"net_power\"\n";
    let two = std::fs::read_to_string(cases.join("two_frames.opt.toml")).unwrap();
    // (name, spec, budget, grid optimum of tests/optimize.rs (W))
    let problems = [("1 variable, 440 Hz", one.to_string(), 56, 6.963249e-2), ("3 variables", two, 1500, 2.657182e-1)];
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    for (name, text, budget, grid) in problems {
        let spec = Spec::from_str(&text, name, dir.path()).expect("valid spec");
        let d = spec.variables.len();
        for method in ["cmaes (Latin hypercube + CMA-ES)", "argmin particle swarm"] {
            let (mut ok, mut sum, mut evals) = (0, 0.0, 0);
            let t0 = std::time::Instant::now();
            for seed in 1..=10u64 {
                let p = Problem { ev: Evaluator::new(&spec), count: AtomicUsize::new(0) };
                let best = pool.install(|| match method.starts_with("cmaes") {
                    true => {
                        search::minimize(
                            d,
                            &p,
                            &Options { seed, starts: spec.search.starts, evaluations: budget, polish: 40 * d },
                        )
                        .best
                        .cost
                    }
                    false => pso(&p, d, seed, budget, 40 * d),
                });
                let f = -best;
                ok += (f >= grid * (1.0 - 1e-9)) as usize;
                sum += f;
                evals += p.count.load(Ordering::Relaxed);
            }
            println!(
                "{name}: {method}: reached the grid optimum {ok}/10, mean best {:.5e} W, {:.0} evaluations per run, {:.2} s per run",
                sum / 10.0,
                evals as f64 / 10.0,
                t0.elapsed().as_secs_f64() / 10.0
            );
        }
    }
}
