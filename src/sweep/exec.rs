//! Running a sweep: one case evaluated, the shard's cases in parallel on a local rayon
//! pool, checkpoints for resuming (batches of rows), and the output file.

use super::reduced::StudySystems;
use super::spec::{Sweep, SweepAnalysis};
use super::table::{decode_part, encode_part, ReductionCheck, Row, Shard, SweepTable};
use crate::analysis::budget::Budget;
use crate::analysis::drive::StackForceCache;
use crate::analysis::plan::{self, calibrated_model};
use crate::analysis::reduction::{complete_modal_basis, ReductionError};
use crate::analysis::steady_state::{self, Detail, HarmonicSolver, SteadyStateResult};
use crate::analysis::transient::{self, TransientResult};
use crate::assembly::{Model, System};
use crate::error::{Error, Result};
use crate::power::balance::balance_error;
use crate::progress::{self, Cancel};
use rayon::prelude::*;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

/// Called after each case is evaluated, with its index (tests count evaluations).
pub type OnEvaluated = Arc<dyn Fn(usize) + Send + Sync>;

/// How to run a sweep.
#[derive(Clone, Default)]
pub struct RunOptions {
    /// Worker threads (a local pool; `None`: one per available core).
    pub threads: Option<usize>,
    /// The part of the sweep to run.
    pub shard: Shard,
    /// Directory of checkpoint files: cases found there are not recomputed, and
    /// every case computed is saved there in batches of at most 256 rows, and when its
    /// group of cases ends or stops.
    pub checkpoint: Option<PathBuf>,
    /// Show a progress bar on stderr (never drawn when stderr is not a terminal).
    pub progress: bool,
    pub on_evaluated: Option<OnEvaluated>,
    /// Evaluate through the full `steady_state::run` (with its period in time) rather than
    /// its headline mode (checks, timing).
    pub reference: bool,
    /// Set to stop: the cases running stop at their next step, cases not yet started are
    /// skipped, and the table comes back with the rows finished so far.
    pub cancel: Option<Cancel>,
    /// What each case may take, held before any case runs ([`Sweep::admit`]).
    pub budget: Budget,
}

impl std::fmt::Debug for RunOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RunOptions")
            .field("threads", &self.threads)
            .field("shard", &self.shard)
            .field("checkpoint", &self.checkpoint)
            .field("progress", &self.progress)
            .finish_non_exhaustive()
    }
}

/// Evaluates the cases of one sweep, sharing what cases have in common.
#[derive(Debug)]
pub struct Evaluator<'a> {
    pub sweep: &'a Sweep,
    /// Stack-force harmonics per drive, shared by the cases.
    pub forces: StackForceCache,
    /// Use the full `steady_state::run` (with its period in time, no force cache) instead
    /// of its headline mode: for checks and timing.
    pub reference: bool,
    /// The systems the steady states are solved on (full, or the base case's reduction).
    pub systems: StudySystems,
}

/// The headline numbers of a case, as a sweep tabulates them.
#[derive(Clone, Debug, Default)]
pub struct Headline {
    /// Net mean power into the beam per actuator (W).
    pub net_power: Vec<f64>,
    /// Mean power into the beam per link (W).
    pub mean_power: Vec<f64>,
    /// |F̂_T| at the fundamental per link (N).
    pub force_amplitude: Vec<f64>,
    pub beam_dissipation: f64,
    pub balance_error: f64,
}

/// |F̂_T| at the fundamental (N) of a spectrum of the transmitted force (0 without one).
fn fundamental(transmitted: &[num_complex::Complex64]) -> f64 {
    transmitted.get(1).map_or(0.0, |c| c.norm())
}

impl Headline {
    fn of_steady_state(r: SteadyStateResult) -> Self {
        Headline {
            force_amplitude: r.spectra.iter().map(|s| fundamental(&s.transmitted)).collect(),
            net_power: r.net_power,
            mean_power: r.mean_power,
            beam_dissipation: r.beam_dissipation,
            balance_error: r.balance_error,
        }
    }

    fn of_transient(r: TransientResult) -> Self {
        Headline {
            force_amplitude: r.spectra.iter().map(|s| fundamental(&s.transmitted)).collect(),
            balance_error: balance_error(r.beam_input_power, r.beam_dissipation),
            net_power: r.net_power,
            mean_power: r.mean_power,
            beam_dissipation: r.beam_dissipation,
        }
    }
}

