//! A plate from a mesh file (`[plate.mesh] file = "…"`, format `beamflow-plate-mesh-1`):
//! graded grid lines and regions of other thickness or material, each against something
//! independent of the file reader — the generated grid, Navier's closed form and its
//! convergence order, the scaling of Kirchhoff plates with thickness, first-order
//! perturbation theory from the Navier shapes, `sha256sum`, and a hand-computed mass.

mod common;

use beamflow::analysis::modes;
use beamflow::case::build::build_structure;
use beamflow::case::LoadedCase;
use beamflow::plate::navier;
use common::example_plate::*;
use common::rel;
use std::f64::consts::PI;
use std::path::Path;

/// A plate case with `edges` (x0, x1, y0, y1), the `[plate.mesh]` body `mesh` and `rest`.
fn plate_case(edges: [&str; 4], mesh: &str, rest: &str) -> String {
    let [x0, x1, y0, y1] = edges;
    format!(
        "[plate]\nlength_x = {LX}\nlength_y = {LY}\nthickness = {H}\nyoungs_modulus = {E}\npoisson_ratio = {NU}\n\
         density = {RHO}\n[plate.mesh]\n{mesh}\n[plate.edges]\nx0 = \"{x0}\"\nx1 = \"{x1}\"\ny0 = \"{y0}\"\n\
         y1 = \"{y1}\"\n{rest}"
    )
}

const SS: [&str; 4] = ["simply_supported"; 4];

/// The case `text` in `dir`, with the mesh file `mesh.toml` holding `mesh` beside it.
fn with_mesh(dir: &Path, text: &str, mesh: &str) -> LoadedCase {
    std::fs::write(dir.join("mesh.toml"), mesh).unwrap();
    LoadedCase::from_str(text, &dir.join("case.toml").display().to_string(), dir.to_path_buf()).unwrap()
}

/// `n` + 1 grid lines on [0, l] at l·map(k/n), the last exactly l.
fn lines(n: usize, l: f64, map: impl Fn(f64) -> f64) -> Vec<f64> {
    let mut v: Vec<f64> = (0..=n).map(|k| l * map(k as f64 / n as f64)).collect();
    v[n] = l;
    v
}

/// A mesh file's text: its lines, then `tail` (materials and regions).
fn mesh_text(x: &[f64], y: &[f64], tail: &str) -> String {
    format!("format = \"beamflow-plate-mesh-1\"\nx = {x:?}\ny = {y:?}\n{tail}")
}

fn frequencies(lc: &LoadedCase, count: usize) -> Vec<f64> {
    modes::run(&build_structure(lc).unwrap(), count).unwrap().frequencies_hz
}

/// A file of uniform lines is the generated grid with `through_points = false`: the same
/// frequencies, and the same point power of an actuator whose foot stands between nodes
/// (attached through the shape functions), to 1e-12.
#[test]
fn uniform_lines_give_the_generated_grid() {
    use beamflow::analysis::case_run::AnalysisResult;
    use beamflow::analysis::mesh_estimate::MeshCheck;
    let dir = tempfile::tempdir().unwrap();
    let (nx, ny) = (20, 16);
    // Not on a grid line of the 20 × 16 grid (every 25 mm).
    let rest = "[damping]\nkind = \"rayleigh\"\na0 = 4.0\na1 = 3.0e-6\n\
                [[actuator]]\ntype = \"inertial\"\nat = [0.13, 0.11]\nm_t = 0.1\n\
                [actuator.stack]\nk_p = 3.0e7\nc_p = 200.0\nm_p = 0.03\nd_p = 1.3e-7\nhysteresis = false\n\
                [actuator.voltage]\nkind = \"sine\"\namplitude = 50.0\nfrequency = 83.0\n\
                [[analysis]]\ntype = \"steady_state\"\nharmonics = 1\nsamples_per_period = 32\n";
    let generated = common::case(&plate_case(SS, &format!("elements = [{nx}, {ny}]\nthrough_points = false"), rest));
    let uniform = |n: usize, l: f64| -> Vec<f64> { (0..=n).map(|k| l * k as f64 / n as f64).collect() };
    let from_file = with_mesh(
        dir.path(),
        &plate_case(SS, "file = \"mesh.toml\"", rest),
        &mesh_text(&uniform(nx, LX), &uniform(ny, LY), ""),
    );
    let (fg, ff) = (frequencies(&generated, 8), frequencies(&from_file, 8));
    for (a, b) in fg.iter().zip(&ff) {
        assert!(rel(*b, *a) < 1e-12, "{b} Hz from the file vs {a} Hz generated");
    }
    let power = |lc: &LoadedCase| {
        let run = beamflow::app::runner::run_case(lc).unwrap();
        let AnalysisResult::SteadyState(s) = &run.results[0] else { panic!("a steady state") };
        (s.mean_power.clone(), run.mesh[0].clone())
    };
    let ((pg, mg), (pf, mf)) = (power(&generated), power(&from_file));
    // The generated grid states its error against half its elements; a mesh file's grid
    // has no coarser grid, and says so.
    assert!(matches!(mg, Some(MeshCheck::Estimate(ref e)) if e.coarse_elements == [10, 8]), "{mg:?}");
    assert!(matches!(mf, Some(MeshCheck::NotEstimated(ref why)) if why.contains("mesh file")), "{mf:?}");
    assert!(!pg.is_empty() && pg.iter().all(|p| p.abs() > 0.0), "{pg:?}");
    for (a, b) in pg.iter().zip(&pf) {
        assert!(rel(*b, *a) < 1e-12, "point power {b:e} W from the file vs {a:e} W generated");
    }
}

