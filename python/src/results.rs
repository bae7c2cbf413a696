//! A case run's results: the in-memory tree of the results layout (what `Results` shows),
//! kept with the run itself for the figures and the headline summary.

use crate::background::{self, OnInterrupt};
use crate::convert::array;
use crate::errors::IntoPy;
use beamflow::analysis::budget::Budget;
use beamflow::analysis::case_run::CaseRun;
use beamflow::app::case_inputs;
use beamflow::app::runner::run_case_within;
use beamflow::case::LoadedCase;
use beamflow::io::csv::Cells;
use beamflow::io::hdf5::{ResultsFile, ResultsReader};
use beamflow::io::paths::{refuse_input, Input};
use beamflow::io::tree::{Group, TreeSink};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;
use std::sync::Arc;

/// A results tree (of a run, or read from a file), with the files it came from: the case
/// and its data files, or the results file it was read from. Writing over one of them is
/// refused, as the command line refuses an output that names an input.
#[pyclass(module = "beamflow._native", frozen)]
pub struct NativeTree {
    tree: Arc<Group>,
    inputs: Arc<Vec<Input>>,
}

#[pymethods]
impl NativeTree {
    /// The tree as nested dicts of numpy arrays (see `convert::tree`).
    fn to_python<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::convert::tree(py, &self.tree)
    }

    /// The tidy tables of `beamflow run --csv`, by the name of their file
    /// (`<analysis group>_<table>`): each a list of `(header, column)`, the header with its
    /// unit in brackets, the column a numpy array (a list of text for a text column).
    fn tables<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        for (name, t) in beamflow::io::results_csv::tables(&self.tree) {
            let cols = PyList::empty(py);
            for c in &t.columns {
                let n = c.cells.len();
                let data = match &c.cells {
                    Cells::Num(v) => array(py, v.clone(), &[n])?,
                    Cells::Int(v) => array(py, v.clone(), &[n])?,
                    Cells::Text(v) => PyList::new(py, v)?.into_any(),
                };
                cols.append((c.header(), data))?;
            }
            out.set_item(name, cols)?;
        }
        Ok(out)
    }

    /// Writes the tree as an HDF5 results file (atomically), unless `path` is one of the
    /// files the results came from.
    fn write_hdf5(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        refuse_input("path", &path, &self.inputs).py_err()?;
        let tree = self.tree.clone();
        background::run(py, move || {
            let f = ResultsFile::create(&path)?;
            tree.write_to(&f.root_group())?;
            f.finish()
        })
    }
}

/// Reads an HDF5 file written by beamflow (a case run or a sweep table) into a tree.
#[pyfunction]
pub fn read_results(py: Python<'_>, path: PathBuf) -> PyResult<NativeTree> {
    let inputs = vec![Input::new(&path, "the results file these results were read from")];
    let tree = background::run(py, move || ResultsReader::open(&path)?.read_tree())?;
    Ok(NativeTree { tree: Arc::new(tree), inputs: Arc::new(inputs) })
}

/// A finished case run.
#[pyclass(module = "beamflow._native", frozen)]
pub struct NativeRun {
    lc: Arc<LoadedCase>,
    run: Arc<CaseRun>,
    tree: Arc<Group>,
    inputs: Arc<Vec<Input>>,
}

impl NativeRun {
    /// Runs the case and lays its results out in memory, both on a worker thread;
    /// `progress` is called with the library's tasks as they go (periods, harmonics).
    pub fn compute(
        py: Python<'_>,
        lc: LoadedCase,
        budget: Budget,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<NativeRun> {
        let ((lc, run, tree), _) = background::watched(py, progress, OnInterrupt::Drop, move |_| {
            let run = run_case_within(&lc, &budget)?;
            let sink = TreeSink::new();
            beamflow::io::results::write_into(&sink, &lc, &run)?;
            let tree = sink.tree();
            Ok((lc, run, tree))
        })?;
        let inputs = case_inputs(&lc);
        Ok(NativeRun { lc: Arc::new(lc), run: Arc::new(run), tree: Arc::new(tree), inputs: Arc::new(inputs) })
    }
}

#[pymethods]
impl NativeRun {
    fn tree(&self) -> NativeTree {
        NativeTree { tree: self.tree.clone(), inputs: self.inputs.clone() }
    }

    /// The headline numbers, as the command line's `<case>.json`.
    fn summary_json(&self) -> String {
        serde_json::to_string(&beamflow::io::summary::summary(&self.lc, &self.run)).expect("plain data serialises")
    }

    /// The command line's figures of this run, as PNG and SVG files in `dir`.
    fn write_figures(&self, py: Python<'_>, dir: PathBuf, stem: String) -> PyResult<Vec<PathBuf>> {
        let run = self.run.clone();
        background::run(py, move || {
            std::fs::create_dir_all(&dir).map_err(|e| beamflow::Error::io(&dir, e))?;
            beamflow::report::figures::plot_run(&dir, &stem, &run)
        })
    }

    /// The figures `write_figures` draws, as `[(name, description)]` (see `drawings`).
    fn drawings<'py>(&self, py: Python<'py>) -> PyResult<Vec<(String, Bound<'py, PyDict>)>> {
        let run = self.run.clone();
        let kept = background::run(py, move || beamflow::report::figures::run_drawings(&run))?;
        kept.iter().map(|(name, d)| Ok((name.clone(), crate::drawings::drawing(py, d)?))).collect()
    }

    /// The case file the run came from, as messages name it.
    #[getter]
    fn case_file(&self) -> String {
        self.lc.file.clone()
    }
}
