//! Modal-reduced against full-model transient of the paper's coupled frame case
//! (cases/beam-frame-12V-60Hz.toml: frame actuator with hysteresis on the 200-element
//! clamped–clamped beam, 12 V at 60 Hz, 9 harmonics, run to steady state).
//!
//! `cargo bench --bench reduction`. Results and machine in docs/performance.md.

use beamflow::analysis::plan::calibrated_model;
use beamflow::analysis::reduction::{self, Cutoff, ReductionSettings};
use beamflow::analysis::steady_state;
use beamflow::analysis::transient::{self, TransientSettings};
use beamflow::assembly::System;
use beamflow::case::LoadedCase;
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/beam-frame-12V-60Hz.toml");
    let lc = LoadedCase::load(&path).unwrap();
    let model = calibrated_model(&lc).unwrap();
    let full = System::assemble(&model).unwrap();
    let settings = TransientSettings { harmonics: Some(9), ..Default::default() };
    let rs = ReductionSettings {
        cutoff: Cutoff::HarmonicFactor(5.0),
        static_correction: true,
        error_estimate: false,
        modal_damping: None,
    };
    let hz = reduction::cutoff_hz(&model, &rs, 9).unwrap();
    let (red, report) = reduction::reduce(&model, &full, &rs, hz).unwrap();
    let r = transient::run(&model, &red, &settings).unwrap();
    eprintln!(
        "frame case: {} → {} DOFs ({} modes to {hz} Hz + {} residual), {} periods × {} steps",
        report.full_dofs,
        report.reduced_dofs,
        report.modes_kept,
        report.residual_vectors,
        r.periods_run,
        r.steps_per_period
    );

    let mut g = c.benchmark_group("reduction_frame_12V_60Hz");
    g.sample_size(20).measurement_time(Duration::from_secs(8));
    g.bench_function("reduced_transient", |b| b.iter(|| transient::run(&model, black_box(&red), &settings).unwrap()));
    // The same work as the full-model coupled benchmark (`--bench core -- coupled`): 100
    // periods of 200 steps, 20,000 steps, recording and energy bookkeeping included.
    let same_work = TransientSettings {
        dt: Some(1e-4 / 1.2),
        periods: Some(100),
        steady_state: false,
        record_periods: 1,
        harmonics: Some(9),
        ..Default::default()
    };
    g.bench_function("reduced_transient_20000_steps", |b| {
        b.iter(|| transient::run(&model, black_box(&red), &same_work).unwrap())
    });
    g.bench_function("build_reduced_system", |b| {
        b.iter(|| reduction::reduce(&model, black_box(&full), &rs, hz).unwrap())
    });
    g.bench_function("reduced_steady_state", |b| {
        b.iter(|| steady_state::run(&model, black_box(&red), 9, 1024).unwrap())
    });
    g.bench_function("full_steady_state", |b| b.iter(|| steady_state::run(&model, black_box(&full), 9, 1024).unwrap()));
    g.finish();

    let mut g = c.benchmark_group("reduction_frame_12V_60Hz_full");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    g.bench_function("full_transient", |b| b.iter(|| transient::run(&model, black_box(&full), &settings).unwrap()));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
