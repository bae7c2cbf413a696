//! The thin (Kirchhoff) rectangular plate of spec §16, described (not solved) here: a grid
//! of Bogner–Fox–Schmit elements, each with its section and material (uniform, or by
//! region from a mesh file), edge conditions, and point supports, masses and springs at
//! grid nodes.

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

/// An isotropic plate's section and material: thickness h (m), Young's modulus E (Pa),
/// Poisson's ratio ν, density ρ (kg/m³).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sheet {
    pub thickness: f64,
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    pub density: f64,
}

impl Sheet {
    /// Bending stiffness D = E·h³/(12(1 − ν²)) (N·m).
    pub fn bending_stiffness(&self) -> f64 {
        let h = self.thickness;
        self.youngs_modulus * h * h * h / (12.0 * (1.0 - self.poisson_ratio * self.poisson_ratio))
    }

    /// Mass per area ρ·h (kg/m²).
    pub fn mass_per_area(&self) -> f64 {
        self.density * self.thickness
    }
}

/// An isotropic plate on its grid: the plate's own sheet, and where a mesh file says so,
/// others on some elements.
#[derive(Clone, Debug)]
pub struct Plate {
    pub grid: Grid,
    /// The plate's own section and material (`[plate]`).
    pub thickness: f64,
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    pub density: f64,
    /// The other sheets its elements may have (a mesh file's regions), by index from 1
    /// (0 is the plate's own).
    pub sheets: Vec<Sheet>,
    /// Each element's sheet, element (i, j) at i + j·n_x: 0 the plate's own, k the
    /// `sheets[k − 1]`. Empty: every element has the plate's own (a uniform plate).
    pub element_sheet: Vec<u32>,
    pub edges: Edges,
    pub supports: Vec<PointSupport>,
    /// Masses on w (the rotary inertia is not used on a plate).
    pub point_masses: Vec<PointMass>,
    /// Spring–dampers from a node's w to the ground.
    pub springs: Vec<GroundedSpring>,
}

impl Plate {
    /// The plate's own section and material (`[plate]`).
    pub fn own(&self) -> Sheet {
        Sheet {
            thickness: self.thickness,
            youngs_modulus: self.youngs_modulus,
            poisson_ratio: self.poisson_ratio,
            density: self.density,
        }
    }

    /// Whether every element has the plate's own sheet.
    pub fn is_uniform(&self) -> bool {
        self.element_sheet.iter().all(|&k| k == 0)
    }

    /// The index of element (i, j)'s sheet (0: the plate's own, k: `sheets[k − 1]`).
    pub fn sheet_index(&self, i: usize, j: usize) -> u32 {
        self.element_sheet.get(i + j * self.grid.nx()).copied().unwrap_or(0)
    }

    /// Element (i, j)'s section and material.
    pub fn sheet(&self, i: usize, j: usize) -> Sheet {
        match self.sheet_index(i, j) {
            0 => self.own(),
            k => self.sheets[k as usize - 1],
        }
    }

    /// Bending stiffness of the plate's own sheet, D = E·h³/(12(1 − ν²)) (N·m).
    pub fn bending_stiffness(&self) -> f64 {
        self.own().bending_stiffness()
    }

    /// Mass per area of the plate's own sheet, ρ·h (kg/m²).
    pub fn mass_per_area(&self) -> f64 {
        self.own().mass_per_area()
    }

    /// Mass of the plate itself (kg), without point masses.
    pub fn mass(&self) -> f64 {
        let (lx, ly) = self.grid.lengths();
        if self.is_uniform() {
            return self.mass_per_area() * lx * ly;
        }
        let g = &self.grid;
        (0..g.ny())
            .flat_map(|j| (0..g.nx()).map(move |i| (i, j)))
            .map(|(i, j)| self.sheet(i, j).mass_per_area() * g.dx[i] * g.dy[j])
            .sum()
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
        let s = self.sheet(i, j);
        (element::stiffness(a, b, s.bending_stiffness(), s.poisson_ratio), element::mass(a, b, s.mass_per_area()))
    }

    /// Whether the plate is uniform, nothing but its edges holds it or rides on it (no
    /// point supports, masses or springs), and every edge is `edge`: the plates with closed
    /// forms.
    pub fn is_bare_with(&self, edge: Edge) -> bool {
        let e = self.edges;
        self.is_uniform()
            && [e.x0, e.x1, e.y0, e.y1].iter().all(|&k| k == edge)
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
