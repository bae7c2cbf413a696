//! The model and its assembled system.

use super::damping::Damping;
use super::dofs::DofMap;
use super::projection::Projection;
use crate::actuator::{Actuator, Component, FootBase};
use crate::beam::{element_stiffness_rows, Beam, SupportKind};
use crate::error::{Error, Result};
use crate::linalg::{BandedR, Csr, Skyline};
use crate::signal::voltage::VoltageInput;
use crate::structure::{single_node, Location, Structure};
use std::sync::Arc;

/// A point where the structure's motion (its w) is recorded.
#[derive(Clone, Debug)]
pub struct Sensor {
    pub name: String,
    pub at: Location,
}

/// A prescribed point force on the structure: F(t) (N, along w) at a point.
#[derive(Clone, Debug)]
pub struct PointLoad {
    pub name: String,
    pub at: Location,
    /// The force's time history (N).
    pub force: VoltageInput,
}

/// What is simulated: the structure (a beam or a plate, or none for a rigid base), the
/// actuators and the prescribed point loads.
#[derive(Clone, Debug)]
pub struct Model {
    pub structure: Option<Structure>,
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
    /// The bare structure: the structure alone, undamped, with nothing on it.
    pub fn bare(structure: impl Into<Structure>) -> Self {
        Model {
            structure: Some(structure.into()),
            damping: Damping::None,
            actuators: Vec::new(),
            sensors: Vec::new(),
            loads: Vec::new(),
            roundoff_tolerance: crate::analysis::roundoff::DEFAULT_TOLERANCE,
        }
    }

    /// The structure if it is a beam (for the beam's own fast paths and references).
    pub fn beam(&self) -> Option<&Beam> {
        self.structure.as_ref().and_then(Structure::beam)
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
    /// Structure node and w DOF of a foot standing on a node (dof None if a support fixes w
    /// or the base is rigid). A foot attached through shape functions, or in a reduced
    /// system (see [`Projection`]), is not one DOF: `foot_dof` is None there and `foot`
    /// holds the combination.
    pub foot_node: Option<usize>,
    pub foot_dof: Option<usize>,
    /// The foot's structure displacement w = Σ coeff·q[dof] (empty on a fixed or rigid
    /// base); analyses read the foot through it.
    pub foot: Vec<(usize, f64)>,
    /// Where the foot stands, if on the structure.
    pub foot_at: Option<Location>,
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
    /// K, M and C (row-major n × n, entry for entry `k`, `m` and `c`) where the system was
    /// formed dense (a placement's reduced system): a dense solve reads them instead of
    /// expanding the sparse ones again.
    pub dense: Option<Arc<[Vec<f64>; 3]>>,
}

impl System {
    pub fn n(&self) -> usize {
        self.dofs.n
    }

    /// Assembles a model. Errors if an actuator foot is not on a mesh node or the damping is
    /// still a ratio (see [`crate::analysis::plan::calibrate`]).
    pub fn assemble(model: &Model) -> Result<System> {
        Self::assemble_parts(model, true, None)
    }

    /// The model's actuators and loads alone on its structure, for a reduction basis that
    /// supplies the structure ([`crate::solve::shared_basis`]): the structure's DOFs
    /// numbered as in the bare structure's assembly, every body after them, and no
    /// structure matrices (`m_beam`, `c_beam`, `k_beam` zero; `m`, `c`, `k` the actuators').
    pub fn assemble_attachments(model: &Model) -> Result<System> {
        Self::assemble_parts(model, false, None)
    }

    /// [`System::assemble_attachments`] on a structure already numbered as `structure`
    /// (the bare structure's DOF map, without bodies): the numbering depends on the
    /// structure alone, so a study's cases skip its node ordering.
    pub fn assemble_attachments_on(model: &Model, structure: &DofMap) -> Result<System> {
        Self::assemble_parts(model, false, Some(structure))
    }

