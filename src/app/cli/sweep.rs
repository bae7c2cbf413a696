//! `beamflow sweep` and `beamflow merge`.

use crate::error::{Error, Result};
use crate::report::sweep as report;
use crate::sweep::{self, RunOptions, Shard, SweepTable};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `beamflow sweep`.
#[derive(Args, Debug)]
pub struct SweepArgs {
    /// Sweep file (TOML; see docs/sweeps.md).
    pub sweep: PathBuf,
    /// Output HDF5 table. Checkpoints of finished cases are kept in FILE.h5.parts/ until
    /// the table is written; rerunning the same command resumes from them.
    #[arg(long)]
    pub out: PathBuf,
    /// Run only part k of N (cases i with i mod N = k − 1), e.g. --shard 3/16.
    #[arg(long)]
    pub shard: Option<String>,
    /// Worker threads (default: one per core).
    #[arg(long, allow_negative_numbers = true, value_parser = super::count::<1>)]
    pub threads: Option<usize>,
    /// Skip the figure and the best-case table.
    #[arg(long)]
    pub no_plots: bool,
    /// Also write the table as tidy CSV beside the HDF5 table (FILE.csv).
    #[arg(long)]
    pub csv: bool,
    #[command(flatten)]
    pub budget: super::BudgetArgs,
}

/// Arguments of `beamflow merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// Shard files to join (the HDF5 tables of `beamflow sweep --shard`).
    pub shards: Vec<PathBuf>,
    /// The joined HDF5 table.
    #[arg(long)]
    pub out: PathBuf,
    /// Skip the figure and the best-case table.
    #[arg(long)]
    pub no_plots: bool,
    /// Also write the table as tidy CSV beside the HDF5 table (FILE.csv).
    #[arg(long)]
    pub csv: bool,
}

pub fn sweep(args: &SweepArgs) -> Result<()> {
    let shard = match &args.shard {
        Some(s) => Shard::parse(s, "<cli>", "--shard")?,
        None => Shard::ALL,
    };
    sweep::exec::worker_threads(args.threads).map_err(|r| Error::input("<cli>", "--threads", r))?;
    let s = sweep::load(&args.sweep)?;
    let (n, _) = s.cases_cost(shard);
    crate::app::console::note_line(format_args!(
        "{}: {} cases{}, {} analysis, {} harmonics{}",
        s.file,
        s.len(),
        if shard == Shard::ALL { String::new() } else { format!(", shard {shard}: {n} of them") },
        s.analysis.as_str(),
        s.harmonics,
        match s.base.cached_damping {
            Some(r) => format!(
                ", Rayleigh a0 = {} 1/s, a1 = {} computed once",
                crate::report::eng(r.a0, 4),
                crate::report::si(r.a1, "s", 4)
            ),
            None => String::new(),
        }
    ));
    let opts =
        RunOptions { threads: args.threads, shard, progress: true, budget: args.budget.budget(), ..Default::default() };
    let t0 = std::time::Instant::now();
    let (ex, files) = crate::app::sweep::sweep_into(&s, &args.sweep, &args.out, &opts, args.csv, !args.no_plots)?;
    let dt = t0.elapsed().as_secs_f64();
    crate::app::console::note_line(format_args!(
        "{} cases computed in {dt:.2} s ({:.1} cases/s), {} reused",
        ex.computed,
        if dt > 0.0 { ex.computed as f64 / dt } else { 0.0 },
        ex.reused
    ));
    if let Some(c) = &ex.table.reduction {
        crate::app::console::note_line(format_args!("{}", report::reduction_text(c)));
    }
    crate::say!("wrote {}", args.out.display());
    report_files(&ex.table, &files, !args.no_plots);
    Ok(())
}

pub fn merge(args: &MergeArgs) -> Result<()> {
    let (t, files) = crate::app::sweep::merge(&args.shards, &args.out, args.csv, !args.no_plots)?;
    crate::say!("merged {} shards, {} cases: wrote {}", args.shards.len(), t.rows.len(), args.out.display());
    report_files(&t, &files, !args.no_plots);
    Ok(())
}

/// Says which files were written beside the table, and with `plots` shows the best cases.
fn report_files(t: &SweepTable, files: &[PathBuf], plots: bool) {
    for p in files {
        crate::say!("wrote {}", p.display());
    }
    if plots {
        crate::say!(
            "\n{} by net power into the {}:\n{}",
            report::best_title(t),
            t.into_word(),
            report::best_table(t, t.best)
        );
    }
}
