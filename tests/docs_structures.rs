//! Every TOML snippet of docs/structures.md runs as written: a plate case and an imported
//! model's case pass `beamflow check`, the mesh file is read by a plate case that names it,
//! and the study over nodes is a sweep file that runs.

use std::path::{Path, PathBuf};

const DOC: &str = include_str!("../docs/structures.md");

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The ```toml blocks of the page, in order.
fn snippets() -> Vec<String> {
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in DOC.lines() {
        match (&mut current, line.trim_end()) {
            (None, "```toml") => current = Some(String::new()),
            (Some(b), "```") => {
                blocks.push(std::mem::take(b));
                current = None;
            }
            (Some(b), l) => *b += &format!("{l}\n"),
            (None, _) => {}
        }
    }
    blocks
}

/// A plate case that names the mesh file snippet.
const GRADED_CASE: &str = "[plate]\nlength_x = 0.5\nlength_y = 0.4\nthickness = 0.003\nyoungs_modulus = 70e9\n\
    poisson_ratio = 0.33\ndensity = 2700.0\n[plate.mesh]\nfile = \"graded.toml\"\n[plate.edges]\n\
    x0 = \"simply_supported\"\nx1 = \"simply_supported\"\ny0 = \"simply_supported\"\ny1 = \"simply_supported\"\n\
    [[analysis]]\ntype = \"modes\"\ncount = 3\n";

fn beamflow(dir: &Path, args: &[&str]) {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_beamflow")).current_dir(dir).args(args).output().unwrap();
    assert!(
        o.status.success(),
        "{args:?}: {}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// A folder with the portal frame's files, which the imported snippets name.
fn portal(dir: &Path) {
    for f in std::fs::read_dir(repo().join("cases/portal-frame")).unwrap() {
        let f = f.unwrap().path();
        std::fs::copy(&f, dir.join(f.file_name().unwrap())).unwrap();
    }
}

#[test]
fn every_toml_snippet_of_the_structures_page_runs_as_written() {
    let blocks = snippets();
    assert_eq!(blocks.len(), 4, "a new snippet needs its way to run here");
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    portal(d);
    let mut ran = 0;
    for (i, text) in blocks.iter().enumerate() {
        let name = format!("snippet{i}.toml");
        std::fs::write(d.join(&name), text).unwrap();
        if text.contains("[plate]") {
            beamflow(d, &["check", &name]);
            ran += 1;
        } else if text.contains("beamflow-plate-mesh-1") {
            // The page says this is the shipped graded mesh: the same file, and a plate case reads it.
            let shipped = std::fs::read_to_string(repo().join("meshes/plate-graded.toml")).unwrap();
            assert_eq!(text.parse::<toml::Table>().unwrap(), shipped.parse::<toml::Table>().unwrap());
            std::fs::write(d.join("graded.toml"), text).unwrap();
            std::fs::write(d.join("graded-case.toml"), GRADED_CASE).unwrap();
            beamflow(d, &["check", "graded-case.toml"]);
            ran += 1;
        } else if text.contains("[imported]") {
            beamflow(d, &["check", &name]);
            ran += 1;
        } else if text.contains("[[parameter]]") {
            let sweep = format!("snippet{i}.sweep.toml");
            std::fs::write(d.join(&sweep), text).unwrap();
            beamflow(d, &["sweep", &sweep, "--out", "study.h5", "--quiet"]);
            ran += 1;
        }
    }
    assert_eq!(ran, 4);
}
