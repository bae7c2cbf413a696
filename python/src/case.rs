//! `beamflow.Case`'s engine: a case file held as its TOML document, read and changed by
//! the dotted paths of sweeps (`actuator[0].x_e`), checked in full after every change.

use crate::background;
use crate::convert::{from_toml, to_toml};
use crate::errors::{field_not_found, IntoPy};
use crate::results::NativeRun;
use beamflow::case::{Case, LoadedCase};
use beamflow::error::Error;
use beamflow::sweep::spec::{get_path, parse_path, set_path, Segment};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// A case: its TOML document, the name messages give it, and the directory its relative
/// paths (voltage series, meshes) resolve against. Always valid: every change is checked.
#[pyclass(module = "beamflow._native")]
#[derive(Clone, Debug)]
pub struct NativeCase {
    doc: toml::Value,
    file: String,
    dir: PathBuf,
    /// The text as read, while the document is unchanged (results embed it verbatim, as the
    /// command line does).
    text: Option<String>,
}

/// Refuses what `beamflow check` refuses once the structure is built (an imported model's
/// unknown node, a point off a plate, a frame's feet), with its messages. The budget is
/// the machine's default; `check()` and `run()` hold the analyses to the one they are given.
fn built(lc: &LoadedCase) -> beamflow::Result<()> {
    beamflow::analysis::plan::built_within(lc, &beamflow::analysis::budget::Budget::default()).map(drop)
}

impl NativeCase {
    fn parse(text: &str, file: &str, dir: PathBuf) -> beamflow::Result<NativeCase> {
        built(&LoadedCase::from_str(text, file, dir.clone())?)?;
        let doc = toml::from_str(text)
            .map_err(|e| Error::Parse { file: file.to_string(), message: e.to_string().trim_end().to_string() })?;
        Ok(NativeCase { doc, file: file.to_string(), dir, text: Some(text.to_string()) })
    }

    /// The case as the library takes it: deserialised and validated.
    pub fn loaded(&self) -> beamflow::Result<LoadedCase> {
        let case = self.case()?;
        case.validate(&self.file)?;
        Ok(LoadedCase { case, file: self.file.clone(), dir: self.dir.clone(), text: self.to_toml()? })
    }

    fn case(&self) -> beamflow::Result<Case> {
        let toml::Value::Table(doc) = &self.doc else {
            return Err(Error::input(&self.file, "<case>", "a case is a table (a dict)"));
        };
        beamflow::toml_input::from_value(doc.clone(), &self.file, beamflow::toml_input::Kind::Case)
    }

    fn segments(&self, path: &str) -> beamflow::Result<Vec<Segment>> {
        parse_path(path).map_err(|r| Error::input(&self.file, path, r))
    }

    /// Sets the values on a copy, checks it, and keeps it if it is valid. A float with an
    /// integral value is written as an integer where the field is one (`beam.mesh.elements`).
    fn apply(&mut self, changes: &[(String, toml::Value)]) -> beamflow::Result<()> {
        let mut next = self.clone();
        next.text = None;
        for (path, value) in changes {
            let seg = self.segments(path)?;
            // The sweep's messages speak of its base case; here the case is the one at hand.
            set_path(&mut next.doc, &seg, value.clone())
                .map_err(|r| Error::input(&self.file, path, r.replace("the base case", "the case")))?;
            if let toml::Value::Float(x) = value {
                if x.fract() == 0.0 && x.abs() < 9e15 && next.case().is_err() {
                    let mut as_int = next.doc.clone();
                    set_path(&mut as_int, &seg, toml::Value::Integer(*x as i64)).expect("the path was just set");
                    if toml::Value::try_into::<Case>(as_int.clone()).is_ok() {
                        next.doc = as_int;
                    }
                }
            }
        }
        let field = changes.iter().map(|(p, _)| p.as_str()).collect::<Vec<_>>().join(", ");
        next.loaded().and_then(|lc| built(&lc)).map_err(|e| match e {
            Error::Parse { file, message } => Error::input(file, &field, message),
            e => e,
        })?;
        *self = next;
        Ok(())
    }

    fn to_toml(&self) -> beamflow::Result<String> {
        match &self.text {
            Some(t) => Ok(t.clone()),
            None => toml::to_string(&self.doc)
                .map_err(|e| Error::input(&self.file, "<case>", format!("cannot write as TOML: {e}"))),
        }
    }
}

#[pymethods]
impl NativeCase {
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Self> {
        let text = beamflow::input_file::read_text(&path).py_err()?;
        let dir = path.parent().map(PathBuf::from).unwrap_or_default();
        NativeCase::parse(&text, &path.display().to_string(), dir).py_err()
    }

    #[staticmethod]
    fn from_toml(text: &str, name: &str, dir: PathBuf) -> PyResult<Self> {
        NativeCase::parse(text, name, dir).py_err()
    }

