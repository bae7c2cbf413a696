//! Modal reduction of a coupled beam–actuator system.
//!
//! The full system has beam DOFs (w, θ per node) and actuator body DOFs. The reduced
//! system keeps the bodies physical and replaces the beam DOFs by a few generalised
//! coordinates: `q_full = T·q_red` with
//!
//! ```text
//!         ⎡ Φ_r  Ψ  0 ⎤   beam DOFs
//!     T = ⎣ 0    0  I ⎦   actuator body DOFs
//! ```
//!
//! * **Φ_r**: the bare beam's mass-normalised modes (K_beam·φ = ω²·M_beam·φ, the beam with
//!   its supports, point masses and grounded springs, but without the actuators) with
//!   ω_r at or below the cut-off.
//! * **Ψ**: a static correction by *residual flexibility* (MacNeal/Rubin attachment
//!   modes). For every beam DOF an actuator touches (its feet: links' stretches and the
//!   stacks' load patterns) the static shape under a unit force there, with the retained
//!   modes' part removed:
//!   `ψ_j = K_beam⁻¹·e_j − Σ_r φ_r·φ_r(j)/ω_r²`.
//!   Exactly, ψ_j is M_beam- and K_beam-orthogonal to every retained mode, and
//!   ψ_iᵀ·K_beam·ψ_j = G_ij, the residual flexibility `S_f − Φ_fᵀ·Ω⁻²·Φ_f` between feet i
//!   and j. We re-orthogonalise the vectors against the modes (twice, Gram–Schmidt in the
//!   M_beam inner product) to remove eigensolver round-off, then diagonalise the small
//!   pencil (G, Ψᵀ·M_beam·Ψ), which turns them into M-orthonormal, K-orthogonal "residual
//!   modes" with pseudo-frequencies above the cut-off. Vectors are dropped when they carry
//!   no energy of their own: a foot whose residual flexibility cancels to round-off (the
//!   modes already span its static shape, at a cut-off above most of the mesh) or one that
//!   depends on the others. Dependence is judged in the energy (K) norm, not the M norm:
//!   a residual vector's mass is tiny next to its stiffness at high cut-offs, and an
//!   M-norm test would throw away stiffness the feet need.
//! * **I**: the actuator bodies, untouched.
//!
//! Why residual flexibility: the forces an actuator puts on the beam act only at its feet,
//! so with Ψ the basis contains the *exact* static response of the beam to any foot load.
//! The reduced model is then exact at ω = 0 and its error at a frequency ω comes only from
//! the dynamics of the discarded modes. On the paper's frame case, with modes to 5× the
//! highest harmonic, point powers agree with the full model to 2e-8 with the correction and
//! are 80 % off without it (stiff legs on a beam whose local flexibility the modes miss).
//! It keeps the bare-beam modes themselves as coordinates (the η_r of §11, so modal
//! quantities read straight off the reduced state) and leaves M_beam, K_beam and, with
//! Rayleigh damping, C_beam diagonal; that is also what makes modal damping (ζ_r per
//! mode) a diagonal 2ζ_r·ω_r here, added from the formula like K_beam. The price is that a foot's w is a combination of all
//! reduced beam coordinates (a dense row of T), which links and drives carry as coefficient
//! lists anyway. A Craig–Bampton form of the same subspace (feet kept physical, constraint
//! modes plus fixed-interface modes) was tried: same results to 1e-8, but the mass coupling
//! between modal and interface coordinates leaves the matrices just as full, so the
//! transient ran no faster, and the modal coordinates would no longer be the bare beam's.
//!
//! The reduced K_beam is set from the formulas, diag(Ω², ω̃²), rather than projected: K·ψ
//! is a difference of large numbers at every node away from the feet, and its round-off
//! would otherwise show as spurious coupling. The actuators' stiffness (K − K_beam), M, C,
//! M_beam and C_beam are projected, `Tᵀ·A·T`, as small dense matrices (tens of DOFs) and go
//! back into a [`System`] with a full skyline envelope, so every solver and analysis runs on
//! it unchanged. Entries below 1e-12 of the geometric mean of their diagonal pair (the
//! round-off of the orthogonality relations) are dropped.
//!
//! Accuracy floor: with every mode of the mesh kept the reduced model reproduces the full
//! one's point powers to about 1e-8 (inertial 2e-8, frame 1e-8), not 1e-15. The full
//! model's own complex solve is good to 1e-10 (one step of iterative refinement changes it
//! by less), so the floor is on the basis side; the likely cause is that a stretch such as
//! a leg's u = y + a·φ − w is a small difference of large displacements (k_l = 1.5e9 N/m),
//! which amplifies the round-off of the dense eigenvectors and of K_beam⁻¹.

