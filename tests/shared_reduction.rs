//! Placement studies on one modal reduction shared by their cases (plates and imported
//! models): each case's reduced system against the same case on the full model, the sweep
//! and the optimiser against their runs on the full model, and a case run alone against
//! the study's number for it.

use beamflow::analysis::plan::calibrated_model;
use beamflow::analysis::reduction::{self, Cutoff, ReductionSettings, SharedReduction};
use beamflow::analysis::steady_state;
use beamflow::assembly::{Model, System};
use beamflow::case::LoadedCase;
use beamflow::{optimize, sweep};
use std::path::{Path, PathBuf};

/// The example plate (spec §16) on one uniform 16 × 12 grid, a frame turned 30° at `at`
/// (between nodes), 83 Hz; `reduction` the steady state's option ("" for none).
fn plate_case(at: [f64; 2], reduction: &str) -> String {
    format!(
        "[plate]\nlength_x = 0.5\nlength_y = 0.4\nthickness = 0.003\nyoungs_modulus = 70e9\npoisson_ratio = 0.33\n\
         density = 2700.0\n[plate.mesh]\nelements = [16, 12]\nthrough_points = false\n[plate.edges]\n\
         x0 = \"simply_supported\"\nx1 = \"simply_supported\"\ny0 = \"clamped\"\ny1 = \"simply_supported\"\n\
         [damping]\nkind = \"rayleigh_ratio\"\nzeta = 0.01\nmodes = [1, 3]\n\
         [[actuator]]\ntype = \"frame\"\nname = \"frame\"\nat = [{}, {}]\ndirection = 30.0\n\
         [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 83.0\n\
         [[analysis]]\ntype = \"steady_state\"\n{reduction}\n",
        at[0], at[1]
    )
}

fn model(text: &str) -> Model {
    calibrated_model(&LoadedCase::from_str(text, "plate.toml", PathBuf::from(".")).unwrap()).unwrap()
}

