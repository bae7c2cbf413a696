//! One candidate evaluated: its case built from the base, the placement and drive limits
//! checked, the periodic steady state solved in the sweep's headline mode, and the result
//! quantities, objectives and constraint margins computed.

use super::constraint::{peak_voltage, Violation};
use super::quantity::Outcome;
use super::spec::Spec;
use crate::analysis::drive::StackForceCache;
use crate::analysis::plan::calibrated_model;
use crate::analysis::steady_state::{self, Detail, HarmonicSolver};
use crate::case::LoadedCase;
use crate::power::modal::{decompose, ModalDamping};
use crate::power::point::net_power;
use crate::sweep::reduced::StudySystems;
use num_complex::Complex64;
use std::f64::consts::PI;

/// Costs of candidates the optimiser must avoid, far above any objective: a broken
/// result bound, a broken placement limit, a case that cannot be solved. Ranking-based
/// searches only compare them, so the margin by which a limit is broken is kept in the
/// factor (1 + margin).
const BROKEN_BOUND: f64 = 1e30;
const BROKEN_LIMIT: f64 = 1e60;
const UNSOLVABLE: f64 = 1e90;

/// What became of one candidate.
#[derive(Clone, Debug)]
pub enum Status {
    /// Solved and within every constraint.
    Feasible,
    /// Solved, but these result bounds (index, relative excess) are broken.
    Bounds(Vec<(usize, f64)>),
    /// Not solved: these placement or drive limits are broken.
    Limits(Vec<Violation>),
    /// Not solved: the case is refused or the solver failed (the reason).
    Failed(String),
}

/// One evaluated candidate.
#[derive(Clone, Debug)]
pub struct Evaluation {
    /// The candidate in the unit box, one coordinate per variable.
    pub u: Vec<f64>,
    pub status: Status,
    /// The objectives' values (NaN where not solved).
    pub values: Vec<f64>,
    pub outcome: Option<Outcome>,
}

impl Evaluation {
    pub fn feasible(&self) -> bool {
        matches!(self.status, Status::Feasible)
    }

    /// The cost of objective `k` for a minimiser, with the constraint penalties.
    pub fn cost(&self, spec: &Spec, k: usize) -> f64 {
        penalised(&self.status, spec.objectives[k].cost(self.values[k]))
    }
}

/// The cost with the penalty of `status` (`raw`: the objective's own cost).
pub fn penalised(status: &Status, raw: f64) -> f64 {
    match status {
        Status::Feasible => raw,
        Status::Bounds(b) => BROKEN_BOUND * (1.0 + b.iter().map(|x| x.1).sum::<f64>()),
        Status::Limits(v) => BROKEN_LIMIT * (1.0 + v.iter().map(|x| x.amount).sum::<f64>()),
        Status::Failed(_) => UNSOLVABLE,
    }
}

/// Evaluates candidates of one optimisation; shared by the threads (the stack-force cache
/// is filled by whichever thread needs a drive first, which changes no bit).
#[derive(Debug)]
pub struct Evaluator<'s> {
    pub spec: &'s Spec,
    forces: StackForceCache,
    /// Bare-beam modes to decompose the power into (0: none).
    modes: usize,
    /// The systems candidates are solved on: the base case's reduction, or (with modes to
    /// decompose into, which need the structure's own DOFs) the full system.
    systems: StudySystems,
}

impl<'s> Evaluator<'s> {
    pub fn new(spec: &'s Spec) -> Self {
        Self::with_modes(spec, 0)
    }

    /// The same, decomposing the power into at least `modes` bare-beam modes (figures).
    pub fn with_modes(spec: &'s Spec, modes: usize) -> Self {
        let modes = modes.max(spec.modes);
        let systems = match modes {
            0 => StudySystems::new(&spec.file, &spec.base, spec.harmonics, spec.extremes()),
            _ => StudySystems::full(spec.harmonics),
        };
        Evaluator { spec, forces: StackForceCache::default(), modes, systems }
    }

    /// An optimisation on a shared reduction checks it: candidate `e` (the optimum) solved
    /// again on the full model, its net powers and dissipation compared with the reduced
    /// ones (as point powers are in a sweep's check). None without a shared reduction, or
    /// where the full model cannot be solved.
    pub fn check_reduction(&self, e: &Evaluation) -> Option<crate::sweep::ReductionCheck> {
        let reduced = e.outcome.as_ref()?;
        let shared = self.systems.shared()?;
        let full = Evaluator {
            spec: self.spec,
            forces: StackForceCache::default(),
            modes: 0,
            systems: StudySystems::full(self.spec.harmonics),
        };
        let f = full.evaluate(&e.u).outcome?;
        let error = crate::analysis::reduction::ReductionError::between(
            self.spec.harmonics,
            (&[f.dissipation], &f.net_power),
            (&[reduced.dissipation], &reduced.net_power),
        );
        Some(crate::sweep::ReductionCheck {
            cutoff_hz: shared.cutoff_hz(),
            modes_kept: shared.modes_kept(),
            case: None,
            max_relative_error: error.largest(),
        })
    }

