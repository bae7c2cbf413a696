//! Analyses: each takes a model (and its assembled system), runs a solver and returns a
//! result struct that output and figures read. Nothing here writes files.
//!
//! [`drive`] holds the drive's timing and the stacks' periodic forces, [`series`] the
//! result vocabulary the analyses share; the power flow itself is computed by
//! [`crate::power`].

pub mod budget;
pub mod case_run;
pub mod cost;
pub mod drive;
pub mod harmonic;
pub mod measured;
pub mod mesh_estimate;
pub mod modes;
pub mod plan;
pub mod reduction;
pub mod roundoff;
pub mod series;
pub mod steady_state;
pub mod transient;
