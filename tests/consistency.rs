//! One convention for what a run writes: every CSV header `name [unit]`, every power and
//! energy of the JSON summary keyed by name, and numbers with SI prefixes in the console.

mod common;

use std::path::Path;

fn beamflow(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_beamflow")).args(args).output().unwrap()
}

/// `beamflow run --csv` of a shipped case into `out`: its console text.
fn run_csv(case: &str, out: &Path) -> String {
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases").join(case);
    let o = beamflow(&["run", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--csv", "--no-plots"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn every_csv_a_run_writes_names_its_columns_with_units_in_brackets() {
    let dir = tempfile::tempdir().unwrap();
    run_csv("beam-frame-12V-60Hz.toml", dir.path());
    let mut n = 0;
    for e in std::fs::read_dir(dir.path()).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "csv") {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            common::csv_header_convention(&name, &std::fs::read_to_string(&p).unwrap()).unwrap();
            n += 1;
        }
    }
    assert!(n >= 8, "only {n} CSV files");
    // The check finds the other conventions.
    assert!(common::csv_header_convention("x.csv", "time (s),v [V]\n0,1\n").is_err());
    assert!(common::csv_header_convention("x.csv", "time,v [V]\n0.5,1\n").is_err());
    assert!(common::csv_header_convention("x.csv", "mode,v [V]\n1,1\n").is_ok());
}

#[test]
fn the_summary_keys_every_power_by_name() {
    let dir = tempfile::tempdir().unwrap();
    run_csv("two-frames.toml", dir.path());
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("two-frames.json")).unwrap()).unwrap();
    let actuators: Vec<&str> = v["actuators"].as_array().unwrap().iter().map(|a| a.as_str().unwrap()).collect();
    assert_eq!(actuators.len(), 2);
    let mut powers = 0;
    for a in v["analyses"].as_array().unwrap() {
        if a["net_power_w"].is_null() {
            continue;
        }
        let net = a["net_power_w"].as_object().expect("net_power_w is an object");
        let mut keys: Vec<&str> = net.keys().map(String::as_str).collect();
        keys.sort_unstable();
        let mut want = actuators.clone();
        want.sort_unstable();
        assert_eq!(keys, want);
        let points = a["mean_power_w"].as_object().expect("mean_power_w is an object");
        // Each actuator's net power is the sum of its points' powers.
        for name in &actuators {
            let sum: f64 = points
                .iter()
                .filter(|(k, _)| k.starts_with(&format!("{name}_")))
                .map(|(_, p)| p.as_f64().unwrap())
                .sum();
            let p = net[*name].as_f64().unwrap();
            assert!((sum - p).abs() <= 1e-9 * p.abs(), "{name}: {sum:e} against {p:e}");
        }
        powers += 1;
    }
    assert!(powers > 0);
}

#[test]
fn the_console_shows_powers_and_steps_with_si_prefixes() {
    let dir = tempfile::tempdir().unwrap();
    let console = run_csv("beam-frame-12V-60Hz.toml", dir.path());
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("beam-frame-12V-60Hz.json")).unwrap()).unwrap();
    let net = v["analyses"][0]["net_power_w"]["frame"].as_f64().unwrap();
    // The number with four significant digits and its prefixed unit, as in the report.
    let shown = beamflow::report::si(net, "W", 4);
    assert!(shown.ends_with(" µW") && !shown.contains('e'), "{shown}");
    let line = console.lines().find(|l| l.contains("net power of frame")).expect(&console);
    assert!(line.trim_end().ends_with(&shown), "{line}");
    let powers = console.lines().filter(|l| l.starts_with("  mean power") || l.starts_with("  net power"));
    for l in powers {
        let value = l.rsplit("  ").next().unwrap();
        assert!(!value.contains("e-") && !value.contains("e0"), "not SI-prefixed: {l}");
    }
    assert!(console.contains("Δt = 83.333 µs"), "{console}");
}

