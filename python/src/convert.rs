//! Values across the boundary: TOML values ↔ Python objects, and results trees → nested
//! Python dicts of numpy arrays (the `beamflow` package wraps them in `Results`).

use beamflow::io::tree::{Attr, Data, Group};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyList, PyString, PyTuple};
use pyo3::IntoPyObjectExt;

/// A Python value as TOML: bool, int, float (numpy scalars too), str, path-like, mappings,
/// and sequences (lists, tuples, numpy arrays).
pub fn to_toml(v: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract()?));
    }
    if v.hasattr("__fspath__")? {
        let os = v.py().import("os")?;
        return Ok(toml::Value::String(os.call_method1("fspath", (v,))?.extract()?));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut t = toml::map::Map::new();
        for (k, x) in d.iter() {
            let key: String =
                k.extract().map_err(|_| PyTypeError::new_err(format!("table keys must be str, got {k}")))?;
            t.insert(key, to_toml(&x)?);
        }
        return Ok(toml::Value::Table(t));
    }
    if v.hasattr("keys")? && v.hasattr("__getitem__")? {
        let d = PyDict::new(v.py());
        d.call_method1("update", (v,))?;
        return to_toml(d.as_any());
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        return v.try_iter()?.map(|x| to_toml(&x?)).collect::<PyResult<Vec<_>>>().map(toml::Value::Array);
    }
    if !v.is_instance_of::<PyFloat>() {
        if let Ok(i) = v.extract::<i64>() {
            return Ok(toml::Value::Integer(i));
        }
    }
    if let Ok(x) = v.extract::<f64>() {
        return Ok(toml::Value::Float(x));
    }
    if v.hasattr("tolist")? {
        return to_toml(&v.call_method0("tolist")?);
    }
    Err(PyTypeError::new_err(format!(
        "cannot put a {} into a case (use bool, int, float, str, list or dict)",
        v.get_type().name()?
    )))
}

/// A TOML value as a plain Python object (dates become their text).
pub fn from_toml<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => s.into_bound_py_any(py)?,
        toml::Value::Integer(i) => i.into_bound_py_any(py)?,
        toml::Value::Float(x) => x.into_bound_py_any(py)?,
        toml::Value::Boolean(b) => b.into_bound_py_any(py)?,
        toml::Value::Datetime(d) => d.to_string().into_bound_py_any(py)?,
        toml::Value::Array(a) => {
            PyList::new(py, a.iter().map(|x| from_toml(py, x)).collect::<PyResult<Vec<_>>>()?)?.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, from_toml(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// A numpy array of `shape` holding `data` (row-major).
pub fn array<'py, T: numpy::Element>(py: Python<'py>, data: Vec<T>, shape: &[usize]) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, data).reshape(shape.to_vec())?.into_any())
}

/// A results tree as nested dicts: `{"attrs": {…}, "groups": {name: …}, "datasets": {name:
/// {"data": ndarray | str | list[str], "unit": str, "description": str}}}`.
pub fn tree<'py>(py: Python<'py>, g: &Group) -> PyResult<Bound<'py, PyDict>> {
    let attrs = PyDict::new(py);
    for (k, a) in &g.attrs {
        match a {
            Attr::Str(s) => attrs.set_item(k, s)?,
            Attr::F64(x) => attrs.set_item(k, x)?,
            Attr::I64(i) => attrs.set_item(k, i)?,
        }
    }
    let datasets = PyDict::new(py);
    for (k, d) in &g.datasets {
        let data = match &d.data {
            Data::F64(v) => array(py, v.clone(), &d.shape)?,
            Data::C64(v) => array(py, v.clone(), &d.shape)?,
            Data::I64(v) => array(py, v.clone(), &d.shape)?,
            Data::Str(s) => s.into_bound_py_any(py)?,
            Data::StrList(v) => PyList::new(py, v)?.into_any(),
        };
        let entry = PyDict::new(py);
        entry.set_item("data", data)?;
        entry.set_item("unit", &d.unit)?;
        entry.set_item("description", &d.description)?;
        datasets.set_item(k, entry)?;
    }
    let groups = PyDict::new(py);
    for (k, sub) in &g.groups {
        groups.set_item(k, tree(py, sub)?)?;
    }
    let out = PyDict::new(py);
    out.set_item("attrs", attrs)?;
    out.set_item("groups", groups)?;
    out.set_item("datasets", datasets)?;
    Ok(out)
}

/// A dict as TOML text (sweep files given as dicts).
#[pyfunction]
pub fn toml_dumps(value: &Bound<'_, PyAny>) -> PyResult<String> {
    let v = to_toml(value)?;
    if !v.is_table() {
        return Err(PyTypeError::new_err("TOML text is written from a dict"));
    }
    toml::to_string(&v).map_err(|e| PyTypeError::new_err(format!("cannot write as TOML: {e}")))
}
