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
//! * the static shapes K⁻¹·b_j of the case's attachment patterns b_j (a foot's w: one DOF
//!   at a node, the element's shape functions between nodes; a point load's likewise), one
//!   solve each, turned into residual vectors exactly as a single system's reduction does
//!   (`modal_basis::residual_vectors`: M-orthogonal to Φ, diagonalising the residual
//!   flexibility);
//! * the structure blocks that involve them (Φᵀ·M·ψ, ψᵀ·M·ψ, and C's), from one product
//!   with M and one with C per residual vector;
//! * the actuators' bodies, springs, dampers and foot masses projected on the rows of the
//!   basis at their feet (`Basis::project_rows`).
//!
//! The reduced system is the one `modal_basis::reduce` builds from the case's assembled
//! system, except that its static correction is spanned by the attachment patterns b_j
//! rather than by every DOF they touch: the forces an actuator or a load puts on the
//! structure act only along those patterns, so K⁻¹·b_j is the whole static response, and a
//! point between nodes costs one vector, not sixteen. Nothing of the size of the
//! structure's matrices is assembled per placement.

use super::modal_basis::{
    at, mul, reduced_system, residual_vectors, sparse_of_dense, Basis, Reduction, ReductionOptions, Residual,
};
use crate::assembly::{DofMap, System};
use crate::error::{Error, Result};
use crate::linalg::sparse_ldlt::OwnedLdlt;
use crate::linalg::{dot, Csr};
use crate::solve::eigen::{ratio_of, Modes};

