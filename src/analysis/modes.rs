//! Natural modes of the bare structure (the beam with its supports and attachments, no
//! actuators): the modal analysis with closed-form references where they exist, and the
//! modes other analyses need (Rayleigh calibration, the mode-resolved power flow); and the
//! modes of the coupled system (beam and actuators) beside them.

use crate::assembly::system::structure_stiffness_root;
use crate::assembly::{Model, System};
use crate::beam::analytic::{natural_frequencies_hz, End};
use crate::beam::{Beam, SupportKind};
use crate::error::Result;
use crate::plate::navier;
use crate::solve::eigen::{self, Modes};
use crate::structure::Structure;
use serde::Serialize;

/// The bare structure's modes (no actuators), used for Rayleigh damping and modal analysis.
pub fn bare_modes(structure: &Structure, count: usize) -> Result<Modes> {
    bare_modes_of(structure, &bare_system(structure)?, count)
}

/// The bare structure's first `count` modes where only a few are wanted (the Rayleigh
/// calibration's): a plate or an imported model beyond [`FEW_MODES_DENSE_LIMIT`] DOFs takes
/// shift-invert Lanczos on its sparse factor, which costs O(DOFs) where the dense solver
/// finds every mode in O(DOFs³) (a 20 × 16 plate's 1,281 DOFs: seconds of work for three
/// modes). Every beam (whose calibration keeps its dense path bit for bit up to
/// [`DENSE_EIGEN_LIMIT`]) takes [`bare_modes`], as does a model the sparse path fails on.
pub fn few_bare_modes(structure: &Structure, count: usize) -> Result<Modes> {
    few_bare_modes_of(structure, &bare_system(structure)?, count)
}

/// [`few_bare_modes`] with the bare system already assembled (`sys` from [`bare_system`]).
pub fn few_bare_modes_of(structure: &Structure, sys: &System, count: usize) -> Result<Modes> {
    if structure.beam().is_none() && sys.n() > FEW_MODES_DENSE_LIMIT && count < sys.n() / 4 {
        if let Ok(m) = crate::solve::lanczos::modes_sparse(&sys.k, &sys.m, count, 0.0) {
            return Ok(m);
        }
    }
    bare_modes_of(structure, sys, count)
}

/// The largest K_ii/M_ii over the DOFs with mass (rad²/s²): the scale of the stiffest DOF's
/// own frequency, against which the lowest eigenvalues are judged.
pub fn stiffest_ratio(sys: &System) -> f64 {
    (0..sys.n())
        .filter_map(|i| {
            let (k, m) = (sys.k.get(i, i), sys.m.get(i, i));
            (m > 0.0).then_some(k / m)
        })
        .fold(0.0f64, f64::max)
}

/// How many of the lowest `modes` of a system whose stiffest DOF has `stiffest`
/// ([`stiffest_ratio`]) are rigid-body modes, their frequencies zero up to round-off: ω²
/// within 100·ε of that scale, where an eigenvalue of K as assembled is round-off (a free
/// structure's computed rigid-body ω² sit at a few ε of it). Modes from the square-root
/// factor of the element rows belong to a supported structure, which has none; and the
/// scale is not a stiffness fraction, so that the lowest modes of a very fine mesh are
/// not taken for rigid motion.
pub fn rigid_body_count(modes: &Modes, stiffest: f64) -> usize {
    if modes.from_root {
        return 0;
    }
    let floor = 100.0 * f64::EPSILON * stiffest;
    modes.omega.iter().take_while(|&&w| w * w < floor).count()
}

/// Largest plate or imported model whose few modes the dense solver finds.
pub const FEW_MODES_DENSE_LIMIT: usize = 300;

/// The bare structure's assembled system (the structure with its supports and attachments,
/// no actuators).
pub fn bare_system(structure: &Structure) -> Result<System> {
    System::assemble(&Model::bare(structure.clone()))
}