fn max_rel(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter().zip(b).map(|(x, y)| (x - y).abs() / y.abs().max(1e-6 * scale)).fold(0.0, f64::max)
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("beamflow-shared-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn placements_on_one_shared_basis_match_the_full_plate() {
    let settings = ReductionSettings {
        cutoff: Cutoff::HarmonicFactor(reduction::AUTO_FACTOR),
        static_correction: true,
        error_estimate: false,
        modal_damping: None,
    };
    let first = model(&plate_case([0.173, 0.228], ""));
    let cutoff = reduction::cutoff_hz(&first, &settings, 9).unwrap();
    let shared = SharedReduction::new(&first, &settings, cutoff).unwrap();
    // Two placements, one basis: the second's feet fall in other elements.
    for at in [[0.173, 0.228], [0.331, 0.107]] {
        let m = model(&plate_case(at, ""));
        let full = steady_state::run(&m, &System::assemble(&m).unwrap(), 9, 256).unwrap();
        let (sys, report) = shared.system(&m).unwrap();
        assert!(report.residual_vectors <= 3, "one residual vector per foot pattern: {}", report.residual_vectors);
        assert!(report.reduced_dofs < report.full_dofs / 5, "{} of {}", report.reduced_dofs, report.full_dofs);
        let red = steady_state::run(&m, &sys, 9, 256).unwrap();
        let e = max_rel(&red.mean_power, &full.mean_power).max(max_rel(&red.net_power, &full.net_power));
        assert!(e < 1e-6, "at {at:?}: reduced point powers {:?} vs full {:?}: {e:e}", red.mean_power, full.mean_power);
        // Without the static correction the same modes miss the legs' local flexibility.
        let bare =
            SharedReduction::new(&m, &ReductionSettings { static_correction: false, ..settings.clone() }, cutoff)
                .unwrap();
        let r0 = steady_state::run(&m, &bare.system(&m).unwrap().0, 9, 256).unwrap();
        let e0 = max_rel(&r0.mean_power, &full.mean_power);
        assert!(e0 > 100.0 * e, "the correction matters: {e0:e} without, {e:e} with");
    }
}

/// Static shapes solved up front in blocks of right-hand sides, kept per DOF for later
/// cases and summed into each pattern's shape, reduce each case as its own solve of the
/// pattern does: to round-off carried through K's conditioning (the two are different sums
/// of K⁻¹'s rounding, and the residual flexibility takes a difference of them).
#[test]
fn kept_static_shapes_reduce_as_a_cases_own_solve() {
    let settings = ReductionSettings {
        cutoff: Cutoff::HarmonicFactor(reduction::AUTO_FACTOR),
        static_correction: true,
        error_estimate: false,
        modal_damping: None,
    };
    let models: Vec<Model> =
        [[0.173, 0.228], [0.331, 0.107], [0.25, 0.2]].iter().map(|&at| model(&plate_case(at, ""))).collect();
    let cutoff = reduction::cutoff_hz(&models[0], &settings, 9).unwrap();
    let own = SharedReduction::new(&models[0], &settings, cutoff).unwrap().with_shape_cache(0);
    let kept = SharedReduction::new(&models[0], &settings, cutoff).unwrap();
    let patterns: Vec<_> = models.iter().flat_map(|m| kept.attachment_patterns(m).unwrap()).collect();
    let mut distinct = patterns.clone();
    distinct.dedup();
    assert!(distinct.len() >= 6, "two feet per frame: {}", distinct.len());
    // One unit load's shape per structure DOF the patterns touch.
    let mut dofs: Vec<usize> = patterns.iter().flatten().map(|&(d, _)| d).collect();
    dofs.sort_unstable();
    dofs.dedup();
    assert_eq!(kept.prefetch(&patterns), dofs.len());
    assert_eq!(kept.prefetch(&patterns), 0, "each shape is solved once");
    assert_eq!(own.prefetch(&patterns), 0, "no room: every case solves its own");
    for m in &models {
        let a = steady_state::run(m, &own.system(m).unwrap().0, 9, 256).unwrap();
        let b = steady_state::run(m, &kept.system(m).unwrap().0, 9, 256).unwrap();
        let e = max_rel(&b.mean_power, &a.mean_power)
            .max(max_rel(&b.net_power, &a.net_power))
            .max(max_rel(&[b.beam_dissipation], &[a.beam_dissipation]));
        assert!(e < 1e-10, "kept {:?} against own {:?}: {e:e}", b.mean_power, a.mean_power);
    }
}

#[test]
fn a_case_run_alone_is_reduced_as_the_study_reduces_it() {
    // The case-level reduction of a plate is the shared basis built for that case alone:
    // the same system, so a study's number for a case is the case's own.
    let m = model(&plate_case([0.21, 0.17], "reduction = \"auto\""));
    let settings = ReductionSettings {
        cutoff: Cutoff::HarmonicFactor(reduction::AUTO_FACTOR),
        static_correction: true,
        error_estimate: false,
        modal_damping: None,
    };
    let cutoff = reduction::cutoff_hz(&m, &settings, 9).unwrap();
    let full = System::assemble(&m).unwrap();
    let (a, _) = reduction::reduce(&m, &full, &settings, cutoff).unwrap();
    let (b, _) = SharedReduction::new(&m, &settings, cutoff).unwrap().system(&m).unwrap();
    let (ra, rb) = (steady_state::run(&m, &a, 9, 256).unwrap(), steady_state::run(&m, &b, 9, 256).unwrap());
    assert_eq!(ra.mean_power, rb.mean_power);
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

const POSITIONS: &str = "[[parameter]]\npath = \"actuator[0].at[0]\"\nstart = 0.06\nstop = 0.44\ncount = 5\n\
    [[parameter]]\npath = \"actuator[0].at[1]\"\nstart = 0.06\nstop = 0.34\ncount = 4\n";

#[test]
fn a_reduced_plate_sweep_matches_the_full_sweep_and_states_its_check() {
    let d = scratch("sweep");
    write(&d, "reduced.toml", &plate_case([0.2, 0.2], "reduction = \"auto\""));
    write(&d, "full.toml", &plate_case([0.2, 0.2], ""));
    let run = |base: &str, threads: usize| {
        let text = format!("base = \"{base}\"\nharmonics = 9\n{POSITIONS}");
        let s = sweep::Sweep::from_str(&text, &format!("{base}.sweep.toml"), &d).unwrap();
        sweep::run(&s, &sweep::RunOptions { threads: Some(threads), ..Default::default() }).unwrap()
    };
    let (reduced, full) = (run("reduced.toml", 2), run("full.toml", 2));
    assert!(full.reduction.is_none());
    for (r, f) in reduced.rows.iter().zip(&full.rows) {
        let e = max_rel(&r.mean_power, &f.mean_power).max(max_rel(&r.net_power, &f.net_power));
        assert!(e < 1e-6, "case {}: {e:e}", r.index);
    }
    let check = reduced.reduction.clone().expect("a reduced sweep states its check");
    let best = full.rows.iter().max_by(|a, b| a.net_power[0].total_cmp(&b.net_power[0])).unwrap();
    assert_eq!(check.case, Some(best.index), "the check is at the best case");
    assert!(check.max_relative_error < 1e-6 && check.max_relative_error > 0.0, "{check:?}");
    // Reproducible: one thread gives the same table, and the check survives the file.
    let one = run("reduced.toml", 1);
    assert!(one.rows.iter().zip(&reduced.rows).all(|(a, b)| a.net_power == b.net_power));
    let out = d.join("reduced.h5");
    reduced.write(&out).unwrap();
    assert_eq!(sweep::SweepTable::read(&out).unwrap().reduction, Some(check));
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn a_reduced_plate_optimisation_checks_its_optimum_on_the_full_model() {
    let d = scratch("opt");
    write(&d, "reduced.toml", &plate_case([0.2, 0.2], "reduction = \"auto\""));
    let text = "base = \"reduced.toml\"\nharmonics = 9\n[search]\nseed = 3\nstarts = 2\nevaluations = 60\n\
        [[variable]]\npath = \"actuator[0].at[0]\"\nmin = 0.08\nmax = 0.42\n\
        [[variable]]\npath = \"actuator[0].at[1]\"\nmin = 0.08\nmax = 0.32\n\
        [[objective]]\nquantity = \"net_power\"\ngoal = \"maximize\"\n";
    write(&d, "p.opt.toml", text);
    let spec = optimize::Spec::from_str(text, "p.opt.toml", &d).unwrap();
    let r = optimize::run(&spec, &Default::default()).unwrap();
    let c = r.reduction.expect("a reduced optimisation states its check");
    assert!(c.case.is_none() && c.max_relative_error < 1e-6 && c.modes_kept > 10, "{c:?}");
    // The optimum's best.toml run alone (its own reduction) gives the optimum's net power.
    let out = d.join("out");
    let cli = std::process::Command::new(env!("CARGO_BIN_EXE_beamflow"))
        .args(["--quiet", "optimize", "p.opt.toml", "--no-plots", "--out"])
        .arg(&out)
        .current_dir(&d)
        .status()
        .unwrap();
    assert!(cli.success());
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let best = summary["best"]["objectives"].as_object().unwrap().values().next().unwrap().as_f64().unwrap();
    assert!(summary["reduction"]["max_relative_error_at_optimum"].as_f64().unwrap() < 1e-6);
    let lc = LoadedCase::load(&out.join("best.toml")).unwrap();
    let run = beamflow::app::runner::run_case(&lc).unwrap();
    let alone = run
        .results
        .iter()
        .find_map(|a| match a {
            beamflow::analysis::case_run::AnalysisResult::SteadyState(s) => Some(s.net_power[0]),
            _ => None,
        })
        .unwrap();
    assert!((alone - best).abs() <= 1e-12 * best.abs(), "alone {alone:e}, in the study {best:e}");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn a_reduced_sweep_over_an_imported_models_nodes_matches_the_full_model() {
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases/portal-frame");
    let d = scratch("portal");
    for f in ["portal_K.mtx", "portal_M.mtx", "portal_dofs.csv", "girder.sweep.toml"] {
        std::fs::copy(src.join(f), d.join(f)).unwrap();
    }
    let base = std::fs::read_to_string(src.join("portal-frame.toml")).unwrap();
    assert!(base.contains("type = \"steady_state\"\n"));
    write(&d, "portal-frame.toml", &base);
    let reduced = base.replace("type = \"steady_state\"\n", "type = \"steady_state\"\nreduction = \"auto\"\n");
    let sweep_text = std::fs::read_to_string(d.join("girder.sweep.toml")).unwrap();
    let run = |base_text: &str| {
        write(&d, "portal-frame.toml", base_text);
        let s = sweep::Sweep::from_str(&sweep_text, "girder.sweep.toml", &d).unwrap();
        sweep::run(&s, &sweep::RunOptions { threads: Some(2), ..Default::default() }).unwrap()
    };
    let (f, r) = (run(&base), run(&reduced));
    assert!(r.reduction.as_ref().is_some_and(|c| c.max_relative_error < 1e-6), "{:?}", r.reduction);
    assert!(r.rows.len() > 5);
    for (a, b) in r.rows.iter().zip(&f.rows) {
        let e = max_rel(&a.net_power, &b.net_power);
        assert!(e < 1e-6, "node case {}: {e:e}", a.index);
    }
    std::fs::remove_dir_all(&d).ok();
}

/// A sweep over the positions of `POSITIONS` on the plate case `text` (in a scratch folder).
fn position_sweep(name: &str, text: &str) -> sweep::SweepTable {
    let d = scratch(name);
    write(&d, "base.toml", text);
    let s = sweep::Sweep::from_str(&format!("base = \"base.toml\"\nharmonics = 9\n{POSITIONS}"), "s.toml", &d).unwrap();
    let t = sweep::run(&s, &sweep::RunOptions { threads: Some(2), ..Default::default() }).unwrap();
    std::fs::remove_dir_all(&d).ok();
    t
}

#[test]
fn modal_damping_on_the_shared_basis_matches_the_full_plate() {
    // Modal damping is a matrix only in the bare modes: the full model's sweep solves each
    // case in the complete modal basis, the shared reduction adds 2ζ_r·ω_r to its modes.
    let modal = |text: String| {
        text.replace(
            "kind = \"rayleigh_ratio\"\nzeta = 0.01\nmodes = [1, 3]\n",
            "kind = \"modal\"\nratios = [0.01, 0.02, 0.015]\n",
        )
    };
    // The residual vectors stand in for the discarded modes and take the last ratio at
    // their pseudo-frequencies, not each discarded mode's damping: a modelling difference
    // of the reduction (per mille here), which its check against the full model states.
    let reduced = position_sweep("modal-red", &modal(plate_case([0.2, 0.2], "reduction = \"auto\"")));
    let full = position_sweep("modal-full", &modal(plate_case([0.2, 0.2], "")));
    let check = reduced.reduction.clone().unwrap();
    let mut worst: f64 = 0.0;
    for (r, f) in reduced.rows.iter().zip(&full.rows) {
        let e = max_rel(&r.mean_power, &f.mean_power).max(max_rel(&r.net_power, &f.net_power));
        assert!(e < 1e-2, "case {}: {e:e}", r.index);
        worst = worst.max(e);
        if Some(r.index) == check.case {
            assert!((e - check.max_relative_error).abs() <= 1e-6 * e, "check {check:?} against {e:e}");
        }
    }
    assert!(worst > 1e-6, "modal damping's substitution shows: {worst:e}");
}

#[test]
fn a_plate_whose_point_supports_need_grid_lines_is_swept_on_its_full_model() {
    // On the uniform grid the support at (0.123, 0.2) would fall between nodes: the sweep
    // keeps each case's own grid and solves it in full, stating no reduction check.
    let text = plate_case([0.2, 0.2], "reduction = \"auto\"")
        .replace("through_points = false\n", "")
        .replace("[damping]", "[[plate.support]]\nat = [0.123, 0.2]\nkind = \"pinned\"\n[damping]");
    let t = position_sweep("support", &text);
    assert!(t.reduction.is_none());
    assert!(t.rows.iter().all(|r| r.net_power[0].is_finite() && r.net_power[0] > 0.0));
}
