//! Cases per second of a placement sweep (position × frequency, inertial actuator, default
//! 200-element beam, 9 harmonics): the fast path on 1 thread and on all threads, and what
//! the two shortcuts save (Rayleigh damping cached, fast steady state vs
//! `steady_state::run`). Criterion reports the throughput in cases ("elements") per second.
//!
//! `fast_2x250` is 2 placements × 250 frequencies: the cases of a placement share one
//! assembled system, as in a full placement sweep.
//!
//! `cargo bench --bench sweep`; numbers and machine in docs/performance.md (## Sweeps).

use beamflow::sweep::{self, RunOptions, Sweep};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::path::Path;

fn placement(positions: usize, frequencies: usize, extra: &str) -> Sweep {
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/placement-inertial.toml");
    let text = format!(
        "base = {:?}\n{extra}\n[[parameter]]\npath = \"actuator[0].x_e\"\nstart = 0.05\nstop = 0.68\ncount = {positions}\n\
         [[parameter]]\npath = \"actuator[0].voltage.frequency\"\nstart = 10.0\nstop = 500.0\ncount = {frequencies}\n",
        base.display().to_string()
    );
    Sweep::from_str(&text, "bench.sweep.toml", Path::new(".")).expect("bench sweep")
}

fn bench(c: &mut Criterion) {
    let all = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut g = c.benchmark_group("placement_sweep");
    g.sample_size(10);

    let s = placement(10, 10, "");
    g.throughput(Throughput::Elements(s.len() as u64));
    for threads in [1, all] {
        g.bench_function(format!("fast/{threads}_threads"), |b| {
            b.iter(|| sweep::run(&s, &RunOptions { threads: Some(threads), ..Default::default() }).unwrap())
        });
    }
    // Few placements, many frequencies: the cases of a placement share one assembled system.
    let wide = placement(2, 250, "");
    g.throughput(Throughput::Elements(wide.len() as u64));
    g.bench_function("fast_2x250/1_thread", |b| {
        b.iter(|| sweep::run(&wide, &RunOptions { threads: Some(1), ..Default::default() }).unwrap())
    });
    g.throughput(Throughput::Elements(s.len() as u64));
    g.bench_function("steady_state_run/1_thread", |b| {
        b.iter(|| sweep::run(&s, &RunOptions { threads: Some(1), reference: true, ..Default::default() }).unwrap())
    });

    // Without the cached damping every case computes the bare beam's modes: far slower, so
    // fewer cases.
    let s = placement(4, 5, "cache_damping = false");
    g.throughput(Throughput::Elements(s.len() as u64));
    g.bench_function("fast_no_damping_cache/1_thread", |b| {
        b.iter(|| sweep::run(&s, &RunOptions { threads: Some(1), ..Default::default() }).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
