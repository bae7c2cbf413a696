//! DOF numbering.

use crate::error::Error;
use crate::structure::Structure;

/// Global DOF index of every structure node DOF and every actuator body DOF.
#[derive(Clone, Debug, Default)]
pub struct DofMap {
    /// Number of free DOFs.
    pub n: usize,
    /// The DOF kinds each structure node carries (`w`, `theta` on a beam; `w`, `w_x`,
    /// `w_y`, `w_xy` on a plate); the first is the normal displacement w.
    pub kinds: &'static [&'static str],
    /// `nodes[node·kinds.len() + kind]`: the DOF of that node and kind (None where a support
    /// fixes it).
    pub nodes: Vec<Option<usize>>,
    /// For each actuator, the global index of each of its body DOFs.
    pub bodies: Vec<Vec<usize>>,
    /// The structure's kind, for messages ("beam", "plate").
    pub structure: &'static str,
}

impl DofMap {
    /// Numbers the DOFs: the structure's nodes in its own order
    /// ([`Structure::node_order`]), each with its free DOFs, and each actuator's body DOFs
    /// right after `anchors[a]`, the node its feet reach last in that order (None for an
    /// actuator on the rigid ground: after everything); `body_sizes[a]` its body DOFs.
    pub fn number(structure: Option<&Structure>, anchors: &[Option<usize>], body_sizes: &[usize]) -> DofMap {
        let order = structure.map(Structure::node_order).unwrap_or_default();
        DofMap::number_in(structure, &order, anchors, body_sizes)
    }

    /// [`DofMap::number`] with the structure's node order already computed (`order`, from
    /// [`Structure::node_order`]).
    pub fn number_in(
        structure: Option<&Structure>,
        order: &[usize],
        anchors: &[Option<usize>],
        body_sizes: &[usize],
    ) -> DofMap {
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
        if let Some(s) = structure {
            map.kinds = s.dof_names();
            map.structure = s.kind();
            map.nodes = vec![None; s.n_nodes() * map.kinds.len()];
            for &node in order {
                for (k, &fixed) in s.fixed(node).iter().enumerate() {
                    map.nodes[node * map.kinds.len() + k] = (!fixed).then(&mut take);
                }
                place_bodies(&mut map, &mut take, Some(node));
            }
        }
        place_bodies(&mut map, &mut take, None);
        map.n = next;
        map
    }

    /// This numbering of a structure alone (no bodies) with bodies of `body_sizes` DOFs
    /// after it, as [`DofMap::number`] places bodies without anchors. Errors if `structure`
    /// is not the one numbered (its nodes or DOF kinds differ).
    pub fn with_bodies(&self, structure: Option<&Structure>, body_sizes: &[usize]) -> crate::error::Result<DofMap> {
        let same = structure.map_or(self.nodes.is_empty(), |s| {
            s.dof_names() == self.kinds && s.n_nodes() * self.kinds.len() == self.nodes.len()
        });
        if !same || self.bodies.iter().any(|b| !b.is_empty()) {
            return Err(crate::error::Error::Numerical(
                "the case's structure is not the one the study's shared reduction was built on".into(),
            ));
        }
        let mut next = self.n;
        let bodies = body_sizes
            .iter()
            .map(|&size| {
                next += size;
                (next - size..next).collect()
            })
            .collect();
        Ok(DofMap { n: next, bodies, ..self.clone() })
    }

    /// Number of structure nodes.
    pub fn n_nodes(&self) -> usize {
        if self.kinds.is_empty() {
            0
        } else {
            self.nodes.len() / self.kinds.len()
        }
    }

    /// The DOF of a node's `kind` (index into [`DofMap::kinds`]).
    pub fn node_dof(&self, node: usize, kind: usize) -> Option<usize> {
        self.nodes[node * self.kinds.len() + kind]
    }

    /// The normal displacement w of a node.
    pub fn w(&self, node: usize) -> Option<usize> {
        self.node_dof(node, 0)
    }

