//! The I/O edge of beamflow: everything that touches files on the way *out*.
//!
//! Simulation code builds plain values (slices, `Vec`s, sparse matrices); the modules here
//! turn them into files that other tools can read without beamflow:
//!
//! * [`atomic`]: write-to-temp-then-rename, so a crash or a failed run never leaves a
//!   half-written result where a finished one is expected (sweeps skip existing outputs).
//! * [`hdf5`]: the self-describing results file (units and descriptions as attributes),
//!   plus a small reader used by tests and for merging sweep shards.
//! * [`plot`]: report figures (PNG and SVG from one description).
//! * [`sink`], [`tree`]: the results layout is written through [`sink::GroupSink`], into an
//!   HDF5 file or an in-memory [`tree::Group`] (the Python package's results) alike.
//! * [`csv`], [`results_csv`]: tidy CSV tables (units in the header) of a run's results,
//!   made from the same layout as the HDF5 file.
//! * [`mtx`]: Matrix Market export of sparse system matrices, for checking them in
//!   other tools (SciPy, MATLAB, Julia).
//!
//! * [`output_set`]: a run's files committed as a set; [`lock`]: one writer at a time per
//!   output folder; [`paths`]: output paths that stay inside the output folder and never
//!   name an input.
//!
//! Every function returns [`crate::error::Result`], and every error names the file.

pub mod atomic;
pub mod csv;
pub mod hash;
pub mod hdf5;
pub mod lock;
pub mod measurement;
pub mod mtx;
pub mod output_set;
pub mod paths;
pub mod results;
pub mod results_csv;
pub mod sink;
pub mod summary;
pub mod tree;
