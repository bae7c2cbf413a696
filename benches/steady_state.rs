//! The frequency-domain periodic steady state (`steady_state::run`, physics spec §9) of the
//! paper cases with 9 harmonics and 1024 samples per period: the frame actuator
//! (cases/beam-frame-12V-60Hz.toml) and the inertial one (cases/beam-inertial-12V-60Hz.toml),
//! both on the 200-element clamped–clamped beam with Bouc–Wen hysteresis. The model and
//! its assembled system are built once; what is timed is the whole `run`: settling the
//! hysteresis cycle, the 10 complex solves and the reconstruction of one period.
//!
//! `cargo bench --bench steady_state`; numbers and machine in docs/perf-notes-ss.md.

use beamflow::analysis::plan::calibrated_model;
use beamflow::analysis::steady_state;
use beamflow::assembly::System;
use beamflow::case::LoadedCase;
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::Path;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("steady_state_9_harmonics");
    g.sample_size(50);
    for (name, file) in
        [("frame_12V_60Hz", "beam-frame-12V-60Hz.toml"), ("inertial_12V_60Hz", "beam-inertial-12V-60Hz.toml")]
    {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases").join(file);
        let model = calibrated_model(&LoadedCase::load(&path).unwrap()).unwrap();
        let sys = System::assemble(&model).unwrap();
        let r = steady_state::run(&model, &sys, 9, 1024).unwrap();
        eprintln!("{name}: {} DOFs, hysteresis settled in {} periods", sys.n(), r.hysteresis_periods);
        g.bench_function(name, |b| b.iter(|| steady_state::run(&model, black_box(&sys), 9, 1024).unwrap()));
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
