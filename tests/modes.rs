//! Natural modes against closed-form beam theory.

mod common;
use beamflow::analysis::modes;
use beamflow::assembly::{Model, System};
use beamflow::beam::analytic::{natural_frequencies_hz, End};
use beamflow::case::build::build_beam;
use common::*;

fn beam_case(elements: usize, supports: &str) -> beamflow::beam::Beam {
    let lc = case(&format!("[beam.mesh]\nelements = {elements}\n{supports}"));
    build_beam(&lc).unwrap()
}

const EI: f64 = 210e9 * 0.05 * 0.005 * 0.005 * 0.005 / 12.0;
const RHO_A: f64 = 7850.0 * 0.05 * 0.005;

#[test]
fn clamped_clamped_frequencies_match_beta_l_roots_at_200_elements() {
    let r = modes::run(&beamflow::structure::Structure::from(beam_case(200, "")), 6).unwrap();
    let exact = natural_frequencies_hz(End::Clamped, End::Clamped, 0.73, EI, RHO_A, 6).unwrap();
    for (k, (f, a)) in r.frequencies_hz.iter().zip(&exact).enumerate() {
        assert!(rel(*f, *a) < 1e-6, "mode {}: {f} Hz vs {a} Hz", k + 1);
    }
    assert!((r.frequencies_hz[0] - 49.88).abs() < 0.01, "f1 = {}", r.frequencies_hz[0]);
    assert_eq!(r.analytic_hz.len(), 6, "the run itself reports the closed-form reference");
}

#[test]
fn frequency_error_converges_at_fourth_order_under_mesh_halving() {
    let exact = natural_frequencies_hz(End::Clamped, End::Clamped, 0.73, EI, RHO_A, 3).unwrap();
    let meshes = [8, 16, 32];
    let errs: Vec<Vec<f64>> = meshes
        .iter()
        .map(|&n| {
            let r = modes::run(&beamflow::structure::Structure::from(beam_case(n, "")), 3).unwrap();
            r.frequencies_hz.iter().zip(&exact).map(|(f, a)| rel(*f, *a)).collect()
        })
        .collect();
    for mode in 0..3 {
        for w in errs.windows(2) {
            let order = (w[0][mode] / w[1][mode]).log2();
            assert!(
                (3.7..4.3).contains(&order),
                "mode {}: observed order {order:.3} (errors {:?})",
                mode + 1,
                errs.iter().map(|e| e[mode]).collect::<Vec<_>>()
            );
        }
    }
}

#[test]
fn modes_are_mass_normalised_and_diagonalise_stiffness() {
    let beam = beam_case(60, "");
    let model = Model::bare(beam.clone());
    let sys = System::assemble(&model).unwrap();
    let r = modes::run(&beamflow::structure::Structure::from(&beam), 12).unwrap();
    let n = sys.n();
    let phis: Vec<Vec<f64>> = (0..12).map(|k| r.modes.shape_global(k, n)).collect();
    for i in 0..12 {
        for j in 0..12 {
            let m = sys.m.bilinear(&phis[i], &phis[j]);
            let k = sys.k.bilinear(&phis[i], &phis[j]);
            let w2 = r.modes.omega[i].powi(2);
            let (em, ek) = if i == j { (1.0, w2) } else { (0.0, 0.0) };
            assert!((m - em).abs() < 1e-9, "phi{i}ᵀMphi{j} = {m}");
            assert!((k - ek).abs() < 1e-9 * r.modes.omega[11].powi(2), "phi{i}ᵀKphi{j} = {k}");
        }
    }
}

