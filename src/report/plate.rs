//! Figures of a plate: its mode shapes as colour maps with their nodal lines, and the plate
//! drawn with its edges, point supports, actuator feet and sensors.

use super::figures::{save, Dest};
use super::plot::{HeatMap, MapGrid, MapMark, Marker};
use crate::analysis::case_run::CaseRun;
use crate::analysis::modes::ModesResult;
use crate::error::Result;
use crate::plate::{element as bfs, Edge, Plate};
use std::path::PathBuf;

/// Samples per element side: the field between nodes follows the element's own bicubic
/// shape functions, so maps of coarse meshes are smooth.
const SUB: usize = 4;

/// A field given by its node DOFs (`node·4 + kind`, the plate's w, w_x, w_y, w_xy) sampled
/// at the centres of SUB × SUB cells of every element: cell centres along x and y, and the
/// values row-major (`z[j·nx + i]`).
pub fn sample(plate: &Plate, dofs: &[f64]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let g = &plate.grid;
    let centres = |lines: &[f64], sides: &[f64]| -> Vec<(usize, f64, f64)> {
        (0..sides.len())
            .flat_map(|e| (0..SUB).map(move |k| (e, (k as f64 + 0.5) / SUB as f64)))
            .map(|(e, t)| (e, t, lines[e] + t * sides[e]))
            .collect()
    };
    let (cx, cy) = (centres(&g.x, &g.dx), centres(&g.y, &g.dy));
    let mut z = Vec::with_capacity(cx.len() * cy.len());
    for &(j, eta, _) in &cy {
        for &(i, xi, _) in &cx {
            let n = bfs::shape(g.dx[i], g.dy[j], xi, eta)[0];
            let nodes = g.element_nodes(i, j);
            z.push(
                (0..bfs::DOFS)
                    .map(|c| n[c] * dofs[nodes[c / bfs::NODE_DOFS] * bfs::NODE_DOFS + c % bfs::NODE_DOFS])
                    .sum(),
            );
        }
    }
    (cx.iter().map(|c| c.2).collect(), cy.iter().map(|c| c.2).collect(), z)
}

/// The zero level of a sampled field as line segments (marching squares between the
/// sample points, the crossing found by linear interpolation): a mode's nodal lines.
pub fn zero_lines(x: &[f64], y: &[f64], z: &[f64]) -> Vec<Vec<(f64, f64)>> {
    let nx = x.len();
    let at = |i: usize, j: usize| z[j * nx + i];
    let cut = |(xa, ya, za): (f64, f64, f64), (xb, yb, zb): (f64, f64, f64)| {
        let t = za / (za - zb);
        (xa + t * (xb - xa), ya + t * (yb - ya))
    };
    let mut out = Vec::new();
    for j in 0..y.len().saturating_sub(1) {
        for i in 0..nx.saturating_sub(1) {
            let c = [
                (x[i], y[j], at(i, j)),
                (x[i + 1], y[j], at(i + 1, j)),
                (x[i + 1], y[j + 1], at(i + 1, j + 1)),
                (x[i], y[j + 1], at(i, j + 1)),
            ];
            let crossings: Vec<(f64, f64)> = (0..4)
                .filter(|&k| (c[k].2 < 0.0) != (c[(k + 1) % 4].2 < 0.0))
                .map(|k| cut(c[k], c[(k + 1) % 4]))
                .collect();
            // Two crossings: one segment; four (a saddle): pair them around the corners.
            for pair in crossings.chunks_exact(2) {
                out.push(vec![pair[0], pair[1]]);
            }
        }
    }
    out
}

/// The plate's outline, each edge its own line (so a figure can tell them apart).
fn outline(plate: &Plate) -> Vec<Vec<(f64, f64)>> {
    let (lx, ly) = plate.grid.lengths();
    vec![vec![(0.0, 0.0), (lx, 0.0), (lx, ly), (0.0, ly), (0.0, 0.0)]]
}

/// A map of the plate of `plate`'s proportions (`width` px wide plus its colour bar).
fn plate_map(plate: &Plate, title: String, label: &str, width: u32) -> HeatMap {
    let (lx, ly) = plate.grid.lengths();
    let mut h = HeatMap::new(title, "x (m)", "y (m)", label);
    h.size = (width + 150, ((width as f64 * ly / lx) as u32 + 130).max(260));
    h
}

/// `<tag>` of a modes analysis on a plate: the first six mode shapes as colour maps of w
/// with their nodal lines (w = 0) in black.
pub fn modes_figure(dir: Dest, tag: &str, plate: &Plate, m: &ModesResult) -> Result<Vec<PathBuf>> {
    let mut panels = Vec::new();
    for (r, dofs) in m.node_shapes.iter().enumerate().take(6) {
        let mut h = plate_map(plate, format!("mode {}: {:.2} Hz", r + 1, m.frequencies_hz[r]), "w (m/√kg)", 520);
        let (x, y, z) = sample(plate, dofs);
        h.lines = zero_lines(&x, &y, &z);
        h.lines.extend(outline(plate));
        (h.x, h.y, h.z) = (x, y, z);
        h.diverging = true;
        panels.push(h);
    }
    let grid = MapGrid {
        title: "Mode shapes of the bare plate (mass-normalised; nodal lines in black)".into(),
        panels,
        columns: 2,
    };
    save(&grid, dir, tag)
}

