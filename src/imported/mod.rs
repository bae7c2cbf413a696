//! A structure imported from another finite-element code (spec §17): its mass, stiffness
//! and optionally damping matrices as Matrix Market files, and a DOF map naming each row's
//! node, position and component. beamflow's own matrix export writes the same format.
//!
//! The model is checked when loaded, each failure naming the file and the row or entry:
//! sizes, finite entries, symmetry ([`matrix_market`]), the map ([`dof_map`]), and the
//! definiteness of M and K from the inertia of their factorisations ([`check`]).

pub mod check;
pub mod dof_map;
pub mod matrix_market;

pub use dof_map::{Node, COMPONENTS};

use crate::error::{Error, Result};
use crate::linalg::Csr;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// An imported linear model: matrices over its rows, and which node and component each row
/// is. Rows listed as fixed are held at zero.
#[derive(Clone, Debug)]
pub struct Imported {
    pub nodes: Vec<Node>,
    /// For each matrix row, its node (index into `nodes`) and component (index into
    /// [`COMPONENTS`]).
    pub rows: Vec<(usize, usize)>,
    /// Mass (kg, kg·m² on rotations), stiffness and the given damping, over the rows.
    pub m: Csr,
    pub k: Csr,
    pub c: Option<Csr>,
    /// Rows held at zero (boundary conditions not yet applied in the files).
    pub fixed: Vec<bool>,
    by_id: HashMap<i64, usize>,
    /// Row of each node's components, node-major (`node · COMPONENTS.len() + component`):
    /// a table, not a map, since numbering a case's DOFs asks for every node's.
    row_of: Vec<Option<usize>>,
    /// Which components of each node are held, in the same layout.
    held: Vec<bool>,
    /// What the model's check found (rigid-body modes, massless rows).
    pub report: check::Report,
    /// The nodes in reverse Cuthill–McKee order of their coupling: the order assembly
    /// numbers them in ([`crate::structure::Structure::node_order`]), found once here.
    pub node_order: Vec<usize>,
    /// How far back a skyline row reaches on average in that numbering: what a profile
    /// factor of the model costs.
    pub mean_band: usize,
}

/// What fraction of the local node spacing a point written by position may lie from its
/// node when the case gives no `tolerance` ([`Imported::node_near`]).
pub const NEAR_FRACTION: f64 = 0.01;

/// The distance between two points (m).
pub fn distance(p: &[f64; 3], q: &[f64; 3]) -> f64 {
    p.iter().zip(q).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt()
}

/// Where an imported model's files are, resolved against the case's folder, and which rows
/// its boundary conditions hold.
#[derive(Clone, Debug)]
pub struct Files {
    pub mass: PathBuf,
    pub stiffness: PathBuf,
    pub damping: Option<PathBuf>,
    pub dofs: PathBuf,
    /// 1-based rows held at zero.
    pub fixed: Vec<usize>,
}

/// The model `files` name, loaded once per process and shared: a sweep builds its model
/// for every case, and an imported model can be large. A cached model is used while its
/// files keep their length and modification time.
pub fn shared(files: &Files, case_file: &str) -> Result<std::sync::Arc<Imported>> {
    use std::sync::{Arc, Mutex};
    type Stamp = Vec<(PathBuf, u64, Option<std::time::SystemTime>)>;
    static LAST: Mutex<Option<(Stamp, Vec<usize>, Arc<Imported>)>> = Mutex::new(None);
    let paths = [Some(&files.mass), Some(&files.stiffness), files.damping.as_ref(), Some(&files.dofs)];
    let stamp: Stamp = paths
        .into_iter()
        .flatten()
        .map(|p| {
            let meta = std::fs::metadata(p).ok();
            (p.clone(), meta.as_ref().map_or(0, |m| m.len()), meta.and_then(|m| m.modified().ok()))
        })
        .collect();
    let mut last = LAST.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((s, fixed, model)) = last.as_ref() {
        if *s == stamp && *fixed == files.fixed {
            return Ok(model.clone());
        }
    }
    let max_entries = crate::analysis::budget::machine_memory() / 2 / matrix_market::BYTES_PER_ENTRY;
    let model = Arc::new(Imported::load(files, max_entries, case_file)?);
    *last = Some((stamp, files.fixed.clone(), model.clone()));
    Ok(model)
}

