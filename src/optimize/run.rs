//! Running an optimisation: the candidates of each generation evaluated in parallel on a
//! local rayon pool, every evaluation kept in a deterministic order (the history), a
//! progress bar showing the best objective, the distinct optima, and for two objectives
//! the Pareto front.

use super::evaluate::{penalised, Evaluation, Evaluator, Status};
use super::local;
use super::search::{self, Cost, Options, Point};
use super::spec::Spec;
use crate::error::{Error, Result};
use crate::progress::{self, Cancel};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// The least step of the best's climb in the unit box: it is a local optimum to 1e-5 of
/// each range (6 µm along the paper beam), the others to 1e-3.
const MIN_STEP: f64 = 1e-5;

/// How to run an optimisation.
#[derive(Clone, Default)]
pub struct RunOptions {
    /// Worker threads (a local pool; `None`: one per available core).
    pub threads: Option<usize>,
    /// Show a progress bar on stderr (never drawn when stderr is not a terminal).
    pub progress: bool,
    /// Called after each evaluation (tests count them).
    pub on_evaluated: Option<Arc<dyn Fn() + Send + Sync>>,
    /// What each candidate may take, held before the search starts ([`Spec::admit`]).
    pub budget: crate::analysis::budget::Budget,
    /// Set to stop: the candidates being solved stop at their next step, no more are
    /// evaluated, and the run ends in [`Error::Cancelled`].
    pub cancel: Option<Cancel>,
    /// Evaluates a candidate elsewhere (another process or machine) instead of here; it
    /// must give what [`Evaluator::evaluate`] of the same spec gives.
    pub evaluate: Option<Remote>,
}

/// A candidate's evaluation done elsewhere: u in the unit box → its [`Evaluation`].
pub type Remote = Arc<dyn Fn(&[f64]) -> Evaluation + Send + Sync>;

/// What an optimisation found.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// The best feasible candidate (two objectives: the front's point nearest the ideal).
    pub best: Evaluation,
    /// Up to `search.top` local optima of the first objective at least `search.distinct`
    /// apart, best first ([`local`]).
    pub optima: Vec<Evaluation>,
    /// Every evaluation, in order (generation by generation).
    pub history: Vec<Evaluation>,
    /// Two objectives: the non-dominated feasible candidates, by the first objective.
    pub pareto: Vec<Evaluation>,
    /// Evaluations by the global search and by the polish.
    pub evaluations: usize,
    pub seconds: f64,
    /// A reduced optimisation's check of its reduction at the optimum.
    pub reduction: Option<crate::sweep::ReductionCheck>,
}

/// The scalar a search minimises: one objective, or the weighted Chebyshev distance of the
/// two from the ideal point, each normalised by its range on the front.
#[derive(Clone, Copy, Debug)]
enum Scalar {
    One(usize),
    Chebyshev { w: [f64; 2], ideal: [f64; 2], range: [f64; 2] },
}

impl Scalar {
    fn of(&self, spec: &Spec, e: &Evaluation) -> f64 {
        match *self {
            Scalar::One(k) => e.cost(spec, k),
            Scalar::Chebyshev { w, ideal, range } => {
                let c = |k: usize| spec.objectives[k].cost(e.values[k]);
                let raw = (w[0] * (c(0) - ideal[0]) / range[0]).max(w[1] * (c(1) - ideal[1]) / range[1]);
                penalised(&e.status, raw)
            }
        }
    }
}

/// Evaluates candidates for a search and keeps them, stamped by generation.
struct Recorder<'a> {
    ev: &'a Evaluator<'a>,
    scalar: Scalar,
    stamp: AtomicU64,
    records: Mutex<Vec<(u64, Evaluation)>>,
    best: Mutex<f64>,
    bar: &'a indicatif::ProgressBar,
    on_evaluated: Option<Arc<dyn Fn() + Send + Sync>>,
    count: AtomicUsize,
    cancel: Option<Cancel>,
    remote: Option<Remote>,
}