/// [`bare_modes`] with the bare system already assembled (`sys` from [`bare_system`]).
pub fn bare_modes_of(structure: &Structure, sys: &System, count: usize) -> Result<Modes> {
    // K enters through its square-root factor built from the element rows when it has one
    // (a supported structure): that keeps the lowest modes of fine meshes accurate
    // (round-off ~ε·elements² instead of ~ε·elements⁴ for K as assembled). An unsupported
    // structure has none and takes the assembled K (shifted by a little of M: see
    // `lanczos::modes_sparse` and `eigen::modes`).
    let root = structure.beam().and_then(|beam| structure_stiffness_root(beam, &sys.dofs).ok());
    // Dense reduction up to a few thousand DOFs (all modes at once, robust); beyond that,
    // or when only a few modes of a large model are wanted, shift-invert Lanczos (linear
    // cost in the number of DOFs).
    // Beams keep their banded or profile factor (their profile is a band); other
    // structures' profiles are wide (a plate's is a grid row) and take the sparse LDLᵀ.
    if sys.n() > DENSE_EIGEN_LIMIT && count < sys.n() / 4 {
        match (root, structure.beam()) {
            (Some(root), _) => crate::solve::lanczos::lowest_modes_from_root(&root, &sys.m, count),
            (None, Some(_)) => crate::solve::lanczos::modes_shift_invert(&sys.k, &sys.m, &sys.envelope, count, 0.0),
            (None, None) => crate::solve::lanczos::modes_sparse(&sys.k, &sys.m, count, 0.0),
        }
    } else {
        match root {
            Some(root) => eigen::modes_from_root(&root, &sys.m, count),
            None => eigen::modes(&sys.k, &sys.m, &sys.dofs.structure_dofs(), count),
        }
    }
}

/// Largest model solved by the dense eigensolver.
pub const DENSE_EIGEN_LIMIT: usize = 1500;

/// The bare structure's first `count` modes with their rows numbered on the DOFs of `sys`,
/// a system of the same model with its actuators (the bare system numbers its DOFs without
/// them): the modes the mode-resolved power flow takes. None if the model has no beam.
pub fn bare_modes_on(model: &Model, sys: &System, count: usize) -> Result<Option<Modes>> {
    bare_modes_mapped(model, sys, count, false)
}

/// [`bare_modes_on`] for a few modes of a small model, many times over (an optimiser's
/// candidates): shift-invert Lanczos on the square-root factor whenever the structure is
/// supported and `count` is under a quarter of its DOFs, where the dense solver would find
/// every mode. The modes agree with the dense solver's to the solvers' tolerance.
pub fn few_bare_modes_on(model: &Model, sys: &System, count: usize) -> Result<Option<Modes>> {
    bare_modes_mapped(model, sys, count, true)
}

fn bare_modes_mapped(model: &Model, sys: &System, count: usize, sparse: bool) -> Result<Option<Modes>> {
    let Some(structure) = model.structure.as_ref() else { return Ok(None) };
    let bare = bare_system(structure)?;
    let root = match structure.beam() {
        Some(beam) if sparse && count < bare.n() / 4 => structure_stiffness_root(beam, &bare.dofs).ok(),
        _ => None,
    };
    let mut modes = match root {
        Some(root) => crate::solve::lanczos::lowest_modes_from_root(&root, &bare.m, count)?,
        None => bare_modes_of(structure, &bare, count)?,
    };
    // Map node by node: the same node's DOFs of each kind in both numberings.
    let mut to_coupled = vec![usize::MAX; bare.n()];
    for node in 0..bare.dofs.n_nodes() {
        for k in 0..bare.dofs.kinds.len() {
            if let (Some(b), Some(c)) = (bare.dofs.node_dof(node, k), sys.dofs.node_dof(node, k)) {
                to_coupled[b] = c;
            }
        }
    }
    for d in &mut modes.dofs {
        *d = to_coupled[*d];
    }
    Ok(Some(modes))
}

