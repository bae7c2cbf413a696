//! The round-off a mesh brings into the harmonic, steady-state and transient solves.
//!
//! They factor the assembled stiffness, whose condition number grows as elements⁴. Against
//! the exact continuous beam (`cargo run --release --example mesh_accuracy`, and
//! `tests/mesh_roundoff.rs`) the point mobility's round-off grows 16-fold per doubling of
//! the mesh but scatters by a factor of about five from one mesh to the next (at 60 and
//! 445 Hz: 2.5e-6 at 650 elements, 5.7e-7 at 800, 4.5e-6 at 1,000, 9.4e-5 at 2,000, 1e-3 at
//! 3,000). The estimate is the envelope of those measurements, 1.5e-5·(elements/1000)⁴, so
//! 1e-6 holds up to 500 elements. Results report it; the runner refuses meshes beyond
//! [`MESH_ELEMENTS_LIMIT`]. Modes come from the elements' curvature rows and are not limited
//! this way.

use crate::assembly::Model;

/// Most elements for which the solves hold point powers and mobilities to 1e-6.
pub const MESH_ELEMENTS_LIMIT: usize = 500;

/// The estimated relative round-off of point powers and mobilities on `model`'s mesh
/// (0 without a beam): 1.5e-5·(elements / 1000)⁴, an upper envelope of the measured error.
pub fn mesh_roundoff(model: &Model) -> f64 {
    model.beam.as_ref().map_or(0.0, |b| 1.5e-5 * (b.mesh.elements.len() as f64 / 1000.0).powi(4))
}
