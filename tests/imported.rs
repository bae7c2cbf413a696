//! Imported models (spec §17): beamflow's own beam and plate exported in the imported
//! format and read back give the native results; a model checked on load refuses what is
//! not a structure's M, K and map, naming the file and the row; and a model built by hand
//! has the modes its closed form says.

use beamflow::analysis::budget::Budget;
use beamflow::imported::{Files, Imported};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn run(case: &Path, out: &Path) -> Value {
    beamflow::app::commands::run(case, Some(out), None, false, false, &Budget::default()).unwrap();
    let stem = case.file_stem().unwrap().to_str().unwrap();
    serde_json::from_str(&std::fs::read_to_string(out.join(format!("{stem}.json"))).unwrap()).unwrap()
}

/// The id of the exported node at (x, y).
fn node_at(dofs: &Path, x: f64, y: f64) -> i64 {
    let text = std::fs::read_to_string(dofs).unwrap();
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let (px, py): (f64, f64) = (f[2].parse().unwrap(), f[3].parse().unwrap());
        if (px - x).abs() < 1e-12 && (py - y).abs() < 1e-12 {
            return f[1].parse().unwrap();
        }
    }
    panic!("no node at ({x}, {y}) in {}", dofs.display());
}

/// Every number of `a` found at the same place in `b`, relative difference (largest).
fn largest_difference(a: &Value, b: &Value, skip: &[&str], path: &str) -> (f64, String) {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => x
            .iter()
            .filter(|(k, _)| !skip.contains(&k.as_str()))
            .filter_map(|(k, v)| y.get(k).map(|w| largest_difference(v, w, skip, &format!("{path}/{k}"))))
            .fold((0.0, String::new()), |m, d| if d.0 > m.0 { d } else { m }),
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() && x.iter().all(Value::is_number) => {
            // A list of numbers (a spectrum, a table column) against its largest entry.
            let num = |v: &Value| v.as_f64().unwrap();
            let scale = x.iter().chain(y).fold(0.0f64, |m, v| m.max(num(v).abs()));
            x.iter()
                .zip(y)
                .enumerate()
                .map(|(i, (v, w))| {
                    let d = if scale == 0.0 { 0.0 } else { (num(v) - num(w)).abs() / scale };
                    (d, format!("{path}[{i}]"))
                })
                .fold((0.0, String::new()), |m, d| if d.0 > m.0 { d } else { m })
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => x
            .iter()
            .zip(y)
            .enumerate()
            .map(|(i, (v, w))| largest_difference(v, w, skip, &format!("{path}[{i}]")))
            .fold((0.0, String::new()), |m, d| if d.0 > m.0 { d } else { m }),
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            let scale = x.abs().max(y.abs());
            (if scale == 0.0 { 0.0 } else { (x - y).abs() / scale }, path.to_string())
        }
        _ => (0.0, String::new()),
    }
}

fn imported_table(out: &Path, stem: &str) -> String {
    let p = |n: &str| out.join(format!("{stem}_structure_{n}")).display().to_string();
    format!(
        "[imported]\nmass = {:?}\nstiffness = {:?}\ndamping = {:?}\ndofs = {:?}\n[damping]\nkind = \"given\"\n",
        p("M.mtx"),
        p("K.mtx"),
        p("C.mtx"),
        p("dofs.csv")
    )
}

/// Quantities that differ by construction: round-off residues and the stated bounds (each
/// path estimates its own: the beam's modes come from its stiffness root, the imported
/// model's from LDLᵀ), the closed forms only a native structure has, and the names.
const BOUNDS: [&str; 9] = [
    "truncation_estimate",
    "mesh_roundoff",
    "roundoff_bound",
    "energy_balance_rel_error",
    "analytic_hz",
    "relative_error",
    "case",
    "structure",
    "title",
];

/// A case solved natively, `{structure}{native}{drive}` with `[output] matrices = true`,
/// and as the imported model exported from it, its actuator `imported(dofs)` (named by
/// nodes of the exported map `dofs`): both results, the folder, and where the export is.
fn round_trip(
    structure: &str,
    native: &str,
    imported: impl Fn(&Path) -> String,
    drive: &str,
) -> (Value, Value, tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let native_case = dir.path().join("native.toml");
    std::fs::write(&native_case, format!("{structure}{native}{drive}[output]\nmatrices = true\n")).unwrap();
    let out = dir.path().join("out");
    let a = run(&native_case, &out);
    let actuator = imported(&out.join("native_structure_dofs.csv"));
    let imported_case = dir.path().join("imported.toml");
    std::fs::write(&imported_case, format!("{}{actuator}{drive}", imported_table(&out, "native"))).unwrap();
    let b = run(&imported_case, &dir.path().join("out2"));
    assert_eq!(b["structure"], "imported");
    (a, b, dir, out)
}