impl Imported {
    /// Reads and checks a model; `max_entries` bounds each matrix file (from the memory
    /// budget); `case_file` names the case in the message about a fixed row.
    pub fn load(files: &Files, max_entries: u64, case_file: &str) -> Result<Imported> {
        let k = matrix_market::read(&files.stiffness, max_entries)?.matrix;
        let n = k.dim();
        let same_size = |p: &Path, a: &Csr| -> Result<()> {
            if a.dim() == n {
                Ok(())
            } else {
                Err(Error::input(
                    p.display().to_string(),
                    "size",
                    format!("{} rows, but the stiffness {} has {n}", a.dim(), files.stiffness.display()),
                ))
            }
        };
        let m = matrix_market::read(&files.mass, max_entries)?.matrix;
        same_size(&files.mass, &m)?;
        let c = match &files.damping {
            Some(p) => {
                let c = matrix_market::read(p, max_entries)?.matrix;
                same_size(p, &c)?;
                Some(c)
            }
            None => None,
        };
        let table = dof_map::read(&files.dofs, n)?;
        let mut fixed = vec![false; n];
        for (i, &r) in files.fixed.iter().enumerate() {
            if !(1..=n).contains(&r) {
                return Err(Error::input(
                    case_file,
                    format!("imported.fixed[{i}]"),
                    format!("row {r} is not in 1..={n}"),
                ));
            }
            fixed[r - 1] = true;
        }
        let mut row_of = vec![None; table.nodes.len() * COMPONENTS.len()];
        for (r, &(node, c)) in table.rows.iter().enumerate() {
            row_of[node * COMPONENTS.len() + c] = Some(r);
        }
        let mut model = Imported {
            nodes: table.nodes,
            rows: table.rows,
            m,
            k,
            c,
            fixed,
            by_id: table.by_id,
            held: Vec::new(),
            row_of,
            report: Default::default(),
            node_order: Vec::new(),
            mean_band: 0,
        };
        model.held = (0..model.nodes.len() * COMPONENTS.len())
            .map(|i| model.row(i / COMPONENTS.len(), i % COMPONENTS.len()).is_none_or(|r| model.fixed[r]))
            .collect();
        model.report = check::check(&model, files)?;
        model.node_order = crate::structure::ordering::reverse_cuthill_mckee(&model.node_graph());
        model.mean_band = model.profile_band();
        Ok(model)
    }

    /// Number of matrix rows.
    pub fn n(&self) -> usize {
        self.rows.len()
    }

    /// The index of node `id`, if the model has it.
    pub fn node_index(&self, id: i64) -> Option<usize> {
        self.by_id.get(&id).copied()
    }

    /// The row of a node's component, if the model has that DOF.
    pub fn row(&self, node: usize, component: usize) -> Option<usize> {
        match component < COMPONENTS.len() {
            true => self.row_of.get(node * COMPONENTS.len() + component).copied().flatten(),
            false => None,
        }
    }

    /// Which components of a node are held (absent from the model, or a fixed row).
    pub fn fixed(&self, node: usize) -> &[bool] {
        &self.held[node * COMPONENTS.len()..(node + 1) * COMPONENTS.len()]
    }

