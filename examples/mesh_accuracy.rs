//! Point mobility of the bare paper beam against the exact continuous beam as the mesh is
//! refined: discretisation error falls as elements⁻⁴, and the refined solves keep round-off
//! below 1e-6 where the assembled factor alone lost ε·elements⁴ (`analysis::roundoff`);
//! then the time of the frame case's steady state and transient on fine meshes
//! (docs/performance.md).
//! Usage: cargo run --release --example mesh_accuracy [-- steady]
//! (`steady`: only the frame case's steady-state times, each mesh three times).
use beamflow::analysis::case_run::AnalysisResult;
use beamflow::analysis::harmonic::{self, PointForce};
use beamflow::analysis::plan::calibrated_model;
use beamflow::assembly::System;
use beamflow::beam::analytic::clamped_point_receptance;
use beamflow::case::LoadedCase;
use num_complex::Complex64;
use std::path::PathBuf;

fn main() {
    if std::env::args().nth(1).as_deref() == Some("steady") {
        for n in [200, 2000, 20000] {
            let times: Vec<String> = (0..3).map(|_| format!("{:.2}", frame_run(n, "transient").0)).collect();
            println!("frame steady state, {n:>6} elements: {} s", times.join(", "));
        }
        return;
    }
    let (ei, rho_a, l, x) = (210e9 * 0.05 * 0.005f64.powi(3) / 12.0, 7850.0 * 0.05 * 0.005, 0.73, 0.15);
    let freqs = [5.0, 60.0, 445.0];
    println!("elements  {}", freqs.map(|f| format!("{f:>10} Hz")).join(""));
    for n in [100, 200, 500, 1000, 2000, 5000, 10000, 20000] {
        let text = format!(
            "[beam.mesh]\nelements = {n}\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n[[analysis]]\ntype = \"harmonic\"\n\
             [analysis.frequencies]\nvalues = {freqs:?}\n[[analysis.force]]\nx = {x}\n"
        );
        let lc = LoadedCase::from_str(&text, "m.toml", PathBuf::from(".")).unwrap();
        let model = calibrated_model(&lc).unwrap();
        let sys = System::assemble(&model).unwrap();
        let force = [PointForce { at: beamflow::structure::Location::Beam { x }, amplitude: 1.0, phase: 0.0 }];
        let h = harmonic::run(&model, &sys, &freqs, &force, None).unwrap();
        let errs: Vec<String> = freqs
            .iter()
            .enumerate()
            .map(|(i, &f)| {
                let w = 2.0 * std::f64::consts::PI * f;
                // Rayleigh damping makes EI* = EI(1 + iωa₁) and ρA* = ρA(1 − ia₀/ω); dividing the
                // equation by ρA*/ρA leaves a real ρA and scales the unit force.
                let mass = Complex64::new(1.0, -5.0 / w);
                let ei_c = Complex64::new(ei, ei * w * 1e-5) / mass;
                let exact = Complex64::new(0.0, w) * clamped_point_receptance(l, ei_c, rho_a, w, x, x) / mass;
                format!("{:>13.2e}", (h.mobility[i][0][0] - exact).norm() / exact.norm())
            })
            .collect();
        println!("{n:>8}  {}   (stated round-off {:.1e})", errs.join(""), h.mesh_roundoff);
    }
    for n in [200, 2000, 20000] {
        let (secs, result) = frame_run(n, "transient");
        let AnalysisResult::SteadyState(s) = &result else { unreachable!() };
        println!(
            "frame steady state, {n:>6} elements: {secs:.2} s ({} harmonics), stated round-off {:.1e}",
            s.harmonics, s.mesh_roundoff
        );
    }
    // The frame case's transient (default step and tolerance) on fine meshes: the step takes
    // the element rows' stiffness and refines its increments beyond 286 elements.
    for n in [200, 2000, 20000] {
        let (secs, result) = frame_run(n, "steady_state");
        let AnalysisResult::Transient(t) = &result else { unreachable!() };
        println!(
            "frame transient, {n:>6} elements: {secs:.2} s ({} periods), settling {:.1e}, stated round-off {:.1e}",
            t.periods_run, t.settling_estimate, t.mesh_roundoff
        );
    }
}

/// The frame case on `n` elements without its analysis of type `without`, run whole: its
/// wall time (s) and the analysis left.
fn frame_run(n: usize, without: &str) -> (f64, AnalysisResult) {
    let frame =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/cases/beam-frame-12V-60Hz.toml")).unwrap();
    let text = frame
        .replace("[beam]", &format!("[beam]\n[beam.mesh]\nelements = {n}"))
        .replace(&format!("[[analysis]]\ntype = \"{without}\"\n"), "");
    let lc = LoadedCase::from_str(&text, "frame.toml", PathBuf::from(".")).unwrap();
    let start = std::time::Instant::now();
    let mut run = beamflow::app::runner::run_case(&lc).unwrap();
    (start.elapsed().as_secs_f64(), run.results.swap_remove(0))
}
