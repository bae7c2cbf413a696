//! Solvers: they consume an assembled [`System`](crate::assembly::System) and know nothing
//! of beams or actuators.

pub mod band_newmark;
pub mod dynamic_stiffness;
pub mod eigen;
pub mod lanczos;
pub mod modal_basis;
pub mod modal_coupling;
pub mod newmark;
pub mod refine;
pub mod shared_basis;
