//! Matrix Market export of sparse system matrices (stiffness, mass, damping).
//!
//! Why: being able to load beamflow's assembled matrices into SciPy
//! (`scipy.io.mmread`), MATLAB or Julia is the quickest way to check assembly and
//! boundary conditions independently. The coordinate format is plain text, lossless
//! (values are printed with Rust's shortest round-trip formatting) and 1-based.

use std::path::Path;

use sprs::CsMat;

use crate::error::{Error, Result};

/// Writes `mat` in Matrix Market coordinate format, atomically: `symmetric` storage (the
/// lower triangle only) when the matrix is exactly symmetric, `general` otherwise. Values
/// are printed in Rust's shortest round-trip form, so reading them back is exact.
pub fn write_system_matrix(path: &Path, mat: &CsMat<f64>) -> Result<()> {
    let csr = if mat.is_csr() { mat.clone() } else { mat.to_csr() };
    let symmetric = csr.rows() == csr.cols() && csr.iter().all(|(&v, (i, j))| csr.get(j, i) == Some(&v));
    let entries: Vec<(usize, usize, f64)> =
        csr.iter().filter(|(_, (i, j))| !symmetric || i >= j).map(|(&v, (i, j))| (i, j, v)).collect();
    let mut text = format!(
        "%%MatrixMarket matrix coordinate real {}\n{} {} {}\n",
        if symmetric { "symmetric" } else { "general" },
        csr.rows(),
        csr.cols(),
        entries.len()
    );
    for (i, j, v) in entries {
        text += &format!("{} {} {v:?}\n", i + 1, j + 1);
    }
    super::atomic::write_atomic_string(path, &text)
}

/// Writes the DOF map of a system as CSV beside its matrices: one line per row/column
/// (1-based `row` as in the Matrix Market files, the structure's `node` — its index, or on
/// an imported model the source model's node number —, the node's x, y, z in m where the
/// structure has them, the DOF kind and the actuator a body DOF belongs to), so a matrix
/// row can be named.
pub fn write_dof_map(path: &Path, rows: &[crate::assembly::DofRow]) -> Result<()> {
    let mut text = String::from("row,node,x_m,y_m,z_m,kind,actuator\n");
    let real = |v: Option<f64>| v.map(|v| format!("{v:?}")).unwrap_or_default();
    for r in rows {
        let node = r.node_id.map(|v| v.to_string()).or(r.node.map(|v| v.to_string())).unwrap_or_default();
        let (x, y, z) = (real(r.x), real(r.y), real(r.z));
        let actuator = r.actuator.as_deref().unwrap_or("");
        text += &format!("{},{node},{x},{y},{z},{},{actuator}\n", r.index + 1, r.kind);
    }
    super::atomic::write_atomic_string(path, &text)
}

/// Writes the structure's own M, K and C (elements, point masses, supports' and grounded
/// springs, its damping; no actuator) and their DOF map in the format an imported model
/// reads (spec §17): `{stem}_structure_{M,K,C}.mtx` and `{stem}_structure_dofs.csv` in
/// `dir`, the rows in the system's numbering of the structure's free DOFs. Components are
/// beamflow's own DOF kinds (w, theta, w_x, …), which have no exact name among ux … rz.
/// Returns the files written.
pub fn write_structure(
    dir: &Path,
    stem: &str,
    sys: &crate::assembly::System,
    model: &crate::assembly::Model,
) -> Result<Vec<std::path::PathBuf>> {
    let Some(structure) = &model.structure else { return Ok(Vec::new()) };
    let dofs = &sys.dofs;
    let rows = dofs.structure_dofs();
    let mut written = Vec::new();
    for (name, a) in [("M", &sys.m_beam), ("K", &sys.k_beam), ("C", &sys.c_beam)] {
        let mut t = sprs::TriMat::new((rows.len(), rows.len()));
        for (i, j, v) in a.restricted(&rows).triplets() {
            t.add_triplet(i, j, v);
        }
        let p = dir.join(format!("{stem}_structure_{name}.mtx"));
        write_system_matrix(&p, &t.to_csr())?;
        written.push(p);
    }
    let k = dofs.kinds.len();
    let mut owner = vec![(0, 0); sys.n()];
    for (at, d) in dofs.nodes.iter().enumerate() {
        if let Some(d) = d {
            owner[*d] = (at / k, at % k);
        }
    }
    let mut text = format!("{}\n", crate::imported::dof_map::HEADER);
    for (r, &d) in rows.iter().enumerate() {
        let (node, kind) = owner[d];
        let xyz = match structure.node_location(node) {
            crate::structure::Location::Node { xyz, .. } => xyz,
            at => [at.x(), at.y().unwrap_or(0.0), 0.0],
        };
        let id = structure.imported().map_or(node as i64, |m| m.nodes[node].id);
        text += &format!("{},{id},{:?},{:?},{:?},{}\n", r + 1, xyz[0], xyz[1], xyz[2], dofs.kinds[kind]);
    }
    let p = dir.join(format!("{stem}_structure_dofs.csv"));
    super::atomic::write_atomic_string(&p, &text)?;
    written.push(p);
    Ok(written)
}

