//! The command line's other commands from Python: `optimize`, `identify dp|bouc-wen|modal`,
//! `synth`, `paper`, `merge` and `sweep --out`, each the library's own function (src/app)
//! run on a worker thread. Arguments left out (None) take the command line's defaults;
//! the library's messages name the command line's flags, which the Python package turns
//! into its argument names.

use crate::background::{self, OnInterrupt};
use crate::errors::IntoPy;
use beamflow::analysis::budget::{parse_bytes, parse_steps, Budget};
use beamflow::app::identify::{self, BoucWenRequest, DpRequest, ModalRequest, SynthRequest};
use beamflow::identify::bouc_wen_fit::{CycleOptions, FitOptions, FitTarget};
use beamflow::identify::dp::DpOptions;
use beamflow::identify::modal_fit::IdentifiedElement;
use beamflow::identify::pso::PsoOptions;
use beamflow::identify::synth::{SynthKind, SynthOptions};
use beamflow::io::measurement::LoadOptions;
use beamflow::optimize::{RunOptions, Spec};
use beamflow::progress;
use beamflow::sweep::{self, Shard, Sweep};
use beamflow::Error;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::Arc;

/// An argument the caller gave that the library does not check itself.
fn argument(field: &str, reason: impl Into<String>) -> PyErr {
    crate::errors::to_py(Error::input("<arguments>", field, reason))
}

/// The budget of `max_memory` (e.g. "8G") and `max_steps` (e.g. "1e9"); None: the default.
pub fn budget(max_memory: Option<String>, max_steps: Option<String>) -> PyResult<Budget> {
    let memory = max_memory.map(|m| parse_bytes(&m).map_err(|r| argument("max_memory", r))).transpose()?;
    let steps = max_steps.map(|s| parse_steps(&s).map_err(|r| argument("max_steps", r))).transpose()?;
    Ok(Budget::with(memory, steps))
}

fn paths(files: &[PathBuf]) -> Vec<String> {
    files.iter().map(|p| p.display().to_string()).collect()
}

/// Runs an optimisation given as TOML text (`name` labels it, `dir` resolves its base
/// case), its candidates evaluated by `remote` (see `remote.rs`) if given; with `out`,
/// writes the command line's output set there. Returns the text files
/// of the output set by name (`best.toml`, `history.csv`, …), the files written, the base
/// case's folder, the evaluations and the seconds taken.
#[pyfunction]
#[pyo3(signature = (text, name, dir, out=None, threads=None, plots=true, max_memory=None, max_steps=None, progress=None, remote=None))]
#[allow(clippy::too_many_arguments)]
pub fn run_optimize<'py>(
    py: Python<'py>,
    text: String,
    name: String,
    dir: PathBuf,
    out: Option<PathBuf>,
    threads: Option<usize>,
    plots: bool,
    max_memory: Option<String>,
    max_steps: Option<String>,
    progress: Option<Bound<'py, PyAny>>,
    remote: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let budget = budget(max_memory, max_steps)?;
    sweep::exec::worker_threads(threads).map_err(|r| argument("threads", r))?;
    let spec = Spec::from_str(&text, &name, &dir).py_err()?;
    let evaluate = remote.map(|f| crate::remote::remote(f, spec.objectives.len()));
    let (texts, files, base_dir, evaluations, seconds) =
        background::watched(py, progress.as_ref(), OnInterrupt::Drop, move |report| {
            let on_evaluated = report.counter("optimize", spec.max_evaluations(), "evaluations");
            let opts = RunOptions {
                threads,
                budget,
                cancel: progress::current_cancel(),
                on_evaluated: Some(on_evaluated),
                evaluate,
                ..Default::default()
            };
            let file = PathBuf::from(&name);
            let (r, files) = beamflow::app::optimize::run_into(&spec, &file, &opts, out.as_deref(), plots)?;
            let texts = beamflow::app::optimize::text_outputs(&spec, &r)?;
            let base_dir = PathBuf::from(&spec.base.file).parent().map(PathBuf::from).unwrap_or_default();
            Ok((texts, files, base_dir, r.evaluations, r.seconds))
        })?
        .0;
    let d = PyDict::new(py);
    d.set_item("texts", texts.into_iter().collect::<Vec<_>>())?;
    d.set_item("files", paths(&files))?;
    d.set_item("base_dir", base_dir)?;
    d.set_item("evaluations", evaluations)?;
    d.set_item("seconds", seconds)?;
    Ok(d)
}

