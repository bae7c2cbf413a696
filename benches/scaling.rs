//! Cost of one Newmark step against problem size, and the OpenSees anchor.
//!
//! * `scaling/newmark_step/<DOFs>`: bare clamped–clamped default beams of 50 … 500,000
//!   elements (≈ 10² … 10⁶ DOFs), fused integrator, one core, a point force at 0.15 m.
//!   Criterion's throughput is DOF-steps per second. `cargo run --release --example
//!   scaling_report` fits the exponent and draws `docs/img/scaling.png` from the results.
//! * `anchor/bare_paper_beam_20000_steps`: the OpenSeesPy comparison — the bare
//!   200-element beam, Δt = 1e-4 s, 20,000 steps, factorised once, recording the
//!   displacement under the load every step.
//!
//! * `modes/20_modes_99998_dofs`: the 20 lowest modes of a 50,000-element beam.
//!
//! `cargo bench --bench scaling`; numbers in docs/performance.md.

use beamflow::analysis::plan::calibrated_model;
use beamflow::assembly::System;
use beamflow::case::LoadedCase;
use beamflow::solve::band_newmark::{BandNewmark, StepOptions};
use beamflow::solve::newmark::Scheme;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::path::PathBuf;
use std::time::Duration;

/// The Rayleigh coefficients of `bare_beam` (1/s, s).
const A0: f64 = 5.29;
const A1: f64 = 9.96e-6;

/// The default beam with `elements` elements and fixed Rayleigh coefficients (no modal
/// analysis at set-up), as an assembled system, and the w DOF under x = 0.15 m.
pub fn bare_beam(elements: usize) -> (System, usize) {
    let text = format!(
        "[beam.mesh]\nelements = {elements}\n[damping]\nkind = \"rayleigh\"\na0 = {A0}\na1 = {A1}\n\
         [[sensor]]\nname = \"load\"\nx = 0.15\n"
    );
    let lc = LoadedCase::from_str(&text, "scaling.toml", PathBuf::from(env!("CARGO_MANIFEST_DIR"))).unwrap();
    let model = calibrated_model(&lc).unwrap();
    let sys = System::assemble(&model).unwrap();
    let d = sys.w_at(&model, &beamflow::structure::Location::Beam { x: 0.15 }, "sensor").unwrap()[0].0;
    (sys, d)
}

fn scaling(c: &mut Criterion) {
    let mut g = c.benchmark_group("scaling");
    g.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
    for elements in [50usize, 500, 5_000, 50_000, 500_000] {
        let (sys, d) = bare_beam(elements);
        let n = sys.n();
        let options = StepOptions { rayleigh: Some((A0, A1)), ..StepOptions::default() };
        let mut nm =
            BandNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, Scheme::average_acceleration(), 1e-4, options)
                .unwrap();
        assert!(nm.uses_proportional_damping());
        eprintln!(
            "{n} DOFs: band half-width {}, integrator storage {:.1} bytes per DOF, FMA build: {}",
            nm.band_width(),
            nm.memory_bytes() as f64 / n as f64,
            nm.uses_fma()
        );
        let mut k = 0usize;
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::new("newmark_step", n), &n, |b, _| {
            b.iter(|| {
                k += 1;
                nm.step(&[(d, (k as f64 * 0.0377).sin())])
            })
        });
    }
    g.finish();
}

fn anchor(c: &mut Criterion) {
    let (sys, d) = bare_beam(200);
    let mut g = c.benchmark_group("anchor");
    g.sample_size(10);
    g.bench_function("bare_paper_beam_20000_steps", |b| {
        b.iter(|| {
            let options = StepOptions { rayleigh: Some((A0, A1)), ..StepOptions::default() };
            let mut nm =
                BandNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, Scheme::average_acceleration(), 1e-4, options)
                    .unwrap();
            assert!(nm.uses_proportional_damping());
            let mut w = Vec::with_capacity(20_000);
            for k in 1..=20_000 {
                let t = k as f64 * 1e-4;
                nm.step(&[(d, (2.0 * std::f64::consts::PI * 60.0 * t).sin())]);
                w.push(nm.u()[d]);
            }
            w
        })
    });
    g.finish();
}

/// The 20 lowest modes of a 99,998-DOF clamped–clamped beam (50,000 elements), shift-invert
/// Lanczos on the profile factorisation.
fn modes_large(c: &mut Criterion) {
    let text = "[beam.mesh]\nelements = 50000\n";
    let lc = LoadedCase::from_str(text, "modes.toml", PathBuf::from(env!("CARGO_MANIFEST_DIR"))).unwrap();
    let beam = beamflow::case::build::build_structure(&lc).unwrap();
    let mut g = c.benchmark_group("modes");
    g.sample_size(10);
    g.bench_function("20_modes_99998_dofs", |b| b.iter(|| beamflow::analysis::modes::run(&beam, 20).unwrap()));
    g.finish();
}

criterion_group!(benches, scaling, anchor, modes_large);
criterion_main!(benches);
