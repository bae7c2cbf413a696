//! The physics does not depend on the order the drives are listed in: the time step, the
//! harmonic content and every power come out the same with two actuators swapped.

use beamflow::analysis::case_run::AnalysisResult;
use beamflow::app::runner::run_case;
use beamflow::case::LoadedCase;
use std::collections::HashMap;
use std::path::PathBuf;

const SLOW: &str = "[[actuator]]\nname = \"slow\"\ntype = \"frame\"\nx_e = 0.2\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 30.0\n";
const FAST: &str = "[[actuator]]\nname = \"fast\"\ntype = \"inertial\"\nx_e = 0.5\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 600.0\n";
const ANALYSES: &str = "[[analysis]]\ntype = \"steady_state\"\n[[analysis]]\ntype = \"transient\"\nperiods = 4\n\
                        [output]\nhdf5 = false\nplots = false\n";

/// Net power per actuator name, per analysis, and the transient's Δt.
fn powers(first: &str, second: &str) -> (Vec<HashMap<String, f64>>, f64) {
    let text = format!("{first}{second}{ANALYSES}");
    let run = run_case(&LoadedCase::from_str(&text, "order.toml", PathBuf::from(".")).unwrap()).unwrap();
    let names: Vec<String> = run.model.actuators.iter().map(|a| a.name().to_string()).collect();
    let mut dt = 0.0;
    let per = run
        .results
        .iter()
        .map(|r| {
            let net = match r {
                AnalysisResult::SteadyState(s) => &s.net_power,
                AnalysisResult::Transient(t) => {
                    dt = t.dt;
                    &t.net_power
                }
                _ => unreachable!(),
            };
            names.iter().cloned().zip(net.iter().copied()).collect()
        })
        .collect();
    (per, dt)
}

#[test]
fn swapping_two_drives_changes_nothing() {
    let (a, dt_a) = powers(SLOW, FAST);
    let (b, dt_b) = powers(FAST, SLOW);
    // The step resolves the fast drive whichever comes first: 20 steps per 600 Hz period
    // at least, so ≥ 400 steps per 1/30 s.
    assert_eq!(dt_a, dt_b);
    assert!(1.0 / 30.0 / dt_a >= 400.0 - 1e-9, "{} steps per period", 1.0 / 30.0 / dt_a);
    for (pa, pb) in a.iter().zip(&b) {
        for name in ["slow", "fast"] {
            let (x, y) = (pa[name], pb[name]);
            assert!((x - y).abs() <= 1e-9 * x.abs().max(y.abs()), "{name}: {x:e} vs {y:e}");
            assert!(x != 0.0, "{name} puts power in");
        }
    }
}
