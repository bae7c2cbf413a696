//! The dynamic stiffness applied from the beam's curvature rows, never from assembled K.
//!
//! The assembled stiffness's entries are ~EI/h³, and a smooth response cancels them by
//! ~elements⁴: rounding those entries alone (let alone a product K·x with them) loses
//! ε·elements⁴ of a smooth K·x. Here the beam's part is applied as Gᵀ(G·x), G holding the
//! elements' curvature rows ([`element_stiffness_rows`]) and √k on each support spring's
//! DOF (so K_el = GᵀG exactly as [`super::system::structure_stiffness_root`] builds it);
//! G·x cancels only by ~elements², and so does the product. The grounded spring–dampers
//! and the actuators' links are applied the same way, as rank-one ties k·g·(gᵀ·x) on their
//! stretch g (a link's stretch is small beside its ends' motion for a stiff stack). The
//! masses are applied from their own matrices, built from the same triplets
//! [`System::assemble`] sums, never split off the sum.
//!
//! The product is the residual of the harmonic and steady-state solves' refinement
//! ([`crate::analysis::roundoff`]), for A = K + c_m·M + c_c·C + i·η·K_beam (c_m = −ω²,
//! c_c = iω for the continuous system), with C = a₀·M_el + a₁·K_el + C_grounded + C_links.

use super::system::{actuator_matrices, feet_attachments, System};
use super::Model;
use crate::actuator::Component;
use crate::beam::{element_stiffness_rows, element_stiffness_rows_wide, SupportKind};
use crate::error::{Error, Result};
use crate::linalg::{Csr, PackedRows};
use crate::simd::twofold::Twofold;
use crate::simd::{self, Builds};
use num_complex::Complex64;
use twofloat::TwoFloat;

/// One row of G: up to four (DOF, value) entries, in doubles and to twice their precision;
/// the `len..4` unused ones are 0 at DOF 0.
#[derive(Clone, Copy, Debug)]
struct Row {
    dofs: [usize; 4],
    values: [f64; 4],
    wide: [Twofold; 4],
    len: usize,
}

fn twofold(v: TwoFloat) -> Twofold {
    Twofold { hi: v.hi(), lo: v.lo() }
}

/// The first-order relative rounding of a stored entry of the mass matrices and of their
/// coefficient m_el = c_m + a₀·c_c: each is formed by at most six roundings of u = ε/2 (a
/// consistent-mass entry: ρA·l/420, ·156 or ·l², and the sum of two elements).
const COEFFICIENT_ROUNDING: f64 = 3.0 * f64::EPSILON;

/// The relative rounding of a compensated sum of at most eight products of twofold numbers
/// (γ₈² for the sum, and the lo·lo terms left out, ≤ 2u² a product), u = ε/2.
const WIDE_ROUNDING: f64 = 20.0 * f64::EPSILON * f64::EPSILON;

/// The relative rounding of a sum of at most eight products in doubles (γ₈ ≤ 8u, taken as
/// 8ε with the coefficient's own product).
const REST_ROUNDING: f64 = 8.0 * f64::EPSILON;

/// A rank-one spring–damper (k + c_c·c, and iη·k where it is part of the beam's loss)·g·gᵀ:
/// g the stretch of an actuator's link over the DOFs, or a grounded spring's one DOF.
#[derive(Clone, Debug)]
struct Tie {
    g: Vec<(usize, f64)>,
    k: f64,
    c: f64,
    lossy: bool,
}

impl Tie {
    fn coefficient(&self, c_c: Complex64, eta: f64) -> Complex64 {
        let loss = if self.lossy { eta * self.k } else { 0.0 };
        Complex64::new(self.k, loss) + c_c * self.c
    }