    /// The w DOF of every node, in node order.
    pub fn w_dofs(&self) -> impl Iterator<Item = Option<usize>> + '_ {
        self.nodes.iter().step_by(self.kinds.len().max(1)).copied()
    }

    /// All structure DOFs in numbering order.
    pub fn structure_dofs(&self) -> Vec<usize> {
        let mut d: Vec<usize> = self.nodes.iter().flatten().copied().collect();
        d.sort_unstable();
        d
    }

    /// The node and kind of a structure DOF.
    pub fn node_of(&self, d: usize) -> Option<(usize, usize)> {
        let k = self.kinds.len();
        self.nodes.iter().position(|&x| x == Some(d)).map(|at| (at / k, at % k))
    }

    /// Where DOF `d` is, for messages: `w (deflection) at beam node 12`, `θ (rotation) at
    /// beam node 3`, `w_x at plate node 40`, or `body DOF 1 of actuator 0`.
    pub fn describe(&self, d: usize) -> String {
        if let Some((node, k)) = self.node_of(d) {
            let kind = match self.kinds[k] {
                "w" => "w (deflection)",
                "theta" => "θ (rotation)",
                other => other,
            };
            format!("DOF {d}, {kind} at {} node {node}", self.structure)
        } else if let Some((a, k)) =
            self.bodies.iter().enumerate().find_map(|(a, b)| b.iter().position(|&x| x == d).map(|k| (a, k)))
        {
            format!("DOF {d}, body DOF {k} of actuator {a}")
        } else {
            format!("DOF {d}")
        }
    }

    /// Names the place of a [`Error::Singular`] pivot of a matrix numbered by this map, with
    /// the structure node's position and what to change; other errors pass through.
    pub fn locate(&self, e: Error, structure: Option<&Structure>) -> Error {
        let Error::Singular { row, detail } = e else { return e };
        if row >= self.n {
            return Error::Singular { row, detail };
        }
        let node = self.node_of(row).map(|(n, _)| n);
        let (at, fields) = match (node, structure) {
            (Some(n), Some(s)) if n < s.n_nodes() => {
                (format!("{} ({})", self.describe(row), s.node_location(n)), s.support_fields())
            }
            (_, Some(s)) => (self.describe(row), s.support_fields()),
            _ => (self.describe(row), "the supports"),
        };
        Error::Numerical(format!(
            "{detail} at {at}: the structure is not held against that motion (check {fields}), or a \
             frequency meets an undamped resonance (add damping)"
        ))
    }

    /// The global DOFs of an element's nodes, node by node, each node's kinds in order.
    pub fn element_dofs(&self, nodes: &[usize]) -> Vec<Option<usize>> {
        let k = self.kinds.len();
        nodes.iter().flat_map(|&n| self.nodes[n * k..(n + 1) * k].iter().copied()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::{Beam, Material, Mesh, Section, Support, SupportKind};
    use crate::linalg::Skyline;

    /// A cantilever of two elements (node 0 clamped): rows 0, 1 are w, θ of node 1 and
    /// rows 2, 3 those of node 2; a singular column at node 2's w is named by node and x.
    #[test]
    fn a_singular_pivot_is_named_by_node_and_position() {
        let section = Section { width: 0.05, thickness: 0.005 };
        let material = Material { youngs_modulus: 210e9, density: 7850.0 };
        let beam = Beam::new(
            Mesh::uniform(0.5, 2, &[], section, material),
            vec![Support { node: 0, kind: SupportKind::Clamped }],
        );
        let structure = Structure::Beam(beam);
        let map = DofMap::number(Some(&structure), &[], &[]);
        assert_eq!(map.n, 4);
        assert_eq!((map.w(1), map.node_dof(1, 1), map.w(2), map.node_dof(2, 1)), (Some(0), Some(1), Some(2), Some(3)));
        // Diagonal except row 2, which repeats row 0: the pivot of row 2 vanishes.
        let mut a = Skyline::<f64>::zeros(Skyline::<f64>::envelope_of(4, [(0, 2)]));
        for (i, v) in [(0, 2.0), (1, 1.0), (2, 2.0), (3, 1.0)] {
            a.add(i, i, v);
        }
        a.add(2, 0, 2.0);
        let e = a.factorize().map(|_| ()).unwrap_err();
        assert!(matches!(e, Error::Singular { row: 2, .. }), "{e:?}");
        let msg = map.locate(e, Some(&structure)).to_string();
        assert!(msg.contains("w (deflection) at beam node 2 (x = 0.5 m)") && msg.contains("beam.support"), "{msg}");
        // Rows past the map and other errors pass through unchanged.
        let e = map.locate(Error::Singular { row: 9, detail: "d".into() }, None);
        assert!(matches!(e, Error::Singular { row: 9, .. }));
        assert!(matches!(map.locate(Error::Numerical("n".into()), None), Error::Numerical(_)));
    }
}
