//! Bad input is rejected with a message naming the file, the field and the reason.

mod common;
use beamflow::case::LoadedCase;
use common::*;
use std::path::PathBuf;

const SINE: &str = "[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";

fn expect(text: &str, needles: &[&str]) {
    let msg = case_error(text);
    assert!(msg.contains("bad.toml"), "message must name the file: {msg}");
    for n in needles {
        assert!(msg.contains(n), "message must mention `{n}`: {msg}");
    }
}

#[test]
fn non_positive_beam_properties() {
    for (field, v) in
        [("youngs_modulus", "0.0"), ("density", "-7850.0"), ("length", "0.0"), ("width", "-0.05"), ("thickness", "0.0")]
    {
        expect(&format!("[beam]\n{field} = {v}\n"), &[&format!("beam.{field}"), "positive"]);
    }
}

#[test]
fn points_outside_the_beam() {
    expect(&format!("[[actuator]]\ntype = \"inertial\"\nx_e = 0.9\n{SINE}"), &["actuator[0].x_e", "outside the beam"]);
    expect("[[sensor]]\nname = \"s\"\nx = -0.1\n", &["sensor[0].x", "outside"]);
    expect(&format!("[[actuator]]\ntype = \"frame\"\nx_e = 0.02\n{SINE}"), &["actuator[0].x_e", "left leg"]);
}

#[test]
fn unknown_fields_and_misplaced_fields() {
    expect("[beam]\nyoung = 1.0\n", &["unknown field", "young"]);
    // A field of the other actuator type: named with the line of its table.
    expect(&format!("[[actuator]]\ntype = \"inertial\"\nk_l = 1e9\n{SINE}"), &["line 1", "`k_l`", "only to a frame"]);
    expect(&format!("[[actuator]]\ntype = \"frame\"\nm_t = 0.2\n{SINE}"), &["line 1", "`m_t`", "only to an inertial"]);
    expect(&format!("[[actuator]]\ntype = \"frame\"\n{SINE}amplitud = 3.0\n"), &["unknown field", "amplitud"]);
}

#[test]
fn malformed_toml_reports_line_and_column() {
    expect("[beam]\nlength = = 3\n", &["line 2", "column"]);
}

#[test]
fn non_positive_frequency() {
    expect("[[analysis]]\ntype = \"harmonic\"\n[analysis.frequencies]\nvalues = [10.0, 0.0]\n[[analysis.force]]\nx = 0.1\n", &["analysis[0].frequencies.values[1]", "positive"]);
    expect(
        "[[actuator]]\ntype = \"inertial\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 1.0\nfrequency = -5.0\n",
        &["actuator[0].voltage", "frequency"],
    );
}

