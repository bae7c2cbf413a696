//! The ratio "coupled run against the bare step, per DOF", measured in pairs.
//!
//! On a shared VM the same binary runs ≈ 1.6× slower for minutes at a time, so two criterion
//! runs taken minutes apart cannot give a ratio to a few per cent. This alternates the two
//! workloads (each ≈ 0.1 s) and reports the median of the per-pair ratios, which both halves
//! of a pair see at the same machine state:
//!
//! * bare: the OpenSees anchor of `benches/scaling.rs` — the bare 200-element beam, fused
//!   integrator built and factorised, 20,000 steps at Δt = 1e-4 s, recording w under the load;
//! * coupled: `transient::run` as in `benches/core.rs` — the same beam with the frame
//!   actuator (Bouc–Wen hysteresis), 20,000 steps, every link, body and drive series
//!   recorded, both energy balances kept.
//!
//! Two more workloads between them split the ratio into its causes (each as a ratio to
//! the bare anchor of the same round):
//!
//! * bare + dissipation: the bare anchor with the integrator's dissipation tracking on,
//!   which every transient run keeps for its energy balance;
//! * frame step: the coupled system's 20,000 integrator steps alone (dissipation tracked,
//!   the stack's force as a sine load), without the run's hysteresis and bookkeeping.
//!
//! `cargo run --release --example coupled_vs_bare [-- <pairs> [<elements>]]` (default 30
//! pairs, 200 elements: the paper's mesh). Both beams take the given number of elements; the
//! frame beam's mesh is split at the stack foot and legs as the case builder does it.

use beamflow::analysis::plan::calibrated_model;
use beamflow::analysis::transient::{self, TransientSettings};
use beamflow::assembly::System;
use beamflow::case::LoadedCase;
use beamflow::solve::band_newmark::{BandNewmark, StepOptions};
use beamflow::solve::newmark::Scheme;
use std::path::PathBuf;
use std::time::Instant;

const FRAME: &str =
    "[[actuator]]\ntype = \"frame\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";
const BARE: &str = "[damping]\nkind = \"rayleigh\"\na0 = 5.29\na1 = 9.96e-6\n[[sensor]]\nname = \"load\"\nx = 0.15\n";
const STEPS: usize = 20_000;

/// (min, lower quartile, median, upper quartile).
fn quartiles(mut v: Vec<f64>) -> [f64; 4] {
    v.sort_by(f64::total_cmp);
    [v[0], v[v.len() / 4], v[v.len() / 2], v[3 * v.len() / 4]]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |k: usize, default: usize| -> Result<usize, Box<dyn std::error::Error>> {
        Ok(std::env::args().nth(k).map(|s| s.parse()).transpose()?.unwrap_or(default).max(1))
    };
    let (pairs, elements) = (arg(1, 30)?, arg(2, 200)?);
    let mesh = format!("[beam.mesh]\nelements = {elements}\n");
    let cases = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases");
    let bare_model = calibrated_model(&LoadedCase::from_str(&(mesh.clone() + BARE), "bare.toml", cases.clone())?)?;
    let bare = System::assemble(&bare_model)?;
    let load = bare.w_at(&bare_model, &beamflow::structure::Location::Beam { x: 0.15 }, "sensor")?[0].0;
    let model = calibrated_model(&LoadedCase::from_str(&(mesh + FRAME), "frame.toml", cases)?)?;
    let coupled = System::assemble(&model)?;
    let settings = TransientSettings {
        dt: Some(1e-4 / 1.2),
        periods: Some(100),
        steady_state: false,
        record_periods: 1,
        ..Default::default()
    };
    // The integrator steps alone, ns per DOF-step.
    // `rayleigh`: the system's Rayleigh coefficients, for the proportional form as
    // transient::run uses it.
    let steps_only = |sys: &System,
                      rayleigh: (f64, f64),
                      load: &[(usize, f64)],
                      diss: bool|
     -> Result<f64, Box<dyn std::error::Error>> {
        let t0 = Instant::now();
        let options = StepOptions { rayleigh: Some(rayleigh), track_dissipation: diss, ..StepOptions::default() };
        let mut nm =
            BandNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, Scheme::average_acceleration(), 1e-4, options)?;
        assert!(nm.uses_proportional_damping());
        let probe = load[0].0;
        let mut w = Vec::with_capacity(STEPS);
        let mut f = load.to_vec();
        for k in 1..=STEPS {
            let s = (2.0 * std::f64::consts::PI * 60.0 * k as f64 * 1e-4).sin();
            f.iter_mut().zip(load).for_each(|(x, &(_, c))| x.1 = c * s);
            nm.step(&f);
            w.push(nm.u()[probe]);
        }
        std::hint::black_box((w, nm.dissipated()));
        Ok(t0.elapsed().as_secs_f64() * 1e9 / (STEPS * sys.n()) as f64)
    };
    let bare_rayleigh = (bare_model.rayleigh().a0, bare_model.rayleigh().a1);
    let coupled_rayleigh = (model.rayleigh().a0, model.rayleigh().a1);
    let stack_drive: Vec<(usize, f64)> = coupled.drives[0].iter().map(|&(d, c)| (d, 46.8 * c)).collect();
    let (mut tb, mut tc, mut ratio) = (Vec::new(), Vec::new(), Vec::new());
    let (mut r_diss, mut r_frame) = (Vec::new(), Vec::new());
    for _ in 0..pairs {
        let b = steps_only(&bare, bare_rayleigh, &[(load, 1.0)], false)?;
        r_diss.push(steps_only(&bare, bare_rayleigh, &[(load, 1.0)], true)? / b);
        r_frame.push(steps_only(&coupled, coupled_rayleigh, &stack_drive, true)? / b);
        let t0 = Instant::now();
        let result = transient::run(&model, &coupled, &settings)?;
        assert_eq!(result.steps_run, STEPS);
        std::hint::black_box(result);
        let c = t0.elapsed().as_secs_f64() * 1e9 / (STEPS * coupled.n()) as f64;
        tb.push(b);
        tc.push(c);
        ratio.push(c / b);
    }
    println!("{pairs} pairs; ns per DOF-step as (min, lower quartile, median, upper quartile)");
    println!("bare anchor ({} DOFs):   {:.2?}", bare.n(), quartiles(tb));
    println!("coupled run ({} DOFs):   {:.2?}", coupled.n(), quartiles(tc));
    println!("coupled / bare, per pair: {:.3?}", quartiles(ratio));
    let factor_rows = |sys: &System| -> Result<usize, Box<dyn std::error::Error>> {
        let scheme = Scheme::average_acceleration();
        let nm = BandNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, scheme, 1e-4, StepOptions::default())?;
        Ok(nm.periodic_factor_rows())
    };
    println!("periodic factor rows:     bare {}, coupled {}", factor_rows(&bare)?, factor_rows(&coupled)?);
    println!("its causes, each against the bare anchor of the same round:");
    println!("  bare + dissipation:     {:.3?}", quartiles(r_diss));
    println!("  frame step + dissipation: {:.3?}", quartiles(r_frame));
    Ok(())
}
