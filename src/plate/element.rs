//! The conforming four-node Bogner–Fox–Schmit rectangle (spec §16): bicubic Hermite
//! interpolation of the deflection w, per node (w, ∂w/∂x, ∂w/∂y, ∂²w/∂x∂y), 16 DOFs.
//!
//! Corner order: (0, 0), (a, 0), (a, b), (0, b) in element coordinates, a × b the sides
//! (m). Every shape function is a product f(ξ)·g(η) of two cubic Hermite functions on
//! ξ = x/a, η = y/b ∈ [0, 1], so w and its normal slope are continuous across element sides
//! (the element is conforming) and frequencies converge as h⁴ from above.

// The quadrature loops index several element arrays by one DOF index on purpose: that is
// the form of the integrals they compute.
#![allow(clippy::needless_range_loop)]

/// DOFs per node, in the order each node carries them.
pub const NODE_DOFS: usize = 4;

/// Names of the node DOFs, for messages and the DOF table.
pub const DOF_NAMES: [&str; NODE_DOFS] = ["w", "w_x", "w_y", "w_xy"];

/// Nodes per element.
pub const NODES: usize = 4;

/// Element DOFs.
pub const DOFS: usize = NODE_DOFS * NODES;

/// A dense element matrix, row-major.
pub type ElementMatrix = [[f64; DOFS]; DOFS];

/// Where each corner sits: (i, j) ∈ {0, 1}², i along x, j along y.
const CORNERS: [(usize, usize); NODES] = [(0, 0), (1, 0), (1, 1), (0, 1)];

/// The cubic Hermite functions on [0, 1] for one end (`end` 0 or 1) and their first and
/// second derivatives in ξ: value functions (k = 0) and slope functions (k = 1, scaled
/// by the side length `h` so that they interpolate the slope in physical units).
fn hermite(end: usize, k: usize, h: f64, s: f64) -> [f64; 3] {
    let s2 = s * s;
    let s3 = s2 * s;
    match (end, k) {
        (0, 0) => [1.0 - 3.0 * s2 + 2.0 * s3, -6.0 * s + 6.0 * s2, -6.0 + 12.0 * s],
        (0, _) => [h * (s - 2.0 * s2 + s3), h * (1.0 - 4.0 * s + 3.0 * s2), h * (-4.0 + 6.0 * s)],
        (_, 0) => [3.0 * s2 - 2.0 * s3, 6.0 * s - 6.0 * s2, 6.0 - 12.0 * s],
        _ => [h * (-s2 + s3), h * (-2.0 * s + 3.0 * s2), h * (-2.0 + 6.0 * s)],
    }
}

/// The 16 shape functions at (ξ, η) ∈ [0, 1]² and their derivatives in physical units:
/// `[N, N_x, N_y, N_xx, N_yy, N_xy]`, each over the element DOFs.
pub fn shape(a: f64, b: f64, xi: f64, eta: f64) -> [[f64; DOFS]; 6] {
    let mut out = [[0.0; DOFS]; 6];
    for (node, &(i, j)) in CORNERS.iter().enumerate() {
        // Node DOFs: w → (0, 0), w_x → (1, 0), w_y → (0, 1), w_xy → (1, 1) in (kx, ky).
        for (d, (kx, ky)) in [(0, 0), (1, 0), (0, 1), (1, 1)].into_iter().enumerate() {
            let f = hermite(i, kx, a, xi);
            let g = hermite(j, ky, b, eta);
            let c = NODE_DOFS * node + d;
            out[0][c] = f[0] * g[0];
            out[1][c] = f[1] * g[0] / a;
            out[2][c] = f[0] * g[1] / b;
            out[3][c] = f[2] * g[0] / (a * a);
            out[4][c] = f[0] * g[2] / (b * b);
            out[5][c] = f[1] * g[1] / (a * b);
        }
    }
    out
}