/// Modal analysis result.
#[derive(Clone, Debug, Serialize)]
pub struct ModesResult {
    pub frequencies_hz: Vec<f64>,
    /// Closed-form frequencies (Hz) for a uniform beam with plain end supports, else empty.
    pub analytic_hz: Vec<f64>,
    /// (f − f_analytic)/f_analytic per mode, where a reference exists.
    pub relative_error: Vec<f64>,
    /// Description of the reference used.
    pub reference: String,
    /// Order-of-magnitude bound on each frequency's relative round-off error. With K from
    /// its element rows (every supported structure): ε·ω_max/ω_r, ω_max² ≈ max_i(K_ii/M_ii),
    /// which grows as (elements)² (about 5e-7 for mode 1 of the paper beam at 50,000
    /// elements; measured errors sit two orders below). With K as assembled (unsupported
    /// structures): ε·(ω_max/ω_r)²/2, growing as (elements)⁴. See docs/physics-notes.md.
    /// 1 for a rigid-body mode, whose computed frequency is round-off of zero.
    pub roundoff_bound: Vec<f64>,
    /// How many of the lowest modes are rigid-body modes (a structure not held against
    /// rigid motion, e.g. a free plate): frequencies zero up to round-off.
    pub rigid_body_modes: usize,
    /// The modes asked for: more than the structure's free DOFs give (a very coarse mesh)
    /// and only those come back.
    #[serde(skip)]
    pub requested: usize,
    /// The bare structure's free DOFs: no more modes than these exist.
    #[serde(skip)]
    pub free_dofs: usize,
    #[serde(skip)]
    pub modes: Modes,
    /// Node coordinates (m) and the w of each mode at each node (row per mode).
    #[serde(skip)]
    pub node_x: Vec<f64>,
    /// Node y coordinates (m) on a plate; empty on a beam.
    #[serde(skip)]
    pub node_y: Vec<f64>,
    /// Node z coordinates (m) and node ids (the source model's numbering) on an imported
    /// model; empty on a beam and a plate.
    #[serde(skip)]
    pub node_z: Vec<f64>,
    #[serde(skip)]
    pub node_id: Vec<i64>,
    /// On a plate, every node DOF of each mode (row per mode, `node·kinds + kind`, zero
    /// where fixed): what the plate's shape functions interpolate between nodes.
    #[serde(skip)]
    pub node_shapes: Vec<Vec<f64>>,
    #[serde(skip)]
    pub shapes_w: Vec<Vec<f64>>,
    /// The modes of the beam with its actuators attached, beside the bare beam's (a model
    /// with actuators on a beam only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coupled: Option<CoupledModes>,
}

/// Natural modes of the coupled system: the beam with its actuators' bodies and links (the
/// stacks as springs), mass-normalised over the whole system.
#[derive(Clone, Debug, Default, Serialize)]
pub struct CoupledModes {
    pub frequencies_hz: Vec<f64>,
    /// w of each mode at each beam node (row per mode), m/√kg.
    #[serde(skip)]
    pub shapes_w: Vec<Vec<f64>>,
    /// The actuators' body DOFs (`<actuator>_<dof>`) and each mode's amplitude on them (row
    /// per mode; m/√kg, rad/√kg for rotations).
    pub body_names: Vec<String>,
    #[serde(skip)]
    pub body_shapes: Vec<Vec<f64>>,
}

/// The lowest `count` modes of the coupled system `sys` of `model` (None without a beam or
/// actuators): dense up to [`DENSE_EIGEN_LIMIT`] DOFs, shift-invert Lanczos beyond.
pub fn coupled_modes(model: &Model, sys: &System, count: usize) -> Result<Option<CoupledModes>> {
    if model.structure.is_none() || model.actuators.is_empty() {
        return Ok(None);
    }
    let n = sys.n();
    let modes = if n > DENSE_EIGEN_LIMIT && count < n / 4 {
        crate::solve::lanczos::modes_shift_invert(&sys.k, &sys.m, &sys.envelope, count, 0.0)?
    } else {
        eigen::modes(&sys.k, &sys.m, &(0..n).collect::<Vec<_>>(), count)?
    };
    let bodies = super::series::body_dofs(model, sys);
    let shapes: Vec<Vec<f64>> = (0..modes.count()).map(|r| modes.shape_global(r, n)).collect();
    Ok(Some(CoupledModes {
        frequencies_hz: modes.frequencies_hz(),
        shapes_w: shapes.iter().map(|g| sys.dofs.w_dofs().map(|d| d.map_or(0.0, |d| g[d])).collect()).collect(),
        body_names: bodies.iter().map(|b| format!("{}_{}", model.actuators[b.actuator].name(), b.name)).collect(),
        body_shapes: shapes.iter().map(|g| bodies.iter().map(|b| g[b.dof]).collect()).collect(),
    }))
}

/// End conditions of a beam supported only at its two ends, if it is uniform and bare.
pub fn plain_ends(beam: &Beam) -> Option<(End, End)> {
    let mesh = &beam.mesh;
    let e0 = mesh.elements.first()?;
    let uniform = mesh
        .elements
        .iter()
        .all(|e| (e.ei - e0.ei).abs() <= 1e-12 * e0.ei && (e.rho_a - e0.rho_a).abs() <= 1e-12 * e0.rho_a);
    if !uniform || !beam.point_masses.is_empty() || !beam.springs.is_empty() {
        return None;
    }
    let last = mesh.n_nodes() - 1;
    let mut ends = [End::Free, End::Free];
    for s in &beam.supports {
        let slot = if s.node == 0 {
            0
        } else if s.node == last {
            1
        } else {
            return None;
        };
        ends[slot] = match s.kind {
            SupportKind::Clamped => End::Clamped,
            SupportKind::Pinned => End::Pinned,
            _ => return None,
        };
    }
    Some((ends[0], ends[1]))
}

