//! The dynamic stiffness applied from the beam's curvature rows, never from assembled K.
//!
//! The assembled stiffness's entries are ~EI/h³, and a smooth response cancels them by
//! ~elements⁴: rounding those entries alone (let alone a product K·x with them) loses
//! ε·elements⁴ of a smooth K·x. Here the beam's part is applied as Gᵀ(G·x), G holding the
//! elements' curvature rows ([`element_stiffness_rows`]) and √k on each support spring's
//! DOF (so K_el = GᵀG exactly as [`super::system::structure_stiffness_root`] builds it);
//! G·x cancels only by ~elements², and so does the product. Everything else (masses,
//! grounded spring–dampers, actuator links and bodies) is applied from its own matrices,
//! built from the same triplets [`System::assemble`] sums, never split off the sum.
//!
//! The product is the residual of the harmonic and steady-state solves' refinement
//! ([`crate::analysis::roundoff`]), for A = K + c_m·M + c_c·C + i·η·K_beam (c_m = −ω²,
//! c_c = iω for the continuous system), with C = a₀·M_el + a₁·K_el + C_grounded + C_links.

use super::system::{actuator_matrices, feet_attachments, structure_matrices, System};
use super::Model;
use crate::actuator::Component;
use crate::beam::{element_stiffness_rows, SupportKind};
use crate::error::Result;
use crate::linalg::Csr;
use num_complex::Complex64;

/// One row of G: up to four (DOF, value) entries.
#[derive(Clone, Copy, Debug)]
struct Row {
    dofs: [usize; 4],
    values: [f64; 4],
    len: usize,
}

/// A model's dynamic stiffness as products, split so that no beam stiffness is assembled.
#[derive(Clone, Debug)]
pub struct StiffnessRows {
    n: usize,
    /// G: elements' curvature rows, then √k of each support spring (K_el = GᵀG).
    rows: Vec<Row>,
    /// Grounded spring–dampers (DOF, k, c): in K_beam (and its loss) but not in K_el.
    grounded: Vec<(usize, f64, f64)>,
    /// Element and point masses (M_el, which a₀ multiplies), and the actuators' masses.
    m_el: Csr,
    m_act: Csr,
    /// The actuators' links: stiffness and dampers.
    k_act: Csr,
    c_act: Csr,
    a0: f64,
    a1: f64,
    eta: f64,
}

impl StiffnessRows {
    /// The split of a full (unreduced) system of `model`; None without a beam or for a
    /// reduced system (whose coordinates are not the element DOFs).
    pub fn of(model: &Model, sys: &System) -> Result<Option<Self>> {
        let Some(beam) = model.beam() else { return Ok(None) };
        let structure = model.structure.as_ref();
        if sys.projection.is_some() {
            return Ok(None);
        }
        let dofs = &sys.dofs;
        let mut rows = Vec::with_capacity(2 * beam.mesh.elements.len() + beam.supports.len());
        for e in &beam.mesh.elements {
            let d = dofs.element_dofs(&e.nodes);
            for g in element_stiffness_rows(e.ei, e.length) {
                let mut row = Row { dofs: [0; 4], values: [0.0; 4], len: 0 };
                for (dof, v) in d.iter().zip(g) {
                    if let Some(i) = dof {
                        row.dofs[row.len] = *i;
                        row.values[row.len] = v;
                        row.len += 1;
                    }
                }
                rows.push(row);
            }
        }
        for s in &beam.supports {
            if let SupportKind::Spring { k_w, k_theta } = s.kind {
                for (dof, k) in [(dofs.w(s.node), k_w), (dofs.node_dof(s.node, 1), k_theta)] {
                    if let Some(i) = dof {
                        // K_el holds k itself; k·x = √k·(√k·x) keeps the row form (k ≥ 0
                        // is checked where the case is read).
                        rows.push(Row { dofs: [i, 0, 0, 0], values: [k.max(0.0).sqrt(), 0.0, 0.0, 0.0], len: 1 });
                    }
                }
            }
        }
        let grounded =
            beam.springs.iter().filter_map(|s| dofs.w(s.node).map(|i| (i, s.stiffness, s.damping))).collect();
        let [m_el, _, _] = structure_matrices(structure, dofs, Default::default());
        let comps: Vec<Component> = model.actuators.iter().map(|a| a.component()).collect();
        let feet = feet_attachments(&comps, structure)?;
        let act = actuator_matrices(&comps, &feet, structure, dofs);
        let n = dofs.n;
        let rayleigh = model.rayleigh();
        Ok(Some(StiffnessRows {
            n,
            rows,
            grounded,
            m_el,
            m_act: Csr::from_triplets(n, &act.m),
            k_act: Csr::from_triplets(n, &act.k),
            c_act: Csr::from_triplets(n, &act.c),
            a0: rayleigh.a0,
            a1: rayleigh.a1,
            eta: model.loss_factor(),
        }))
    }

