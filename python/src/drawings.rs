//! A run's figures as the descriptions the command line renders (titles, axes, series,
//! bars), for the Python package to draw again with matplotlib: the same plots, and the
//! numbers in them the library's.

use crate::convert::array;
use beamflow::report::figures::Drawing;
use beamflow::report::plot::{BarChart, LinePlot, MultiPanel, SeriesStyle};
use pyo3::prelude::*;
use pyo3::types::PyDict;

fn style(s: SeriesStyle) -> &'static str {
    match s {
        SeriesStyle::Line => "line",
        SeriesStyle::LineMarkers => "line_markers",
        SeriesStyle::Markers => "markers",
        SeriesStyle::Stems => "stems",
        SeriesStyle::Dashed => "dashed",
    }
}

fn lines<'py>(py: Python<'py>, p: &LinePlot) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("kind", "lines")?;
    d.set_item("title", &p.title)?;
    d.set_item("x_label", &p.x_label)?;
    d.set_item("y_label", &p.y_label)?;
    let series = p
        .series
        .iter()
        .map(|s| {
            let e = PyDict::new(py);
            e.set_item("label", &s.label)?;
            e.set_item("x", array(py, s.x.clone(), &[s.x.len()])?)?;
            e.set_item("y", array(py, s.y.clone(), &[s.y.len()])?)?;
            e.set_item("style", style(s.style))?;
            e.set_item("wrap", s.wrap)?;
            e.set_item("breaks", s.breaks.clone())?;
            Ok(e)
        })
        .collect::<PyResult<Vec<_>>>()?;
    d.set_item("series", series)?;
    d.set_item("x_range", p.x_range)?;
    d.set_item("y_range", p.y_range)?;
    d.set_item("log_x", p.log_x)?;
    d.set_item("log_y", p.log_y)?;
    d.set_item("symlog_y", p.symlog_y)?;
    d.set_item("stem_base", p.stem_base)?;
    d.set_item("notes", p.notes.clone())?;
    d.set_item("size", p.size)?;
    Ok(d)
}

fn panels<'py>(py: Python<'py>, m: &MultiPanel) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("kind", "panels")?;
    d.set_item("title", &m.title)?;
    d.set_item("panels", m.panels.iter().map(|p| lines(py, p)).collect::<PyResult<Vec<_>>>()?)?;
    d.set_item("columns", m.columns)?;
    d.set_item("size", m.size)?;
    Ok(d)
}

fn bars<'py>(py: Python<'py>, b: &BarChart) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("kind", "bars")?;
    d.set_item("title", &b.title)?;
    d.set_item("x_label", &b.x_label)?;
    d.set_item("y_label", &b.y_label)?;
    d.set_item("categories", b.categories.clone())?;
    let groups = b
        .groups
        .iter()
        .map(|(name, v)| Ok((name.clone(), array(py, v.clone(), &[v.len()])?)))
        .collect::<PyResult<Vec<_>>>()?;
    d.set_item("groups", groups)?;
    d.set_item("show_values", b.show_values)?;
    d.set_item("log_y", b.log_y)?;
    d.set_item("notes", b.notes.clone())?;
    d.set_item("size", b.size)?;
    Ok(d)
}

fn map<'py>(py: Python<'py>, h: &beamflow::report::plot::HeatMap) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("kind", "map")?;
    d.set_item("title", &h.title)?;
    d.set_item("x_label", &h.x_label)?;
    d.set_item("y_label", &h.y_label)?;
    d.set_item("z_label", &h.z_label)?;
    d.set_item("x", array(py, h.x.clone(), &[h.x.len()])?)?;
    d.set_item("y", array(py, h.y.clone(), &[h.y.len()])?)?;
    d.set_item("z", array(py, h.z.clone(), &[h.y.len(), h.x.len()])?)?;
    d.set_item("log_z", h.log_z)?;
    d.set_item("diverging", h.diverging)?;
    d.set_item("lines", h.lines.clone())?;
    d.set_item("marks", h.marks.iter().map(|m| (m.x, m.y, m.label.clone())).collect::<Vec<_>>())?;
    d.set_item("size", h.size)?;
    Ok(d)
}

/// A drawing as a dict: `kind` (`lines`, `panels`, `bars`, `map`, `maps`) and the
/// description's fields.
pub fn drawing<'py>(py: Python<'py>, d: &Drawing) -> PyResult<Bound<'py, PyDict>> {
    match d {
        Drawing::Lines(p) => lines(py, p),
        Drawing::Panels(m) => panels(py, m),
        Drawing::Bars(b) => bars(py, b),
        Drawing::Map(h) => map(py, h),
        Drawing::Maps(g) => {
            let d = PyDict::new(py);
            d.set_item("kind", "maps")?;
            d.set_item("title", &g.title)?;
            d.set_item("columns", g.columns)?;
            d.set_item("panels", g.panels.iter().map(|h| map(py, h)).collect::<PyResult<Vec<_>>>()?)?;
            Ok(d)
        }
    }
}
