//! An optimisation's candidates evaluated on other processes (a Dask cluster): a worker
//! evaluates a candidate with the library's evaluator and hands back the evaluation as
//! plain Python values (floats cross exactly, NaN included); the run rebuilds it.

use crate::errors::IntoPy;
use beamflow::optimize::constraint::Violation;
use beamflow::optimize::evaluate::{Evaluation, Evaluator, Status};
use beamflow::optimize::quantity::Outcome;
use beamflow::optimize::run::Remote;
use beamflow::optimize::Spec;
use num_complex::Complex64;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

type Sensors = Vec<(String, Vec<(f64, f64)>)>;
type OutcomeParts = (Vec<Vec<f64>>, Vec<f64>, [f64; 5], Sensors, Vec<f64>, Vec<f64>);
/// (kind, bounds, limits, reason) of a status.
type StatusParts = (String, Vec<(usize, f64)>, Vec<(String, String, f64)>, String);
type EvaluationParts = (Vec<f64>, StatusParts, Vec<f64>, Option<OutcomeParts>);

fn status_parts(s: &Status) -> StatusParts {
    match s {
        Status::Feasible => ("feasible".into(), vec![], vec![], String::new()),
        Status::Bounds(b) => ("bounds".into(), b.clone(), vec![], String::new()),
        Status::Limits(v) => (
            "limits".into(),
            vec![],
            v.iter().map(|v| (v.constraint.clone(), v.detail.clone(), v.amount)).collect(),
            String::new(),
        ),
        Status::Failed(r) => ("failed".into(), vec![], vec![], r.clone()),
    }
}

fn status(p: StatusParts) -> Status {
    match p.0.as_str() {
        "feasible" => Status::Feasible,
        "bounds" => Status::Bounds(p.1),
        "limits" => Status::Limits(
            p.2.into_iter().map(|(constraint, detail, amount)| Violation { constraint, detail, amount }).collect(),
        ),
        _ => Status::Failed(p.3),
    }
}

fn parts(e: &Evaluation) -> EvaluationParts {
    let outcome = e.outcome.as_ref().map(|o| {
        let sensors = o.sensors.iter().map(|(n, w)| (n.clone(), w.iter().map(|c| (c.re, c.im)).collect())).collect();
        let scalars = [o.dissipation, o.balance_error, o.omega0, o.volt2, o.mass];
        (
            o.net_power_harmonic.clone(),
            o.net_power.clone(),
            scalars,
            sensors,
            o.modal_power.clone(),
            o.mode_frequency_hz.clone(),
        )
    });
    (e.u.clone(), status_parts(&e.status), e.values.clone(), outcome)
}

fn evaluation(p: EvaluationParts) -> Evaluation {
    let outcome = p.3.map(|(net_power_harmonic, net_power, s, sensors, modal_power, mode_frequency_hz)| Outcome {
        net_power_harmonic,
        net_power,
        dissipation: s[0],
        balance_error: s[1],
        omega0: s[2],
        volt2: s[3],
        mass: s[4],
        sensors: sensors
            .into_iter()
            .map(|(n, w)| (n, w.into_iter().map(|(re, im)| Complex64::new(re, im)).collect()))
            .collect(),
        modal_power,
        mode_frequency_hz,
    });
    Evaluation { u: p.0, status: status(p.1), values: p.2, outcome }
}

/// An optimisation loaded on a worker, to evaluate its candidates there.
#[pyclass(module = "beamflow._native", frozen)]
pub struct NativeEvaluator {
    spec: Spec,
}

#[pymethods]
impl NativeEvaluator {
    #[new]
    fn new(text: String, name: String, dir: PathBuf) -> PyResult<Self> {
        Ok(NativeEvaluator { spec: Spec::from_str(&text, &name, &dir).py_err()? })
    }

    /// The evaluation of the candidate `u` (unit box), as plain values (GIL released).
    fn evaluate(&self, py: Python<'_>, u: Vec<f64>) -> EvaluationParts {
        py.detach(|| parts(&Evaluator::new(&self.spec).evaluate(&u)))
    }
}

/// A remote evaluation through the Python callable `f(u) -> parts`; a call that raises
/// gives a failed candidate (no values of its `objectives`), the exception its reason.
pub fn remote(f: Py<PyAny>, objectives: usize) -> Remote {
    Arc::new(move |u: &[f64]| {
        Python::attach(|py| {
            let got = f.call1(py, (u.to_vec(),)).and_then(|r| r.extract::<EvaluationParts>(py));
            match got {
                Ok(p) => evaluation(p),
                Err(e) => Evaluation {
                    u: u.to_vec(),
                    status: Status::Failed(format!("evaluation on the cluster failed: {e}")),
                    values: vec![f64::NAN; objectives],
                    outcome: None,
                },
            }
        })
    })
}
