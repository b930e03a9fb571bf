//! `subdiv.interpolate`, its result `subdiv.Interpolation`, and `subdiv.subdivide`.

use crate::errors::{detached, Error, RaiseExt};
use crate::mesh::PyMesh;
use crate::options::{self, Kwargs};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyDict;
use std::sync::Arc;
use std::time::Instant;
use subdiv::budget::MemoryBudget;
use subdiv::prelude::*;

/// The result of :func:`subdiv.interpolate`: the control mesh whose limit surface (by the
/// method's plain scheme) passes through the input's vertices, the report, the surface.
#[pyclass(frozen, name = "Interpolation", module = "subdiv")]
pub struct PyInterpolation {
    result: Interpolant,
    /// The data (for the report's error and input summary).
    input: Arc<Mesh>,
    /// The input's file, when it was read from one.
    file: Option<String>,
    /// Milliseconds the call took.
    total_ms: f64,
    /// The report as JSON, computed at its first use (measuring the error costs a limit
    /// evaluation, which a caller who only wants the control points does not pay).
    report_json: PyOnceLock<String>,
    control: PyOnceLock<Py<PyMesh>>,
}

impl PyInterpolation {
    /// The report's JSON, as the command line computes it: the error measured on the control
    /// mesh (as written: OBJ keeps every f64), then the report.
    fn report_json(&self, py: Python<'_>) -> PyResult<&str> {
        let json = self.report_json.get_or_try_init(py, || {
            detached(py, || {
                let (input, result) = (&self.input, &self.result);
                let error = result.error(input.positions(), &result.interpolated, input.bbox_diagonal());
                let mut report = Report::new(input, result, error).with_control(&result.control);
                if let Some(file) = &self.file {
                    report = report.with_input_file(file.clone());
                }
                let report = report.with_total_ms(self.total_ms);
                serde_json::to_string(&report).map_err(|e| Error::Other(e.to_string()))
            })
        })?;
        Ok(json)
    }
}

#[pymethods]
impl PyInterpolation {
    /// The control mesh (:class:`Mesh`; for ``deng-ma``, whose scheme interpolates, the input).
    #[getter]
    fn control(&self, py: Python<'_>) -> PyResult<Py<PyMesh>> {
        let control = self.control.get_or_try_init(py, || Py::new(py, PyMesh::new(self.result.control.clone())))?;
        Ok(control.clone_ref(py))
    }

    /// The report, a dict: exactly the JSON of the command line's ``--report``
    /// (keys: docs/ARCHITECTURE.md, "Contract: report JSON").
    #[getter]
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py.import("json")?.call_method1("loads", (self.report_json(py)?,))
    }

    /// The measured error (from the control mesh by the plain scheme's limit rules, never
    /// the solver's residual): ``{"max_rel", "mean_rel", "max_abs", "mean_abs", "vertices"}``,
    /// relative values over the bounding-box diagonal d (``report["error"]``).
    #[getter]
    fn error<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.report(py)?.get_item("error")
    }

    /// The method's name (``report["method"]``).
    #[getter]
    fn method(&self) -> &'static str {
        self.result.method.name()
    }

    /// The surface (:class:`Mesh`): the control mesh refined ``levels`` times by its plain
    /// scheme with its tags and surface options, at limit positions (the command line's
    /// ``--surface``; write it with ``normals=True`` for its file).
    #[pyo3(signature = (levels = 3))]
    fn surface(&self, py: Python<'_>, levels: usize) -> PyResult<PyMesh> {
        detached(py, || {
            let control = &self.result.control;
            let budget = MemoryBudget::available();
            budget.check("surface", control.topology(), self.result.options().scheme, levels, 1, None)?;
            Ok(self.result.surface(levels)?)
        })
        .map(PyMesh::new)
    }

    fn __repr__(&self) -> String {
        let t = self.result.control.topology();
        format!(
            "Interpolation(method={:?}, control=Mesh({} vertices, {} faces))",
            self.result.method.name(),
            t.vertex_count(),
            t.face_count()
        )
    }
}

/// The optional `progress` callable of `interpolate` as the solver's observer: called as
/// `progress(iteration, relative_residual)` after each solver iteration, from the thread that
/// runs the solve, with the GIL taken for the call only. An exception it raises cannot stop
/// the solve: it is reported as unraisable (`sys.unraisablehook`) and the solve goes on.
fn progress_observer(progress: Option<Py<PyAny>>) -> subdiv::solve::IterationObserver {
    match progress {
        None => subdiv::solve::IterationObserver::default(),
        Some(callback) => subdiv::solve::IterationObserver::new(move |iteration, residual| {
            Python::attach(|py| {
                if let Err(e) = callback.call1(py, (iteration, residual)) {
                    e.write_unraisable(py, Some(callback.bind(py)));
                }
            })
        }),
    }
}