/// `beamflow sweep --out`: runs a sweep given as TOML text into the HDF5 table `out`,
/// resuming from its checkpoints, and writes the CSV and report files beside it. Returns
/// the table's path, the files beside it and the cases computed and reused; the table is
/// read back by the caller.
#[pyfunction]
#[pyo3(signature = (text, name, dir, out, shard=None, threads=None, csv=false, plots=true, max_memory=None, max_steps=None, progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn sweep_into<'py>(
    py: Python<'py>,
    text: String,
    name: String,
    dir: PathBuf,
    out: PathBuf,
    shard: Option<String>,
    threads: Option<usize>,
    csv: bool,
    plots: bool,
    max_memory: Option<String>,
    max_steps: Option<String>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let budget = budget(max_memory, max_steps)?;
    let shard = match &shard {
        Some(s) => Shard::parse(s, "<arguments>", "shard").py_err()?,
        None => Shard::ALL,
    };
    sweep::exec::worker_threads(threads).map_err(|r| argument("threads", r))?;
    let s = Sweep::from_str(&text, &name, &dir).py_err()?;
    let (ex, files) = background::watched(py, progress.as_ref(), OnInterrupt::Drop, move |report| {
        let (total, _) = s.cases_cost(shard);
        let tick = report.counter("sweep", Some(total as u64), "cases");
        let on_evaluated: sweep::OnEvaluated = Arc::new(move |_| tick());
        let opts = sweep::RunOptions {
            threads,
            shard,
            budget,
            cancel: progress::current_cancel(),
            on_evaluated: Some(on_evaluated),
            ..Default::default()
        };
        beamflow::app::sweep::sweep_into(&s, &PathBuf::from(&name), &out, &opts, csv, plots)
    })?
    .0;
    let d = PyDict::new(py);
    d.set_item("files", paths(&files))?;
    d.set_item("computed", ex.computed)?;
    d.set_item("reused", ex.reused)?;
    Ok(d)
}

/// `beamflow merge`: joins shard tables into `out` and writes the files beside it; returns
/// those files.
#[pyfunction]
#[pyo3(signature = (shards, out, csv=false, plots=true))]
pub fn merge(py: Python<'_>, shards: Vec<PathBuf>, out: PathBuf, csv: bool, plots: bool) -> PyResult<Vec<String>> {
    if shards.is_empty() {
        return Err(argument("shards", "give the shard files to merge"));
    }
    let (_, files) = background::run(py, move || beamflow::app::sweep::merge(&shards, &out, csv, plots))?;
    Ok(paths(&files))
}

/// `beamflow paper`: the paper's experiments into `out`.
#[pyfunction]
#[pyo3(signature = (out, csv=false, max_memory=None, max_steps=None, progress=None))]
pub fn paper(
    py: Python<'_>,
    out: PathBuf,
    csv: bool,
    max_memory: Option<String>,
    max_steps: Option<String>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<()> {
    let budget = budget(max_memory, max_steps)?;
    background::watched(py, progress.as_ref(), OnInterrupt::Drop, move |_| {
        beamflow::app::paper::run(&out, csv, &budget)
    })?;
    Ok(())
}

/// What an identification gives back: its result as the JSON the command line writes, the
/// case fragment, the files written and the command line's report.
fn outcome<'py>(
    py: Python<'py>,
    json: String,
    fragment: String,
    written: &[PathBuf],
    report: String,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("json", json)?;
    d.set_item("fragment", fragment)?;
    d.set_item("files", paths(written))?;
    d.set_item("report", report)?;
    Ok(d)
}