    /// Evaluates candidate `u`.
    pub fn evaluate(&self, u: &[f64]) -> Evaluation {
        let spec = self.spec;
        let n = spec.objectives.len();
        let fail = |status: Status| Evaluation { u: u.to_vec(), status, values: vec![f64::NAN; n], outcome: None };
        let case = match spec.case_of(u) {
            Ok(c) => c,
            Err(r) => return fail(Status::Failed(r)),
        };
        let broken = spec.limits.violations(&case);
        if !broken.is_empty() {
            return fail(Status::Limits(broken));
        }
        let outcome = match self.solve(case) {
            Ok(o) => o,
            Err(r) => return fail(Status::Failed(r)),
        };
        let values: Vec<f64> = spec.objectives.iter().map(|o| o.value(&outcome).unwrap_or(f64::NAN)).collect();
        if values.iter().any(|v| !v.is_finite()) {
            return Evaluation {
                status: Status::Failed("an objective is not finite".into()),
                ..fail(Status::Feasible)
            };
        }
        let broken: Vec<(usize, f64)> = spec
            .bounds
            .iter()
            .enumerate()
            .filter_map(|(i, b)| match b.violation(&outcome) {
                Ok(x) if x > 0.0 => Some((i, x)),
                Ok(_) => None,
                Err(_) => Some((i, f64::INFINITY)),
            })
            .collect();
        let status = if broken.is_empty() { Status::Feasible } else { Status::Bounds(broken) };
        Evaluation { u: u.to_vec(), status, values, outcome: Some(outcome) }
    }

    /// Builds and solves the case, and gathers what the quantities read.
    fn solve(&self, case: crate::case::Case) -> std::result::Result<Outcome, String> {
        let spec = self.spec;
        let s = |e: crate::Error| e.to_string();
        let lc = LoadedCase::unwritten(case, &format!("{} [candidate]", spec.base.file), spec.base.dir.clone())
            .map_err(s)?;
        let model = &calibrated_model(&lc).map_err(s)?;
        let sys = self.systems.system(model, &lc.file).map_err(s)?.0;
        let mut solver = HarmonicSolver::new(&sys);
        let r = steady_state::run_with(
            model,
            &mut solver,
            spec.harmonics,
            spec.samples_per_period,
            Detail::Headline(&self.forces),
        )
        .map_err(s)?;
        let n_act = model.actuators.len();
        let nk = r.harmonics + 1;
        let per_harmonic: Vec<Vec<f64>> = (0..nk)
            .map(|k| {
                let p: Vec<f64> = r.spectra.iter().map(|sp| sp.power[k]).collect();
                net_power(&sys.links, &p, n_act)
            })
            .collect();
        let net_power_harmonic = (0..n_act).map(|a| per_harmonic.iter().map(|p| p[a]).collect()).collect();
        let omega0 = 2.0 * PI / r.period;
        let mut sensors = Vec::new();
        for se in &model.sensors {
            let pattern = sys.w_at(model, &se.at, "sensor.x").map_err(s)?;
            let w: Vec<Complex64> = solver.q.iter().map(|qk| pattern.iter().map(|&(d, c)| qk[d] * c).sum()).collect();
            sensors.push((se.name.clone(), w));
        }
        let (mut modal_power, mut mode_frequency_hz) = (Vec::new(), Vec::new());
        if self.modes > 0 {
            if let Some(m) = crate::analysis::modes::few_bare_modes_on(model, &sys, self.modes).map_err(s)? {
                let interface: Vec<Vec<Complex64>> = r.spectra.iter().map(|sp| sp.interface.clone()).collect();
                let loads: Vec<Vec<Complex64>> = r.load_spectra.iter().map(|l| l.force.clone()).collect();
                let damping = ModalDamping::of_model(model, &sys);
                let d = decompose(&sys, &m, damping, (&solver.q, omega0), &interface, &loads);
                modal_power = (0..m.count()).map(|k| d.point_power.iter().map(|p| p[k]).sum()).collect();
                mode_frequency_hz = d.mode_frequency_hz;
            }
        }
        let acts = &lc.case.actuator;
        Ok(Outcome {
            net_power_harmonic,
            net_power: r.net_power,
            dissipation: r.beam_dissipation,
            balance_error: r.balance_error,
            omega0,
            sensors,
            modal_power,
            mode_frequency_hz,
            volt2: acts.iter().map(|a| peak_voltage(&a.voltage).powi(2)).sum(),
            mass: acts.iter().map(|a| a.stack.m_p + a.body_mass()).sum(),
        })
    }
}
