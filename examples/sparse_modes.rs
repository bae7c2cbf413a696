//! The first `count` modes of the bench's simply supported plate on an `nx` × `ny` grid
//! through the sparse LDLᵀ and shift-invert Lanczos, timing assembly, ordering and
//! symbolic analysis, the numeric factorisation and the Lanczos run separately, with the
//! factor's size. For grids too large for a criterion bench (≈ 10⁶ DOFs); peak memory with
//! `/usr/bin/time -v`.
//!
//! `cargo run --release --example sparse_modes -- <nx> <ny> <count>`

use beamflow::analysis::budget::bytes_text;
use beamflow::analysis::modes;
use beamflow::case::build::build_structure;
use beamflow::case::LoadedCase;
use beamflow::linalg::SparsePattern;
use beamflow::solve::lanczos::modes_sparse;
use std::path::PathBuf;
use std::time::Instant;

const PLATE: &str = "[plate]\nlength_x = 0.5\nlength_y = 0.4\nthickness = 0.003\nyoungs_modulus = 70e9\n\
    poisson_ratio = 0.33\ndensity = 2700.0\n[plate.edges]\nx0 = \"simply_supported\"\nx1 = \"simply_supported\"\n\
    y0 = \"simply_supported\"\ny1 = \"simply_supported\"\n";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let arg = |i: usize, default: usize| args.get(i).map_or(Ok(default), |s| s.parse());
    let (nx, ny, count) = (arg(1, 100)?, arg(2, 80)?, arg(3, 20)?);
    let t = Instant::now();
    let text = format!("{PLATE}[plate.mesh]\nelements = [{nx}, {ny}]\n");
    let case = LoadedCase::from_str(&text, "plate.toml", PathBuf::from("."))?;
    let structure = build_structure(&case)?;
    let sys = modes::bare_system(&structure)?;
    println!("assembly: {} DOFs, K {} entries, {:.2} s", sys.n(), sys.k.nnz(), t.elapsed().as_secs_f64());
    let t = Instant::now();
    let pattern = SparsePattern::analyse(&[&sys.k, &sys.m])?;
    println!(
        "ordering and symbolic analysis: {:.2} s; factor {} entries, {} at the peak of a factorisation",
        t.elapsed().as_secs_f64(),
        pattern.factor_entries(),
        bytes_text(pattern.factor_bytes())
    );
    let t = Instant::now();
    let fac = pattern.factorize(&[(1.0, &sys.k)])?;
    println!("numeric factorisation: {:.2} s ({} negative pivots)", t.elapsed().as_secs_f64(), fac.negative_pivots());
    let t = Instant::now();
    let mut x = vec![1.0; sys.n()];
    for _ in 0..10 {
        fac.solve_in_place(&mut x);
    }
    println!("one solve: {:.1} ms", t.elapsed().as_secs_f64() * 100.0);
    drop(fac);
    drop(pattern);
    let t = Instant::now();
    let m = modes_sparse(&sys.k, &sys.m, count, 0.0)?;
    println!("modes_sparse (analysis, factorisation and Lanczos): {:.2} s", t.elapsed().as_secs_f64());
    let hz = m.frequencies_hz();
    println!("f_1 = {:.6} Hz, f_{count} = {:.6} Hz", hz[0], hz[hz.len() - 1]);
    if args.get(4).is_some_and(|s| s == "run") {
        let t = Instant::now();
        modes::run(&structure, count)?;
        println!("modes::run (the whole modal analysis): {:.2} s", t.elapsed().as_secs_f64());
    }
    Ok(())
}
