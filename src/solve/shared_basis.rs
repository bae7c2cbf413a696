//! A reduction basis of a bare structure, computed once and shared by every placement of a
//! study (a sweep or an optimisation that moves actuators on one structure).
//!
//! [`super::modal_basis::reduce`] builds the basis of one assembled system: the bare modes
//! below the cut-off, then the static correction at that system's attachment DOFs. Across
//! the cases of a placement study the bare structure does not change, only where the
//! actuators stand, so [`SharedBasis`] keeps what depends on the structure alone — the
//! retained modes Φ, the structure's M and C and their projections ΦᵀMΦ and ΦᵀCΦ, and the
//! factor of its K — and per placement adds what depends on it:
//!
//! * the static shapes x_j = K⁻¹·b_j of the case's attachment patterns b_j (a foot's w: one
//!   DOF at a node, the element's shape functions between nodes; a point load's likewise),
//!   combinations of the unit loads' shapes K⁻¹·e_d of the pattern's DOFs, each with
//!   K⁻¹·M·K⁻¹·e_d and K⁻¹·C·K⁻¹·e_d, kept per DOF ([`ShapeCache`]: a study that knows its
//!   candidates solves them up front,
//!   [`SharedBasis::prefetch`], a block of right-hand sides per pass over the factor;
//!   others as cases meet them), turned into residual vectors ψ_j = x_j − Φ·α_j as a single system's
//!   reduction does (`modal_basis::residual_vectors`: M-orthogonal to Φ, diagonalising the
//!   residual flexibility);
//! * the structure blocks that involve them (Φᵀ·M·ψ, ψᵀ·M·ψ, and C's);
//! * the actuators' bodies, springs, dampers and foot masses projected through their links:
//!   each link's stretch and foot on the reduced coordinates (rows of the basis at their
//!   DOFs), rank-one terms of the links' weights.
//!
//! None of these forms ψ_j. What the modes carry of a static shape, Φᵀ·M·x_j, is
//! (K⁻¹·M·Φ)ᵀ·b_j, read off at the pattern's few DOFs from K⁻¹·M·Φ, solved once for the
//! study (and K⁻¹·C·Φ likewise for C); the Gram matrices ψᵀ·M·ψ and ψᵀ·C·ψ follow from
//! x_iᵀ·M·x_j = b_iᵀ·K⁻¹·M·K⁻¹·b_j, read off the kept K⁻¹·M·K⁻¹·e_d at the patterns' DOFs,
//! and those coefficients; and T keeps ψ factored as X·Y − Φ·B ([`Factored`], X the
//! kept unit shapes themselves). A placement whose shapes are kept so costs
//! O(pattern size × modes + pattern size²), nothing over the structure's DOFs: not a
//! sparse solve per pattern, nor O(modes × structure DOFs) per residual vector.
//!
//! The reduced system is the one `modal_basis::reduce` builds from the case's assembled
//! system, except that its static correction is spanned by the attachment patterns b_j
//! rather than by every DOF they touch: the forces an actuator or a load puts on the
//! structure act only along those patterns, so K⁻¹·b_j is the whole static response, and a
//! point between nodes costs one vector, not sixteen. Nothing of the size of the
//! structure's matrices is assembled per placement.

use super::modal_basis::{
    at, links_on, mul, pencil_basis, reduced_system_with, residual_flexibility, sparse_of_dense, Reduction,
    ReductionOptions,
};
use crate::analysis::budget::machine_memory;
use crate::assembly::projection::Factored;
use crate::assembly::{DofMap, LinkDofs, Projection, System};
use crate::error::{Error, Result};
use crate::linalg::sparse_ldlt::OwnedLdlt;
use crate::linalg::{dot, dots, symmetrise, Csr};
use crate::solve::eigen::{ratio_of, Modes};
use faer::Mat;
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// An attachment pattern b: structure DOFs and their coefficients, by DOF.
pub type Pattern = Vec<(usize, f64)>;

/// Right-hand sides solved together in one pass over the factor of K: enough to turn the
/// memory-bound solve of one vector into products of the factor's blocks with 32 columns,
/// few enough that a block (8 MB at 32,000 DOFs) stays small.
const BLOCK: usize = 32;

/// What the static shapes a study keeps may take: a quarter of the default memory budget
/// (half of the machine's available memory). 24 bytes per structure DOF per kept shape, so
/// 1 GB holds ≈ 1,400 shapes of a 32,000-DOF model.
fn default_shape_cache() -> u64 {
    machine_memory() / 4
}

/// The bare structure's part of a reduction, shared by the placements of a study.
#[derive(Debug)]
pub struct SharedBasis {
    /// The bare structure's DOF numbering (no actuators): a placement's system must number
    /// the structure the same way.
    dofs: DofMap,
    /// Retained modes (mass-normalised), row-major `structure DOFs × modes`, and their ω
    /// (rad/s).
    phi: Arc<Vec<f64>>,
    omega: Vec<f64>,
    first_discarded: Option<f64>,
    /// The structure's M and C, and Φᵀ·M·Φ, Φᵀ·C·Φ (row-major nm × nm, symmetrised).
    m: Csr,
    c: Csr,
    phi_m: Vec<f64>,
    phi_c: Vec<f64>,
    /// What the static correction needs (None without it).
    statics: Option<Statics>,
    modal_damping: Option<Vec<f64>>,
}

