//! `beamflow optimize`.

use crate::error::{Error, Result};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `beamflow optimize`.
#[derive(Args, Debug)]
pub struct OptimizeArgs {
    /// Optimisation file (TOML; see docs/optimize.md).
    pub spec: PathBuf,
    /// Output directory (default: out/<file name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Worker threads (default: one per core). The result does not depend on it.
    #[arg(long, allow_negative_numbers = true, value_parser = super::count::<1>)]
    pub threads: Option<usize>,
    /// Skip the figures.
    #[arg(long)]
    pub no_plots: bool,
    #[command(flatten)]
    pub budget: super::BudgetArgs,
}

pub fn optimize(args: &OptimizeArgs) -> Result<()> {
    crate::sweep::exec::worker_threads(args.threads).map_err(|r| Error::input("<cli>", "--threads", r))?;
    let name = args.spec.file_name().and_then(|s| s.to_str()).unwrap_or("optimize");
    let stem = name.strip_suffix(".toml").unwrap_or(name).trim_end_matches(".opt");
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from("out").join(stem));
    let (spec, r, files) =
        crate::app::optimize::optimize(&args.spec, &out, args.threads, !args.no_plots, &args.budget.budget())?;
    crate::app::console::note_line(format_args!(
        "{}: {} variables, {} evaluations in {:.2} s ({:.0} per second)",
        spec.file,
        spec.variables.len(),
        r.evaluations,
        r.seconds,
        r.evaluations as f64 / r.seconds.max(1e-9)
    ));
    if let Some(o) = &r.best.outcome {
        crate::app::console::note_line(format_args!(
            "best: {} harmonics solved, energy balance |Σ P − dissipation| / dissipation = {:.1e}",
            spec.harmonics, o.balance_error
        ));
    }
    if let Some(c) = &r.reduction {
        crate::app::console::note_line(format_args!("{}", crate::report::sweep::reduction_text(c)));
    }
    for p in &files {
        crate::say!("wrote {}", p.display());
    }
    let what = if r.pareto.is_empty() { "Local optima" } else { "Local optima of the first objective" };
    crate::say!("\n{what}:\n{}", crate::app::optimize::optima_table(&spec, &r.optima));
    if !r.pareto.is_empty() {
        // The front can hold hundreds of points: its ends and the chosen compromise here,
        // the whole front in pareto.csv and pareto.png.
        let (first, last) = (&r.pareto[0], &r.pareto[r.pareto.len() - 1]);
        crate::say!(
            "\nPareto front: {} points (all in pareto.csv); its two ends and the chosen point nearest the ideal:\n{}",
            r.pareto.len(),
            crate::app::optimize::optima_table(&spec, &[first.clone(), last.clone(), r.best.clone()])
        );
    }
    Ok(())
}
