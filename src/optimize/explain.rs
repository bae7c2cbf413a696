//! What explains an optimum: the objective along each variable through it (the others held
//! at the optimum), and the mode-resolved power of the optimum beside a poor placement.

use super::evaluate::{Evaluation, Evaluator};
use super::spec::{Domain, Spec};
use rayon::prelude::*;

/// The objective along one variable through the optimum.
#[derive(Clone, Debug)]
pub struct Profile {
    pub variable: String,
    pub unit: &'static str,
    /// Variable values and the objective there (feasible candidates only), by x.
    pub x: Vec<f64>,
    pub f: Vec<f64>,
    /// Indices i where infeasible candidates lie between point i − 1 and point i.
    pub gaps: Vec<usize>,
    /// The optimum: its value of the variable and its objective.
    pub x_best: f64,
    pub f_best: f64,
}

/// Extra points on each side of the optimum, within one grid cell: a resonant optimum is
/// narrower than the grid, and a profile that misses its top misstates it.
const NEAR_OPTIMUM: usize = 6;

/// Power into each mode of the bare structure (W) of the best and of a poor candidate.
#[derive(Clone, Debug)]
pub struct ModalComparison {
    pub mode_frequency_hz: Vec<f64>,
    pub best: Vec<f64>,
    pub poor: Vec<f64>,
    /// The structure whose modes they are: `beam`, `plate` or `imported model`.
    pub structure: &'static str,
    /// The candidates' objective values with their unit (`26.43 mW`).
    pub best_label: String,
    pub poor_label: String,
    /// Each variable: its name in words (`position x, frame`) and its value with its unit
    /// at the best and at the poor candidate (`93.17 mm`).
    pub variables: Vec<[String; 3]>,
}

/// Profiles of objective 0 through `best`, `points` per real variable evenly spaced plus
/// the optimum itself and [`NEAR_OPTIMUM`] points on each side of it within one spacing
/// (one per value for integers and choices), evaluated in parallel on the caller's pool.
pub fn profiles(spec: &Spec, best: &Evaluation, points: usize) -> Vec<Profile> {
    let ev = Evaluator::new(spec);
    spec.variables
        .iter()
        .enumerate()
        .map(|(i, var)| {
            let us: Vec<f64> = match &var.domain {
                Domain::Real { .. } => real_points(best.u[i], points),
                Domain::Integer { min, max } => (*min..=*max).map(|x| var.unit_of(x as f64)).collect(),
                Domain::Choice(v) => (0..v.len()).map(|x| var.unit_of(x as f64)).collect(),
            };
            let evals: Vec<Evaluation> = us
                .par_iter()
                .map(|&x| {
                    let mut u = best.u.clone();
                    u[i] = x;
                    ev.evaluate(&u)
                })
                .collect();
            let (mut x, mut f, mut gaps) = (Vec::new(), Vec::new(), Vec::new());
            for e in &evals {
                if !e.feasible() {
                    if !x.is_empty() && gaps.last() != Some(&x.len()) {
                        gaps.push(x.len());
                    }
                    continue;
                }
                x.push(var.number(e.u[i]));
                f.push(e.values[0]);
            }
            gaps.retain(|&g| g < x.len());
            let (x_best, f_best) = (var.number(best.u[i]), best.values[0]);
            Profile { variable: var.name.clone(), unit: var.unit(), x, f, gaps, x_best, f_best }
        })
        .collect()
}

/// `points` evenly spaced in [0, 1], the optimum `at` and points near it, sorted.
fn real_points(at: f64, points: usize) -> Vec<f64> {
    let h = 1.0 / (points - 1) as f64;
    let mut us: Vec<f64> = (0..points).map(|j| j as f64 * h).collect();
    us.push(at);
    for k in 1..=NEAR_OPTIMUM {
        let d = h * k as f64 / (NEAR_OPTIMUM + 1) as f64;
        us.extend([at - d, at + d].into_iter().filter(|u| (0.0..=1.0).contains(u)));
    }
    us.sort_by(f64::total_cmp);
    us.dedup();
    us
}

/// The mode-resolved power of `best` and of the worst feasible candidate of `history`, in
/// the first `modes` bare-beam modes. None if no candidate can be decomposed (no beam).
pub fn modal_comparison(
    spec: &Spec,
    best: &Evaluation,
    history: &[Evaluation],
    modes: usize,
) -> Option<ModalComparison> {
    let poor = history.iter().filter(|e| e.feasible()).max_by(|a, b| a.cost(spec, 0).total_cmp(&b.cost(spec, 0)))?;
    let ev = Evaluator::with_modes(spec, modes);
    let (b, p) = rayon::join(|| ev.evaluate(&best.u), || ev.evaluate(&poor.u));
    let (ob, op) = (b.outcome?, p.outcome?);
    if ob.modal_power.is_empty() {
        return None;
    }
    let unit = spec.objectives[0].unit();
    let variables = spec
        .variables
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let name = crate::report::sweep::axis_text(&v.name, "1", &spec.base.actuators);
            [name, value_text(v.value(best.u[i]), v.unit()), value_text(v.value(poor.u[i]), v.unit())]
        })
        .collect();
    Some(ModalComparison {
        mode_frequency_hz: ob.mode_frequency_hz,
        best: ob.modal_power,
        poor: op.modal_power,
        structure: structure_name(&spec.base.case),
        best_label: crate::report::plot::text::quantity(best.values[0], &unit),
        poor_label: crate::report::plot::text::quantity(poor.values[0], &unit),
        variables,
    })
}

/// The structure of a case in words: `beam`, `plate` or `imported model`.
fn structure_name(case: &crate::case::Case) -> &'static str {
    if case.imported.is_some() {
        "imported model"
    } else if case.plate.is_some() {
        "plate"
    } else {
        "beam"
    }
}

/// A variable's value with its unit, as a reader writes it: `93.17 mm`, `179.9°`, `31`.
fn value_text(v: toml::Value, unit: &str) -> String {
    match v {
        toml::Value::Float(f) => crate::report::plot::text::quantity(f, unit),
        toml::Value::String(s) => s,
        other => other.to_string(),
    }
}