/// The factor of the structure's K, and K⁻¹·M·Φ and K⁻¹·C·Φ (row-major `structure DOFs ×
/// modes`): b_jᵀ·K⁻¹·M·φ_r is what mode r carries of the static shape K⁻¹·b_j.
#[derive(Debug)]
struct Statics {
    k: OwnedLdlt,
    k_inv_m_phi: Vec<f64>,
    k_inv_c_phi: Vec<f64>,
    shapes: ShapeCache,
}

/// A static shape x = K⁻¹·L of a load L (a unit load on one DOF, or a pattern), with
/// K⁻¹·M·x and K⁻¹·C·x: the Gram entry x'ᵀ·M·x of two shapes is then L'ᵀ·(K⁻¹·M·x), read
/// off at the few DOFs of L', not summed over the structure.
#[derive(Debug)]
struct StaticShape {
    x: Arc<Vec<f64>>,
    kmx: Vec<f64>,
    kcx: Vec<f64>,
}

/// A placement's static shapes as combinations of kept ones: b_a = Σ_k w_ak·L_k, so
/// x_a = Σ_k w_ak·x_k with x_k = K⁻¹·L_k.
struct Combined {
    loads: Vec<Pattern>,
    shapes: Vec<Arc<StaticShape>>,
    /// Per pattern a, its (k, w_ak).
    weights: Vec<Vec<(usize, f64)>>,
}

impl Combined {
    /// G_kl = L_kᵀ·v_l (row-major n × n) for the three fields v of each kept shape: x
    /// itself (the flexibility L_kᵀ·K⁻¹·L_l), K⁻¹·M·x (x_kᵀ·M·x_l) and K⁻¹·C·x (x_kᵀ·C·x_l),
    /// as read (symmetric up to K⁻¹'s rounding): the flexibility's entries are the shapes'
    /// values at the loads, which rows of T take as they are. The reads are scattered over
    /// the kept shapes and miss the caches, so the three fields are read side by side.
    fn grams(&self) -> [Vec<f64>; 3] {
        let n = self.loads.len();
        let mut g = [vec![0.0; n * n], vec![0.0; n * n], vec![0.0; n * n]];
        for (l, shape) in self.shapes.iter().enumerate() {
            let fields = [&shape.x[..], &shape.kmx[..], &shape.kcx[..]];
            for (k, load) in self.loads.iter().enumerate() {
                for (g, v) in g.iter_mut().zip(fields) {
                    g[k * n + l] = at(load, v);
                }
            }
        }
        g
    }

    /// The patterns' Gram matrix Wᵀ·G·W (row-major, symmetrised) of a Gram matrix G of
    /// the kept shapes ([`Combined::grams`], symmetrised first).
    fn on_patterns(&self, g: &[f64]) -> Vec<f64> {
        let (n, p) = (self.loads.len(), self.weights.len());
        let mut g = g.to_vec();
        symmetrise(&mut g, n);
        let mut gw = vec![0.0; n * p];
        for (b, wb) in self.weights.iter().enumerate() {
            for k in 0..n {
                gw[k * p + b] = wb.iter().map(|&(l, w)| g[k * n + l] * w).sum();
            }
        }
        let mut r = vec![0.0; p * p];
        for (a, wa) in self.weights.iter().enumerate() {
            for b in 0..p {
                r[a * p + b] = wa.iter().map(|&(k, w)| w * gw[k * p + b]).sum();
            }
        }
        symmetrise(&mut r, p);
        r
    }

    /// Each kept shape's value at the DOF of each unit load, from the flexibility `g_x` as
    /// read ([`Combined::grams`]), for the shapes `used` (by DOF; none where the loads are
    /// the patterns themselves).
    fn values_at_loads(&self, g_x: &[f64], used: &[usize]) -> HashMap<usize, Vec<f64>> {
        let n = self.loads.len();
        let unit = |load: &Pattern| match load[..] {
            [(d, 1.0)] => Some(d),
            _ => None,
        };
        let dofs: Option<Vec<usize>> = self.loads.iter().map(unit).collect();
        let rows = dofs.into_iter().flatten().enumerate();
        rows.map(|(k, d)| (d, used.iter().map(|&l| g_x[k * n + l]).collect())).collect()
    }
}

/// The static shapes of unit loads on the structure DOFs a study has met, K⁻¹·e_d by DOF d,
/// at most `room` of them. A pattern's shape is their weighted sum: a foot between a
/// plate's nodes is the element's 16 DOFs with its shape functions' values, so positions an
/// optimiser moves continuously share the shapes of the DOFs around them. Beyond `room` a
/// case solves its patterns' own shapes (and drops them).
#[derive(Debug)]
struct ShapeCache {
    room: usize,
    shapes: Mutex<HashMap<usize, Arc<StaticShape>>>,
}

impl ShapeCache {
    /// A cache of at most `bytes` of shapes over `ns` DOFs.
    fn new(bytes: u64, ns: usize) -> Self {
        let per_shape = (3 * ns * std::mem::size_of::<f64>()).max(1) as u64;
        ShapeCache { room: usize::try_from(bytes / per_shape).unwrap_or(usize::MAX), shapes: Mutex::default() }
    }

    fn get(&self, dof: usize) -> Option<Arc<StaticShape>> {
        self.shapes.lock().ok()?.get(&dof).cloned()
    }

    /// Keeps `shape` of the unit load on `dof` while there is room.
    fn keep(&self, dof: usize, shape: &Arc<StaticShape>) {
        if let Ok(mut map) = self.shapes.lock() {
            if map.len() < self.room {
                map.entry(dof).or_insert_with(|| Arc::clone(shape));
            }
        }
    }

    /// How many more shapes fit.
    fn free(&self) -> usize {
        self.shapes.lock().map_or(0, |m| self.room.saturating_sub(m.len()))
    }