use crate::assembly::{DofMap, LinkDofs, Projection, System};
use crate::error::{Error, Result};
use crate::linalg::sparse_ldlt::SparsePattern;
use crate::linalg::{dot, Csr, Skyline};
use crate::solve::eigen::{ratio_of, Modes};
use faer::{Mat, MatRef, Side};
use std::sync::Arc;

/// Relative size below which a projected entry counts as round-off.
const DROP: f64 = 1e-12;

/// A residual vector whose residual flexibility ψᵀ·K·ψ is below this fraction of the
/// flexibility at its foot is round-off (that difference cancels to ε of the total).
pub(super) const RESIDUAL_FLOOR: f64 = 1e-10;

/// What to keep.
#[derive(Clone, Debug, PartialEq)]
pub struct ReductionOptions {
    /// Keep the bare-beam modes with ω_r ≤ this (rad/s).
    pub cutoff: f64,
    /// Add the residual-flexibility vectors at the attachment DOFs.
    pub static_correction: bool,
    /// Modal damping ratios ζ_r per bare-beam mode (the last repeats), added to the beam's
    /// damping as 2ζ_r·ω_r on the diagonal of the reduced coordinates; see [`reduce`].
    pub modal_damping: Option<Vec<f64>>,
    /// Factor K for the static correction with the sparse LDLᵀ (a large plate or imported
    /// model, whose profile is wide) rather than the profile of the system's envelope.
    pub sparse_factor: bool,
}

/// A reduced system and what went into it.
#[derive(Clone, Debug)]
pub struct Reduction {
    /// The reduced system: coordinates [modes, residual vectors, actuator bodies].
    pub system: System,
    /// Circular frequencies of the retained modes (rad/s).
    pub mode_omega: Vec<f64>,
    /// The lowest discarded mode's ω (rad/s), if the beam has more modes.
    pub first_discarded_omega: Option<f64>,
    /// Pseudo-frequencies √(ψᵀ·K·ψ) of the (M-orthonormal, K-orthogonal) residual vectors
    /// (rad/s), one per attachment DOF unless dropped.
    pub residual_omega: Vec<f64>,
    /// Residual vectors dropped because the retained modes already span their static shape
    /// (a cut-off above most of the mesh's modes) or another one does (dependence).
    pub dropped: usize,
}

impl Reduction {
    pub fn full_dofs(&self) -> usize {
        self.system.projection.as_ref().map_or(0, |p| p.full.n)
    }
}

/// The bare beam's modes over the beam DOFs of an assembled system (all of them, ascending).
pub fn beam_modes(full: &System) -> Result<Modes> {
    crate::solve::eigen::modes(&full.k_beam, &full.m_beam, &full.dofs.structure_dofs(), usize::MAX)
}

/// The bare structure's modes up to `cutoff` (rad/s) and the first above it, for a
/// reduction of a large plate or imported model: shift-invert Lanczos on the sparse LDLᵀ of
/// the structure's K, the count read off the inertia of K − ω_c²·M (Sylvester: its
/// negative pivots are the eigenvalues below ω_c²), so no mode below the cut-off is missed.
/// A beam keeps [`beam_modes`], every mode from its dense (or root) path.
pub fn structure_modes_to(full: &System, cutoff: f64) -> Result<Modes> {
    let dofs = full.dofs.structure_dofs();
    let (k, m) = (full.k_beam.restricted(&dofs), full.m_beam.restricted(&dofs));
    let pattern = SparsePattern::analyse(&[&k, &m])?;
    let below = pattern.factorize(&[(1.0, &k), (-cutoff * cutoff, &m)])?.negative_pivots();
    let wanted = (below + 1).min(dofs.len());
    let mut modes = crate::solve::lanczos::modes_on_pattern(&pattern, &k, &m, wanted, 0.0)?;
    modes.dofs = dofs;
    Ok(modes)
}