impl Cost for Recorder<'_> {
    fn cost(&self, u: &[f64]) -> f64 {
        let solve = || match &self.remote {
            Some(f) => f(u),
            None => self.ev.evaluate(u),
        };
        // What a stopped run would evaluate is of no use: the search winds down unsolved.
        let e = match &self.cancel {
            Some(c) if c.is_cancelled() => return f64::INFINITY,
            Some(c) => progress::cancellable(c.clone(), solve),
            None => solve(),
        };
        let c = self.scalar.of(self.ev.spec, &e);
        if e.feasible() {
            let mut b = self.best.lock().expect("not poisoned");
            let spec = self.ev.spec;
            if b.is_nan() || spec.objectives[0].better(e.values[0], *b) {
                *b = e.values[0];
                self.bar.set_message(format!("{:.6e} {}", e.values[0], spec.objectives[0].unit()));
            }
        }
        let stamp = self.stamp.load(Ordering::SeqCst);
        self.records.lock().expect("not poisoned").push((stamp, e));
        self.count.fetch_add(1, Ordering::Relaxed);
        self.bar.inc(1);
        if let Some(cb) = &self.on_evaluated {
            cb();
        }
        c
    }

    fn generation(&self, _start: usize) {
        self.stamp.fetch_add(1, Ordering::SeqCst);
    }
}

impl Recorder<'_> {
    /// The evaluations so far in a deterministic order: by generation, and within one by
    /// the candidate's bits (the calls of a generation arrive in any order across threads;
    /// the polish runs one candidate per generation).
    fn take(self) -> Vec<Evaluation> {
        let mut r = self.records.into_inner().expect("not poisoned");
        r.sort_by(|a, b| {
            a.0.cmp(&b.0).then_with(|| {
                let ka: Vec<u64> = a.1.u.iter().map(|x| x.to_bits()).collect();
                let kb: Vec<u64> = b.1.u.iter().map(|x| x.to_bits()).collect();
                ka.cmp(&kb)
            })
        });
        r.into_iter().map(|(_, e)| e).collect()
    }
}

