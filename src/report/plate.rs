//! Figures of a plate: its mode shapes as colour maps with their nodal lines, and the plate
//! drawn with its edges, point supports, actuator feet and sensors.

use super::figures::{save, Dest};
use super::plot::legend::{Entry, Swatch};
use super::plot::{HeatMap, MapGrid, MapMark, Marker, Shape};
use crate::analysis::case_run::CaseRun;
use crate::analysis::modes::ModesResult;
use crate::error::Result;
use crate::plate::{element as bfs, Edge, Plate, PointSupportKind};
use plotters::style::RGBColor;
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

/// Width of the layout's legend strip (px at 100 dpi), added to the plate's drawing.
const LEGEND_PX: u32 = 220;

/// `<stem>_layout`: the plate drawn to scale with a margin around it, each edge drawn as
/// its support is (clamped hatched, simply supported dashed, free thin, as in structural
/// drawings), point supports, masses and springs, actuator feet and sensors, and a legend
/// of those symbols.
pub fn layout_figure(dir: Dest, stem: &str, plate: &Plate, run: &CaseRun) -> Result<Vec<PathBuf>> {
    let (lx, ly) = plate.grid.lengths();
    let regions = if plate.is_uniform() { "" } else { " (regions of other sheets)" };
    let title = format!("The plate, {lx} × {ly} × {} m{regions}, and what stands on it", plate.thickness);
    // A blank field over the plate and a margin (m) around it, so that a marker on an edge
    // or at a corner is drawn whole, and the hatching of a clamped edge has room.
    let pad = 0.04 * lx.max(ly);
    let mut h = plate_map(plate, title, "", 900);
    // To scale: a plot area about 900 px wide beside the tick labels and the legend, and
    // as high as the plate and its margin are in proportion, above the x axis' labels.
    h.size = (900 + 110 + LEGEND_PX, 135 + (900.0 * (ly + 2.0 * pad) / (lx + 2.0 * pad)) as u32);
    (h.x, h.y, h.z) = (blank_cells(lx, pad), blank_cells(ly, pad), vec![0.0; 4]);
    h.diverging = true;
    draw_edges(&mut h, plate, pad);
    mark_points(&mut h, plate, run);
    save(&h, dir, &format!("{stem}_layout"))
}

/// Centres of two cells whose edges run from −pad to `length` + pad.
fn blank_cells(length: f64, pad: f64) -> Vec<f64> {
    let d = 0.5 * (length + 2.0 * pad);
    vec![-pad + 0.5 * d, -pad + 1.5 * d]
}

/// Each edge in the style of its support, hatched outside the plate where clamped, and a
/// legend entry per kind of edge the plate has.
fn draw_edges(h: &mut HeatMap, plate: &Plate, pad: f64) {
    let (lx, ly) = plate.grid.lengths();
    let e = plate.edges;
    // (support, from, to, outward normal)
    let edges = [
        (e.x0, (0.0, 0.0), (0.0, ly), (-1.0, 0.0)),
        (e.x1, (lx, 0.0), (lx, ly), (1.0, 0.0)),
        (e.y0, (0.0, 0.0), (lx, 0.0), (0.0, -1.0)),
        (e.y1, (0.0, ly), (lx, ly), (0.0, 1.0)),
    ];
    for &(support, a, b, n) in &edges {
        match support {
            Edge::Clamped => {
                h.lines.push(vec![a, b]);
                h.thin.extend(hatching(a, b, n, 0.6 * pad));
            }
            Edge::SimplySupported => h.dashed.push(vec![a, b]),
            Edge::Free => h.thin.push(vec![a, b]),
        }
    }
    let black = RGBColor(0, 0, 0);
    for (kind, label, swatch) in [
        (Edge::Clamped, "clamped edge", Swatch::Hatched),
        (Edge::SimplySupported, "simply supported edge", Swatch::Dashed),
        (Edge::Free, "free edge", Swatch::Thin),
    ] {
        if edges.iter().any(|ed| ed.0 == kind) {
            h.legend.push(Entry { label: label.into(), color: black, swatch, marker: Marker::nth(0) });
        }
    }
}