/// Reduces an assembled system with the bare-beam `modes` (from [`beam_modes`] or
/// [`structure_modes_to`]).
pub fn reduce(full: &System, modes: &Modes, opts: &ReductionOptions) -> Result<Reduction> {
    if full.projection.is_some() {
        return Err(Error::Numerical("the system is already reduced".into()));
    }
    let n = full.n();
    let beam_dofs = full.dofs.structure_dofs();
    if beam_dofs.is_empty() {
        return Err(Error::Numerical("modal reduction needs a beam with free DOFs".into()));
    }
    let bodies: Vec<usize> = full.dofs.bodies.iter().flatten().copied().collect();
    if beam_dofs.len() + bodies.len() != n {
        return Err(Error::Numerical(format!(
            "modal reduction: {} beam and {} body DOFs do not make up the system's {n}",
            beam_dofs.len(),
            bodies.len()
        )));
    }
    let kept: Vec<usize> = (0..modes.count()).filter(|&r| modes.omega[r] <= opts.cutoff).collect();
    let first_discarded_omega = modes.omega.get(kept.len()).copied();
    let phi: Vec<Vec<f64>> = kept.iter().map(|&r| modes.shape_global(r, n)).collect();
    let mode_omega: Vec<f64> = kept.iter().map(|&r| modes.omega[r]).collect();
    let attach = attachment_dofs(full, &beam_dofs);

    // Beam columns of T: the retained modes, then (static correction) the residual
    // vectors. The reduced K_beam is known in closed form, diag(Ω², ω̃²): taking it from
    // the formulas rather than projecting K keeps it free of the round-off that K·ψ carries
    // (a difference of large numbers at every node away from the feet).
    let Residual { vectors: residual, omega: residual_omega, dropped } = if opts.static_correction && !attach.is_empty()
    {
        let shapes = static_shapes(full, &bodies, &attach, opts.sparse_factor)?;
        let unit: Vec<Vec<(usize, f64)>> = attach.iter().map(|&j| vec![(j, 1.0)]).collect();
        residual_vectors(&full.m_beam, &unit, shapes, &phi, &mode_omega)?
    } else {
        Residual { vectors: Vec::new(), omega: Vec::new(), dropped: 0 }
    };
    let k_diag: Vec<f64> = mode_omega.iter().chain(&residual_omega).map(|w| w * w).collect();

    // T, row-major n × nr: columns [modes, residual vectors, bodies].
    let (nm, np) = (phi.len(), residual.len());
    let nr = nm + np + bodies.len();
    let mut t = vec![0.0; n * nr];
    for (c, v) in phi.iter().chain(&residual).enumerate() {
        for &d in &beam_dofs {
            t[d * nr + c] = v[d];
        }
    }
    for (k, &b) in bodies.iter().enumerate() {
        t[b * nr + nm + np + k] = 1.0;
    }
    drop((phi, residual));

    let basis = Basis { t: &t, n, nr };
    let [m, mut c, m_beam, mut c_beam] = [&full.m, &full.c, &full.m_beam, &full.c_beam].map(|a| basis.project(a));
    if let Some(ratios) = &opts.modal_damping {
        // Modal damping lives in the bare beam's modal coordinates, which the beam block of
        // the basis is: M-orthonormal and K-diagonal, so C_beam = diag(2ζ_r·ω_r) there. The
        // residual vectors stand in for the discarded modes, so they take the next ratios
        // in order (the last repeating) at their pseudo-frequencies.
        let diag: Vec<(usize, usize, f64)> = mode_omega
            .iter()
            .chain(&residual_omega)
            .enumerate()
            .map(|(r, &w)| (r, r, 2.0 * ratio_of(ratios, r) * w))
            .collect();
        let modal = Csr::from_triplets(nr, &diag);
        c = Csr::combine(&[(1.0, &c), (1.0, &modal)]);
        c_beam = Csr::combine(&[(1.0, &c_beam), (1.0, &modal)]);
    }
    let k_beam = Csr::from_triplets(nr, &k_diag.iter().enumerate().map(|(r, &v)| (r, r, v)).collect::<Vec<_>>());
    // The actuators' stiffness (links), projected.
    let k_links = basis.project(&Csr::combine(&[(1.0, &full.k), (-1.0, &full.k_beam)]));
    let k = Csr::combine(&[(1.0, &k_beam), (1.0, &k_links)]);

    let projection = Projection::dense(full.dofs.clone(), t, nr);
    let system = reduced_system(full, projection, [m, c, k, m_beam, c_beam, k_beam], nm + np);
    Ok(Reduction { system, mode_omega, first_discarded_omega, residual_omega, dropped })
}