/// The paper beam with a frame actuator at 60 Hz, solved natively and as an imported model
/// exported from it (M, K, C and the map), both with `analyses`: the two results.
fn frame_round_trip(analyses: &str) -> (Value, Value) {
    let drive = format!("[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n{analyses}");
    let frame = "[[actuator]]\ntype = \"frame\"\nname = \"frame\"\n";
    let on_nodes = |dofs: &Path| {
        let [s, l, r] = [0.150, 0.109, 0.189].map(|x| node_at(dofs, x, 0.0));
        format!("{frame}node = {s}\ncomponent = \"w\"\nlegs = [{l}, {r}]\n")
    };
    let (a, b, dir, out) = round_trip("[beam]\n", &format!("{frame}x_e = 0.150\n"), on_nodes, &drive);
    // The results say which files the model came from: the hashes `sha256sum` prints.
    let h5 = beamflow::io::hdf5::ResultsReader::open(dir.path().join("out2/imported.h5")).unwrap();
    for (role, name) in [("mass", "M.mtx"), ("stiffness", "K.mtx"), ("damping", "C.mtx"), ("dofs", "dofs.csv")] {
        let path = out.join(format!("native_structure_{name}"));
        let sum = std::process::Command::new("sha256sum").arg(&path).output().unwrap().stdout;
        let hex = String::from_utf8(sum).unwrap().split_whitespace().next().unwrap().to_string();
        assert_eq!(h5.attr_str("model", &format!("imported_{role}_hash")).unwrap(), format!("sha256:{hex}"), "{role}");
    }
    (a, b)
}

#[test]
fn a_frame_on_the_beam_exported_and_imported_puts_in_the_same_power() {
    let (a, b) = frame_round_trip(
        "[[analysis]]\ntype = \"steady_state\"\n[[analysis]]\ntype = \"modes\"\ncount = 6\n\
         [[analysis]]\ntype = \"harmonic\"\nsystem = \"coupled\"\n[analysis.frequencies]\nvalues = [30.0, 60.0, 250.0]\n",
    );
    let p = |v: &Value| v["analyses"][0]["mean_power_w"].clone();
    assert!(p(&a).as_object().is_some_and(|m| m.len() == 3), "{}", p(&a));
    let (d, at) = largest_difference(&a, &b, &BOUNDS, "");
    assert!(d <= 1e-8, "largest relative difference {d:e} at {at}");
}

/// The transient runs on the imported model's general (sparse) path, the native beam's on
/// its band kernels: the same discrete model stepped by the same Newmark scheme settles to
/// the same point powers, the settled periods included.
#[test]
fn a_frame_on_the_beam_exported_and_imported_settles_to_the_same_transient() {
    let (a, b) = frame_round_trip("[[analysis]]\ntype = \"transient\"\n");
    let t = |v: &Value| v["analyses"][0].clone();
    assert_eq!(t(&a)["type"], "transient");
    for same in ["dt_s", "periods_run", "steps_per_period", "harmonics"] {
        assert_eq!(t(&a)[same], t(&b)[same], "{same}");
    }
    // A leg's power is the product of its force, k_l times a stretch that is a small
    // difference of large displacements, and a velocity: the two paths sum those in a
    // different order, so they agree to the round-off each result states of itself.
    let roundoff = |v: &Value| t(v)["mesh_roundoff"].as_f64().unwrap();
    let tol = roundoff(&a) + roundoff(&b);
    // The change between the last two periods and the settling bound built on it are
    // differences of nearly equal powers: their round-off is relative to the power, not
    // to themselves.
    let skip = [&BOUNDS[..], &["final_change", "settling_estimate"]].concat();
    let (d, at) = largest_difference(&a, &b, &skip, "");
    assert!(d <= tol, "largest relative difference {d:e} at {at}, above the stated round-off {tol:e}");
    let change = |v: &Value| t(v)["final_change"].as_f64().unwrap();
    assert!((change(&a) - change(&b)).abs() <= 2.0 * tol, "final change {:e} against {:e}", change(&a), change(&b));
}

