//! Data for other tools: the Matrix Market matrices and the DOF map beside them name each
//! row, checked against element stiffnesses computed here.

mod common;

use beamflow::io::mtx::read_matrix_market;
use std::path::Path;

/// A row of `<stem>_dofs.csv`: (row − 1, node, x, kind, actuator).
type DofLine = (usize, Option<usize>, Option<f64>, String, String);

fn dof_map(path: &Path) -> Vec<DofLine> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("row,node,x_m,kind,actuator"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[0].parse::<usize>().unwrap() - 1, f[1].parse().ok(), f[2].parse().ok(), f[3].into(), f[4].into())
        })
        .collect()
}

#[test]
fn the_dof_map_names_the_stack_foot_and_the_top_mass_rows() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("foot.toml");
    let k_p = 3.0e7;
    std::fs::write(
        &case,
        format!(
            "[beam.mesh]\nelements = 40\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n\
             [[actuator]]\ntype = \"inertial\"\nname = \"shaker\"\nx_e = 0.15\n\
             [actuator.stack]\nk_p = {k_p:e}\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n\
             [[analysis]]\ntype = \"modes\"\ncount = 2\n[output]\nmatrices = true\nplots = false\n"
        ),
    )
    .unwrap();
    let out = dir.path().join("out");
    beamflow::app::commands::run(&case, Some(&out), None, false).unwrap();
    let k = read_matrix_market(&out.join("foot_K.mtx")).unwrap();
    assert!(std::fs::read_to_string(out.join("foot_K.mtx"))
        .unwrap()
        .starts_with("%%MatrixMarket matrix coordinate real symmetric"));
    let rows = dof_map(&out.join("foot_dofs.csv"));
    assert_eq!(rows.len(), k.rows());
    let foot =
        rows.iter().find(|r| r.3 == "w" && r.2.is_some_and(|x| (x - 0.15).abs() < 1e-12)).expect("w row at 0.15 m");
    let top = rows.iter().find(|r| r.3 == "z_t" && r.4 == "shaker").expect("the top mass's row");
    // Neighbouring nodes of the foot give the two element lengths around it.
    let xs: Vec<f64> = rows.iter().filter(|r| r.3 == "w").filter_map(|r| r.2).collect();
    let at = xs.iter().position(|&x| (x - 0.15).abs() < 1e-12).unwrap();
    let (h1, h2) = (xs[at] - xs[at - 1], xs[at + 1] - xs[at]);
    // A Hermite element's w–w stiffness is 12·EI/h³ at each end; the stack adds k_p.
    let beam = 12.0 * common::EI / h1.powi(3) + 12.0 * common::EI / h2.powi(3);
    let kd = |i: usize, j: usize| k.get(i, j).copied().unwrap_or(0.0);
    assert!(common::rel(kd(foot.0, foot.0), beam + k_p) < 1e-12, "{} vs {}", kd(foot.0, foot.0), beam + k_p);
    assert_eq!(kd(top.0, top.0), k_p);
    assert_eq!(kd(top.0, foot.0), -k_p);
    assert_eq!(kd(foot.0, top.0), -k_p);
}

/// A small transient-free case in `dir` (modes and a steady state, no figures).
fn small_case(dir: &Path) -> std::path::PathBuf {
    let case = dir.join("small.toml");
    std::fs::write(
        &case,
        "[beam.mesh]\nelements = 20\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n\
         [[actuator]]\ntype = \"inertial\"\nname = \"shaker\"\n\
         [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n\
         [[analysis]]\ntype = \"steady_state\"\n[output]\nplots = false\n",
    )
    .unwrap();
    case
}

fn beamflow(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_beamflow")).args(args).output().unwrap()
}

#[test]
fn json_to_standard_output_is_the_only_thing_there() {
    let dir = tempfile::tempdir().unwrap();
    let case = small_case(dir.path());
    let out = dir.path().join("out");
    let o = beamflow(&["run", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--json", "-"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is one JSON document");
    assert!(v.is_object());
    // The same numbers as the file the run writes, and the status lines on standard error.
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("small.json")).unwrap()).unwrap();
    assert_eq!(v, file);
    assert!(String::from_utf8_lossy(&o.stderr).contains("wrote"));
    let q = beamflow(&["run", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--quiet"]);
    assert!(q.status.success() && q.stdout.is_empty() && q.stderr.is_empty());
}

#[test]
fn json_may_not_replace_the_case_or_another_output() {
    let dir = tempfile::tempdir().unwrap();
    let case = small_case(dir.path());
    let before = std::fs::read(&case).unwrap();
    let out = dir.path().join("out");
    let targets = [
        (case.clone(), "the case file"),
        (out.join("small.h5"), "another output"),
        (out.join("sub/../small.json"), "another output"),
    ];
    for (target, why) in targets {
        let o = beamflow(&[
            "run",
            case.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--json",
            target.to_str().unwrap(),
        ]);
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && e.contains("--json") && e.contains(why), "{e}");
    }
    assert_eq!(std::fs::read(&case).unwrap(), before);
}

#[test]
fn completions_are_printed_for_each_shell() {
    for shell in ["bash", "zsh", "fish"] {
        let o = beamflow(&["completions", shell]);
        assert!(o.status.success());
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(text.contains("beamflow") && text.contains("sweep"), "{shell}");
    }
}

/// The keys of every analysis of a summary, sorted.
fn analysis_keys(v: &serde_json::Value) -> Vec<Vec<String>> {
    v["analyses"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| {
            let mut k: Vec<String> = a.as_object().unwrap().keys().cloned().collect();
            k.sort();
            k
        })
        .collect()
}

#[test]
fn a_rigid_base_reports_forces_and_no_beam_fields_in_the_same_shape() {
    let dir = tempfile::tempdir().unwrap();
    let cases = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    let out = dir.path().join("out");
    let run = |case: &str| {
        let o = beamflow(&[
            "run",
            cases.join(case).to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--no-plots",
            "--json",
            "-",
        ]);
        assert!(o.status.success());
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        (v, String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let (rigid, console) = run("rigid-base-48V-30Hz.toml");
    let (beam, _) = run("beam-frame-12V-60Hz.toml");
    assert_eq!((rigid["base"].as_str(), beam["base"].as_str()), (Some("rigid"), Some("beam")));
    let t = &rigid["analyses"][0];
    for key in ["mean_power_w", "net_power_w", "beam_dissipation_w"] {
        assert!(t[key].is_null(), "{key}: {}", t[key]);
    }
    assert!(t["energy_balance_rel_error"]["beam_run"].is_null());
    assert!(t["energy_balance_rel_error"]["system_run"].as_f64().unwrap() < 1e-9);
    // The same keys as a transient on the beam.
    assert_eq!(analysis_keys(&rigid)[0], analysis_keys(&beam)[1]);
    // The console shows the forces and the stack-force ratio, the point of the case.
    let f = &t["transmitted_force_amplitude_at_drive_n"];
    let ratio = f["frame_stack"].as_f64().unwrap() / f["inertial_stack"].as_f64().unwrap();
    assert!(console.contains(&format!("frame_stack / inertial_stack force ratio {ratio:.1}")), "{console}");
    assert!(!console.contains("mean power into the base"), "{console}");
}
