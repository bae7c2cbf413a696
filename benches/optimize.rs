//! Placement optimisation: evaluations per second of the steady-state objective (paper
//! beam, 200 elements, 9 harmonics; one frame actuator and two), and the time to the
//! optimum of the two benchmark problems of tests/optimize.rs (one variable: the frame at
//! 440 Hz along the beam; three: two frames' positions and their common frequency,
//! cases/two_frames.opt.toml), on all threads.
//!
//! `cargo bench --bench optimize`; numbers and machine in docs/performance.md
//! (## Placement optimisation).

use beamflow::optimize::evaluate::Evaluator;
use beamflow::optimize::{self, RunOptions, Spec};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::path::Path;

fn one_variable(dir: &Path) -> Spec {
    let cases = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    let base = std::fs::read_to_string(cases.join("placement-frame.toml")).expect("shipped case");
    std::fs::write(dir.join("frame-440Hz.toml"), base.replace("frequency = 60.0", "frequency = 440.0")).unwrap();
    let text = "base = \"frame-440Hz.toml\"\n[search]\nstarts = 3\nevaluations = 56\n[[variable]]\n\
                path = \"actuator[0].x_e\"\nmin = 0.05\nmax = 0.68\n[[objective]]\nquantity = \"net_power\"\n";
    Spec::from_str(text, "one.opt.toml", dir).expect("bench spec")
}

fn bench(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temp dir");
    let one = one_variable(dir.path());
    let three = optimize::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/two_frames.opt.toml")).unwrap();

    let mut g = c.benchmark_group("optimize_evaluation");
    // 100 feasible candidates spread over the box, one thread: each builds, assembles and
    // solves (the two frames: the left in the left half, the right in the right half).
    for (name, spec) in [("one_frame", &one), ("two_frames", &three)] {
        let d = spec.variables.len();
        let us: Vec<Vec<f64>> = (0..100)
            .map(|i| {
                let t = i as f64 / 100.0;
                match d {
                    1 => vec![t],
                    _ => vec![0.05 + 0.35 * t, 0.6 + 0.35 * (1.0 - t), (t * 7.0).fract()],
                }
            })
            .collect();
        assert!(us.iter().all(|u| Evaluator::new(spec).evaluate(u).feasible()));
        g.throughput(Throughput::Elements(us.len() as u64));
        g.bench_function(name, |b| {
            b.iter(|| {
                let ev = Evaluator::new(spec);
                us.iter().map(|u| ev.evaluate(u).values[0]).sum::<f64>()
            })
        });
    }
    g.finish();

    let mut g = c.benchmark_group("optimize_to_optimum");
    g.sample_size(10);
    for (name, spec) in [("one_variable", &one), ("three_variables", &three)] {
        g.bench_function(name, |b| b.iter(|| optimize::run(spec, &RunOptions::default()).unwrap().best.values[0]));
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
