//! The model and its assembled system.

use super::damping::Damping;
use super::dofs::DofMap;
use crate::actuator::{Actuator, Component, FootBase};
use crate::beam::{element_mass, element_stiffness, element_stiffness_rows, Beam, SupportKind};
use crate::error::{Error, Result};
use crate::linalg::{BandedR, Csr, Skyline};
use crate::signal::voltage::VoltageInput;
use num_complex::Complex64;
use std::sync::Arc;

/// A point where the beam's motion is recorded.
#[derive(Clone, Debug)]
pub struct Sensor {
    pub name: String,
    /// Position along the beam (m).
    pub x: f64,
}

/// A prescribed point force on the beam: F(t) (N, along w) at x (m).
#[derive(Clone, Debug)]
pub struct PointLoad {
    pub name: String,
    /// Position along the beam (m); a mesh node.
    pub x: f64,
    /// The force's time history (N).
    pub force: VoltageInput,
}

/// What is simulated: the structure (a beam, or none for a rigid base), the actuators and
/// the prescribed point loads.
#[derive(Clone, Debug)]
pub struct Model {
    pub beam: Option<Beam>,
    /// The structure's damping (spec §3).
    pub damping: Damping,
    pub actuators: Vec<Actuator>,
    pub sensors: Vec<Sensor>,
    pub loads: Vec<PointLoad>,
    /// The relative accuracy point powers and mobilities are solved to
    /// ([`crate::analysis::roundoff`]).
    pub roundoff_tolerance: f64,
}

impl Model {
    /// The bare structure: the beam alone, undamped, with nothing on it.
    pub fn bare(beam: Beam) -> Self {
        Model {
            beam: Some(beam),
            damping: Damping::None,
            actuators: Vec::new(),
            sensors: Vec::new(),
            loads: Vec::new(),
            roundoff_tolerance: crate::analysis::roundoff::DEFAULT_TOLERANCE,
        }
    }

    /// The beam's Rayleigh coefficients (zero unless its damping is Rayleigh).
    pub fn rayleigh(&self) -> super::damping::Rayleigh {
        self.damping.rayleigh()
    }

    /// The beam's hysteretic loss factor η (zero unless its damping is hysteretic).
    pub fn loss_factor(&self) -> f64 {
        self.damping.loss_factor()
    }

    /// The bare-beam modal damping ratios, if the damping is modal.
    pub fn modal_ratios(&self) -> Option<&[f64]> {
        self.damping.modal_ratios()
    }

    /// The signals that drive the model, actuators' voltages first, then the loads' forces:
    /// together they set its period and the frequencies a run must resolve.
    pub fn drive_signals(&self) -> impl Iterator<Item = &VoltageInput> {
        self.actuators.iter().map(|a| &a.stack().voltage).chain(self.loads.iter().map(|l| &l.force))
    }
}

/// A link with its global DOFs resolved.
#[derive(Clone, Debug)]
pub struct LinkDofs {
    pub actuator: usize,
    pub name: String,
    pub k: f64,
    pub c: f64,
    /// Stretch u = Σ coeff·q[dof] (top minus foot).
    pub stretch: Vec<(usize, f64)>,
    /// Beam node and w DOF of the foot (dof None if a support fixes w or the base is rigid).
    /// In a reduced system (see [`Projection`]) the foot is not one DOF: `foot_dof` is None
    /// there and `foot` holds the combination.
    pub foot_node: Option<usize>,
    pub foot_dof: Option<usize>,
    /// The foot's beam displacement w = Σ coeff·q[dof] (empty on a fixed or rigid base).
    /// In the full model this is `[(foot_dof, 1.0)]`; analyses read the foot through it.
    pub foot: Vec<(usize, f64)>,
    /// Foot position on the beam (m), if on the beam.
    pub foot_x: Option<f64>,
    pub foot_mass: f64,
    pub active: bool,
}