/// Grid lines graded smoothly (spacing varying 2.3-fold across each side): the simply
/// supported frequencies converge to Navier's as h⁴ over three refinements, from above.
#[test]
fn graded_lines_converge_to_navier_as_h4() {
    let dir = tempfile::tempdir().unwrap();
    let grade = |a: f64| move |t: f64| t + a * (2.0 * PI * t).sin() / (2.0 * PI);
    let rho_h = RHO * H;
    let exact: Vec<f64> = navier::lowest(6, LX, LY, d(), rho_h).into_iter().map(|(_, _, w)| w / (2.0 * PI)).collect();
    let mut errors = Vec::new();
    for (nx, ny) in [(12, 10), (24, 20), (48, 40)] {
        let mesh = mesh_text(&lines(nx, LX, grade(0.4)), &lines(ny, LY, grade(-0.4)), "");
        let f = frequencies(&with_mesh(dir.path(), &plate_case(SS, "file = \"mesh.toml\"", ""), &mesh), 6);
        assert!(f.iter().zip(&exact).all(|(a, b)| a >= &(b * (1.0 - 1e-12))), "{f:?} vs {exact:?}");
        errors.push(f.iter().zip(&exact).map(|(a, b)| rel(*a, *b)).collect::<Vec<_>>());
    }
    for r in 0..6 {
        for k in 0..2 {
            let order = (errors[k][r] / errors[k + 1][r]).log2();
            let e: Vec<f64> = errors.iter().map(|e| e[r]).collect();
            assert!((3.6..4.4).contains(&order), "mode {}: order {order} ({e:?})", r + 1);
        }
    }
}

/// A region over the whole plate with thickness s·h scales every frequency by s: K grows
/// as h³ and M as h, so ω ∝ h for a Kirchhoff plate, whatever its edges and grid.
#[test]
fn a_region_of_the_whole_plate_s_times_thicker_scales_the_frequencies_by_s() {
    let dir = tempfile::tempdir().unwrap();
    let s = 1.5;
    let edges = ["clamped", "simply_supported", "free", "clamped"];
    let (x, y) = (lines(14, LX, |t| t * t * (3.0 - 2.0 * t)), lines(11, LY, |t| t.sqrt()));
    let case = plate_case(edges, "file = \"mesh.toml\"", "");
    let bare = frequencies(&with_mesh(dir.path(), &case, &mesh_text(&x, &y, "")), 8);
    let whole = format!("[[region]]\nx = [0.0, {LX}]\ny = [0.0, {LY}]\nthickness = {}\n", s * H);
    let thick = frequencies(&with_mesh(dir.path(), &case, &mesh_text(&x, &y, &whole)), 8);
    for (a, b) in bare.iter().zip(&thick) {
        assert!(rel(*b, s * a) < 1e-10, "{b} Hz vs {s} × {a} Hz");
    }
}

/// ∫ sin²(mπx/L) dx over [a, b].
fn sin2(m: usize, l: f64, a: f64, b: f64) -> f64 {
    let k = m as f64 * PI / l;
    let f = |x: f64| x / 2.0 - (2.0 * k * x).sin() / (4.0 * k);
    f(b) - f(a)
}