/// Reads a real Matrix Market file (general or symmetric) into CSR form; used to check
/// round trips and to load reference matrices in tests.
pub fn read_matrix_market(path: &Path) -> Result<CsMat<f64>> {
    let tri = sprs::io::read_matrix_market::<f64, usize, _>(path).map_err(|e| match e {
        sprs::io::IoError::Io(io) => Error::io(path, io),
        other => Error::Parse { file: path.display().to_string(), message: format!("Matrix Market: {other}") },
    })?;
    Ok(tri.to_csr())
}

#[cfg(test)]
mod tests {
    use super::*;
    use sprs::TriMat;

    #[test]
    fn round_trip_is_exact() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out/k.mtx");
        let mut t = TriMat::new((3, 4));
        t.add_triplet(0, 0, 1.0e9);
        t.add_triplet(1, 2, -0.1);
        t.add_triplet(2, 3, std::f64::consts::PI);
        t.add_triplet(2, 0, 1.0e-300);
        let m: CsMat<f64> = t.to_csr();
        write_system_matrix(&p, &m).unwrap();
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.starts_with("%%MatrixMarket matrix coordinate real general"), "{text}");
        let back = read_matrix_market(&p).unwrap();
        assert_eq!(back.shape(), (3, 4));
        assert_eq!(back.nnz(), 4);
        assert_eq!(back.to_dense(), m.to_dense());
        // Column-major input is written the same.
        write_system_matrix(&p, &m.to_csc()).unwrap();
        assert_eq!(read_matrix_market(&p).unwrap().to_dense(), m.to_dense());
        assert_eq!(std::fs::read_dir(p.parent().unwrap()).unwrap().count(), 1);
    }

    #[test]
    fn symmetric_storage_round_trips_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("k.mtx");
        let mut t = TriMat::new((3, 3));
        for (i, j, v) in [(0, 0, 2.5e9), (1, 1, 0.1), (2, 2, 3.0), (0, 1, -1.0 / 3.0), (1, 0, -1.0 / 3.0)] {
            t.add_triplet(i, j, v);
        }
        let m: CsMat<f64> = t.to_csr();
        write_system_matrix(&p, &m).unwrap();
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.starts_with("%%MatrixMarket matrix coordinate real symmetric\n3 3 4\n"), "{text}");
        assert_eq!(read_matrix_market(&p).unwrap().to_dense(), m.to_dense());
        // One entry off symmetry: stored in full.
        let mut t = TriMat::new((2, 2));
        t.add_triplet(0, 1, 1.0);
        t.add_triplet(1, 0, 1.0 + f64::EPSILON);
        let m: CsMat<f64> = t.to_csr();
        write_system_matrix(&p, &m).unwrap();
        assert!(std::fs::read_to_string(&p).unwrap().contains("general"));
        assert_eq!(read_matrix_market(&p).unwrap().to_dense(), m.to_dense());
    }

    #[test]
    fn errors_name_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("bad.mtx");
        std::fs::write(&p, "not a matrix\n").unwrap();
        let e = read_matrix_market(&p).unwrap_err().to_string();
        assert!(e.contains("bad.mtx"), "{e}");
        let e = read_matrix_market(&dir.path().join("none.mtx")).unwrap_err().to_string();
        assert!(e.contains("none.mtx"), "{e}");
    }
}