#[test]
fn pinned_pinned_and_cantilever_frequencies() {
    let pp = modes::run(
        &beamflow::structure::Structure::from(beam_case(
            100,
            "[[beam.support]]\nx = 0.0\nkind = \"pinned\"\n[[beam.support]]\nx = 0.73\nkind = \"pinned\"",
        )),
        4,
    )
    .unwrap();
    let cf = modes::run(
        &beamflow::structure::Structure::from(beam_case(100, "[[beam.support]]\nx = 0.0\nkind = \"clamped\"")),
        4,
    )
    .unwrap();
    for (r, ends) in [(&pp, (End::Pinned, End::Pinned)), (&cf, (End::Clamped, End::Free))] {
        let exact = natural_frequencies_hz(ends.0, ends.1, 0.73, EI, RHO_A, 4).unwrap();
        for (f, a) in r.frequencies_hz.iter().zip(&exact) {
            assert!(rel(*f, *a) < 1e-6, "{ends:?}: {f} vs {a}");
        }
    }
    // Pinned–pinned has the closed form f_r = (rπ)²/(2πL²)·√(EI/ρA) exactly.
    let f1 = std::f64::consts::PI / (2.0 * 0.73 * 0.73) * (EI / RHO_A).sqrt();
    assert!(rel(pp.frequencies_hz[0], f1) < 1e-7);
}

#[test]
fn cantilever_static_tip_deflection_is_exact() {
    let beam = beam_case(7, "[[beam.support]]\nx = 0.0\nkind = \"clamped\"");
    let model = Model::bare(beam.clone());
    let sys = System::assemble(&model).unwrap();
    let tip = sys.dofs.w(beam.mesh.n_nodes() - 1).unwrap();
    let mut f = vec![0.0; sys.n()];
    f[tip] = 10.0;
    let q = sys.static_solve(&f).unwrap();
    let exact = 10.0 * 0.73f64.powi(3) / (3.0 * EI);
    assert!(rel(q[tip], exact) < 1e-12, "{} vs {exact}", q[tip]);
}

#[test]
fn unsupported_beam_is_reported_not_solved() {
    let beam = beam_case(10, "[[beam.support]]\nx = 0.0\nkind = \"free\"");
    let model = Model::bare(beam);
    let sys = System::assemble(&model).unwrap();
    let err = sys.static_solve(&vec![1.0; sys.n()]).unwrap_err().to_string();
    assert!(err.contains("singular"), "{err}");
}

#[test]
fn shift_invert_lanczos_matches_the_dense_solver_and_scales_to_large_meshes() {
    let beam = beam_case(200, "");
    let model = Model::bare(beam.clone());
    let sys = System::assemble(&model).unwrap();
    let lz = beamflow::solve::lanczos::modes_shift_invert(&sys.k, &sys.m, &sys.envelope, 20, 0.0).unwrap();
    let dense = modes::run(&beamflow::structure::Structure::from(&beam), 20).unwrap();
    for r in 0..20 {
        assert!(
            rel(lz.omega[r], dense.modes.omega[r]) < 1e-9,
            "mode {}: {} vs {}",
            r + 1,
            lz.omega[r],
            dense.modes.omega[r]
        );
        let phi = lz.shape_global(r, sys.n());
        assert!((sys.m.bilinear(&phi, &phi) - 1.0).abs() < 1e-9);
    }
    // 1000 elements (≈ 2000 DOFs) go through the sparse path and still match βL roots
    // (much finer meshes too: see `very_fine_meshes_keep_the_lowest_frequencies`).
    let big = beam_case(1000, "");
    const { assert!(2 * 1000 > beamflow::analysis::modes::DENSE_EIGEN_LIMIT) };
    let r = modes::run(&beamflow::structure::Structure::from(&big), 6).unwrap();
    let exact = natural_frequencies_hz(End::Clamped, End::Clamped, 0.73, EI, RHO_A, 6).unwrap();
    for (f, a) in r.frequencies_hz.iter().zip(&exact) {
        assert!(rel(*f, *a) < 1e-6, "{f} vs {a}");
    }
}

