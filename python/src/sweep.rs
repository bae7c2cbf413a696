//! `beamflow.sweep`: a sweep file (or the same as a dict) run on the library's parallel
//! sweep, its table handed back as named numpy columns.

use crate::background;
use crate::background::OnInterrupt;
use crate::convert::array;
use crate::errors::IntoPy;
use beamflow::progress;
use beamflow::sweep::{self, OnEvaluated, RunOptions, Sweep, SweepTable};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;
use std::sync::Arc;

/// The table as `{"columns": [(name, array, unit, description), …], "meta": {…}}`.
/// Columns: `case`, each parameter by its path, `net_power[<actuator>]`,
/// `mean_power[<link>]`, `force_amplitude[<link>]`, `beam_dissipation`, `balance_error`.
fn table<'py>(py: Python<'py>, t: &SweepTable) -> PyResult<Bound<'py, PyDict>> {
    let n = t.rows.len();
    let cols = PyList::empty(py);
    let push = |name: String, data: Vec<f64>, unit: &str, desc: String| -> PyResult<()> {
        cols.append((name, array(py, data, &[n])?, unit, desc))
    };
    let idx: Vec<i64> = t.rows.iter().map(|r| r.index as i64).collect();
    cols.append(("case", array(py, idx, &[n])?, "1", "case index in the whole sweep"))?;
    for (k, p) in t.parameters.iter().enumerate() {
        push(p.clone(), t.rows.iter().map(|r| r.inputs[k]).collect(), &t.units[k], format!("swept case field `{p}`"))?;
    }
    for (a, name) in t.actuators.iter().enumerate() {
        let d = format!("net mean power into the beam of actuator `{name}`");
        push(format!("net_power[{name}]"), t.rows.iter().map(|r| r.net_power[a]).collect(), "W", d)?;
    }
    for (l, name) in t.links.iter().enumerate() {
        let d = format!("mean power into the beam at the foot of `{name}`");
        push(format!("mean_power[{name}]"), t.rows.iter().map(|r| r.mean_power[l]).collect(), "W", d)?;
    }
    for (l, name) in t.links.iter().enumerate() {
        let d = format!("transmitted force amplitude at the drive's fundamental, `{name}`");
        push(format!("force_amplitude[{name}]"), t.rows.iter().map(|r| r.force_amplitude[l]).collect(), "N", d)?;
    }
    let d = "mean power dissipated by the beam's damping".to_string();
    push("beam_dissipation".into(), t.rows.iter().map(|r| r.beam_dissipation).collect(), "W", d)?;
    let d = "relative energy-balance error (net input vs beam dissipation)".to_string();
    push("balance_error".into(), t.rows.iter().map(|r| r.balance_error).collect(), "1", d)?;
    let meta = PyDict::new(py);
    meta.set_item("title", &t.title)?;
    meta.set_item("sweep_file", &t.sweep_file)?;
    meta.set_item("sweep_hash", &t.hash)?;
    meta.set_item("analysis", &t.analysis)?;
    meta.set_item("harmonics", t.harmonics)?;
    meta.set_item("samples_per_period", t.samples_per_period)?;
    meta.set_item("total_cases", t.total_cases)?;
    meta.set_item("parameters", t.parameters.clone())?;
    meta.set_item("actuators", t.actuators.clone())?;
    meta.set_item("links", t.links.clone())?;
    let out = PyDict::new(py);
    out.set_item("columns", cols)?;
    out.set_item("meta", meta)?;
    Ok(out)
}

/// Runs a sweep given as TOML text; `name` labels it in messages, `dir` resolves its `base`.
/// `progress` is called with the cases done. Ctrl-C stops it: the cases running stop at
/// their next step, and the rows finished come back with the `KeyboardInterrupt`, as
/// `(table, exception)` (`exception` None when the sweep ran to the end).
#[pyfunction]
#[pyo3(signature = (text, name, dir, threads=None, max_memory=None, max_steps=None, progress=None))]
pub fn run_sweep<'py>(
    py: Python<'py>,
    text: String,
    name: String,
    dir: PathBuf,
    threads: Option<usize>,
    max_memory: Option<String>,
    max_steps: Option<String>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<(Bound<'py, PyDict>, Option<Py<PyAny>>)> {
    let budget = crate::commands::budget(max_memory, max_steps)?;
    let s = Sweep::from_str(&text, &name, &dir).py_err()?;
    let (t, interrupt) = background::watched(py, progress.as_ref(), OnInterrupt::Keep, move |report| {
        let tick = report.counter("sweep", Some(s.len() as u64), "cases");
        let on_evaluated: OnEvaluated = Arc::new(move |_| tick());
        let opts = RunOptions {
            threads,
            budget,
            cancel: progress::current_cancel(),
            on_evaluated: Some(on_evaluated),
            ..Default::default()
        };
        sweep::run(&s, &opts)
    })?;
    Ok((table(py, &t)?, interrupt.map(|e| e.into_value(py).into_any())))
}

/// Reads a sweep table written by `beamflow sweep` (or `merge`).
#[pyfunction]
pub fn read_sweep_table(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyDict>> {
    let t = background::run(py, move || SweepTable::read(&path))?;
    table(py, &t)
}
