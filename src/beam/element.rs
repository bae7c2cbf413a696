//! The two-node Hermite-cubic Euler–Bernoulli element, DOFs (w₁, θ₁, w₂, θ₂).

use nalgebra::Matrix4;
use twofloat::TwoFloat;

/// How the element mass is represented.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MassKind {
    /// The consistent mass of the cubic shape functions (default; converges as h⁴ for
    /// frequencies).
    #[default]
    Consistent,
    /// HRZ diagonal lumping: ρAl/2 on each w and ρAl³/78 on each θ (the consistent
    /// diagonal scaled to keep the translational mass), so M stays positive definite.
    Lumped,
}

/// Element stiffness Kₑ = EI/l³·[…] (N/m, N, N·m blocks) for bending stiffness `ei` (N·m²)
/// and length `l` (m).
pub fn element_stiffness(ei: f64, l: f64) -> Matrix4<f64> {
    let c = ei / (l * l * l);
    let l2 = l * l;
    c * Matrix4::new(
        12.0,
        6.0 * l,
        -12.0,
        6.0 * l, //
        6.0 * l,
        4.0 * l2,
        -6.0 * l,
        2.0 * l2, //
        -12.0,
        -6.0 * l,
        12.0,
        -6.0 * l, //
        6.0 * l,
        2.0 * l2,
        -6.0 * l,
        4.0 * l2,
    )
}

/// The element stiffness as a sum of squares, Kₑ = g₁·g₁ᵀ + g₂·g₂ᵀ: one row g per Gauss
/// point of ∫₀ˡ EI·w″² ds, gₚ = √(EI·l/2)·B(ξₚ), where B = N″ is the curvature of the cubic
/// shape functions (1/m for w, 1/rad·1/m … entries ~1/l², 1/l) and ξₚ = ½ ∓ 1/(2√3).
/// Curvature is linear along the element, so two-point Gauss quadrature is exact and
/// Σ gₚ·gₚᵀ equals [`element_stiffness`] in exact arithmetic. gₚ·qₑ is in √J (strain
/// energy ½·Σ(gₚ·qₑ)²), so entries on w are in √(N·m)/m and on θ in √(N·m)/rad.
///
/// Why: a factor of K assembled from these rows by orthogonal transformations never forms
/// K's entries ~EI/l³, whose round-off, in a smooth mode's tiny strain energy, is amplified
/// by ~(L/l)⁴; the rows' own round-off is amplified only by ~(L/l)².
///
/// The entries are written so that a rigid translation (1, 0, 1, 0) gives exactly zero.
pub fn element_stiffness_rows(ei: f64, l: f64) -> [[f64; 4]; 2] {
    let s3 = 3.0f64.sqrt();
    let c = (0.5 * ei * l).sqrt();
    // At ξ = ½ ∓ 1/(2√3): N₁″ = ∓2√3/l², N₂″ = (−1 ∓ √3)/l, N₃″ = −N₁″, N₄″ = (1 ∓ √3)/l.
    let a = c * 2.0 * s3 / (l * l);
    let b = c * (1.0 + s3) / l;
    let d = c * (s3 - 1.0) / l;
    [[-a, -b, a, -d], [a, d, -a, b]]
}

/// [`element_stiffness_rows`] in double-word arithmetic (to ~u² of the exact rows of `ei`
/// and `l`): where a refinement's residual must not carry the double rows' own rounding,
/// which breaks their rigid-rotation null space by ~ε and so stands for a model ~ε·elements
/// off the one meant.
pub fn element_stiffness_rows_wide(ei: f64, l: f64) -> [[TwoFloat; 4]; 2] {
    let s3 = TwoFloat::from(3.0).sqrt();
    let c = (TwoFloat::new_mul(0.5 * ei, l)).sqrt();
    let a = c * 2.0 * s3 / TwoFloat::new_mul(l, l);
    let b = c * (s3 + 1.0) / l;
    let d = c * (s3 - 1.0) / l;
    [[-a, -b, a, -d], [a, d, -a, b]]
}

/// Element mass for mass per length `rho_a` (kg/m) and length `l` (m).
pub fn element_mass(rho_a: f64, l: f64, kind: MassKind) -> Matrix4<f64> {
    let l2 = l * l;
    match kind {
        MassKind::Consistent => {
            let c = rho_a * l / 420.0;
            c * Matrix4::new(
                156.0,
                22.0 * l,
                54.0,
                -13.0 * l, //
                22.0 * l,
                4.0 * l2,
                13.0 * l,
                -3.0 * l2, //
                54.0,
                13.0 * l,
                156.0,
                -22.0 * l, //
                -13.0 * l,
                -3.0 * l2,
                -22.0 * l,
                4.0 * l2,
            )
        }
        MassKind::Lumped => {
            let m = rho_a * l;
            Matrix4::from_diagonal(&nalgebra::Vector4::new(m / 2.0, m * l2 / 78.0, m / 2.0, m * l2 / 78.0))
        }
    }
}

/// Hermite shape functions at ξ = s/l ∈ [0, 1] for (w₁, θ₁, w₂, θ₂): the displacement
/// inside an element, used to sample w between nodes for plots.
pub fn shape_functions(xi: f64, l: f64) -> [f64; 4] {
    let x2 = xi * xi;
    let x3 = x2 * xi;
    [1.0 - 3.0 * x2 + 2.0 * x3, l * (xi - 2.0 * x2 + x3), 3.0 * x2 - 2.0 * x3, l * (x3 - x2)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rigid_body_modes_carry_no_strain_energy() {
        let l = 0.37;
        let k = element_stiffness(3.0, l);
        // Translation and rotation about node 1.
        let translation = nalgebra::Vector4::new(1.0, 0.0, 1.0, 0.0);
        let rotation = nalgebra::Vector4::new(0.0, 1.0, l, 1.0);
        assert!((k * translation).norm() < 1e-12);
        assert!((k * rotation).norm() < 1e-10);
    }

    #[test]
    fn stiffness_rows_are_a_square_root_of_the_element_stiffness() {
        for (ei, l) in [(3.0, 0.37), (0.109375, 1.46e-5), (2.5e4, 2.0)] {
            let k = element_stiffness(ei, l);
            let g = element_stiffness_rows(ei, l);
            for a in 0..4 {
                for b in 0..4 {
                    let sum = g[0][a] * g[0][b] + g[1][a] * g[1][b];
                    let scale = (k[(a, a)] * k[(b, b)]).sqrt();
                    assert!((sum - k[(a, b)]).abs() <= 1e-14 * scale, "({a},{b}): {sum} vs {}", k[(a, b)]);
                }
            }
            // A rigid translation strains nothing, exactly.
            for r in &g {
                assert_eq!(r[0] + r[2], 0.0);
            }
        }
    }

    #[test]
    fn mass_matrices_carry_the_element_mass() {
        let (rho_a, l) = (2.5, 0.3);
        let t = nalgebra::Vector4::new(1.0, 0.0, 1.0, 0.0);
        for kind in [MassKind::Consistent, MassKind::Lumped] {
            let m = element_mass(rho_a, l, kind);
            assert!(((t.transpose() * m * t)[0] - rho_a * l).abs() < 1e-14);
            assert!((m - m.transpose()).norm() == 0.0);
        }
    }

    #[test]
    fn shape_functions_interpolate_nodal_values() {
        let l = 0.2;
        let n0 = shape_functions(0.0, l);
        let n1 = shape_functions(1.0, l);
        assert_eq!(n0, [1.0, 0.0, 0.0, 0.0]);
        assert!((n1[2] - 1.0).abs() < 1e-15 && n1[0].abs() < 1e-15);
    }
}
