//! Stored (kinetic plus strain) energies of the beam and of the whole system, as a transient
//! run evaluates them at every period boundary for its two energy balances.
//!
//! `Csr::bilinear` walks rows of five to seven entries whose varying lengths cost a branch
//! miss per row, about 2 ns per stored entry: 19 µs for the four forms of the paper's frame
//! case, ≈ 2 % of a run. Here each symmetric form is kept once, as its lower triangle in a
//! flat list (i ≥ j, weight ½ on the diagonal, 1 below it), so ½·xᵀ·A·x is one loop without
//! inner branches; and the system's energy is the beam's plus the actuators' part, the few
//! entries where M, K differ from M_beam, K_beam (link springs, feet and body masses).

use crate::assembly::System;
use crate::linalg::Csr;
use std::sync::Arc;

/// The strain energy ½·uᵀ·K·u formed without the assembled K, whose entries a smooth u
/// cancels by ~elements⁴ (fine meshes, `crate::assembly::rows`).
pub trait StrainEnergy: Send + Sync {
    /// (structure's, actuators' links') strain energy (J) at displacement u.
    fn structure_and_links(&self, u: &[f64]) -> (f64, f64);
}

/// ½·xᵀ·A·x of a symmetric A as Σ w·x_i·x_j over A's lower triangle. M and K are
/// symmetric by assembly (element matrices and link terms g·gᵀ), so the upper triangle
/// adds nothing the lower does not already count.
#[derive(Clone, Debug, Default)]
struct HalfForm {
    i: Vec<u32>,
    j: Vec<u32>,
    w: Vec<f64>,
}

impl HalfForm {
    /// From lower-triangle entries (i ≥ j, value a_ij), dropping exact zeros.
    fn from_lower(entries: impl Iterator<Item = (usize, usize, f64)>) -> Self {
        let mut f = HalfForm::default();
        for (i, j, a) in entries.filter(|e| e.2 != 0.0) {
            debug_assert!(i >= j);
            f.i.push(i as u32);
            f.j.push(j as u32);
            f.w.push(if i == j { 0.5 * a } else { a });
        }
        f
    }

    fn lower(a: &Csr) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        a.triplets().filter(|&(i, j, _)| i >= j)
    }

    /// ½·xᵀ·A·x (J when x is a velocity and A a mass matrix, or a displacement and A a
    /// stiffness). Four partial sums so that the adds do not form one dependent chain.
    fn eval(&self, x: &[f64]) -> f64 {
        let mut acc = [0.0; 4];
        let (ci, cj, cw) = (self.i.chunks_exact(4), self.j.chunks_exact(4), self.w.chunks_exact(4));
        let (ri, rj, rw) = (ci.remainder(), cj.remainder(), cw.remainder());
        for ((i, j), w) in ci.zip(cj).zip(cw) {
            for l in 0..4 {
                acc[l] += w[l] * x[i[l] as usize] * x[j[l] as usize];
            }
        }
        for ((&i, &j), &w) in ri.iter().zip(rj).zip(rw) {
            acc[0] += w * x[i as usize] * x[j as usize];
        }
        (acc[0] + acc[1]) + (acc[2] + acc[3])
    }
}

/// The beam's and the system's stored energy at a state (u, v), from the system's M, K and
/// the structure's own M_beam, K_beam. Built once per run.
#[derive(Clone)]
pub struct StoredEnergy {
    n: usize,
    m_beam: HalfForm,
    k_beam: HalfForm,
    /// M − M_beam and K − K_beam: the actuators' masses and link springs.
    m_rest: HalfForm,
    k_rest: HalfForm,
    /// The strain energies from element rows in place of `k_beam` and `k_rest`, when set.
    strain: Option<Arc<dyn StrainEnergy>>,
}

impl StoredEnergy {
    pub fn new(sys: &System) -> Self {
        assert!(sys.n() <= u32::MAX as usize, "{} DOFs do not fit the 32-bit indices", sys.n());
        // M − M_beam (K − K_beam): exactly zero where only the beam contributes, so only
        // the actuators' entries survive `from_lower`'s zero filter.
        let rest =
            |a: &Csr, beam: &Csr| HalfForm::from_lower(HalfForm::lower(&Csr::combine(&[(1.0, a), (-1.0, beam)])));
        StoredEnergy {
            n: sys.n(),
            m_beam: HalfForm::from_lower(HalfForm::lower(&sys.m_beam)),
            k_beam: HalfForm::from_lower(HalfForm::lower(&sys.k_beam)),
            m_rest: rest(&sys.m, &sys.m_beam),
            k_rest: rest(&sys.k, &sys.k_beam),
            strain: None,
        }
    }