    fn assemble_parts(model: &Model, with_structure: bool, numbered: Option<&DofMap>) -> Result<System> {
        model.damping.require_calibrated()?;
        let comps: Vec<Component> = model.actuators.iter().map(|a| a.component()).collect();
        let structure = model.structure.as_ref();
        let feet = feet_attachments(&comps, structure)?;
        let sizes: Vec<usize> = comps.iter().map(|c| c.dof_names.len()).collect();
        let dofs = match numbered {
            Some(numbered) => numbered.with_bodies(structure, &sizes)?,
            None => {
                // Each actuator's bodies are numbered after the last node its feet reach
                // (keeping the profile narrow), or all after the structure when it is not
                // assembled here.
                let order = structure.map(Structure::node_order).unwrap_or_default();
                let mut rank = vec![0; order.len()];
                for (r, &node) in order.iter().enumerate() {
                    rank[node] = r;
                }
                let anchors: Vec<Option<usize>> = feet
                    .iter()
                    .map(|links| links.iter().flatten().flat_map(|a| a.iter().map(|t| t.0)).max_by_key(|&n| rank[n]))
                    .map(|anchor| anchor.filter(|_| with_structure))
                    .collect();
                DofMap::number_in(structure, &order, &anchors, &sizes)
            }
        };
        let n = dofs.n;
        let [m_beam, c_beam, k_beam] = match with_structure {
            true => structure_matrices(structure, &dofs, model.rayleigh()),
            false => [Csr::zeros(n), Csr::zeros(n), Csr::zeros(n)],
        };
        let actuators = actuator_matrices(&comps, &feet, structure, &dofs);
        // Without the structure (a placement on a shared reduction, assembled per case) the
        // actuators' matrices are the whole: no pass over the structure's rows to add zeros.
        let [m, k, c] = [(&m_beam, &actuators.m), (&k_beam, &actuators.k), (&c_beam, &actuators.c)].map(|(s, a)| {
            let a = Csr::from_triplets(n, a);
            match with_structure {
                // The bare structure (no actuators): its own matrices, as the sum gives them.
                true if a.nnz() == 0 => s.clone(),
                true => Csr::combine(&[(1.0, s), (1.0, &a)]),
                false => a,
            }
        });
        // Without the structure the pattern is the actuators' triplets', read without a
        // pass over every row.
        let envelope = match with_structure {
            true => Csr::envelope_of(n, &[&m, &k, &c]),
            false => Skyline::<f64>::envelope_of(
                n,
                actuators.m.iter().chain(&actuators.k).chain(&actuators.c).map(|&(i, j, _)| (i, j)),
            ),
        };
        let k_loss = (with_structure && model.loss_factor() > 0.0).then(|| k_beam.scaled(model.loss_factor()));
        let loads = load_patterns(model, &dofs)?;
        let ActuatorMatrices { links, drives, .. } = actuators;
        Ok(System {
            dofs,
            m,
            c,
            k,
            m_beam,
            c_beam,
            k_beam,
            k_loss,
            links,
            drives,
            loads,
            envelope,
            projection: None,
            dense: None,
        })
    }

    /// The structure's w at a point as a combination Σ coeff·q[dof] of this system's DOFs:
    /// one DOF at a node of the full system, the element's shape functions between nodes,
    /// rows of the basis in a reduced system; empty where supports fix it. Errors (naming
    /// `field`) if the point is not on the structure.
    pub fn w_at(&self, model: &Model, at: &Location, field: &str) -> Result<Vec<(usize, f64)>> {
        let s = model
            .structure
            .as_ref()
            .ok_or_else(|| Error::case_field(field, "the model has no structure (base = \"rigid\")"))?;
        let attachment = s.attach(at).map_err(|e| Error::case_field(field, e))?;
        let dofs = self.projection.as_ref().map_or(&self.dofs, |p| &p.full);
        let mut pattern = Vec::new();
        for (node, kind, c) in attachment {
            if let Some(d) = dofs.node_dof(node, kind) {
                match &self.projection {
                    None => pattern.push((d, c)),
                    Some(p) => pattern.extend(p.row(d).into_iter().map(|(j, t)| (j, c * t))),
                }
            }
        }
        Ok(pattern)
    }

