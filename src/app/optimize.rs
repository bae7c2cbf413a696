//! `beamflow optimize`: runs an optimisation and writes what it found — the best case as a
//! runnable case file, the convergence history, the distinct optima (and the Pareto front
//! for two objectives), a JSON summary and the figures that explain the optimum — as one
//! output set (io::output_set).

use crate::analysis::budget::Budget;
use crate::error::{Error, Result};
use crate::io::atomic::write_atomic_string;
use crate::io::paths::{output_file, refuse_input, Input};
use crate::optimize::evaluate::Evaluation;
use crate::optimize::{self, RunOptions, RunResult, Spec};
use crate::report::sweep::num;
use crate::sweep::field::set_path;
use std::path::{Path, PathBuf};

/// Every file an optimisation may write into its output folder.
const TEXT_OUTPUTS: [&str; 6] = ["best.toml", "history.csv", "optima.csv", "pareto.csv", "summary.json", REPORT];

/// The figures of a run (each written in every figure format).
const FIGURES: [&str; 3] = ["profiles", "modes", "pareto"];

/// The run's report: its best case, optima and figures on one page.
const REPORT: &str = "report.html";

/// Every file a run may write into its folder.
fn outputs() -> Vec<String> {
    let figures = FIGURES.iter().flat_map(|f| crate::report::plot::Format::ALL.map(|x| format!("{f}.{}", x.ext())));
    TEXT_OUTPUTS.iter().map(|s| s.to_string()).chain(figures).collect()
}

/// Points per real variable in the profile figure.
const PROFILE_POINTS: usize = 41;
/// Bare-beam modes in the mode-resolved comparison.
const FIGURE_MODES: usize = 8;

/// Loads, runs and writes an optimisation into `out`; returns the result and the files.
pub fn optimize(
    file: &Path,
    out: &Path,
    threads: Option<usize>,
    plots: bool,
    budget: &Budget,
) -> Result<(Spec, RunResult, Vec<PathBuf>)> {
    let spec = optimize::load(file)?;
    let opts = RunOptions { threads, progress: true, budget: *budget, ..Default::default() };
    let (r, files) = run_into(&spec, file, &opts, Some(out), plots)?;
    Ok((spec, r, files))
}

/// Runs a loaded optimisation (`file` names its file, an input no output may replace) and,
/// with `out`, writes its output set there; returns the result and the files written.
pub fn run_into(
    spec: &Spec,
    file: &Path,
    opts: &RunOptions,
    out: Option<&Path>,
    plots: bool,
) -> Result<(RunResult, Vec<PathBuf>)> {
    opts.budget.admit(&spec.evaluations_cost()).map_err(|e| e.in_file(&spec.file))?;
    if let Some(out) = out {
        let mut inputs = vec![Input::new(file, "the optimisation file")];
        inputs.extend(spec.base.input_files(&spec.file).into_iter().map(|(p, what)| Input::new(p, what)));
        for name in outputs() {
            refuse_input("--out", &output_file(out, &name)?, &inputs)?;
        }
    }
    let r = optimize::run(spec, opts)?;
    let files = match out {
        Some(out) => write(spec, &r, out, opts.threads, plots)?,
        None => Vec::new(),
    };
    Ok((r, files))
}

/// The text files of a run's output set, by name: the best case, the history, the optima,
/// the Pareto front (two objectives) and the JSON summary.
pub fn text_outputs(spec: &Spec, r: &RunResult) -> Result<Vec<(&'static str, String)>> {
    let mut files = vec![
        ("best.toml", best_case(spec, r)?),
        ("history.csv", history_csv(spec, &r.history)),
        ("optima.csv", table_csv(spec, &r.optima)),
    ];
    if !r.pareto.is_empty() {
        files.push(("pareto.csv", table_csv(spec, &r.pareto)));
    }
    files.push(("summary.json", serde_json::to_string_pretty(&summary(spec, r)).expect("plain data serialises")));
    Ok(files)
}

