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
