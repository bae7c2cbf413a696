//! Natural modes of the bare beam, with closed-form references where they exist.

use crate::beam::analytic::{natural_frequencies_hz, End};
use crate::beam::{Beam, SupportKind};
use crate::case::build::{bare_modes_of, bare_system};
use crate::error::Result;
use crate::solve::eigen::Modes;
use serde::Serialize;

/// Modal analysis result.
#[derive(Clone, Debug, Serialize)]
pub struct ModesResult {
    pub frequencies_hz: Vec<f64>,
    /// Closed-form frequencies (Hz) for a uniform beam with plain end supports, else empty.
    pub analytic_hz: Vec<f64>,
    /// (f − f_analytic)/f_analytic per mode, where a reference exists.
    pub relative_error: Vec<f64>,
    /// Description of the reference used.
    pub reference: String,
    /// Order-of-magnitude bound on each frequency's relative round-off error. With K from
    /// its element rows (every supported structure): ε·ω_max/ω_r, ω_max² ≈ max_i(K_ii/M_ii),
    /// which grows as (elements)² (about 5e-7 for mode 1 of the paper beam at 50,000
    /// elements; measured errors sit two orders below). With K as assembled (unsupported
    /// structures): ε·(ω_max/ω_r)²/2, growing as (elements)⁴. See docs/physics-notes.md.
    pub roundoff_bound: Vec<f64>,
    #[serde(skip)]
    pub modes: Modes,
    /// Node coordinates (m) and the w of each mode at each node (row per mode).
    #[serde(skip)]
    pub node_x: Vec<f64>,
    #[serde(skip)]
    pub shapes_w: Vec<Vec<f64>>,
}

/// End conditions of a beam supported only at its two ends, if it is uniform and bare.
pub fn plain_ends(beam: &Beam) -> Option<(End, End)> {
    let mesh = &beam.mesh;
    let e0 = mesh.elements.first()?;
    let uniform = mesh
        .elements
        .iter()
        .all(|e| (e.ei - e0.ei).abs() <= 1e-12 * e0.ei && (e.rho_a - e0.rho_a).abs() <= 1e-12 * e0.rho_a);
    if !uniform || !beam.point_masses.is_empty() || !beam.springs.is_empty() {
        return None;
    }
    let last = mesh.n_nodes() - 1;
    let mut ends = [End::Free, End::Free];
    for s in &beam.supports {
        let slot = if s.node == 0 {
            0
        } else if s.node == last {
            1
        } else {
            return None;
        };
        ends[slot] = match s.kind {
            SupportKind::Clamped => End::Clamped,
            SupportKind::Pinned => End::Pinned,
            _ => return None,
        };
    }
    Some((ends[0], ends[1]))
}

pub fn run(beam: &Beam, count: usize) -> Result<ModesResult> {
    // One assembly for the solver, the round-off bound and the node-wise shapes.
    let sys = bare_system(beam)?;
    let modes = bare_modes_of(beam, &sys, count)?;
    let f = modes.frequencies_hz();
    let mut analytic = Vec::new();
    let mut reference = String::from("none (no closed form for this beam)");
    if let Some((l, r)) = plain_ends(beam) {
        let e = &beam.mesh.elements[0];
        // A free–free beam's first two modes are rigid; compare flexible modes only where
        // the numbering agrees.
        let rigid = [l, r].iter().filter(|&&x| x == End::Free).count();
        if rigid == 0 {
            if let Some(a) = natural_frequencies_hz(l, r, beam.mesh.length(), e.ei, e.rho_a, f.len()) {
                analytic = a;
                reference = format!("uniform Euler–Bernoulli beam, {l:?}–{r:?}");
            }
        }
    }
    let relative_error = analytic.iter().zip(&f).map(|(a, x)| (x - a) / a).collect();
    let mut stiffest = 0.0f64;
    for i in 0..sys.n() {
        let (k, m) = (sys.k.get(i, i), sys.m.get(i, i));
        if m > 0.0 {
            stiffest = stiffest.max(k / m);
        }
    }
    let roundoff_bound = modes
        .omega
        .iter()
        .map(|w| {
            // ω_max²/ω_r²: how far the stiffest DOF's scale is above this mode's energy.
            let ratio = stiffest / (w * w).max(f64::MIN_POSITIVE);
            if modes.from_root {
                f64::EPSILON * ratio.sqrt()
            } else {
                0.5 * f64::EPSILON * ratio
            }
        })
        .collect();
    // w of each mode at each node, from the bare system's numbering.
    let shapes_w = (0..modes.count())
        .map(|r| {
            let g = modes.shape_global(r, sys.n());
            sys.dofs.w.iter().map(|d| d.map_or(0.0, |d| g[d])).collect()
        })
        .collect();
    Ok(ModesResult {
        frequencies_hz: f,
        analytic_hz: analytic,
        relative_error,
        reference,
        roundoff_bound,
        node_x: beam.mesh.x.clone(),
        shapes_w,
        modes,
    })
}
