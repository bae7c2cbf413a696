//! The basis of a reduced system: full-model DOFs q_full = T·q_reduced.
//!
//! T is kept in one of two forms. A reduction of one assembled system stores it dense
//! (`n × n_reduced`, row-major). A placement on a shared modal basis stores it factored,
//!
//! ```text
//!         ⎡ Φ   X·Y − Φ·B   0 ⎤   structure DOFs
//!     T = ⎣ 0   0           I ⎦   actuator body DOFs
//! ```
//!
//! with Φ the structure's retained modes (shared by every placement), X static shapes
//! (the unit loads' K⁻¹·e_d that the placement's attachment patterns are sums of, kept by
//! the study and shared), Y their combinations into residual vectors and B what the modes
//! carry of them. A row of T then costs O(modes) and nothing of the size of the structure
//! is formed per placement; [`Projection::expand`] forms the full field only when asked.

use super::dofs::DofMap;
use num_complex::Complex64;
use std::collections::HashMap;
use std::sync::Arc;

/// T of a reduced system.
#[derive(Clone, Debug)]
pub struct Projection {
    /// The full model's DOF map (structure DOFs per node; actuator bodies).
    pub full: DofMap,
    pub n_reduced: usize,
    columns: Columns,
}

#[derive(Clone, Debug)]
enum Columns {
    /// T itself, `full.n` rows × `n_reduced` columns, row-major.
    Dense(Vec<f64>),
    Factored(Factored),
}

/// T = [Φ, X·Y − Φ·B, bodies] (see the module's doc comment).
#[derive(Clone, Debug)]
pub struct Factored {
    /// Φ over the structure's DOFs (the first rows of the full numbering), row-major
    /// `structure DOFs × modes`.
    pub phi: Arc<Vec<f64>>,
    pub modes: usize,
    /// The static shapes x_k over the structure's DOFs.
    pub shapes: Vec<Arc<Vec<f64>>>,
    /// Every shape's value x_k(i) at the structure DOFs i where the placement has read it
    /// already (the attachment patterns' DOFs, off their flexibility): a row of T there
    /// reads nothing of the shapes, which lie scattered over the structure.
    pub shapes_at: HashMap<usize, Vec<f64>>,
    /// Y, row-major `shapes × residual columns`.
    pub y: Vec<f64>,
    /// B, row-major `modes × residual columns`.
    pub b: Vec<f64>,
    /// The full DOF of each body column, in column order.
    pub bodies: Vec<usize>,
}

impl Factored {
    fn residual_columns(&self) -> usize {
        self.y.len().checked_div(self.shapes.len()).unwrap_or(0)
    }

    fn structure_dofs(&self) -> usize {
        self.phi.len().checked_div(self.modes).unwrap_or(0)
    }

    /// Row `i` of T into `row` (length nm + residual columns + bodies, zeroed).
    fn row_into(&self, i: usize, row: &mut [f64]) {
        let (nm, nq) = (self.modes, self.residual_columns());
        if i < self.structure_dofs() {
            let phi_i = &self.phi[i * nm..(i + 1) * nm];
            row[..nm].copy_from_slice(phi_i);
            let mut on_shapes = vec![0.0; self.shapes.len()];
            self.add_shapes_at(i, 1.0, &mut on_shapes);
            for c in 0..nq {
                let from_shapes: f64 = on_shapes.iter().enumerate().map(|(a, x)| self.y[a * nq + c] * x).sum();
                let from_modes: f64 = phi_i.iter().enumerate().map(|(r, p)| p * self.b[r * nq + c]).sum();
                row[nm + c] = from_shapes - from_modes;
            }
        } else if let Some(k) = self.bodies.iter().position(|&d| d == i) {
            row[nm + nq + k] = 1.0;
        }
    }

    /// coef·x_k(i) into `on_shapes[k]`, for every shape k.
    fn add_shapes_at(&self, i: usize, coef: f64, on_shapes: &mut [f64]) {
        match self.shapes_at.get(&i) {
            Some(at) => on_shapes.iter_mut().zip(at).for_each(|(s, x)| *s += coef * x),
            None => on_shapes.iter_mut().zip(&self.shapes).for_each(|(s, x)| *s += coef * x[i]),
        }
    }