/// The assembled system `M·q̈ + C·q̇ + K·q = Σ_a b_a·F_p,a(t) + f(t)`.
#[derive(Clone, Debug)]
pub struct System {
    pub dofs: DofMap,
    /// Whole-system matrices (kg, N·s/m, N/m in mixed units of each DOF).
    pub m: Csr,
    pub c: Csr,
    pub k: Csr,
    /// The structure's own matrices (beam elements, its point masses, supports' springs,
    /// grounded spring–dampers), same dimension, zero on actuator DOFs: the beam's
    /// energies and dissipation are computed from these.
    pub m_beam: Csr,
    pub c_beam: Csr,
    pub k_beam: Csr,
    /// The imaginary part η·K_beam of a hysteretically damped structure's stiffness
    /// (frequency-domain analyses only).
    pub k_loss: Option<Csr>,
    pub links: Vec<LinkDofs>,
    /// For each actuator, the load pattern b of its stack's F_p (top minus foot).
    pub drives: Vec<Vec<(usize, f64)>>,
    /// For each point load, its pattern: the beam's w at its point.
    pub loads: Vec<Vec<(usize, f64)>>,
    /// Skyline envelope covering the pattern of M, C and K.
    pub envelope: Vec<usize>,
    /// For a reduced system, how its coordinates map to the full model's; None for the
    /// assembled (full) system.
    pub projection: Option<Arc<Projection>>,
}

/// The basis of a reduced system: full-model DOFs q_full = T·q_reduced.
#[derive(Clone, Debug)]
pub struct Projection {
    /// The full model's DOF map (beam w, θ per node; actuator bodies).
    pub full: DofMap,
    /// T, `full.n` rows × `n_reduced` columns, row-major.
    pub t: Vec<f64>,
    pub n_reduced: usize,
}

impl Projection {
    /// Row `i` of T (full DOF i in reduced coordinates), without exact zeros.
    pub fn row(&self, i: usize) -> Vec<(usize, f64)> {
        let r = &self.t[i * self.n_reduced..(i + 1) * self.n_reduced];
        r.iter().enumerate().filter(|(_, v)| **v != 0.0).map(|(j, &v)| (j, v)).collect()
    }

    /// Full-model amplitudes T·q of reduced ones (complex, e.g. one harmonic's Q_k).
    pub fn expand(&self, q: &[Complex64]) -> Vec<Complex64> {
        assert_eq!(q.len(), self.n_reduced, "reduced vector length");
        self.t.chunks_exact(self.n_reduced).map(|row| row.iter().zip(q).map(|(&t, &x)| x * t).sum()).collect()
    }
}

impl System {
    pub fn n(&self) -> usize {
        self.dofs.n
    }

    /// Assembles a model. Errors if an actuator foot is not on a mesh node or the damping is
    /// still a ratio (see [`crate::analysis::plan::calibrate`]).
    pub fn assemble(model: &Model) -> Result<System> {
        model.damping.require_calibrated()?;
        let comps: Vec<Component> = model.actuators.iter().map(|a| a.component()).collect();
        let beam = model.beam.as_ref();
        let feet_nodes = feet_nodes(&comps, beam)?;
        // Each actuator's bodies are numbered after the last node its feet stand on.
        let anchors: Vec<Option<usize>> =
            feet_nodes.iter().map(|nodes| nodes.iter().flatten().max().copied()).collect();
        let sizes: Vec<usize> = comps.iter().map(|c| c.dof_names.len()).collect();
        let dofs = DofMap::number(beam, &anchors, &sizes);
        let n = dofs.n;
        let [m_beam, c_beam, k_beam] = structure_matrices(beam, &dofs, model.rayleigh());
        let actuators = actuator_matrices(&comps, &feet_nodes, beam, &dofs);
        let m = Csr::combine(&[(1.0, &m_beam), (1.0, &Csr::from_triplets(n, &actuators.m))]);
        let k = Csr::combine(&[(1.0, &k_beam), (1.0, &Csr::from_triplets(n, &actuators.k))]);
        let c = Csr::combine(&[(1.0, &c_beam), (1.0, &Csr::from_triplets(n, &actuators.c))]);
        let envelope = Skyline::<f64>::envelope_of(
            n,
            m.triplets().chain(k.triplets()).chain(c.triplets()).map(|(i, j, _)| (i, j)),
        );
        let k_loss = (model.loss_factor() > 0.0).then(|| k_beam.scaled(model.loss_factor()));
        let loads = load_patterns(model, &dofs)?;
        let ActuatorMatrices { links, drives, .. } = actuators;
        Ok(System { dofs, m, c, k, m_beam, c_beam, k_beam, k_loss, links, drives, loads, envelope, projection: None })
    }