fn to_json<T: serde::Serialize>(value: &T) -> String {
    serde_json::to_string_pretty(value).expect("plain data serialises")
}

fn load_options(uniform_tolerance: Option<f64>) -> LoadOptions {
    let d = LoadOptions::default();
    LoadOptions { uniform_tolerance: uniform_tolerance.unwrap_or(d.uniform_tolerance) }
}

fn element(name: Option<&str>) -> PyResult<IdentifiedElement> {
    match name.unwrap_or("stack") {
        "stack" => Ok(IdentifiedElement::Stack),
        "leg" => Ok(IdentifiedElement::Leg),
        "leg_right" => Ok(IdentifiedElement::LegRight),
        other => Err(argument("element", format!("`{other}`: give \"stack\", \"leg\" or \"leg_right\""))),
    }
}

/// `beamflow identify dp`.
#[pyfunction]
#[pyo3(signature = (first, second, k_p=None, offset_tolerance=None, align=true, out=None, plots=true, uniform_tolerance=None))]
#[allow(clippy::too_many_arguments)]
pub fn identify_dp<'py>(
    py: Python<'py>,
    first: PathBuf,
    second: PathBuf,
    k_p: Option<f64>,
    offset_tolerance: Option<f64>,
    align: bool,
    out: Option<PathBuf>,
    plots: bool,
    uniform_tolerance: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = DpOptions::default();
    let req = DpRequest {
        first,
        second,
        options: DpOptions { offset_tolerance: offset_tolerance.unwrap_or(d.offset_tolerance), align, k_p, ..d },
        load: load_options(uniform_tolerance),
        out,
        plots,
    };
    let o = background::run(py, move || identify::identify_dp(&req))?;
    outcome(py, to_json(&o.estimate), o.fragment.clone(), &o.written, o.report())
}

/// `beamflow identify bouc-wen`.
#[pyfunction]
#[pyo3(signature = (file, d_p, target=None, k_p=None, seeds=None, period=None, cycles=None, particles=None, max_iterations=None, out=None, plots=true, uniform_tolerance=None, max_memory=None, max_steps=None))]
#[allow(clippy::too_many_arguments)]
pub fn identify_bouc_wen<'py>(
    py: Python<'py>,
    file: PathBuf,
    d_p: f64,
    target: Option<String>,
    k_p: Option<f64>,
    seeds: Option<Vec<u64>>,
    period: Option<f64>,
    cycles: Option<usize>,
    particles: Option<usize>,
    max_iterations: Option<usize>,
    out: Option<PathBuf>,
    plots: bool,
    uniform_tolerance: Option<f64>,
    max_memory: Option<String>,
    max_steps: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let target = match (target.as_deref().unwrap_or("stroke"), k_p) {
        ("stroke", _) => FitTarget::Stroke,
        ("force", Some(k_p)) => FitTarget::BlockedForce { k_p },
        ("force", None) => return Err(argument("k_p", "target=\"force\" needs the stack stiffness k_p (N/m)")),
        (other, _) => return Err(argument("target", format!("`{other}`: give \"stroke\" or \"force\""))),
    };
    let (pso, cycle) = (PsoOptions::default(), CycleOptions::default());
    let req = BoucWenRequest {
        file,
        target,
        cycle: CycleOptions { period, cycles: cycles.unwrap_or(cycle.cycles) },
        fit: FitOptions {
            pso: PsoOptions {
                particles: particles.unwrap_or(pso.particles),
                max_iterations: max_iterations.unwrap_or(pso.max_iterations),
                ..pso
            },
            budget: budget(max_memory, max_steps)?,
            ..FitOptions::new(d_p)
        },
        seeds: seeds.unwrap_or_else(|| vec![1, 2, 3]),
        load: load_options(uniform_tolerance),
        out,
        plots,
    };
    let o = background::run(py, move || identify::identify_bouc_wen(&req))?;
    outcome(py, to_json(&o), o.fragment.clone(), &o.written, o.report())
}