    /// The node a point written by position stands on (spec §15): the node nearest `xyz`
    /// (m) among those with a `component` row, if it lies within `tolerance` (m) and no
    /// other such node is as near. Without a tolerance the default is [`NEAR_FRACTION`] of
    /// the distance from that node to its nearest neighbour: a point means a node only if
    /// it is written at that node up to rounding, never if it lies out along an element.
    /// The reason, naming the nearest node and its distance, if there is no such node.
    pub fn node_near(
        &self,
        xyz: [f64; 3],
        component: usize,
        tolerance: Option<f64>,
    ) -> std::result::Result<usize, String> {
        let name = COMPONENTS[component];
        crate::structure::location::finite_point(&xyz)?;
        let mut order: Vec<(f64, usize)> = (0..self.nodes.len())
            .filter(|&i| self.row(i, component).is_some())
            .map(|i| (distance(&self.nodes[i].xyz, &xyz), i))
            .collect();
        let at = format!("({}, {}, {}) m", xyz[0], xyz[1], xyz[2]);
        // Distances to the nanometre: what a user compares with the coordinates written.
        let m = |v: f64| (v * 1e9).round() / 1e9;
        if order.len() > 2 {
            order.select_nth_unstable_by(1, |a, b| a.0.total_cmp(&b.0));
        }
        order.truncate(2);
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        let Some(&(d, i)) = order.first() else { return Err(format!("the model has no {name} DOF at any node")) };
        let id = self.nodes[i].id;
        let (tolerance, why) = match tolerance {
            Some(t) => (t, "`tolerance`".to_string()),
            None => {
                let spacing = self.spacing(i);
                (
                    NEAR_FRACTION * spacing,
                    format!(
                        "the default, {NEAR_FRACTION} of the {} m from node {id} to its nearest neighbour",
                        m(spacing)
                    ),
                )
            }
        };
        if !(d <= tolerance) {
            return Err(format!(
                "no node with a {name} DOF lies within {} m ({why}) of {at}: the nearest is node {id}, {} m away; \
                 write its position, name it with `node = {id}`, or give a larger `tolerance` (m)",
                m(tolerance),
                m(d)
            ));
        }
        if let Some(&(d2, j)) = order.get(1) {
            if d2 - d <= 1e-9 * d2.max(tolerance) {
                return Err(format!(
                    "nodes {id} and {} are equally near {at} ({} m): name one with `node`",
                    self.nodes[j].id,
                    m(d)
                ));
            }
        }
        Ok(i)
    }

    /// The distance (m) from node `i` to the nearest node at another position (0 if every
    /// node is there).
    fn spacing(&self, i: usize) -> f64 {
        let p = self.nodes[i].xyz;
        let d = self.nodes.iter().map(|n| distance(&n.xyz, &p)).filter(|&d| d > 0.0).fold(f64::INFINITY, f64::min);
        if d.is_finite() {
            d
        } else {
            0.0
        }
    }

    /// Total mass (kg): the translational mass along the first translation the model has,
    /// uᵀ·M·u with u = 1 on every row of that component (the rigid translation).
    pub fn mass(&self) -> f64 {
        let Some(comp) = (0..3).chain([6]).find(|&c| self.rows.iter().any(|r| r.1 == c)) else { return 0.0 };
        let u: Vec<f64> = self.rows.iter().map(|r| if r.1 == comp { 1.0 } else { 0.0 }).collect();
        self.m.bilinear(&u, &u)
    }

    /// The mean reach of a skyline row with the nodes in `node_order`, a node's rows
    /// together: what a profile factor of the model costs.
    fn profile_band(&self) -> usize {
        let mut first_row = vec![0usize; self.nodes.len()];
        for (rank, &node) in self.node_order.iter().enumerate() {
            first_row[node] = rank * COMPONENTS.len();
        }
        let pos: Vec<usize> = self.rows.iter().map(|&(node, c)| first_row[node] + c).collect();
        let mut first = pos.clone();
        for (i, j, _) in self.k.triplets().chain(self.m.triplets()) {
            first[i] = first[i].min(pos[j]);
        }
        let total: usize = pos.iter().zip(&first).map(|(p, f)| p - f).sum();
        total / self.n().max(1) + 1
    }

    /// Node adjacency through K's and M's pattern (for the fill-reducing node order).
    fn node_graph(&self) -> Vec<Vec<usize>> {
        let mut adj: Vec<Vec<usize>> = vec![Vec::new(); self.nodes.len()];
        for a in [&self.k, &self.m] {
            for (i, j, _) in a.triplets() {
                let (ni, nj) = (self.rows[i].0, self.rows[j].0);
                if ni != nj {
                    adj[ni].push(nj);
                }
            }
        }
        for l in &mut adj {
            l.sort_unstable();
            l.dedup();
        }
        adj
    }
}
