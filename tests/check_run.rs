//! `beamflow check` refuses what `run` refuses, with the same message, and `run` refuses it
//! before any solve: nothing is written.

use beamflow::analysis::budget::Budget;
use beamflow::app::commands;
use std::path::Path;

const SINE: &str = "[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";
const CHIRP: &str =
    "[actuator.voltage]\nkind = \"chirp\"\namplitude = 10.0\nf_start = 5.0\nf_end = 50.0\nduration = 1.0\nsweep = \"linear\"\n";

fn inertial(voltage: &str) -> String {
    format!("[[actuator]]\ntype = \"inertial\"\n{voltage}")
}

/// (case text, field the message must name, words it must hold)
fn table() -> Vec<(String, &'static str, &'static str)> {
    let beam = "[beam.mesh]\nelements = 40\n";
    vec![
        (format!("{beam}{}[[analysis]]\ntype = \"transient\"\ndt = 1e-3\n", inertial(SINE)), "analysis[0].dt", "whole steps"),
        (format!("{beam}{}[[analysis]]\ntype = \"transient\"\nsteps_per_period = 10\n", inertial(SINE)), "analysis[0].dt", "too coarse"),
        (format!("{beam}{}[[analysis]]\ntype = \"transient\"\nscheme = \"linear_acceleration\"\n", inertial(SINE)), "analysis[0].dt", "stability limit"),
        (format!("{beam}{}[[analysis]]\ntype = \"steady_state\"\n", inertial(CHIRP)), "analysis[0].type", "non-periodic"),
        (
            format!("{beam}[damping]\nkind = \"modal\"\nratios = [0.01]\n{}[[analysis]]\ntype = \"transient\"\n", inertial(SINE)),
            "damping",
            "transient analysis without `reduction`",
        ),
        (
            format!("{beam}{}[[analysis]]\ntype = \"transient\"\nduration = 0.5\nreduction = \"auto\"\n", inertial(CHIRP)),
            "analysis[0].reduction",
            "periodic drive",
        ),
        (
            format!("{beam}[[actuator]]\ntype = \"inertial\"\nname = \"a\"\n{SINE}[[actuator]]\ntype = \"frame\"\nname = \"a\"\n{SINE}[[analysis]]\ntype = \"steady_state\"\n"),
            "actuator[1].name",
            "already the name",
        ),
        (format!("{beam}[[actuator]]\ntype = \"inertial\"\nname = \"x/../../up\"\n{SINE}"), "actuator[0].name", "not a valid name"),
        (format!("base = \"rigid\"\n{}[[analysis]]\ntype = \"modes\"\n", inertial(SINE)), "analysis[0]", "needs a structure"),
        (format!("{beam}[[sensor]]\nname = \"s\"\nx = 0.1\n[[sensor]]\nname = \"s\"\nx = 0.2\n"), "sensor[1].name", "already the name"),
        (
            format!("[beam.mesh]\nroundoff_tolerance = 2.0\n{}[[analysis]]\ntype = \"steady_state\"\n", inertial(SINE)),
            "beam.mesh.roundoff_tolerance",
            "[1e-12, 1)",
        ),
    ]
}

fn visible_files(dir: &Path) -> usize {
    std::fs::read_dir(dir)
        .map_or(0, |rd| rd.flatten().filter(|e| !e.file_name().to_string_lossy().starts_with('.')).count())
}

#[test]
fn check_refuses_what_run_refuses_before_any_solve() {
    let dir = tempfile::tempdir().unwrap();
    for (i, (text, field, words)) in table().into_iter().enumerate() {
        let case = dir.path().join(format!("c{i}.toml"));
        std::fs::write(&case, &text).unwrap();
        let checked = match commands::check(&case, &Budget::default()) {
            Err(e) => e.to_string(),
            Ok(()) => panic!("case {i}: check accepted\n{text}"),
        };
        let out = dir.path().join(format!("out{i}"));
        let ran = commands::run(&case, Some(&out), None, false, false, &Budget::default()).unwrap_err().to_string();
        assert_eq!(checked, ran, "case {i}: check and run differ");
        assert!(
            checked.contains(&format!("c{i}.toml")) && checked.contains(field) && checked.contains(words),
            "case {i}: {checked}"
        );
        assert_eq!(visible_files(&out), 0, "case {i}: run wrote files before refusing");
    }
}