/// A density change δρ = ε·ρ on a sub-rectangle R moves ω_mn of the simply supported plate
/// as first-order perturbation theory from the Navier shapes w = sin·sin says:
/// δω/ω = −½·∫_R δρ·h·w² / ∫ ρ·h·w² = −½·ε·(4/(L_x·L_y))·∫sin²(mπx/L_x)dx·∫sin²(nπy/L_y)dy.
/// The rest is second order: with δM ≤ ε·M, the coupling of mode j to the others is at
/// most ε in the mass norm, so |δω/ω − first order| ≤ ε²·(1 + ω_j²/min_k|ω_k² − ω_j²|).
#[test]
fn a_density_change_on_a_patch_moves_frequencies_as_perturbation_theory_says() {
    let dir = tempfile::tempdir().unwrap();
    let eps = 1e-3;
    let (rx, ry) = ((0.1, 0.25), (0.1, 0.3));
    let (x, y) = (lines(20, LX, |t| t), lines(16, LY, |t| t));
    let case = plate_case(SS, "file = \"mesh.toml\"", "");
    let base = frequencies(&with_mesh(dir.path(), &case, &mesh_text(&x, &y, "")), 6);
    let patch = format!(
        "[[material]]\nname = \"denser\"\nyoungs_modulus = {E}\npoisson_ratio = {NU}\ndensity = {}\n\
         [[region]]\nx = [{}, {}]\ny = [{}, {}]\nmaterial = \"denser\"\n",
        RHO * (1.0 + eps),
        rx.0,
        rx.1,
        ry.0,
        ry.1
    );
    let moved = frequencies(&with_mesh(dir.path(), &case, &mesh_text(&x, &y, &patch)), 6);
    let navier = navier::lowest(8, LX, LY, d(), RHO * H);
    for (r, &(m, n, w)) in navier.iter().take(3).enumerate() {
        let first = -0.5 * eps * 4.0 / (LX * LY) * sin2(m, LX, rx.0, rx.1) * sin2(n, LY, ry.0, ry.1);
        let gap =
            navier.iter().filter(|o| (o.0, o.1) != (m, n)).map(|o| (o.2 * o.2 - w * w).abs()).fold(f64::MAX, f64::min);
        let bound = eps * eps * (1.0 + w * w / gap);
        let shift = moved[r] / base[r] - 1.0;
        assert!(bound < 0.1 * first.abs(), "mode ({m}, {n}): the bound {bound:e} says nothing beside {first:e}");
        assert!(
            (shift - first).abs() <= bound,
            "mode ({m}, {n}): δω/ω = {shift:e}, first order {first:e}, off by {:e} > {bound:e}",
            (shift - first).abs()
        );
    }
}

/// The results file names the mesh file (`parameters/plate/mesh`, as written) and holds
/// its hash (`mesh_hash`, what `sha256sum` prints), as it does a beam's mesh file.
#[test]
fn results_name_the_mesh_file_and_its_hash() {
    use beamflow::io::hdf5::ResultsReader;
    let dir = tempfile::tempdir().unwrap();
    let beam = "[beam.mesh]\nfile = \"mesh.toml\"\n[damping]\nkind = \"rayleigh\"\na0 = 1.0\na1 = 1e-6\n";
    let plate = plate_case(SS, "file = \"mesh.toml\"", "");
    let meshes = [
        ("beam", beam.to_string(), "format = \"beamflow-mesh-1\"\nnodes = [0.0, 0.2, 0.5, 0.73]\n".to_string()),
        ("plate", plate, mesh_text(&lines(6, LX, |t| t * t), &lines(5, LY, |t| t), "")),
    ];
    for (kind, case, mesh) in meshes {
        let case = format!("{case}[[analysis]]\ntype = \"modes\"\ncount = 2\n");
        std::fs::write(dir.path().join("case.toml"), case).unwrap();
        std::fs::write(dir.path().join("mesh.toml"), mesh).unwrap();
        let out = dir.path().join(format!("out-{kind}"));
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_beamflow"))
            .args(["--quiet", "run", "--no-plots", "--out"])
            .arg(&out)
            .arg(dir.path().join("case.toml"))
            .output()
            .unwrap();
        assert!(run.status.success(), "{kind}: {}", String::from_utf8_lossy(&run.stderr));
        let sum = std::process::Command::new("sha256sum").arg(dir.path().join("mesh.toml")).output().unwrap();
        let hex = String::from_utf8(sum.stdout).unwrap().split_whitespace().next().unwrap().to_string();
        let r = ResultsReader::open(out.join("case.h5")).unwrap();
        assert_eq!(r.attr_str("model", "mesh_hash").unwrap(), format!("sha256:{hex}"), "{kind}");
        assert_eq!(r.attr_str(&format!("model/parameters/{kind}/mesh"), "file").unwrap(), "mesh.toml", "{kind}");
    }
}

/// The shipped graded mesh (`meshes/plate-graded.toml`): its plate weighs what its regions
/// say by hand (aluminium, a 5 mm pad, a steel strip), and its lines alone (regions
/// dropped) give the simply supported plate's Navier frequencies to 1e-3.
#[test]
fn the_shipped_graded_mesh_weighs_what_its_regions_say() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("meshes/plate-graded.toml")).unwrap();
    let lc =
        LoadedCase::from_str(&plate_case(SS, "file = \"plate-graded.toml\"", ""), "case.toml", root.join("meshes"))
            .unwrap();
    let (pad, strip) = (0.10 * 0.08, 0.06 * 0.4);
    let mass = RHO * H * (LX * LY - pad - strip) + RHO * 0.005 * pad + 7850.0 * H * strip;
    let built = build_structure(&lc).unwrap().mass();
    assert!(rel(built, mass) < 1e-12, "{built} kg vs {mass} kg");
    let dir = tempfile::tempdir().unwrap();
    let lines_only = &text[..text.find("[[material]]").unwrap()];
    let f = frequencies(&with_mesh(dir.path(), &plate_case(SS, "file = \"mesh.toml\"", ""), lines_only), 6);
    let exact = navier::lowest(6, LX, LY, d(), RHO * H);
    for (a, (m, n, w)) in f.iter().zip(exact) {
        assert!(rel(*a, w / (2.0 * PI)) < 1e-3, "mode ({m}, {n}): {a} Hz vs {} Hz", w / (2.0 * PI));
    }
}
