//! From a model (beam + actuators) to the assembled second-order system
//! `M·q̈ + C·q̇ + K·q = b·F_p(t) + f(t)`.
//!
//! DOF numbering keeps the matrix profile small: beam nodes in order, each with (w, θ)
//! unless a support fixes them, and each actuator's body DOFs right after the beam DOFs
//! of the last node its feet stand on. Rows of a body then reach back only to its own
//! feet, so the profile grows by a few rows' worth per actuator, not with the beam size.

pub mod damping;
pub mod dofs;
pub mod projection;
pub mod rows;
pub mod system;

pub use damping::{Damping, Rayleigh};
pub use dofs::DofMap;
pub use projection::Projection;
pub use system::{dof_rows, DofRow, LinkDofs, Model, PointLoad, System};
