//! The round-off a mesh brings into the harmonic and steady-state solves, removed where
//! it matters and bounded everywhere.
//!
//! Why the error: the assembled stiffness's entries are ~EI/h³ and a smooth response
//! cancels them by ~elements⁴, so the LDLᵀ of the assembled K − ω²M + iωC loses
//! ε·elements⁴ (measured 1.5e-5·(elements/1000)⁴ of a point mobility: 2e-5 at 1,000
//! elements, O(1) at 20,000). No factorisation of the assembled matrix avoids it: the
//! rounding of its entries alone does it.
//!
//! The cure ([`crate::solve::refine`]): residuals r = b − A·x computed from the elements'
//! curvature rows, A·x = (1 + iωa₁ + iη)·Gᵀ(G·x) + the ties (grounded springs, links) +
//! the masses ([`crate::assembly::rows::StiffnessRows`]), the rows and ties in compensated
//! sums (twice the working precision, [`crate::simd::twofold`]) from rows themselves exact
//! to that precision, and GMRES-based iterative refinement preconditioned by the assembled
//! factor (whose error sits in the few smooth modes, so GMRES needs few iterations even
//! where ε·cond ≳ 1). Every solve also gets its error estimate per DOF from the same
//! residual (the first-order error F⁻¹r of the factor's solution, or the last correction
//! of a refined one, plus what can still separate the residual from the exact model's —
//! the mass matrices' rounding, ~ε of the inertia forces — carried through the solve).
//! Only a solve whose bound is stated pays for the compensated residual: the harmonic
//! count's solves, which only judge, take the residual in doubles (ε·elements² of the
//! stiffness forces), which is as much as they need.
//!
//! Refinement runs only where that first estimate exceeds a hundredth of the tolerance
//! (relative, Euclidean over the DOFs): on ordinary meshes the factor's solution is kept
//! bit for bit, and only the bound is new. A steady state's harmonic is also kept where
//! its estimate takes no more than its share of every point power's tolerance
//! ([`MeshRefinement::refine_unless`]; the shares in `steady_state::Shares`): the higher
//! harmonics, whose part of the power is small, need far less of their solution than the
//! tolerance asks of the whole.
//!
//! The stated bound is per point power, cancellation included: a power P = ½Re Σ_k F̄_k·v_k
//! with errors |δF_k|, |δv_k| from the DOF errors is off by at most
//! ½Σ_k(|F_k||δv_k| + |δF_k||v_k| + |δF_k||δv_k|) ([`crate::power::point::mean_power_error`]),
//! relative to |P|: a point whose active power is small beside its apparent power gets the
//! larger bound it needs. A mobility's bound is its DOF's error over its amplitude. A
//! result's `mesh_roundoff` is the largest over its points.
//!
//! The transient's step on a mesh beyond the envelope's bound takes −K·u from the same rows
//! and refines each increment against them (`solve::band_newmark::accurate`); its periodic
//! state is then measured against the refined frequency-domain one, whose bound it states.
//! On coarser meshes it states the measured envelope [`envelope`].

use crate::assembly::rows::StiffnessRows;
use crate::assembly::{Model, System};
use crate::error::{Error, Result};
use crate::solve::dynamic_stiffness::DynamicStiffness;
use crate::solve::refine::{estimate, refine, working_residual, Refinable, Refined};
use num_complex::Complex64;

/// The default relative tolerance of point powers and mobilities.
pub const DEFAULT_TOLERANCE: f64 = 1e-6;

/// Refinement starts where the factor's own error estimate exceeds this fraction of the
/// tolerance, and stops when a correction falls below [`STEP_FRACTION`] of it.
pub const REFINE_FRACTION: f64 = 1e-2;
const STEP_FRACTION: f64 = 1e-4;

/// The measured envelope of the unrefined solves' round-off: 1.5e-5·(N/1000)⁴ for N
/// elements along the structure (a beam's elements, a plate's along its longer side, where
/// the cancellation of a smooth response is the same in h⁴; 0 without a structure). What
/// the transient states.
pub fn envelope(model: &Model) -> f64 {
    1.5e-5 * (elements_along(model) as f64 / 1000.0).powi(4)
}

/// The measured envelope of a transient step that takes its stiffness from the element rows
/// and refines its increments (`solve::band_newmark::accurate`): 1e-9·(N/20,000)² for N
/// elements along the structure, where the rows' product in doubles cancels by ~N². The
/// largest error measured, a point power at 60 Hz against the exact beam, was 1.3e-11 at
/// 20,000 elements (3.5e-12 at 1,000, 1.2e-13 at 5,000): the envelope is ≥ 77× that. What
/// a run states where no refined periodic state bounds it (a non-periodic drive).
pub fn refined_step_envelope(model: &Model) -> f64 {
    1e-9 * (elements_along(model) as f64 / 20_000.0).powi(2)
}

