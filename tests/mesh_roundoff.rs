//! Fine meshes: the round-off of the assembled stiffness grows as elements⁴. Each result
//! states its estimate, meshes where 1e-6 cannot be held are refused, and the estimate is
//! checked here against the real error: the harmonic solve (called directly, past the
//! runner's limit) against the exact continuous beam.

use beamflow::analysis::harmonic::{self, PointForce};
use beamflow::analysis::plan::calibrated_model;
use beamflow::analysis::roundoff::{mesh_roundoff, MESH_ELEMENTS_LIMIT};
use beamflow::app::runner::run_case;
use beamflow::assembly::System;
use beamflow::beam::analytic::clamped_point_receptance;
use beamflow::case::LoadedCase;
use num_complex::Complex64;
use std::f64::consts::PI;
use std::path::PathBuf;

const EI: f64 = 210e9 * 0.05 * 0.005 * 0.005 * 0.005 / 12.0;
const RHO_A: f64 = 7850.0 * 0.05 * 0.005;

fn case(elements: usize) -> LoadedCase {
    let text = format!(
        "[beam.mesh]\nelements = {elements}\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n\
         [[analysis]]\ntype = \"harmonic\"\n[analysis.frequencies]\nvalues = [60.0, 445.0]\n[[analysis.force]]\nx = 0.15\n"
    );
    LoadedCase::from_str(&text, "mesh.toml", PathBuf::from(".")).unwrap()
}

/// The largest relative error of the point mobility at 60 and 445 Hz, and the estimate.
fn error_and_estimate(elements: usize) -> (f64, f64) {
    let model = calibrated_model(&case(elements)).unwrap();
    let sys = System::assemble(&model).unwrap();
    let freqs = [60.0, 445.0];
    let h = harmonic::run(&model, &sys, &freqs, &[PointForce { x: 0.15, amplitude: 1.0, phase: 0.0 }], None).unwrap();
    let err = freqs.iter().enumerate().fold(0.0f64, |m, (i, &f)| {
        let w = 2.0 * PI * f;
        let mass = Complex64::new(1.0, -5.0 / w);
        let ei = Complex64::new(EI, EI * w * 1e-5) / mass;
        let exact = Complex64::new(0.0, w) * clamped_point_receptance(0.73, ei, RHO_A, w, 0.15, 0.15) / mass;
        m.max((h.mobility[i][0][0] - exact).norm() / exact.norm())
    });
    assert_eq!(h.mesh_roundoff, mesh_roundoff(&model));
    (err, h.mesh_roundoff)
}

#[test]
fn the_roundoff_estimate_tracks_the_real_error() {
    // At the limit the results hold 1e-6 and say so (on the default 200 elements the
    // discretisation error at 445 Hz, mode 4, is 1.2e-6: that is not round-off).
    let (err, est) = error_and_estimate(MESH_ELEMENTS_LIMIT);
    assert!(err < 1e-6 && est < 1e-6, "{MESH_ELEMENTS_LIMIT} elements: error {err:e}, estimate {est:e}");
    // Past it the estimate bounds the error, and is not idly pessimistic.
    for n in [650, 1000, 1500, 2000, 3000] {
        let (err, est) = error_and_estimate(n);
        eprintln!("{n} elements: error {err:.2e}, estimate {est:.2e}");
        assert!(err <= est && err > est / 30.0, "{n} elements: error {err:e}, estimate {est:e}");
    }
}

#[test]
fn a_mesh_past_the_limit_is_refused_with_its_estimate() {
    let e = run_case(&case(1000)).unwrap_err().to_string();
    assert!(e.contains("beam.mesh.elements") && e.contains("2e-5") && e.contains("500"), "{e}");
    let run = run_case(&case(400)).unwrap();
    let json = beamflow::io::summary::summary(&case(400), &run);
    let est = json["analyses"][0]["mesh_roundoff"].as_f64().unwrap();
    assert!((est - 1.5e-5 * 0.4f64.powi(4)).abs() < 1e-20, "{est:e}");
}