    fn len(&self) -> usize {
        self.shapes.lock().map_or(0, |m| m.len())
    }
}

/// A placement's residual vectors ψ̃_c = Σ_a Y_ac·(x_a − Φ·α_a), with what the reduced
/// structure matrices need of them.
struct PlacementResidual {
    /// The kept shapes x_k the static shapes x_a are combined from.
    shapes: Vec<Arc<Vec<f64>>>,
    /// Their values at the attachment patterns' DOFs ([`Factored::shapes_at`]).
    shapes_at: HashMap<usize, Vec<f64>>,
    /// W·Y (kept shapes × columns), B = [α_a]·Y (modes × columns), row-major.
    y: Vec<f64>,
    b: Vec<f64>,
    omega: Vec<f64>,
    dropped: usize,
    /// Φᵀ·A·ψ̃ (modes × columns) and ψ̃ᵀ·A·ψ̃ (columns × columns) for A = M and A = C.
    m_blocks: (Vec<f64>, Vec<f64>),
    c_blocks: (Vec<f64>, Vec<f64>),
}

impl PlacementResidual {
    fn none() -> Self {
        PlacementResidual {
            shapes: Vec::new(),
            shapes_at: HashMap::new(),
            y: Vec::new(),
            b: Vec::new(),
            omega: Vec::new(),
            dropped: 0,
            m_blocks: (Vec::new(), Vec::new()),
            c_blocks: (Vec::new(), Vec::new()),
        }
    }
}

/// Row-major `rows × cols` of column vectors.
fn row_major(columns: &[Vec<f64>], rows: usize) -> Vec<f64> {
    let cols = columns.len();
    let mut r = vec![0.0; rows * cols];
    for (c, v) in columns.iter().enumerate() {
        v.iter().enumerate().for_each(|(i, &x)| r[i * cols + c] = x);
    }
    r
}

/// Vᵀ·A·V of column vectors V given A·V, symmetrised (row-major).
fn gram(v: &[impl AsRef<[f64]>], av: &[impl AsRef<[f64]>]) -> Vec<f64> {
    let n = v.len();
    let mut r = vec![0.0; n * n];
    for i in 0..n {
        // vᵢ·(A·vⱼ) and vⱼ·(A·vᵢ) for j ≤ i, the chains side by side.
        let to_av: Vec<&[f64]> = av[..=i].iter().map(AsRef::as_ref).collect();
        let to_v: Vec<&[f64]> = v[..=i].iter().map(AsRef::as_ref).collect();
        let (left, right) = (dots(v[i].as_ref(), &to_av), dots(av[i].as_ref(), &to_v));
        for j in 0..=i {
            let s = 0.5 * (left[j] + right[j]);
            r[i * n + j] = s;
            r[j * n + i] = s;
        }
    }
    r
}

impl SharedBasis {
    /// The basis of the bare structure's system `bare` (its structure alone, damped, no
    /// actuators) with its `modes` (ascending, over its DOFs) kept up to `opts.cutoff`.
    pub fn new(bare: &System, modes: &Modes, opts: &ReductionOptions) -> Result<Self> {
        let ns = bare.n();
        if !bare.dofs.bodies.iter().all(Vec::is_empty) || ns == 0 {
            return Err(Error::Numerical("a shared basis is built on the bare structure's free DOFs".into()));
        }
        let kept: Vec<usize> = (0..modes.count()).filter(|&r| modes.omega[r] <= opts.cutoff).collect();
        let phi: Vec<Vec<f64>> = kept.iter().map(|&r| modes.shape_global(r, ns)).collect();
        let times = |a: &Csr, vs: &[Vec<f64>]| -> Vec<Vec<f64>> { vs.iter().map(|v| mul(a, v)).collect() };
        let (m_phi, c_phi) = (times(&bare.m_beam, &phi), times(&bare.c_beam, &phi));
        let statics = match opts.static_correction {
            true => {
                let k = OwnedLdlt::of(&bare.k_beam)?;
                let solved = |vs: &[Vec<f64>]| -> Vec<Vec<f64>> {
                    vs.par_chunks(BLOCK)
                        .flat_map_iter(|block| {
                            let mut x: Vec<f64> = block.concat();
                            k.solve_columns_in_place(&mut x);
                            x.chunks_exact(ns).map(<[f64]>::to_vec).collect::<Vec<_>>()
                        })
                        .collect()
                };
                let (k_inv_m_phi, k_inv_c_phi) = (row_major(&solved(&m_phi), ns), row_major(&solved(&c_phi), ns));
                Some(Statics { k, k_inv_m_phi, k_inv_c_phi, shapes: ShapeCache::new(default_shape_cache(), ns) })
            }
            false => None,
        };
        Ok(SharedBasis {
            dofs: bare.dofs.clone(),
            omega: kept.iter().map(|&r| modes.omega[r]).collect(),
            first_discarded: modes.omega.get(kept.len()).copied(),
            phi_m: gram(&phi, &m_phi),
            phi_c: gram(&phi, &c_phi),
            phi: Arc::new(row_major(&phi, ns)),
            m: bare.m_beam.clone(),
            c: bare.c_beam.clone(),
            statics,
            modal_damping: opts.modal_damping.clone(),
        })
    }

    /// The bare structure's DOF numbering, which a placement's attachments take
    /// ([`System::assemble_attachments_on`]).
    pub fn structure_dofs(&self) -> &DofMap {
        &self.dofs
    }

    /// Retained modes.
    pub fn modes(&self) -> usize {
        self.omega.len()
    }