    /// Σ coeff·(row `i` of T) over the full DOFs of `g`, into `row` (zeroed): the rows'
    /// modal parts summed first, so a combination of many DOFs costs one product with Y
    /// and B.
    fn combination_into(&self, g: &[(usize, f64)], row: &mut [f64]) {
        let (nm, nq, ns) = (self.modes, self.residual_columns(), self.structure_dofs());
        let mut on_shapes = vec![0.0; self.shapes.len()];
        for &(i, coef) in g {
            if i < ns {
                let phi_i = &self.phi[i * nm..(i + 1) * nm];
                row[..nm].iter_mut().zip(phi_i).for_each(|(r, p)| *r += coef * p);
                self.add_shapes_at(i, coef, &mut on_shapes);
            } else if let Some(k) = self.bodies.iter().position(|&d| d == i) {
                row[nm + nq + k] += coef;
            }
        }
        for c in 0..nq {
            let from_shapes: f64 = on_shapes.iter().enumerate().map(|(a, s)| self.y[a * nq + c] * s).sum();
            let from_modes: f64 = row[..nm].iter().enumerate().map(|(r, p)| p * self.b[r * nq + c]).sum();
            row[nm + c] = from_shapes - from_modes;
        }
    }

    /// T·q.
    fn expand(&self, q: &[Complex64], n: usize) -> Vec<Complex64> {
        let (nm, nq) = (self.modes, self.residual_columns());
        let (q_modes, q_residual) = (&q[..nm], &q[nm..nm + nq]);
        // Φ·(q_m − B·q_ψ) + X·(Y·q_ψ).
        let on_modes: Vec<Complex64> = (0..nm)
            .map(|r| q_modes[r] - (0..nq).map(|c| q_residual[c] * self.b[r * nq + c]).sum::<Complex64>())
            .collect();
        let on_shapes: Vec<Complex64> =
            (0..self.shapes.len()).map(|a| (0..nq).map(|c| q_residual[c] * self.y[a * nq + c]).sum()).collect();
        let mut out = vec![Complex64::default(); n];
        for (i, o) in out.iter_mut().enumerate().take(self.structure_dofs()) {
            let phi_i = &self.phi[i * nm..(i + 1) * nm];
            *o = phi_i.iter().zip(&on_modes).map(|(&p, &x)| x * p).sum::<Complex64>()
                + self.shapes.iter().zip(&on_shapes).map(|(x, &s)| s * x[i]).sum::<Complex64>();
        }
        for (k, &d) in self.bodies.iter().enumerate() {
            out[d] = q[nm + nq + k];
        }
        out
    }
}

impl Projection {
    /// T given dense (row-major `full.n × n_reduced`).
    pub fn dense(full: DofMap, t: Vec<f64>, n_reduced: usize) -> Self {
        assert_eq!(t.len(), full.n * n_reduced, "T's size");
        Projection { full, n_reduced, columns: Columns::Dense(t) }
    }

    /// T given factored.
    pub fn factored(full: DofMap, f: Factored) -> Self {
        let n_reduced = f.modes + f.residual_columns() + f.bodies.len();
        Projection { full, n_reduced, columns: Columns::Factored(f) }
    }

    /// The retained modes of a factored T (a placement on a shared modal basis), the first
    /// reduced coordinates; None for a dense T.
    pub fn shared_modes(&self) -> Option<usize> {
        match &self.columns {
            Columns::Factored(f) => Some(f.modes),
            Columns::Dense(_) => None,
        }
    }

    /// Row `i` of T (full DOF i in reduced coordinates), dense.
    pub fn row_dense(&self, i: usize) -> Vec<f64> {
        match &self.columns {
            Columns::Dense(t) => t[i * self.n_reduced..(i + 1) * self.n_reduced].to_vec(),
            Columns::Factored(f) => {
                let mut row = vec![0.0; self.n_reduced];
                f.row_into(i, &mut row);
                row
            }
        }
    }

    /// Row `i` of T, without exact zeros.
    pub fn row(&self, i: usize) -> Vec<(usize, f64)> {
        let r = self.row_dense(i);
        r.into_iter().enumerate().filter(|(_, v)| *v != 0.0).collect()
    }

    /// Full-model amplitudes T·q of reduced ones (complex, e.g. one harmonic's Q_k).
    pub fn expand(&self, q: &[Complex64]) -> Vec<Complex64> {
        assert_eq!(q.len(), self.n_reduced, "reduced vector length");
        match &self.columns {
            Columns::Dense(t) => {
                t.chunks_exact(self.n_reduced).map(|row| row.iter().zip(q).map(|(&t, &x)| x * t).sum()).collect()
            }
            Columns::Factored(f) => f.expand(q, self.full.n),
        }
    }

    /// A combination Σ coeff·q[dof] of full DOFs as one of the reduced coordinates.
    pub fn row_combination(&self, g: &[(usize, f64)]) -> Vec<(usize, f64)> {
        let mut r = vec![0.0; self.n_reduced];
        match &self.columns {
            Columns::Factored(f) => f.combination_into(g, &mut r),
            Columns::Dense(_) => {
                for &(d, coef) in g {
                    r.iter_mut().zip(self.row_dense(d)).for_each(|(x, t)| *x += coef * t);
                }
            }
        }
        r.into_iter().enumerate().filter(|(_, v)| *v != 0.0).collect()
    }
}