    /// [`Tie::coefficient`] to twice the working precision: its real and imaginary parts.
    fn twofold_coefficient(&self, c_c: Complex64, eta: f64) -> [Twofold; 2] {
        let mut re = Twofold::product(c_c.re, self.c);
        re.add(self.k);
        let mut im = Twofold::product(c_c.im, self.c);
        if self.lossy {
            im.add_twofold_product::<false>(Twofold::of(eta), Twofold::of(self.k));
        }
        [re.normalised(), im.normalised()]
    }
}

/// A model's dynamic stiffness as products, split so that no beam stiffness is assembled.
#[derive(Clone, Debug)]
pub struct StiffnessRows {
    n: usize,
    /// G: elements' curvature rows, then √k of each support spring (K_el = GᵀG).
    rows: Vec<Row>,
    /// G's rows in doubles alone, packed (48 bytes a row, not a [`Row`]'s 136): what the
    /// transient step's product streams every step.
    packed: Vec<([u32; 4], [f64; 4])>,
    /// Grounded spring–dampers (DOF, k, c): in K_beam (and its loss) but not in K_el.
    grounded: Vec<(usize, f64, f64)>,
    /// The grounded spring–dampers, then the actuators' links, as ties.
    ties: Vec<Tie>,
    /// Element and point masses (M_el, which a₀ multiplies), and the actuators' masses.
    m_el: Csr,
    m_act: Csr,
    /// The same two, packed for the products every residual and GMRES iteration takes.
    masses: [PackedRows; 2],
    a0: f64,
    a1: f64,
    eta: f64,
}

impl StiffnessRows {
    /// The split of a full (unreduced) system of `model` ([`System::assemble`]: its
    /// structure's mass is taken from it); None without a beam or for a reduced system
    /// (whose coordinates are not the element DOFs).
    pub fn of(model: &Model, sys: &System) -> Result<Option<Self>> {
        let Some(beam) = model.beam() else { return Ok(None) };
        let structure = model.structure.as_ref();
        if sys.projection.is_some() {
            return Ok(None);
        }
        if sys.m_beam.nnz() == 0 {
            return Err(Error::Numerical(
                "element rows need the system assembled with its structure, not the actuators alone".into(),
            ));
        }
        let dofs = &sys.dofs;
        let mut rows = Vec::with_capacity(2 * beam.mesh.elements.len() + beam.supports.len());
        for e in &beam.mesh.elements {
            let d = dofs.element_dofs(&e.nodes);
            let wide = element_stiffness_rows_wide(e.ei, e.length);
            for (g, gw) in element_stiffness_rows(e.ei, e.length).into_iter().zip(wide) {
                let mut row = Row { dofs: [0; 4], values: [0.0; 4], wide: Default::default(), len: 0 };
                for ((dof, v), vw) in d.iter().zip(g).zip(gw) {
                    if let Some(i) = dof {
                        row.dofs[row.len] = *i;
                        row.values[row.len] = v;
                        row.wide[row.len] = twofold(vw);
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
                        let root = twofold(TwoFloat::from(k.max(0.0)).sqrt());
                        let wide = [root, Twofold::default(), Twofold::default(), Twofold::default()];
                        rows.push(Row { dofs: [i, 0, 0, 0], values: [k.max(0.0).sqrt(), 0.0, 0.0, 0.0], wide, len: 1 });
                    }
                }
            }
        }
        let grounded: Vec<(usize, f64, f64)> =
            beam.springs.iter().filter_map(|s| dofs.w(s.node).map(|i| (i, s.stiffness, s.damping))).collect();
        // The structure's own mass (elements and point inertia), as the full system holds it.
        let m_el = sys.m_beam.clone();
        let comps: Vec<Component> = model.actuators.iter().map(|a| a.component()).collect();
        let feet = feet_attachments(&comps, structure)?;
        let act = actuator_matrices(&comps, &feet, structure, dofs);
        let ties = grounded
            .iter()
            .map(|&(i, k, c)| Tie { g: vec![(i, 1.0)], k, c, lossy: true })
            .chain(act.links.iter().map(|l| Tie { g: l.stretch.clone(), k: l.k, c: l.c, lossy: false }))
            .collect();
        let n = dofs.n;
        let rayleigh = model.rayleigh();
        let packed = rows.iter().map(|r| (r.dofs.map(|d| d as u32), r.values)).collect();
        let m_act = Csr::from_triplets(n, &act.m);
        Ok(Some(StiffnessRows {
            n,
            rows,
            packed,
            grounded,
            ties,
            masses: [PackedRows::of(&m_el), PackedRows::of(&m_act)],
            m_el,
            m_act,
            a0: rayleigh.a0,
            a1: rayleigh.a1,
            eta: model.loss_factor(),
        }))
    }