/// Names the case an error of its evaluation came from; a cancellation stays one.
fn in_case(sweep: &Sweep, i: usize) -> impl Fn(Error) -> Error + '_ {
    move |e| match e {
        Error::Cancelled => e,
        e => Error::input(&sweep.file, format!("case {i} ({})", sweep.describe(i)), e.to_string()),
    }
}

impl<'a> Evaluator<'a> {
    pub fn new(sweep: &'a Sweep, reference: bool) -> Self {
        let systems = StudySystems::new(&sweep.file, &sweep.base, sweep.harmonics, sweep.extremes());
        Evaluator { sweep, forces: StackForceCache::default(), reference, systems }
    }

    /// Evaluates case `i`: builds its model (the mesh follows the actuator) and solves the
    /// periodic steady state (or the transient) for the headline outputs.
    pub fn evaluate(&self, i: usize) -> Result<Row> {
        let sweep = self.sweep;
        let lc = sweep.case(i)?;
        let wrap = in_case(sweep, i);
        let model = calibrated_model(&lc).map_err(&wrap)?;
        let sys = self.system(&model, &lc.file).map_err(&wrap)?;
        let head = match (sweep.analysis, self.reference) {
            (SweepAnalysis::SteadyState, false) => self.steady_state(&model, &mut HarmonicSolver::new(&sys)),
            (SweepAnalysis::SteadyState, true) => {
                steady_state::run(&model, &sys, sweep.harmonics, sweep.samples_per_period)
                    .map(Headline::of_steady_state)
            }
            (SweepAnalysis::Transient, _) => {
                let s = transient::TransientSettings { harmonics: Some(sweep.harmonics), ..Default::default() };
                transient::run(&model, &sys, &s).map(Headline::of_transient)
            }
        };
        self.row(i, head.map_err(&wrap)?)
    }

    /// The system a case is solved on: a steady state's from [`StudySystems`] (the full
    /// system or the base case's reduction), a transient's assembled.
    fn system(&self, model: &Model, file: &str) -> Result<System> {
        match self.sweep.analysis {
            SweepAnalysis::SteadyState => Ok(self.systems.system(model, file)?.0),
            SweepAnalysis::Transient => frequency_domain_system(model, file, SweepAnalysis::Transient),
        }
    }

    /// The steady state of `model` in its headline mode, against `solver`'s system (the
    /// model's, up to the actuators' voltages), with this sweep's harmonics and cache.
    fn steady_state(&self, model: &Model, solver: &mut HarmonicSolver) -> Result<Headline> {
        let (h, n) = (self.sweep.harmonics, self.sweep.samples_per_period);
        steady_state::run_with(model, solver, h, n, Detail::Headline(&self.forces)).map(Headline::of_steady_state)
    }

    /// Whether [`Evaluator::evaluate_group`] shares one assembled system between the cases
    /// of a group (the steady state in its headline mode); otherwise it evaluates them one by one.
    pub fn shares_systems(&self) -> bool {
        self.sweep.analysis == SweepAnalysis::SteadyState && !self.reference
    }

    /// Evaluates cases that differ only in their drives (equal [`Sweep::model_key`]), in the
    /// given order, and hands each row to `sink` as soon as it is done. The model and system
    /// are built once, from the first case; every case then sets its actuators' voltages on
    /// that model and solves against the shared system and its [`HarmonicSolver`]. Each
    /// row is bit for bit what [`Evaluator::evaluate`] gives for the case alone. Stops before
    /// a case when `cancelled()` says so.
    pub fn evaluate_group(
        &self,
        indices: &[usize],
        cancelled: impl Fn() -> bool,
        mut sink: impl FnMut(Row) -> Result<()>,
    ) -> Result<()> {
        let Some(&first) = indices.first() else {
            return Ok(());
        };
        if !self.shares_systems() || indices.len() == 1 {
            for &i in indices {
                if cancelled() {
                    return Ok(());
                }
                sink(self.evaluate(i)?)?;
            }
            return Ok(());
        }
        let sweep = self.sweep;
        let wrap = |i: usize| in_case(sweep, i);
        debug_assert!(indices.iter().all(|&i| sweep.model_key(i) == sweep.model_key(first)));
        let lc = sweep.case(first)?;
        let mut model = calibrated_model(&lc).map_err(wrap(first))?;
        let sys = self.system(&model, &lc.file).map_err(wrap(first))?;
        let mut solver = HarmonicSolver::new(&sys);
        let driven = sweep.driven_actuators();
        for &i in indices {
            if cancelled() {
                return Ok(());
            }
            if i != first {
                for &a in &driven {
                    let v = sweep.voltage(i, a)?;
                    let slot = model.actuators.get_mut(a).ok_or_else(|| {
                        wrap(i)(Error::Numerical("the case's actuators differ from the base case's".into()))
                    })?;
                    slot.stack_mut().voltage = v;
                }
            }
            let head = self.steady_state(&model, &mut solver).map_err(wrap(i))?;
            sink(self.row(i, head)?)?;
        }
        Ok(())
    }

