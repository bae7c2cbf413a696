//! What an imported model's M and K must be: positive semi-definite, with no motion that
//! has neither mass nor stiffness. Judged from the inertia of LDLᵀ factorisations
//! (Sylvester's law: the number of negative pivots of K − σM is the number of eigenvalues
//! below σ), each failure naming the matrix file and a row's node and component.
//!
//! A singular M is normal (shell and frame elements often lump no rotary inertia) and is
//! not refused; a singular K means rigid-body modes, which are counted and reported.

use super::{Files, Imported, COMPONENTS};
use crate::error::{Error, Result};
use crate::linalg::{Csr, SparsePattern};

/// Eigenvalues below this fraction of the model's stiffness-to-mass scale count as zero
/// (rigid-body): far above the round-off of a zero eigenvalue (≈ ε of that scale) and far
/// below any elastic mode a structural model resolves.
pub const RIGID_FRACTION: f64 = 1e-12;

/// What the check found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Report {
    /// Eigenvalues of (K, M) below `rigid_below_hz` (rigid-body modes and mechanisms).
    pub rigid_body_modes: usize,
    pub rigid_below_hz: f64,
    /// Free rows with no mass on the diagonal (massless DOFs).
    pub massless_rows: usize,
    /// Whether definiteness was checked (false when the factor would not fit in half the
    /// machine's memory).
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
    let (k, m) = (model.k.restricted(&free), model.m.restricted(&free));
    let pattern = SparsePattern::analyse(&[&k, &m])?;
    if pattern.factor_bytes() > crate::analysis::budget::machine_memory() / 2 {
        return Ok(report);
    }
    let identity = Csr::from_triplets(free.len(), &(0..free.len()).map(|i| (i, i, 1.0)).collect::<Vec<_>>());
    // A row of a singular factorisation, by its place among the free rows.
    let row_of = |e: Error| match e {
        Error::Singular { row, .. } if row < free.len() => name(free[row]),
        _ => "rows".to_string(),
    };
    // M ⪰ 0: M + τ·I has no negative pivot (τ lifts massless rows off zero).
    let mp = SparsePattern::analyse(&[&m, &identity])?;
    let negative = mp
        .factorize(&[(1.0, &m), (RIGID_FRACTION * m_max, &identity)])
        .map_err(|e| Error::input(&mfile, row_of(e), "the mass matrix is singular beyond its massless rows"))?
        .negative_pivots();
    semi_definite(&mfile, "mass", negative)?;
    // K ⪰ 0 relative to M, and no motion without mass and stiffness: K + σM is regular
    // with no negative pivot; K − σM's negative pivots count the rigid-body modes.
    let sigma = RIGID_FRACTION * k_max / m_max;
    report.rigid_below_hz = sigma.sqrt() / (2.0 * std::f64::consts::PI);
    let negative = pattern
        .factorize(&[(1.0, &k), (sigma, &m)])
        .map_err(|e| {
            Error::input(
                &kfile,
                row_of(e),
                "this DOF (or a motion through it) has neither stiffness nor mass: hold it (`imported.fixed`) or \
                 give it mass",
            )
        })?
        .negative_pivots();
    semi_definite(&kfile, "stiffness", negative)?;
    // K − σM singular means σ hit an eigenvalue: count at a slightly larger shift.
    let below = |s: f64| pattern.factorize(&[(1.0, &k), (-s, &m)]).map(|f| f.negative_pivots());
    report.rigid_body_modes = below(sigma).or_else(|_| below(2.0 * sigma)).unwrap_or(0);
    report.definiteness_checked = true;
    Ok(report)
}

/// An error naming `file` if its matrix (`what`: mass, stiffness) has `negative`
/// negative eigenvalues.
fn semi_definite(file: &str, what: &str, negative: usize) -> Result<()> {
    if negative > 0 {
        return Err(Error::input(
            file,
            "entries",
            format!("the {what} matrix has {negative} negative eigenvalue(s): it must be positive semi-definite"),
        ));
    }
    Ok(())
}