    /// Keeps at most `bytes` of static shapes from now on (0: every case solves its own).
    pub fn set_shape_cache(&mut self, bytes: u64) {
        let ns = self.dofs.n;
        if let Some(s) = &mut self.statics {
            s.shapes = ShapeCache::new(bytes, ns);
        }
    }

    /// Static shapes kept.
    pub fn shapes_kept(&self) -> usize {
        self.statics.as_ref().map_or(0, |s| s.shapes.len())
    }

    /// The patterns along which the actuators and loads of `attached` act on the structure.
    pub fn attachment_patterns(&self, attached: &System) -> Vec<Pattern> {
        attachment_patterns(attached, self.dofs.n)
    }

    /// Solves the unit loads' static shapes of the DOFs of `patterns` not yet kept,
    /// [`BLOCK`] right-hand sides per pass over the factor of K, as many as the cache has
    /// room for, and keeps them with their products with M and C. Returns how many it
    /// solved.
    pub fn prefetch(&self, patterns: &[Pattern]) -> usize {
        let Some(s) = &self.statics else { return 0 };
        let mut todo: Vec<usize> =
            dofs_of(patterns, self.dofs.n).into_iter().filter(|&d| s.shapes.get(d).is_none()).collect();
        todo.truncate(s.shapes.free());
        self.solve_units(s, &todo);
        todo.len()
    }

    /// Solves the unit loads' static shapes at `dofs`, [`BLOCK`] right-hand sides per pass
    /// over the factor of K (the blocks in parallel), keeps them, and returns them in the
    /// order of `dofs`.
    fn solve_units(&self, s: &Statics, dofs: &[usize]) -> Vec<Arc<StaticShape>> {
        let units: Vec<Pattern> = dofs.iter().map(|&d| vec![(d, 1.0)]).collect();
        let blocks: Vec<Vec<Arc<StaticShape>>> = units
            .par_chunks(BLOCK)
            .zip(dofs.par_chunks(BLOCK))
            .map(|(block, dofs)| {
                let block: Vec<&Pattern> = block.iter().collect();
                let shapes = self.solve_block(s, &block);
                dofs.iter().zip(&shapes).for_each(|(&d, shape)| s.shapes.keep(d, shape));
                shapes
            })
            .collect();
        blocks.into_iter().flatten().collect()
    }

    /// The static shapes of `block` (at most [`BLOCK`] patterns) in one pass over the
    /// factor of K, with their products with M and C one pass over each matrix.
    fn solve_block(&self, s: &Statics, block: &[&Pattern]) -> Vec<Arc<StaticShape>> {
        let ns = self.dofs.n;
        let mut x = vec![0.0; ns * block.len()];
        for (b, column) in block.iter().zip(x.chunks_exact_mut(ns)) {
            load(b, column);
        }
        s.k.solve_columns_in_place(&mut x);
        // M·x and C·x, then K⁻¹ of both in one more pass over the factor.
        let nb = block.len();
        let mut w = vec![0.0; 2 * x.len()];
        let (wm, wc) = w.split_at_mut(x.len());
        self.m.mul_columns(&x, wm);
        self.c.mul_columns(&x, wc);
        s.k.solve_columns_in_place(&mut w);
        let column = |v: &[f64], j: usize| v[j * ns..(j + 1) * ns].to_vec();
        (0..nb)
            .map(|j| Arc::new(StaticShape { x: Arc::new(column(&x, j)), kmx: column(&w, j), kcx: column(&w, nb + j) }))
            .collect()
    }

    /// The static shapes of `patterns`: combinations of the unit loads' shapes at their
    /// DOFs, those not yet kept solved now in blocks and kept; where the cache has no room
    /// for them, the patterns' own shapes solved in blocks.
    fn static_shapes(&self, s: &Statics, patterns: &[Pattern]) -> Combined {
        let dofs = dofs_of(patterns, self.dofs.n);
        let mut units: HashMap<usize, Arc<StaticShape>> =
            dofs.iter().filter_map(|&d| s.shapes.get(d).map(|x| (d, x))).collect();
        let missing: Vec<usize> = dofs.iter().copied().filter(|d| !units.contains_key(d)).collect();
        if missing.len() > s.shapes.free() {
            let own: Vec<&Pattern> = patterns.iter().collect();
            return Combined {
                loads: patterns.to_vec(),
                shapes: own.chunks(BLOCK).flat_map(|block| self.solve_block(s, block)).collect(),
                weights: (0..patterns.len()).map(|a| vec![(a, 1.0)]).collect(),
            };
        }
        units.extend(missing.iter().copied().zip(self.solve_units(s, &missing)));
        let index: HashMap<usize, usize> = dofs.iter().enumerate().map(|(k, &d)| (d, k)).collect();
        Combined {
            loads: dofs.iter().map(|&d| vec![(d, 1.0)]).collect(),
            shapes: dofs.iter().map(|d| Arc::clone(&units[d])).collect(),
            weights: patterns.iter().map(|b| b.iter().map(|&(d, c)| (index[&d], c)).collect()).collect(),
        }
    }