/// K as assembled loses ~ε·elements⁴ of its lowest eigenvalues (28 % for f₁ at 50,000
/// elements); the square-root factor from the element rows keeps ~ε·elements² (a few 1e-9).
#[test]
fn very_fine_meshes_keep_the_lowest_frequencies() {
    for n in [20_000, 50_000] {
        let r = modes::run(&beamflow::structure::Structure::from(beam_case(n, "")), 10).unwrap();
        assert_eq!(r.analytic_hz.len(), 10);
        for k in 0..10 {
            let err = rel(r.frequencies_hz[k], r.analytic_hz[k]);
            assert!(err < 1e-6, "{n} elements, mode {}: {} Hz vs {} Hz", k + 1, r.frequencies_hz[k], r.analytic_hz[k]);
            // Discretisation error is far below round-off here, so the bound must hold.
            assert!(err < r.roundoff_bound[k], "{n} elements, mode {}: error {err:e} above its bound", k + 1);
        }
        assert!(r.roundoff_bound[0] < 1e-6, "bound {}", r.roundoff_bound[0]);
        let table = beamflow::app::commands::modes_table(&r);
        assert!(!table.contains("note:"), "no round-off warning expected at {n} elements:\n{table}");
    }
}

/// The dense path (≤ 1500 DOFs) reduces with the same factor: its f₁ error keeps falling
/// as h⁴ up to its largest meshes, where K's own Cholesky factor had stalled it at ~1e-7.
#[test]
fn dense_path_converges_at_fourth_order_up_to_its_largest_meshes() {
    let exact = natural_frequencies_hz(End::Clamped, End::Clamped, 0.73, EI, RHO_A, 3).unwrap();
    let err = |n: usize| {
        let r = modes::run(&beamflow::structure::Structure::from(beam_case(n, "")), 3).unwrap();
        assert!(2 * n <= beamflow::analysis::modes::DENSE_EIGEN_LIMIT);
        r.frequencies_hz.iter().zip(&exact).map(|(f, a)| rel(*f, *a)).collect::<Vec<_>>()
    };
    let (coarse, fine) = (err(250), err(500));
    for mode in 0..3 {
        let order = (coarse[mode] / fine[mode]).log2();
        assert!((3.7..4.3).contains(&order), "mode {}: order {order:.3} ({coarse:?} → {fine:?})", mode + 1);
    }
}

/// Springs, point masses, an interior support and varying sections: the square-root path
/// (Lanczos and dense) agrees with the assembled-K path where the latter is still accurate.
#[test]
fn square_root_path_matches_the_assembled_stiffness_on_an_irregular_beam() {
    use beamflow::assembly::system::structure_stiffness_root;
    let text = "[beam.mesh]\nelements = 800\n\
        [[beam.support]]\nx = 0.0\nkind = \"clamped\"\n\
        [[beam.support]]\nx = 0.3\nkind = \"pinned\"\n\
        [[beam.support]]\nx = 0.73\nkind = \"spring\"\nk_w = 2.0e4\nk_theta = 15.0\n\
        [[beam.spring]]\nx = 0.5\nstiffness = 3.0e5\n\
        [[beam.point_mass]]\nx = 0.61\nmass = 0.08\nrotary_inertia = 2e-5\n";
    let mut beam = build_beam(&case(text)).unwrap();
    for (i, e) in beam.mesh.elements.iter_mut().enumerate() {
        e.ei *= 1.0 + 0.5 * (i as f64 * 0.01).sin();
    }
    let model = Model::bare(beam.clone());
    let sys = System::assemble(&model).unwrap();
    assert!(sys.n() > beamflow::analysis::modes::DENSE_EIGEN_LIMIT);
    let root = structure_stiffness_root(&beam, &sys.dofs).unwrap();
    let reference = beamflow::solve::lanczos::modes_shift_invert(&sys.k, &sys.m, &sys.envelope, 8, 0.0).unwrap();
    let sparse = beamflow::solve::lanczos::lowest_modes_from_root(&root, &sys.m, 8).unwrap();
    let dense = beamflow::solve::eigen::modes_from_root(&root, &sys.m, 8).unwrap();
    assert!(sparse.from_root && dense.from_root && !reference.from_root);
    for r in 0..8 {
        // The reference itself carries ~ε·n⁴-scale round-off at 800 elements (~1e-7).
        assert!(rel(sparse.omega[r], reference.omega[r]) < 1e-6, "mode {}", r + 1);
        assert!(rel(dense.omega[r], sparse.omega[r]) < 1e-10, "mode {}", r + 1);
        let phi = sparse.shape_global(r, sys.n());
        assert!((sys.m.bilinear(&phi, &phi) - 1.0).abs() < 1e-9);
    }
}

