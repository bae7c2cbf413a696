//! beamflow's errors as the Python exceptions of `beamflow.errors`, with their fields as
//! attributes (`InputError(file, field, reason)`, …).

use beamflow::Error;
use pyo3::call::PyCallArgs;
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError};
use pyo3::prelude::*;

/// An instance of `beamflow.errors.<class>` built from `args`.
fn raise<'py>(py: Python<'py>, class: &str, args: impl PyCallArgs<'py>) -> PyErr {
    let made =
        py.import("beamflow.errors").and_then(|m| m.getattr(class)).and_then(|c| c.call1(args)).map(PyErr::from_value);
    made.unwrap_or_else(|e| e)
}

/// The Python exception for a beamflow error.
pub fn to_py(e: Error) -> PyErr {
    Python::attach(|py| match e {
        Error::Input { file, field, reason } => raise(py, "InputError", (file, field, reason)),
        // Settings reach Python named by their scope when no file is known (library calls
        // on models built in code); case runs name the file before this.
        Error::Setting { scope, field, reason } => raise(py, "InputError", (scope.to_string(), field, reason)),
        Error::Parse { file, message } => raise(py, "ParseError", (file, message)),
        Error::Io { path, source } => raise(py, "IoError", (path, source.to_string(), source.raw_os_error())),
        Error::Hdf5 { path, message } => raise(py, "Hdf5Error", (path, message)),
        Error::Numerical(message) => raise(py, "NumericalError", (message,)),
        e @ Error::Singular { .. } => raise(py, "NumericalError", (e.to_string(),)),
        e @ Error::Cancelled => PyKeyboardInterrupt::new_err(e.to_string()),
    })
}

/// An input error for a case field that does not exist (`beamflow.errors.FieldNotFound`,
/// also a `KeyError`).
pub fn field_not_found(file: &str, field: &str, reason: &str) -> PyErr {
    Python::attach(|py| raise(py, "FieldNotFound", (file, field, reason)))
}

/// A worker thread that panicked: a bug in beamflow, not bad input.
pub fn panicked(payload: Box<dyn std::any::Any + Send>) -> PyErr {
    let msg = payload
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "unknown panic".into());
    PyRuntimeError::new_err(format!("beamflow panicked (a bug, please report it): {msg}"))
}

/// `Result<T, beamflow::Error>` → `PyResult<T>`.
pub trait IntoPy<T> {
    fn py_err(self) -> PyResult<T>;
}

impl<T> IntoPy<T> for beamflow::Result<T> {
    fn py_err(self) -> PyResult<T> {
        self.map_err(to_py)
    }
}