    /// The reduced system of a placement: `attached` holds the case's actuators and loads
    /// on the structure ([`System::assemble_attachments`]: the structure numbered as the
    /// bare one, the bodies after it, no structure matrices).
    pub fn reduce(&self, attached: &System) -> Result<Reduction> {
        if attached.dofs.nodes != self.dofs.nodes || attached.projection.is_some() {
            return Err(Error::Numerical(
                "the case's structure is not the one the study's shared reduction was built on".into(),
            ));
        }
        let bodies: Vec<usize> = attached.dofs.bodies.iter().flatten().copied().collect();
        let patterns = attachment_patterns(attached, self.dofs.n);
        let res = match &self.statics {
            Some(s) if !patterns.is_empty() => self.residual(s, &patterns)?,
            _ => PlacementResidual::none(),
        };
        let (nm, nq) = (self.modes(), res.omega.len());
        let nr = nm + nq + bodies.len();

        let m_beam = self.structure_block(&self.phi_m, &res.m_blocks, nq, nr);
        let mut c_beam = self.structure_block(&self.phi_c, &res.c_blocks, nq, nr);
        if let Some(ratios) = &self.modal_damping {
            // As in `modal_basis::reduce`: 2ζ_r·ω_r on the modal coordinates, the residual
            // vectors taking the next ratios at their pseudo-frequencies.
            for (r, &w) in self.omega.iter().chain(&res.omega).enumerate() {
                c_beam[r * nr + r] += 2.0 * ratio_of(ratios, r) * w;
            }
        }
        let k_diag: Vec<f64> = self.omega.iter().chain(&res.omega).map(|w| w * w).collect();
        let residual_omega = res.omega;
        let factored = Factored {
            phi: Arc::clone(&self.phi),
            modes: nm,
            shapes: res.shapes,
            shapes_at: res.shapes_at,
            y: res.y,
            b: res.b,
            bodies,
        };
        let basis = Projection::factored(attached.dofs.clone(), factored);
        let links = links_on(attached, &basis);
        let [mut m, mut c, mut k] = attachments_on_basis(attached, &links, nr, nm + nq);
        for (r, s) in [(&mut m, &m_beam), (&mut c, &c_beam)] {
            r.iter_mut().zip(s).for_each(|(x, y)| *x += y);
        }
        k_diag.iter().enumerate().for_each(|(r, w2)| k[r * nr + r] += w2);
        let mut dense = [k, m, c];
        let [k, m, c] = dense.each_mut().map(|r| sparse_of_dense(r, nr));
        let [m_beam, c_beam] = [m_beam, c_beam].map(|mut r| sparse_of_dense(&mut r, nr));
        let k_beam = diagonal(&k_diag);
        let mut system = reduced_system_with(attached, basis, [m, c, k, m_beam, c_beam, k_beam], nm + nq, links);
        system.dense = Some(Arc::new(dense));
        Ok(Reduction {
            system,
            mode_omega: self.omega.clone(),
            first_discarded_omega: self.first_discarded,
            residual_omega,
            dropped: res.dropped,
        })
    }

    /// Pattern b's value on each retained mode, or on each column of a row-major
    /// `structure DOFs × modes` array `rows` (bᵀ·Φ, bᵀ·K⁻¹·M·Φ, …).
    fn on_modes(&self, rows: &[f64], b: &[(usize, f64)]) -> Vec<f64> {
        let nm = self.modes();
        let mut r = vec![0.0; nm];
        for &(d, c) in b {
            r.iter_mut().zip(&rows[d * nm..(d + 1) * nm]).for_each(|(x, v)| *x += c * v);
        }
        r
    }