    pub fn dim(&self) -> usize {
        self.n
    }

    /// The coefficients of A = k_el·K_el + m_el·M_el + c_m·M_act plus the ties:
    /// k_el = 1 + a₁·c_c + iη, m_el = c_m + a₀·c_c.
    fn coefficients(&self, c_m: Complex64, c_c: Complex64) -> (Complex64, Complex64) {
        let i_eta = Complex64::new(0.0, self.eta);
        (1.0 + c_c * self.a1 + i_eta, c_m + c_c * self.a0)
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
        let (k_el, _) = self.coefficients(c_m, c_c);
        y.iter_mut().for_each(|v| *v = Complex64::default());
        for (d, g) in &self.packed {
            // Every row as four entries (the unused ones 0 at DOF 0), so the loops unroll.
            let s = (0..4).map(|e| x[d[e] as usize] * g[e]).sum::<Complex64>() * k_el;
            for e in 0..4 {
                y[d[e] as usize] += s * g[e];
            }
        }
        for t in &self.ties {
            let s = t.g.iter().map(|&(i, v)| x[i] * v).sum::<Complex64>() * t.coefficient(c_c, self.eta);
            t.g.iter().for_each(|&(i, v)| y[i] += s * v);
        }
        self.apply_masses(c_m, c_c, x, y);
    }

    /// y += the masses' product: c_m·M + c_c·a₀·M_el.
    fn apply_masses(&self, c_m: Complex64, c_c: Complex64, x: &[Complex64], y: &mut [Complex64]) {
        let (_, m_el) = self.coefficients(c_m, c_c);
        let [el, act] = &self.masses;
        for (a, coef) in [(el, m_el), (act, c_m)] {
            if !a.is_empty() && coef != Complex64::default() {
                a.mul_vec_add(coef, x, y);
            }
        }
    }

    /// z ← z − K·x for real x: the stiffness alone (c_m = c_c = 0, no loss), in doubles,
    /// the beam's part as Gᵀ(G·x), so a smooth x cancels by ~elements², not ~elements⁴ as
    /// with the assembled K.
    pub fn subtract_stiffness(&self, x: &[f64], z: &mut [f64]) {
        for (d, g) in &self.packed {
            // Every row as four entries (the unused ones 0 at DOF 0), so the loops unroll.
            let s = (0..4).map(|e| x[d[e] as usize] * g[e]).sum::<f64>();
            for e in 0..4 {
                z[d[e] as usize] -= s * g[e];
            }
        }
        for t in &self.ties {
            let s = t.k * t.g.iter().map(|&(i, v)| x[i] * v).sum::<f64>();
            t.g.iter().for_each(|&(i, v)| z[i] -= s * v);
        }
    }

    /// The strain energies ½·xᵀ·K·x of the structure (its elements, supports and grounded
    /// springs) and of the actuators' links, as sums of squares: (G·x)² per row and
    /// k·(gᵀ·x)² per tie, which keep a smooth x's cancellation to ~elements².
    pub fn strain_energies(&self, x: &[f64]) -> (f64, f64) {
        let row = |(d, g): &([u32; 4], [f64; 4])| (0..4).map(|e| x[d[e] as usize] * g[e]).sum::<f64>().powi(2);
        let tie = |t: &Tie| t.k * t.g.iter().map(|&(i, v)| x[i] * v).sum::<f64>().powi(2);
        let (grounded, links) = self.ties.split_at(self.grounded.len());
        let structure = self.packed.iter().map(row).sum::<f64>() + grounded.iter().map(tie).sum::<f64>();
        (0.5 * structure, 0.5 * links.iter().map(tie).sum::<f64>())
    }

