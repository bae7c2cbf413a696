//! The extension module `beamflow._native`: the beamflow library itself, called from
//! Python. The Python package (`python/beamflow`) wraps it in the documented API; nothing
//! here computes physics of its own.

mod background;
mod case;
mod commands;
mod convert;
mod drawings;
mod errors;
mod remote;
mod results;
mod sweep;
mod system;

use pyo3::prelude::*;

/// The `beamflow` command installed with the package: the command line's own main on
/// `argv` (program name first), with the GIL released; returns its exit status.
#[pyfunction]
fn cli_main(py: Python<'_>, argv: Vec<std::ffi::OsString>) -> u8 {
    py.detach(|| beamflow::app::cli::main_with(argv))
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<case::NativeCase>()?;
    m.add_class::<results::NativeRun>()?;
    m.add_class::<results::NativeTree>()?;
    m.add_class::<remote::NativeEvaluator>()?;
    m.add_function(wrap_pyfunction!(results::read_results, m)?)?;
    m.add_function(wrap_pyfunction!(convert::toml_dumps, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::run_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::read_sweep_table, m)?)?;
    m.add_function(wrap_pyfunction!(cli_main, m)?)?;
    m.add_function(wrap_pyfunction!(commands::run_optimize, m)?)?;
    m.add_function(wrap_pyfunction!(commands::sweep_into, m)?)?;
    m.add_function(wrap_pyfunction!(commands::merge, m)?)?;
    m.add_function(wrap_pyfunction!(commands::paper, m)?)?;
    m.add_function(wrap_pyfunction!(commands::identify_dp, m)?)?;
    m.add_function(wrap_pyfunction!(commands::identify_bouc_wen, m)?)?;
    m.add_function(wrap_pyfunction!(commands::identify_modal, m)?)?;
    m.add_function(wrap_pyfunction!(commands::synth, m)?)?;
    Ok(())
}