    /// Solves the static shapes of the cases of `groups` up front when they run on a shared
    /// reduction ([`StudySystems::prefetch`]): one case per group, whose cases differ only
    /// in their drives and so share their attachments.
    fn prefetch(&self, groups: &[Vec<usize>]) {
        let sweep = self.sweep;
        let firsts: Vec<usize> = groups.iter().filter_map(|g| g.first().copied()).collect();
        let Some(first) = firsts.first().and_then(|&i| sweep.case(i).ok()).and_then(|lc| calibrated_model(&lc).ok())
        else {
            return;
        };
        self.systems.prefetch(&first, firsts.len(), |k| {
            // Where the actuators stand does not depend on the damping: its calibration
            // (the bare modes, for a damping ratio) is left to the case.
            let model = crate::case::build::build_model(&sweep.case(firsts[k])?)?;
            Ok(Model { damping: crate::assembly::Damping::None, ..model })
        });
    }

    /// A sweep on a shared reduction checks it: the case of `rows` with the largest total
    /// net power solved again on the full model, its point and net powers compared. None
    /// for a sweep on the full model, without rows, or where the full model of that case
    /// cannot be solved (the table is kept either way).
    pub fn check_reduction(&self, rows: &[Row]) -> Option<ReductionCheck> {
        let sweep = self.sweep;
        let total = |r: &Row| r.net_power.iter().sum::<f64>();
        let best = rows.iter().filter(|r| total(r).is_finite()).max_by(|a, b| total(a).total_cmp(&total(b)))?;
        let shared =
            self.systems.shared().filter(|_| !self.reference && sweep.analysis == SweepAnalysis::SteadyState)?;
        let lc = sweep.case(best.index).ok()?;
        let model = calibrated_model(&lc).ok()?;
        let full = frequency_domain_system(&model, &lc.file, SweepAnalysis::SteadyState).ok()?;
        let head = self.steady_state(&model, &mut HarmonicSolver::new(&full)).ok()?;
        let e = ReductionError::between(
            sweep.harmonics,
            (&head.mean_power, &head.net_power),
            (&best.mean_power, &best.net_power),
        );
        Some(ReductionCheck {
            cutoff_hz: shared.cutoff_hz(),
            modes_kept: shared.modes_kept(),
            case: Some(best.index),
            max_relative_error: e.largest(),
        })
    }

    fn row(&self, i: usize, head: Headline) -> Result<Row> {
        let sweep = self.sweep;
        if head.net_power.len() != sweep.base.actuators.len() || head.mean_power.len() != sweep.base.links.len() {
            let e = Error::Numerical("the case's actuators differ from the base case's".into());
            return Err(Error::input(&sweep.file, format!("case {i} ({})", sweep.describe(i)), e.to_string()));
        }
        Ok(Row {
            index: i,
            inputs: sweep.values(i),
            net_power: head.net_power,
            mean_power: head.mean_power,
            force_amplitude: head.force_amplitude,
            beam_dissipation: head.beam_dissipation,
            balance_error: head.balance_error,
        })
    }
}