/// The reduced system of `full` on `basis` with its matrices `[m, c, k, m_beam, c_beam,
/// k_beam]`: `full`'s links, drives and loads on the reduced coordinates, its bodies
/// numbered after the `first_body` structure coordinates. A reduced basis is for viscous
/// damping: hysteretic damping is refused before.
pub(super) fn reduced_system(full: &System, basis: Projection, matrices: [Csr; 6], first_body: usize) -> System {
    let links = links_on(full, &basis);
    reduced_system_with(full, basis, matrices, first_body, links)
}

/// `full`'s links on the reduced coordinates of `basis`.
pub(super) fn links_on(full: &System, basis: &Projection) -> Vec<LinkDofs> {
    let on_basis = |l: &LinkDofs| LinkDofs {
        stretch: basis.row_combination(&l.stretch),
        foot: basis.row_combination(&l.foot),
        foot_dof: None,
        ..l.clone()
    };
    full.links.iter().map(on_basis).collect()
}

/// [`reduced_system`] with `full`'s links on the basis already formed ([`links_on`]).
pub(super) fn reduced_system_with(
    full: &System,
    basis: Projection,
    matrices: [Csr; 6],
    first_body: usize,
    links: Vec<LinkDofs>,
) -> System {
    let [m, c, k, m_beam, c_beam, k_beam] = matrices;
    let nr = basis.n_reduced;
    let combine = |bs: &[Vec<(usize, f64)>]| -> Vec<_> { bs.iter().map(|b| basis.row_combination(b)).collect() };
    let (drives, loads) = (combine(&full.drives), combine(&full.loads));
    let envelope = Csr::envelope_of(nr, &[&m, &c, &k]);
    System {
        dofs: reduced_dofs(full, first_body, nr),
        m,
        c,
        k,
        m_beam,
        c_beam,
        k_beam,
        k_loss: None,
        links,
        drives,
        loads,
        envelope,
        projection: Some(Arc::new(basis)),
        dense: None,
    }
}

/// Beam DOFs the actuators and loads touch, ascending.
fn attachment_dofs(full: &System, beam_dofs: &[usize]) -> Vec<usize> {
    let mut is_beam = vec![false; full.n()];
    for &d in beam_dofs {
        is_beam[d] = true;
    }
    let mut attach: Vec<usize> = full
        .links
        .iter()
        .flat_map(|l| l.stretch.iter().map(|&(d, _)| d))
        .chain(full.drives.iter().flatten().map(|&(d, _)| d))
        .chain(full.loads.iter().flatten().map(|&(d, _)| d))
        .filter(|&d| is_beam[d])
        .collect();
    attach.sort_unstable();
    attach.dedup();
    attach
}

/// The static correction's residual vectors over the full DOFs, their pseudo-frequencies
/// ω̃ (rad/s) and how many attachment DOFs gave none.
pub(super) struct Residual {
    pub(super) vectors: Vec<Vec<f64>>,
    pub(super) omega: Vec<f64>,
    pub(super) dropped: usize,
}

/// The value bᵀ·v of an attachment pattern b (a DOF combination) on a vector.
pub(super) fn at(pattern: &[(usize, f64)], v: &[f64]) -> f64 {
    pattern.iter().fold(0.0, |s, &(d, c)| s + c * v[d])
}

