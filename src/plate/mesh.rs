//! A plate's rectangular grid: lines x = xᵢ and y = yⱼ, Bogner–Fox–Schmit elements between
//! them, and how a point (x, y) is found on it.

use super::element;

/// Grid lines of a rectangular plate mesh. Node (i, j) at (x[i], y[j]) has id
/// i + j·(x.len()); element (i, j) spans [x[i], x[i+1]] × [y[j], y[j+1]].
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Node coordinates along x (m), strictly increasing from 0.
    pub x: Vec<f64>,
    /// Node coordinates along y (m), strictly increasing from 0.
    pub y: Vec<f64>,
    /// Element sides along x and y (m): the segments' nominal lengths, see
    /// [`crate::beam::mesh::grid_line`].
    pub dx: Vec<f64>,
    pub dy: Vec<f64>,
}

/// Where a point lies in the grid: its element and local coordinates (ξ, η) ∈ [0, 1]².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spot {
    pub element: (usize, usize),
    pub xi: f64,
    pub eta: f64,
}

impl Grid {
    /// A grid of about `nx` × `ny` elements on [0, lx] × [0, ly] with a grid line through
    /// every point's x and every point's y, so each point is a node.
    pub fn through(lx: f64, ly: f64, nx: usize, ny: usize, points: &[(f64, f64)]) -> Grid {
        let xs: Vec<f64> = points.iter().map(|p| p.0).collect();
        let ys: Vec<f64> = points.iter().map(|p| p.1).collect();
        let (x, dx) = crate::beam::mesh::grid_line(lx, nx, &xs);
        let (y, dy) = crate::beam::mesh::grid_line(ly, ny, &ys);
        Grid { x, y, dx, dy }
    }

    /// A grid on the given lines (strictly increasing from 0, as a mesh file's are checked
    /// to be); each element's side is the difference of its lines, or, where a side's lines
    /// are evenly spaced to within rounding (1e-12), the nominal length L/n of all its
    /// elements, as [`Grid::through`] gives them (a uniform file is the generated grid, and
    /// its rows of M, C, K are bitwise periodic).
    pub fn from_lines(x: Vec<f64>, y: Vec<f64>) -> Grid {
        let sides = |v: &[f64]| -> Vec<f64> {
            let d: Vec<f64> = v.windows(2).map(|w| w[1] - w[0]).collect();
            let h = v[v.len() - 1] / d.len() as f64;
            if d.iter().all(|s| (s - h).abs() <= 1e-12 * h) {
                vec![h; d.len()]
            } else {
                d
            }
        };
        let (dx, dy) = (sides(&x), sides(&y));
        Grid { x, y, dx, dy }
    }

    pub fn nx(&self) -> usize {
        self.dx.len()
    }

    pub fn ny(&self) -> usize {
        self.dy.len()
    }

    pub fn n_nodes(&self) -> usize {
        self.x.len() * self.y.len()
    }

    pub fn node(&self, i: usize, j: usize) -> usize {
        i + j * self.x.len()
    }

    /// Grid indices (i, j) of a node id.
    pub fn ij(&self, node: usize) -> (usize, usize) {
        (node % self.x.len(), node / self.x.len())
    }

    /// Coordinates (m) of a node.
    pub fn position(&self, node: usize) -> (f64, f64) {
        let (i, j) = self.ij(node);
        (self.x[i], self.y[j])
    }

    pub fn lengths(&self) -> (f64, f64) {
        (*self.x.last().unwrap_or(&0.0), *self.y.last().unwrap_or(&0.0))
    }

    /// Tolerance within which a coordinate counts as on a grid line (m).
    pub fn tolerance(&self) -> f64 {
        let (lx, ly) = self.lengths();
        1e-9 * lx.max(ly).max(1e-12)
    }

    /// The element's nodes in the element's corner order (see [`element`]).
    pub fn element_nodes(&self, i: usize, j: usize) -> [usize; element::NODES] {
        [self.node(i, j), self.node(i + 1, j), self.node(i + 1, j + 1), self.node(i, j + 1)]
    }

    /// The node at (x, y), if both lie on grid lines within the tolerance.
    pub fn node_at(&self, x: f64, y: f64) -> Option<usize> {
        let tol = self.tolerance();
        let on = |v: &[f64], c: f64| {
            let i = v.partition_point(|&t| t < c - tol);
            (i < v.len() && (v[i] - c).abs() <= tol).then_some(i)
        };
        Some(self.node(on(&self.x, x)?, on(&self.y, y)?))
    }

    /// The element holding (x, y) and the point's local coordinates; None outside the plate.
    pub fn locate(&self, x: f64, y: f64) -> Option<Spot> {
        let tol = self.tolerance();
        let (lx, ly) = self.lengths();
        if !(x >= -tol && x <= lx + tol && y >= -tol && y <= ly + tol) {
            return None;
        }
        let cell = |v: &[f64], c: f64| v.partition_point(|&t| t <= c).clamp(1, v.len() - 1) - 1;
        let (i, j) = (cell(&self.x, x), cell(&self.y, y));
        let xi = ((x - self.x[i]) / self.dx[i]).clamp(0.0, 1.0);
        let eta = ((y - self.y[j]) / self.dy[j]).clamp(0.0, 1.0);
        Some(Spot { element: (i, j), xi, eta })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_lines_pass_through_every_point_and_points_are_found() {
        let g = Grid::through(0.5, 0.4, 10, 8, &[(0.123, 0.301), (0.25, 0.05)]);
        for (x, y) in [(0.123, 0.301), (0.25, 0.05), (0.0, 0.0), (0.5, 0.4)] {
            let n = g.node_at(x, y).expect("a node");
            assert_eq!(g.position(n), (x, y));
        }
        assert!(g.node_at(0.124, 0.301).is_none());
        let s = g.locate(0.124, 0.301).unwrap();
        let (i, j) = s.element;
        let x = g.x[i] + s.xi * g.dx[i];
        let y = g.y[j] + s.eta * g.dy[j];
        assert!((x - 0.124).abs() < 1e-15 && (y - 0.301).abs() < 1e-15);
        assert!(g.locate(0.6, 0.1).is_none());
    }
}
