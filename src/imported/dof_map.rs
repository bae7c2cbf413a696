//! The DOF map of an imported model (spec §17): a CSV file with header
//! `row,node,x_m,y_m,z_m,component`, one line per matrix row, naming the node the row
//! belongs to, where that node is and which of its motions the row is.

use crate::error::{Error, Result};
use std::collections::HashMap;
use std::path::Path;

/// The header every DOF map starts with.
pub const HEADER: &str = "row,node,x_m,y_m,z_m,component";

/// The components a row may be: translations and rotations along the global axes, then
/// beamflow's own DOF kinds (the beam's w, θ and the plate's w, ∂w/∂x, ∂w/∂y, ∂²w/∂x∂y),
/// which its own matrix export writes, so that its files round-trip exactly, then the
/// slope along an edge's normal of elements such as Morley's triangle ([`EDGE_SLOPE`]).
pub const COMPONENTS: [&str; 12] = ["ux", "uy", "uz", "rx", "ry", "rz", "w", "theta", "w_x", "w_y", "w_xy", "w_n"];

/// The slope ∂w/∂n along an edge's normal, at a node of the edge. Which way the normal
/// points is the exporter's choice and the map does not say it, so nothing attaches there.
pub const EDGE_SLOPE: &str = "w_n";

/// A component as a case writes it, `uz`, `+uz` or `-uz` (the side an actuator stands on):
/// its index into [`COMPONENTS`] and its sign.
pub fn parse_component(text: &str) -> std::result::Result<(u8, i8), String> {
    let t = text.trim();
    let (sign, name) = match t.strip_prefix('-').or_else(|| t.strip_prefix('−')) {
        Some(rest) => (-1, rest),
        None => (1, t.strip_prefix('+').unwrap_or(t)),
    };
    if name.trim().eq_ignore_ascii_case(EDGE_SLOPE) {
        return Err(format!(
            "{text:?} is the slope along an edge's normal, which points the way the exporter chose: \
             nothing attaches to it; give a deflection (uz or w) at a vertex node"
        ));
    }
    COMPONENTS.iter().position(|c| c.eq_ignore_ascii_case(name.trim())).map(|i| (i as u8, sign)).ok_or_else(|| {
        let attachable: Vec<&str> = COMPONENTS.iter().copied().filter(|c| *c != EDGE_SLOPE).collect();
        format!("{text:?} is not a component: give one of {} with an optional sign", attachable.join(", "))
    })
}

/// A node of the imported model: its id in the source code and where it is (m).
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub id: i64,
    pub xyz: [f64; 3],
}

/// The rows of the matrices by node and component.
#[derive(Clone, Debug)]
pub struct DofTable {
    pub nodes: Vec<Node>,
    /// For each matrix row (0-based), its node (index into `nodes`) and component (index
    /// into [`COMPONENTS`]).
    pub rows: Vec<(usize, usize)>,
    pub by_id: HashMap<i64, usize>,
}