/// Elements along the structure's longest line of elements (0 without a structure).
fn elements_along(model: &Model) -> usize {
    match &model.structure {
        Some(crate::structure::Structure::Beam(b)) => b.mesh.elements.len(),
        Some(crate::structure::Structure::Plate(p)) => p.grid.nx().max(p.grid.ny()),
        // A chain through every node is the longest line of elements a mesh can hold, so
        // the envelope it gives bounds any imported mesh's.
        Some(crate::structure::Structure::Imported(m)) => m.nodes.len(),
        None => 0,
    }
}

/// The envelope's margin for a point whose active power is small beside its apparent power:
/// the largest such excess measured is the frame's legs at 30 Hz on 500 elements, 6.9e-6
/// against the envelope's 9.4e-7 (7.3×).
const CANCELLATION_MARGIN: f64 = 10.0;

/// The stated bound of a steady state on a mesh coarse enough that its solves are not
/// estimated one by one: the measured envelope with [`CANCELLATION_MARGIN`], where that is
/// within the tolerance (up to 286 elements at the default 1e-6). Estimating each solve
/// costs a residual, its rounding and two back-substitutions, three times a sweep's whole
/// solve on the paper beam; below this size the estimate could only confirm the envelope.
pub fn coarse_bound(model: &Model) -> Option<f64> {
    let bound = CANCELLATION_MARGIN * envelope(model);
    (bound <= model.roundoff_tolerance).then_some(bound)
}

/// The transient step's −K·u from the element rows ([`StiffnessRows::subtract_stiffness`]).
pub struct RowStiffness(pub StiffnessRows);

impl crate::solve::band_newmark::StiffnessProduct for RowStiffness {
    fn subtract(&self, x: &[f64], z: &mut [f64]) {
        self.0.subtract_stiffness(x, z);
    }
    fn quadratic(&self, x: &[f64]) -> f64 {
        let (structure, links) = self.0.strain_energies(x);
        2.0 * (structure + links)
    }
}

impl crate::power::energy::StrainEnergy for RowStiffness {
    fn structure_and_links(&self, u: &[f64]) -> (f64, f64) {
        self.0.strain_energies(u)
    }
}

/// The refinement of one system's solves.
pub struct MeshRefinement {
    rows: Option<StiffnessRows>,
    tolerance: f64,
}

/// One factorisation seen as a [`Refinable`].
struct Lane<'a> {
    rows: &'a StiffnessRows,
    dk: &'a DynamicStiffness,
    lane: usize,
    c_m: Complex64,
    c_c: Complex64,
    /// Whether the residual is compensated ([`StiffnessRows::residual`]): where a bound is
    /// stated. Without, the residual is in doubles — enough to refine a solution whose
    /// estimate only judges it (the harmonic count's), at a quarter of the cost — and no
    /// floor is asked of it.
    accurate: bool,
}

impl<'a> Lane<'a> {
    fn of(rows: &'a StiffnessRows, dk: &'a DynamicStiffness, lane: usize, accurate: bool) -> Self {
        let (c_m, c_c) = dk.coefficients(lane);
        Lane { rows, dk, lane, c_m, c_c, accurate }
    }
}

impl Refinable for Lane<'_> {
    fn apply(&self, x: &[Complex64], y: &mut [Complex64]) {
        self.rows.apply(self.c_m, self.c_c, x, y);
    }
    fn residual(&self, b: &[Complex64], x: &[Complex64], r: &mut [Complex64]) {
        if self.accurate {
            self.rows.residual(self.c_m, self.c_c, b, x, r);
        } else {
            working_residual(self, b, x, r);
        }
    }
    fn rounding(&self, x: &[Complex64]) -> Vec<Vec<Complex64>> {
        self.rows.rounding(self.c_m, self.c_c, x).into()
    }
    fn precondition(&self, x: &mut [Complex64]) {
        self.dk.solve_lane(self.lane, x);
    }
}

/// The Euclidean norm.
fn norm(x: &[Complex64]) -> f64 {
    x.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt()
}

impl MeshRefinement {
    /// For `sys` assembled from `model`, to the model's tolerance. A reduced system or one
    /// without a beam has no element rows: its solves keep the factor's solution, with the
    /// error estimate ε·|x|.
    pub fn new(model: &Model, sys: &System) -> Result<Self> {
        Ok(MeshRefinement { rows: StiffnessRows::of(model, sys)?, tolerance: model.roundoff_tolerance })
    }

    /// `x` holds the solution from factorisation `lane` of `dk` for right-hand side `b`:
    /// refines it if its error estimate exceeds [`REFINE_FRACTION`] of the tolerance, and
    /// returns the estimate of the error left.
    pub fn refine(&self, dk: &DynamicStiffness, lane: usize, b: &[Complex64], x: &mut [Complex64]) -> Refined {
        self.refine_unless(None, dk, lane, b, x, |_, _| false, true)
    }

