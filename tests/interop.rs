//! Data for other tools: the Matrix Market matrices and the DOF map beside them name each
//! row, checked against element stiffnesses computed here.

mod common;

use beamflow::io::mtx::read_matrix_market;
use std::path::Path;

/// A row of `<stem>_dofs.csv`: (row − 1, node, x, kind, actuator).
type DofLine = (usize, Option<usize>, Option<f64>, String, String);

fn dof_map(path: &Path) -> Vec<DofLine> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("row,node,x_m,kind,actuator"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[0].parse::<usize>().unwrap() - 1, f[1].parse().ok(), f[2].parse().ok(), f[3].into(), f[4].into())
        })
        .collect()
}

#[test]
fn the_dof_map_names_the_stack_foot_and_the_top_mass_rows() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("foot.toml");
    let k_p = 3.0e7;
    std::fs::write(
        &case,
        format!(
            "[beam.mesh]\nelements = 40\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n\
             [[actuator]]\ntype = \"inertial\"\nname = \"shaker\"\nx_e = 0.15\n\
             [actuator.stack]\nk_p = {k_p:e}\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n\
             [[analysis]]\ntype = \"modes\"\ncount = 2\n[output]\nmatrices = true\nplots = false\n"
        ),
    )
    .unwrap();
    let out = dir.path().join("out");
    beamflow::app::commands::run(&case, Some(&out), None, false).unwrap();
    let k = read_matrix_market(&out.join("foot_K.mtx")).unwrap();
    assert!(std::fs::read_to_string(out.join("foot_K.mtx"))
        .unwrap()
        .starts_with("%%MatrixMarket matrix coordinate real symmetric"));
    let rows = dof_map(&out.join("foot_dofs.csv"));
    assert_eq!(rows.len(), k.rows());
    let foot =
        rows.iter().find(|r| r.3 == "w" && r.2.is_some_and(|x| (x - 0.15).abs() < 1e-12)).expect("w row at 0.15 m");
    let top = rows.iter().find(|r| r.3 == "z_t" && r.4 == "shaker").expect("the top mass's row");
    // Neighbouring nodes of the foot give the two element lengths around it.
    let xs: Vec<f64> = rows.iter().filter(|r| r.3 == "w").filter_map(|r| r.2).collect();
    let at = xs.iter().position(|&x| (x - 0.15).abs() < 1e-12).unwrap();
    let (h1, h2) = (xs[at] - xs[at - 1], xs[at + 1] - xs[at]);
    // A Hermite element's w–w stiffness is 12·EI/h³ at each end; the stack adds k_p.
    let beam = 12.0 * common::EI / h1.powi(3) + 12.0 * common::EI / h2.powi(3);
    let kd = |i: usize, j: usize| k.get(i, j).copied().unwrap_or(0.0);
    assert!(common::rel(kd(foot.0, foot.0), beam + k_p) < 1e-12, "{} vs {}", kd(foot.0, foot.0), beam + k_p);
    assert_eq!(kd(top.0, top.0), k_p);
    assert_eq!(kd(top.0, foot.0), -k_p);
    assert_eq!(kd(foot.0, top.0), -k_p);
}
