//! Parameter sweeps: many cases from one base case, run in parallel, one table out.
//!
//! A sweep file ([`spec`]) names a base case and varies any of its fields by dotted path
//! (`actuator[0].x_e`, `actuator[0].voltage.frequency`, `damping.zeta`, …) over lists or
//! ranges, combined as a cartesian product or zipped. Each case is the base with its values
//! set on the TOML document, deserialised and validated like any case file, then solved by
//! the frequency-domain periodic steady state (or the transient) for the headline numbers:
//! net power per actuator, mean power and transmitted-force amplitude per link, beam
//! dissipation and the energy-balance error ([`exec`]). Results go into one table
//! ([`table`]): one row per case, in case order, written as HDF5.
//!
//! Reproducibility: a case is computed on one thread from its own inputs, so the table
//! does not depend on the thread count or on how the sweep was sharded — the merge of
//! shards is bit for bit the single run. Cases that differ only in their drives
//! (`actuator[a].voltage.…`) share one assembled system ([`exec::Evaluator::evaluate_group`]);
//! that saves the assembly and gives the same bits as building it per case. Shards are round-robin (`k/N` takes cases
//! i with i mod N = k − 1). A running sweep saves every finished case in a checkpoint
//! directory; rerunning it skips them.
//!
//! ```no_run
//! # fn main() -> beamflow::Result<()> {
//! use beamflow::sweep;
//! let s = sweep::load(std::path::Path::new("cases/placement-inertial.sweep.toml"))?;
//! let table = sweep::run(&s, &sweep::RunOptions { threads: Some(2), ..Default::default() })?;
//! table.write(std::path::Path::new("out/placement-inertial.h5"))?;
//! # Ok(()) }
//! ```

pub mod base;
pub mod exec;
pub mod field;
pub mod reduced;
pub mod spec;
pub mod table;

pub use base::BaseCase;
pub use exec::{evaluate, execute, group_cases, parts_dir, run, Evaluator, Execution, OnEvaluated, RunOptions};
pub use field::Field;
pub use spec::{load, Combine, Parameter, Sweep, SweepAnalysis};
pub use table::{encode_part, merge, merge_files, ReductionCheck, Row, Shard, SweepTable};