/// A case's system as the sweep solves it: assembled, or with modal damping (steady-state
/// sweeps only) the same model in the bare beam's complete modal basis, where that damping
/// is a matrix. A transient sweep of a modal-damped case is refused.
pub fn frequency_domain_system(model: &Model, file: &str, analysis: SweepAnalysis) -> Result<System> {
    if analysis == SweepAnalysis::Transient {
        plan::require_viscous_damping(model, "transient sweep").map_err(|e| e.in_file(file))?;
    }
    let sys = System::assemble(model).map_err(|e| e.in_file(file))?;
    match model.modal_ratios() {
        None => Ok(sys),
        Some(r) => complete_modal_basis(&sys, r),
    }
}

/// The cases of `todo` (in order) in groups that share their model up to the drives (equal
/// [`Sweep::model_key`]), each group in the order of `todo`, groups in the order of their
/// first case. Groups longer than `max_len` are cut, so that a sweep of few placements and
/// many frequencies still keeps every thread busy.
pub fn group_cases(sweep: &Sweep, todo: &[usize], max_len: usize) -> Vec<Vec<usize>> {
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut by_key: std::collections::HashMap<Vec<u64>, usize> = std::collections::HashMap::new();
    for &i in todo {
        let g = *by_key.entry(sweep.model_key(i)).or_insert_with(|| {
            groups.push(Vec::new());
            groups.len() - 1
        });
        groups[g].push(i);
    }
    let max_len = max_len.max(1);
    groups.into_iter().flat_map(|g| g.chunks(max_len).map(<[usize]>::to_vec).collect::<Vec<_>>()).collect()
}

/// Evaluates case `i` of a sweep on its own (headline steady state, fresh cache).
pub fn evaluate(sweep: &Sweep, i: usize) -> Result<Row> {
    Evaluator::new(sweep, false).evaluate(i)
}

/// Checkpoint rows are flushed to a file at least this often (and when a group ends).
const ROWS_PER_PART: usize = 256;

/// Writes checkpoint rows as one part file: temporary file, then rename (atomic against a
/// crash of this process). Rows are batched because one file per case made the file system,
/// not the physics, the cost of a large sweep. No fsync — it would cost more than many
/// cases; after a power loss a damaged row fails its checksum and is simply recomputed.
fn write_part(dir: &Path, rows: &[Row], hash: &str) -> Result<()> {
    static SEQ: AtomicUsize = AtomicUsize::new(0);
    let Some(first) = rows.first() else { return Ok(()) };
    let seq = SEQ.fetch_add(1, Ordering::Relaxed);
    let name = format!("rows-{:09}-{}-{seq}.bin", first.index, std::process::id());
    let dest = dir.join(&name);
    let tmp = dir.join(format!(".{name}.tmp"));
    let bytes: Vec<u8> = rows.iter().flat_map(|r| encode_part(r, hash)).collect();
    std::fs::write(&tmp, bytes).map_err(|e| Error::io(&tmp, e))?;
    std::fs::rename(&tmp, &dest).map_err(|e| Error::io(&dest, e))
}

/// Every intact checkpoint row in `dir` (part files hold fixed-length records; a damaged
/// record is skipped, so only its case is recomputed).
fn read_parts(dir: &Path, hash: &str, shape: (usize, usize, usize)) -> Vec<Row> {
    let record = 36 + 8 * (shape.0 + shape.1 + 2 * shape.2 + 2) + 8;
    let Ok(entries) = std::fs::read_dir(dir) else { return Vec::new() };
    let files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "bin"))
        .collect();
    files
        .par_iter()
        .flat_map_iter(|p| {
            // Only the regular files this program wrote: a FIFO planted here would block.
            let b = crate::input_file::regular_file(p).ok().and_then(|()| std::fs::read(p).ok()).unwrap_or_default();
            b.chunks_exact(record).filter_map(|c| decode_part(c, hash, shape)).collect::<Vec<_>>()
        })
        .collect()
}