/// Writes the output set of a run into `out`: the text files and, with `plots`, the figures.
fn write(spec: &Spec, r: &RunResult, out: &Path, threads: Option<usize>, plots: bool) -> Result<Vec<PathBuf>> {
    let set = crate::io::output_set::OutputSet::begin(out)?;
    let dir = set.dir().to_path_buf();
    let mut written = Vec::new();
    for (name, text) in text_outputs(spec, r)? {
        let p = output_file(&dir, name)?;
        write_atomic_string(&p, &text)?;
        written.push(p);
    }
    if plots {
        let threads = threads.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| Error::Numerical(format!("cannot start {threads} worker threads: {e}")))?;
        let (profiles, modal) = pool.install(|| {
            rayon::join(
                || optimize::explain::profiles(spec, &r.best, PROFILE_POINTS),
                || optimize::explain::modal_comparison(spec, &r.best, &r.history, FIGURE_MODES),
            )
        });
        let o = &spec.objectives[0];
        let title = "Objective through the optimum";
        let [profiles_name, modes_name, pareto_name] = FIGURES;
        let objective = (o.label.as_str(), o.unit());
        let objective = (objective.0, objective.1.as_str());
        written.extend(crate::report::optimize::plot_profiles(
            &dir,
            profiles_name,
            title,
            objective,
            &profiles,
            &spec.base.actuators,
        )?);
        if !r.pareto.is_empty() {
            written.extend(plot_pareto(spec, r, &dir, pareto_name)?);
        }
        if let Some(m) = modal {
            written.extend(crate::report::optimize::plot_modal(&dir, modes_name, &m)?);
        }
    }
    let report = output_file(&dir, REPORT)?;
    written.push(report.clone());
    write_atomic_string(&report, &report_page(spec, r, &written)?)?;
    let finals = written.iter().map(|p| set.final_path(p)).collect();
    set.commit()?;
    Ok(finals)
}

/// The front of a two-objective run among every feasible candidate it evaluated.
fn plot_pareto(spec: &Spec, r: &RunResult, dir: &Path, name: &str) -> Result<Vec<PathBuf>> {
    let column = |rows: &[&Evaluation], k: usize| rows.iter().map(|e| e.values[k]).collect::<Vec<f64>>();
    let feasible: Vec<&Evaluation> = r.history.iter().filter(|e| e.feasible()).collect();
    let front: Vec<&Evaluation> = r.pareto.iter().collect();
    let units: Vec<String> = spec.objectives.iter().map(|o| o.unit()).collect();
    let axes = [
        (spec.objectives[0].label.as_str(), units[0].as_str()),
        (spec.objectives[1].label.as_str(), units[1].as_str()),
    ];
    crate::report::optimize::plot_pareto(
        (dir, name),
        axes,
        [column(&feasible, 0), column(&feasible, 1)],
        [column(&front, 0), column(&front, 1)],
        [r.best.values[0], r.best.values[1]],
    )
}

/// The run's report: the best case, the optima, the figures and the files, one page.
fn report_page(spec: &Spec, r: &RunResult, files: &[PathBuf]) -> Result<String> {
    use crate::report::html::{cell, escape, figure, file_list, num as number, table, Page};
    let mut p = Page::new();
    let mut header: Vec<String> = vec!["rank".into()];
    header.extend(spec.objectives.iter().map(|o| o.label.clone()));
    header.extend(spec.variables.iter().map(|v| v.name.clone()));
    let rows = |set: &[Evaluation]| -> Vec<Vec<String>> {
        set.iter()
            .enumerate()
            .map(|(i, e)| {
                let mut row = vec![cell(&(i + 1).to_string())];
                row.extend(spec.objectives.iter().zip(&e.values).map(|(o, v)| number(*v, &o.unit())));
                row.extend(spec.variables.iter().zip(&e.u).map(|(v, &u)| match v.value(u) {
                    toml::Value::Float(x) => number(x, v.unit()),
                    other => cell(&other.to_string()),
                }));
                row
            })
            .collect()
    };
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    p.section("best", "Best case");
    p.para(&format!("{} evaluations in {:.1} s, seed {}.", r.evaluations, r.seconds, spec.search.seed));
    if let Some(c) = &r.reduction {
        p.para(&crate::report::sweep::reduction_text(c));
    }
    p.push(&table(&header, &rows(std::slice::from_ref(&r.best))));
    p.section("optima", "Distinct local optima");
    p.push(&table(&header, &rows(&r.optima)));
    if !r.pareto.is_empty() {
        p.section("pareto", "Pareto front");
        p.push(&table(&header, &rows(&r.pareto)));
    }
    let svgs: Vec<&PathBuf> = files.iter().filter(|f| f.extension().is_some_and(|e| e == "svg")).collect();
    if !svgs.is_empty() {
        p.section("figures", "Figures");
        for svg in svgs {
            p.push(&figure(svg)?);
        }
    }
    p.section("files", "Files of this run");
    p.push(&file_list(files));
    if let Ok(text) = crate::input_file::read_text(Path::new(&spec.file)) {
        p.section("file", "Optimisation file");
        p.push(&format!("<p><code>{}</code></p>\n<pre>{}</pre>\n", escape(&spec.file), escape(&text)));
    }
    let title = if spec.title.is_empty() { spec.file.clone() } else { spec.title.clone() };
    let meta = format!(
        "optimisation <code>{}</code> · base <code>{}</code> · beamflow {}",
        escape(&spec.file),
        escape(&spec.base.file),
        env!("CARGO_PKG_VERSION")
    );
    Ok(p.finish(&format!("Optimisation: {title}"), &meta))
}

