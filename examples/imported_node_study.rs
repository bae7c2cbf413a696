//! The time of one case of a node study on an imported model's shared reduction: the
//! example plate (0.5 × 0.4 × 0.003 m aluminium, simply supported, Rayleigh ζ = 0.01 at
//! modes 1 and 3) on an `nx` × `ny` grid, exported as an imported model (its M, K, C and
//! DOF map, as `[output] matrices = true` writes them), an inertial actuator at 83 Hz
//! swept over the w-nodes of a box (`nodes_in`), 9 harmonics, its steady state reduced.
//!
//! `cargo run --release --example imported_node_study [nx ny box_mm threads]` (default 100
//! 80 150 2: 32,000 DOFs, the box 0.10–0.25 m, 961 nodes) prints the wall time per case,
//! from the first case finished to the last (the shared modes, the static shapes solved up
//! front and the check on the full model fall outside it), and the sweep's total.

use beamflow::analysis::plan::calibrated_model;
use beamflow::assembly::System;
use beamflow::case::LoadedCase;
use beamflow::sweep::{self, RunOptions, Sweep};
use std::sync::{Arc, Mutex};
use std::time::Instant;

const PLATE: &str = "[plate]\nlength_x = 0.5\nlength_y = 0.4\nthickness = 0.003\nyoungs_modulus = 70e9\n\
    poisson_ratio = 0.33\ndensity = 2700.0\n[plate.edges]\nx0 = \"simply_supported\"\nx1 = \"simply_supported\"\n\
    y0 = \"simply_supported\"\ny1 = \"simply_supported\"\n\
    [damping]\nkind = \"rayleigh_ratio\"\nzeta = 0.01\nmodes = [1, 3]\n";

const ACTUATOR: &str = "[[actuator]]\ntype = \"inertial\"\nname = \"shaker\"\nat = [0.1, 0.1, 0.0]\n\
    component = \"w\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 83.0\n\
    [[analysis]]\ntype = \"steady_state\"\nreduction = \"auto\"\n";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, default: f64| std::env::args().nth(i).map_or(Ok(default), |s| s.parse::<f64>());
    let (nx, ny, box_mm, threads) = (arg(1, 100.0)?, arg(2, 80.0)?, arg(3, 150.0)?, arg(4, 2.0)? as usize);
    let dir = std::env::temp_dir().join(format!("beamflow-imported-study-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;

    // The plate's own matrices and DOF map, written as an imported model reads them.
    let text = format!("{PLATE}[plate.mesh]\nelements = [{nx}, {ny}]\nthrough_points = false\n");
    let model = calibrated_model(&LoadedCase::from_str(&text, "plate.toml", dir.clone())?)?;
    let sys = System::assemble(&model)?;
    beamflow::io::mtx::write_structure(&dir, "plate", &sys, &model)?;
    let file = |n: &str| format!("\"plate_structure_{n}\"");
    let imported = format!(
        "[imported]\nmass = {}\nstiffness = {}\ndamping = {}\ndofs = {}\n[damping]\nkind = \"given\"\n{ACTUATOR}",
        file("M.mtx"),
        file("K.mtx"),
        file("C.mtx"),
        file("dofs.csv")
    );
    std::fs::write(dir.join("imported.toml"), imported)?;
    let hi = 0.1 + box_mm * 1e-3;
    let study = format!(
        "base = \"imported.toml\"\nharmonics = 9\n[[parameter]]\npath = \"actuator[0].node\"\n\
         nodes_in = {{ min = [0.0999, 0.0999, -1.0], max = [{hi}, {hi}, 1.0] }}\n"
    );
    let s = Sweep::from_str(&study, "imported.sweep.toml", &dir)?;

    let finished: Arc<Mutex<Vec<Instant>>> = Arc::default();
    let log = Arc::clone(&finished);
    let opts = RunOptions {
        threads: Some(threads),
        on_evaluated: Some(Arc::new(move |_| log.lock().unwrap().push(Instant::now()))),
        ..Default::default()
    };
    let t0 = Instant::now();
    let table = sweep::run(&s, &opts)?;
    let total = t0.elapsed().as_secs_f64();
    let times = finished.lock().unwrap().clone();
    let (first, last) = (times.iter().min().ok_or("no case ran")?, times.iter().max().ok_or("no case ran")?);
    let per_case = last.duration_since(*first).as_secs_f64() * 1e3 / (times.len().max(2) - 1) as f64;
    let check = table.reduction.as_ref().ok_or("the sweep was not reduced")?;
    println!(
        "{} DOFs, {} nodes, {} modes: {per_case:.2} ms wall per case ({threads} thread{}), sweep {total:.1} s, check {:.1e}",
        sys.n(),
        times.len(),
        check.modes_kept,
        if threads == 1 { "" } else { "s" },
        check.max_relative_error
    );
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}