/// The residual flexibility G = S_f − Φ_fᵀ·Ω⁻²·Φ_f (= Ψᵀ·K·Ψ) between attachment patterns
/// b_a, from their static flexibility (`flex[a·p + b]` = b_bᵀ·K⁻¹·b_a, p patterns) and their
/// values on the retained modes (`on_modes[a][r]` = b_aᵀ·φ_r, at `mode_omega`), over the
/// patterns it keeps; and those patterns. A pattern whose own residual flexibility cancels
/// to round-off is already spanned by the retained modes (a cut-off above most of the
/// mesh's modes); keeping it would make T singular.
pub(super) fn residual_flexibility(flex: &[f64], on_modes: &[Vec<f64>], mode_omega: &[f64]) -> (Vec<usize>, Mat<f64>) {
    let p = on_modes.len();
    let g = |a: usize, b: usize| {
        let sf = 0.5 * (flex[a * p + b] + flex[b * p + a]);
        sf - on_modes[a].iter().zip(&on_modes[b]).zip(mode_omega).map(|((x, y), w)| x * y / (w * w)).sum::<f64>()
    };
    let live: Vec<usize> = (0..p).filter(|&a| g(a, a) > RESIDUAL_FLOOR * flex[a * p + a]).collect();
    let kg = Mat::<f64>::from_fn(live.len(), live.len(), |a, b| g(live[a], live[b]));
    (live, kg)
}

/// Residual vectors for the attachment patterns `patterns` (b_j: a DOF, or a point's
/// shape functions) with static shapes `shapes` (K⁻¹·b_j): the static shapes minus what
/// the retained modes `phi` (at `mode_omega`) carry of them, M-orthogonal (`m`) to the
/// modes and diagonalising the residual flexibility.
pub(super) fn residual_vectors(
    m: &Csr,
    patterns: &[Vec<(usize, f64)>],
    shapes: Vec<Vec<f64>>,
    phi: &[Vec<f64>],
    mode_omega: &[f64],
) -> Result<Residual> {
    let n = shapes.first().map_or(0, Vec::len);
    let on_modes: Vec<Vec<f64>> = patterns.iter().map(|b| phi.iter().map(|v| at(b, v)).collect()).collect();
    let p = patterns.len();
    let flex: Vec<f64> = (0..p * p).map(|x| at(&patterns[x % p], &shapes[x / p])).collect();
    let (live, kg) = residual_flexibility(&flex, &on_modes, mode_omega);
    let mut dropped = patterns.len() - live.len();
    // ψ_j = S_j − Φ·Ω⁻²·Φ_f,j, then M-orthogonalised against Φ (twice) for round-off.
    let psi: Vec<Vec<f64>> = live
        .iter()
        .map(|&a| {
            let mut x = shapes[a].clone();
            for ((v, w), f) in phi.iter().zip(mode_omega).zip(&on_modes[a]) {
                let c = f / (w * w);
                x.iter_mut().zip(v).for_each(|(xi, vi)| *xi -= c * vi);
            }
            for _ in 0..2 {
                let mx = mul(m, &x);
                let coefficients: Vec<f64> = phi.iter().map(|v| dot(v, &mx)).collect();
                for (v, c) in phi.iter().zip(coefficients) {
                    x.iter_mut().zip(v).for_each(|(xi, vi)| *xi -= c * vi);
                }
            }
            x
        })
        .collect();
    let q = live.len();
    let mp: Vec<Vec<f64>> = psi.iter().map(|v| mul(m, v)).collect();
    let mg = Mat::<f64>::from_fn(q, q, |a, b| 0.5 * (dot(&psi[a], &mp[b]) + dot(&psi[b], &mp[a])));
    let (y, omega) = pencil_basis(&kg, &mg)?;
    dropped += q - omega.len();
    let vectors = (0..omega.len())
        .map(|c| {
            let mut v = vec![0.0; n];
            for (r, pr) in psi.iter().enumerate() {
                let w = y[(r, c)];
                v.iter_mut().zip(pr).for_each(|(a, b)| *a += w * b);
            }
            v
        })
        .collect();
    Ok(Residual { vectors, omega, dropped })
}