    /// The w DOF of the beam node at x, if free. Errors if x is not on a node, or if this
    /// is a reduced system (use [`System::w_at`]).
    pub fn w_dof_at(&self, model: &Model, x: f64, field: &str) -> Result<Option<usize>> {
        let beam = model.beam.as_ref().ok_or_else(|| Error::case_field(field, "the model has no beam"))?;
        let node =
            beam.mesh.node_at(x).ok_or_else(|| Error::case_field(field, format!("x = {x} m is not on a mesh node")))?;
        if self.projection.is_some() {
            return Err(Error::Numerical(format!(
                "{field}: a reduced system has no single w DOF at x = {x} m (use w_at)"
            )));
        }
        Ok(self.dofs.w[node])
    }

    /// The beam's w at x as a combination Σ coeff·q[dof] of this system's DOFs: one DOF in
    /// the full system, a row of the basis in a reduced one, empty where a support fixes w.
    /// Errors if x is not on a node.
    pub fn w_at(&self, model: &Model, x: f64, field: &str) -> Result<Vec<(usize, f64)>> {
        let beam = model.beam.as_ref().ok_or_else(|| Error::case_field(field, "the model has no beam"))?;
        let node =
            beam.mesh.node_at(x).ok_or_else(|| Error::case_field(field, format!("x = {x} m is not on a mesh node")))?;
        Ok(match &self.projection {
            None => self.dofs.w[node].map(|d| vec![(d, 1.0)]).unwrap_or_default(),
            Some(p) => p.full.w[node].map(|d| p.row(d)).unwrap_or_default(),
        })
    }

    /// Skyline matrix α·K + β·C + γ·M (real), e.g. the Newmark effective stiffness.
    pub fn skyline_combination(&self, alpha: f64, beta: f64, gamma: f64) -> Skyline<f64> {
        let mut s = Skyline::zeros(self.envelope.clone());
        self.k.add_into_skyline(alpha, &mut s);
        self.c.add_into_skyline(beta, &mut s);
        self.m.add_into_skyline(gamma, &mut s);
        s
    }
}

/// A square-root factor R of the structure's stiffness (`k_beam` of [`System::assemble`]:
/// elements, support springs, grounded springs) over the free DOFs of `dofs`, with
/// RᵀR = K_beam, built from G's rows — two per element ([`element_stiffness_rows`]), √k
/// on the DOF of each spring — by Givens QR, never forming K. Banded in `dofs`' numbering
/// (half-bandwidth 3 for a bare beam). Errors if a spring is negative (K is then no Gram
/// matrix) or if K is singular or nearly so (an unsupported structure), so the caller can
/// fall back to the LDLᵀ of K.
pub fn structure_stiffness_root(beam: &Beam, dofs: &DofMap) -> Result<BandedR> {
    // G's rows, flat: entries of row r at `entries[starts[r]..starts[r + 1]]`.
    let mut entries: Vec<(usize, f64)> = Vec::with_capacity(8 * beam.mesh.elements.len());
    let mut starts = vec![0];
    for e in &beam.mesh.elements {
        let d = dofs.element_dofs(e.nodes);
        for g in element_stiffness_rows(e.ei, e.length) {
            entries.extend(d.iter().zip(g).filter_map(|(dof, v)| dof.map(|i| (i, v))));
            starts.push(entries.len());
        }
    }
    let springs = beam.supports.iter().flat_map(|s| match s.kind {
        SupportKind::Spring { k_w, k_theta } => vec![(dofs.w[s.node], k_w), (dofs.theta[s.node], k_theta)],
        _ => vec![],
    });
    for (dof, k) in springs.chain(beam.springs.iter().map(|s| (dofs.w[s.node], s.stiffness))) {
        if k < 0.0 {
            return Err(Error::Numerical(format!("a negative spring ({k} N/m) has no square-root factor")));
        }
        if let (Some(i), true) = (dof, k > 0.0) {
            entries.push((i, k.sqrt()));
            starts.push(entries.len());
        }
    }
    let mut r = BandedR::from_rows(dofs.n, starts.windows(2).map(|w| &entries[w[0]..w[1]]));
    r.check()?;
    Ok(r)
}