/// Runs an optimisation. Placement limits no candidate can meet are refused before anything
/// is solved; when no solved candidate meets the constraints, the error names the one
/// broken most often.
pub fn run(spec: &Spec, opts: &RunOptions) -> Result<RunResult> {
    spec.admit(&opts.budget)?;
    spec.check_limits_can_hold(2000)?;
    let pool = crate::sweep::exec::thread_pool(opts.threads)?;
    let t0 = std::time::Instant::now();
    let ev = Evaluator::new(spec);
    let s = &spec.search;
    let d = spec.variables.len();
    let polish = spec.polish_evaluations();
    let bar = progress_bar(opts.progress, spec.max_evaluations().unwrap_or(u64::MAX));

    let mut session = Session {
        ev: &ev,
        pool: &pool,
        bar: &bar,
        on_evaluated: &opts.on_evaluated,
        cancel: &opts.cancel,
        remote: &opts.evaluate,
        evaluations: 0,
    };
    let search_with = |session: &mut Session, scalar: Scalar, seed: u64, evals: usize| -> Vec<Evaluation> {
        let o = Options { seed, starts: s.starts, evaluations: evals, polish };
        session.record(scalar, |f| search::minimize(d, f, &o)).0
    };
    let stopped = || opts.cancel.as_ref().map_or(Ok(()), Cancel::check);

    let mut history: Vec<Evaluation> = Vec::new();
    let (best, pareto, optima) = if spec.objectives.len() == 1 {
        history = search_with(&mut session, Scalar::One(0), s.seed, s.evaluations);
        stopped()?;
        let best = best_of(spec, &history, Scalar::One(0)).ok_or_else(|| infeasible(spec, &history))?;
        let optima = climb_optima(spec, &mut session, &mut history);
        (optima.first().cloned().unwrap_or(best), Vec::new(), optima)
    } else {
        // The two single-objective optima fix the ideal point and the ranges; the
        // scalarisations in between fill the front.
        let per = s.evaluations;
        for k in 0..2 {
            history.extend(search_with(&mut session, Scalar::One(k), s.seed.wrapping_add(k as u64), per));
            stopped()?;
        }
        let anchors: Vec<Evaluation> = (0..2)
            .map(|k| best_of(spec, &history, Scalar::One(k)).ok_or_else(|| infeasible(spec, &history)))
            .collect::<Result<_>>()?;
        let c = |e: &Evaluation, k: usize| spec.objectives[k].cost(e.values[k]);
        let ideal = [c(&anchors[0], 0), c(&anchors[1], 1)];
        let range = [
            (c(&anchors[1], 0) - ideal[0]).abs().max(f64::MIN_POSITIVE),
            (c(&anchors[0], 1) - ideal[1]).abs().max(f64::MIN_POSITIVE),
        ];
        let n = s.pareto_points;
        for j in 1..n - 1 {
            let w0 = j as f64 / (n - 1) as f64;
            let scalar = Scalar::Chebyshev { w: [w0, 1.0 - w0], ideal, range };
            history.extend(search_with(&mut session, scalar, s.seed.wrapping_add(2 + j as u64), per));
            stopped()?;
        }
        // The climbs' candidates can join the front: they come first.
        let optima = climb_optima(spec, &mut session, &mut history);
        let front = pareto_front(spec, &history);
        let knee = Scalar::Chebyshev { w: [0.5, 0.5], ideal, range };
        let best = best_of(spec, &front, knee).expect("the front has the anchors");
        (best, front, optima)
    };
    stopped()?;
    let evaluations = session.evaluations;
    bar.finish_and_clear();
    let seconds = t0.elapsed().as_secs_f64();
    let reduction = pool.install(|| ev.check_reduction(&best));
    Ok(RunResult { best, optima, history, pareto, evaluations, seconds, reduction })
}

/// What a run's searches share: the evaluator, the pool, the progress bar and the count.
struct Session<'a> {
    ev: &'a Evaluator<'a>,
    pool: &'a rayon::ThreadPool,
    bar: &'a indicatif::ProgressBar,
    on_evaluated: &'a Option<Arc<dyn Fn() + Send + Sync>>,
    cancel: &'a Option<Cancel>,
    remote: &'a Option<Remote>,
    evaluations: usize,
}

impl Session<'_> {
    /// Runs `job` on the pool against the cost `scalar`, and returns every evaluation it
    /// made (in the deterministic order of [`Recorder::take`]) and what it returned.
    fn record<T: Send>(&mut self, scalar: Scalar, job: impl FnOnce(&dyn Cost) -> T + Send) -> (Vec<Evaluation>, T) {
        let rec = Recorder {
            ev: self.ev,
            scalar,
            stamp: AtomicU64::new(0),
            records: Mutex::new(Vec::new()),
            best: Mutex::new(f64::NAN),
            bar: self.bar,
            on_evaluated: self.on_evaluated.clone(),
            count: AtomicUsize::new(0),
            cancel: self.cancel.clone(),
            remote: self.remote.clone(),
        };
        let out = self.pool.install(|| job(&rec));
        self.evaluations += rec.count.load(Ordering::Relaxed);
        (rec.take(), out)
    }
}

