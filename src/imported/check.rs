//! What an imported model's M and K must be: positive semi-definite, with no motion that
//! has neither mass nor stiffness. Judged from the inertia of LDLᵀ factorisations
//! (Sylvester's law: the number of negative pivots of K − σM is the number of eigenvalues
//! below σ), each failure naming the matrix file and a row's node and component.
//!
//! A singular M is normal (shell and frame elements often lump no rotary inertia) and is
//! not refused; a singular K means rigid-body modes, which are counted and reported.

use super::{Files, Imported, COMPONENTS};
use crate::error::{Error, Result};
use crate::linalg::{Csr, Skyline};
use crate::structure::ordering::reverse_cuthill_mckee;

/// Eigenvalues below this fraction of the model's stiffness-to-mass scale count as zero
/// (rigid-body): far above the round-off of a zero eigenvalue (≈ ε of that scale) and far
/// below any elastic mode a structural model resolves.
pub const RIGID_FRACTION: f64 = 1e-12;

/// Most profile entries the check factorises (8 bytes each).
pub const MAX_PROFILE: usize = 300_000_000;

/// What the check found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Report {
    /// Eigenvalues of (K, M) below `rigid_below_hz` (rigid-body modes and mechanisms).
    pub rigid_body_modes: usize,
    pub rigid_below_hz: f64,
    /// Free rows with no mass on the diagonal (massless DOFs).
    pub massless_rows: usize,
    /// Whether definiteness was checked (false above [`MAX_PROFILE`]).
    pub definiteness_checked: bool,
}

/// Checks a loaded model's definiteness on its free rows (not fixed).
pub fn check(model: &Imported, files: &Files) -> Result<Report> {
    let free: Vec<usize> = (0..model.n()).filter(|&r| !model.fixed[r]).collect();
    let mut report =
        Report { massless_rows: free.iter().filter(|&&r| model.m.get(r, r) == 0.0).count(), ..Default::default() };
    if free.is_empty() {
        return Err(Error::input(
            files.dofs.display().to_string(),
            "row",
            "every row is fixed: the model has no free DOF",
        ));
    }
    let order = row_order(model, &free);
    let envelope = envelope(model, &order);
    if profile(&envelope) > MAX_PROFILE {
        return Ok(report);
    }
    let name = |r: usize| {
        let (node, c) = model.rows[r];
        format!("row {} (node {} {})", r + 1, model.nodes[node].id, COMPONENTS[c])
    };
    let diag_max = |a: &Csr| free.iter().map(|&r| a.get(r, r).abs()).fold(0.0f64, f64::max);
    let (k_max, m_max) = (diag_max(&model.k), diag_max(&model.m));
    let mfile = files.mass.display().to_string();
    let kfile = files.stiffness.display().to_string();
    if m_max == 0.0 {
        return Err(Error::input(&mfile, "entries", "the mass matrix is zero on every free row"));
    }
    // M ⪰ 0: M + τ·I has no negative pivot (τ lifts massless rows off zero).
    let m_pivots = factor(model, &order, &envelope, &[(1.0, &model.m)], RIGID_FRACTION * m_max)
        .map_err(|r| Error::input(&mfile, name(order[r]), "the mass matrix is singular beyond its massless rows"))?;
    if let Some(r) = m_pivots.iter().position(|&d| d < 0.0) {
        return Err(Error::input(
            &mfile,
            name(order[r]),
            "the mass matrix has a negative eigenvalue (it must be positive semi-definite)",
        ));
    }
    // K ⪰ 0 relative to M, and no motion without mass and stiffness: K + σM is regular
    // with no negative pivot; K − σM's negative pivots count the rigid-body modes.
    let sigma = RIGID_FRACTION * k_max / m_max;
    report.rigid_below_hz = sigma.sqrt() / (2.0 * std::f64::consts::PI);
    let above = factor(model, &order, &envelope, &[(1.0, &model.k), (sigma, &model.m)], 0.0).map_err(|r| {
        Error::input(&kfile, name(order[r]), "this DOF (or a motion through it) has neither stiffness nor mass: hold it (`imported.fixed`) or give it mass")
    })?;
    if let Some(r) = above.iter().position(|&d| d < 0.0) {
        return Err(Error::input(
            &kfile,
            name(order[r]),
            "the stiffness matrix has a negative eigenvalue (it must be positive semi-definite)",
        ));
    }
    report.rigid_body_modes = match factor(model, &order, &envelope, &[(1.0, &model.k), (-sigma, &model.m)], 0.0) {
        Ok(d) => d.iter().filter(|&&d| d < 0.0).count(),
        // K − σM singular: σ hit an eigenvalue; count at a slightly larger shift.
        Err(_) => factor(model, &order, &envelope, &[(1.0, &model.k), (-2.0 * sigma, &model.m)], 0.0)
            .map(|d| d.iter().filter(|&&d| d < 0.0).count())
            .unwrap_or(0),
    };
    report.definiteness_checked = true;
    Ok(report)
}

/// The free rows in reverse Cuthill–McKee order of their coupling (a small profile).
fn row_order(model: &Imported, free: &[usize]) -> Vec<usize> {
    let mut local = vec![usize::MAX; model.n()];
    for (i, &r) in free.iter().enumerate() {
        local[r] = i;
    }
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); free.len()];
    for a in [&model.k, &model.m] {
        for (i, j, _) in a.triplets() {
            if i != j && local[i] != usize::MAX && local[j] != usize::MAX {
                adj[local[i]].push(local[j]);
            }
        }
    }
    reverse_cuthill_mckee(&adj).into_iter().map(|i| free[i]).collect()
}

/// The skyline envelope (first column of each row) of K and M in `order`.
fn envelope(model: &Imported, order: &[usize]) -> Vec<usize> {
    let mut pos = vec![usize::MAX; model.n()];
    for (p, &r) in order.iter().enumerate() {
        pos[r] = p;
    }
    let pairs = [&model.k, &model.m]
        .into_iter()
        .flat_map(|a| a.triplets())
        .filter(|t| pos[t.0] != usize::MAX && pos[t.1] != usize::MAX)
        .map(|(i, j, _)| (pos[i], pos[j]));
    Skyline::<f64>::envelope_of(order.len(), pairs)
}

fn profile(envelope: &[usize]) -> usize {
    envelope.iter().enumerate().map(|(i, &f)| i + 1 - f).sum()
}

/// D of the LDLᵀ of Σ cᵢ·Aᵢ + τ·I over `order`, or the position of a singular pivot.
fn factor(
    model: &Imported,
    order: &[usize],
    envelope: &[usize],
    terms: &[(f64, &Csr)],
    tau: f64,
) -> std::result::Result<Vec<f64>, usize> {
    let mut pos = vec![usize::MAX; model.n()];
    for (p, &r) in order.iter().enumerate() {
        pos[r] = p;
    }
    let mut s = Skyline::zeros(envelope.to_vec());
    for &(c, a) in terms {
        for (i, j, v) in a.triplets() {
            let (pi, pj) = (pos[i], pos[j]);
            if pi != usize::MAX && pj != usize::MAX && pj <= pi {
                s.add(pi, pj, c * v);
            }
        }
    }
    for p in 0..order.len() {
        s.add(p, p, tau);
    }
    match s.factorize() {
        Ok(f) => Ok(f.into_parts().3),
        Err(Error::Singular { row, .. }) => Err(row),
        Err(_) => Err(0),
    }
}