/// The static shapes S = K_beam⁻¹·e_j at the attachment DOFs `attach`, zero on the bodies.
/// K_beam is zero on the body rows: 1 on their diagonal makes it factorisable.
fn static_shapes(full: &System, bodies: &[usize], attach: &[usize], sparse: bool) -> Result<Vec<Vec<f64>>> {
    let n = full.n();
    let unit = |j: usize| {
        let mut x = vec![0.0; n];
        x[j] = 1.0;
        x
    };
    let shapes = |solve: &dyn Fn(&mut [f64])| -> Vec<Vec<f64>> {
        let shape = |j: usize| {
            let mut x = unit(j);
            solve(&mut x);
            bodies.iter().for_each(|&b| x[b] = 0.0);
            x
        };
        attach.iter().map(|&j| shape(j)).collect()
    };
    if sparse {
        let ones = Csr::from_triplets(n, &bodies.iter().map(|&b| (b, b, 1.0)).collect::<Vec<_>>());
        let kb = Csr::combine(&[(1.0, &full.k_beam), (1.0, &ones)]);
        let pattern = SparsePattern::analyse(&[&kb])?;
        let kf = pattern.factorize(&[(1.0, &kb)])?;
        return Ok(shapes(&|x| kf.solve_in_place(x)));
    }
    let mut ks = Skyline::<f64>::zeros(full.envelope.clone());
    full.k_beam.add_into_skyline(1.0, &mut ks);
    for &b in bodies {
        ks.add(b, b, 1.0);
    }
    let kf = ks.factorize()?;
    Ok(shapes(&|x| kf.solve_in_place(x)))
}

/// A dense reduction basis T (row-major n × nr) and what it does to a whole matrix.
struct Basis<'t> {
    t: &'t [f64],
    n: usize,
    nr: usize,
}

impl Basis<'_> {
    /// Tᵀ·A·T, symmetrised, as a sparse matrix without entries below round-off.
    fn project(&self, a: &Csr) -> Csr {
        let (t, n, nr) = (self.t, self.n, self.nr);
        // AT = A·T (n × nr) by A's entries, then Tᵀ·AT as one dense product (with every
        // mode kept, nr ≈ n and this is the reduction's main cost), symmetrised.
        let mut at = vec![0.0; n * nr];
        for (i, j, v) in a.triplets() {
            let (src, dst) = (&t[j * nr..(j + 1) * nr], i * nr);
            for c in 0..nr {
                at[dst + c] += v * src[c];
            }
        }
        let t_ref = MatRef::from_row_major_slice(t, n, nr);
        let prod = t_ref.transpose() * MatRef::from_row_major_slice(&at, n, nr);
        let mut r = vec![0.0; nr * nr];
        for a in 0..nr {
            for b in 0..=a {
                let s = 0.5 * (prod[(a, b)] + prod[(b, a)]);
                r[a * nr + b] = s;
                r[b * nr + a] = s;
            }
        }
        sparse_of_dense(&mut r, nr)
    }
}

/// A symmetric dense matrix (row-major nr × nr) as a sparse one, without the entries below
/// round-off of their diagonal pair (the orthogonality relations' rounding), which are set
/// to zero in `r` too: `r` is then the sparse matrix's dense form, entry for entry.
pub(super) fn sparse_of_dense(r: &mut [f64], nr: usize) -> Csr {
    let (mut indptr, mut indices, mut data) = (vec![0], Vec::with_capacity(nr * nr), Vec::with_capacity(nr * nr));
    let root: Vec<f64> = (0..nr).map(|a| r[a * nr + a].abs().sqrt()).collect();
    let (mut row_indices, mut row_data) = (vec![0; nr], vec![0.0; nr]);
    for (a, row) in r.chunks_exact_mut(nr).enumerate() {
        let bound = DROP * root[a];
        // Every entry of the row is written and the kept ones advance: no branch per
        // entry, whose outcome a dense block's pattern leaves to chance.
        let mut len = 0;
        for (b, (v, &root_b)) in row.iter_mut().zip(&root).enumerate() {
            let keep = (*v != 0.0) & ((a == b) | (v.abs() > bound * root_b));
            row_indices[len] = b;
            row_data[len] = *v;
            len += keep as usize;
            *v = if keep { *v } else { 0.0 };
        }
        indices.extend_from_slice(&row_indices[..len]);
        data.extend_from_slice(&row_data[..len]);
        indptr.push(indices.len());
    }
    Csr::from_sorted_rows(nr, indptr, indices, data)
}

