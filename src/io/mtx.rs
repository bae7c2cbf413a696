//! Matrix Market export of sparse system matrices (stiffness, mass, damping).
//!
//! Why: being able to load beamflow's assembled matrices into SciPy
//! (`scipy.io.mmread`), MATLAB or Julia is the quickest way to check assembly and
//! boundary conditions independently. The coordinate format is plain text, lossless
//! (values are printed with Rust's shortest round-trip formatting) and 1-based.

use std::path::Path;

use sprs::CsMat;

use super::atomic::write_atomic;
use crate::error::{Error, Result};

/// Writes `mat` as a general real coordinate Matrix Market file, atomically.
/// Units are whatever the matrix holds (e.g. N/m for stiffness, kg for mass); the file
/// format has no place for them, so name files accordingly (`stiffness.mtx`).
pub fn write_matrix_market(path: &Path, mat: &CsMat<f64>) -> Result<()> {
    write_atomic(path, |tmp| sprs::io::write_matrix_market(tmp, mat).map_err(|e| Error::io(path, e)))
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
        write_matrix_market(&p, &m).unwrap();
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.starts_with("%%MatrixMarket matrix coordinate real general"), "{text}");
        let back = read_matrix_market(&p).unwrap();
        assert_eq!(back.shape(), (3, 4));
        assert_eq!(back.nnz(), 4);
        assert_eq!(back.to_dense(), m.to_dense());
        // Column-major input is written the same.
        write_matrix_market(&p, &m.to_csc()).unwrap();
        assert_eq!(read_matrix_market(&p).unwrap().to_dense(), m.to_dense());
        assert_eq!(std::fs::read_dir(p.parent().unwrap()).unwrap().count(), 1);
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
