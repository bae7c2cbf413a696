//! What must be settled about a model before its analyses run.
//!
//! The case layer builds the model exactly as written; damping stated as a ratio at the
//! bare beam's modes needs those modes, so it is calibrated here, by an eigen-analysis,
//! once per model. Errors of the model's own settings are named in the case file at this
//! boundary.

use super::budget::Budget;
use super::cost;
use super::modes::{bare_system, few_bare_modes_of, rigid_body_count, stiffest_ratio};
use crate::assembly::{Damping, DofMap, Model, Rayleigh, System};
use crate::case::{build_model, LoadedCase};
use crate::error::{Error, Result};
use crate::structure::Structure;

/// The model a case describes, with its damping calibrated: the model every analysis runs.
pub fn calibrated_model(lc: &LoadedCase) -> Result<Model> {
    let mut model = build_model(lc)?;
    calibrate(&mut model).map_err(|e| e.in_file(&lc.file))?;
    Ok(model)
}

/// The calibrated model and its assembled system, errors named in the case file, within
/// the machine's default [`Budget`] (what the Python package builds).
pub fn model_and_system(lc: &LoadedCase) -> Result<(Model, System)> {
    model_and_system_within(lc, &Budget::default())
}

/// [`model_and_system`] within `budget`: the mesh is sized before it is built, and the
/// model (its DOFs and the modes its damping is calibrated at) before it is calibrated
/// and assembled. (Fine meshes are not refused: the solves refine against their round-off,
/// see [`crate::analysis::roundoff`].)
pub fn model_and_system_within(lc: &LoadedCase, budget: &Budget) -> Result<(Model, System)> {
    let mut model = built_within(lc, budget)?;
    calibrate(&mut model).map_err(|e| e.in_file(&lc.file))?;
    let system = System::assemble(&model).map_err(|e| e.in_file(&lc.file))?;
    Ok((model, system))
}

/// The case's model built exactly as written, its mesh held to `budget` before it is
/// built and the model after: the checks of `beamflow check` that need the structure (an
/// imported model's node ids and components, points on a plate, a frame's feet), without
/// calibrating damping or assembling.
pub fn built_within(lc: &LoadedCase, budget: &Budget) -> Result<Model> {
    if let Some(c) = cost::mesh(lc) {
        budget.admit(&c).map_err(|e| e.in_file(&lc.file))?;
    }
    if let (crate::case::BaseKind::Beam, Some((_, file))) = (lc.case.base, lc.case.mesh_file()) {
        // Counted from the text before it is parsed; unreadable files are left to the
        // build, which names the field.
        if let Ok(text) = crate::input_file::read_text(&lc.dir.join(file)) {
            if let Some(c) = cost::mesh_file(lc, &text) {
                budget.admit(&c).map_err(|e| e.in_file(&lc.file))?;
            }
        }
    }
    let model = build_model(lc)?;
    budget.admit(&cost::model(&model)).map_err(|e| e.in_file(&lc.file))?;
    Ok(model)
}

/// Turns Rayleigh damping given by ratio into its coefficients (other damping is left as
/// it is). A model without a beam has no structural damping to calibrate.
pub fn calibrate(model: &mut Model) -> Result<()> {
    if let Damping::RayleighRatio { zeta, modes } = model.damping {
        model.damping = match &model.structure {
            Some(structure) => Damping::Rayleigh(rayleigh_from_ratio(structure, zeta, modes)?),
            None => Damping::None,
        };
    }
    Ok(())
}