/// The reduced system's DOF map: no beam DOFs, the bodies numbered after the `first_body`
/// beam coordinates.
fn reduced_dofs(full: &System, first_body: usize, nr: usize) -> DofMap {
    let mut next = first_body;
    DofMap {
        n: nr,
        kinds: &[],
        nodes: Vec::new(),
        structure: full.dofs.structure,
        bodies: full
            .dofs
            .bodies
            .iter()
            .map(|ds| {
                ds.iter()
                    .map(|_| {
                        next += 1;
                        next - 1
                    })
                    .collect()
            })
            .collect(),
    }
}

pub(super) fn mul(a: &Csr, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; x.len()];
    a.mul_vec(x, &mut y);
    y
}

/// Combinations Y of a set of vectors that are M-orthonormal and K-orthogonal, given the
/// pencil's Gram matrices `kg` = Vᵀ·K·V and `mg` = Vᵀ·M·V; returns Y (columns ascending
/// in ω) and ω = √(yᵀ·K·y). Directions with less than 1e-10 of the largest K-norm² (after
/// scaling each vector to unit K-norm) are dropped as dependent: the energy norm is the
/// one that decides whether a direction matters for the static correction.
pub(super) fn pencil_basis(kg: &Mat<f64>, mg: &Mat<f64>) -> Result<(Mat<f64>, Vec<f64>)> {
    let q = kg.nrows();
    if q == 0 {
        return Ok((Mat::zeros(0, 0), Vec::new()));
    }
    let eig = |a: &Mat<f64>| {
        a.self_adjoint_eigen(Side::Lower)
            .map_err(|e| Error::Numerical(format!("reduction basis eigensolver failed: {e:?}")))
    };
    let kmax = (0..q).map(|i| kg[(i, i)]).fold(0.0f64, f64::max);
    if kmax.is_nan() || kmax <= 0.0 {
        return Err(Error::Numerical("reduction basis: the modal vectors carry no strain energy".into()));
    }
    let d: Vec<f64> = (0..q).map(|i| 1.0 / kg[(i, i)].max(1e-300 * kmax).sqrt()).collect();
    let ks = Mat::<f64>::from_fn(q, q, |i, j| d[i] * kg[(i, j)] * d[j]);
    let ek = eig(&ks)?;
    let lam = ek.S().column_vector();
    let big = (0..q).map(|i| lam[i]).fold(0.0f64, f64::max);
    let keep: Vec<usize> = (0..q).filter(|&i| lam[i] > 1e-10 * big).collect();
    // X = D·V·Λ^{-1/2}: Xᵀ·kg·X = I.
    let x = Mat::<f64>::from_fn(q, keep.len(), |i, j| d[i] * ek.U()[(i, keep[j])] / lam[keep[j]].sqrt());
    let mx = x.transpose() * mg * &x;
    let mx = Mat::<f64>::from_fn(mx.nrows(), mx.ncols(), |i, j| 0.5 * (mx[(i, j)] + mx[(j, i)]));
    let em = eig(&mx)?;
    let mu = em.S().column_vector();
    let nk = keep.len();
    // Largest μ = lowest ω first; μ ≤ 0 would be a direction without mass.
    let cols: Vec<usize> = (0..nk).rev().filter(|&c| mu[c] > 0.0).collect();
    let v = &x * em.U();
    let y = Mat::<f64>::from_fn(q, cols.len(), |i, j| v[(i, cols[j])] / mu[cols[j]].sqrt());
    let omega = cols.iter().map(|&c| (1.0 / mu[c]).sqrt()).collect();
    Ok((y, omega))
}
