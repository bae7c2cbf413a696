//! `beamflow sweep --out` and `beamflow merge`: a sweep's HDF5 table, run (or resumed from
//! its checkpoints) or joined from shards, and the files written beside it (CSV, figure,
//! best-case table, report.html). The command line and the Python package call these.

use crate::error::{Error, Result};
use crate::io::lock::OutputLock;
use crate::io::paths::{refuse_input, Input};
use crate::report::sweep as report;
use crate::sweep::{self, Execution, RunOptions, Sweep, SweepTable};
use std::path::{Path, PathBuf};

/// Runs `s` into the table `out` (`file` names the sweep file, an input `out` must not
/// replace), resuming from `out`'s checkpoints, and writes the files beside it
/// ([`files_beside`]); returns the run and those files.
pub fn sweep_into(
    s: &Sweep,
    file: &Path,
    out: &Path,
    opts: &RunOptions,
    csv: bool,
    plots: bool,
) -> Result<(Execution, Vec<PathBuf>)> {
    let mut inputs = vec![Input::new(file, "the sweep file")];
    inputs.extend(s.base.input_files(&s.file).into_iter().map(|(p, what)| Input::new(p, what)));
    refuse_overwrite(out, csv, &inputs)?;
    check_csv_name(out, csv)?;
    let (_, cost) = s.cases_cost(opts.shard);
    opts.budget.admit(&cost).map_err(|e| e.in_file(&s.file))?;
    // Held to the last report file: a second sweep into the same table waits, then reuses
    // it (shards into one folder have tables of their own and run at once).
    let _lock = OutputLock::file(out)?;
    let ex = sweep::execute(s, out, opts)?;
    let files = files_beside(&ex.table, out, csv, plots)?;
    Ok((ex, files))
}

/// Joins the shard tables `shards` into `out` and writes the files beside it.
pub fn merge(shards: &[PathBuf], out: &Path, csv: bool, plots: bool) -> Result<(SweepTable, Vec<PathBuf>)> {
    if shards.is_empty() {
        return Err(Error::input("<cli>", "SHARD", "give the shard files to merge"));
    }
    let inputs: Vec<Input> = shards.iter().map(|p| Input::new(p, "a shard to merge")).collect();
    refuse_overwrite(out, csv, &inputs)?;
    check_csv_name(out, csv)?;
    let t = sweep::merge_files(shards)?;
    let _lock = OutputLock::file(out)?;
    t.write(out)?;
    let files = files_beside(&t, out, csv, plots)?;
    Ok((t, files))
}

/// Writes beside the table `out`: with `csv` the tidy CSV (FILE.csv), with `plots` the
/// figure, the best-case table (Markdown) and report.html. Returns them in that order.
fn files_beside(t: &SweepTable, out: &Path, csv: bool, plots: bool) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    if csv {
        let p = out.with_extension("csv");
        t.csv_table().write(&p)?;
        files.push(p);
    }
    if plots {
        files.extend(report::plot(t, out)?);
        files.push(report::write_markdown(t, out)?);
        files.push(report::write_report(t, out)?);
    }
    Ok(files)
}

/// With `csv`, the table must be FILE.h5 so that its CSV, FILE.csv, is another file.
fn check_csv_name(out: &Path, csv: bool) -> Result<()> {
    if csv && out.with_extension("csv") == out {
        return Err(Error::input("<cli>", "--out", "with --csv, name the HDF5 table FILE.h5 (the CSV is FILE.csv)"));
    }
    Ok(())
}

/// Refuses an `--out` table whose file, checkpoint folder, report files or (with `csv`)
/// CSV table beside it would replace one of `inputs`.
fn refuse_overwrite(out: &Path, csv: bool, inputs: &[Input]) -> Result<()> {
    let mut outputs = vec![out.to_path_buf(), sweep::parts_dir(out)];
    outputs.extend(report::files_beside(out));
    if csv {
        outputs.push(out.with_extension("csv"));
    }
    for o in &outputs {
        refuse_input("--out", o, inputs)?;
    }
    Ok(())
}
