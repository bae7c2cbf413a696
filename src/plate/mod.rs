//! The thin (Kirchhoff) rectangular plate of spec §16, described (not solved) here: a grid
//! of Bogner–Fox–Schmit elements, edge conditions, and point supports, masses and springs
//! at grid nodes.

pub mod element;
pub mod mesh;
pub mod navier;

pub use mesh::Grid;

use crate::beam::{GroundedSpring, PointMass};

/// How one edge of the plate is held.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edge {
    /// w = ∂w/∂n = 0 along the edge.
    Clamped,
    /// w = 0 along the edge (so its tangential slope is zero too); the normal slope is free.
    SimplySupported,
    Free,
}

/// The four edges: x = 0, x = L_x, y = 0, y = L_y.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edges {
    pub x0: Edge,
    pub x1: Edge,
    pub y0: Edge,
    pub y1: Edge,
}

/// What holds a node of the plate at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PointSupportKind {
    /// w = 0.
    Pinned,
    /// w = ∂w/∂x = ∂w/∂y = 0.
    Clamped,
    /// A spring on w (N/m).
    Spring { k_w: f64 },
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointSupport {
    pub node: usize,
    pub kind: PointSupportKind,
}

/// A uniform isotropic plate on its grid.
#[derive(Clone, Debug)]
pub struct Plate {
    pub grid: Grid,
    /// Thickness h (m), Young's modulus E (Pa), Poisson's ratio ν, density ρ (kg/m³).
    pub thickness: f64,
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    pub density: f64,
    pub edges: Edges,
    pub supports: Vec<PointSupport>,
    /// Masses on w (the rotary inertia is not used on a plate).
    pub point_masses: Vec<PointMass>,
    /// Spring–dampers from a node's w to the ground.
    pub springs: Vec<GroundedSpring>,
}

impl Plate {
    /// Bending stiffness D = E·h³/(12(1 − ν²)) (N·m).
    pub fn bending_stiffness(&self) -> f64 {
        let h = self.thickness;
        self.youngs_modulus * h * h * h / (12.0 * (1.0 - self.poisson_ratio * self.poisson_ratio))
    }

    /// Mass per area ρ·h (kg/m²).
    pub fn mass_per_area(&self) -> f64 {
        self.density * self.thickness
    }

    /// Mass of the plate itself (kg), without point masses.
    pub fn mass(&self) -> f64 {
        let (lx, ly) = self.grid.lengths();
        self.mass_per_area() * lx * ly
    }

    /// Which of a node's (w, w_x, w_y, w_xy) the edges and point supports fix.
    pub fn fixed(&self, node: usize) -> [bool; element::NODE_DOFS] {
        let (i, j) = self.grid.ij(node);
        let mut f = [false; element::NODE_DOFS];
        let mut hold = |edge: Edge, tangent: usize| match edge {
            Edge::Clamped => f = [true; element::NODE_DOFS],
            Edge::SimplySupported => {
                f[0] = true;
                f[tangent] = true;
            }
            Edge::Free => {}
        };
        // On x = const the tangent is y (w_y, index 2); on y = const it is x (w_x, index 1).
        if i == 0 {
            hold(self.edges.x0, 2);
        }
        if i == self.grid.nx() {
            hold(self.edges.x1, 2);
        }
        if j == 0 {
            hold(self.edges.y0, 1);
        }
        if j == self.grid.ny() {
            hold(self.edges.y1, 1);
        }
        for s in self.supports.iter().filter(|s| s.node == node) {
            match s.kind {
                PointSupportKind::Pinned => f[0] = true,
                PointSupportKind::Clamped => f[..3].iter_mut().for_each(|v| *v = true),
                PointSupportKind::Spring { .. } => {}
            }
        }
        f
    }

    /// Element (i, j)'s stiffness and mass over its 16 DOFs.
    pub fn element_matrices(&self, i: usize, j: usize) -> (element::ElementMatrix, element::ElementMatrix) {
        let (a, b) = (self.grid.dx[i], self.grid.dy[j]);
        (
            element::stiffness(a, b, self.bending_stiffness(), self.poisson_ratio),
            element::mass(a, b, self.mass_per_area()),
        )
    }

    /// Whether nothing but its edges holds the plate or rides on it (no point supports,
    /// masses or springs), and every edge is `edge`: the plates with closed forms.
    pub fn is_bare_with(&self, edge: Edge) -> bool {
        let e = self.edges;
        [e.x0, e.x1, e.y0, e.y1].iter().all(|&k| k == edge)
            && self.supports.is_empty()
            && self.point_masses.is_empty()
            && self.springs.is_empty()
    }

    /// All four edges simply supported and nothing else on the plate: the case with the
    /// Navier solution.
    pub fn is_navier(&self) -> bool {
        self.is_bare_with(Edge::SimplySupported)
    }
}
