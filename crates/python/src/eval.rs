//! The limit surface between the data points: `evaluate`, `sample`, `project`, `fit`
//! (the library's `subdiv::eval`), NumPy in and out, the GIL released while they run.

use crate::errors::{detached, input, Error, RaiseExt};
use crate::mesh::{array2, with_positions, PyMesh};
use crate::options::{self, Kwargs};
use numpy::{AllowTypeChange, PyArray1, PyArrayLike2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use subdiv::budget::MemoryBudget;
use subdiv::eval::{
    fit as fit_surface, per_domain_count, project_points, sample_surface, EvalError, FitLoss, FitMethod, FitOptions,
    FitTarget, LimitSurface, ProjectOptions, Projection, Sampling, SurfaceParam, SurfaceSample, SAMPLE_BYTES,
};
use subdiv::mesh::DVec3;
use subdiv::Options;

impl From<EvalError> for Error {
    fn from(e: EvalError) -> Self {
        // Bad parameters, unsupported meshes and options: the command line's exit 2.
        Error::Input(e.to_string())
    }
}

/// The surface options of `scheme` and the keyword arguments (as `subdivide` takes them), the
/// mesh's own option tags (`file`) where the keywords give none.
fn surface_options(
    py: Python<'_>,
    function: &'static str,
    scheme: &str,
    kwargs: Option<Bound<'_, PyDict>>,
    file: subdiv::mesh::FileOptions,
) -> PyResult<Options> {
    let mut kw = Kwargs::new(function, kwargs.map(|d| d.copy()).transpose()?);
    let plan = options::subdivide(scheme, 1, false, &mut kw)?;
    let plan = plan.raise(py)?;
    if plan.triangulate {
        return Err(
            input(format!("{function}: triangulate does not apply (triangulate the mesh first)")).into_pyerr(py)
        );
    }
    Ok(plan.options(file))
}

/// `(n, 3)` rows `[face, u, v]` or `(n, 4)` rows `[face, corner, u, v]` as parameters.
fn parameters(params: &Bound<'_, PyAny>) -> Result<Vec<SurfaceParam>, Error> {
    let array: PyArrayLike2<'_, f64, AllowTypeChange> = params
        .extract()
        .map_err(|_| input("params must be an (n, 3) array of [face, u, v] or (n, 4) of [face, corner, u, v]"))?;
    let view = array.as_array();
    let cols = view.ncols();
    if cols != 3 && cols != 4 {
        return Err(input(format!("params must have 3 or 4 columns, got {cols}")));
    }
    let id = |x: f64, what: &str, row: usize| -> Result<u32, Error> {
        (x >= 0.0 && x.fract() == 0.0 && x <= f64::from(u32::MAX))
            .then_some(x as u32)
            .ok_or_else(|| input(format!("params row {row}: {what} {x} is not a non-negative integer")))
    };
    view.rows()
        .into_iter()
        .enumerate()
        .map(|(row, r)| {
            let face = id(r[0], "face", row)?;
            let corner = if cols == 4 { id(r[1], "corner", row)? } else { 0 };
            Ok(SurfaceParam::new(face, corner, r[cols - 2], r[cols - 1]))
        })
        .collect()
}

/// A result beyond the range of `f64` (the command line's exit 3): `subdiv.NotConvergedError`.
fn not_representable(what: String) -> Error {
    Error::NotConverged {
        message: format!("{what}: the result is not representable in f64 (beyond ±1.8e308); nothing returned"),
        iterations: None,
        residual: None,
    }
}

fn points(values: &[DVec3]) -> Vec<f64> {
    values.iter().flat_map(|p| p.to_array()).collect()
}

/// `evaluate` (docstring in the Python wrapper).
#[pyfunction]
#[pyo3(signature = (mesh, params, scheme = "catmull-clark", **options))]
pub fn evaluate<'py>(
    py: Python<'py>,
    mesh: &PyMesh,
    params: &Bound<'py, PyAny>,
    scheme: &str,
    options: Option<Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let surface_options = surface_options(py, "evaluate", scheme, options, mesh.inner.tags().options())?;
    let params = parameters(params).raise(py)?;
    let input_mesh = mesh.inner.clone();
    let samples = detached(py, move || {
        MemoryBudget::available().check_items(
            "evaluate",
            u64::try_from(params.len()).ok(),
            "parameters",
            EVALUATE_BYTES,
            "evaluate fewer parameters at a time",
        )?;
        let surface = LimitSurface::new(&input_mesh, &surface_options)?;
        // On the normalised positions, mapped back (the numeric rule).
        let samples = surface
            .evaluate_all(input_mesh.positions(), &params)
            .map_err(|(row, e)| input(format!("params row {row}: {e}")))?;
        let finite = |s: &subdiv::eval::LimitSample| [s.position, s.normal, s.du, s.dv].iter().all(|p| p.is_finite());
        if let Some(row) = samples.iter().position(|s| !finite(s)) {
            return Err(not_representable(format!("params row {row}")));
        }
        Ok(samples)
    })?;
    let n = samples.len();
    let out = PyDict::new(py);
    let column = |f: &dyn Fn(&subdiv::eval::LimitSample) -> DVec3| points(&samples.iter().map(f).collect::<Vec<_>>());
    out.set_item("position", array2(py, column(&|s| s.position), n, 3))?;
    out.set_item("normal", array2(py, column(&|s| s.normal), n, 3))?;
    out.set_item("du", array2(py, column(&|s| s.du), n, 3))?;
    out.set_item("dv", array2(py, column(&|s| s.dv), n, 3))?;
    Ok(out)
}