/// Gauss–Legendre points and weights on [0, 1], four points: exact to degree 7, so the
/// bicubic mass (degree 6 per direction) and the stiffness are integrated exactly.
fn gauss4() -> [(f64, f64); 4] {
    let p = [
        (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
        (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    ];
    p.map(|(x, w)| (0.5 * (1.0 + x), 0.5 * w))
}

/// Element stiffness of Kirchhoff bending (N/m in w-units), bending stiffness `d` =
/// E·h³/(12(1 − ν²)) (N·m), Poisson's ratio `nu`:
/// Kₑ = ∫ Bᵀ·D·B dA, B = (N_xx, N_yy, 2·N_xy), D = d·[[1, ν, 0], [ν, 1, 0], [0, 0, (1 − ν)/2]].
pub fn stiffness(a: f64, b: f64, d: f64, nu: f64) -> ElementMatrix {
    let mut k = [[0.0; DOFS]; DOFS];
    let g = gauss4();
    for &(xi, wx) in &g {
        for &(eta, wy) in &g {
            let s = shape(a, b, xi, eta);
            let w = wx * wy * a * b * d;
            let (nxx, nyy, nxy) = (&s[3], &s[4], &s[5]);
            for r in 0..DOFS {
                for c in r..DOFS {
                    let bend = nxx[r] * nxx[c] + nyy[r] * nyy[c] + nu * (nxx[r] * nyy[c] + nyy[r] * nxx[c]);
                    let twist = 2.0 * (1.0 - nu) * nxy[r] * nxy[c];
                    k[r][c] += w * (bend + twist);
                }
            }
        }
    }
    mirror(k)
}

/// The full symmetric matrix from its upper triangle, so it is symmetric bit for bit.
fn mirror(mut a: ElementMatrix) -> ElementMatrix {
    for r in 1..DOFS {
        let (upper, lower) = a.split_at_mut(r);
        for (c, row) in upper.iter().enumerate() {
            lower[0][c] = row[r];
        }
    }
    a
}

/// Consistent element mass (kg in w-units) for mass per area `rho_h` = ρ·h (kg/m²):
/// Mₑ = ∫ ρh·N·Nᵀ dA.
pub fn mass(a: f64, b: f64, rho_h: f64) -> ElementMatrix {
    let mut m = [[0.0; DOFS]; DOFS];
    let g = gauss4();
    for &(xi, wx) in &g {
        for &(eta, wy) in &g {
            let n = shape(a, b, xi, eta)[0];
            let w = wx * wy * a * b * rho_h;
            for r in 0..DOFS {
                for c in r..DOFS {
                    m[r][c] += w * n[r] * n[c];
                }
            }
        }
    }
    mirror(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rigid motions (w = 1, w = x, w = y) and the pure twist w = xy store no energy;
    /// a constant curvature w = x²/2 stores exactly D·A/2.
    #[test]
    fn rigid_motions_are_free_and_constant_curvature_stores_d_area_half() {
        let (a, b, d, nu) = (0.13, 0.07, 170.0, 0.3);
        let k = stiffness(a, b, d, nu);
        let nodal = |w: &dyn Fn(f64, f64) -> [f64; 4]| {
            let mut q = [0.0; DOFS];
            for (n, &(i, j)) in CORNERS.iter().enumerate() {
                q[NODE_DOFS * n..NODE_DOFS * (n + 1)].copy_from_slice(&w(i as f64 * a, j as f64 * b));
            }
            q
        };
        let energy = |q: &[f64; DOFS]| {
            0.5 * (0..DOFS).map(|r| (0..DOFS).map(|c| q[r] * k[r][c] * q[c]).sum::<f64>()).sum::<f64>()
        };
        let scale = d * a * b / (a * a);
        for rigid in
            [nodal(&|_, _| [1.0, 0.0, 0.0, 0.0]), nodal(&|_, y| [y, 0.0, 1.0, 0.0]), nodal(&|x, _| [x, 1.0, 0.0, 0.0])]
        {
            assert!(energy(&rigid).abs() < 1e-12 * scale, "{}", energy(&rigid));
        }
        let bend = nodal(&|x, _| [0.5 * x * x, x, 0.0, 0.0]);
        assert!((energy(&bend) - 0.5 * d * a * b).abs() < 1e-12 * d * a * b);
        // Pure twist w = xy: U = ½·D·2(1 − ν)·A.
        let twist = nodal(&|x, y| [x * y, y, x, 1.0]);
        assert!((energy(&twist) - d * (1.0 - nu) * a * b).abs() < 1e-12 * d * a * b);
    }

    #[test]
    fn mass_carries_the_element_mass_and_is_symmetric() {
        let (a, b, rho_h) = (0.2, 0.05, 8.1);
        let m = mass(a, b, rho_h);
        // A rigid translation w = 1 has kinetic energy ½·m_total.
        let mut q = [0.0; DOFS];
        for n in 0..NODES {
            q[NODE_DOFS * n] = 1.0;
        }
        let total: f64 = (0..DOFS).map(|r| (0..DOFS).map(|c| q[r] * m[r][c] * q[c]).sum::<f64>()).sum();
        assert!((total - rho_h * a * b).abs() < 1e-14 * rho_h * a * b);
        for r in 0..DOFS {
            for c in 0..DOFS {
                assert_eq!(m[r][c], m[c][r]);
            }
        }
    }

    /// The shape functions interpolate: at each corner, the w-function of that corner is 1
    /// and its slopes are the DOFs they name.
    #[test]
    fn shape_functions_interpolate_the_node_values() {
        let (a, b) = (0.3, 0.1);
        for (n, &(i, j)) in CORNERS.iter().enumerate() {
            let s = shape(a, b, i as f64, j as f64);
            for c in 0..DOFS {
                let want = |d: usize| if c == NODE_DOFS * n + d { 1.0 } else { 0.0 };
                assert!((s[0][c] - want(0)).abs() < 1e-15);
                assert!((s[1][c] - want(1)).abs() < 1e-12);
                assert!((s[2][c] - want(2)).abs() < 1e-12);
                assert!((s[5][c] - want(3)).abs() < 1e-12);
            }
        }
    }
}