/// Prepares a checkpoint directory: creates it with a `sweep-id` file, or checks that an
/// existing one belongs to this sweep. The directory is removed once the table is written,
/// so one this program did not make (a link, a folder of other files) is refused.
fn open_checkpoint(dir: &Path, sweep: &Sweep) -> Result<()> {
    let id = dir.join("sweep-id");
    let text = format!("{}\n{}\n", sweep.hash, sweep.len());
    if let Ok(meta) = std::fs::symlink_metadata(dir) {
        let empty = || std::fs::read_dir(dir).is_ok_and(|mut d| d.next().is_none());
        let ours = meta.is_dir() && (std::fs::symlink_metadata(&id).is_ok_and(|m| m.is_file()) || empty());
        if !ours {
            return Err(Error::input(
                dir.display().to_string(),
                "sweep-id",
                "is not a checkpoint folder of a sweep (a link, or a folder of other files): move it away or \
                 choose another --out",
            ));
        }
        if let Ok(found) = crate::input_file::read_text(&id) {
            if found != text {
                return Err(Error::input(
                    dir.display().to_string(),
                    "sweep-id",
                    format!(
                        "holds cases of another sweep (id {}, this one is {}): delete the directory or choose \
                         another --out",
                        found.lines().next().unwrap_or(""),
                        sweep.hash
                    ),
                ));
            }
            return Ok(());
        }
    }
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    crate::io::atomic::write_atomic_string(&id, &text)
}

/// Most worker threads a study starts: many times the cores of any machine it runs on, so
/// that a typo of a few orders of magnitude is refused rather than spawned.
pub const MAX_THREADS: usize = 1024;

/// The worker threads `threads` asks for (`None`: one per available core), or why not:
/// none, or more than [`MAX_THREADS`].
pub fn worker_threads(threads: Option<usize>) -> std::result::Result<usize, String> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    match threads.unwrap_or(cores) {
        0 => Err("must be at least 1".into()),
        n if n > MAX_THREADS => {
            Err(format!("{n} worker threads: give at most {MAX_THREADS} (this machine has {cores} cores)"))
        }
        n => Ok(n),
    }
}

/// The worker threads of a run: `threads`, or one per available core.
pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    let threads = worker_threads(threads).map_err(|r| Error::argument("threads", r))?;
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Numerical(format!("cannot start {threads} worker threads: {e}")))
}

/// Runs (a shard of) a sweep and returns its table, rows sorted by case index. Cases
/// already in the checkpoint directory are read, not recomputed. If cancelled, the table
/// lacks the cases not run ([`SweepTable::missing`]).
///
/// Every case is computed from its own inputs, on one thread: the results do not depend on
/// the thread count, the shard or the order of evaluation, bit for bit. Cases that differ
/// only in their drives share the assembled system ([`Evaluator::evaluate_group`]), which
/// gives the same bits as building it per case.
pub fn run(sweep: &Sweep, opts: &RunOptions) -> Result<SweepTable> {
    sweep.admit(&opts.budget)?;
    let mut table = SweepTable::new(sweep, opts.shard);
    let indices = opts.shard.indices(sweep.len());
    let pool = thread_pool(opts.threads)?;
    let shape = table.shape();

    let mut done: Vec<Row> = Vec::new();
    if let Some(dir) = &opts.checkpoint {
        open_checkpoint(dir, sweep)?;
        let wanted: std::collections::HashSet<usize> = indices.iter().copied().collect();
        let mut seen = std::collections::HashSet::new();
        done = pool
            .install(|| read_parts(dir, &sweep.hash, shape))
            .into_iter()
            .filter(|r| wanted.contains(&r.index) && seen.insert(r.index))
            .collect();
    }
    let have: std::collections::HashSet<usize> = done.iter().map(|r| r.index).collect();
    let todo: Vec<usize> = indices.iter().copied().filter(|i| !have.contains(i)).collect();

    let bar = if opts.progress && std::io::stderr().is_terminal() {
        let b =
            indicatif::ProgressBar::with_draw_target(Some(todo.len() as u64), indicatif::ProgressDrawTarget::stderr());
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} cases ({per_sec}, eta {eta})",
            )
            .expect("valid template"),
        );
        b
    } else {
        indicatif::ProgressBar::hidden()
    };
    let ev = Evaluator::new(sweep, opts.reference);
    // Cases that differ only in their drives share one assembled system (most of a case's
    // cost otherwise). Groups are cut so that there are at least ≈ 8 per thread.
    let groups = if ev.shares_systems() {
        group_cases(sweep, &todo, todo.len().div_ceil(8 * pool.current_num_threads()).max(16))
    } else {
        todo.iter().map(|&i| vec![i]).collect()
    };
    if ev.shares_systems() {
        pool.install(|| ev.prefetch(&groups));
    }
    let cancelled = || opts.cancel.as_ref().is_some_and(Cancel::is_cancelled);
    let new: Vec<Row> = pool.install(|| {
        groups
            .par_iter()
            .map(|g| {
                let mut rows = Vec::with_capacity(g.len());
                let mut unsaved = 0;
                let mut evaluate = || {
                    ev.evaluate_group(g, cancelled, |row| {
                        if let Some(cb) = &opts.on_evaluated {
                            cb(row.index);
                        }
                        bar.inc(1);
                        rows.push(row);
                        unsaved += 1;
                        if unsaved == ROWS_PER_PART {
                            if let Some(dir) = &opts.checkpoint {
                                write_part(dir, &rows[rows.len() - unsaved..], &sweep.hash)?;
                            }
                            unsaved = 0;
                        }
                        Ok(())
                    })
                };
                // A case stopped mid-solve ends its group like a case never started.
                let result = match &opts.cancel {
                    Some(c) => match progress::cancellable(c.clone(), evaluate) {
                        Err(Error::Cancelled) => Ok(()),
                        r => r,
                    },
                    None => evaluate(),
                };
                // Save what the group finished, also when it stopped early.
                if let Some(dir) = &opts.checkpoint {
                    write_part(dir, &rows[rows.len() - unsaved..], &sweep.hash)?;
                }
                result?;
                Ok(rows)
            })
            .collect::<Result<Vec<Vec<Row>>>>()
            .map(|v| v.into_iter().flatten().collect())
    })?;
    bar.finish_and_clear();
    done.extend(new);
    done.sort_by_key(|r| r.index);
    table.rows = done;
    if !cancelled() {
        table.reduction = ev.check_reduction(&table.rows);
    }
    Ok(table)
}

