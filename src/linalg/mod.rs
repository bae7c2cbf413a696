//! Linear algebra kernels the solvers need and the general crates do not provide in the
//! form we want: a profile (skyline) LDLᵀ that is fast for the banded-with-a-few-long-rows
//! matrices a beam with actuators produces, for real and complex symmetric matrices alike.

pub mod scalar;
pub mod skyline;
pub mod sparse;

pub use scalar::Scalar;
pub use skyline::{Skyline, SkylineLdlt};
pub use sparse::Csr;