/// An unsupported beam has no square-root factor; a large mesh goes to the profile LDLᵀ of
/// K shifted by a little of M: the two rigid-body modes come first, and the elastic ones are
/// the free–free beam's, whose βL are the clamped–clamped beam's roots (cos βL·cosh βL = 1),
/// within each mode's stated round-off bound (K as assembled: ε·(ω_max/ω)²/2).
#[test]
fn unsupported_fine_beam_has_its_rigid_and_free_free_modes() {
    let free = "[[beam.support]]\nx = 0.0\nkind = \"free\"";
    let r = modes::run(&beamflow::structure::Structure::from(beam_case(1000, free)), 6).unwrap();
    assert_eq!(r.rigid_body_modes, 2, "{:?}", r.frequencies_hz);
    let scale = (EI / RHO_A).sqrt() / (2.0 * std::f64::consts::PI * 0.73 * 0.73);
    for (k, bl) in [4.730_040_744_862_704, 7.853_204_624_095_838, 10.995_607_838_001_671, 14.137_165_491_257_464]
        .iter()
        .enumerate()
    {
        let (m, exact) = (k + 2, bl * bl * scale);
        let e = rel(r.frequencies_hz[m], exact);
        assert!(e <= r.roundoff_bound[m] && e <= 1e-4, "mode {}: {e:e}, bound {:e}", m + 1, r.roundoff_bound[m]);
    }
}

/// Asking the sparse solver for no modes is reported as such, before any factorisation:
/// on a free–free beam (singular K) the error used to be the factorisation's.
#[test]
fn zero_modes_is_an_argument_error_even_with_a_singular_stiffness() {
    let beam = beam_case(20, "[[beam.support]]\nx = 0.0\nkind = \"free\"\n[[beam.support]]\nx = 0.73\nkind = \"free\"");
    let model = Model::bare(beam);
    let sys = System::assemble(&model).unwrap();
    let err =
        beamflow::solve::lanczos::modes_shift_invert(&sys.k, &sys.m, &sys.envelope, 0, 0.0).unwrap_err().to_string();
    assert!(err.contains("at least one mode"), "{err}");
}

/// The written results carry each frequency's round-off bound (JSON, CSV), so a mesh
/// without a closed form still states its accuracy.
#[test]
fn results_files_state_the_roundoff_bound() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("fine.toml");
    std::fs::write(&case, "[beam.mesh]\nelements = 20000\n[[analysis]]\ntype = \"modes\"\ncount = 4\n").unwrap();
    let out = dir.path().join("out");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_beamflow"))
        .args(["run", "--quiet", "--no-plots", "--csv", "--out"])
        .args([&out, &case])
        .status()
        .unwrap();
    assert!(status.success());
    let expected = modes::run(&beamflow::structure::Structure::from(beam_case(20_000, "")), 4).unwrap().roundoff_bound;
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("fine.json")).unwrap()).unwrap();
    let written: Vec<f64> =
        json["analyses"][0]["roundoff_bound"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(written, expected);
    assert!(written.iter().all(|&b| b > 0.0 && b < 1e-6), "{written:?}");
    let csv = std::fs::read_to_string(out.join("fine_analysis_0_modes_modes.csv")).unwrap();
    assert!(csv.lines().next().unwrap().ends_with("roundoff_bound [1]"), "{csv}");
}