#[test]
fn an_inertial_actuator_on_the_plate_exported_and_imported_puts_in_the_same_power() {
    let plate = "[plate]\nlength_x = 0.5\nlength_y = 0.4\nthickness = 0.003\nyoungs_modulus = 70e9\n\
                 poisson_ratio = 0.33\ndensity = 2700.0\n[plate.mesh]\nelements = [10, 8]\n\
                 [plate.edges]\nx0 = \"clamped\"\nx1 = \"simply_supported\"\ny0 = \"free\"\ny1 = \"simply_supported\"\n";
    let drive = "[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 83.0\n\
                 [[analysis]]\ntype = \"steady_state\"\n[[analysis]]\ntype = \"modes\"\ncount = 8\n";
    let shaker = "[[actuator]]\ntype = \"inertial\"\nname = \"shaker\"\n";
    let on_node = |dofs: &Path| format!("{shaker}node = {}\ncomponent = \"w\"\n", node_at(dofs, 0.15, 0.2));
    let (a, b, _dir, out) = round_trip(plate, &format!("{shaker}at = [0.15, 0.2]\n"), on_node, drive);
    let (d, at) = largest_difference(&a, &b, &BOUNDS, "");
    assert!(d <= 1e-8, "largest relative difference {d:e} at {at}");
    // The whole system's DOF map places each plate row at its node, as the structure's
    // own map does; the actuator body's rows have no position.
    let lines = |name: &str| -> Vec<Vec<String>> {
        let text = std::fs::read_to_string(out.join(name)).unwrap();
        text.lines().skip(1).map(|l| l.split(',').map(String::from).collect()).collect()
    };
    let structure_rows = lines("native_structure_dofs.csv");
    let own: std::collections::HashMap<String, (String, String)> =
        structure_rows.iter().map(|f| (f[1].clone(), (f[2].clone(), f[3].clone()))).collect();
    let system = lines("native_dofs.csv");
    let (body, plate_rows): (Vec<_>, Vec<_>) = system.iter().partition(|f| f[6] == "shaker");
    assert_eq!(body.len(), 1, "one body row, the top mass");
    assert!(body.iter().all(|f| f[1].is_empty() && f[2].is_empty() && f[3].is_empty() && f[5] == "z_t"));
    assert_eq!(plate_rows.len(), structure_rows.len());
    for f in plate_rows {
        assert_eq!(own[&f[1]], (f[2].clone(), f[3].clone()), "row {} of node {}", f[0], f[1]);
        assert!(f[4].is_empty(), "a plate row has no z: {f:?}");
    }
}

/// A spring–mass chain written by hand: M, K and a map, in a folder.
struct Chain {
    _dir: tempfile::TempDir,
    files: Files,
}

fn chain(m: &str, k: &str, dofs: &str) -> Chain {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str, text: &str| -> PathBuf {
        let p = dir.path().join(n);
        std::fs::write(&p, text).unwrap();
        p
    };
    let files = Files {
        mass: p("m.mtx", m),
        stiffness: p("k.mtx", k),
        damping: None,
        dofs: p("dofs.csv", dofs),
        fixed: vec![],
    };
    Chain { _dir: dir, files }
}

const SYM: &str = "%%MatrixMarket matrix coordinate real symmetric\n";
const MAP2: &str = "row,node,x_m,y_m,z_m,component\n1,10,0,0,0,uz\n2,11,1,0,0,uz\n";

/// Two masses m on springs k (ground–m–m): ω² = (k/m)·(3 ∓ √5)/2.
#[test]
fn a_two_mass_chain_has_its_closed_form_modes() {
    let (m, k) = (2.0, 8.0e4);
    let c = chain(
        &format!("{SYM}2 2 2\n1 1 {m}\n2 2 {m}\n"),
        &format!("{SYM}2 2 3\n1 1 {}\n2 1 {}\n2 2 {k}\n", 2.0 * k, -k),
        MAP2,
    );
    let model = std::sync::Arc::new(Imported::load(&c.files, 1000, "case.toml").unwrap());
    assert_eq!(model.report.rigid_body_modes, 0);
    let s = beamflow::structure::Structure::Imported(model);
    let r = beamflow::analysis::modes::run(&s, 2).unwrap();
    for (f, sign) in r.frequencies_hz.iter().zip([-1.0, 1.0]) {
        let exact = ((k / m) * (3.0 + sign * 5f64.sqrt()) / 2.0).sqrt() / (2.0 * std::f64::consts::PI);
        assert!((f - exact).abs() <= 1e-12 * exact, "{f} against {exact}");
    }
}