/// `interpolate` (see the Python wrapper's docstring, built from `Method::ALL`).
#[pyfunction]
#[pyo3(signature = (mesh, method = "cheng", tol = 1e-6, solver = "auto", max_iter = None, *, progress = None, **options))]
#[allow(clippy::too_many_arguments)]
pub fn interpolate(
    py: Python<'_>,
    mesh: &PyMesh,
    method: &str,
    tol: f64,
    solver: &str,
    max_iter: Option<usize>,
    progress: Option<Py<PyAny>>,
    options: Option<Bound<'_, PyDict>>,
) -> PyResult<PyInterpolation> {
    if let Some(callback) = &progress {
        if !callback.bind(py).is_callable() {
            return Err(pyo3::exceptions::PyTypeError::new_err("interpolate(): progress must be callable or None"));
        }
    }
    let total = Instant::now();
    let options = options.map(|d| d.copy()).transpose()?;
    let mut kw = Kwargs::new("interpolate", options);
    let options = options::interpolate(method, tol, solver, max_iter, &mut kw)?;
    let options = options.raise(py)?;
    let input = Arc::clone(&mesh.inner);
    // Messages name the mesh's file as the command line's do (or `mesh` for one made in memory).
    let name = std::path::PathBuf::from(mesh.path.as_deref().unwrap_or("mesh"));
    let result =
        detached(py, || Ok(subdiv::job::interpolate_mesh(&name, &input, &options, progress_observer(progress))?))?;
    let total_ms = total.elapsed().as_secs_f64() * 1e3;
    for w in &result.warnings {
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        PyErr::warn(py, &category, &std::ffi::CString::new(w.as_str()).unwrap_or_default(), 1)?;
    }
    Ok(PyInterpolation {
        result,
        input,
        file: mesh.path.clone(),
        total_ms,
        report_json: PyOnceLock::new(),
        control: PyOnceLock::new(),
    })
}

/// `subdivide` (docstring in the Python wrapper).
#[pyfunction]
#[pyo3(signature = (mesh, scheme = "catmull-clark", levels = 1, limit = false, **options))]
pub fn subdivide(
    py: Python<'_>,
    mesh: &PyMesh,
    scheme: &str,
    levels: usize,
    limit: bool,
    options: Option<Bound<'_, PyDict>>,
) -> PyResult<PyMesh> {
    let options = options.map(|d| d.copy()).transpose()?;
    let mut kw = Kwargs::new("subdivide", options);
    let options = options::subdivide(scheme, levels, limit, &mut kw)?;
    let options = options.raise(py)?;
    let input = Arc::clone(&mesh.inner);
    let name = std::path::PathBuf::from(mesh.path.as_deref().unwrap_or("mesh"));
    // As the command line: texture coordinates the scheme cannot refine (Doo-Sabin with seams or
    // tags) are dropped with a warning, the positions are what was asked for.
    let (refined, dropped_uvs) = detached(py, move || {
        let mesh = Mesh::clone(&input);
        let (_, refined, dropped) = subdiv::job::subdivide_mesh(&name, mesh, &options, None, &mut subdiv::job::Silent)?;
        Ok((refined, dropped))
    })?;
    if let Some(message) = dropped_uvs {
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        PyErr::warn(py, &category, &std::ffi::CString::new(message).unwrap_or_default(), 1)?;
    }
    Ok(PyMesh::new(refined))
}

/// `read(path)`: a mesh file, validated (format from the extension).
#[pyfunction]
pub fn read(py: Python<'_>, path: std::path::PathBuf) -> PyResult<PyMesh> {
    let shown = path.display().to_string();
    let (mesh, warnings) = detached(py, move || Ok(subdiv::io::load_mesh_with_warnings(&path)?))?;
    for w in warnings {
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        PyErr::warn(py, &category, &std::ffi::CString::new(w.to_string()).unwrap_or_default(), 1)?;
    }
    Ok(PyMesh { inner: Arc::new(mesh), path: Some(shown) })
}

/// `write(mesh, path, normals=False)`: atomically, format from the extension, with the
/// mesh's tags and texture coordinates where the format has a place for them.
#[pyfunction]
#[pyo3(signature = (mesh, path, normals = false))]
pub fn write(py: Python<'_>, mesh: &PyMesh, path: std::path::PathBuf, normals: bool) -> PyResult<()> {
    let mesh = Arc::clone(&mesh.inner);
    detached(py, move || Ok(write_mesh(&path, &mesh, &WriteOptions::default().with_normals(normals))?))
}

/// `[(name, summary)]` of every subdivision scheme (the scheme table, `Scheme::ALL`).
#[pyfunction]
pub fn schemes() -> Vec<(&'static str, &'static str)> {
    subdiv::Scheme::ALL.iter().map(|s| (s.name(), s.summary())).collect()
}

/// `[(name, summary)]` of every interpolation method (`Method::ALL`), for the docstring.
#[pyfunction]
pub fn methods() -> Vec<(&'static str, &'static str)> {
    Method::ALL.iter().map(|m| (m.name(), m.summary())).collect()
}
