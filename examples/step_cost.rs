//! Cost of one integrator step, ns per DOF-step: the best of 15 blocks of steps (≈ 4·10⁶
//! DOF-steps each) on the default beam with `elements` elements and fixed Rayleigh damping,
//! optionally with the frame actuator's coupling and the dissipation tracked.
//!
//! `cargo run --release --example step_cost -- <elements> [dissipation 0|1] [frame 0|1] [runs 1|0] [avx512 1|0] [proportional 1|0]`
//!
//! (`runs 0` switches the periodic runs off, so a bare beam and the frame system can be
//! compared without the bare beam's longer periodic stretch; `avx512 0` keeps a processor
//! with AVX-512 on the AVX2 kernels, to compare the two on the same machine; `proportional 0`
//! keeps the three-product right-hand side instead of the Rayleigh form.)
//!
//! It prints `best <ns>` so that `scripts/paired.sh` can alternate two builds of it and
//! report the median ratio: on a shared VM whose speed drifts by tens of per cent over
//! minutes, that is how a change of a few per cent was measured (docs/performance.md).

use beamflow::analysis::plan::calibrated_model;
use beamflow::assembly::System;
use beamflow::case::LoadedCase;
use beamflow::solve::band_newmark::{BandNewmark, StepOptions};
use beamflow::solve::newmark::Scheme;
use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let elements: usize = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(200);
    let dissipation = args.get(2).is_some_and(|s| s == "1");
    let frame = args.get(3).is_some_and(|s| s == "1");
    let runs = args.get(4).is_none_or(|s| s != "0");
    let wide = args.get(5).is_none_or(|s| s != "0");
    let proportional = args.get(6).is_none_or(|s| s != "0");
    let mut text =
        format!("[beam.mesh]\nelements = {elements}\n[damping]\nkind = \"rayleigh\"\na0 = 5.29\na1 = 9.96e-6\n");
    if frame {
        text +=
            "[[actuator]]\ntype = \"frame\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";
    }
    let lc = LoadedCase::from_str(&text, "step_cost.toml", PathBuf::from(env!("CARGO_MANIFEST_DIR")))?;
    let sys = System::assemble(&calibrated_model(&lc)?)?;
    let n = sys.n();
    let options = StepOptions {
        rayleigh: proportional.then_some((5.29, 9.96e-6)),
        track_dissipation: dissipation,
        periodic_runs: runs,
        avx512: wide,
        ..StepOptions::default()
    };
    let mut nm =
        BandNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, Scheme::average_acceleration(), 1e-4, options)?;
    assert_eq!(nm.uses_proportional_damping(), proportional);
    let steps = (4_000_000 / n).max(20);
    let load = n / 3;
    let mut best = f64::INFINITY;
    for _ in 0..15 {
        let t0 = Instant::now();
        for k in 1..=steps {
            nm.step(&[(load, (k as f64 * 0.0377).sin())]);
        }
        best = best.min(t0.elapsed().as_secs_f64() * 1e9 / (steps * n) as f64);
    }
    std::hint::black_box((nm.u()[load], nm.dissipated()));
    let avx512 = nm.uses_avx512();
    println!("{n} DOFs, dissipation {dissipation}, frame {frame}, runs {runs}, avx512 {avx512}, proportional {proportional}: best {best:.3} ns per DOF-step; periodic rows {}", nm.periodic_rows());
    Ok(())
}
