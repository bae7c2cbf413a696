//! Mesh text → the mesh reader, and a mesh it accepts → a case built on it and the first
//! modes of its beam (for meshes of up to 64 elements, so each input stays fast).
#![no_main]

use beamflow::beam::{Material, Mesh, Section};
use beamflow::case::LoadedCase;
use libfuzzer_sys::fuzz_target;
use std::io::Write;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let section = Section { width: 0.05, thickness: 0.005 };
    let material = Material { youngs_modulus: 210e9, density: 7850.0 };
    let Ok(mesh) = Mesh::parse(text, "fuzz-mesh.toml", section, material) else { return };
    if mesh.elements.len() > 64 || !(mesh.length() > 0.0) {
        return;
    }
    // The case pipeline reads meshes from files: one file per fuzzing process.
    let dir = std::env::temp_dir().join(format!("beamflow-fuzz-mesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::File::create(dir.join("mesh.toml")).unwrap().write_all(data).unwrap();
    let case = format!(
        "[beam]\nlength = {}\n[beam.mesh]\nfile = \"mesh.toml\"\n[damping]\nkind = \"none\"\n\
         [[analysis]]\ntype = \"modes\"\ncount = 3\n",
        mesh.length()
    );
    let Ok(lc) = LoadedCase::from_str(&case, "fuzz.toml", dir) else { return };
    if let Ok((model, _)) = beamflow::analysis::plan::model_and_system(&lc) {
        if let Some(structure) = &model.structure {
            if let Ok(m) = beamflow::analysis::modes::run(structure, 3) {
                assert!(m.frequencies_hz.iter().all(|f| f.is_finite()), "{:?}", m.frequencies_hz);
            }
        }
    }
});