/// Closed-form frequencies (Hz) of the first `count` modes, where the structure has them,
/// and what they are.
fn closed_form(structure: &Structure, count: usize) -> (Vec<f64>, String) {
    match structure {
        Structure::Beam(beam) => {
            if let Some((l, r)) = plain_ends(beam) {
                let e = &beam.mesh.elements[0];
                // A free–free beam's first two modes are rigid; compare flexible modes only
                // where the numbering agrees.
                let rigid = [l, r].iter().filter(|&&x| x == End::Free).count();
                if rigid == 0 {
                    if let Some(a) = natural_frequencies_hz(l, r, beam.mesh.length(), e.ei, e.rho_a, count) {
                        return (a, format!("uniform Euler–Bernoulli beam, {l:?}–{r:?}"));
                    }
                }
            }
            (Vec::new(), "none (no closed form for this beam)".into())
        }
        Structure::Plate(p) => {
            let (lx, ly) = p.grid.lengths();
            let (d, rho_h) = (p.bending_stiffness(), p.mass_per_area());
            let hz = |w: f64| w / (2.0 * std::f64::consts::PI);
            if p.is_navier() {
                let a = navier::lowest(count, lx, ly, d, rho_h).into_iter().map(|(_, _, w)| hz(w)).collect();
                return (a, "simply supported Kirchhoff plate (Navier)".into());
            }
            if p.is_bare_with(crate::plate::Edge::Clamped) && (lx - ly).abs() <= 1e-12 * lx {
                let scale = (d / rho_h).sqrt() / (lx * lx);
                let a = navier::CLAMPED_SQUARE_LAMBDA.iter().take(count).map(|l| hz(l * scale)).collect();
                return (a, "clamped square Kirchhoff plate (Leissa, 5 digits)".into());
            }
            (Vec::new(), "none (no closed form for this plate)".into())
        }
        Structure::Imported(_) => (Vec::new(), "none (an imported model)".into()),
    }
}

pub fn run(structure: &Structure, count: usize) -> Result<ModesResult> {
    // One assembly for the solver, the round-off bound and the node-wise shapes.
    let sys = bare_system(structure)?;
    let modes = bare_modes_of(structure, &sys, count)?;
    let f = modes.frequencies_hz();
    let (analytic, reference) = closed_form(structure, f.len());
    let relative_error = analytic.iter().zip(&f).map(|(a, x)| (x - a) / a).collect();
    let stiffest = stiffest_ratio(&sys);
    let rigid_body_modes = rigid_body_count(&modes, stiffest);
    let roundoff_bound = modes
        .omega
        .iter()
        .enumerate()
        .map(|(r, w)| {
            if r < rigid_body_modes {
                // Zero up to round-off: relative to itself the computed value is all error.
                return 1.0;
            }
            // ω_max²/ω_r²: how far the stiffest DOF's scale is above this mode's energy.
            let ratio = stiffest / (w * w).max(f64::MIN_POSITIVE);
            if modes.from_root {
                f64::EPSILON * ratio.sqrt()
            } else {
                0.5 * f64::EPSILON * ratio
            }
        })
        .collect();
    // w of each mode at each node, from the bare system's numbering.
    let shapes_w = (0..modes.count())
        .map(|r| {
            let g = modes.shape_global(r, sys.n());
            sys.dofs.w_dofs().map(|d| d.map_or(0.0, |d| g[d])).collect()
        })
        .collect();
    let node_shapes = match structure {
        Structure::Plate(_) | Structure::Imported(_) => (0..modes.count())
            .map(|r| {
                let g = modes.shape_global(r, sys.n());
                sys.dofs.nodes.iter().map(|d| d.map_or(0.0, |d| g[d])).collect()
            })
            .collect(),
        Structure::Beam(_) => Vec::new(),
    };
    Ok(ModesResult {
        node_shapes,
        frequencies_hz: f,
        analytic_hz: analytic,
        relative_error,
        reference,
        roundoff_bound,
        rigid_body_modes,
        requested: count,
        free_dofs: sys.n(),
        node_x: (0..structure.n_nodes()).map(|n| structure.node_location(n).x()).collect(),
        node_y: (0..structure.n_nodes()).filter_map(|n| structure.node_location(n).y()).collect(),
        node_z: (0..structure.n_nodes()).filter_map(|n| structure.node_location(n).z()).collect(),
        node_id: (0..structure.n_nodes())
            .filter_map(|n| structure.node_location(n).node_component())
            .map(|p| p.0)
            .collect(),
        shapes_w,
        modes,
        coupled: None,
    })
}