    /// r = b − A·x with the beam's part summed to twice the working precision
    /// ([`Twofold`]), rounded to doubles at the end: the refinement's residual. A smooth
    /// response's b and A·x agree to ~elements⁴·ε, and in doubles the residual would be
    /// mostly its own rounding; here the beam's part is exact to ~u² of its terms for the
    /// model's data as given (EI, l and k of each element and spring, a₁, η and the lane's
    /// c_c; G's rows to twice the precision, [`element_stiffness_rows_wide`]), and so are
    /// the ties. The masses are applied in doubles: their products cancel little for a
    /// smooth response, and [`Self::rounding`] carries their rounding.
    pub fn residual(&self, c_m: Complex64, c_c: Complex64, b: &[Complex64], x: &[Complex64], r: &mut [Complex64]) {
        self.residual_in(true, c_m, c_c, b, x, r);
    }

    /// [`Self::residual`] in the FMA build where `fma` asks for it and the processor has one
    /// (the same bits either way).
    fn residual_in(
        &self,
        fma: bool,
        c_m: Complex64,
        c_c: Complex64,
        b: &[Complex64],
        x: &[Complex64],
        r: &mut [Complex64],
    ) {
        r.iter_mut().for_each(|v| *v = Complex64::default());
        self.apply_masses(c_m, c_c, x, r);
        let ties: Vec<[Twofold; 2]> = self.ties.iter().map(|t| t.twofold_coefficient(c_c, self.eta)).collect();
        let (a1c, etc) = (Twofold::product(self.a1, c_c.re), Twofold::product(self.a1, c_c.im));
        let mut k_el = [a1c, etc];
        k_el[0].add(1.0);
        k_el[1].add(self.eta);
        let ties = (&self.ties[..], &ties[..]);
        let mut kernel = Residual { rows: &self.rows, k_el: k_el.map(Twofold::normalised), ties, b, x, r };
        simd::dispatch(fma, &mut kernel, ());
    }