/// Rayleigh coefficients giving damping ratio ζ at the bare structure's modes `modes`
/// (1-based). Refuses a rigid-body mode (a structure not held against rigid motion): a
/// damping ratio there has no meaning, and a₀, a₁ set from a zero frequency would damp the
/// elastic modes by orders of magnitude.
pub fn rayleigh_from_ratio(structure: &Structure, zeta: f64, modes: [usize; 2]) -> Result<Rayleigh> {
    let need = modes[0].max(modes[1]);
    let numbering = DofMap::number(Some(structure), &[], &[]);
    let uncomputable = |e: Error| match numbering.locate(e, Some(structure)) {
        e @ (Error::Numerical(_) | Error::Singular { .. }) => Error::case_field(
            "damping",
            format!(
                "the damping ratio is calibrated at the bare {}'s modes, which cannot be computed: {e}",
                structure.kind()
            ),
        ),
        e => e,
    };
    let sys = bare_system(structure).map_err(uncomputable)?;
    let m = few_bare_modes_of(structure, &sys, need).map_err(uncomputable)?;
    if m.count() < need {
        return Err(Error::case_field("damping.modes", format!("the mesh has only {} modes", m.count())));
    }
    let stiffest = stiffest_ratio(&sys);
    if rigid_body_count(&m, stiffest) >= modes[0].min(modes[1]) {
        // Count them all (a free body has up to six), for the modes to give instead.
        let rigid = match few_bare_modes_of(structure, &sys, need + 6) {
            Ok(more) => rigid_body_count(&more, stiffest),
            Err(_) => rigid_body_count(&m, stiffest),
        };
        let span = if rigid == 1 {
            "mode 1 is a rigid-body mode".to_string()
        } else {
            format!("modes 1–{rigid} are rigid-body modes")
        };
        return Err(Error::case_field(
            "damping.modes",
            format!(
                "{span} of the bare {} (it is not held against rigid motion; frequencies zero up to round-off), \
                 where a damping ratio has no meaning: give elastic modes, e.g. `[damping]` modes = [{}, {}] \
                 (without a `[damping]` table the ratio is set at modes 1 and 3)",
                structure.noun(),
                rigid + 1,
                rigid + 3
            ),
        ));
    }
    Ok(Rayleigh::from_ratio(zeta, m.omega[modes[0] - 1], m.omega[modes[1] - 1]))
}

/// Refuses damping that the assembled M, C, K in physical coordinates do not carry, for an
/// analysis (`analysis` names it in the message) that integrates them. Modal damping is a
/// matrix only in the bare beam's modal coordinates (over the beam DOFs it is dense): the
/// harmonic analysis applies it as a modal sum, the steady state in the complete modal
/// basis and a transient on its modal reduction; an analysis that integrates the assembled
/// matrices (a transient without `reduction`, a sweep) refuses it rather than run undamped.
pub fn require_viscous_damping(model: &Model, analysis: &str) -> Result<()> {
    if model.modal_ratios().is_some() {
        return Err(Error::case_field(
            "damping.kind",
            format!(
                "\"modal\" damping is applied by harmonic and steady-state analyses and by transients with a \
                 modal `reduction` (e.g. reduction = \"auto\"); a {analysis} needs \"rayleigh_ratio\", \
                 \"rayleigh\" or \"none\""
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::analytic::{natural_frequencies_hz, End};

    fn case(damping: &str) -> LoadedCase {
        LoadedCase::from_str(&format!("[damping]\n{damping}\n"), "plan.toml", ".".into()).unwrap()
    }

    #[test]
    fn ratio_damping_is_calibrated_at_the_named_modes() {
        let lc = case("kind = \"rayleigh_ratio\"\nzeta = 0.02\nmodes = [1, 3]");
        let raw = build_model(&lc).unwrap();
        assert!(matches!(raw.damping, Damping::RayleighRatio { .. }));
        assert!(crate::assembly::System::assemble(&raw).is_err(), "assembly refuses an uncalibrated ratio");
        let model = calibrated_model(&lc).unwrap();
        let r = model.rayleigh();
        // Closed-form clamped–clamped frequencies of the paper's beam: the calibrated ratio
        // is ζ at modes 1 and 3 to the mesh's discretisation error.
        let b = &lc.case.beam;
        let ei = b.youngs_modulus * b.width * b.thickness.powi(3) / 12.0;
        let rho_a = b.density * b.width * b.thickness;
        let f = natural_frequencies_hz(End::Clamped, End::Clamped, b.length, ei, rho_a, 3).unwrap();
        for hz in [f[0], f[2]] {
            let zeta = r.ratio_at(2.0 * std::f64::consts::PI * hz);
            assert!((zeta - 0.02).abs() < 1e-5, "ζ = {zeta} at {hz} Hz");
        }
    }

    #[test]
    fn too_few_modes_are_named_in_the_case_file() {
        let lc = LoadedCase::from_str(
            "[beam.mesh]\nelements = 2\n[damping]\nkind = \"rayleigh_ratio\"\nzeta = 0.02\nmodes = [1, 40]\n",
            "plan.toml",
            ".".into(),
        );
        // The schema may already refuse it; either way the message names file and field.
        let msg = match lc {
            Err(e) => e.to_string(),
            Ok(lc) => calibrated_model(&lc).unwrap_err().to_string(),
        };
        assert!(msg.contains("plan.toml") && msg.contains("damping.modes"), "{msg}");
    }
}