/// `--quiet` means nothing on either stream, whichever command it is given to.
#[test]
fn quiet_commands_print_nothing() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = tempfile::tempdir().unwrap();
    let o = |name: &str| out.path().join(name).to_string_lossy().into_owned();
    let cases = |name: &str| root.join("cases").join(name).to_string_lossy().into_owned();
    let commands: Vec<Vec<String>> = vec![
        vec!["check".into(), cases("two-frames.toml")],
        vec!["modes".into(), cases("paper-beam.toml")],
        vec!["run".into(), cases("placement-frame.toml"), "--no-plots".into(), "--out".into(), o("run")],
        vec!["sweep".into(), cases("placement-frame.sweep.toml"), "--out".into(), o("sweep.h5")],
        vec!["optimize".into(), cases("two_frames.opt.toml"), "--no-plots".into(), "--out".into(), o("opt")],
    ];
    for args in commands {
        let r = std::process::Command::new(env!("CARGO_BIN_EXE_beamflow")).arg("--quiet").args(&args).output().unwrap();
        assert!(r.status.success(), "{args:?}: {}", String::from_utf8_lossy(&r.stderr));
        let (stdout, stderr) = (String::from_utf8_lossy(&r.stdout), String::from_utf8_lossy(&r.stderr));
        assert!(stdout.is_empty() && stderr.is_empty(), "{args:?} printed:\n{stdout}{stderr}");
    }
}