/// What [`execute`] did.
#[derive(Clone, Debug)]
pub struct Execution {
    pub table: SweepTable,
    /// Cases computed now, and found finished (checkpoints or an existing output).
    pub computed: usize,
    pub reused: usize,
}

/// The checkpoint directory of an output file: `FILE.h5.parts/`.
pub fn parts_dir(out: &Path) -> PathBuf {
    let mut s = out.as_os_str().to_owned();
    s.push(".parts");
    PathBuf::from(s)
}

/// `beamflow sweep`: runs (a shard of) a sweep into `out`, resuming from `out`'s
/// checkpoints (`FILE.h5.parts/`). The table is written atomically when every case of the
/// shard is done; then the checkpoints are removed. If `out` already holds this shard of
/// this sweep, nothing is recomputed.
pub fn execute(sweep: &Sweep, out: &Path, opts: &RunOptions) -> Result<Execution> {
    let outfile = out.display().to_string();
    if out.exists() {
        let t = SweepTable::read(out)?;
        if t.hash != sweep.hash {
            return Err(Error::input(
                &outfile,
                "sweep_hash",
                format!(
                    "already holds another sweep's results (id {}, this sweep is {}): delete it or choose another \
                     --out",
                    t.hash, sweep.hash
                ),
            ));
        }
        if t.shard != opts.shard {
            return Err(Error::input(
                &outfile,
                "shard",
                format!("already holds shard {} of this sweep, not {}: choose another --out", t.shard, opts.shard),
            ));
        }
        if t.is_complete() {
            let reused = t.rows.len();
            return Ok(Execution { table: t, computed: 0, reused });
        }
    }
    let dir = parts_dir(out);
    let counter = Arc::new(AtomicUsize::new(0));
    let mut o = opts.clone();
    o.checkpoint = Some(dir.clone());
    let c2 = counter.clone();
    let user = opts.on_evaluated.clone();
    o.on_evaluated = Some(Arc::new(move |i| {
        c2.fetch_add(1, Ordering::Relaxed);
        if let Some(u) = &user {
            u(i);
        }
    }));
    let table = run(sweep, &o)?;
    let computed = counter.load(Ordering::Relaxed);
    let reused = table.rows.len() - computed;
    let missing = table.missing();
    if !missing.is_empty() {
        return Err(Error::input(
            &outfile,
            "cases",
            format!(
                "interrupted with {} of {} cases done (kept in {}); rerun the same command to resume",
                table.rows.len(),
                table.rows.len() + missing.len(),
                dir.display()
            ),
        ));
    }
    table.write(out)?;
    std::fs::remove_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    Ok(Execution { table, computed, reused })
}
