//! `beamflow sweep` and `beamflow merge`.

use crate::error::{Error, Result};
use crate::io::lock::OutputLock;
use crate::io::paths::{refuse_input, Input};
use crate::report::sweep as report;
use crate::sweep::{self, RunOptions, Shard, SweepTable};
use clap::Args;
use std::path::{Path, PathBuf};

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

/// With `csv`, writes the table as CSV beside `out` (its extension replaced by `.csv`).
fn write_csv(t: &SweepTable, out: &Path, csv: bool) -> Result<()> {
    if csv {
        let p = out.with_extension("csv");
        if p == out {
            return Err(Error::input(
                "<cli>",
                "--out",
                "with --csv, name the HDF5 table FILE.h5 (the CSV is FILE.csv)",
            ));
        }
        t.csv_table().write(&p)?;
        crate::say!("wrote {}", p.display());
    }
    Ok(())
}

pub fn sweep(args: &SweepArgs) -> Result<()> {
    let shard = match &args.shard {
        Some(s) => Shard::parse(s, "<cli>", "--shard")?,
        None => Shard::ALL,
    };
    sweep::exec::worker_threads(args.threads).map_err(|r| Error::input("<cli>", "--threads", r))?;
    let s = sweep::load(&args.sweep)?;
    let mut inputs = vec![Input::new(&args.sweep, "the sweep file")];
    inputs.extend(s.base.input_files(&s.file).into_iter().map(|(p, what)| Input::new(p, what)));
    refuse_overwrite(&args.out, &inputs)?;
    let (n, cost) = s.cases_cost(shard);
    args.budget.budget().admit(&cost).map_err(|e| e.in_file(&s.file))?;
    crate::app::console::note_line(format_args!(
        "{}: {} cases{}, {} analysis, {} harmonics{}",
        s.file,
        s.len(),
        if shard == Shard::ALL { String::new() } else { format!(", shard {shard}: {n} of them") },
        s.analysis.as_str(),
        s.harmonics,
        match s.base.cached_damping {
            Some(r) => format!(", Rayleigh a0 = {:.6e} 1/s, a1 = {:.6e} s computed once", r.a0, r.a1),
            None => String::new(),
        }
    ));
    // Held to the last report file: a second sweep into the same table waits, then reuses
    // it (shards into one folder have tables of their own and run at once).
    let _lock = OutputLock::file(&args.out)?;
    let opts =
        RunOptions { threads: args.threads, shard, progress: true, budget: args.budget.budget(), ..Default::default() };
    let t0 = std::time::Instant::now();
    let ex = sweep::execute(&s, &args.out, &opts)?;
    let dt = t0.elapsed().as_secs_f64();
    crate::app::console::note_line(format_args!(
        "{} cases computed in {dt:.2} s ({:.1} cases/s), {} reused",
        ex.computed,
        if dt > 0.0 { ex.computed as f64 / dt } else { 0.0 },
        ex.reused
    ));
    crate::say!("wrote {}", args.out.display());
    write_csv(&ex.table, &args.out, args.csv)?;
    if !args.no_plots {
        report_files(&ex.table, &args.out)?;
    }
    Ok(())
}

pub fn merge(args: &MergeArgs) -> Result<()> {
    if args.shards.is_empty() {
        return Err(Error::input("<cli>", "SHARD", "give the shard files to merge"));
    }
    let inputs: Vec<Input> = args.shards.iter().map(|p| Input::new(p, "a shard to merge")).collect();
    refuse_overwrite(&args.out, &inputs)?;
    let t = sweep::merge_files(&args.shards)?;
    let _lock = OutputLock::file(&args.out)?;
    t.write(&args.out)?;
    crate::say!("merged {} shards, {} cases: wrote {}", args.shards.len(), t.rows.len(), args.out.display());
    write_csv(&t, &args.out, args.csv)?;
    if !args.no_plots {
        report_files(&t, &args.out)?;
    }
    Ok(())
}

/// Refuses an `--out` table whose file, checkpoint folder or report files (beside it)
/// would replace one of `inputs`.
fn refuse_overwrite(out: &Path, inputs: &[Input]) -> Result<()> {
    let mut outputs = vec![out.to_path_buf(), sweep::parts_dir(out)];
    outputs.extend(report::files_beside(out));
    for o in &outputs {
        refuse_input("--out", o, inputs)?;
    }
    Ok(())
}

fn report_files(t: &SweepTable, out: &Path) -> Result<()> {
    for p in report::plot(t, out)? {
        crate::say!("wrote {}", p.display());
    }
    let md = report::write_markdown(t, out)?;
    crate::say!(
        "\nBest {} cases by net power into the beam:\n{}",
        t.best.min(t.rows.len()),
        report::best_table(t, t.best)
    );
    crate::say!("wrote {}", md.display());
    crate::say!("wrote {}", report::write_report(t, out)?.display());
    Ok(())
}
