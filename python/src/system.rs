//! Lower-level access for custom studies: the assembled M, C, K (CSR parts for
//! scipy.sparse) with the DOF map, the bare beam's modes and the coupled system's modes.

use crate::background;
use crate::convert::array;
use beamflow::analysis::plan::model_and_system;
use beamflow::assembly::System;
use beamflow::case::LoadedCase;
use beamflow::linalg::Csr;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// `(data, indices, indptr, (n, n))`: the arguments of `scipy.sparse.csr_matrix`.
fn csr<'py>(py: Python<'py>, m: &Csr) -> PyResult<Bound<'py, PyAny>> {
    let s = m.as_sprs().to_csr();
    let n = s.rows();
    let data = s.data().to_vec();
    let indices: Vec<i64> = s.indices().iter().map(|&i| i as i64).collect();
    let indptr: Vec<i64> = s.indptr().raw_storage().iter().map(|&i| i as i64).collect();
    let (nd, ni, np) = (data.len(), indices.len(), indptr.len());
    Ok((array(py, data, &[nd])?, array(py, indices, &[ni])?, array(py, indptr, &[np])?, (n, s.cols()))
        .into_pyobject(py)?
        .into_any())
}

/// The DOF map as columns: for each global DOF its structure node (−1 for an actuator
/// body), the node's x, y, z (NaN for a body and where the structure has no such
/// coordinate), the source model's node number on an imported model (−1 elsewhere), its
/// kind (`w`, `theta`, … or the body DOF's name) and the actuator it belongs to (empty
/// for the structure).
fn dof_table<'py>(py: Python<'py>, model: &beamflow::assembly::Model, sys: &System) -> PyResult<Bound<'py, PyDict>> {
    let rows = beamflow::assembly::dof_rows(model, sys);
    let n = rows.len();
    let t = PyDict::new(py);
    t.set_item("index", array(py, (0..n as i64).collect(), &[n])?)?;
    t.set_item("node", array(py, rows.iter().map(|r| r.node.map_or(-1, |v| v as i64)).collect(), &[n])?)?;
    let column =
        |f: fn(&beamflow::assembly::DofRow) -> Option<f64>| rows.iter().map(|r| f(r).unwrap_or(f64::NAN)).collect();
    t.set_item("x", array(py, column(|r| r.x), &[n])?)?;
    t.set_item("y", array(py, column(|r| r.y), &[n])?)?;
    t.set_item("z", array(py, column(|r| r.z), &[n])?)?;
    t.set_item("node_id", array(py, rows.iter().map(|r| r.node_id.unwrap_or(-1)).collect(), &[n])?)?;
    t.set_item("kind", rows.iter().map(|r| r.kind.clone()).collect::<Vec<_>>())?;
    t.set_item("actuator", rows.iter().map(|r| r.actuator.clone().unwrap_or_default()).collect::<Vec<_>>())?;
    Ok(t)
}

/// The case's assembled system (the full model, before any modal reduction).
pub fn system<'py>(py: Python<'py>, lc: LoadedCase) -> PyResult<Bound<'py, PyDict>> {
    let (built, sys) = background::run(py, move || model_and_system(&lc))?;
    let d = PyDict::new(py);
    d.set_item("K", csr(py, &sys.k)?)?;
    d.set_item("M", csr(py, &sys.m)?)?;
    d.set_item("C", csr(py, &sys.c)?)?;
    d.set_item("dofs", dof_table(py, &built, &sys)?)?;
    d.set_item("modal_damping", built.modal_ratios().map(<[f64]>::to_vec))?;
    d.set_item("rayleigh", (built.rayleigh().a0, built.rayleigh().a1))?;
    Ok(d)
}

/// The bare structure's modes (`beamflow modes`): frequencies, closed-form references and
/// the mode shapes' w at every node, with the nodes' coordinates (x; y on a plate; y, z and
/// ids on an imported model).
pub fn bare_modes<'py>(py: Python<'py>, lc: LoadedCase, count: usize) -> PyResult<Bound<'py, PyDict>> {
    let r = background::run(py, move || {
        let structure = beamflow::case::build::build_structure(&lc)?;
        beamflow::analysis::modes::run(&structure, count)
    })?;
    let (m, nx) = (r.frequencies_hz.len(), r.node_x.len());
    let d = PyDict::new(py);
    d.set_item("frequencies_hz", array(py, r.frequencies_hz, &[m])?)?;
    d.set_item("analytic_hz", array(py, r.analytic_hz.clone(), &[r.analytic_hz.len()])?)?;
    d.set_item("relative_error", array(py, r.relative_error.clone(), &[r.relative_error.len()])?)?;
    d.set_item("roundoff_bound", array(py, r.roundoff_bound, &[m])?)?;
    d.set_item("reference", r.reference)?;
    d.set_item("node_x", array(py, r.node_x, &[nx])?)?;
    // A plate's and an imported model's nodes are not on one line: y (and z, and the
    // source model's node ids) place the shapes on the structure.
    if !r.node_y.is_empty() {
        d.set_item("node_y", array(py, r.node_y.clone(), &[r.node_y.len()])?)?;
    }
    if !r.node_z.is_empty() {
        d.set_item("node_z", array(py, r.node_z.clone(), &[r.node_z.len()])?)?;
        d.set_item("node_id", array(py, r.node_id.clone(), &[r.node_id.len()])?)?;
    }
    d.set_item("shapes_w", array(py, r.shapes_w.concat(), &[m, nx])?)?;
    Ok(d)
}

/// The modes of the whole assembled system (beam and actuator bodies), undamped, from the
/// dense generalised eigenproblem K·φ = ω²·M·φ over every DOF; shapes mass-normalised,
/// one row per mode over the global DOFs.
pub fn coupled_modes<'py>(py: Python<'py>, lc: LoadedCase, count: usize) -> PyResult<Bound<'py, PyDict>> {
    let (built, sys, modes) = background::run(py, move || {
        let (built, sys) = model_and_system(&lc)?;
        let all: Vec<usize> = (0..sys.n()).collect();
        let modes = beamflow::solve::eigen::modes(&sys.k, &sys.m, &all, count)?;
        Ok((built, sys, modes))
    })?;
    let (m, n) = (modes.count(), sys.n());
    let shapes: Vec<f64> = (0..m).flat_map(|r| modes.shape_global(r, n)).collect();
    let d = PyDict::new(py);
    d.set_item("frequencies_hz", array(py, modes.frequencies_hz(), &[m])?)?;
    d.set_item("shapes", array(py, shapes, &[m, n])?)?;
    d.set_item("dofs", dof_table(py, &built, &sys)?)?;
    Ok(d)
}