/// The base case as written (analyses and comments of values aside) with the best values
/// set, and a steady-state analysis if it has none: a case `beamflow run` takes as it is.
fn best_case(spec: &Spec, r: &RunResult) -> Result<String> {
    let best = &r.best;
    let mut doc: toml::Value = toml::from_str(&spec.base.text)
        .map_err(|e| Error::Parse { file: spec.base.file.clone(), message: e.to_string() })?;
    for (f, v) in spec.assignment(&best.u) {
        set_path(&mut doc, &f.segments, v).map_err(|r| Error::input(&spec.file, "variable", r))?;
    }
    let t = doc.as_table_mut().expect("a case is a table");
    let mut notes = Vec::new();
    if let Some(r) = &spec.base.cached_damping {
        // Every candidate was solved with the base case's calibration (the ratio is a
        // property of the beam, not of where the actuators stand); recalibrated on this
        // case's mesh it would differ in the last digits, and so would the optimum.
        let d = &spec.base.case.damping;
        let mut table = toml::map::Map::new();
        table.insert("kind".into(), "rayleigh".into());
        table.insert("a0".into(), r.a0.into());
        table.insert("a1".into(), r.a1.into());
        t.insert("damping".into(), toml::Value::Table(table));
        notes.push(format!(
            "# damping: the Rayleigh coefficients of ζ = {} at modes {:?} calibrated on the base case, as every \
             candidate was solved",
            d.zeta, d.modes
        ));
    }
    if spec.base.shared_structure {
        // The study meshed a plate once, uniformly, for its shared reduction.
        crate::sweep::base::uniform_plate_mesh(t);
    }
    if let Some(c) = &r.reduction {
        // The study's shared modes reach the cut-off its variables' bounds asked for; the
        // case alone would take its own, lower one.
        shared_cutoff(t, c.cutoff_hz);
    }
    if !t.contains_key("analysis") {
        let a: toml::Value =
            toml::from_str(&format!("type = \"steady_state\"\nharmonics = {}\n", spec.harmonics)).expect("valid TOML");
        t.insert("analysis".into(), toml::Value::Array(vec![a]));
    }
    let body = toml::to_string_pretty(&doc).map_err(|e| Error::input(&spec.file, "base", e.to_string()))?;
    let values: Vec<String> = spec
        .objectives
        .iter()
        .zip(&best.values)
        .map(|(o, v)| format!("# {} = {} {}", o.label, num(*v), o.unit()))
        .collect();
    notes.splice(0..0, values);
    Ok(format!(
        "# Best case of {} (base {}); relative file paths resolve against the base case's folder.\n# {}\n{}\n\n{body}",
        spec.file,
        spec.base.file,
        spec.describe(&best.u),
        notes.join("\n")
    ))
}

fn header(spec: &Spec) -> String {
    // Brackets of field paths (`actuator[0].x_e`) as in the sweep table's columns, so that
    // the only brackets of a header hold its unit.
    use crate::sweep::table::column_name;
    let mut h: Vec<String> =
        spec.objectives.iter().map(|o| format!("{} [{}]", column_name(&o.label), o.unit())).collect();
    h.extend(spec.variables.iter().map(|v| format!("{} [{}]", column_name(&v.name), v.unit())));
    h.iter().map(|c| format!("\"{c}\"")).collect::<Vec<_>>().join(",")
}

fn row(spec: &Spec, e: &Evaluation) -> String {
    let mut c: Vec<String> = e.values.iter().map(|v| format!("{v:e}")).collect();
    c.extend(spec.variables.iter().zip(&e.u).map(|(v, &u)| format!("{}", v.number(u))));
    c.join(",")
}

