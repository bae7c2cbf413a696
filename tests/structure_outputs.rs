//! What a run writes about plates and imported models: every position with all of its
//! coordinates (a beam's x alone does not place a point on a plate), and words and numbers
//! that name the structure run rather than a beam.

use beamflow::io::tree::{Attr, Data, Group};
use std::path::{Path, PathBuf};

fn beamflow(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_beamflow")).args(args).output().unwrap()
}

/// Runs `case` into `out` with CSV tables; the HDF5 file read back as a tree.
fn run(case: &Path, out: &Path) -> Group {
    let o = beamflow(&["run", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--csv", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stem = case.file_stem().unwrap().to_string_lossy();
    beamflow::io::hdf5::ResultsReader::open(out.join(format!("{stem}.h5"))).unwrap().read_tree().unwrap()
}

fn reals(g: &Group, path: &str) -> Vec<f64> {
    match &g.dataset(path).unwrap_or_else(|| panic!("{path} missing")).data {
        Data::F64(v) => v.clone(),
        d => panic!("{path}: {d:?}"),
    }
}

fn attr(g: &Group, path: &str, name: &str) -> Attr {
    g.group(path)
        .unwrap_or_else(|| panic!("{path} missing"))
        .attrs
        .get(name)
        .cloned()
        .unwrap_or_else(|| panic!("{path}@{name}"))
}

/// The header of a CSV file: column names without their units.
fn header(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines().next().unwrap().split(',').map(|c| c.split(" [").next().unwrap().to_string()).collect()
}

/// A small plate with a frame actuator, a sensor, a load, modes and a forced harmonic.
fn plate_case(dir: &Path) -> PathBuf {
    let case = dir.join("p.toml");
    std::fs::write(
        &case,
        "[plate]\nlength_x = 0.5\nlength_y = 0.4\nthickness = 0.003\nyoungs_modulus = 70e9\n\
         poisson_ratio = 0.33\ndensity = 2700.0\n[plate.mesh]\nelements = [10, 8]\n\
         [plate.edges]\nx0 = \"simply_supported\"\nx1 = \"simply_supported\"\n\
         y0 = \"simply_supported\"\ny1 = \"simply_supported\"\n\
         [damping]\nkind = \"rayleigh_ratio\"\nzeta = 0.01\nmodes = [1, 3]\n\
         [[actuator]]\ntype = \"frame\"\nname = \"frame\"\nat = [0.2, 0.15]\n\
         [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 83.0\n\
         [[sensor]]\nname = \"probe\"\nat = [0.3, 0.25]\n\
         [[load]]\nname = \"tap\"\nat = [0.35, 0.1]\n[load.force]\nkind = \"sine\"\namplitude = 0.5\nfrequency = 83.0\n\
         [[analysis]]\ntype = \"modes\"\ncount = 3\n\
         [[analysis]]\ntype = \"harmonic\"\n[analysis.frequencies]\nvalues = [50.0, 80.0]\n\
         [[analysis.force]]\nat = [0.17, 0.23]\namplitude = 1.0\n\
         [[analysis]]\ntype = \"steady_state\"\nharmonics = 3\n[output]\nplots = false\n",
    )
    .unwrap();
    case
}

#[test]
fn plate_results_place_every_point_and_node_by_x_and_y() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let tree = run(&plate_case(dir.path()), &out);
    // The harmonic's points: the force, then the sensor.
    assert_eq!(reals(&tree, "analysis_1_harmonic/point_x"), [0.17, 0.3]);
    assert_eq!(reals(&tree, "analysis_1_harmonic/point_y"), [0.23, 0.25]);
    let (x, y) = (reals(&tree, "analysis_0_modes/node_x"), reals(&tree, "analysis_0_modes/node_y"));
    assert_eq!(x.len(), 11 * 9);
    assert_eq!(y, reals(&tree, "model/node_y"));
    assert!(y.iter().any(|&v| v > 0.39) && tree.dataset("analysis_0_modes/node_z").is_none());
    let ss = "analysis_2_steady_state";
    assert_eq!(attr(&tree, &format!("{ss}/links/frame_stack"), "foot_y_m"), Attr::F64(0.15));
    assert_eq!(attr(&tree, &format!("{ss}/sensors/probe"), "y_m"), Attr::F64(0.25));
    assert_eq!(attr(&tree, &format!("{ss}/loads/tap"), "y_m"), Attr::F64(0.1));
    assert!(!tree.group(&format!("{ss}/links/frame_stack")).unwrap().attrs.contains_key("foot_z_m"));
    // The CSV tables carry y beside x.
    let points = header(&out.join(format!("p_{ss}_point_power.csv")));
    assert_eq!(points[..4], ["point", "kind", "x", "y"]);
    assert_eq!(header(&out.join("p_analysis_0_modes_mode_shapes.csv"))[..2], ["node_x", "node_y"]);
}

#[test]
fn imported_results_name_each_point_by_node_component_and_position() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/portal-frame/portal-frame.toml");
    let tree = run(&case, &out);
    let link = "analysis_1_steady_state/links/frame_stack";
    assert_eq!(attr(&tree, link, "foot_x_m"), Attr::F64(0.45));
    assert_eq!(attr(&tree, link, "foot_y_m"), Attr::F64(1.0));
    assert_eq!(attr(&tree, link, "foot_z_m"), Attr::F64(0.0));
    assert_eq!(attr(&tree, link, "foot_component"), Attr::Str("uy".into()));
    assert!(matches!(attr(&tree, link, "foot_node"), Attr::I64(_)));
    let n = reals(&tree, "analysis_0_modes/node_x").len();
    assert_eq!(reals(&tree, "analysis_0_modes/node_z").len(), n);
    assert!(matches!(&tree.dataset("model/node_id").unwrap().data, Data::I64(v) if v.len() == n));
    let points = header(&out.join("portal-frame_analysis_1_steady_state_point_power.csv"));
    assert_eq!(points[..7], ["point", "kind", "x", "y", "z", "node", "component"]);
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn a_plate_run_names_the_plate_and_calls_its_round_off_an_estimate() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let tree = run(&plate_case(dir.path()), &out);
    let v = json(&out.join("p.json"));
    let steady = &v["analyses"][2];
    assert!(steady["structure_dissipation_w"].as_f64().unwrap() > 0.0);
    assert_eq!(steady["structure_dissipation_w"], steady["beam_dissipation_w"], "the old key stays");
    let dissipation = |name: &str| attr(&tree, "analysis_2_steady_state", name);
    assert!(matches!(dissipation("structure_dissipation_W"), Attr::F64(w) if w > 0.0));
    assert_eq!(dissipation("structure_dissipation_W"), dissipation("beam_dissipation_W"), "the old attribute stays");
    assert_eq!(steady["mesh_roundoff_kind"], "estimate");
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    for beam in ["base: beam", "into the beam", "in the beam", "beam modes", "beam dissipation"] {
        assert!(!html.contains(beam), "the plate's report says {beam:?}");
    }
    assert!(html.contains("power dissipated in the plate") && html.contains("an estimate, not a bound"));
}

#[test]
fn a_harmonic_analysis_without_forces_states_no_balance() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("tf.toml");
    std::fs::write(
        &case,
        "[beam.mesh]\nelements = 20\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n\
         [[actuator]]\ntype = \"inertial\"\nname = \"shaker\"\n\
         [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n\
         [[analysis]]\ntype = \"harmonic\"\nsystem = \"coupled\"\n[analysis.frequencies]\nvalues = [30.0, 60.0]\n\
         [output]\nplots = false\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let o = beamflow(&["run", case.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let console = String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr);
    assert!(
        console.contains("2 frequencies of transfer functions (no force applied: no power to balance)"),
        "{console}"
    );
    let h = &json(&out.join("tf.json"))["analyses"][0];
    assert!(h["max_balance_error"].is_null() && h["mesh_roundoff"].is_null(), "{h}");
    assert_eq!(h["forced"], false);
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("n/a (no forcing)"));
    let tree = beamflow::io::hdf5::ResultsReader::open(out.join("tf.h5")).unwrap().read_tree().unwrap();
    assert_eq!(attr(&tree, "analysis_0_harmonic", "forced"), Attr::I64(0));
}