#[test]
fn mesh_file_missing_a_required_node_names_the_point() {
    let text = format!(
        "[beam.mesh]\nfile = \"../meshes/paper-beam-50.toml\"\n[[actuator]]\ntype = \"inertial\"\nx_e = 0.2\n{SINE}"
    );
    let lc = LoadedCase::from_str(&text, "bad.toml", PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases")).unwrap();
    let msg = beamflow::analysis::plan::calibrated_model(&lc).unwrap_err().to_string();
    assert!(msg.contains("paper-beam-50.toml") && msg.contains("actuator[0].x_e") && msg.contains("0.2"), "{msg}");
}

#[test]
fn shipped_meshes_load_and_converge() {
    let f: Vec<f64> = [50, 100, 200]
        .iter()
        .map(|n| {
            let text = format!("[beam.mesh]\nfile = \"../meshes/paper-beam-{n}.toml\"\n");
            let lc =
                LoadedCase::from_str(&text, "m.toml", PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases")).unwrap();
            let beam = beamflow::case::build::build_beam(&lc).unwrap();
            beamflow::analysis::modes::run(&beamflow::structure::Structure::from(&beam), 1).unwrap().frequencies_hz[0]
        })
        .collect();
    assert!((f[2] - 49.8837).abs() < 1e-3 && (f[0] - f[2]).abs() > (f[1] - f[2]).abs());
}

#[test]
fn bouc_wen_constraints_and_non_positive_stack_parameters() {
    expect(
        &format!("[[actuator]]\ntype = \"inertial\"\n[actuator.stack]\nbeta = 0.001\ngamma = 0.01\n{SINE}"),
        &["actuator[0].stack", "gamma"],
    );
    expect(
        &format!("[[actuator]]\ntype = \"inertial\"\n[actuator.stack]\nalpha = -0.3\n{SINE}"),
        &["actuator[0].stack.alpha"],
    );
    expect(
        &format!("[[actuator]]\ntype = \"inertial\"\n[actuator.stack]\nd_p = 0.0\n{SINE}"),
        &["actuator[0].stack.d_p"],
    );
    expect(
        &format!("[[actuator]]\ntype = \"inertial\"\n[actuator.stack]\nk_p = 0.0\n{SINE}"),
        &["actuator[0].stack.k_p", "positive"],
    );
    expect(&format!("[[actuator]]\ntype = \"inertial\"\nm_t = -1.0\n{SINE}"), &["actuator[0].m_t", "positive"]);
    expect(&format!("[[actuator]]\ntype = \"frame\"\nm_b = 0.0\n{SINE}"), &["actuator[0].m_b", "positive"]);
    expect(&format!("[[actuator]]\ntype = \"frame\"\nk_l = -1.0\n{SINE}"), &["actuator[0].k_l", "positive"]);
}

#[test]
fn time_step_errors() {
    expect("[[analysis]]\ntype = \"transient\"\ndt = 0.0\n", &["analysis[0].dt", "positive"]);
    let run = |step: &str| {
        let text = format!("base = \"rigid\"\n[[actuator]]\ntype = \"inertial\"\n{SINE}[[analysis]]\ntype = \"transient\"\n{step}\nharmonics = 9\n");
        let lc = LoadedCase::from_str(&text, "bad.toml", PathBuf::from(".")).unwrap();
        beamflow::app::runner::run_case(&lc).unwrap_err().to_string()
    };
    // 1 ms does not divide the 60 Hz period: never rounded silently, the nearest steps named.
    let msg = run("dt = 1e-3");
    assert!(
        msg.contains("bad.toml") && msg.contains("analysis[0].dt") && msg.contains("`steps_per_period` = 17"),
        "{msg}"
    );
    // 100 steps a period resolve harmonic 9 of 60 Hz with 11 steps, not 20: 180 are needed.
    let msg = run("steps_per_period = 100");
    assert!(msg.contains("too coarse") && msg.contains("`steps_per_period` ≥ 180"), "{msg}");
    expect(
        "[[analysis]]\ntype = \"transient\"\ndt = 1e-4\nsteps_per_period = 100\n",
        &["analysis[0].steps_per_period", "not both"],
    );
}

#[test]
fn voltage_series_files() {
    for (file, needle) in [
        ("voltage-non-increasing.csv", "time"),
        ("voltage-nan.csv", "voltage"),
        ("voltage-missing-column.csv", "voltage"),
    ] {
        let text =
            format!("[[actuator]]\ntype = \"inertial\"\n[actuator.voltage]\nkind = \"series\"\nfile = \"{file}\"\n");
        let lc = LoadedCase::from_str(&text, "bad.toml", PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data"))
            .unwrap();
        let msg = beamflow::analysis::plan::calibrated_model(&lc).unwrap_err().to_string();
        assert!(msg.contains(file) && msg.contains(needle), "{file}: {msg}");
    }
}

/// A reader that goes away (`beamflow modes case.toml | head -1`) is not an error: the
/// command neither panics nor fails.
#[test]
fn closed_standard_output_is_not_a_panic() {
    use std::process::{Command, Stdio};
    let case = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases/paper-beam.toml");
    let mut child = Command::new(env!("CARGO_BIN_EXE_beamflow"))
        .args(["modes", case.to_str().unwrap(), "--count", "40"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the beamflow binary runs");
    // Close the read end before the command prints anything.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "status {:?}, stderr: {stderr}", out.status);
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// Modal damping is a matrix only in modal coordinates: a transient without a modal
/// reduction is refused (naming the file and the field and pointing to `reduction`) instead
/// of running undamped; with a reduction it runs, as do the steady-state and harmonic
/// analyses.
#[test]
fn modal_damping_needs_a_reduction_in_the_time_domain() {
    const BASE: &str = "[damping]\nkind = \"modal\"\nratios = [0.01]\n\
        [[actuator]]\ntype = \"frame\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";
    let text = format!("{BASE}[[analysis]]\ntype = \"transient\"\nperiods = 2\n");
    let lc = LoadedCase::from_str(&text, "bad.toml", PathBuf::from(".")).unwrap();
    let msg = match beamflow::app::runner::run_case(&lc) {
        Ok(_) => panic!("a modal-damped transient without reduction ran"),
        Err(e) => e.to_string(),
    };
    for needle in ["bad.toml", "damping.kind", "modal", "reduction"] {
        assert!(msg.contains(needle), "message must mention `{needle}`: {msg}");
    }
    for analysis in [
        "type = \"transient\"\nperiods = 2\nreduction = \"auto\"",
        "type = \"steady_state\"",
        "type = \"harmonic\"\n[analysis.frequencies]\nvalues = [60.0]\n[[analysis.force]]\nx = 0.15",
    ] {
        let text = format!("{BASE}[[analysis]]\n{analysis}\n");
        let lc = LoadedCase::from_str(&text, "ok.toml", PathBuf::from(".")).unwrap();
        if let Err(e) = beamflow::app::runner::run_case(&lc) {
            panic!("modal damping in `{analysis}`: {e}");
        }
    }
}

#[test]
fn amplitudes_beyond_the_admissible_range_are_refused_before_they_overflow() {
    let load = |amplitude: &str, analysis: &str| {
        format!(
            "[[load]]\nx = 0.2\n[load.force]\nkind = \"sine\"\namplitude = {amplitude}\nfrequency = 60.0\n\
             [[analysis]]\ntype = \"{analysis}\"\nperiods = 3\n"
        )
        .replace("periods = 3\n", if analysis == "transient" { "periods = 3\n" } else { "" })
    };
    for analysis in ["steady_state", "transient"] {
        // 1e300 N would overflow the powers (∝ F²): refused at load, with the range.
        let e = LoadedCase::from_str(&load("1e300", analysis), "huge.toml", PathBuf::from(".")).unwrap_err();
        let e = e.to_string();
        assert!(e.contains("huge.toml") && e.contains("load[0].force.amplitude") && e.contains("1e9 N"), "{e}");
        // The largest admissible amplitude gives finite results.
        let lc = LoadedCase::from_str(&load("1e9", analysis), "big.toml", PathBuf::from(".")).unwrap();
        let run = beamflow::app::runner::run_case(&lc).unwrap();
        assert!(run.results.iter().all(|r| r.non_finite().is_none()), "{analysis}");
        // The same case at a physical amplitude runs.
        let lc = LoadedCase::from_str(&load("1.0", analysis), "ok.toml", PathBuf::from(".")).unwrap();
        beamflow::app::runner::run_case(&lc).unwrap();
    }
}

/// A case describes one structure: a `[beam]` of its own beside a `[plate]` or an
/// `[imported]` model is refused, naming the table; one that only repeats the beam's
/// defaults is the same as none.
#[test]
fn one_structure_per_case() {
    let plate = "[plate]\nlength_x = 0.5\nlength_y = 0.4\nthickness = 0.003\nyoungs_modulus = 70e9\n\
        poisson_ratio = 0.33\ndensity = 2700.0\n[plate.edges]\nx0 = \"clamped\"\nx1 = \"free\"\ny0 = \"free\"\ny1 = \"free\"\n";
    expect(&format!("[beam]\nlength = 0.5\n{plate}"), &["plate", "not both"]);
    expect(&format!("[beam.mesh]\nelements = 40\n{plate}"), &["plate", "not both"]);
    let imported = "[imported]\nmass = \"m.mtx\"\nstiffness = \"k.mtx\"\ndofs = \"dofs.csv\"\n";
    expect(&format!("[beam]\nthickness = 0.004\n{imported}"), &["imported", "without `[beam]`"]);
    let defaults = format!("[beam]\nlength = 0.73\n{plate}[[analysis]]\ntype = \"modes\"\n");
    assert!(LoadedCase::from_str(&defaults, "plate.toml", PathBuf::from(".")).is_ok(), "the beam's defaults alone");
}

#[test]
fn a_fixed_row_named_twice_is_refused() {
    let imported = "[imported]\nmass = \"m.mtx\"\nstiffness = \"k.mtx\"\ndofs = \"dofs.csv\"\nfixed = [4, 53, 53]\n";
    expect(imported, &["imported.fixed[2]", "row 53", "imported.fixed[1]"]);
}

/// A frame turned along an axis stands its legs exactly on the edge its stack foot is on
/// (90° in radians is not π/2, and cos ψ ≈ 6e-17 would put a leg a hair outside); a point
/// truly outside is named in readable numbers.
#[test]
fn a_frame_along_an_edge_stands_on_it() {
    let plate = "[plate]\nlength_x = 0.5\nlength_y = 0.4\nthickness = 0.003\nyoungs_modulus = 70e9\n\
        poisson_ratio = 0.33\ndensity = 2700.0\n[plate.edges]\nx0 = \"free\"\nx1 = \"simply_supported\"\n\
        y0 = \"simply_supported\"\ny1 = \"simply_supported\"\n[damping]\nkind = \"rayleigh\"\na0 = 1.0\na1 = 1e-6\n";
    let frame = |x: f64, direction: f64| {
        format!("{plate}[[actuator]]\ntype = \"frame\"\nat = [{x}, 0.2]\ndirection = {direction}\n{SINE}")
    };
    for (x, direction) in [(0.0, 90.0), (0.0, 270.0), (0.0, -90.0), (0.5, 90.0)] {
        let lc = LoadedCase::from_str(&frame(x, direction), "edge.toml", PathBuf::from(".")).unwrap();
        assert!(beamflow::analysis::plan::calibrated_model(&lc).is_ok(), "x = {x}, direction {direction}°");
    }
    let msg = case_error(&frame(0.0, 91.0));
    assert!(msg.contains("actuator[0].direction") && msg.contains("outside the plate"), "{msg}");
    assert!(!msg.contains("0.00000000"), "round-off written out in full: {msg}");
    // An angle beyond a turn either way keeps no digits of what was meant.
    for direction in ["1e300", "400.0", "-361.0"] {
        let msg = case_error(&frame(0.25, 0.0).replace("direction = 0", &format!("direction = {direction}")));
        assert!(msg.contains("actuator[0].direction") && msg.contains("within −360 to 360 degrees"), "{msg}");
    }
}

/// Two points whose grid lines would make a sliver of elements (10 µm wide beside 25 mm)
/// are refused before any solve, naming both points and the ways out; on one line, far
/// enough apart, or attached through shape functions, they are accepted.
#[test]
fn points_a_hair_apart_are_refused_naming_both() {
    let plate = "[plate]\nlength_x = 0.6\nlength_y = 0.4\nthickness = 0.002\nyoungs_modulus = 70e9\n\
        poisson_ratio = 0.33\ndensity = 2700.0\n[plate.mesh]\nelements = [24, 16]\n{mesh}[plate.edges]\n\
        x0 = \"simply_supported\"\nx1 = \"simply_supported\"\ny0 = \"simply_supported\"\ny1 = \"simply_supported\"\n\
        [[actuator]]\ntype = \"inertial\"\nat = [0.2, 0.15]\n";
    let case = |sensor_x: f64, mesh: &str| {
        format!("{}{SINE}[[sensor]]\nname = \"s\"\nat = [{sensor_x}, 0.3]\n", plate.replace("{mesh}", mesh))
    };
    let msg = case_error(&case(0.20001, ""));
    for needle in ["sensor[0].at", "actuator[0] stack foot", "1.000e-5 m", "through_points = false", "2.5e-5 m apart"] {
        assert!(msg.contains(needle), "`{needle}` in: {msg}");
    }
    for (x, mesh) in [(0.2, ""), (0.2001, ""), (0.20001, "through_points = false\n")] {
        let lc = LoadedCase::from_str(&case(x, mesh), "ok.toml", PathBuf::from(".")).unwrap();
        assert!(beamflow::analysis::plan::calibrated_model(&lc).is_ok(), "sensor at x = {x} with {mesh:?}");
    }
}

/// A point written the beam's way on a plate, a position that is not a number, and a
/// beam's `x_e` with a plate's `direction` are each told the plate's way.
#[test]
fn beam_ways_on_a_plate_are_told_the_plates() {
    let plate = "[plate]\nlength_x = 0.6\nlength_y = 0.4\nthickness = 0.002\nyoungs_modulus = 70e9\n\
        poisson_ratio = 0.33\ndensity = 2700.0\n[plate.edges]\nx0 = \"clamped\"\nx1 = \"clamped\"\n\
        y0 = \"clamped\"\ny1 = \"clamped\"\n";
    let frame = |foot: &str| format!("{plate}[[actuator]]\ntype = \"frame\"\n{foot}\n{SINE}");
    expect(
        &format!("{}[[sensor]]\nname = \"s\"\nx = 0.45\n", frame("at = [0.2, 0.2]")),
        &["sensor[0].at", "a plate takes its points as `at = [x, y]` (m), not `x`"],
    );
    expect(&frame("at = [nan, 0.15]"), &["actuator[0].at", "NaN is not a finite number", "[x, y] (m)"]);
    expect(
        &frame("x_e = 0.2\ndirection = 30.0"),
        &["actuator[0]", "needs `at` (plate)", "a beam's frame stands along it"],
    );
}
