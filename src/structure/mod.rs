//! The structure layer (spec §15): what every analysis sees of the structure, whatever its
//! kind — nodes with coordinates, DOF kinds per node, elements (connectivity plus element
//! matrices), supports, point masses and springs, and points where feet, loads and sensors
//! attach. The beam ([`crate::beam`]) and the plate ([`crate::plate`]) are kinds of it;
//! the beam keeps its own fast paths (its stiffness root, band kernels) behind it.

pub mod location;
pub mod ordering;

pub use location::Location;

use crate::beam::{element_mass, element_stiffness, Beam, SupportKind};
use crate::imported::{Imported, COMPONENTS};
use crate::plate::{element as bfs, Plate, PointSupportKind};
use std::collections::HashMap;
use std::sync::Arc;

/// Most distinct plate element matrices [`Structure::for_each_element`] keeps at once
/// (two of 2 kB each).
const PLATE_CACHE: usize = 1024;

/// A structure of any kind.
#[derive(Clone, Debug)]
pub enum Structure {
    Beam(Beam),
    Plate(Plate),
    /// A model from another FE code (spec §17), shared: its matrices can be large.
    Imported(Arc<Imported>),
}

/// An attachment's action on the structure: its normal displacement w at a point as
/// Σ coeff·(node DOF), each term (node, DOF kind, coeff). One term (w of a node, 1) at a
/// node; the element's shape functions inside one.
pub type Attachment = Vec<(usize, usize, f64)>;

/// The node an attachment stands on, if it is one DOF of one node (not shape functions).
pub fn single_node(attachment: &[(usize, usize, f64)]) -> Option<usize> {
    single_dof(attachment).map(|(node, _)| node)
}

/// The node and DOF kind an attachment is, if it is one DOF of one node taken positively
/// (w of a beam or plate node; a component of an imported model's node).
pub fn single_dof(attachment: &[(usize, usize, f64)]) -> Option<(usize, usize)> {
    match attachment {
        [(node, kind, c)] if *c == 1.0 => Some((*node, *kind)),
        _ => None,
    }
}

/// One element as the assembler sees it: its nodes (each carrying the structure's DOF kinds
/// in order) and its stiffness and mass over those DOFs, node by node.
pub struct ElementView<'a> {
    pub nodes: &'a [usize],
    pub stiffness: &'a dyn Fn(usize, usize) -> f64,
    pub mass: &'a dyn Fn(usize, usize) -> f64,
}