    /// Takes the strain energies from `strain` rather than the assembled K.
    pub fn with_strain(mut self, strain: Option<Arc<dyn StrainEnergy>>) -> Self {
        self.strain = strain;
        self
    }

    /// (beam, system) stored energy (J) at displacement u and velocity v (system DOFs).
    pub fn beam_and_system(&self, u: &[f64], v: &[f64]) -> (f64, f64) {
        assert!(u.len() == self.n && v.len() == self.n, "state of {} DOFs for a system of {}", u.len(), self.n);
        let (k_beam, k_rest) = match &self.strain {
            Some(s) => s.structure_and_links(u),
            None => (self.k_beam.eval(u), self.k_rest.eval(u)),
        };
        let beam = self.m_beam.eval(v) + k_beam;
        (beam, beam + (self.m_rest.eval(v) + k_rest))
    }

    /// Entries held for the actuators' part (tests check it stays small).
    pub fn actuator_entries(&self) -> usize {
        self.m_rest.w.len() + self.k_rest.w.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::plan::calibrated_model;
    use crate::case::LoadedCase;
    use std::path::PathBuf;

    fn system(text: &str) -> System {
        let cases = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases");
        let model = calibrated_model(&LoadedCase::from_str(text, "e.toml", cases).unwrap()).unwrap();
        System::assemble(&model).unwrap()
    }

    /// Against the plain quadratic forms through the CSR matrices, at an arbitrary state of
    /// a system with both actuator types (bodies, links, feet masses).
    #[test]
    fn matches_the_csr_quadratic_forms() {
        let sys = system(
            "[beam.mesh]\nelements = 40\n\
             [[actuator]]\ntype = \"frame\"\nx_e = 0.2\n[actuator.voltage]\nkind = \"sine\"\namplitude = 1.0\nfrequency = 60.0\n\
             [[actuator]]\ntype = \"inertial\"\nx_e = 0.5\n[actuator.voltage]\nkind = \"sine\"\namplitude = 1.0\nfrequency = 60.0\n",
        );
        let n = sys.n();
        let u: Vec<f64> = (0..n).map(|i| 1e-4 * (0.37 * i as f64).sin()).collect();
        let v: Vec<f64> = (0..n).map(|i| 1e-2 * (0.91 * i as f64 + 0.3).cos()).collect();
        let e = StoredEnergy::new(&sys);
        let (eb, es) = e.beam_and_system(&u, &v);
        let want_b = 0.5 * sys.m_beam.bilinear(&v, &v) + 0.5 * sys.k_beam.bilinear(&u, &u);
        let want_s = 0.5 * sys.m.bilinear(&v, &v) + 0.5 * sys.k.bilinear(&u, &u);
        assert!((eb - want_b).abs() <= 1e-13 * want_b.abs(), "{eb} vs {want_b}");
        assert!((es - want_s).abs() <= 1e-13 * want_s.abs(), "{es} vs {want_s}");
        assert!(es != eb, "the actuators store energy too");
        // The actuators' part is a handful of entries, not a copy of the beam.
        assert!(e.actuator_entries() > 0 && e.actuator_entries() < 40, "{}", e.actuator_entries());
    }

    /// Without actuators the system's energy is the beam's, and both match the CSR forms.
    #[test]
    fn a_bare_beam_has_no_actuator_part() {
        let sys = system("[beam.mesh]\nelements = 30\n");
        let e = StoredEnergy::new(&sys);
        assert_eq!(e.actuator_entries(), 0);
        let n = sys.n();
        let u: Vec<f64> = (0..n).map(|i| (i as f64).sqrt() * 1e-5).collect();
        let v: Vec<f64> = (0..n).map(|i| 1.0 / (1.0 + i as f64)).collect();
        let (eb, es) = e.beam_and_system(&u, &v);
        let want = 0.5 * sys.m_beam.bilinear(&v, &v) + 0.5 * sys.k_beam.bilinear(&u, &u);
        assert_eq!(eb, es);
        assert!((eb - want).abs() <= 1e-13 * want, "{eb} vs {want}");
    }
}
