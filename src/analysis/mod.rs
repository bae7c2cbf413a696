//! Analyses: each takes a model (and its assembled system), runs a solver and returns a
//! result struct that post-processing and I/O read. Nothing here writes files.

pub mod harmonic;
pub mod modes;
pub mod reduction;
pub mod steady_state;
pub mod transient;