impl Structure {
    /// "beam", "plate" or "imported", for messages and the case file's table name.
    pub fn kind(&self) -> &'static str {
        match self {
            Structure::Beam(_) => "beam",
            Structure::Plate(_) => "plate",
            Structure::Imported(_) => "imported",
        }
    }

    /// "beam", "plate" or "imported model": the structure named in a sentence.
    pub fn noun(&self) -> &'static str {
        match self {
            Structure::Imported(_) => "imported model",
            other => other.kind(),
        }
    }

    pub fn beam(&self) -> Option<&Beam> {
        match self {
            Structure::Beam(b) => Some(b),
            _ => None,
        }
    }

    pub fn plate(&self) -> Option<&Plate> {
        match self {
            Structure::Plate(p) => Some(p),
            _ => None,
        }
    }

    pub fn n_nodes(&self) -> usize {
        match self {
            Structure::Beam(b) => b.mesh.n_nodes(),
            Structure::Plate(p) => p.grid.n_nodes(),
            Structure::Imported(m) => m.nodes.len(),
        }
    }

    /// The DOF kinds every node carries, in order (on a beam and a plate the first is w, the
    /// normal displacement; an imported model's nodes carry the components its map names).
    pub fn dof_names(&self) -> &'static [&'static str] {
        match self {
            Structure::Beam(_) => &["w", "theta"],
            Structure::Plate(_) => &bfs::DOF_NAMES,
            Structure::Imported(_) => &COMPONENTS,
        }
    }

    pub fn imported(&self) -> Option<&Imported> {
        match self {
            Structure::Imported(m) => Some(m),
            _ => None,
        }
    }

    /// Which of a node's DOFs its supports fix.
    pub fn fixed(&self, node: usize) -> std::borrow::Cow<'_, [bool]> {
        match self {
            Structure::Beam(b) => {
                let (w, t) = b.fixed(node);
                vec![w, t].into()
            }
            Structure::Plate(p) => p.fixed(node).to_vec().into(),
            Structure::Imported(m) => m.fixed(node).into(),
        }
    }

    /// The order nodes are numbered in (the DOF numbering strategy): a beam along its axis;
    /// a plate by reverse Cuthill–McKee.
    pub fn node_order(&self) -> Vec<usize> {
        match self {
            Structure::Beam(b) => (0..b.mesh.n_nodes()).collect(),
            Structure::Plate(p) => {
                let g = &p.grid;
                let elements: Vec<[usize; bfs::NODES]> =
                    (0..g.ny()).flat_map(|j| (0..g.nx()).map(move |i| g.element_nodes(i, j))).collect();
                ordering::reverse_cuthill_mckee(&ordering::adjacency(g.n_nodes(), elements.iter().map(|e| &e[..])))
            }
            Structure::Imported(m) => m.node_order.clone(),
        }
    }

    /// Visits every element, in the structure's own order (an imported model has none: its
    /// matrices come assembled, see [`Structure::imported`]).
    pub fn for_each_element(&self, mut visit: impl FnMut(ElementView)) {
        match self {
            Structure::Beam(b) => {
                for e in &b.mesh.elements {
                    let ke = element_stiffness(e.ei, e.length);
                    let me = element_mass(e.rho_a, e.length, b.mass_kind);
                    visit(ElementView { nodes: &e.nodes, stiffness: &|r, c| ke[(r, c)], mass: &|r, c| me[(r, c)] });
                }
            }
            Structure::Plate(p) => {
                let g = &p.grid;
                // Grid segments repeat element sizes and regions their sheet: compute each
                // (size, sheet) once, up to PLATE_CACHE of them (a graded grid's sizes are
                // all different: those beyond are computed where they are visited).
                let mut cache: HashMap<(u64, u64, u32), (bfs::ElementMatrix, bfs::ElementMatrix)> = HashMap::new();
                for j in 0..g.ny() {
                    for i in 0..g.nx() {
                        let key = (g.dx[i].to_bits(), g.dy[j].to_bits(), p.sheet_index(i, j));
                        if cache.len() < PLATE_CACHE && !cache.contains_key(&key) {
                            cache.insert(key, p.element_matrices(i, j));
                        }
                        let fresh;
                        let (ke, me) = match cache.get(&key) {
                            Some(m) => m,
                            None => {
                                fresh = p.element_matrices(i, j);
                                &fresh
                            }
                        };
                        let nodes = g.element_nodes(i, j);
                        visit(ElementView { nodes: &nodes, stiffness: &|r, c| ke[r][c], mass: &|r, c| me[r][c] });
                    }
                }
            }
            Structure::Imported(_) => {}
        }
    }

    /// Rigid point masses and inertias: (node, DOF kind, value) on M.
    pub fn point_inertia(&self) -> Vec<(usize, usize, f64)> {
        match self {
            Structure::Beam(b) => {
                b.point_masses.iter().flat_map(|p| [(p.node, 0, p.mass), (p.node, 1, p.rotary_inertia)]).collect()
            }
            Structure::Plate(p) => p.point_masses.iter().map(|m| (m.node, 0, m.mass)).collect(),
            Structure::Imported(_) => Vec::new(),
        }
    }

    /// Elastic supports: (node, DOF kind, stiffness) on K, damped with the structure.
    pub fn support_springs(&self) -> Vec<(usize, usize, f64)> {
        match self {
            Structure::Beam(b) => b
                .supports
                .iter()
                .flat_map(|s| match s.kind {
                    SupportKind::Spring { k_w, k_theta } => vec![(s.node, 0, k_w), (s.node, 1, k_theta)],
                    _ => vec![],
                })
                .collect(),
            Structure::Plate(p) => p
                .supports
                .iter()
                .filter_map(|s| match s.kind {
                    PointSupportKind::Spring { k_w } => Some((s.node, 0, k_w)),
                    _ => None,
                })
                .collect(),
            Structure::Imported(_) => Vec::new(),
        }
    }

    /// Grounded spring–dampers on w: (node, stiffness N/m, damping N·s/m), outside the
    /// structure's own (Rayleigh) damping.
    pub fn grounded_springs(&self) -> Vec<(usize, f64, f64)> {
        let springs = match self {
            Structure::Beam(b) => &b.springs,
            Structure::Plate(p) => &p.springs,
            Structure::Imported(_) => return Vec::new(),
        };
        springs.iter().map(|s| (s.node, s.stiffness, s.damping)).collect()
    }

    /// Where a node is.
    pub fn node_location(&self, node: usize) -> Location {
        match self {
            Structure::Beam(b) => Location::Beam { x: b.mesh.x[node] },
            Structure::Plate(p) => {
                let (x, y) = p.grid.position(node);
                Location::Plate { x, y }
            }
            Structure::Imported(m) => {
                let n = &m.nodes[node];
                Location::Node { node: n.id, component: 2, sign: 1, xyz: n.xyz }
            }
        }
    }

    /// How a point attaches (see [`Attachment`]): at the node there, or — on a plate, where
    /// the point lies inside an element — through that element's shape functions, which is
    /// exact for the finite-element model. A beam point must be a node. Errors (a reason,
    /// for the caller to name the field) if the point is off the structure, of the other
    /// kind, or between the beam's nodes.
    pub fn attach(&self, at: &Location) -> std::result::Result<Attachment, String> {
        match (self, *at) {
            (Structure::Beam(b), Location::Beam { x }) => {
                b.mesh.node_at(x).map(|n| vec![(n, 0, 1.0)]).ok_or_else(|| format!("x = {x} m is not on a mesh node"))
            }
            (Structure::Plate(p), Location::Plate { x, y }) => {
                if let Some(n) = p.grid.node_at(x, y) {
                    return Ok(vec![(n, 0, 1.0)]);
                }
                let s = p.grid.locate(x, y).ok_or_else(|| format!("{at} is outside the plate"))?;
                let (i, j) = s.element;
                let n = bfs::shape(p.grid.dx[i], p.grid.dy[j], s.xi, s.eta)[0];
                let nodes = p.grid.element_nodes(i, j);
                Ok((0..bfs::DOFS)
                    .map(|c| (nodes[c / bfs::NODE_DOFS], c % bfs::NODE_DOFS, n[c]))
                    .filter(|t| t.2 != 0.0)
                    .collect())
            }
            (Structure::Imported(m), Location::Node { node, component, sign, .. }) => {
                let i = m.node_index(node).ok_or_else(|| format!("node {node} is not in the model's DOF map"))?;
                let c = component as usize;
                match m.row(i, c) {
                    Some(r) if !m.fixed[r] => Ok(vec![(i, c, f64::from(sign))]),
                    Some(_) => Err(format!("{at}: that row is fixed")),
                    None => Err(format!("{at}: the model has no {} DOF at node {node}", COMPONENTS[c])),
                }
            }
            (Structure::Imported(m), Location::Near { xyz, component, tolerance, .. }) => {
                let i = m.node_near(xyz, component as usize, tolerance)?;
                self.attach(&self.resolve(*at)).map_err(|why| format!("{at} is node {}: {why}", m.nodes[i].id))
            }
            (s, _) => Err(format!("{at} is not a point on a {}", s.kind())),
        }
    }

    /// The point with what the structure knows of it filled in: an imported model's node
    /// gets its position, a point written by position becomes its node. Other points, and
    /// nodes the model lacks (which [`Structure::attach`] refuses), come back as they are.
    pub fn resolve(&self, at: Location) -> Location {
        match (self, at) {
            (Structure::Imported(m), Location::Node { node, component, sign, .. }) => match m.node_index(node) {
                Some(i) => Location::Node { node, component, sign, xyz: m.nodes[i].xyz },
                None => at,
            },
            (Structure::Imported(m), Location::Near { xyz, component, sign, tolerance }) => {
                match m.node_near(xyz, component as usize, tolerance) {
                    Ok(i) => Location::Node { node: m.nodes[i].id, component, sign, xyz: m.nodes[i].xyz },
                    Err(_) => at,
                }
            }
            _ => at,
        }
    }

    /// The node at a point, if the point is on the structure and is a node.
    pub fn node_at(&self, at: &Location) -> Option<usize> {
        self.attach(at).ok().as_deref().and_then(single_node)
    }

    /// Which case fields hold the structure, for messages about an unheld motion.
    pub fn support_fields(&self) -> &'static str {
        match self {
            Structure::Beam(_) => "beam.support and beam.spring",
            Structure::Plate(_) => "plate.edges, plate.support and plate.spring",
            Structure::Imported(_) => "imported.fixed (or the model's own boundary conditions)",
        }
    }

    /// Total mass of the structure itself (kg), without point masses.
    pub fn mass(&self) -> f64 {
        match self {
            Structure::Beam(b) => b.mass(),
            Structure::Plate(p) => p.mass(),
            Structure::Imported(m) => m.mass(),
        }
    }
}

impl From<Beam> for Structure {
    fn from(b: Beam) -> Self {
        Structure::Beam(b)
    }
}

impl From<&Beam> for Structure {
    fn from(b: &Beam) -> Self {
        Structure::Beam(b.clone())
    }
}

impl From<Plate> for Structure {
    fn from(p: Plate) -> Self {
        Structure::Plate(p)
    }
}