    #[staticmethod]
    fn from_value(value: &Bound<'_, PyAny>, name: &str, dir: PathBuf) -> PyResult<Self> {
        let doc = to_toml(value, name, "")?;
        if !doc.is_table() {
            return Err(Error::input(name, "<case>", "a case is a table (a dict)")).py_err();
        }
        let c = NativeCase { doc, file: name.to_string(), dir, text: None };
        built(&c.loaded().py_err()?).py_err()?;
        Ok(c)
    }

    #[getter]
    fn file(&self) -> &str {
        &self.file
    }

    #[getter]
    fn dir(&self) -> PathBuf {
        self.dir.clone()
    }

    /// The value at `path`: as written in the case, else the default the case gets.
    fn get<'py>(&self, py: Python<'py>, path: &str) -> PyResult<Bound<'py, PyAny>> {
        let seg = self.segments(path).py_err()?;
        if let Some(v) = get_path(&self.doc, &seg) {
            return from_toml(py, v);
        }
        let full = toml::Value::try_from(self.case().py_err()?)
            .map_err(|e| Error::input(&self.file, path, format!("cannot list the case's defaults: {e}")))
            .py_err()?;
        match get_path(&full, &seg) {
            Some(v) => from_toml(py, v),
            None => Err(field_not_found(
                &self.file,
                path,
                &format!("the case does not set `{path}` and it has no default (or it is no field of a case)"),
            )),
        }
    }

    fn set(&mut self, path: String, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = to_toml(value, &self.file, &path)?;
        self.apply(&[(path, v)]).py_err()
    }

    fn update(&mut self, items: Vec<(String, Bound<'_, PyAny>)>) -> PyResult<()> {
        let changes =
            items.iter().map(|(p, v)| Ok((p.clone(), to_toml(v, &self.file, p)?))).collect::<PyResult<Vec<_>>>()?;
        self.apply(&changes).py_err()
    }

    #[pyo3(name = "to_toml")]
    fn text(&self) -> PyResult<String> {
        self.to_toml().py_err()
    }

    /// The document as written (`full`: every field, defaults filled in).
    fn to_dict<'py>(&self, py: Python<'py>, full: bool) -> PyResult<Bound<'py, PyAny>> {
        if !full {
            return from_toml(py, &self.doc);
        }
        let v = toml::Value::try_from(self.case().py_err()?)
            .map_err(|e| Error::input(&self.file, "<case>", format!("cannot list the case's defaults: {e}")))
            .py_err()?;
        from_toml(py, &v)
    }

    fn copy(&self) -> Self {
        self.clone()
    }

    /// Builds the model and assembles the system, and holds every analysis to the budget
    /// (`max_memory`, `max_steps`; default: the machine's), as `beamflow check` does.
    #[pyo3(signature = (max_memory=None, max_steps=None))]
    fn check<'py>(
        &self,
        py: Python<'py>,
        max_memory: Option<String>,
        max_steps: Option<String>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let lc = self.loaded().py_err()?;
        let budget = crate::commands::budget(max_memory, max_steps)?;
        let (built, sys, _) = background::run(py, move || beamflow::app::runner::planned(&lc, &budget))?;
        let d = PyDict::new(py);
        d.set_item("elements", built.beam().map_or(0, |b| b.mesh.elements.len()))?;
        d.set_item("dofs", sys.n())?;
        d.set_item("actuators", built.actuators.iter().map(|a| a.name().to_string()).collect::<Vec<_>>())?;
        d.set_item(
            "links",
            sys.links
                .iter()
                .map(|l| beamflow::actuator::link_id(built.actuators[l.actuator].name(), &l.name))
                .collect::<Vec<_>>(),
        )?;
        d.set_item("modal_damping", built.modal_ratios().is_some())?;
        Ok(d)
    }

    /// Runs every analysis of the case within the budget (`max_memory`, `max_steps`), GIL
    /// released; Ctrl-C stops the solve and raises at once. `progress` is called with each
    /// task's progress.
    #[pyo3(signature = (progress=None, max_memory=None, max_steps=None))]
    fn run(
        &self,
        py: Python<'_>,
        progress: Option<Bound<'_, PyAny>>,
        max_memory: Option<String>,
        max_steps: Option<String>,
    ) -> PyResult<NativeRun> {
        let lc = self.loaded().py_err()?;
        let budget = crate::commands::budget(max_memory, max_steps)?;
        NativeRun::compute(py, lc, budget, progress.as_ref())
    }

    fn system<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::system::system(py, self.loaded().py_err()?)
    }

    fn modes<'py>(&self, py: Python<'py>, count: usize) -> PyResult<Bound<'py, PyDict>> {
        crate::system::bare_modes(py, self.loaded().py_err()?, count)
    }

    fn coupled_modes<'py>(&self, py: Python<'py>, count: usize) -> PyResult<Bound<'py, PyDict>> {
        crate::system::coupled_modes(py, self.loaded().py_err()?, count)
    }
}
