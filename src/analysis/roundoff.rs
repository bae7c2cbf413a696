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
use crate::error::{Error, Result};

/// Most elements for which the solves hold point powers and mobilities to 1e-6.
pub const MESH_ELEMENTS_LIMIT: usize = 500;

/// The estimated relative round-off of point powers and mobilities on `model`'s mesh
/// (0 without a beam): 1.5e-5·(elements / 1000)⁴, an upper envelope of the measured error.
pub fn mesh_roundoff(model: &Model) -> f64 {
    model.beam.as_ref().map_or(0.0, |b| roundoff_of(b.mesh.elements.len()))
}

/// The estimated relative round-off of a mesh of `elements` elements.
fn roundoff_of(elements: usize) -> f64 {
    1.5e-5 * (elements as f64 / 1000.0).powi(4)
}

/// Refuses a mesh of more than [`MESH_ELEMENTS_LIMIT`] elements for the analyses that
/// solve on it (harmonic, steady state, transient): a count, so it is refused from the case
/// as written, before the mesh is built.
pub fn admit_elements(elements: usize) -> Result<()> {
    if elements <= MESH_ELEMENTS_LIMIT {
        return Ok(());
    }
    Err(Error::case_field(
        "beam.mesh.elements",
        format!(
            "{elements} elements: the round-off of the assembled stiffness would reach ≈ {:.0e} of the point \
             powers and mobilities (it grows as elements⁴), above 1e-6; harmonic, steady-state and transient \
             analyses take at most {MESH_ELEMENTS_LIMIT} elements (modes analyses any number)",
            roundoff_of(elements)
        ),
    ))
}