#[test]
fn a_free_chain_reports_its_rigid_body_mode_and_a_massless_row_is_accepted() {
    // Free–free: one rigid translation.
    let c = chain(&format!("{SYM}2 2 2\n1 1 1\n2 2 1\n"), &format!("{SYM}2 2 3\n1 1 5\n2 1 -5\n2 2 5\n"), MAP2);
    assert_eq!(Imported::load(&c.files, 1000, "case.toml").unwrap().report.rigid_body_modes, 1);
    // A massless middle DOF held by stiffness (a lumped model's rotation, say).
    let map3 = "row,node,x_m,y_m,z_m,component\n1,1,0,0,0,uz\n2,1,0,0,0,ry\n3,2,1,0,0,uz\n";
    let c = chain(
        &format!("{SYM}3 3 2\n1 1 1\n3 3 1\n"),
        &format!("{SYM}3 3 5\n1 1 3\n2 1 -1\n2 2 3\n3 2 -1\n3 3 3\n"),
        map3,
    );
    let model = Imported::load(&c.files, 1000, "case.toml").unwrap();
    assert_eq!((model.report.massless_rows, model.report.rigid_body_modes), (1, 0));
}

#[test]
fn what_is_not_a_structure_is_refused_naming_the_file_and_row() {
    let m = format!("{SYM}2 2 2\n1 1 1\n2 2 1\n");
    let k = format!("{SYM}2 2 3\n1 1 2\n2 1 -1\n2 2 2\n");
    let gen = "%%MatrixMarket matrix coordinate real general\n";
    for (mm, kk, map, file, expect) in [
        (m.clone(), format!("{gen}2 2 4\n1 1 2\n1 2 -1\n2 1 -1.5\n2 2 2\n"), MAP2, "k.mtx", "not symmetric"),
        (format!("{SYM}2 2 2\n1 1 1\n2 2 -1\n"), k.clone(), MAP2, "m.mtx", "negative eigenvalue"),
        (m.clone(), format!("{SYM}2 2 3\n1 1 2\n2 1 -3\n2 2 2\n"), MAP2, "k.mtx", "negative eigenvalue"),
        (m.clone(), format!("{SYM}2 2 3\n1 1 NaN\n2 1 -1\n2 2 2\n"), MAP2, "k.mtx", "line 3"),
        (format!("{SYM}3 3 1\n1 1 1\n"), k.clone(), MAP2, "m.mtx", "3 rows"),
        (m.clone(), k.clone(), "row,node,x_m,y_m,z_m,component\n1,10,0,0,0,uz\n", "dofs.csv", "row 2"),
        (
            m.clone(),
            k.clone(),
            "row,node,x_m,y_m,z_m,component\n1,10,0,0,0,uz\n1,11,1,0,0,uz\n",
            "dofs.csv",
            "given twice",
        ),
        (format!("{SYM}2 2 1\n1 1 1\n"), format!("{SYM}2 2 1\n1 1 1\n"), MAP2, "k.mtx", "neither stiffness nor mass"),
    ] {
        let c = chain(&mm, &kk, map);
        let e = Imported::load(&c.files, 1000, "case.toml")
            .err()
            .unwrap_or_else(|| panic!("accepted {expect}"))
            .to_string();
        assert!(e.contains(file) && e.contains(expect), "{e} (expected {file}: {expect})");
    }
}