/// The first objective's local optima ([`local::local_optima`]), best first, from the
/// history's feasible evaluations: the climbs' evaluations join the history. Never empty
/// when the history has a feasible candidate (the best seen stands in if no climb ends).
fn climb_optima(spec: &Spec, session: &mut Session, history: &mut Vec<Evaluation>) -> Vec<Evaluation> {
    let points: Vec<Point> =
        history.iter().filter(|e| e.feasible()).map(|e| Point { u: e.u.clone(), cost: e.cost(spec, 0) }).collect();
    let Some(first) = points.iter().min_by(|a, b| a.cost.total_cmp(&b.cost)).cloned() else {
        return Vec::new();
    };
    let climb = local::Climb { top: spec.search.top, distinct: spec.search.distinct, min_step: MIN_STEP };
    let (climbed, found) = session.record(Scalar::One(0), |f| local::local_optima(f, &first, &points, &climb));
    history.extend(climbed);
    let evaluation_at = |u: &[f64]| history.iter().find(|e| e.u == u).cloned();
    let optima: Vec<Evaluation> = found.iter().filter_map(|p| evaluation_at(&p.u)).filter(|e| e.feasible()).collect();
    if optima.is_empty() {
        return evaluation_at(&first.u).into_iter().collect();
    }
    optima
}

fn progress_bar(show: bool, len: u64) -> indicatif::ProgressBar {
    if !(show && std::io::stderr().is_terminal()) {
        return indicatif::ProgressBar::hidden();
    }
    let b = indicatif::ProgressBar::with_draw_target(Some(len), indicatif::ProgressDrawTarget::stderr());
    b.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} evaluations, best {msg}",
        )
        .expect("valid template"),
    );
    b
}

/// The feasible evaluation with the least `scalar`.
fn best_of(spec: &Spec, all: &[Evaluation], scalar: Scalar) -> Option<Evaluation> {
    all.iter().filter(|e| e.feasible()).min_by(|a, b| scalar.of(spec, a).total_cmp(&scalar.of(spec, b))).cloned()
}

/// The error for a run in which no candidate met the constraints: the constraint broken
/// by the most candidates, and by how much the closest came.
fn infeasible(spec: &Spec, all: &[Evaluation]) -> Error {
    let mut counts: Vec<(String, usize, String)> = Vec::new();
    let mut add = |name: String, detail: String| match counts.iter_mut().find(|c| c.0 == name) {
        Some(c) => c.1 += 1,
        None => counts.push((name, 1, detail)),
    };
    for e in all {
        match &e.status {
            Status::Feasible => {}
            Status::Limits(v) => {
                let mut seen: Vec<&str> = Vec::new();
                for x in v {
                    if !seen.contains(&x.constraint.as_str()) {
                        add(x.constraint.clone(), x.detail.clone());
                        seen.push(&x.constraint);
                    }
                }
            }
            Status::Bounds(b) => b.iter().for_each(|&(i, x)| {
                add(
                    format!("constraint[{i}].expression"),
                    format!("`{}` missed by {:.3e} (relative)", spec.bounds[i].text, x),
                )
            }),
            Status::Failed(r) => add("base".into(), r.clone()),
        }
    }
    match counts.into_iter().max_by_key(|c| c.1) {
        Some((name, n, detail)) => Error::input(
            &spec.file,
            name,
            format!(
                "infeasible: none of the {} candidates evaluated meets it ({n} break it; e.g. {detail})",
                all.len()
            ),
        ),
        None => Error::Numerical("the optimisation evaluated no candidate".into()),
    }
}

/// The feasible candidates no other feasible candidate dominates (at least as good in both
/// objectives and better in one), by the first objective's cost.
fn pareto_front(spec: &Spec, all: &[Evaluation]) -> Vec<Evaluation> {
    let c = |e: &Evaluation| [spec.objectives[0].cost(e.values[0]), spec.objectives[1].cost(e.values[1])];
    let mut f: Vec<&Evaluation> = all.iter().filter(|e| e.feasible()).collect();
    f.sort_by(|a, b| c(a)[0].total_cmp(&c(b)[0]).then(c(a)[1].total_cmp(&c(b)[1])));
    let mut front: Vec<Evaluation> = Vec::new();
    let mut best1 = f64::INFINITY;
    for e in f {
        if c(e)[1] < best1 {
            best1 = c(e)[1];
            front.push(e.clone());
        }
    }
    front
}