/// Every evaluation in order: whether it met the constraints, the best feasible value of the
/// first objective so far, its objectives and variables.
fn history_csv(spec: &Spec, h: &[Evaluation]) -> String {
    let o = &spec.objectives[0];
    let mut s = format!("evaluation,feasible,\"best so far [{}]\",{}\n", o.unit(), header(spec));
    let mut best = f64::NAN;
    for (i, e) in h.iter().enumerate() {
        if e.feasible() && (best.is_nan() || o.better(e.values[0], best)) {
            best = e.values[0];
        }
        s += &format!("{i},{},{best:e},{}\n", e.feasible() as u8, row(spec, e));
    }
    s
}

fn table_csv(spec: &Spec, rows: &[Evaluation]) -> String {
    let mut s = format!("rank,{}\n", header(spec));
    for (i, e) in rows.iter().enumerate() {
        s += &format!("{},{}\n", i + 1, row(spec, e));
    }
    s
}

fn candidate_json(spec: &Spec, e: &Evaluation) -> serde_json::Value {
    let vars: serde_json::Map<String, serde_json::Value> = spec
        .variables
        .iter()
        .zip(&e.u)
        .map(|(v, &u)| (v.name.clone(), serde_json::to_value(v.value(u)).unwrap_or_default()))
        .collect();
    let objs: serde_json::Map<String, serde_json::Value> =
        spec.objectives.iter().zip(&e.values).map(|(o, v)| (o.label.clone(), serde_json::json!(v))).collect();
    serde_json::json!({ "variables": vars, "objectives": objs })
}

fn summary(spec: &Spec, r: &RunResult) -> serde_json::Value {
    serde_json::json!({
        "file": spec.file,
        "title": spec.title,
        "base": spec.base.file,
        "seed": spec.search.seed,
        "evaluations": r.evaluations,
        "seconds": r.seconds,
        "best": candidate_json(spec, &r.best),
        "best_balance_error": r.best.outcome.as_ref().map(|o| o.balance_error),
        "harmonics": spec.harmonics,
        "optima": r.optima.iter().map(|e| candidate_json(spec, e)).collect::<Vec<_>>(),
        "pareto": r.pareto.iter().map(|e| candidate_json(spec, e)).collect::<Vec<_>>(),
        "reduction": r.reduction.as_ref().map(|c| serde_json::json!({
            "cutoff_hz": c.cutoff_hz,
            "modes_kept": c.modes_kept,
            "max_relative_error_at_optimum": c.max_relative_error,
        })),
    })
}

/// Sets the steady-state analyses' `reduction` of the case table `t` to the explicit
/// cut-off `hz`, keeping their other reduction settings.
fn shared_cutoff(t: &mut toml::Table, hz: f64) {
    let steady = |a: &&mut toml::Value| a.get("type").and_then(toml::Value::as_str) == Some("steady_state");
    let Some(analyses) = t.get_mut("analysis").and_then(toml::Value::as_array_mut) else { return };
    for a in analyses.iter_mut().filter(steady) {
        let Some(table) = a.as_table_mut() else { continue };
        let mut r = match table.get("reduction") {
            Some(toml::Value::Table(r)) => r.clone(),
            Some(_) => toml::Table::new(),
            None => continue,
        };
        r.remove("factor");
        r.insert("modes_up_to_hz".into(), toml::Value::Float(hz));
        table.insert("reduction".into(), toml::Value::Table(r));
    }
}

/// The optima as an aligned text table.
pub fn optima_table(spec: &Spec, rows: &[Evaluation]) -> String {
    // Objectives in units that take SI prefixes read as `311.4 mW`; others (dB, ratios) as
    // plain numbers under their unit.
    let prefixed = |unit: &str| ["W", "J", "N", "m", "V"].contains(&unit);
    let mut s = format!("{:>4}", "rank");
    for o in &spec.objectives {
        let head = if prefixed(&o.unit()) { o.label.to_string() } else { format!("{} ({})", o.label, o.unit()) };
        s += &format!("  {head:>14}");
    }
    for v in &spec.variables {
        s += &format!("  {:>14}", v.name);
    }
    for (i, e) in rows.iter().enumerate() {
        s += &format!("\n{:>4}", i + 1);
        for (v, o) in e.values.iter().zip(&spec.objectives) {
            let shown = if prefixed(&o.unit()) { crate::report::si(*v, &o.unit(), 4) } else { num(*v) };
            s += &format!("  {shown:>14}");
        }
        for (v, &u) in spec.variables.iter().zip(&e.u) {
            let shown = match v.value(u) {
                toml::Value::Float(x) => num(x),
                other => other.to_string(),
            };
            s += &format!("  {shown:>14}");
        }
    }
    s
}
