//! Solvers: they consume an assembled [`System`](crate::assembly::System) and know nothing
//! of beams or actuators.

pub mod dynamic_stiffness;
pub mod eigen;
pub mod fused;
pub mod lanczos;
pub mod modal_basis;
pub mod newmark;
