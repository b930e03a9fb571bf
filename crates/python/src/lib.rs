//! The Python extension module `subdiv._subdiv`, re-exported by the pure
//! Python package `subdiv` (`python/subdiv/__init__.py`, which adds the
//! docstrings built from the library, the exception classes and the type
//! stubs). Installed with `pip install ./crates/python` (maturin).
//!
//! Every function converts its NumPy/Python arguments while holding the GIL
//! (a C-contiguous float64 `(n, 3)` array is read in place, through
//! `bytemuck`), then runs the library's code without it
//! (`Python::detach`), so that other Python threads run meanwhile; errors
//! become Python exceptions (`errors`) and a panic of the library becomes
//! `subdiv.SubdivError`, never a crash.
//!
//! The work is the library's, through its public entry points only:
//! `Mesh::from_soup` (validation), `subdiv::io::{load_mesh, write_mesh}`,
//! `subdiv::subdivide`, the one dispatch `subdiv::interpolate` with
//! `MethodOptions` built as the command line builds them, and `Report`.
//! `subdiv.info`, `subdiv.batch` and `subdiv.dask` wrap the facade's
//! `subdiv::info` and `subdiv::batch` the same way (`batch`).

mod batch;
mod errors;
mod eval;
mod interpolation;
mod mesh;
mod options;

use pyo3::prelude::*;

/// The compiled core of the `subdiv` package; use `import subdiv`.
#[pymodule]
fn _subdiv(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<mesh::PyMesh>()?;
    m.add_class::<interpolation::PyInterpolation>()?;
    m.add_function(wrap_pyfunction!(interpolation::read, m)?)?;
    m.add_function(wrap_pyfunction!(interpolation::write, m)?)?;
    m.add_function(wrap_pyfunction!(interpolation::subdivide, m)?)?;
    m.add_function(wrap_pyfunction!(interpolation::interpolate, m)?)?;
    m.add_function(wrap_pyfunction!(interpolation::methods, m)?)?;
    m.add_function(wrap_pyfunction!(interpolation::schemes, m)?)?;
    m.add_function(wrap_pyfunction!(eval::evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(eval::sample, m)?)?;
    m.add_function(wrap_pyfunction!(eval::project, m)?)?;
    m.add_function(wrap_pyfunction!(eval::fit, m)?)?;
    m.add_function(wrap_pyfunction!(batch::info, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch, m)?)?;
    m.add_function(wrap_pyfunction!(batch::expand_inputs, m)?)?;
    m.add_function(wrap_pyfunction!(batch::run_one, m)?)?;
    m.add_function(wrap_pyfunction!(batch::check_command, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