impl System {
    /// Static displacement K·q = f (m, rad). Errors if the structure is not supported.
    pub fn static_solve(&self, f: &[f64]) -> Result<Vec<f64>> {
        let k = self.skyline_combination(1.0, 0.0, 0.0);
        let fac = k.factorize()?;
        let mut q = f.to_vec();
        fac.solve_in_place(&mut q);
        Ok(q)
    }
}

/// The beam node each actuator link's foot stands on (None on the ground), per actuator.
pub(super) fn feet_nodes(comps: &[Component], beam: Option<&Beam>) -> Result<Vec<Vec<Option<usize>>>> {
    let mut feet_nodes = Vec::with_capacity(comps.len());
    for (ai, comp) in comps.iter().enumerate() {
        let mut nodes = Vec::new();
        for link in &comp.links {
            nodes.push(match (link.foot, beam) {
                (FootBase::Beam { x }, Some(b)) => Some(b.mesh.node_at(x).ok_or_else(|| {
                    Error::case_field(
                        format!("actuator[{ai}].{}", link.name),
                        format!("foot at x = {x} m is not on a mesh node"),
                    )
                })?),
                (FootBase::Beam { x }, None) => {
                    return Err(Error::case_field(
                        format!("actuator[{ai}].{}", link.name),
                        format!("foot at x = {x} m but the model has no beam"),
                    ));
                }
                (FootBase::Ground, _) => None,
            });
        }
        feet_nodes.push(nodes);
    }
    Ok(feet_nodes)
}

/// The structure's own M, C and K: beam elements, point masses, support springs, Rayleigh
/// damping of the elements and point masses (a₀·M + a₁·K, without the grounded springs),
/// and the grounded spring–dampers.
pub(super) fn structure_matrices(beam: Option<&Beam>, dofs: &DofMap, rayleigh: super::damping::Rayleigh) -> [Csr; 3] {
    let n = dofs.n;
    let mut mb = Vec::new();
    let mut kb = Vec::new();
    let mut cb = Vec::new();
    if let Some(beam) = beam {
        for e in &beam.mesh.elements {
            let ke = element_stiffness(e.ei, e.length);
            let me = element_mass(e.rho_a, e.length, beam.mass_kind);
            let d = dofs.element_dofs(e.nodes);
            for a in 0..4 {
                for b in 0..4 {
                    if let (Some(i), Some(j)) = (d[a], d[b]) {
                        kb.push((i, j, ke[(a, b)]));
                        mb.push((i, j, me[(a, b)]));
                    }
                }
            }
        }
        for pm in &beam.point_masses {
            if let Some(i) = dofs.w[pm.node] {
                mb.push((i, i, pm.mass));
            }
            if let Some(i) = dofs.theta[pm.node] {
                mb.push((i, i, pm.rotary_inertia));
            }
        }
        for s in &beam.supports {
            if let SupportKind::Spring { k_w, k_theta } = s.kind {
                if let Some(i) = dofs.w[s.node] {
                    kb.push((i, i, k_w));
                }
                if let Some(i) = dofs.theta[s.node] {
                    kb.push((i, i, k_theta));
                }
            }
        }
    }
    let m_el = Csr::from_triplets(n, &mb);
    let k_el = Csr::from_triplets(n, &kb);
    let mut ctrip: Vec<(usize, usize, f64)> = Vec::new();
    ctrip.extend(m_el.triplets().map(|(i, j, v)| (i, j, rayleigh.a0 * v)));
    ctrip.extend(k_el.triplets().map(|(i, j, v)| (i, j, rayleigh.a1 * v)));
    if let Some(beam) = beam {
        for s in &beam.springs {
            if let Some(i) = dofs.w[s.node] {
                kb.push((i, i, s.stiffness));
                cb.push((i, i, s.damping));
            }
        }
    }
    ctrip.extend(cb);
    [m_el, Csr::from_triplets(n, &ctrip), Csr::from_triplets(n, &kb)]
}