/// A value admissible but likely a slip of units is named with the slip, on `check` and
/// `run`; a refusal it causes elsewhere names it too.
#[test]
fn slips_of_units_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let sine = "[[actuator]]\ntype = \"inertial\"\nx_e = 0.15\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";
    let beamflow =
        |args: &[&str]| std::process::Command::new(env!("CARGO_BIN_EXE_beamflow")).args(args).output().unwrap();
    let light = dir.path().join("light.toml");
    std::fs::write(&light, format!("[beam]\ndensity = 7.85\n{sine}[[analysis]]\ntype = \"modes\"\n")).unwrap();
    let r = beamflow(&["check", light.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(r.status.success() && err.contains("warning") && err.contains("densities are in kg/m³"), "{err}");
    let long = dir.path().join("long.toml");
    std::fs::write(&long, format!("[beam]\nlength = 730.0\n{sine}")).unwrap();
    let r = beamflow(&["check", long.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(!r.status.success() && err.contains("lengths are in metres (730 mm is 0.73)"), "{err}");
    // A plate's slips are its own fields', and a plate case's beam defaults are not read.
    let plate = |field: &str, value: &str| {
        let mut fields = vec![("length_x", "0.6"), ("length_y", "0.4"), ("thickness", "0.002")];
        fields.extend([("youngs_modulus", "70e9"), ("poisson_ratio", "0.33"), ("density", "2700.0")]);
        let table: String =
            fields.iter().map(|(k, v)| format!("{k} = {}\n", if *k == field { value } else { v })).collect();
        let edges = "[plate.edges]\nx0 = \"simply_supported\"\nx1 = \"simply_supported\"\ny0 = \"simply_supported\"\ny1 = \"simply_supported\"\n";
        let at = sine.replace("x_e = 0.15", "at = [0.2, 0.15]");
        let path = dir.path().join(format!("plate_{field}.toml"));
        std::fs::write(&path, format!("[plate]\n{table}{edges}{at}[[analysis]]\ntype = \"modes\"\n")).unwrap();
        let r = beamflow(&["check", path.to_str().unwrap()]);
        (r.status.success(), String::from_utf8_lossy(&r.stderr).into_owned())
    };
    for (field, value, hint) in [
        ("youngs_modulus", "70", "moduli are in Pa (70 GPa is 7e10)"),
        ("density", "2.7", "densities are in kg/m³"),
        ("length_x", "600", "lengths are in metres"),
    ] {
        let (ok, err) = plate(field, value);
        assert!(ok && err.contains(&format!("`plate.{field}`")) && err.contains(hint), "{field}: {err}");
    }
    let (ok, err) = plate("density", "2700.0");
    assert!(ok && !err.contains("warning"), "{err}");
}

/// A foot where the plate cannot move (a held edge, a pinned point support) takes no
/// power: `check` says which foot and why; a foot on a free edge or off the support is
/// not named.
#[test]
fn feet_on_held_points_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let check = |edges: [&str; 4], at: &str, support: &str| {
        let path = dir.path().join("held.toml");
        let [x0, x1, y0, y1] = edges;
        std::fs::write(
            &path,
            format!(
                "[plate]\nlength_x = 0.6\nlength_y = 0.4\nthickness = 0.002\nyoungs_modulus = 70e9\n\
                 poisson_ratio = 0.33\ndensity = 2700.0\n[plate.edges]\nx0 = \"{x0}\"\nx1 = \"{x1}\"\n\
                 y0 = \"{y0}\"\ny1 = \"{y1}\"\n{support}[[actuator]]\ntype = \"frame\"\nat = {at}\n\
                 [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n"
            ),
        )
        .unwrap();
        let r = std::process::Command::new(env!("CARGO_BIN_EXE_beamflow")).args(["check"]).arg(&path).output().unwrap();
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        String::from_utf8_lossy(&r.stderr).into_owned()
    };
    let held = ["clamped", "simply_supported", "simply_supported", "free"];
    let err = check(held, "[0.2, 0.0]", "");
    for foot in ["stack foot at (0.2, 0) m", "left leg foot", "right leg foot"] {
        assert!(err.contains(foot) && err.contains("simply supported edge `plate.edges.y0`"), "{foot}: {err}");
    }
    assert!(check(held, "[0.2, 0.4]", "").is_empty(), "the free edge y1 moves");
    let pinned = "[[plate.support]]\nat = [0.3, 0.2]\nkind = \"pinned\"\n";
    let err = check(held, "[0.3, 0.2]", pinned);
    assert!(err.contains("stack foot at (0.3, 0.2) m is on a point support"), "{err}");
    assert!(!err.contains("leg foot"), "the legs are off the support: {err}");
    assert!(check(held, "[0.3, 0.25]", pinned).is_empty());
}

/// A mesh file of 10⁶ nodes for an analysis that solves on the mesh is refused from a
/// count of its text, before the TOML parser builds its document: within a second and
/// 100 MB (peak resident memory of the child, from `wait4`).
#[test]
fn a_million_node_mesh_file_is_refused_before_it_is_parsed() {
    let dir = tempfile::tempdir().unwrap();
    let n = 1_000_000;
    let nodes: Vec<String> = (0..=n).map(|i| format!("{:.7}", 0.73 * i as f64 / n as f64)).collect();
    std::fs::write(
        dir.path().join("fine.toml"),
        format!("format = \"beamflow-mesh-1\"\nnodes = [{}]\n", nodes.join(", ")),
    )
    .unwrap();
    let case = dir.path().join("c.toml");
    std::fs::write(
        &case,
        "[beam.mesh]\nfile = \"fine.toml\"\n[[actuator]]\ntype = \"inertial\"\nx_e = 0.1825\n\
         [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n[[analysis]]\ntype = \"steady_state\"\n",
    )
    .unwrap();
    let start = std::time::Instant::now();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_beamflow"))
        .args(["check", "--max-memory", "1G", case.to_str().unwrap()])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
    let (mut status, mut usage) = (0, unsafe { std::mem::zeroed::<libc::rusage>() });
    let pid = unsafe { libc::wait4(child.id() as i32, &mut status, 0, &mut usage) };
    let took = start.elapsed();
    assert_eq!(pid, child.id() as i32);
    assert!(libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 1, "{stderr}");
    assert!(stderr.contains("beam.mesh.elements") && stderr.contains("1000000 elements"), "{stderr}");
    let peak = usage.ru_maxrss as u64 * 1024;
    assert!(took.as_secs_f64() < 1.0 && peak < 100 << 20, "took {took:?}, peak {} MB", peak >> 20);
}