/// Reads the DOF map of an `n`-row model, refusing a wrong header, a row outside 1..=n or
/// given twice or missing, an unknown component, a node given two positions, or the same
/// node and component on two rows.
pub fn read(path: &Path, n: usize) -> Result<DofTable> {
    // Each line is at most a few hundred bytes: bound the read by the row count.
    let limit = 64 + 512 * n as u64;
    let text = crate::input_file::read_text_limited(path, limit)?;
    let name = path.display().to_string();
    let at = |line: usize, why: String| Error::input(&name, format!("line {line}"), why);
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim())).filter(|(_, l)| !l.is_empty());
    match lines.next() {
        Some((_, h)) if h.split(',').map(str::trim).eq(HEADER.split(',')) => {}
        Some((i, h)) => return Err(at(i, format!("header {h:?}: write `{HEADER}`"))),
        None => return Err(at(1, format!("the file is empty: write `{HEADER}` and one line per matrix row"))),
    }
    let mut table = DofTable { nodes: Vec::new(), rows: vec![(usize::MAX, 0); n], by_id: HashMap::new() };
    let mut seen: HashMap<(usize, usize), usize> = HashMap::new();
    for (i, line) in lines {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let [row, node, x, y, z, comp] = f.as_slice() else {
            return Err(at(i, format!("{} fields: write `{HEADER}`", f.len())));
        };
        let row = match row.parse::<usize>() {
            Ok(r) if (1..=n).contains(&r) => r - 1,
            _ => return Err(at(i, format!("row {row:?} is not in 1..={n} (the matrices' size)"))),
        };
        let id: i64 = node.parse().map_err(|_| at(i, format!("node {node:?} is not a whole number")))?;
        let mut xyz = [0.0; 3];
        for (v, s) in xyz.iter_mut().zip([x, y, z]) {
            *v = s
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite())
                .ok_or_else(|| at(i, format!("coordinate {s:?} is not a finite number (m)")))?;
        }
        let kind = COMPONENTS
            .iter()
            .position(|c| c.eq_ignore_ascii_case(comp))
            .ok_or_else(|| at(i, format!("component {comp:?} is not one of {}", COMPONENTS.join(", "))))?;
        let index = match table.by_id.get(&id) {
            Some(&k) => {
                let p = table.nodes[k].xyz;
                let scale = p.iter().chain(&xyz).fold(1.0f64, |a, v| a.max(v.abs()));
                if p.iter().zip(&xyz).any(|(a, b)| (a - b).abs() > 1e-9 * scale) {
                    return Err(at(i, format!("node {id} is at {xyz:?} here but at {p:?} on an earlier line")));
                }
                k
            }
            None => {
                table.by_id.insert(id, table.nodes.len());
                table.nodes.push(Node { id, xyz });
                table.nodes.len() - 1
            }
        };
        if table.rows[row].0 != usize::MAX {
            return Err(at(i, format!("row {} is given twice", row + 1)));
        }
        if let Some(r) = seen.insert((index, kind), row) {
            return Err(at(i, format!("node {id} {} is already row {}", COMPONENTS[kind], r + 1)));
        }
        table.rows[row] = (index, kind);
    }
    if let Some(r) = table.rows.iter().position(|r| r.0 == usize::MAX) {
        return Err(Error::input(&name, "row", format!("row {} of the {n} matrix rows has no line", r + 1)));
    }
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_stands_on_a_deflection_or_rotation_never_on_an_edge_slope() {
        assert_eq!(parse_component("-uz"), Ok((2, -1)));
        for text in ["w_n", "-W_N"] {
            let e = parse_component(text).unwrap_err();
            assert!(e.contains("edge's normal") && e.contains("uz or w"), "{e}");
        }
        assert!(!parse_component("sideways").unwrap_err().contains("w_n"));
    }

    #[test]
    fn a_map_names_every_row_and_each_mistake_its_line() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("dofs.csv");
        std::fs::write(&p, format!("{HEADER}\n1,7,0,0,0,uz\n2,7,0,0,0,ry\n3,9,1.5,0,0,uz\n")).unwrap();
        let t = read(&p, 3).unwrap();
        assert_eq!(t.nodes.len(), 2);
        assert_eq!(t.rows, [(0, 2), (0, 4), (1, 2)]);
        for (body, n, expect) in [
            ("1,7,0,0,0,uz\n2,7,0,0,0,uz\n", 2, "already row 1"),
            ("1,7,0,0,0,uz\n1,7,0,0,0,ry\n", 2, "given twice"),
            ("1,7,0,0,0,uz\n", 2, "row 2 of the 2"),
            ("1,7,0,0,0,uz\n2,7,1,0,0,ry\n", 2, "node 7 is at"),
            ("1,7,0,0,0,q\n", 1, "component"),
            ("3,7,0,0,0,uz\n", 1, "not in 1..=1"),
            ("1,x,0,0,0,uz\n", 1, "whole number"),
            ("1,7,nan,0,0,uz\n", 1, "finite"),
        ] {
            std::fs::write(&p, format!("{HEADER}\n{body}")).unwrap();
            let e = read(&p, n).unwrap_err().to_string();
            assert!(e.contains("dofs.csv") && e.contains(expect), "{e} (expected {expect})");
        }
        std::fs::write(&p, format!("{HEADER}\n1,7,0,0,0,uz\n2,8,0.5,0,0,w_n\n")).unwrap();
        assert_eq!(read(&p, 2).unwrap().rows, [(0, 2), (1, 11)]);
        std::fs::write(&p, "row,node,x,kind\n").unwrap();
        assert!(read(&p, 1).unwrap_err().to_string().contains("header"));
    }
}
