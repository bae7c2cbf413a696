//! Values across the boundary: TOML values ↔ Python objects, and results trees → nested
//! Python dicts of numpy arrays (the `beamflow` package wraps them in `Results`).

use beamflow::io::tree::{Attr, Data, Group};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyList, PyString, PyTuple};
use pyo3::IntoPyObjectExt;

/// How deep a value may nest. A case's tables go five levels down; a value nested far
/// deeper is a mistake (or contains itself), and converting it by recursion would exhaust
/// the stack and take the interpreter down.
pub const MAX_DEPTH: usize = 64;

/// A Python value as TOML: bool, int, float (numpy scalars too), str, path-like, mappings,
/// and sequences (lists, tuples, numpy arrays). `file` and `field` name the value in
/// messages; a value nested deeper than [`MAX_DEPTH`] or containing itself is an
/// `InputError` naming the dotted path where that happens.
pub fn to_toml(v: &Bound<'_, PyAny>, file: &str, field: &str) -> PyResult<toml::Value> {
    Walk { file, path: field.to_string(), open: Vec::new() }.value(v)
}

/// A depth-first conversion that knows where it is.
struct Walk<'a> {
    file: &'a str,
    /// The dotted path of the value being converted (`actuator[0].voltage`).
    path: String,
    /// The containers on the way down (their addresses), to tell a cycle from depth.
    open: Vec<usize>,
}

impl Walk<'_> {
    fn value(&mut self, v: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
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
            self.enter(v)?;
            let mut t = toml::map::Map::new();
            for (k, x) in d.iter() {
                let key: String =
                    k.extract().map_err(|_| self.type_error(format!("table keys must be str, got {k}")))?;
                let value = self.child(&format!(".{key}"), &x)?;
                t.insert(key, value);
            }
            self.open.pop();
            return Ok(toml::Value::Table(t));
        }
        if v.hasattr("keys")? && v.hasattr("__getitem__")? {
            let d = PyDict::new(v.py());
            d.call_method1("update", (v,))?;
            return self.value(d.as_any());
        }
        if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
            self.enter(v)?;
            let mut items = Vec::new();
            for (i, x) in v.try_iter()?.enumerate() {
                items.push(self.child(&format!("[{i}]"), &x?)?);
            }
            self.open.pop();
            return Ok(toml::Value::Array(items));
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
            return self.value(&v.call_method0("tolist")?);
        }
        Err(self.type_error(format!(
            "cannot put a {} into a case (use bool, int, float, str, list or dict)",
            v.get_type().name()?
        )))
    }

    /// Converts `v`, found at `self.path` + `segment`.
    fn child(&mut self, segment: &str, v: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
        let len = self.path.len();
        self.path.push_str(segment.strip_prefix('.').filter(|_| len == 0).unwrap_or(segment));
        let out = self.value(v);
        self.path.truncate(len);
        out
    }

    /// Steps into the container `v`, refusing a cycle or a nesting beyond [`MAX_DEPTH`].
    fn enter(&mut self, v: &Bound<'_, PyAny>) -> PyResult<()> {
        let id = v.as_ptr() as usize;
        let reason = if self.open.contains(&id) {
            "the value contains itself (a dict or list that holds a reference to one of its own containers)".to_string()
        } else if self.open.len() >= MAX_DEPTH {
            format!("the value nests more than {MAX_DEPTH} levels deep; a case's tables nest a few levels at most")
        } else {
            self.open.push(id);
            return Ok(());
        };
        Err(crate::errors::to_py(beamflow::Error::input(self.file, self.field(), reason)))
    }

    fn field(&self) -> &str {
        if self.path.is_empty() {
            "<case>"
        } else {
            &self.path
        }
    }

    fn type_error(&self, reason: String) -> PyErr {
        PyTypeError::new_err(format!("{}: field `{}`: {reason}", self.file, self.field()))
    }
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
    let v = to_toml(value, "<dict>", "")?;
    if !v.is_table() {
        return Err(PyTypeError::new_err("TOML text is written from a dict"));
    }
    toml::to_string(&v).map_err(|e| PyTypeError::new_err(format!("cannot write as TOML: {e}")))
}
