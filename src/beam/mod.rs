//! The structure: an Euler–Bernoulli beam on the x axis, described (not solved) here.
//!
//! A [`Beam`] is a mesh of two-node Hermite elements, each with its own section and
//! material, plus supports, point masses and grounded spring–dampers at nodes. Nothing in
//! this module knows about time stepping or frequency sweeps.

pub mod analytic;
pub mod element;
pub mod mesh;
pub mod section;

pub use element::{element_mass, element_stiffness, element_stiffness_rows, element_stiffness_rows_wide, MassKind};
pub use mesh::{Mesh, MeshElement};
pub use section::{Material, Section};

/// What holds a node. Springs act on the transverse displacement w (N/m) and on the
/// rotation θ (N·m/rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SupportKind {
    /// w = θ = 0.
    Clamped,
    /// w = 0, θ free.
    Pinned,
    /// θ = 0, w free (a sliding clamp, e.g. a symmetry plane).
    Guided,
    /// Elastic support.
    Spring { k_w: f64, k_theta: f64 },
}

/// A support at a mesh node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Support {
    pub node: usize,
    pub kind: SupportKind,
}

/// A rigid mass attached at a node: m (kg) on w, rotary inertia j (kg·m²) on θ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointMass {
    pub node: usize,
    pub mass: f64,
    pub rotary_inertia: f64,
}

/// A spring (N/m) and dashpot (N·s/m) from a node's w to the ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundedSpring {
    pub node: usize,
    pub stiffness: f64,
    pub damping: f64,
}

/// The beam model: mesh plus everything attached to its nodes.
#[derive(Clone, Debug)]
pub struct Beam {
    pub mesh: Mesh,
    pub supports: Vec<Support>,
    pub point_masses: Vec<PointMass>,
    pub springs: Vec<GroundedSpring>,
    pub mass_kind: MassKind,
}

impl Beam {
    /// A uniform beam with the given supports and no attachments.
    pub fn new(mesh: Mesh, supports: Vec<Support>) -> Self {
        Beam { mesh, supports, point_masses: Vec::new(), springs: Vec::new(), mass_kind: MassKind::Consistent }
    }

    /// Whether a DOF of a node is fixed by a support: (w fixed, θ fixed).
    pub fn fixed(&self, node: usize) -> (bool, bool) {
        let mut w = false;
        let mut t = false;
        for s in self.supports.iter().filter(|s| s.node == node) {
            match s.kind {
                SupportKind::Clamped => {
                    w = true;
                    t = true;
                }
                SupportKind::Pinned => w = true,
                SupportKind::Guided => t = true,
                SupportKind::Spring { .. } => {}
            }
        }
        (w, t)
    }

    /// Total mass of the beam itself (kg), without point masses.
    pub fn mass(&self) -> f64 {
        self.mesh.elements.iter().map(|e| e.rho_a * e.length).sum()
    }
}