    /// [`MeshRefinement::refine`], refining whatever the first estimate when `always` (a
    /// point quantity's own bound can exceed the tolerance where the whole solution's
    /// error is small: a point that moves little, a power that cancels).
    pub fn refine_if(
        &self,
        dk: &DynamicStiffness,
        lane: usize,
        b: &[Complex64],
        x: &mut [Complex64],
        always: bool,
    ) -> Refined {
        match (&self.rows, always) {
            (Some(rows), true) => {
                let op = Lane::of(rows, dk, lane, true);
                refine(&op, b, x, STEP_FRACTION * self.tolerance).with_floor(&op, x)
            }
            _ => self.refine(dk, lane, b, x),
        }
    }

    /// The first estimates ([`estimate`]) of the solutions `x[l]` from lane l of a pair
    /// factorised in `dk` for right-hand sides `b[l]` (one or two lanes): both residuals, then
    /// one paired solve for both corrections, in about the time of one (a solve of this size
    /// is a chain of dependent rows; two chains run side by side). The same bits as
    /// [`estimate`] lane by lane. None without element rows.
    pub fn first_estimates(
        &self,
        dk: &DynamicStiffness,
        b: &[&[Complex64]],
        x: &[&[Complex64]],
        floor: bool,
    ) -> Option<Vec<Refined>> {
        let rows = self.rows.as_ref()?;
        let mut r: Vec<Vec<Complex64>> = (0..b.len())
            .map(|lane| {
                let mut r = vec![Complex64::default(); x[lane].len()];
                Lane::of(rows, dk, lane, floor).residual(b[lane], x[lane], &mut r);
                r
            })
            .collect();
        dk.solve_lanes(&mut r);
        Some(
            r.into_iter()
                .map(|mut c| {
                    c.iter_mut().for_each(|d| *d *= 2.0);
                    Refined { correction: c, ..Default::default() }
                })
                .collect(),
        )
    }

    /// [`MeshRefinement::refine`], leaving `x` as the factor gave it also where `enough`
    /// accepts its first estimate (without the floor, which refinement cannot shrink): the
    /// caller's judgement of what the quantities it forms from `x` need (a harmonic whose
    /// share of every point power is small needs far less of the solution than the
    /// tolerance asks of the whole). Without `floor` the estimate is the correction alone:
    /// enough to judge x by, not to state a bound with.
    /// `first` is x's first estimate where it is already known
    /// ([`MeshRefinement::first_estimates`]), None to compute it here.
    #[allow(clippy::too_many_arguments)]
    pub fn refine_unless(
        &self,
        first: Option<Refined>,
        dk: &DynamicStiffness,
        lane: usize,
        b: &[Complex64],
        x: &mut [Complex64],
        enough: impl Fn(&[Complex64], &Refined) -> bool,
        floor: bool,
    ) -> Refined {
        let Some(rows) = &self.rows else { return Refined::default() };
        let op = Lane::of(rows, dk, lane, floor);
        let first = first.unwrap_or_else(|| estimate(&op, b, x));
        let held = norm(&first.correction) <= REFINE_FRACTION * self.tolerance * norm(x);
        let kept = if held || enough(x, &first) { first } else { refine(&op, b, x, STEP_FRACTION * self.tolerance) };
        if floor {
            kept.with_floor(&op, x)
        } else {
            kept
        }
    }

    /// Whether a solve can be refined (a beam's element rows are there).
    pub fn can_refine(&self) -> bool {
        self.rows.is_some()
    }

    /// The tolerance the solves are held to.
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// The power the structure dissipates in harmonic motion `q` at ω (rad/s), from the
    /// element rows where there are (the assembled K's round-off would show in a smooth
    /// motion's Qᴴ·K·Q as it does in the solve), else from the assembled matrices.
    pub fn dissipation(&self, sys: &System, q: &[Complex64], omega: f64) -> f64 {
        match &self.rows {
            Some(rows) => rows.dissipation(q, omega),
            None => crate::power::point::beam_dissipation(sys, q, omega),
        }
    }
}

/// The relative bound of a point quantity from its absolute bound (0 where the quantity is
/// exactly zero: a point that receives nothing has no relative error to state).
pub fn relative(bound: f64, value: f64) -> f64 {
    if value == 0.0 {
        0.0
    } else {
        bound / value.abs()
    }
}

/// Whether a result holds its tolerance; a message saying what to do where it does not,
/// as a refusal when the case asks to be strict (`beam.mesh.strict_roundoff`).
pub fn check(model: &Model, strict: bool, analysis: &str, bound: f64) -> Result<Option<String>> {
    let tolerance = model.roundoff_tolerance;
    if bound <= tolerance {
        return Ok(None);
    }
    let elements = elements_along(model);
    let text = format!(
        "{analysis}: the round-off bound of the point powers and mobilities on {elements} elements is {bound:.1e}, \
         above the tolerance {tolerance:.0e} (`beam.mesh.roundoff_tolerance`); a point whose active power is small \
         beside its apparent power needs a coarser mesh or a looser tolerance"
    );
    if strict {
        return Err(Error::case_field("beam.mesh.roundoff_tolerance", format!("{text} (strict_roundoff = true)")));
    }
    Ok(Some(text))
}