/// `beamflow identify modal`.
#[pyfunction]
#[pyo3(signature = (file, mass, modes=None, band=None, element=None, use_mode=None, segment=None, exp_window=None, force_window=None, min_coherence=None, out=None, plots=true, uniform_tolerance=None))]
#[allow(clippy::too_many_arguments)]
pub fn identify_modal<'py>(
    py: Python<'py>,
    file: PathBuf,
    mass: f64,
    modes: Option<usize>,
    band: Option<(f64, f64)>,
    element: Option<String>,
    use_mode: Option<usize>,
    segment: Option<usize>,
    exp_window: Option<f64>,
    force_window: Option<f64>,
    min_coherence: Option<f64>,
    out: Option<PathBuf>,
    plots: bool,
    uniform_tolerance: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = ModalRequest::new(file, mass, self::element(element.as_deref())?);
    let req = ModalRequest {
        modes: modes.unwrap_or(d.modes),
        band,
        use_mode: use_mode.unwrap_or(d.use_mode),
        segment,
        exp_window,
        force_window,
        min_coherence: min_coherence.unwrap_or(d.min_coherence),
        load: load_options(uniform_tolerance),
        out,
        plots,
        ..d
    };
    let o = background::run(py, move || identify::identify_modal(&req))?;
    outcome(py, to_json(&o), o.fragment.clone(), &o.written, o.report())
}

/// `beamflow synth`: synthetic measurements of the case file `case`, written as CSV to
/// `out`. Returns the files, their samples, the parameters they were made with (JSON) and
/// the command line's report.
#[pyfunction]
#[pyo3(signature = (case, out, kind=None, noise=None, voltage_noise=None, seed=None, actuator=None, periods=None, samples_per_period=None, offset=None, element=None, mass=None, hits=None, digits=Some(7), max_memory=None, max_steps=None))]
#[allow(clippy::too_many_arguments)]
pub fn synth<'py>(
    py: Python<'py>,
    case: PathBuf,
    out: PathBuf,
    kind: Option<String>,
    noise: Option<f64>,
    voltage_noise: Option<f64>,
    seed: Option<u64>,
    actuator: Option<String>,
    periods: Option<usize>,
    samples_per_period: Option<usize>,
    offset: Option<f64>,
    element: Option<String>,
    mass: Option<f64>,
    hits: Option<usize>,
    digits: Option<usize>,
    max_memory: Option<String>,
    max_steps: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let kind = match kind.as_deref().unwrap_or("stroke") {
        "stroke" => SynthKind::Stroke,
        "blocked_force" => SynthKind::BlockedForce,
        "impact" => SynthKind::Impact,
        "dp_pair" => SynthKind::DpPair,
        other => {
            return Err(argument(
                "kind",
                format!("`{other}`: give \"stroke\", \"blocked_force\", \"impact\" or \"dp_pair\""),
            ))
        }
    };
    let d = SynthOptions::default();
    let req = SynthRequest {
        case,
        out,
        options: SynthOptions {
            kind,
            actuator,
            noise: noise.unwrap_or(d.noise),
            voltage_noise: voltage_noise.unwrap_or(d.voltage_noise),
            seed: seed.unwrap_or(d.seed),
            periods: periods.unwrap_or(d.periods),
            samples_per_period: samples_per_period.unwrap_or(d.samples_per_period),
            offset,
            element: self::element(element.as_deref())?,
            mass,
            hits: hits.unwrap_or(d.hits),
            budget: budget(max_memory, max_steps)?,
            ..d
        },
        // 0 digits: the shortest exact form, as on the command line.
        digits: digits.filter(|&n| n > 0),
    };
    let o = background::run(py, move || identify::synth(&req))?;
    let d = PyDict::new(py);
    d.set_item("files", paths(&o.files))?;
    d.set_item("samples", o.samples.clone())?;
    d.set_item("truth", to_json(&o.truth))?;
    d.set_item("report", o.report())?;
    Ok(d)
}
