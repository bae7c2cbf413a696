//! Solvers: they consume an assembled [`System`](crate::assembly::System) and know nothing
//! of beams or actuators.

pub mod eigen;
pub mod fused;
pub mod harmonic;
pub mod lanczos;
pub mod newmark;
pub mod reduction;