    /// The single DOF of w at a point of the full system, if the point is a node with a
    /// free w (harmonic analyses read mobilities there). Errors if the point is not a
    /// node, or if this is a reduced system (use [`System::w_at`]).
    pub fn w_dof_at(&self, model: &Model, at: &Location, field: &str) -> Result<Option<usize>> {
        if self.projection.is_some() {
            return Err(Error::Numerical(format!("{field}: a reduced system has no single w DOF at {at} (use w_at)")));
        }
        let s = model.structure.as_ref().ok_or_else(|| Error::case_field(field, "the model has no structure"))?;
        let attachment = s.attach(at).map_err(|e| Error::case_field(field, e))?;
        let (node, kind) = crate::structure::single_dof(&attachment).ok_or_else(|| {
            Error::case_field(field, format!("{at} is not on a mesh node (or acts along a negative component)"))
        })?;
        Ok(self.dofs.node_dof(node, kind))
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
        let d = dofs.element_dofs(&e.nodes);
        for g in element_stiffness_rows(e.ei, e.length) {
            entries.extend(d.iter().zip(g).filter_map(|(dof, v)| dof.map(|i| (i, v))));
            starts.push(entries.len());
        }
    }
    let springs = beam.supports.iter().flat_map(|s| match s.kind {
        SupportKind::Spring { k_w, k_theta } => vec![(dofs.w(s.node), k_w), (dofs.node_dof(s.node, 1), k_theta)],
        _ => vec![],
    });
    for (dof, k) in springs.chain(beam.springs.iter().map(|s| (dofs.w(s.node), s.stiffness))) {
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

/// Each actuator link's foot as an attachment to the structure (None on the ground), per
/// actuator.
pub(super) fn feet_attachments(
    comps: &[Component],
    structure: Option<&Structure>,
) -> Result<Vec<Vec<Option<crate::structure::Attachment>>>> {
    let mut feet = Vec::with_capacity(comps.len());
    for (ai, comp) in comps.iter().enumerate() {
        let mut links = Vec::new();
        for link in &comp.links {
            let field = || format!("actuator[{ai}].{}", link.name);
            links.push(match (link.foot, structure) {
                (FootBase::On(at), Some(s)) => {
                    Some(s.attach(&at).map_err(|e| Error::case_field(field(), format!("foot at {e}")))?)
                }
                (FootBase::On(at), None) => {
                    return Err(Error::case_field(field(), format!("foot at {at} but the model has no structure")));
                }
                (FootBase::Ground, _) => None,
            });
        }
        feet.push(links);
    }
    Ok(feet)
}

/// The structure's own M, C and K: elements, point masses, support springs, Rayleigh
/// damping of the elements and point masses (a₀·M + a₁·K, without the grounded springs),
/// and the grounded spring–dampers.
fn structure_matrices(structure: Option<&Structure>, dofs: &DofMap, rayleigh: super::damping::Rayleigh) -> [Csr; 3] {
    let n = dofs.n;
    let (mb, mut kb) = structure_entries(structure, dofs);
    let m_el = Csr::from_triplets(n, &mb);
    let k_el = Csr::from_triplets(n, &kb);
    let mut cb = Vec::new();
    if let Some(s) = structure {
        for (node, k, c) in s.grounded_springs() {
            if let Some(i) = dofs.w(node) {
                kb.push((i, i, k));
                cb.push((i, i, c));
            }
        }
    }
    let given_c = structure.and_then(Structure::imported).and_then(|m| m.c.as_ref().map(|c| (m, c)));
    // Without grounded springs or a given C, each entry of C is a₀·m + a₁·k on the
    // elements' pattern and K is the elements' own: one merge of two sorted rows per row
    // (two terms sum to the same bits in either order).
    if cb.is_empty() && given_c.is_none() {
        let c = Csr::sum_of((rayleigh.a0, &m_el), (rayleigh.a1, &k_el));
        return [m_el, c, k_el];
    }
    let mut ctrip: Vec<(usize, usize, f64)> = Vec::new();
    ctrip.extend(m_el.triplets().map(|(i, j, v)| (i, j, rayleigh.a0 * v)));
    ctrip.extend(k_el.triplets().map(|(i, j, v)| (i, j, rayleigh.a1 * v)));
    if let Some((model, c)) = given_c {
        ctrip.extend(
            c.triplets()
                .filter_map(|(i, j, v)| Some((imported_dof(model, dofs, i)?, imported_dof(model, dofs, j)?, v))),
        );
    }
    ctrip.extend(cb);
    [m_el, Csr::from_triplets(n, &ctrip), Csr::from_triplets(n, &kb)]
}

/// (row, col, value) triplets, duplicates to be summed.
type Entries = Vec<(usize, usize, f64)>;

/// The entries of the structure's M and K: its elements, an imported model's matrices,
/// point inertia and support springs.
fn structure_entries(structure: Option<&Structure>, dofs: &DofMap) -> (Entries, Entries) {
    let (mut mb, mut kb) = (Vec::new(), Vec::new());
    let Some(s) = structure else { return (mb, kb) };
    s.for_each_element(|e| {
        let d = dofs.element_dofs(e.nodes);
        for a in 0..d.len() {
            for b in 0..d.len() {
                if let (Some(i), Some(j)) = (d[a], d[b]) {
                    kb.push((i, j, (e.stiffness)(a, b)));
                    mb.push((i, j, (e.mass)(a, b)));
                }
            }
        }
    });
    if let Some(model) = s.imported() {
        imported_entries(model, &model.m, dofs, &mut mb);
        imported_entries(model, &model.k, dofs, &mut kb);
    }
    for (node, kind, v) in s.point_inertia() {
        if let Some(i) = dofs.node_dof(node, kind) {
            mb.push((i, i, v));
        }
    }
    for (node, kind, k) in s.support_springs() {
        if let Some(i) = dofs.node_dof(node, kind) {
            kb.push((i, i, k));
        }
    }
    (mb, kb)
}

/// The system DOF of an imported model's row (None for a fixed row).
fn imported_dof(model: &crate::imported::Imported, dofs: &DofMap, row: usize) -> Option<usize> {
    let (node, kind) = model.rows[row];
    dofs.node_dof(node, kind)
}

/// An imported model's entries of `a` (its M or K) on the system's DOFs (fixed rows
/// dropped), into `out`.
fn imported_entries(model: &crate::imported::Imported, a: &Csr, dofs: &DofMap, out: &mut Entries) {
    out.extend(
        a.triplets().filter_map(|(i, j, v)| Some((imported_dof(model, dofs, i)?, imported_dof(model, dofs, j)?, v))),
    );
}

/// The actuators' contributions: body masses and foot masses (m), link springs (k) and
/// dampers (c) as triplets, and each link with its DOFs resolved.
pub(super) struct ActuatorMatrices {
    pub(super) m: Vec<(usize, usize, f64)>,
    pub(super) k: Vec<(usize, usize, f64)>,
    pub(super) c: Vec<(usize, usize, f64)>,
    pub(super) links: Vec<LinkDofs>,
    /// Per actuator, the pattern b_a its stack force F_p acts along.
    drives: Vec<Vec<(usize, f64)>>,
}

pub(super) fn actuator_matrices(
    comps: &[Component],
    feet: &[Vec<Option<crate::structure::Attachment>>],
    structure: Option<&Structure>,
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
            let attachment = feet[ai][li].as_deref().unwrap_or_default();
            // The foot's w over the free DOFs (a support may fix some of them).
            let foot: Vec<(usize, f64)> =
                attachment.iter().filter_map(|&(node, kind, c)| dofs.node_dof(node, kind).map(|d| (d, c))).collect();
            // The stretch u = top − foot as a combination of DOFs.
            let mut g: Vec<(usize, f64)> = link.top.iter().map(|&(d, c)| (body[d], c)).collect();
            g.extend(foot.iter().map(|&(d, c)| (d, -c)));
            // The foot's lumped mass rides on the foot point's w: m·f·fᵀ.
            for &(i, ci) in &foot {
                for &(j, cj) in &foot {
                    out.m.push((i, j, link.foot_mass * ci * cj));
                }
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
            let node = single_node(attachment);
            let foot_dof = crate::structure::single_dof(attachment).and_then(|(n, k)| dofs.node_dof(n, k));
            out.links.push(LinkDofs {
                actuator: ai,
                name: link.name.clone(),
                k: link.k,
                c: link.c,
                stretch: g,
                foot_node: node,
                foot_dof,
                foot,
                foot_at: match (link.foot, structure) {
                    (FootBase::On(at), Some(_)) => Some(at),
                    _ => None,
                },
                foot_mass: link.foot_mass,
                active: link.active,
            });
        }
    }
    out
}

/// Each point load's pattern: the structure's w at its point (empty where supports fix it).
fn load_patterns(model: &Model, dofs: &DofMap) -> Result<Vec<Vec<(usize, f64)>>> {
    let mut loads = Vec::with_capacity(model.loads.len());
    for (i, l) in model.loads.iter().enumerate() {
        let field = format!("load[{i}].{}", l.at.field());
        let s = model.structure.as_ref().ok_or_else(|| Error::case_field(&field, "a point load needs a structure"))?;
        let attachment = s.attach(&l.at).map_err(|e| Error::case_field(&field, e))?;
        loads
            .push(attachment.iter().filter_map(|&(node, kind, c)| dofs.node_dof(node, kind).map(|d| (d, c))).collect());
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
            let model = Model::bare(Structure::Beam(beam.clone()));
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
        let model = Model::bare(Structure::Beam(beam.clone()));
        let sys = System::assemble(&model).unwrap();
        let err = structure_stiffness_root(&beam, &sys.dofs).unwrap_err().to_string();
        assert!(err.contains("singular"), "{err}");
    }
}

/// What a row (and column) of the assembled matrices is: the structure node and its
/// position, or the actuator body it belongs to, and the DOF's kind (`w`, `theta`, `w_x`,
/// …, or the body's DOF name such as `z_t`, `y`, `phi`).
#[derive(Clone, Debug, PartialEq)]
pub struct DofRow {
    pub index: usize,
    /// Structure node (None for an actuator body DOF).
    pub node: Option<usize>,
    /// Position of the node (m): x always, y on a plate and an imported model, z on an
    /// imported model.
    pub x: Option<f64>,
    pub y: Option<f64>,
    pub z: Option<f64>,
    /// The node's number in the source model of an imported structure.
    pub node_id: Option<i64>,
    pub kind: String,
    /// Actuator name (for a body DOF).
    pub actuator: Option<String>,
}

/// One [`DofRow`] per DOF of the full model's system, in index order.
pub fn dof_rows(model: &Model, sys: &System) -> Vec<DofRow> {
    let n = sys.dofs.n;
    let mut rows: Vec<DofRow> = (0..n)
        .map(|index| DofRow {
            index,
            node: None,
            x: None,
            y: None,
            z: None,
            node_id: None,
            kind: String::new(),
            actuator: None,
        })
        .collect();
    if let Some(s) = &model.structure {
        for node in 0..sys.dofs.n_nodes() {
            let at = s.node_location(node);
            for (k, kind) in sys.dofs.kinds.iter().enumerate() {
                if let Some(d) = sys.dofs.node_dof(node, k) {
                    rows[d].node = Some(node);
                    rows[d].x = Some(at.x());
                    rows[d].y = at.y();
                    rows[d].z = at.z();
                    rows[d].node_id = at.node_component().map(|(id, _)| id);
                    rows[d].kind = kind.to_string();
                }
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
