//! Conditionally stable time integration: the linear-acceleration scheme's step limit is
//! the integrator's real limit, and a transient whose step exceeds it on the model's highest
//! mode is refused before any step, with the admissible step in the message.

mod common;

use beamflow::analysis::case_run::AnalysisResult;
use beamflow::app::runner::run_case;
use beamflow::linalg::Csr;
use beamflow::solve::newmark::{Newmark, Scheme};

/// Largest |u| over `steps` free-vibration steps of an undamped oscillator (ω = 100 rad/s,
/// u₀ = 1) under linear acceleration at `dt`.
fn free_vibration_peak(dt: f64, steps: usize) -> f64 {
    let (m, c, k) = (Csr::from_triplets(1, &[(0, 0, 1.0)]), Csr::zeros(1), Csr::from_triplets(1, &[(0, 0, 1e4)]));
    let mut nm = Newmark::new(&m, &c, &k, &[0], Scheme::linear_acceleration(), dt).unwrap();
    nm.initialize(&[1.0], &[0.0], &[0.0], &mut []).unwrap();
    let mut peak = 0.0f64;
    for _ in 0..steps {
        nm.step(&[0.0]);
        peak = peak.max(nm.u[0].abs());
    }
    peak
}

#[test]
fn the_limit_is_where_the_integrator_turns_unstable() {
    let limit = Scheme::linear_acceleration().critical_step(100.0).unwrap();
    // 2√3/ω, the textbook bound for γ = ½, β = 1/6.
    assert!((limit - 2.0 * 3f64.sqrt() / 100.0).abs() < 1e-15);
    assert!(Scheme::average_acceleration().critical_step(100.0).is_none());
    let below = free_vibration_peak(0.99 * limit, 5000);
    let above = free_vibration_peak(1.01 * limit, 5000);
    assert!(below < 1.5, "below the limit the oscillation stays bounded: peak {below}");
    assert!(above > 1e6, "above the limit it grows without bound: peak {above}");
}

fn linear_acceleration_case(elements: usize, steps: Option<usize>) -> String {
    let dt = steps.map(|n| format!("steps_per_period = {n}\n")).unwrap_or_default();
    format!(
        "[beam.mesh]\nelements = {elements}\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n\
         [[actuator]]\ntype = \"inertial\"\nname = \"inertial\"\nx_e = 0.15\n\
         [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n\
         [[analysis]]\ntype = \"transient\"\nscheme = \"linear_acceleration\"\nperiods = 2\n{dt}"
    )
}

#[test]
fn a_step_beyond_the_limit_is_refused_with_the_admissible_step() {
    let lc = common::case(&linear_acceleration_case(200, None));
    let e = run_case(&lc).unwrap_err().to_string();
    assert!(e.contains("analysis[0].dt") && e.contains("stability limit"), "{e}");
    assert!(e.contains("average_acceleration"), "{e}");
}

#[test]
fn the_admissible_step_runs_and_agrees_with_average_acceleration() {
    // A coarse mesh keeps the limit at about 1,500 steps per period.
    let e = match run_case(&common::case(&linear_acceleration_case(20, None))) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("the default step should exceed the limit on 20 elements"),
    };
    let advised: usize =
        e.split("give `steps_per_period` = ").nth(1).and_then(|s| s.split(' ').next()).unwrap().parse().unwrap();
    let run = |text: String| {
        let r = run_case(&common::case(&text)).unwrap();
        match &r.results[0] {
            AnalysisResult::Transient(t) => t.net_power[0],
            _ => unreachable!(),
        }
    };
    let linear = run(linear_acceleration_case(20, Some(advised)));
    let average =
        run(linear_acceleration_case(20, Some(advised)).replace("linear_acceleration", "average_acceleration"));
    assert!(linear.is_finite());
    // Both schemes are second order; at ≈ 1,500 steps per period they agree closely.
    assert!(common::rel(linear, average) < 1e-3, "linear {linear:e}, average {average:e}");
}
