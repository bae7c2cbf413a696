//! Closed-form results for uniform Euler–Bernoulli beams, used as references.
//!
//! Natural frequencies ω_r = (β_r L)²·√(EI/(ρA L⁴)), with β_r L the r-th root of the
//! characteristic equation of the end conditions, found here by bisection to round-off.

use std::f64::consts::PI;

/// End conditions with a closed-form characteristic equation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    Clamped,
    Pinned,
    Free,
}

/// The first `count` roots βL of the characteristic equation (flexible modes only).
pub fn beta_l_roots(left: End, right: End, count: usize) -> Option<Vec<f64>> {
    use End::*;
    let (a, b) = if left as u8 <= right as u8 { (left, right) } else { (right, left) };
    // f(x) whose positive roots are the flexible modes' βL; each root lies in the given
    // bracket (r-th interval) where f changes sign exactly once.
    let f: fn(f64) -> f64 = match (a, b) {
        (Clamped, Clamped) | (Free, Free) => |x| x.cos() * x.cosh() - 1.0,
        (Clamped, Free) => |x| x.cos() * x.cosh() + 1.0,
        (Pinned, Pinned) => |x| x.sin(),
        (Clamped, Pinned) | (Pinned, Free) => |x| x.tan() - x.tanh(),
        _ => return None,
    };
    let mut roots = Vec::with_capacity(count);
    for r in 1..=count {
        let rf = r as f64;
        // Brackets from the asymptotic positions of the roots.
        let (lo, hi) = match (a, b) {
            (Clamped, Clamped) | (Free, Free) => ((rf + 0.5) * PI - 0.5, (rf + 0.5) * PI + 0.5),
            (Clamped, Free) => ((rf - 0.5) * PI - 0.5, (rf - 0.5) * PI + 0.5),
            (Pinned, Pinned) => (rf * PI - 0.5, rf * PI + 0.5),
            _ => ((rf + 0.25) * PI - 0.3, (rf + 0.25) * PI + 0.3),
        };
        roots.push(bisect(f, lo.max(1e-3), hi));
    }
    Some(roots)
}

