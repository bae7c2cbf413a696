//! The thin plate: modes 1–20 of a 100 × 80 grid (≈ 32,000 DOFs, the size) — the
//! whole modal analysis (assembly included), and the solver alone on the assembled K and M
//! through the profile and through the sparse LDLᵀ — and one
//! steady-state evaluation of the shipped inertial plate case (20 × 16 grid, 1,281 DOFs,
//! 9 harmonics, the stack with hysteresis), the unit of a placement study on the plate.
//!
//! `cargo bench --bench plate`. Results and machine in docs/performance.md.

use beamflow::analysis::modes;
use beamflow::analysis::plan::calibrated_model;
use beamflow::analysis::steady_state;
use beamflow::assembly::System;
use beamflow::case::build::build_structure;
use beamflow::case::LoadedCase;
use beamflow::solve::lanczos;
use criterion::{criterion_group, criterion_main, Criterion};
use std::path::PathBuf;
use std::time::Duration;

const PLATE: &str = "[plate]\nlength_x = 0.5\nlength_y = 0.4\nthickness = 0.003\nyoungs_modulus = 70e9\n\
    poisson_ratio = 0.33\ndensity = 2700.0\n[plate.edges]\nx0 = \"simply_supported\"\nx1 = \"simply_supported\"\n\
    y0 = \"simply_supported\"\ny1 = \"simply_supported\"\n";

fn bench(c: &mut Criterion) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases");
    let big = LoadedCase::from_str(&format!("{PLATE}[plate.mesh]\nelements = [100, 80]\n"), "plate.toml", dir.clone())
        .unwrap();
    let structure = build_structure(&big).unwrap();
    let mut g = c.benchmark_group("plate");
    g.sample_size(10).measurement_time(Duration::from_secs(30));
    g.bench_function("modes_1_20_of_100x80", |b| b.iter(|| modes::run(&structure, 20).unwrap()));
    let sys = modes::bare_system(&structure).unwrap();
    g.bench_function("modes_1_20_of_100x80_solver_profile", |b| {
        b.iter(|| lanczos::modes_shift_invert(&sys.k, &sys.m, &sys.envelope, 20, 0.0).unwrap())
    });
    g.bench_function("modes_1_20_of_100x80_solver_sparse", |b| {
        b.iter(|| lanczos::modes_sparse(&sys.k, &sys.m, 20, 0.0).unwrap())
    });
    let lc = LoadedCase::load(&dir.join("plate-inertial.toml")).unwrap();
    let model = calibrated_model(&lc).unwrap();
    let sys = System::assemble(&model).unwrap();
    g.bench_function("steady_state_20x16_9_harmonics", |b| b.iter(|| steady_state::run(&model, &sys, 9, 64).unwrap()));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