    pub fn dim(&self) -> usize {
        self.n
    }

    /// The coefficients of A = k_el·K_el + m_el·M_el + c_m·M_act + K_act + c_c·C_act plus
    /// the grounded springs' k_g·k + c_c·c: k_el = 1 + a₁·c_c + iη, m_el = c_m + a₀·c_c.
    fn coefficients(&self, c_m: Complex64, c_c: Complex64) -> (Complex64, Complex64, Complex64) {
        let i_eta = Complex64::new(0.0, self.eta);
        (1.0 + c_c * self.a1 + i_eta, c_m + c_c * self.a0, 1.0 + i_eta)
    }

    /// The power (W) the structure dissipates in harmonic motion `q` at ω (rad/s), as
    /// [`crate::power::point::beam_dissipation`] states it — ½ω²·Qᴴ·C_beam·Q plus
    /// ½ω·η·Qᴴ·K_beam·Q — with Qᴴ·K_el·Q = |G·Q|² from the rows.
    pub fn dissipation(&self, q: &[Complex64], omega: f64) -> f64 {
        let strain: f64 = self
            .rows
            .iter()
            .map(|r| {
                r.dofs[..r.len].iter().zip(&r.values[..r.len]).map(|(&i, &v)| q[i] * v).sum::<Complex64>().norm_sqr()
            })
            .sum();
        let (k_g, c_g) = self
            .grounded
            .iter()
            .fold((0.0, 0.0), |(k, c), &(i, kg, cg)| (k + kg * q[i].norm_sqr(), c + cg * q[i].norm_sqr()));
        let viscous = self.a0 * self.m_el.hermitian_form(q) + self.a1 * strain + c_g;
        0.5 * omega * omega * viscous + 0.5 * omega * self.eta * (strain + k_g)
    }

    /// y = A·x for A = K + c_m·M + c_c·C + i·η·K_beam.
    pub fn apply(&self, c_m: Complex64, c_c: Complex64, x: &[Complex64], y: &mut [Complex64]) {
        let (k_el, m_el, k_g) = self.coefficients(c_m, c_c);
        y.iter_mut().for_each(|v| *v = Complex64::default());
        for r in &self.rows {
            let (d, g) = (&r.dofs[..r.len], &r.values[..r.len]);
            let s: Complex64 = d.iter().zip(g).map(|(&i, &v)| x[i] * v).sum::<Complex64>() * k_el;
            for (&i, &v) in d.iter().zip(g) {
                y[i] += s * v;
            }
        }
        for &(i, k, c) in &self.grounded {
            y[i] += x[i] * (k_g * k + c_c * c);
        }
        for (a, coef) in
            [(&self.m_el, m_el), (&self.m_act, c_m), (&self.k_act, Complex64::new(1.0, 0.0)), (&self.c_act, c_c)]
        {
            if a.nnz() > 0 && coef != Complex64::default() {
                a.mul_vec_add(coef, x, y);
            }
        }
    }

