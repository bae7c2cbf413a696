//! Benchmarks of the foundation paths: assembly, modal analysis, harmonic sweeps, Newmark
//! steps on the rigid-base models and on a 1000-DOF system, and the coupled transient.
//! Run: `cargo bench --bench core`. Numbers are recorded in docs/performance.md.

use beamflow::analysis::harmonic::{self, PointForce};
use beamflow::analysis::modes;
use beamflow::analysis::plan::calibrated_model;
use beamflow::assembly::System;
use beamflow::case::build::build_structure;
use beamflow::case::LoadedCase;
use beamflow::solve::band_newmark::{BandNewmark, StepOptions};
use beamflow::solve::newmark::{Newmark, Scheme};
use criterion::{criterion_group, criterion_main, Criterion};
use std::path::PathBuf;
use std::time::Duration;

fn case(text: &str) -> LoadedCase {
    LoadedCase::from_str(text, "bench.toml", PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases")).unwrap()
}

const FRAME: &str =
    "[[actuator]]\ntype = \"frame\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";

fn foundation(c: &mut Criterion) {
    let lc = case("[damping]\nkind = \"rayleigh\"\na0 = 3.0\na1 = 2e-6\n[[sensor]]\nname = \"drive\"\nx = 0.15\n");
    let model = calibrated_model(&lc).unwrap();
    c.bench_function("assembly: paper beam, 200 elements", |b| b.iter(|| System::assemble(&model).unwrap()));
    let beam = build_structure(&lc).unwrap();
    c.bench_function("modes: paper beam, 200 elements, 20 modes", |b| b.iter(|| modes::run(&beam, 20).unwrap()));
    let sys = System::assemble(&model).unwrap();
    let freqs: Vec<f64> = (0..1000).map(|i| 10.0 + i as f64 * 0.99).collect();
    let f = [PointForce { at: beamflow::structure::Location::Beam { x: 0.15 }, amplitude: 1.0, phase: 0.0 }];
    c.bench_function("harmonic: 1000 frequencies, 200 elements", |b| {
        b.iter(|| harmonic::run(&model, &sys, &freqs, &f, None).unwrap())
    });
}

fn newmark(c: &mut Criterion) {
    for (name, text) in [("inertial", "base = \"rigid\"\n[[actuator]]\ntype = \"inertial\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 48.0\nfrequency = 30.0\n"), ("frame", "base = \"rigid\"\n[[actuator]]\ntype = \"frame\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 48.0\nfrequency = 30.0\n")] {
        let model = calibrated_model(&case(text)).unwrap();
        let sys = System::assemble(&model).unwrap();
        let mut nm = Newmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, Scheme::average_acceleration(), 1e-5).unwrap();
        let f = vec![1.0; sys.n()];
        c.bench_function(&format!("newmark step: rigid-base {name} ({} DOFs)", sys.n()), |b| b.iter(|| nm.step(&f)));
    }
    // 1000 DOFs: a 500-element beam (998 free DOFs) plus a frame actuator.
    let model = calibrated_model(&case(&format!("[beam.mesh]\nelements = 500\n{FRAME}"))).unwrap();
    let sys = System::assemble(&model).unwrap();
    let mut nm = Newmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, Scheme::average_acceleration(), 1e-5).unwrap();
    let f = vec![1.0; sys.n()];
    c.bench_function(&format!("newmark step: beam + frame ({} DOFs)", sys.n()), |b| b.iter(|| nm.step(&f)));
    let band = |options: StepOptions| {
        BandNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, Scheme::average_acceleration(), 1e-5, options).unwrap()
    };
    let rayleigh = StepOptions { rayleigh: Some((model.rayleigh().a0, model.rayleigh().a1)), ..StepOptions::default() };
    let mut fused = band(rayleigh);
    assert!(fused.uses_proportional_damping());
    let load: Vec<(usize, f64)> = sys.drives[0].clone();
    c.bench_function(&format!("fused newmark step: beam + frame ({} DOFs)", sys.n()), |b| b.iter(|| fused.step(&load)));
    let mut fused = band(StepOptions { track_dissipation: true, ..rayleigh });
    c.bench_function(&format!("fused newmark step with dissipation: beam + frame ({} DOFs)", sys.n()), |b| {
        b.iter(|| fused.step(&load))
    });
    // The same with the three band products M·w₁ + C·w₂ − K·u (the step without the
    // proportional form, as for damping that is not Rayleigh plus a few entries).
    let mut fused = band(StepOptions { track_dissipation: true, ..StepOptions::default() });
    c.bench_function(
        &format!("fused newmark step with dissipation, three-product right-hand side: beam + frame ({} DOFs)", sys.n()),
        |b| b.iter(|| fused.step(&load)),
    );
}

fn coupled(c: &mut Criterion) {
    let model = calibrated_model(&case(FRAME)).unwrap();
    let sys = System::assemble(&model).unwrap();
    let s = beamflow::analysis::transient::TransientSettings {
        dt: Some(1e-4 / 1.2),
        periods: Some(100),
        steady_state: false,
        record_periods: 1,
        ..Default::default()
    };
    let mut g = c.benchmark_group("coupled transient");
    g.sample_size(10);
    g.bench_function("200 elements + frame, 20,000 steps (hysteresis, recording, energy)", |b| {
        b.iter(|| beamflow::analysis::transient::run(&model, &sys, &s).unwrap())
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().measurement_time(Duration::from_secs(3)).warm_up_time(Duration::from_secs(1));
    targets = foundation, newmark, coupled
}
criterion_main!(benches);
