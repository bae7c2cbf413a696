//! The time of one placement evaluation on the reduced plate: candidates of
//! `cases/plate-placement.opt.toml` (two frame actuators on the 20 × 16 simply supported
//! plate, 9 harmonics, its steady state on the modal reduction the study shares) and of the
//! same study with one inertial actuator, each candidate a new position.
//!
//! `cargo run --release --example placement_evaluation [count]` prints the median time per
//! evaluation (ms) of each, after the shared modes are built by a first evaluation.
//! `benches/scipy_placement.py` runs it beside SciPy's solve of the same plate.

use beamflow::optimize::{self, evaluate::Evaluator};
use std::path::PathBuf;
use std::time::Instant;

/// Median milliseconds per evaluation of `count` candidates of `spec` (u in a fixed
/// low-discrepancy sequence).
fn per_evaluation_ms(spec: &optimize::Spec, count: usize) -> f64 {
    let ev = Evaluator::new(spec);
    let d = spec.variables.len();
    let u = |i: usize| -> Vec<f64> {
        (0..d).map(|j| ((i + 1) as f64 * (0.618_033_988_7 + 0.1 * j as f64)).fract()).collect()
    };
    assert!(ev.evaluate(&u(0)).outcome.is_some(), "the first candidate solves");
    let mut times: Vec<f64> = (1..=count)
        .map(|i| {
            let t = Instant::now();
            let e = ev.evaluate(&u(i));
            assert!(e.outcome.is_some() || !e.feasible());
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let count: usize = std::env::args().nth(1).map_or(Ok(200), |s| s.parse())?;
    let cases = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases");
    let two = optimize::load(&cases.join("plate-placement.opt.toml"))?;
    println!("two frames (5 variables): {:.3} ms per evaluation", per_evaluation_ms(&two, count));
    // The shipped inertial case, its steady state reduced and its grid uniform, as the
    // shipped frame cases are.
    let dir = std::env::temp_dir().join(format!("beamflow-placement-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let base = std::fs::read_to_string(cases.join("plate-inertial.toml"))?
        .replace("elements = [20, 16]\n", "elements = [20, 16]\nthrough_points = false\n")
        .replace("type = \"steady_state\"\n", "type = \"steady_state\"\nreduction = \"auto\"\n");
    std::fs::write(dir.join("plate-inertial.toml"), base)?;
    let text = "base = \"plate-inertial.toml\"\nharmonics = 9\n\
        [[variable]]\npath = \"actuator[0].at[0]\"\nmin = 0.05\nmax = 0.45\n\
        [[variable]]\npath = \"actuator[0].at[1]\"\nmin = 0.05\nmax = 0.35\n\
        [[objective]]\nquantity = \"net_power\"\ngoal = \"maximize\"\n";
    let one = optimize::Spec::from_str(text, "inertial.opt.toml", &dir)?;
    println!("one inertial actuator (2 variables): {:.3} ms per evaluation", per_evaluation_ms(&one, count));
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}
