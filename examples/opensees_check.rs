//! beamflow's response on the OpenSees anchor problem against another code's: the same
//! discrete problem (200 Euler–Bernoulli elements with consistent mass, C = a₀·M + a₁·K, a
//! unit sine force at 60 Hz on the node x = 41·L/200, Newmark average acceleration, 20,000
//! steps at Δt = 1e-4 s, from rest), so the w(t) at the load differ only by each code's
//! round-off. The other series is a file of one w per step:
//!
//! * OpenSeesPy: `python scripts/opensees_anchor.py 1 /tmp/w_opensees.txt`;
//! * an extended-precision (80-bit) Newmark of the same matrices:
//!   `python scripts/newmark_reference.py /tmp/w_reference.txt`.
//!
//! `cargo run --release --example opensees_check -- /tmp/w_opensees.txt` prints the largest
//! difference as a fraction of the peak response, and the same for beamflow's fast step
//! against its textbook step (docs/performance.md, "Against OpenSees and an
//! extended-precision reference").

use beamflow::analysis::plan::calibrated_model;
use beamflow::assembly::System;
use beamflow::case::LoadedCase;
use beamflow::solve::band_newmark::{BandNewmark, StepOptions};
use beamflow::solve::newmark::{Newmark, Scheme};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .ok_or("usage: opensees_check <w-file: one w per step, e.g. from scripts/opensees_anchor.py>")?;
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{path}: {e}"))?;
    let w_other: Vec<f64> = text
        .lines()
        .enumerate()
        .map(|(i, l)| l.trim().parse::<f64>().map_err(|e| format!("{path}, line {}: {e}", i + 1)))
        .collect::<Result<_, _>>()?;
    let x_load = 41.0 * 0.730 / 200.0;
    let case = format!(
        "[beam.mesh]\nelements = 200\n[damping]\nkind = \"rayleigh\"\na0 = 5.29\na1 = 9.96e-6\n\
         [[sensor]]\nname = \"load\"\nx = {x_load}\n"
    );
    let lc = LoadedCase::from_str(&case, "opensees_check.toml", PathBuf::from(env!("CARGO_MANIFEST_DIR")))?;
    let model = calibrated_model(&lc)?;
    let sys = System::assemble(&model)?;
    let d = sys.w_at(&model, &beamflow::structure::Location::Beam { x: x_load }, "sensor")?[0].0;
    let (dt, f_hz) = (1e-4, 60.0);
    let options = StepOptions { rayleigh: Some((model.rayleigh().a0, model.rayleigh().a1)), ..StepOptions::default() };
    let mut nm = BandNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, Scheme::average_acceleration(), dt, options)?;
    // The textbook step on CSR and profile storage, as a measure of beamflow's own round-off.
    let mut tb = Newmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, Scheme::average_acceleration(), dt)?;
    let zeros = vec![0.0; sys.n()];
    tb.initialize(&zeros, &zeros, &zeros, &mut [])?;
    let mut f = zeros.clone();
    let (mut w, mut w_tb) = (Vec::with_capacity(w_other.len()), Vec::with_capacity(w_other.len()));
    for k in 1..=w_other.len() {
        let t = k as f64 * dt;
        let fd = (2.0 * std::f64::consts::PI * f_hz * t).sin();
        nm.step(&[(d, fd)]);
        w.push(nm.u()[d]);
        f[d] = fd;
        tb.step(&f);
        w_tb.push(tb.u[d]);
    }
    let peak = w_other.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let worst = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .enumerate()
            .fold((0, 0.0f64), |m, (k, e)| if e > m.1 { (k, e) } else { m })
    };
    let (k_worst, diff) = worst(&w, &w_other);
    let (_, diff_tb) = worst(&w, &w_tb);
    println!(
        "{} steps, {} DOFs; max |w| beamflow {:.6e} m, other {:.6e} m",
        w.len(),
        sys.n(),
        w.iter().fold(0.0f64, |m, x| m.max(x.abs())),
        peak
    );
    println!("max |w_beamflow − w_other| = {diff:.3e} m = {:.3e} of the peak, at step {}", diff / peak, k_worst + 1);
    println!("beamflow's fast step against its textbook step: {:.3e} of the peak", diff_tb / peak);
    Ok(())
}