/// The actuators' contributions: body masses and foot masses (m), link springs (k) and
/// dampers (c) as triplets, and each link with its DOFs resolved.
pub(super) struct ActuatorMatrices {
    pub(super) m: Vec<(usize, usize, f64)>,
    pub(super) k: Vec<(usize, usize, f64)>,
    pub(super) c: Vec<(usize, usize, f64)>,
    links: Vec<LinkDofs>,
    /// Per actuator, the pattern b_a its stack force F_p acts along.
    drives: Vec<Vec<(usize, f64)>>,
}

pub(super) fn actuator_matrices(
    comps: &[Component],
    feet_nodes: &[Vec<Option<usize>>],
    beam: Option<&Beam>,
    dofs: &DofMap,
) -> ActuatorMatrices {
    let mut out = ActuatorMatrices {
        m: Vec::new(),
        k: Vec::new(),
        c: Vec::new(),
        links: Vec::new(),
        drives: vec![Vec::new(); comps.len()],
    };
    for (ai, comp) in comps.iter().enumerate() {
        let body = &dofs.bodies[ai];
        for a in 0..body.len() {
            for b in 0..body.len() {
                out.m.push((body[a], body[b], comp.mass[(a, b)]));
            }
        }
        for (li, link) in comp.links.iter().enumerate() {
            let node = feet_nodes[ai][li];
            let foot_dof = node.and_then(|nd| dofs.w[nd]);
            // The stretch u = top − foot as a combination of DOFs.
            let mut g: Vec<(usize, f64)> = link.top.iter().map(|&(d, c)| (body[d], c)).collect();
            if let Some(fd) = foot_dof {
                g.push((fd, -1.0));
                out.m.push((fd, fd, link.foot_mass));
            }
            for &(i, gi) in &g {
                for &(j, gj) in &g {
                    out.k.push((i, j, link.k * gi * gj));
                    out.c.push((i, j, link.c * gi * gj));
                }
            }
            if link.active {
                out.drives[ai] = g.clone();
            }
            out.links.push(LinkDofs {
                actuator: ai,
                name: link.name.clone(),
                k: link.k,
                c: link.c,
                stretch: g,
                foot_node: node,
                foot_dof,
                foot: foot_dof.map(|d| vec![(d, 1.0)]).unwrap_or_default(),
                foot_x: node.map(|nd| beam.expect("a foot on a node has a beam").mesh.x[nd]),
                foot_mass: link.foot_mass,
                active: link.active,
            });
        }
    }
    out
}