    /// What can still separate [`Self::residual`] at `x` from the exact model's, as vectors
    /// whose images under A⁻¹ stand for its effect on a solution:
    /// * the stored entries of the mass matrices, each within [`COEFFICIENT_ROUNDING`] of
    ///   the exact model's, and their products in doubles, within [`REST_ROUNDING`]: those
    ///   times |coefficient|·|M|·|x| per DOF (a mass matrix's rows cancel little for a
    ///   smooth response, so this is ~ε of the inertia forces, a perturbation of the
    ///   density, not the mesh-amplified rounding of the stiffness);
    /// * the compensated sums' own rounding (G's rows and the ties), ≤ [`WIDE_ROUNDING`] of
    ///   each sum's terms: of the products applied last, |Gᵀ|·|k_el·G·x| per DOF, and of
    ///   G·x, |G|·|x| per row, which reaches the residual only through Gᵀ: Gᵀ(σ·|k_el||G||x|)
    ///   (taking magnitudes before Gᵀ would forfeit the cancellation Gᵀ does).
    ///
    /// Each carries independent pseudo-random signs σ = ±1: roundings of separate sums and
    /// entries are independent and add up through A⁻¹ as a random walk, not all in the one
    /// sign pattern the smooth response amplifies most; the caller's margin covers the
    /// walk's spread. The residual's last rounding to doubles, u·|r|, moves the correction
    /// by u of itself.
    pub fn rounding(&self, c_m: Complex64, c_c: Complex64, x: &[Complex64]) -> [Vec<Complex64>; 2] {
        let (k_el, m_el) = self.coefficients(c_m, c_c);
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
        // The stiffness's and the rest's magnitudes per DOF, signed in place at the end.
        let (mut stiff, mut rest) = (vec![0.0; self.n], vec![0.0; self.n]);
        let mut rows = vec![Complex64::default(); self.n];
        for r in &self.rows {
            let (d, g) = (&r.dofs[..r.len], &r.values[..r.len]);
            let y: Complex64 = d.iter().zip(g).map(|(&i, &v)| x[i] * v).sum::<Complex64>() * k_el;
            let y_abs = modulus(y);
            let dy = sign() * WIDE_ROUNDING * k_abs * d.iter().zip(g).map(|(&i, &v)| ax[i] * v.abs()).sum::<f64>();
            for (&i, &v) in d.iter().zip(g) {
                stiff[i] += y_abs * v.abs();
                rows[i] += dy * v;
            }
        }
        for t in &self.ties {
            let (c, y) = (t.coefficient(c_c, self.eta), t.g.iter().map(|&(i, v)| x[i] * v).sum::<Complex64>());
            let y_abs = modulus(c * y);
            let dy = sign() * WIDE_ROUNDING * c.norm() * t.g.iter().map(|&(i, v)| ax[i] * v.abs()).sum::<f64>();
            for &(i, v) in &t.g {
                stiff[i] += y_abs * v.abs();
                rows[i] += dy * v;
            }
        }
        for (a, coef) in [(&self.m_el, m_el), (&self.m_act, c_m)] {
            let c_abs = coef.norm();
            for (i, j, v) in a.triplets() {
                rest[i] += c_abs * v.abs() * ax[j];
            }
        }
        let out = stiff
            .iter()
            .zip(&rest)
            .map(|(s, r)| {
                Complex64::new(sign() * (WIDE_ROUNDING * s + (REST_ROUNDING + COEFFICIENT_ROUNDING) * r), 0.0)
            })
            .collect();
        [out, rows]
    }
}

/// The beam's part of the residual, r ← b − r − k_el·Gᵀ(G·x) with r holding the rest's
/// product on entry, compensated throughout; in both of [`simd::dispatch`]'s builds (the
/// same bits: every product's error is exact either way).
struct Residual<'a> {
    rows: &'a [Row],
    /// k_el's real and imaginary parts.
    k_el: [Twofold; 2],
    /// The ties and their coefficients' real and imaginary parts.
    ties: (&'a [Tie], &'a [[Twofold; 2]]),
    b: &'a [Complex64],
    x: &'a [Complex64],
    r: &'a mut [Complex64],
}

impl Builds<()> for Residual<'_> {
    type Out = ();
    #[inline(always)]
    fn run<const FMA: bool>(&mut self, _: ()) {
        let x = self.x;
        let start = |b: f64, rest: f64| {
            let mut t = Twofold::of(b);
            t.add(-rest);
            t
        };
        let mut re: Vec<Twofold> = self.b.iter().zip(self.r.iter()).map(|(b, y)| start(b.re, y.re)).collect();
        let mut im: Vec<Twofold> = self.b.iter().zip(self.r.iter()).map(|(b, y)| start(b.im, y.im)).collect();
        for row in self.rows {
            let entries = row.dofs[..row.len].iter().copied().zip(row.wide[..row.len].iter().copied());
            tie::<FMA>(entries, self.k_el, x, (&mut re, &mut im));
        }
        for (t, &c) in self.ties.0.iter().zip(self.ties.1) {
            tie::<FMA>(t.g.iter().map(|&(i, v)| (i, Twofold::of(v))), c, x, (&mut re, &mut im));
        }
        for ((r, re), im) in self.r.iter_mut().zip(&re).zip(&im) {
            *r = Complex64::new(re.value(), im.value());
        }
    }
}