    /// The rounding of [`StiffnessRows::apply`] at `x`, as vectors whose images under A⁻¹
    /// stand for its effect on a solution (γ = 8ε: each entry is a sum of at most eight
    /// products):
    /// * the rounding of the products A applies last, up to γ·(|Gᵀ|·|G·x| + |A_rest|·|x|)
    ///   per DOF;
    /// * the rounding of G·x, up to γ·|G|·|x| per row, which reaches the residual only
    ///   through Gᵀ: Gᵀ(σ·γ|k_el||G||x|). Taking magnitudes before Gᵀ would forfeit the
    ///   cancellation Gᵀ does and overstate it by ~elements².
    ///
    /// Each carries independent pseudo-random signs σ = ±1: roundings of separate sums are
    /// independent and add up through A⁻¹ as a random walk, not all in the one sign pattern
    /// the smooth response amplifies most (which would overstate them by ~√elements); the
    /// caller's margin covers the walk's spread.
    pub fn rounding(&self, c_m: Complex64, c_c: Complex64, x: &[Complex64]) -> [Vec<Complex64>; 2] {
        let (k_el, m_el, k_g) = self.coefficients(c_m, c_c);
        let gamma = 8.0 * f64::EPSILON;
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut sign = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            if seed >> 63 == 0 {
                1.0
            } else {
                -1.0
            }
        };
        // Moduli taken once per entry or row (|c·v| = |c|·|v| for real v), as √(re² + im²):
        // this runs beside every refined solve, and `norm` is a hypot (whose guard against
        // overflow displacements and forces of a structure never need).
        let modulus = |z: Complex64| z.norm_sqr().sqrt();
        let ax: Vec<f64> = x.iter().map(|&z| modulus(z)).collect();
        let k_abs = k_el.norm();
        // The first part's magnitudes, signed in place at the end.
        let mut out = vec![Complex64::default(); self.n];
        let mut rows = vec![Complex64::default(); self.n];
        for r in &self.rows {
            let (d, g) = (&r.dofs[..r.len], &r.values[..r.len]);
            let y: Complex64 = d.iter().zip(g).map(|(&i, &v)| x[i] * v).sum::<Complex64>() * k_el;
            let y_abs = modulus(y);
            let dy = sign() * gamma * k_abs * d.iter().zip(g).map(|(&i, &v)| ax[i] * v.abs()).sum::<f64>();
            for (&i, &v) in d.iter().zip(g) {
                out[i].re += y_abs * v.abs();
                rows[i] += dy * v;
            }
        }
        for &(i, k, c) in &self.grounded {
            out[i].re += ax[i] * (k_g * k + c_c * c).norm();
        }
        for (a, coef) in
            [(&self.m_el, m_el), (&self.m_act, c_m), (&self.k_act, Complex64::new(1.0, 0.0)), (&self.c_act, c_c)]
        {
            let c_abs = coef.norm();
            for (i, j, v) in a.triplets() {
                out[i].re += c_abs * v.abs() * ax[j];
            }
        }
        out.iter_mut().for_each(|v| v.re *= sign() * gamma);
        [out, rows]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::{GroundedSpring, Material, Mesh, PointMass, Section, Support};

    /// The split applies what the assembled matrices hold, up to their round-off.
    #[test]
    fn the_split_applies_the_assembled_dynamic_stiffness() {
        let section = Section { width: 0.05, thickness: 0.005 };
        let material = Material { youngs_modulus: 210e9, density: 7850.0 };
        let mesh = Mesh::uniform(0.73, 9, &[], section, material);
        let supports = vec![
            Support { node: 0, kind: SupportKind::Clamped },
            Support { node: 9, kind: SupportKind::Spring { k_w: 3.0e5, k_theta: 40.0 } },
        ];
        let mut beam = crate::beam::Beam::new(mesh, supports);
        beam.springs.push(GroundedSpring { node: 4, stiffness: 1.2e6, damping: 3.0 });
        beam.point_masses.push(PointMass { node: 3, mass: 0.3, rotary_inertia: 1e-4 });
        for damping in [
            crate::assembly::Damping::Rayleigh(crate::assembly::Rayleigh { a0: 5.0, a1: 1e-5 }),
            crate::assembly::Damping::Hysteretic { eta: 0.02 },
        ] {
            let mut model = Model::bare(crate::structure::Structure::Beam(beam.clone()));
            model.damping = damping;
            let sys = System::assemble(&model).unwrap();
            let split = StiffnessRows::of(&model, &sys).unwrap().unwrap();
            let n = sys.n();
            let x: Vec<Complex64> = (0..n).map(|i| Complex64::new((i as f64).sin(), (0.3 * i as f64).cos())).collect();
            let w = 2.0 * std::f64::consts::PI * 45.0;
            let (c_m, c_c) = (Complex64::new(-w * w, 0.0), Complex64::new(0.0, w));
            let mut y = vec![Complex64::default(); n];
            split.apply(c_m, c_c, &x, &mut y);
            let (mut kx, mut mx, mut cx, mut lx) = (y.clone(), y.clone(), y.clone(), vec![Complex64::default(); n]);
            sys.k.mul_vec(&x, &mut kx);
            sys.m.mul_vec(&x, &mut mx);
            sys.c.mul_vec(&x, &mut cx);
            if let Some(kl) = &sys.k_loss {
                kl.mul_vec(&x, &mut lx);
            }
            let [direct, rows] = split.rounding(c_m, c_c, &x);
            for i in 0..n {
                let bound = direct[i].norm() + rows[i].norm();
                let a = kx[i] + c_m * mx[i] + c_c * cx[i] + Complex64::new(0.0, 1.0) * lx[i];
                let scale = (sys.k.get(i, i) + w * w * sys.m.get(i, i)).abs() * 10.0;
                assert!((a - y[i]).norm() <= 1e-13 * scale, "row {i}: {a} vs {}", y[i]);
                assert!(bound < 1e-12 * scale);
            }
        }
    }
}