/// Each point load's pattern: the w DOF of its node (empty where a support fixes w).
fn load_patterns(model: &Model, dofs: &DofMap) -> Result<Vec<Vec<(usize, f64)>>> {
    let mut loads = Vec::with_capacity(model.loads.len());
    for (i, l) in model.loads.iter().enumerate() {
        let field = format!("load[{i}].x");
        let beam = model.beam.as_ref().ok_or_else(|| Error::case_field(&field, "a point load needs a beam"))?;
        let node = beam
            .mesh
            .node_at(l.x)
            .ok_or_else(|| Error::case_field(&field, format!("x = {} m is not on a mesh node", l.x)))?;
        loads.push(dofs.w[node].map(|d| vec![(d, 1.0)]).unwrap_or_default());
    }
    Ok(loads)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::{GroundedSpring, Material, Mesh, PointMass, Section, Support};

    /// Small beams with varying sections and element lengths, interior supports (DOFs
    /// removed mid-numbering), support springs, grounded springs and point masses.
    fn odd_beams() -> Vec<Beam> {
        let section = Section { width: 0.05, thickness: 0.005 };
        let material = Material { youngs_modulus: 210e9, density: 7850.0 };
        let mut beams = Vec::new();
        for (n, seed) in [(7usize, 1u32), (12, 2), (19, 3)] {
            let mut mesh = Mesh::uniform(0.73, n, &[], section, material);
            for (i, e) in mesh.elements.iter_mut().enumerate() {
                // Sections two decades apart, deterministic but irregular.
                let t = ((i as f64 + 1.0) * 0.754_877_666 * seed as f64).fract();
                e.ei *= 10f64.powf(2.0 * t - 1.0);
                e.rho_a *= 1.0 + t;
            }
            let last = mesh.n_nodes() - 1;
            let supports = vec![
                Support { node: 0, kind: SupportKind::Clamped },
                Support { node: n / 3, kind: SupportKind::Pinned },
                Support { node: n / 2, kind: SupportKind::Guided },
                Support { node: last, kind: SupportKind::Spring { k_w: 3.0e5 * seed as f64, k_theta: 40.0 } },
            ];
            let mut beam = Beam::new(mesh, supports);
            beam.springs.push(GroundedSpring { node: 2 * n / 3, stiffness: 1.2e6, damping: 3.0 });
            beam.springs.push(GroundedSpring { node: last, stiffness: 7.0e3, damping: 0.0 });
            beam.point_masses.push(PointMass { node: n / 4 + 1, mass: 0.3, rotary_inertia: 1e-4 });
            beams.push(beam);
        }
        beams
    }

    #[test]
    fn stiffness_root_squares_to_the_assembled_stiffness_and_is_banded() {
        for beam in odd_beams() {
            let model = Model::bare(beam.clone());
            let sys = System::assemble(&model).unwrap();
            let r = structure_stiffness_root(&beam, &sys.dofs).unwrap();
            let n = sys.n();
            assert_eq!(r.dim(), n);
            assert!(r.bandwidth() <= 3, "bandwidth {}", r.bandwidth());
            for i in 0..n {
                assert!(r.get(i, i) > 0.0);
                for j in 0..n {
                    let rtr: f64 = (0..n).map(|k| r.get(k, i) * r.get(k, j)).sum();
                    let scale = (sys.k.get(i, i) * sys.k.get(j, j)).sqrt();
                    assert!(
                        (rtr - sys.k.get(i, j)).abs() <= 1e-14 * scale,
                        "({i},{j}): RᵀR = {rtr}, K = {}",
                        sys.k.get(i, j)
                    );
                }
            }
        }
    }

    #[test]
    fn an_unsupported_beam_has_no_stiffness_root() {
        let mut beam = odd_beams().remove(0);
        beam.supports.clear();
        beam.springs.clear();
        let model = Model::bare(beam.clone());
        let sys = System::assemble(&model).unwrap();
        let err = structure_stiffness_root(&beam, &sys.dofs).unwrap_err().to_string();
        assert!(err.contains("singular"), "{err}");
    }
}

/// What a row (and column) of the assembled matrices is: the beam node and its position, or
/// the actuator body it belongs to, and the DOF's kind (`w`, `theta`, or the body's DOF
/// name such as `z_t`, `y`, `phi`).
#[derive(Clone, Debug, PartialEq)]
pub struct DofRow {
    pub index: usize,
    /// Beam node (None for an actuator body DOF).
    pub node: Option<usize>,
    /// Position of the node on the beam (m).
    pub x: Option<f64>,
    pub kind: String,
    /// Actuator name (for a body DOF).
    pub actuator: Option<String>,
}

/// One [`DofRow`] per DOF of the full model's system, in index order.
pub fn dof_rows(model: &Model, sys: &System) -> Vec<DofRow> {
    let n = sys.dofs.n;
    let mut rows: Vec<DofRow> =
        (0..n).map(|index| DofRow { index, node: None, x: None, kind: String::new(), actuator: None }).collect();
    let xs = model.beam.as_ref().map(|b| b.mesh.x.clone()).unwrap_or_default();
    for (kind, dofs) in [("w", &sys.dofs.w), ("theta", &sys.dofs.theta)] {
        for (node, d) in dofs.iter().enumerate() {
            if let Some(d) = *d {
                rows[d].node = Some(node);
                rows[d].x = xs.get(node).copied();
                rows[d].kind = kind.to_string();
            }
        }
    }
    for (a, body) in sys.dofs.bodies.iter().enumerate() {
        let names = model.actuators[a].component().dof_names;
        for (k, &d) in body.iter().enumerate() {
            rows[d].kind = names.get(k).map_or_else(|| format!("body_{k}"), |s| s.to_string());
            rows[d].actuator = Some(model.actuators[a].name().to_string());
        }
    }
    rows
}