/// (re, im) −= g·k·(gᵀ·x) for one row g (DOF, value) and coefficient k = [re, im],
/// compensated throughout.
#[inline(always)]
fn tie<const FMA: bool>(
    g: impl Iterator<Item = (usize, Twofold)> + Clone,
    [kr, ki]: [Twofold; 2],
    x: &[Complex64],
    (re, im): (&mut [Twofold], &mut [Twofold]),
) {
    let (mut s_re, mut s_im) = (Twofold::default(), Twofold::default());
    for (i, v) in g.clone() {
        s_re.add_twofold_product::<FMA>(v, Twofold::of(x[i].re));
        s_im.add_twofold_product::<FMA>(v, Twofold::of(x[i].im));
    }
    let (s_re, s_im) = (s_re.normalised(), s_im.normalised());
    let (mut t_re, mut t_im) = (Twofold::default(), Twofold::default());
    t_re.add_twofold_product::<FMA>(s_re, kr);
    t_re.add_twofold_product::<FMA>(s_im.neg(), ki);
    t_im.add_twofold_product::<FMA>(s_re, ki);
    t_im.add_twofold_product::<FMA>(s_im, kr);
    let (t_re, t_im) = (t_re.normalised().neg(), t_im.normalised().neg());
    for (i, v) in g {
        re[i].add_twofold_product::<FMA>(t_re, v);
        im[i].add_twofold_product::<FMA>(t_im, v);
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
            // The transient's real product and strain energies: −K·x and ½xᵀ·K·x, split at
            // the structure (K_beam) and the links (K − K_beam).
            let xr: Vec<f64> = x.iter().map(|z| z.re).collect();
            let (mut z, mut k_xr, mut kb_xr) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
            split.subtract_stiffness(&xr, &mut z);
            sys.k.mul_vec(&xr, &mut k_xr);
            sys.k_beam.mul_vec(&xr, &mut kb_xr);
            for i in 0..n {
                assert!((z[i] + k_xr[i]).abs() <= 1e-13 * sys.k.get(i, i).abs() * 10.0, "row {i}");
            }
            let half = |v: &[f64]| 0.5 * xr.iter().zip(v).map(|(a, b)| a * b).sum::<f64>();
            let (structure, links) = split.strain_energies(&xr);
            let (e_beam, e_all) = (half(&kb_xr), half(&k_xr));
            assert!((structure - e_beam).abs() <= 1e-12 * e_all, "{structure} vs {e_beam}");
            assert!((structure + links - e_all).abs() <= 1e-12 * e_all, "{} vs {e_all}", structure + links);
        }
    }

    /// On a fine mesh a smooth motion's stiffness forces cancel by ~elements⁴: the
    /// compensated residual keeps them to ~u² of the terms (against the same sums in the
    /// `twofloat` crate's double-word arithmetic), where doubles lose ~1e-6 of them, and
    /// both builds give the same bits.
    #[test]
    fn the_compensated_residual_keeps_what_a_fine_mesh_cancels() {
        let section = Section { width: 0.05, thickness: 0.005 };
        let material = Material { youngs_modulus: 210e9, density: 7850.0 };
        let (l, n_el) = (0.73, 4000);
        let mesh = Mesh::uniform(l, n_el, &[], section, material);
        let supports = vec![
            Support { node: 0, kind: SupportKind::Clamped },
            Support { node: n_el, kind: SupportKind::Spring { k_w: 3.0e5, k_theta: 40.0 } },
        ];
        let mut model = Model::bare(crate::structure::Structure::Beam(crate::beam::Beam::new(mesh, supports)));
        model.damping = crate::assembly::Damping::Rayleigh(crate::assembly::Rayleigh { a0: 5.0, a1: 1e-5 });
        let sys = System::assemble(&model).unwrap();
        let split = StiffnessRows::of(&model, &sys).unwrap().unwrap();
        let crate::structure::Structure::Beam(beam) = model.structure.as_ref().unwrap() else { unreachable!() };
        // A smooth shape: w = sin(πs/L)·(1 + 0.3i), θ = w′.
        let mut x = vec![Complex64::default(); sys.n()];
        for node in 0..=n_el {
            let s = l * node as f64 / n_el as f64;
            let k = std::f64::consts::PI / l;
            let z = Complex64::new(1.0, 0.3);
            if let Some(i) = sys.dofs.w(node) {
                x[i] = z * (k * s).sin() * 1e-3;
            }
            if let Some(i) = sys.dofs.node_dof(node, 1) {
                x[i] = z * k * (k * s).cos() * 1e-3;
            }
        }
        let w = 2.0 * std::f64::consts::PI * 60.0;
        let (c_m, c_c) = (Complex64::new(-w * w, 0.0), Complex64::new(0.0, w));
        let b = vec![Complex64::default(); sys.n()];
        let mut r = vec![Complex64::default(); sys.n()];
        split.residual(c_m, c_c, &b, &x, &mut r);
        // The beam's part, −k_el·Gᵀ(G·x), in twofloat; the rest as the residual applies it.
        let k_el = (TwoFloat::new_mul(1e-5, w), TwoFloat::from(1.0));
        let mut re = vec![TwoFloat::from(0.0); sys.n()];
        let mut im = vec![TwoFloat::from(0.0); sys.n()];
        for e in &beam.mesh.elements {
            let d = sys.dofs.element_dofs(&e.nodes);
            for g in element_stiffness_rows_wide(e.ei, e.length) {
                let (mut s_re, mut s_im) = (TwoFloat::from(0.0), TwoFloat::from(0.0));
                for (dof, v) in d.iter().zip(g) {
                    if let Some(i) = dof {
                        s_re += v * x[*i].re;
                        s_im += v * x[*i].im;
                    }
                }
                // (s_re + i·s_im)·(1 + i·a₁ω)
                let (t_re, t_im) = (s_re * k_el.1 - s_im * k_el.0, s_re * k_el.0 + s_im * k_el.1);
                for (dof, v) in d.iter().zip(g) {
                    if let Some(i) = dof {
                        re[*i] -= v * t_re;
                        im[*i] -= v * t_im;
                    }
                }
            }
        }
        // The end spring, k·x per DOF, stiffness-proportional damped as the elements are.
        for (dof, k) in [(sys.dofs.w(n_el), 3.0e5), (sys.dofs.node_dof(n_el, 1), 40.0)] {
            let i = dof.unwrap();
            re[i] -= (TwoFloat::from(x[i].re) * k_el.1 - TwoFloat::from(x[i].im) * k_el.0) * k;
            im[i] -= (TwoFloat::from(x[i].re) * k_el.0 + TwoFloat::from(x[i].im) * k_el.1) * k;
        }
        let mut rest = vec![Complex64::default(); sys.n()];
        split.apply_masses(c_m, c_c, &x, &mut rest);
        let mut apply = vec![Complex64::default(); sys.n()];
        split.apply(c_m, c_c, &x, &mut apply);
        let (mut worst, mut worst_double, mut scale) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..sys.n() {
            let reference = Complex64::new(f64::from(re[i] - rest[i].re), f64::from(im[i] - rest[i].im));
            worst = worst.max((r[i] - reference).norm());
            worst_double = worst_double.max((-apply[i] - reference).norm());
            scale = scale.max(reference.norm());
        }
        assert!(worst <= 1e-12 * scale, "compensated {worst:.2e} of {scale:.2e}");
        assert!(worst_double > 1e3 * worst.max(1e-300), "doubles {worst_double:.2e} vs {worst:.2e}");
        for fma in crate::simd::builds() {
            let mut again = vec![Complex64::default(); sys.n()];
            split.residual_in(fma, c_m, c_c, &b, &x, &mut again);
            assert!(again
                .iter()
                .zip(&r)
                .all(|(a, r)| a.re.to_bits() == r.re.to_bits() && a.im.to_bits() == r.im.to_bits()));
        }
    }
}
