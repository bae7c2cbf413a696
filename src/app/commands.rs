//! What the CLI commands do, as library functions (the CLI only parses arguments).

use super::case_inputs;
use crate::analysis::budget::Budget;
use crate::analysis::case_run::AnalysisResult;
use crate::analysis::modes;
use crate::app::runner::run_case_within;
use crate::case::build::build_structure;
use crate::case::{AnalysisSpec, LoadedCase};
use crate::error::{Error, Result};
use crate::io::atomic::write_atomic_string;
use crate::io::paths::{output_file, refuse_duplicates, refuse_input, refuse_output, Input};
use std::path::{Path, PathBuf};

/// `beamflow modes`: prints the table and optionally writes JSON.
pub fn modes(case: &Path, count: Option<usize>, json: Option<&Path>) -> Result<()> {
    let lc = LoadedCase::load(case)?;
    check_json_target(json, &case_inputs(&lc), &[])?;
    let count = count
        .or_else(|| {
            lc.case
                .analysis
                .iter()
                .find_map(|a| if let AnalysisSpec::Modes { count } = a { Some(*count) } else { None })
        })
        .unwrap_or(10);
    if count == 0 {
        return Err(Error::input("<cli>", "--count", "must be at least 1"));
    }
    let structure = build_structure(&lc)?;
    // A failure of the solve is the structure's: named by its file and table.
    let r = modes::run(&structure, count).map_err(|e| e.in_analysis(&lc.file, structure.kind()))?;
    crate::say!("{}", modes_table(&r));
    if let Some(path) = json {
        let text = serde_json::to_string_pretty(&r).expect("plain data serialises");
        crate::app::console::write_text_or_stdout(path, &text)?;
    }
    Ok(())
}

/// The modes as an aligned text table.
pub fn modes_table(r: &modes::ModesResult) -> String {
    let mut s = format!(
        "reference: {}\n{:>4}  {:>14}  {:>14}  {:>11}\n",
        r.reference, "mode", "f (Hz)", "analytic (Hz)", "rel. error"
    );
    for (i, f) in r.frequencies_hz.iter().enumerate() {
        match (r.analytic_hz.get(i), r.relative_error.get(i)) {
            (Some(a), Some(e)) => s += &format!("{:>4}  {:>14.6}  {:>14.6}  {:>11.3e}\n", i + 1, f, a, e),
            _ => s += &format!("{:>4}  {:>14.6}  {:>14}  {:>11}\n", i + 1, f, "–", "–"),
        }
    }
    if let Some(c) = &r.coupled {
        s += &format!("coupled with the actuators ({}):\n{:>4}  {:>14}\n", c.body_names.join(", "), "mode", "f (Hz)");
        for (i, f) in c.frequencies_hz.iter().enumerate() {
            s += &format!("{:>4}  {:>14.6}\n", i + 1, f);
        }
    }
    let found = r.frequencies_hz.len();
    if found < r.requested && found >= r.free_dofs {
        s += &format!(
            "note: {} modes asked for, and the mesh has {found} free DOFs: a finer mesh gives more (and more \
             accurate) modes.\n",
            r.requested
        );
    } else if found < r.requested {
        s += &format!(
            "note: {} modes asked for, {found} found among the {} free DOFs: the others have no finite \
             frequency (DOFs without mass, as a model with massless rotations has).\n",
            r.requested, r.free_dofs
        );
    }
    let rigid = r.rigid_body_modes;
    if rigid > 0 {
        let span = if rigid == 1 {
            "mode 1 is a rigid-body mode".to_string()
        } else {
            format!("modes 1–{rigid} are rigid-body modes")
        };
        s += &format!(
            "note: {span}: the structure is not held against rigid motion, and their computed frequencies \
             are zero up to round-off.\n"
        );
    }
    if let Some(&bound) = r.roundoff_bound.get(rigid) {
        if bound > 1e-3 {
            s += &format!(
                "note: this mesh is fine enough for round-off to matter: mode {} may be off by up to ~{bound:.0e} \
                 (relative; it grows as elements², or elements⁴ for a structure without supports). Fewer \
                 elements give more accurate low modes.\n",
                rigid + 1
            );
        }
    }
    s.trim_end().to_string()
}

/// Says on standard error which values of the case look like a slip of units
/// ([`crate::case::plausible`]); the run goes on.
fn warn_implausible(lc: &LoadedCase) {
    for w in crate::case::plausible::warnings(&lc.case) {
        crate::app::console::note_line(format_args!("warning: {}: {w}", lc.file));
    }
}

/// Says on standard error, besides the summary, what the report's warnings say of the
/// run's accuracy (a record whose spectra cannot be trusted, harmonics or settling short of
/// the tolerance, a poor energy balance or reduction) and what to do.
fn warn_inaccurate(report: &crate::report::run_page::RunReport) {
    for w in report.console_warnings() {
        crate::app::console::note_line(format_args!("warning: {}: {w}", report.lc.file));
    }
}