    /// The residual vectors of the attachment `patterns` (as `modal_basis::residual_vectors`
    /// builds them, without forming them): static shapes x_a, coefficients α_a with
    /// Φᵀ·M·(x_a − Φ·α_a) = 0, the pencil of (G, ψᵀ·M·ψ) diagonalised.
    fn residual(&self, s: &Statics, patterns: &[Pattern]) -> Result<PlacementResidual> {
        let (nm, p) = (self.modes(), patterns.len());
        let combined = self.static_shapes(s, patterns);
        let [g_x, g_m, g_c] = combined.grams();
        let on_phi: Vec<Vec<f64>> = patterns.iter().map(|b| self.on_modes(&self.phi, b)).collect();
        let (live, kg) = residual_flexibility(&combined.on_patterns(&g_x), &on_phi, &self.omega);
        let q = live.len();
        let mut dropped = p - q;
        // Φᵀ·M·x_a and Φᵀ·C·x_a from the shared K⁻¹·M·Φ and K⁻¹·C·Φ; α_a by two passes of
        // M-orthogonalisation (Φᵀ·M·Φ is I to round-off), as the explicit vectors get.
        let phi_m_x: Vec<Vec<f64>> = live.iter().map(|&a| self.on_modes(&s.k_inv_m_phi, &patterns[a])).collect();
        let phi_c_x: Vec<Vec<f64>> = live.iter().map(|&a| self.on_modes(&s.k_inv_c_phi, &patterns[a])).collect();
        let on_first = mat_vecs(&self.phi_m, &phi_m_x, nm);
        let alpha: Vec<Vec<f64>> = phi_m_x
            .iter()
            .zip(&on_first)
            .map(|(p, once)| p.iter().zip(sub(p, once)).map(|(x, d)| x + d).collect())
            .collect();
        // (Φᵀ·A·Φ)·α_a, which both the Gram matrices and the coupling blocks need.
        let (m_alpha, c_alpha) = (mat_vecs(&self.phi_m, &alpha, nm), mat_vecs(&self.phi_c, &alpha, nm));
        // ψ_aᵀ·A·ψ_b = x_aᵀ·A·x_b − α_aᵀ·(Φᵀ·A·x_b) − (Φᵀ·A·x_a)ᵀ·α_b + α_aᵀ·(Φᵀ·A·Φ)·α_b.
        let psi_gram = |shapes_gram: Vec<f64>, phi_a_x: &[Vec<f64>], p_alpha: &[Vec<f64>]| -> Vec<f64> {
            let mut r: Vec<f64> = (0..q * q).map(|x| shapes_gram[live[x / q] * p + live[x % q]]).collect();
            for i in 0..q {
                for j in 0..q {
                    r[i * q + j] +=
                        dot(&alpha[i], &p_alpha[j]) - dot(&alpha[i], &phi_a_x[j]) - dot(&phi_a_x[i], &alpha[j]);
                }
            }
            symmetrise(&mut r, q);
            r
        };
        let mg = psi_gram(combined.on_patterns(&g_m), &phi_m_x, &m_alpha);
        let cg = psi_gram(combined.on_patterns(&g_c), &phi_c_x, &c_alpha);
        let (y, omega) = pencil_basis(&kg, &Mat::<f64>::from_fn(q, q, |a, b| mg[a * q + b]))?;
        let nq = omega.len();
        dropped += q - nq;
        let y: Vec<f64> = (0..q).flat_map(|a| (0..nq).map(move |c| (a, c))).map(|(a, c)| y[(a, c)]).collect();
        // Φᵀ·A·ψ_a = Φᵀ·A·x_a − (Φᵀ·A·Φ)·α_a, then on the columns Y.
        let coupling = |phi_a_x: &[Vec<f64>], p_alpha: &[Vec<f64>]| -> Vec<f64> {
            let per_shape: Vec<Vec<f64>> = (0..q).map(|a| sub(&phi_a_x[a], &p_alpha[a])).collect();
            times_y(&per_shape, &y, nm, nq)
        };
        let on_columns = |gram_q: &[f64]| -> Vec<f64> {
            // Yᵀ·G·Y.
            let mut r = vec![0.0; nq * nq];
            for c in 0..nq {
                for d in 0..nq {
                    r[c * nq + d] = (0..q)
                        .flat_map(|a| (0..q).map(move |b| (a, b)))
                        .map(|(a, b)| y[a * nq + c] * gram_q[a * q + b] * y[b * nq + d])
                        .sum();
                }
            }
            symmetrise(&mut r, nq);
            r
        };
        let (used, wy) = on_kept_shapes(&combined, &live, &y, nq);
        Ok(PlacementResidual {
            shapes: used.iter().map(|&k| Arc::clone(&combined.shapes[k].x)).collect(),
            shapes_at: combined.values_at_loads(&g_x, &used),
            b: times_y(&alpha, &y, nm, nq),
            m_blocks: (coupling(&phi_m_x, &m_alpha), on_columns(&mg)),
            c_blocks: (coupling(&phi_c_x, &c_alpha), on_columns(&cg)),
            y: wy,
            omega,
            dropped,
        })
    }

    /// The structure's matrix A on the basis (dense nr × nr, zero on the bodies): the
    /// shared Φᵀ·A·Φ (`phi_a`), and the residual vectors' blocks (Φᵀ·A·ψ̃, ψ̃ᵀ·A·ψ̃).
    fn structure_block(&self, phi_a: &[f64], (coupling, own): &(Vec<f64>, Vec<f64>), nq: usize, nr: usize) -> Vec<f64> {
        let nm = self.modes();
        let mut r = vec![0.0; nr * nr];
        for i in 0..nm {
            r[i * nr..i * nr + nm].copy_from_slice(&phi_a[i * nm..(i + 1) * nm]);
            for c in 0..nq {
                r[i * nr + nm + c] = coupling[i * nq + c];
                r[(nm + c) * nr + i] = coupling[i * nq + c];
            }
        }
        for c in 0..nq {
            r[(nm + c) * nr + nm..(nm + c) * nr + nm + nq].copy_from_slice(&own[c * nq..(c + 1) * nq]);
        }
        r
    }
}

/// Σ_a v_a·Y_a,: (rows × columns, row-major) of per-shape vectors `v` (each `rows` long).
fn times_y(v: &[Vec<f64>], y: &[f64], rows: usize, nq: usize) -> Vec<f64> {
    let mut r = vec![0.0; rows * nq];
    for (a, va) in v.iter().enumerate() {
        for (i, &x) in va.iter().enumerate() {
            for c in 0..nq {
                r[i * nq + c] += x * y[a * nq + c];
            }
        }
    }
    r
}

/// The actuators' M, C and K of `attached` on the reduced coordinates of `basis` (dense
/// row-major, upper half mirrored), its bodies from column `first_body` on. By assembly
/// (`assembly::system::actuator_matrices`) each is a sum of rank-one terms on the links —
/// k·g·gᵀ and c·g·gᵀ on the stretch g = top − foot, m_f·f·fᵀ on the foot f — and, for M,
/// the bodies' own mass blocks, on DOFs whose rows of T are unit rows. So Tᵀ·A·T is
/// Σ w·(Tᵀ·g)·(Tᵀ·g)ᵀ: O(links × n²), whatever the number of DOFs the feet touch.
fn attachments_on_basis(attached: &System, links: &[LinkDofs], nr: usize, first_body: usize) -> [Vec<f64>; 3] {
    let mut out = [vec![0.0; nr * nr], vec![0.0; nr * nr], vec![0.0; nr * nr]];
    let mut dense = vec![0.0; nr];
    let mut rank_one = |r: &mut [f64], w: f64, g: &[(usize, f64)]| {
        if w != 0.0 {
            dense.iter_mut().for_each(|x| *x = 0.0);
            g.iter().for_each(|&(j, gj)| dense[j] = gj);
            // Row i of the upper half: (w·g_i)·g_j for j ≥ i.
            for &(i, gi) in g {
                let scale = w * gi;
                r[i * nr + i..(i + 1) * nr].iter_mut().zip(&dense[i..]).for_each(|(x, gj)| *x += scale * gj);
            }
        }
    };
    let [m, c, k] = &mut out;
    for link in links {
        rank_one(k, link.k, &link.stretch);
        rank_one(c, link.c, &link.stretch);
        rank_one(m, link.foot_mass, &link.foot);
    }
    let ns = attached.dofs.n - attached.dofs.bodies.iter().map(Vec::len).sum::<usize>();
    let bodies: Vec<usize> = attached.dofs.bodies.iter().flatten().copied().collect();
    let column = |d: usize| bodies.iter().position(|&b| b == d).map(|p| first_body + p);
    for (i, j, v) in attached.m.triplets().filter(|&(i, j, _)| i >= ns && j >= ns && i <= j) {
        if let (Some(a), Some(b)) = (column(i), column(j)) {
            m[a.min(b) * nr + a.max(b)] += v;
        }
    }
    for r in &mut out {
        for i in 0..nr {
            for j in 0..i {
                r[i * nr + j] = r[j * nr + i];
            }
        }
    }
    out
}