/// `[output.figures]`: which figures, in which formats, how wide, at which font scale and
/// whether log axes are used, as the case says; the command line's `--formats` wins.
#[test]
fn a_case_sets_its_figures() {
    let dir = tempfile::tempdir().unwrap();
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/beam-frame-12V-60Hz.toml");
    let text = std::fs::read_to_string(shipped).unwrap()
        + "\n[output.figures]\nwidth_in = 6.0\nfont_scale = 2.0\nformats = [\"svg\", \"pdf\"]\nlog_axes = false\n\
           only = [\"power_spectrum\"]\n";
    let case = dir.path().join("c.toml");
    std::fs::write(&case, text).unwrap();
    let run = |out: &str, extra: &[&str]| {
        let out = dir.path().join(out);
        let mut args = vec!["run", case.to_str().unwrap(), "--out", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        let o = beamflow(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let mut names: Vec<String> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".svg") || n.ends_with(".png") || n.ends_with(".pdf"))
            .collect();
        names.sort();
        (out, names)
    };
    let (out, names) = run("a", &[]);
    assert_eq!(
        names,
        [
            "c_steady_state_frame_power_spectrum.pdf",
            "c_steady_state_frame_power_spectrum.svg",
            "c_transient_frame_power_spectrum.pdf",
            "c_transient_frame_power_spectrum.svg"
        ]
    );
    let svg = std::fs::read_to_string(out.join("c_steady_state_frame_power_spectrum.svg")).unwrap();
    // 6 in at 100 px to the inch, drawn on half the canvas: text twice its size.
    assert!(svg.starts_with("<svg width=\"600\" height=\"360\" viewBox=\"0 0 300 180\""), "{:.100}", svg);
    // Linear axes: the unit's prefix on the axis, plain numbers on the ticks (a log or
    // symmetric-log axis puts units on its ticks, `100 nW`).
    assert!(svg.contains("aria-label=\"power into the beam (µW)\""));
    assert!(!svg.contains(" nW\"") && !svg.contains(" µW\""));
    // The report: each figure with its anchor and links to its files, every file linked.
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    let id = "fig-c_steady_state_frame_power_spectrum";
    assert!(html.contains(&format!("<figure id=\"{id}\">")) && html.contains(&format!("href=\"#{id}\"")));
    for name in names.iter().map(String::as_str).chain(["c.json", "c.h5"]) {
        assert!(html.contains(&format!("<a href=\"{name}\">")), "{name} not linked");
    }
    // The command line's formats win over the case's.
    let (_, names) = run("b", &["--formats", "png,svg"]);
    assert!(names.iter().any(|n| n.ends_with(".png")) && !names.iter().any(|n| n.ends_with(".pdf")), "{names:?}");
}

/// The results file says what was computed: the program, the case text's hash and every
/// parameter as resolved, defaults included, beside the calibrated damping.
#[test]
fn the_model_group_holds_every_resolved_parameter() {
    use beamflow::io::hdf5::ResultsReader;
    let dir = tempfile::tempdir().unwrap();
    run_csv("beam-frame-12V-60Hz.toml", dir.path());
    let r = ResultsReader::open(dir.path().join("beam-frame-12V-60Hz.h5")).unwrap();
    // The hash `sha256sum` prints of the case file.
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/beam-frame-12V-60Hz.toml");
    let sum = std::process::Command::new("sha256sum").arg(&case).output().unwrap();
    let sum = String::from_utf8(sum.stdout).unwrap();
    let hex = sum.split_whitespace().next().unwrap();
    assert_eq!(hex.len(), 64, "{sum}");
    assert_eq!(r.attr_str("model", "case_hash").unwrap(), format!("sha256:{hex}"));
    assert_eq!(r.attr_str("model", "version").unwrap(), env!("CARGO_PKG_VERSION"));
    // Written in the case: as written.
    assert_eq!(r.attr_f64("model/parameters/actuator_0", "x_e").unwrap(), 0.150);
    assert_eq!(r.attr_f64("model/parameters/actuator_0/voltage", "frequency").unwrap(), 60.0);
    // Not written: the defaults the run used, every group of the case present.
    let lc =
        beamflow::case::LoadedCase::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/beam-frame-12V-60Hz.toml"))
            .unwrap();
    assert_eq!(r.attr_f64("model/parameters/beam", "length").unwrap(), lc.case.beam.length);
    let groups = r.list_groups("model/parameters").unwrap();
    for g in ["beam", "damping", "actuator_0", "analysis_0", "analysis_1", "output"] {
        assert!(groups.iter().any(|x| x == g), "{g} missing in {groups:?}");
    }
    let stack = r.list_groups("model/parameters/actuator_0").unwrap();
    assert!(stack.iter().any(|x| x == "stack"), "{stack:?}");
    // The damping the solves applied: calibrated, positive.
    assert!(r.attr_f64("model", "rayleigh_a0").unwrap() > 0.0 && r.attr_f64("model", "rayleigh_a1").unwrap() > 0.0);
    // The resolved case reads back as the same case.
    let back: toml::Value = toml::from_str(&r.read_str("model/resolved_toml").unwrap()).unwrap();
    assert_eq!(back, toml::Value::try_from(&lc.case).unwrap());
}