/// Parameters, positions and normals of samples or projections, as a dict of arrays.
fn located<'py>(
    py: Python<'py>,
    params: impl Iterator<Item = SurfaceParam> + Clone,
    position: Vec<DVec3>,
    normal: Vec<DVec3>,
) -> PyResult<Bound<'py, PyDict>> {
    let n = position.len();
    let out = PyDict::new(py);
    out.set_item("face", PyArray1::from_vec(py, params.clone().map(|p| i64::from(p.face)).collect()))?;
    out.set_item("corner", PyArray1::from_vec(py, params.clone().map(|p| i64::from(p.corner)).collect()))?;
    out.set_item("u", PyArray1::from_vec(py, params.clone().map(|p| p.u).collect()))?;
    out.set_item("v", PyArray1::from_vec(py, params.map(|p| p.v).collect()))?;
    out.set_item("position", array2(py, points(&position), n, 3))?;
    out.set_item("normal", array2(py, points(&normal), n, 3))?;
    Ok(out)
}

/// Bytes `sample` holds per sample: the library's, the positions and normals, their flat copies
/// and the six NumPy arrays.
const PY_SAMPLE_BYTES: u64 = SAMPLE_BYTES + 48 + 48 + 80;

/// Bytes `evaluate` holds per parameter: the parameter, the sample and the four flat copies and
/// arrays of it.
const EVALUATE_BYTES: u64 = 24 + 96 + 4 * 48;

/// `sample` (docstring in the Python wrapper).
#[pyfunction]
#[pyo3(signature = (mesh, scheme = "catmull-clark", per_face = None, count = None, seed = 0, **options))]
pub fn sample<'py>(
    py: Python<'py>,
    mesh: &PyMesh,
    scheme: &str,
    per_face: Option<usize>,
    count: Option<usize>,
    seed: u64,
    options: Option<Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let surface_options = surface_options(py, "sample", scheme, options, mesh.inner.tags().options())?;
    let how = match (per_face, count) {
        (Some(n), None) => Ok(Sampling::PerDomain(n)),
        (None, Some(n)) => Ok(Sampling::ByArea { count: n, seed }),
        _ => Err(input("sample: give exactly one of per_face (an N×N grid per domain) and count (by area)")),
    };
    let how = how.raise(py)?;
    let input_mesh = mesh.inner.clone();
    let samples: Vec<SurfaceSample> = detached(py, move || {
        let surface = LimitSurface::new(&input_mesh, &surface_options)?;
        // Sized against the memory budget before anything is allocated.
        let (count, what) = match how {
            Sampling::PerDomain(n) => (per_domain_count(surface.domains().len(), n), "sample: per_face"),
            Sampling::ByArea { count, .. } => (u64::try_from(count).ok(), "sample: count"),
        };
        let remedy = format!("use a smaller {}", &what[8..]);
        MemoryBudget::available().check_items(what, count, "samples", PY_SAMPLE_BYTES, &remedy)?;
        let samples = sample_surface(&surface, input_mesh.positions(), how)?;
        if let Some(k) = samples.iter().position(|s| !(s.position.is_finite() && s.normal.is_finite())) {
            return Err(not_representable(format!("sample {k}")));
        }
        Ok(samples)
    })?;
    located(
        py,
        samples.iter().map(|s| s.param),
        samples.iter().map(|s| s.position).collect(),
        samples.iter().map(|s| s.normal).collect(),
    )
}