#[test]
fn a_case_on_an_imported_model_names_a_missing_node_and_a_bad_component() {
    let c = chain(&format!("{SYM}2 2 2\n1 1 1\n2 2 1\n"), &format!("{SYM}2 2 3\n1 1 2e6\n2 1 -1e6\n2 2 2e6\n"), MAP2);
    let dir = c.files.mass.parent().unwrap().to_path_buf();
    let case = |point: &str| {
        format!(
            "[imported]\nmass = \"m.mtx\"\nstiffness = \"k.mtx\"\ndofs = \"dofs.csv\"\n\
             [damping]\nkind = \"rayleigh\"\na0 = 2.0\na1 = 1e-5\n\
             [[actuator]]\ntype = \"inertial\"\n{point}\n[actuator.stack]\nhysteresis = false\n[actuator.voltage]\nkind = \"sine\"\namplitude = 1.0\nfrequency = 10.0\n\
             [[analysis]]\ntype = \"steady_state\"\n"
        )
    };
    for (point, field, expect) in [
        ("node = 99\ncomponent = \"uz\"", "actuator[0].node", "node 99 is not in the model"),
        ("node = 10\ncomponent = \"ux\"", "actuator[0].node", "no ux DOF at node 10"),
        ("node = 10\ncomponent = \"sideways\"", "actuator[0].component", "not a component"),
        ("x_e = 0.1", "actuator[0].node", "imported model takes the stack foot"),
    ] {
        let p = dir.join("case.toml");
        std::fs::write(&p, case(point)).unwrap();
        let e = beamflow::app::commands::run(&p, Some(&dir.join("out")), None, false, false, &Budget::default())
            .err()
            .unwrap_or_else(|| panic!("accepted {point}"))
            .to_string();
        assert!(e.contains("case.toml") && e.contains(field) && e.contains(expect), "{e} (expected {field}: {expect})");
    }
    // Driven on the +uz side and on the −uz side: the same power into the model.
    let power = |point: &str| {
        let p = dir.join("case.toml");
        std::fs::write(&p, case(point)).unwrap();
        let v = run(&p, &dir.join("out"));
        v["analyses"][0]["mean_power_w"]["inertial_stack"].as_f64().unwrap()
    };
    let (up, down) = (power("node = 11\ncomponent = \"uz\""), power("node = 11\ncomponent = \"-uz\""));
    assert!(up > 0.0 && (up - down).abs() <= 1e-12 * up, "{up} against {down}");
}

/// A lattice of `nx` × `ny` masses m, each tied to its four neighbours (and the walls
/// around it) by springs k, moving out of plane: M = m·I, K = k times the five-point
/// Laplacian with fixed edges. Its modes are known in closed form,
/// ω²_pq = (k/m)·[4 sin²(pπ/(2(nx+1))) + 4 sin²(qπ/(2(ny+1)))].
fn lattice(nx: usize, ny: usize, m: f64, k: f64) -> Chain {
    use std::fmt::Write;
    let n = nx * ny;
    let at = |i: usize, j: usize| j * nx + i + 1;
    let (mut mass, mut stiff, mut map) = (String::new(), String::new(), String::new());
    let mut entries = 0;
    for j in 0..ny {
        for i in 0..nx {
            let r = at(i, j);
            writeln!(mass, "{r} {r} {m}").unwrap();
            writeln!(stiff, "{r} {r} {}", 4.0 * k).unwrap();
            entries += 1;
            if i > 0 {
                writeln!(stiff, "{r} {} {}", at(i - 1, j), -k).unwrap();
                entries += 1;
            }
            if j > 0 {
                writeln!(stiff, "{r} {} {}", at(i, j - 1), -k).unwrap();
                entries += 1;
            }
            writeln!(map, "{r},{r},{},{},0,uz", 0.01 * i as f64, 0.01 * j as f64).unwrap();
        }
    }
    chain(
        &format!("{SYM}{n} {n} {n}\n{mass}"),
        &format!("{SYM}{n} {n} {entries}\n{stiff}"),
        &format!("row,node,x_m,y_m,z_m,component\n{map}"),
    )
}

/// About 10⁵ DOFs through the imported path: loaded and checked (two sparse LDLᵀ
/// inertias), then its lowest 50 modes by shift-invert Lanczos on the sparse factor, each
/// against the closed form.
#[test]
fn a_lattice_of_a_hundred_thousand_dofs_has_its_closed_form_modes() {
    let (nx, ny, m, k) = (400, 250, 0.05, 2.0e4);
    let c = lattice(nx, ny, m, k);
    let model = std::sync::Arc::new(Imported::load(&c.files, 10_000_000, "case.toml").unwrap());
    assert_eq!(model.report.rigid_body_modes, 0);
    let s = beamflow::structure::Structure::Imported(model);
    let count = 50;
    let r = beamflow::analysis::modes::run(&s, count).unwrap();
    let s2 = |p: usize, n: usize| (p as f64 * std::f64::consts::PI / (2.0 * (n + 1) as f64)).sin().powi(2);
    let mut exact: Vec<f64> = (1..=20)
        .flat_map(|p| (1..=20).map(move |q| (p, q)))
        .map(|(p, q)| ((k / m) * 4.0 * (s2(p, nx) + s2(q, ny))).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    exact.sort_by(f64::total_cmp);
    assert_eq!(r.frequencies_hz.len(), count);
    for (i, (f, e)) in r.frequencies_hz.iter().zip(&exact).enumerate() {
        assert!((f - e).abs() <= 1e-8 * e, "mode {}: {f} Hz against {e} Hz", i + 1);
    }
}