/// A diagonal matrix of its nonzero entries.
fn diagonal(d: &[f64]) -> Csr {
    let trip: Vec<(usize, usize, f64)> =
        d.iter().enumerate().filter(|(_, v)| **v != 0.0).map(|(r, &v)| (r, r, v)).collect();
    Csr::from_triplets(d.len(), &trip)
}

/// A·x of each x in `xs` for a row-major n × n symmetric A (Φᵀ·M·Φ, Φᵀ·C·Φ, symmetrised),
/// column by column, A read once for all of them:
/// A's columns are its rows, so each entry gets the terms A_ij·x_j in the order of a row's
/// dot product (the same bits), and the columns' updates run in vector lanes where the
/// dot products are one chain of dependent additions each.
fn mat_vecs(a: &[f64], xs: &[Vec<f64>], n: usize) -> Vec<Vec<f64>> {
    let mut rs = vec![vec![-0.0; n]; xs.len()];
    for (j, column) in a.chunks_exact(n).enumerate() {
        for (r, x) in rs.iter_mut().zip(xs) {
            r.iter_mut().zip(column).for_each(|(ri, aij)| *ri += aij * x[j]);
        }
    }
    rs
}

fn sub(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

/// The distinct patterns along which the actuators and loads of `attached` act on the
/// structure (its DOFs below `ns`): each link's foot, each drive's and each load's
/// structure part, signed so that the first coefficient is positive.
fn attachment_patterns(attached: &System, ns: usize) -> Vec<Pattern> {
    let structure_part = |g: &[(usize, f64)]| {
        let mut b: Vec<(usize, f64)> = g.iter().copied().filter(|&(d, c)| d < ns && c != 0.0).collect();
        b.sort_by_key(|&(d, _)| d);
        if b.first().is_some_and(|&(_, c)| c < 0.0) {
            b.iter_mut().for_each(|x| x.1 = -x.1);
        }
        b
    };
    let mut patterns: Vec<Pattern> = Vec::new();
    let all = attached.links.iter().map(|l| &l.foot).chain(&attached.drives).chain(&attached.loads);
    for b in all.map(|g| structure_part(g)).filter(|b| !b.is_empty()) {
        if !patterns.contains(&b) {
            patterns.push(b);
        }
    }
    patterns
}

/// The distinct structure DOFs (below `ns`) of `patterns`, ascending.
fn dofs_of(patterns: &[Pattern], ns: usize) -> Vec<usize> {
    let mut dofs: Vec<usize> = patterns.iter().flatten().map(|&(d, _)| d).filter(|&d| d < ns).collect();
    dofs.sort_unstable();
    dofs.dedup();
    dofs
}

/// The residual columns' static part X·Y = Σ_k x_k·(W·Y)_k on the kept shapes x_k of
/// `combined`, for Y (row-major, the `live` patterns × `nq` columns): the shapes whose
/// rows of W·Y are not zero (by index), and those rows.
fn on_kept_shapes(combined: &Combined, live: &[usize], y: &[f64], nq: usize) -> (Vec<usize>, Vec<f64>) {
    let n = combined.loads.len();
    let mut wy = vec![0.0; n * nq];
    for (i, &a) in live.iter().enumerate() {
        for &(k, w) in &combined.weights[a] {
            wy[k * nq..(k + 1) * nq].iter_mut().zip(&y[i * nq..(i + 1) * nq]).for_each(|(r, y)| *r += w * y);
        }
    }
    let used: Vec<usize> = (0..n).filter(|&k| wy[k * nq..(k + 1) * nq].iter().any(|&v| v != 0.0)).collect();
    let rows = used.iter().flat_map(|&k| wy[k * nq..(k + 1) * nq].to_vec()).collect();
    (used, rows)
}

/// Pattern b as a vector over the structure's DOFs, added into `x`.
fn load(b: &[(usize, f64)], x: &mut [f64]) {
    for &(d, c) in b {
        x[d] += c;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::plan::calibrated_model;
    use crate::assembly::Model;
    use crate::case::LoadedCase;
    use num_complex::Complex64;

    /// A frame turned 30° on an 8 × 6 plate, its feet between nodes, one edge clamped.
    fn placement() -> Model {
        let text = "[plate]\nlength_x = 0.5\nlength_y = 0.4\nthickness = 0.003\nyoungs_modulus = 70e9\n\
            poisson_ratio = 0.33\ndensity = 2700.0\n[plate.mesh]\nelements = [8, 6]\nthrough_points = false\n\
            [plate.edges]\nx0 = \"simply_supported\"\nx1 = \"simply_supported\"\ny0 = \"clamped\"\n\
            y1 = \"simply_supported\"\n[damping]\nkind = \"rayleigh_ratio\"\nzeta = 0.01\nmodes = [1, 3]\n\
            [[actuator]]\ntype = \"frame\"\nname = \"frame\"\nat = [0.173, 0.228]\ndirection = 30.0\n\
            [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 83.0\n\
            [[analysis]]\ntype = \"steady_state\"\n";
        calibrated_model(&LoadedCase::from_str(text, "plate.toml", ".".into()).unwrap()).unwrap()
    }

    /// The reduced structure matrices and the basis rows, which the factored form builds
    /// from Gram matrices and never forms ψ for, against the explicit columns of T: Tᵀ·A·T
    /// from dense products, and K-orthogonality of the residual columns to the modes.
    #[test]
    fn the_factored_basis_reduces_as_its_explicit_columns() {
        let model = placement();
        let bare = Model { damping: model.damping.clone(), ..Model::bare(model.structure.clone().unwrap()) };
        let bare_sys = System::assemble(&bare).unwrap();
        let modes =
            crate::solve::eigen::modes(&bare_sys.k_beam, &bare_sys.m_beam, &bare_sys.dofs.structure_dofs(), usize::MAX)
                .unwrap();
        let opts = ReductionOptions {
            cutoff: modes.omega[11] * 1.001,
            static_correction: true,
            modal_damping: None,
            sparse_factor: false,
        };
        let attached = System::assemble_attachments(&model).unwrap();
        let r = SharedBasis::new(&bare_sys, &modes, &opts).unwrap().reduce(&attached).unwrap();
        let (nm, nq) = (r.mode_omega.len(), r.residual_omega.len());
        assert_eq!(nm, 12);
        assert!(nq >= 2, "the frame's feet give residual vectors: {nq}");
        let p = r.system.projection.as_ref().unwrap();
        let ns = bare_sys.n();
        let column = |c: usize| -> Vec<f64> {
            let mut e = vec![Complex64::default(); p.n_reduced];
            e[c] = Complex64::new(1.0, 0.0);
            p.expand(&e)[..ns].iter().map(|z| z.re).collect()
        };
        let t: Vec<Vec<f64>> = (0..nm + nq).map(column).collect();
        // Rows of T agree with its columns, the feet's rows (read off the flexibility, not
        // the shapes) too.
        let feet = attached.links.iter().flat_map(|l| l.foot.iter().map(|&(d, _)| d)).filter(|&d| d < ns);
        for d in (0..ns).step_by(7).chain(feet) {
            let row = p.row_dense(d);
            for (c, tc) in t.iter().enumerate() {
                assert!((row[c] - tc[d]).abs() <= 1e-12 * tc.iter().fold(0.0f64, |m, x| m.max(x.abs())));
            }
        }
        for (a, reduced) in [(&bare_sys.m_beam, &r.system.m_beam), (&bare_sys.c_beam, &r.system.c_beam)] {
            let at: Vec<Vec<f64>> = t.iter().map(|v| mul(a, v)).collect();
            let diag: Vec<f64> = (0..nm + nq).map(|i| dot(&t[i], &at[i])).collect();
            for i in 0..nm + nq {
                for j in 0..nm + nq {
                    let explicit = dot(&t[i], &at[j]);
                    let scale = (diag[i] * diag[j]).sqrt();
                    let e = (reduced.get(i, j) - explicit).abs() / scale;
                    assert!(e < 1e-10, "({i}, {j}): {} against {explicit}: {e:e}", reduced.get(i, j));
                }
            }
        }
        // K: diagonal Ω², ω̃² as set, and the explicit columns K-orthogonal to it.
        let kt: Vec<Vec<f64>> = t.iter().map(|v| mul(&bare_sys.k_beam, v)).collect();
        for i in 0..nm + nq {
            for j in 0..nm + nq {
                let scale = (dot(&t[i], &kt[i]) * dot(&t[j], &kt[j])).sqrt();
                let e = (r.system.k_beam.get(i, j) - dot(&t[i], &kt[j])).abs() / scale;
                assert!(e < 1e-8, "K ({i}, {j}): {e:e}");
            }
        }
        // The actuators' matrices, projected through their links, against Tᵀ·A·T of the
        // assembled attachments on every column of T (the bodies' too).
        let nr = p.n_reduced;
        let full_column = |c: usize| -> Vec<f64> {
            let mut e = vec![Complex64::default(); nr];
            e[c] = Complex64::new(1.0, 0.0);
            p.expand(&e).iter().map(|z| z.re).collect()
        };
        let t: Vec<Vec<f64>> = (0..nr).map(full_column).collect();
        let s = &r.system;
        for (name, a, total, own) in [
            ("M", &attached.m, &s.m, &s.m_beam),
            ("C", &attached.c, &s.c, &s.c_beam),
            ("K", &attached.k, &s.k, &s.k_beam),
        ] {
            let at: Vec<Vec<f64>> = t.iter().map(|v| mul(a, v)).collect();
            let explicit: Vec<f64> = (0..nr * nr).map(|x| dot(&t[x / nr], &at[x % nr])).collect();
            let scale = explicit.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for (x, e) in explicit.iter().enumerate() {
                let (i, j) = (x / nr, x % nr);
                let projected = total.get(i, j) - own.get(i, j);
                assert!((projected - e).abs() <= 1e-12 * scale, "{name} ({i}, {j}): {projected:e} against {e:e}");
            }
        }
    }
}