/// `project` (docstring in the Python wrapper).
#[pyfunction]
#[pyo3(signature = (mesh, points, scheme = "catmull-clark", **options))]
pub fn project<'py>(
    py: Python<'py>,
    mesh: &PyMesh,
    points: &Bound<'py, PyAny>,
    scheme: &str,
    options: Option<Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let surface_options = surface_options(py, "project", scheme, options, mesh.inner.tags().options())?;
    let queries: Vec<DVec3> = with_positions(points, |p| Ok(p.iter().map(|&q| DVec3::from_array(q)).collect()))?;
    let input_mesh = mesh.inner.clone();
    let found: Vec<Projection> = detached(py, move || {
        // On the normalised mesh and queries, mapped back (the numeric rule).
        let found = project_points(&input_mesh, &surface_options, &queries, &ProjectOptions::default())?;
        if let Some(k) = found.iter().position(|p| !(p.position.is_finite() && p.distance.is_finite())) {
            return Err(not_representable(format!("point {k}")));
        }
        Ok(found)
    })?;
    let out = located(
        py,
        found.iter().map(|p| p.param),
        found.iter().map(|p| p.position).collect(),
        found.iter().map(|p| p.normal).collect(),
    )?;
    out.set_item("distance", PyArray1::from_vec(py, found.iter().map(|p| p.distance).collect()))?;
    Ok(out)
}

/// `fit` (docstring in the Python wrapper): the fitted mesh and one dict per kept round (the
/// last one also names the stopping rule and the regularised control vertices).
#[pyfunction]
#[pyo3(signature = (target, control, scheme = "catmull-clark", iterations = 30, smoothness = 0.0,
    tolerance = 0.0, method = "gauss-newton", loss = "l2", min_improvement = 1e-3, max_time = None,
    lambda_ = 0.05, **options))]
#[allow(clippy::too_many_arguments)]
pub fn fit<'py>(
    py: Python<'py>,
    target: &Bound<'py, PyAny>,
    control: &PyMesh,
    scheme: &str,
    iterations: usize,
    smoothness: f64,
    tolerance: f64,
    method: &str,
    loss: &str,
    min_improvement: f64,
    max_time: Option<f64>,
    lambda_: f64,
    options: Option<Bound<'py, PyDict>>,
) -> PyResult<(PyMesh, Vec<Bound<'py, PyDict>>)> {
    let surface_options = surface_options(py, "fit", scheme, options, control.inner.tags().options())?;
    let method =
        method.parse::<FitMethod>().map_err(|e| input(format!("fit: {e}")).into_pyerr(py))?.with_lambda(lambda_);
    let loss = loss.parse::<FitLoss>().map_err(|e| input(format!("fit: {e}")).into_pyerr(py))?;
    let target = match target.extract::<PyRef<'_, PyMesh>>() {
        Ok(mesh) => FitTarget::from_mesh(&mesh.inner),
        Err(_) => FitTarget::cloud(with_positions(target, |p| Ok(p.iter().map(|&q| DVec3::from_array(q)).collect()))?),
    };
    let fit_options = FitOptions {
        surface: surface_options,
        iterations,
        smoothness,
        tolerance,
        min_improvement,
        max_time,
        method,
        loss,
        ..FitOptions::default()
    };
    let control_mesh = control.inner.clone();
    let result = detached(py, move || Ok(fit_surface(&target, &control_mesh, &fit_options)?))?;
    let count = result.iterations.len();
    let history = result
        .iterations
        .iter()
        .enumerate()
        .map(|(k, it)| {
            let d = PyDict::new(py);
            d.set_item("iteration", it.iteration)?;
            d.set_item("rms_target_to_surface", it.rms_target_to_surface)?;
            d.set_item("max_target_to_surface", it.max_target_to_surface)?;
            d.set_item("rms_surface_to_target", it.rms_surface_to_target)?;
            d.set_item("max_surface_to_target", it.max_surface_to_target)?;
            d.set_item("scale", it.scale)?;
            d.set_item("damping", it.damping)?;
            d.set_item("retries", it.retries)?;
            d.set_item("regularised", it.regularised)?;
            d.set_item("seconds", it.seconds)?;
            d.set_item("solver", it.solver)?;
            d.set_item("solver_iterations", it.solver_iterations)?;
            if k + 1 == count {
                d.set_item("method", method.name())?;
                d.set_item("loss", loss.name())?;
                d.set_item("stop", result.stop.name())?;
                d.set_item("regularised_vertices", result.regularised.clone())?;
            }
            Ok(d)
        })
        .collect::<PyResult<Vec<_>>>()?;
    Ok((PyMesh::new(result.mesh), history))
}