/// `<stem>_layout`: the plate with its edges named, point supports, actuator feet and
/// sensors, drawn to scale.
pub fn layout_figure(dir: Dest, stem: &str, plate: &Plate, run: &CaseRun) -> Result<Vec<PathBuf>> {
    let (lx, ly) = plate.grid.lengths();
    let edge = |e: Edge| match e {
        Edge::Clamped => "clamped",
        Edge::SimplySupported => "simply supported",
        Edge::Free => "free",
    };
    let e = plate.edges;
    let regions = if plate.is_uniform() { "" } else { " (regions of other sheets)" };
    let title =
        format!("The plate, {lx} × {ly} × {} m{regions}, its edges, actuator feet and sensors", plate.thickness);
    let mut h = plate_map(plate, title, "", 900);
    // A blank field over the whole plate: the figure is the drawing on top of it.
    (h.x, h.y, h.z) = (vec![0.25 * lx, 0.75 * lx], vec![0.25 * ly, 0.75 * ly], vec![0.0; 4]);
    h.diverging = true;
    h.lines = outline(plate);
    let side = |label: &str, e: Edge, x: f64, y: f64| MapMark {
        x,
        y,
        label: format!("{label}: {}", edge(e)),
        marker: Marker { shape: super::plot::Shape::Diamond, hollow: true },
    };
    h.marks.extend([
        side("x = 0", e.x0, 0.0, 0.5 * ly),
        side(&format!("x = {lx}"), e.x1, lx, 0.08 * ly),
        side("y = 0", e.y0, 0.3 * lx, 0.0),
        side(&format!("y = {ly}"), e.y1, 0.3 * lx, ly),
    ]);
    for s in &plate.supports {
        let (x, y) = plate.grid.position(s.node);
        h.marks.push(MapMark {
            x,
            y,
            label: "support".into(),
            marker: Marker { shape: super::plot::Shape::Square, hollow: false },
        });
    }
    for lk in &run.system.links {
        let Some(at) = lk.foot_at else { continue };
        let name = crate::actuator::link_id(run.model.actuators[lk.actuator].name(), &lk.name);
        let marker = Marker { shape: super::plot::Shape::TriangleUp, hollow: !lk.active };
        h.marks.push(MapMark { x: at.x(), y: at.y().unwrap_or(0.0), label: name, marker });
    }
    for s in &run.model.sensors {
        let marker = Marker { shape: super::plot::Shape::Circle, hollow: true };
        h.marks.push(MapMark { x: s.at.x(), y: s.at.y().unwrap_or(0.0), label: s.name.clone(), marker });
    }
    save(&h, dir, &format!("{stem}_layout"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plate::{Edges, Grid};
    use std::f64::consts::PI;

    /// The (2, 1) mode of a simply supported plate, given by its exact node DOFs: sampled
    /// through the shape functions it matches the sine to the bicubic's accuracy, and its
    /// nodal line is found at x = L_x/2.
    #[test]
    fn a_sampled_mode_matches_its_function_and_its_nodal_line_is_found() {
        let (lx, ly) = (0.5, 0.4);
        let ss = crate::plate::Edge::SimplySupported;
        let plate = Plate {
            grid: Grid::through(lx, ly, 10, 8, &[]),
            thickness: 0.003,
            youngs_modulus: 70e9,
            poisson_ratio: 0.33,
            density: 2700.0,
            sheets: vec![],
            element_sheet: vec![],
            edges: Edges { x0: ss, x1: ss, y0: ss, y1: ss },
            supports: vec![],
            point_masses: vec![],
            springs: vec![],
        };
        let (a, b) = (2.0 * PI / lx, PI / ly);
        let dofs: Vec<f64> = (0..plate.grid.n_nodes())
            .flat_map(|n| {
                let (x, y) = plate.grid.position(n);
                let (sx, cx, sy, cy) = ((a * x).sin(), (a * x).cos(), (b * y).sin(), (b * y).cos());
                [sx * sy, a * cx * sy, b * sx * cy, a * b * cx * cy]
            })
            .collect();
        let (xs, ys, z) = sample(&plate, &dofs);
        for (k, v) in z.iter().enumerate() {
            let (x, y) = (xs[k % xs.len()], ys[k / xs.len()]);
            assert!((v - (a * x).sin() * (b * y).sin()).abs() < 2e-3, "at ({x}, {y})");
        }
        let lines = zero_lines(&xs, &ys, &z);
        assert!(!lines.is_empty());
        for seg in &lines {
            for &(x, _) in seg {
                assert!((x - 0.5 * lx).abs() < 1e-3, "nodal line point at x = {x}");
            }
        }
    }
}
