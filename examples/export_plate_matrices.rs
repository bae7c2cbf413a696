//! Writes K and M of the bench's simply supported plate (0.5 × 0.4 × 0.003 m aluminium)
//! on an `nx` × `ny` grid as Matrix Market files, for `benches/scipy_modes.py` to time
//! SciPy's shift-invert Lanczos on the very matrices the plate bench solves.
//!
//! `cargo run --release --example export_plate_matrices -- <nx> <ny> <folder>`
//! writes `<folder>/plate_K.mtx` and `<folder>/plate_M.mtx`.

use beamflow::analysis::modes;
use beamflow::case::build::build_structure;
use beamflow::case::LoadedCase;
use beamflow::io::mtx::write_system_matrix;
use std::path::PathBuf;

/// The plate of `benches/plate.rs`.
const PLATE: &str = "[plate]\nlength_x = 0.5\nlength_y = 0.4\nthickness = 0.003\nyoungs_modulus = 70e9\n\
    poisson_ratio = 0.33\ndensity = 2700.0\n[plate.edges]\nx0 = \"simply_supported\"\nx1 = \"simply_supported\"\n\
    y0 = \"simply_supported\"\ny1 = \"simply_supported\"\n";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let (Some(nx), Some(ny), Some(dir)) = (args.get(1), args.get(2), args.get(3)) else {
        return Err("usage: export_plate_matrices <nx> <ny> <folder>".into());
    };
    let text = format!("{PLATE}[plate.mesh]\nelements = [{nx}, {ny}]\n");
    let case = LoadedCase::from_str(&text, "plate.toml", PathBuf::from("."))?;
    let sys = modes::bare_system(&build_structure(&case)?)?;
    let dir = PathBuf::from(dir);
    std::fs::create_dir_all(&dir)?;
    write_system_matrix(&dir.join("plate_K.mtx"), sys.k.as_sprs())?;
    write_system_matrix(&dir.join("plate_M.mtx"), sys.m.as_sprs())?;
    println!("{} DOFs, K {} entries, M {} entries", sys.n(), sys.k.nnz(), sys.m.nnz());
    Ok(())
}