/// `beamflow check`: loads and builds the model, holds every analysis to `budget` as
/// `run` does, prints what it contains.
pub fn check(case: &Path, budget: &Budget) -> Result<()> {
    let lc = LoadedCase::load(case)?;
    warn_implausible(&lc);
    let (built, sys, _) = crate::app::runner::planned(&lc, budget)?;
    let parts = match &built.structure {
        Some(crate::structure::Structure::Beam(b)) => format!("{} elements", b.mesh.elements.len()),
        Some(crate::structure::Structure::Plate(p)) => format!("{} elements", p.grid.nx() * p.grid.ny()),
        Some(crate::structure::Structure::Imported(m)) if !m.report.definiteness_checked => format!(
            "{} nodes, {} massless row(s); M and K not checked for definiteness (the model is above the \
             check's factor size)",
            m.nodes.len(),
            m.report.massless_rows
        ),
        Some(crate::structure::Structure::Imported(m)) => format!(
            "{} nodes, {} rigid-body mode(s) (below {:.3e} Hz), {} massless row(s)",
            m.nodes.len(),
            m.report.rigid_body_modes,
            m.report.rigid_below_hz,
            m.report.massless_rows
        ),
        None => "0 elements".to_string(),
    };
    crate::say!(
        "{}: ok — {}, {} DOFs, {} actuator(s), {} load(s), {} analysis(es)",
        lc.file,
        parts,
        sys.n(),
        built.actuators.len(),
        built.loads.len(),
        lc.case.analysis.len()
    );
    Ok(())
}

/// Refuses a `--json` file that is an input, the output folder or one of `outputs`.
fn check_json_target(json: Option<&Path>, inputs: &[Input], outputs: &[PathBuf]) -> Result<()> {
    let Some(j) = json.filter(|j| !crate::app::console::is_stdout(j)) else { return Ok(()) };
    refuse_input("--json", j, inputs)?;
    refuse_output("--json", j, outputs)?;
    if j.is_dir() {
        return Err(Error::input("<cli>", "--json", format!("{} is a folder; name a file", j.display())));
    }
    Ok(())
}

/// Default output directory for a case: out/<file stem>.
pub fn default_out(case: &Path) -> PathBuf {
    PathBuf::from("out").join(case.file_stem().unwrap_or_default())
}

/// `beamflow run` within `budget` (`csv`: also write the results as tidy CSV tables).
pub fn run(
    case: &Path,
    out: Option<&Path>,
    json: Option<&Path>,
    plots: bool,
    csv: bool,
    budget: &Budget,
) -> Result<()> {
    let lc = LoadedCase::load(case)?;
    warn_implausible(&lc);
    let dir = out.map(Path::to_path_buf).unwrap_or_else(|| default_out(case));
    let stem = case.file_stem().and_then(|s| s.to_str()).unwrap_or("case");
    let inputs = case_inputs(&lc);
    refuse_input("--out", &dir, &inputs)?;
    let named = |name: String| output_file(&dir, &name);
    check_json_target(
        json,
        &inputs,
        &[
            dir.clone(),
            named(format!("{stem}.h5"))?,
            named(format!("{stem}.json"))?,
            named(crate::report::run_page::FILE.to_string())?,
        ],
    )?;
    let run = run_case_within(&lc, budget)?;
    // Every file goes to a staging folder first and appears in `dir` only once all are
    // complete (io::output_set).
    let set = crate::io::output_set::OutputSet::begin(&dir)?;
    let staged = |name: String| output_file(set.dir(), &name);
    let mut written = Vec::new();
    if lc.case.output.hdf5 {
        let h5 = staged(format!("{stem}.h5"))?;
        crate::io::results::write(&h5, &lc, &run)?;
        written.push(h5);
    }
    if lc.case.output.matrices {
        for (name, m) in [("K", &run.system.k), ("M", &run.system.m), ("C", &run.system.c)] {
            let p = staged(format!("{stem}_{name}.mtx"))?;
            crate::io::mtx::write_system_matrix(&p, m.as_sprs())?;
            written.push(p);
        }
        let p = staged(format!("{stem}_dofs.csv"))?;
        crate::io::mtx::write_dof_map(&p, &crate::assembly::dof_rows(&run.model, &run.system))?;
        written.push(p);
        // The structure alone, in the format `[imported]` reads, from the full model.
        let full = crate::assembly::System::assemble(&run.model)?;
        written.extend(crate::io::mtx::write_structure(set.dir(), stem, &full, &run.model)?);
    }
    if csv {
        written.extend(crate::io::results_csv::write(set.dir(), stem, &lc, &run)?);
    }
    // The case's figure settings, for its figures and the report that holds them.
    let _figures = crate::report::plot::Scoped::new((&lc.case.output.figures).into());
    if plots && lc.case.output.plots {
        let _drawing = crate::progress::Task::start("figures", None, "");
        written.extend(crate::report::figures::plot_run(set.dir(), stem, &run)?);
    }
    let summary = crate::io::summary::summary(&lc, &run);
    let text = serde_json::to_string_pretty(&summary).expect("plain data serialises");
    let json_path = staged(format!("{stem}.json"))?;
    write_atomic_string(&json_path, &text)?;
    written.push(json_path);
    let page = crate::report::run_page::RunReport { lc: &lc, run: &run, summary: &summary, files: &written }.html()?;
    let report_path = staged(crate::report::run_page::FILE.to_string())?;
    write_atomic_string(&report_path, &page)?;
    written.push(report_path);
    let finals: Vec<PathBuf> = written.iter().map(|p| set.final_path(p)).collect();
    // Checked before anything becomes visible: an uncommitted set is removed.
    refuse_duplicates(&finals)?;
    for f in &finals {
        refuse_input("--out", f, &inputs)?;
    }
    check_json_target(json, &inputs, &finals)?;
    set.commit()?;
    for p in &finals {
        crate::say!("wrote {}", p.display());
    }
    for r in &run.results {
        if let AnalysisResult::Modes(m) = r {
            crate::say!("{}", modes_table(m));
        }
    }
    crate::say!("{}", crate::io::summary::headline_text(&summary));
    warn_inaccurate(&crate::report::run_page::RunReport { lc: &lc, run: &run, summary: &summary, files: &finals });
    if let Some(j) = json {
        crate::app::console::write_text_or_stdout(j, &text)?;
    }
    Ok(())
}
