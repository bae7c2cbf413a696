//! DOF numbering.

use crate::beam::Beam;
use crate::error::Error;

/// Global DOF index of every beam node DOF and every actuator body DOF.
#[derive(Clone, Debug, Default)]
pub struct DofMap {
    /// Number of free DOFs.
    pub n: usize,
    /// w DOF of each beam node (None where a support fixes it).
    pub w: Vec<Option<usize>>,
    /// θ DOF of each beam node.
    pub theta: Vec<Option<usize>>,
    /// For each actuator, the global index of each of its body DOFs.
    pub bodies: Vec<Vec<usize>>,
}

impl DofMap {
    /// Numbers the DOFs. `anchors[a]` is the last beam node actuator a's feet stand on
    /// (None for an actuator on the rigid ground), `body_sizes[a]` its number of body DOFs.
    pub fn number(beam: Option<&Beam>, anchors: &[Option<usize>], body_sizes: &[usize]) -> DofMap {
        let mut map = DofMap { bodies: vec![Vec::new(); anchors.len()], ..Default::default() };
        let mut next = 0usize;
        let mut take = || {
            next += 1;
            next - 1
        };
        let place_bodies = |map: &mut DofMap, take: &mut dyn FnMut() -> usize, node: Option<usize>| {
            for (a, anchor) in anchors.iter().enumerate() {
                if *anchor == node {
                    map.bodies[a] = (0..body_sizes[a]).map(|_| take()).collect();
                }
            }
        };
        if let Some(beam) = beam {
            for node in 0..beam.mesh.n_nodes() {
                let (wf, tf) = beam.fixed(node);
                map.w.push((!wf).then(&mut take));
                map.theta.push((!tf).then(&mut take));
                place_bodies(&mut map, &mut take, Some(node));
            }
        }
        place_bodies(&mut map, &mut take, None);
        map.n = next;
        map
    }

    /// All beam DOFs in numbering order.
    pub fn beam_dofs(&self) -> Vec<usize> {
        let mut d: Vec<usize> = self.w.iter().chain(&self.theta).flatten().copied().collect();
        d.sort_unstable();
        d
    }

    /// Where DOF `d` is, for messages: `w (deflection) at node 12`, `θ (rotation) at node
    /// 3`, or `body DOF 1 of actuator 0`.
    pub fn describe(&self, d: usize) -> String {
        let at = |v: &[Option<usize>]| v.iter().position(|&x| x == Some(d));
        if let Some(node) = at(&self.w) {
            format!("DOF {d}, w (deflection) at beam node {node}")
        } else if let Some(node) = at(&self.theta) {
            format!("DOF {d}, θ (rotation) at beam node {node}")
        } else if let Some((a, k)) =
            self.bodies.iter().enumerate().find_map(|(a, b)| b.iter().position(|&x| x == d).map(|k| (a, k)))
        {
            format!("DOF {d}, body DOF {k} of actuator {a}")
        } else {
            format!("DOF {d}")
        }
    }

    /// Names the place of a [`Error::Singular`] pivot of a matrix numbered by this map, with
    /// the beam node's position (`node_x`, m) and what to change; other errors pass through.
    pub fn locate(&self, e: Error, node_x: &[f64]) -> Error {
        let Error::Singular { row, detail } = e else { return e };
        if row >= self.n {
            return Error::Singular { row, detail };
        }
        let node_of = |v: &[Option<usize>]| v.iter().position(|&x| x == Some(row));
        let node = node_of(&self.w).or_else(|| node_of(&self.theta));
        let at = match node.and_then(|n| node_x.get(n)) {
            Some(x) => format!("{} (x = {x} m)", self.describe(row)),
            None => self.describe(row),
        };
        Error::Numerical(format!(
            "{detail} at {at}: the structure is not held against that motion (check beam.support and \
             beam.spring), or a frequency meets an undamped resonance (add damping)"
        ))
    }

    /// The global DOFs of a beam element's (w₁, θ₁, w₂, θ₂).
    pub fn element_dofs(&self, nodes: [usize; 2]) -> [Option<usize>; 4] {
        [self.w[nodes[0]], self.theta[nodes[0]], self.w[nodes[1]], self.theta[nodes[1]]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::Skyline;

    /// A cantilever of two elements (node 0 clamped): rows 0, 1 are w, θ of node 1 and
    /// rows 2, 3 those of node 2; a singular column at node 2's w is named by node and x.
    #[test]
    fn a_singular_pivot_is_named_by_node_and_position() {
        let map = DofMap { n: 4, w: vec![None, Some(0), Some(2)], theta: vec![None, Some(1), Some(3)], bodies: vec![] };
        // Diagonal except row 2, which repeats row 0: the pivot of row 2 vanishes.
        let mut a = Skyline::<f64>::zeros(Skyline::<f64>::envelope_of(4, [(0, 2)]));
        for (i, v) in [(0, 2.0), (1, 1.0), (2, 2.0), (3, 1.0)] {
            a.add(i, i, v);
        }
        a.add(2, 0, 2.0);
        let e = a.factorize().map(|_| ()).unwrap_err();
        assert!(matches!(e, Error::Singular { row: 2, .. }), "{e:?}");
        let msg = map.locate(e, &[0.0, 0.25, 0.5]).to_string();
        assert!(msg.contains("w (deflection) at beam node 2 (x = 0.5 m)") && msg.contains("beam.support"), "{msg}");
        // Rows past the map and other errors pass through unchanged.
        let e = map.locate(Error::Singular { row: 9, detail: "d".into() }, &[]);
        assert!(matches!(e, Error::Singular { row: 9, .. }));
        assert!(matches!(map.locate(Error::Numerical("n".into()), &[]), Error::Numerical(_)));
    }
}