/// Short strokes from edge `a`–`b` outwards along `n`, slanted, `len` (m) long.
fn hatching(a: (f64, f64), b: (f64, f64), n: (f64, f64), len: f64) -> Vec<Vec<(f64, f64)>> {
    let span = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
    let t = ((b.0 - a.0) / span, (b.1 - a.1) / span);
    let count = (span / len).round().max(2.0) as usize;
    (0..=count)
        .map(|k| {
            let s = k as f64 / count as f64;
            let p = (a.0 + s * (b.0 - a.0), a.1 + s * (b.1 - a.1));
            vec![p, (p.0 + len * (n.0 - t.0), p.1 + len * (n.1 - t.1))]
        })
        .collect()
}

/// The legend's name for the line joining a frame actuator's legs.
const FRAME_BASE: &str = "frame base (joins its legs)";

/// A point to mark: its marker shape, whether hollow, its kind (the legend entry), where
/// (m) and its label.
type PointMark<'a> = (Shape, bool, &'a str, (f64, f64), String);

/// Point supports, masses and springs, actuator feet and sensors, each kind its own
/// marker with a legend entry.
fn mark_points(h: &mut HeatMap, plate: &Plate, run: &CaseRun) {
    use super::plot::text::{si, significant};
    let at = |node: usize| plate.grid.position(node);
    let mut marks: Vec<PointMark> = Vec::new();
    for s in &plate.supports {
        let what = match s.kind {
            PointSupportKind::Pinned => "pinned".to_string(),
            PointSupportKind::Clamped => "clamped".to_string(),
            PointSupportKind::Spring { k_w } => si(k_w, "N/m", 3),
        };
        marks.push((Shape::Square, false, "point support", at(s.node), what));
    }
    for m in &plate.point_masses {
        marks.push((Shape::Circle, false, "point mass", at(m.node), format!("{} kg", significant(m.mass, 3))));
    }
    for k in &plate.springs {
        marks.push((Shape::Diamond, true, "spring to the ground", at(k.node), si(k.stiffness, "N/m", 3)));
    }
    // An actuator is named once, at its stack's foot; a frame's legs are joined by a solid
    // line (its rigid base, unhatched: not a clamped edge), so that two frames side by side
    // stay apart without a label per foot.
    for (a, actuator) in run.model.actuators.iter().enumerate() {
        let feet: Vec<_> = run
            .system
            .links
            .iter()
            .filter(|lk| lk.actuator == a)
            .filter_map(|lk| lk.foot_at.map(|foot| (lk.active, (foot.x(), foot.y().unwrap_or(0.0)))))
            .collect();
        let legs: Vec<(f64, f64)> = feet.iter().filter(|f| !f.0).map(|f| f.1).collect();
        if legs.len() == 2 {
            h.lines.push(legs.clone());
            if !h.legend.iter().any(|e| e.label == FRAME_BASE) {
                let black = RGBColor(0, 0, 0);
                h.legend.push(Entry {
                    label: FRAME_BASE.into(),
                    color: black,
                    swatch: Swatch::Line,
                    marker: Marker::nth(0),
                });
            }
        }
        for (active, at) in feet {
            let (kind, label) = if active {
                ("actuator foot: stack", actuator.name().to_string())
            } else {
                ("actuator foot: leg", String::new())
            };
            marks.push((Shape::TriangleUp, !active, kind, at, label));
        }
    }
    for s in &run.model.sensors {
        marks.push((Shape::Circle, true, "sensor", (s.at.x(), s.at.y().unwrap_or(0.0)), s.name.clone()));
    }
    for (shape, hollow, kind, (x, y), label) in marks {
        let marker = Marker { shape, hollow };
        if !h.legend.iter().any(|e| e.label == kind) {
            let black = RGBColor(0, 0, 0);
            h.legend.push(Entry { label: kind.into(), color: black, swatch: Swatch::Markers, marker });
        }
        h.marks.push(MapMark { x, y, label, marker });
    }
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
