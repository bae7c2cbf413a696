//! DOF numbering.

use crate::beam::Beam;

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

    /// The global DOFs of a beam element's (w₁, θ₁, w₂, θ₂).
    pub fn element_dofs(&self, nodes: [usize; 2]) -> [Option<usize>; 4] {
        [self.w[nodes[0]], self.theta[nodes[0]], self.w[nodes[1]], self.theta[nodes[1]]]
    }
}