/// The bare structure's part of a reduction, shared by the placements of a study.
#[derive(Debug)]
pub struct SharedBasis {
    /// The bare structure's DOF numbering (no actuators): a placement's system must number
    /// the structure the same way.
    dofs: DofMap,
    /// Retained modes over the structure's DOFs (mass-normalised) and their ω (rad/s).
    phi: Vec<Vec<f64>>,
    omega: Vec<f64>,
    first_discarded: Option<f64>,
    /// The structure's M and C, M·φ_r and C·φ_r per mode, and Φᵀ·M·Φ, Φᵀ·C·Φ (row-major
    /// nm × nm, symmetrised).
    m: Csr,
    c: Csr,
    m_phi: Vec<Vec<f64>>,
    c_phi: Vec<Vec<f64>>,
    phi_m: Vec<f64>,
    phi_c: Vec<f64>,
    /// The factor of the structure's K for the static shapes (None without the static
    /// correction).
    k: Option<OwnedLdlt>,
    modal_damping: Option<Vec<f64>>,
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
        let times_phi = |a: &Csr| -> Vec<Vec<f64>> { phi.iter().map(|v| mul(a, v)).collect() };
        let project = |ap: &[Vec<f64>]| {
            let nm = phi.len();
            let mut r = vec![0.0; nm * nm];
            for i in 0..nm {
                for j in 0..=i {
                    let s = 0.5 * (dot(&phi[i], &ap[j]) + dot(&phi[j], &ap[i]));
                    r[i * nm + j] = s;
                    r[j * nm + i] = s;
                }
            }
            r
        };
        let (m_phi, c_phi) = (times_phi(&bare.m_beam), times_phi(&bare.c_beam));
        let k = match opts.static_correction {
            true => Some(OwnedLdlt::of(&bare.k_beam)?),
            false => None,
        };
        Ok(SharedBasis {
            dofs: bare.dofs.clone(),
            omega: kept.iter().map(|&r| modes.omega[r]).collect(),
            first_discarded: modes.omega.get(kept.len()).copied(),
            phi_m: project(&m_phi),
            phi_c: project(&c_phi),
            m_phi,
            c_phi,
            phi,
            m: bare.m_beam.clone(),
            c: bare.c_beam.clone(),
            k,
            modal_damping: opts.modal_damping.clone(),
        })
    }

    /// Retained modes.
    pub fn modes(&self) -> usize {
        self.phi.len()
    }

    /// The reduced system of a placement: `attached` holds the case's actuators and loads
    /// on the structure ([`System::assemble_attachments`]: the structure numbered as the
    /// bare one, the bodies after it, no structure matrices).
    pub fn reduce(&self, attached: &System) -> Result<Reduction> {
        let ns = self.dofs.n;
        if attached.dofs.nodes != self.dofs.nodes || attached.projection.is_some() {
            return Err(Error::Numerical(
                "the case's structure is not the one the study's shared reduction was built on".into(),
            ));
        }
        let n = attached.n();
        let bodies: Vec<usize> = attached.dofs.bodies.iter().flatten().copied().collect();
        let patterns = attachment_patterns(attached, ns);
        let Residual { vectors: psi, omega: residual_omega, dropped } = match &self.k {
            Some(k) if !patterns.is_empty() => {
                let shapes = patterns.iter().map(|b| static_shape(k, b, ns)).collect();
                residual_vectors(&self.m, &patterns, shapes, (&self.phi, Some(&self.m_phi)), &self.omega)?
            }
            _ => Residual { vectors: Vec::new(), omega: Vec::new(), dropped: 0 },
        };
        let (nm, np) = (self.phi.len(), psi.len());
        let nr = nm + np + bodies.len();
        let t = self.basis_rows(&psi, &bodies, n, nr);
        let basis = Basis { t: &t, n, nr };

        let m_beam = self.structure_block((&self.phi_m, &self.m_phi), &self.m, &psi, nr);
        let mut c_beam = self.structure_block((&self.phi_c, &self.c_phi), &self.c, &psi, nr);
        let k_diag: Vec<f64> = self.omega.iter().chain(&residual_omega).map(|w| w * w).collect();
        if let Some(ratios) = &self.modal_damping {
            // As in `modal_basis::reduce`: 2ζ_r·ω_r on the modal coordinates, the residual
            // vectors taking the next ratios at their pseudo-frequencies.
            for (r, &w) in self.omega.iter().chain(&residual_omega).enumerate() {
                c_beam[r * nr + r] += 2.0 * ratio_of(ratios, r) * w;
            }
        }
        let mut k_beam = vec![0.0; nr * nr];
        k_diag.iter().enumerate().for_each(|(r, &v)| k_beam[r * nr + r] = v);
        let [m, c, k] = [(&m_beam, &attached.m), (&c_beam, &attached.c), (&k_beam, &attached.k)].map(|(s, a)| {
            let mut r = basis.project_rows(a);
            r.iter_mut().zip(s).for_each(|(x, y)| *x += y);
            sparse_of_dense(&r, nr)
        });
        let [m_beam, c_beam, k_beam] = [&m_beam, &c_beam, &k_beam].map(|r| sparse_of_dense(r, nr));
        let system = reduced_system(attached, t, nr, [m, c, k, m_beam, c_beam, k_beam], nm + np);
        Ok(Reduction {
            system,
            mode_omega: self.omega.clone(),
            first_discarded_omega: self.first_discarded,
            residual_omega,
            dropped,
        })
    }

    /// T (row-major n × nr): the modes and residual vectors on the structure's rows, the
    /// identity on the bodies'.
    fn basis_rows(&self, psi: &[Vec<f64>], bodies: &[usize], n: usize, nr: usize) -> Vec<f64> {
        let mut t = vec![0.0; n * nr];
        for (c, v) in self.phi.iter().chain(psi).enumerate() {
            for (d, &x) in v.iter().enumerate() {
                t[d * nr + c] = x;
            }
        }
        let first_body = self.phi.len() + psi.len();
        for (k, &b) in bodies.iter().enumerate() {
            t[b * nr + first_body + k] = 1.0;
        }
        t
    }

    /// The structure's matrix `a` on the basis (dense nr × nr, zero on the bodies): the
    /// shared Φᵀ·A·Φ (`phi_a`), and the blocks of the residual vectors `psi` from A·Φ
    /// (`a_phi`) and A·ψ.
    fn structure_block(&self, (phi_a, a_phi): (&[f64], &[Vec<f64>]), a: &Csr, psi: &[Vec<f64>], nr: usize) -> Vec<f64> {
        let nm = self.phi.len();
        let mut r = vec![0.0; nr * nr];
        for i in 0..nm {
            r[i * nr..i * nr + nm].copy_from_slice(&phi_a[i * nm..(i + 1) * nm]);
        }
        let a_psi: Vec<Vec<f64>> = psi.iter().map(|v| mul(a, v)).collect();
        for (k, ak) in a_psi.iter().enumerate() {
            let col = nm + k;
            for (i, av) in a_phi.iter().enumerate() {
                let s = dot(av, &psi[k]);
                r[i * nr + col] = s;
                r[col * nr + i] = s;
            }
            for (l, al) in a_psi.iter().enumerate().take(k + 1) {
                let s = 0.5 * (dot(&psi[k], al) + dot(&psi[l], ak));
                r[col * nr + nm + l] = s;
                r[(nm + l) * nr + col] = s;
            }
        }
        r
    }
}

/// The distinct patterns along which the actuators and loads of `attached` act on the
/// structure (its DOFs below `ns`): each link's foot, each drive's and each load's
/// structure part, signed so that the first coefficient is positive.
fn attachment_patterns(attached: &System, ns: usize) -> Vec<Vec<(usize, f64)>> {
    let structure_part = |g: &[(usize, f64)]| {
        let mut b: Vec<(usize, f64)> = g.iter().copied().filter(|&(d, c)| d < ns && c != 0.0).collect();
        b.sort_by_key(|&(d, _)| d);
        if b.first().is_some_and(|&(_, c)| c < 0.0) {
            b.iter_mut().for_each(|x| x.1 = -x.1);
        }
        b
    };
    let mut patterns: Vec<Vec<(usize, f64)>> = Vec::new();
    let all = attached.links.iter().map(|l| &l.foot).chain(&attached.drives).chain(&attached.loads);
    for b in all.map(|g| structure_part(g)).filter(|b| !b.is_empty()) {
        if !patterns.contains(&b) {
            patterns.push(b);
        }
    }
    patterns
}

/// K⁻¹·b over the structure's `ns` DOFs.
fn static_shape(k: &OwnedLdlt, b: &[(usize, f64)], ns: usize) -> Vec<f64> {
    let mut x = vec![0.0; ns];
    for &(d, c) in b {
        x[d] += c;
    }
    k.solve_in_place(&mut x);
    debug_assert!(at(b, &x).is_finite());
    x
}