fn bisect(f: fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let mut flo = f(lo);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        let fm = f(mid);
        if (fm < 0.0) == (flo < 0.0) {
            lo = mid;
            flo = fm;
        } else {
            hi = mid;
        }
        if hi - lo <= 4.0 * f64::EPSILON * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

/// Natural frequencies (Hz) of a uniform beam: length L (m), EI (N·m²), ρA (kg/m).
pub fn natural_frequencies_hz(
    left: End,
    right: End,
    length: f64,
    ei: f64,
    rho_a: f64,
    count: usize,
) -> Option<Vec<f64>> {
    let c = (ei / rho_a).sqrt() / (2.0 * PI * length * length);
    beta_l_roots(left, right, count).map(|r| r.iter().map(|bl| bl * bl * c).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_match_published_values() {
        let cc = beta_l_roots(End::Clamped, End::Clamped, 3).unwrap();
        for (r, v) in cc.iter().zip([4.730040745, 7.853204624, 10.995607838]) {
            assert!((r - v).abs() < 1e-8, "{r} vs {v}");
        }
        let cf = beta_l_roots(End::Clamped, End::Free, 2).unwrap();
        assert!((cf[0] - 1.875104069).abs() < 1e-8 && (cf[1] - 4.694091133).abs() < 1e-8);
        let cp = beta_l_roots(End::Clamped, End::Pinned, 1).unwrap();
        assert!((cp[0] - 3.926602312).abs() < 1e-8);
    }
}

/// Steady harmonic displacement w(x) (m per N of force amplitude) of a uniform
/// clamped–clamped Euler–Bernoulli beam of length `l` under a unit point force at `a`, at
/// circular frequency ω, for complex bending stiffness `ei` (N·m²; EI·(1 + iη) for
/// hysteretic damping) and mass per length `rho_a` (kg/m): the exact solution of
/// EI·w'''' − ρA·ω²·w = δ(x − a), convention q(t) = Re(w·e^{iωt}).
///
/// Each of the two segments is written in cos k(x−x₀), sin k(x−x₀), e^{−k(x−x₀)} and
/// e^{−k(x₁−x)} (k⁴ = ρAω²/EI, Re k > 0) rather than cosh and sinh, so the 8 × 8 system for
/// the clamped ends and the jump conditions at the force stays well conditioned at high kL.
pub fn clamped_point_receptance(
    l: f64,
    ei: num_complex::Complex64,
    rho_a: f64,
    omega: f64,
    a: f64,
    x: f64,
) -> num_complex::Complex64 {
    use nalgebra::{DMatrix, DVector};
    use num_complex::Complex64 as C;
    let k = (C::new(rho_a * omega * omega, 0.0) / ei).powf(0.25);
    // Value and first three derivatives of the four basis functions of a segment [x0, x1].
    let basis = |x0: f64, x1: f64, x: f64| -> [[C; 4]; 4] {
        let (c, s) = ((k * (x - x0)).cos(), (k * (x - x0)).sin());
        let (e1, e2) = ((-k * (x - x0)).exp(), (-k * (x1 - x)).exp());
        let (k2, k3) = (k * k, k * k * k);
        [
            [c, -k * s, -k2 * c, k3 * s],
            [s, k * c, -k2 * s, -k3 * c],
            [e1, -k * e1, k2 * e1, -k3 * e1],
            [e2, k * e2, k2 * e2, k3 * e2],
        ]
    };
    let mut m = DMatrix::<C>::zeros(8, 8);
    let mut r = DVector::<C>::zeros(8);
    let (left0, left_a) = (basis(0.0, a, 0.0), basis(0.0, a, a));
    let (right_a, right_l) = (basis(a, l, a), basis(a, l, l));
    for j in 0..4 {
        // Clamped at 0 and at l: w = w' = 0.
        m[(0, j)] = left0[j][0];
        m[(1, j)] = left0[j][1];
        m[(2, 4 + j)] = right_l[j][0];
        m[(3, 4 + j)] = right_l[j][1];
        // At the force: w, w', w'' continuous, EI·(w'''(a+) − w'''(a−)) = 1.
        for d in 0..3 {
            m[(4 + d, j)] = left_a[j][d];
            m[(4 + d, 4 + j)] = -right_a[j][d];
        }
        m[(7, j)] = -ei * left_a[j][3];
        m[(7, 4 + j)] = ei * right_a[j][3];
    }
    r[7] = C::new(1.0, 0.0);
    let coef = m.lu().solve(&r).expect("the clamped beam's jump system is regular away from resonance");
    let (seg, off) = if x <= a { (basis(0.0, a, x), 0) } else { (basis(a, l, x), 4) };
    (0..4).map(|j| coef[off + j] * seg[j][0]).sum()
}

#[cfg(test)]
mod receptance_tests {
    use super::*;
    use num_complex::Complex64 as C;

    /// Far below the first mode the beam responds statically: the clamped–clamped
    /// deflection under a point force, w(x) = b²x²(3aL − 3ax − bx)/(6EIL³) for x ≤ a.
    #[test]
    fn static_limit_and_reciprocity() {
        let (l, ei, rho_a) = (0.73, 109.375, 1.9625);
        let (a, x) = (0.3, 0.15);
        let b = l - a;
        // At 0.05 rad/s the dynamic correction is (ω/ω₁)² ≈ 3e-8; the basis functions grow
        // alike as kL → 0, so the static limit is met to ~1e-8, not to round-off.
        let w = clamped_point_receptance(l, C::new(ei, 0.0), rho_a, 0.05, a, x);
        let exact = b * b * x * x * (3.0 * a * l - 3.0 * a * x - b * x) / (6.0 * ei * l.powi(3));
        assert!((w.re - exact).abs() < 1e-6 * exact && w.im.abs() < 1e-9 * exact, "{w} vs {exact}");
        let (p, q) = (
            clamped_point_receptance(l, C::new(ei, 30.0), rho_a, 2000.0, 0.2, 0.55),
            clamped_point_receptance(l, C::new(ei, 30.0), rho_a, 2000.0, 0.55, 0.2),
        );
        assert!((p - q).norm() < 1e-9 * p.norm(), "reciprocity: {p} vs {q}");
    }
}
