//! `subdiv.Mesh`: a validated mesh, built from NumPy arrays and read back as NumPy arrays.

use crate::errors::{detached, input, Error, RaiseExt};
use numpy::ndarray::Array2;
use numpy::prelude::*;
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLike1, PyArrayLike2, PyUntypedArray};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use std::sync::Arc;
use subdiv::mesh::{DVec2, EdgeTag, FaceArrays, FaceVarying, PolygonSoup, TagList, VertexTag};

/// A polygon mesh: vertex positions and faces, validated (manifold, consistently oriented,
/// faces of at least 3 distinct vertices, finite coordinates), with the crease/corner tags and
/// texture coordinates of the file it was read from.
///
/// ``Mesh(vertices, faces)``: ``vertices`` an ``(n, 3)`` float array (anything
/// ``numpy.asarray`` takes; a C-contiguous float64 array is read in place, without a copy),
/// ``faces`` an ``(m, k)`` integer array (every face has ``k`` corners) or a list of sequences
/// of vertex indices (faces of mixed sizes); indices 0-based, counter-clockwise seen from
/// outside. Bad input raises ``subdiv.InputError`` (a ``ValueError``) naming the face or
/// vertex; isolated vertices and zero-area faces are accepted with a ``UserWarning``.
///
/// Keyword-only, as a file would give them: ``tags``, the crease and corner tags in the form
/// :attr:`tags` returns (``{"creases": [(v0, v1, s), ...], "corners": [(v, s), ...]}``, either
/// key optional; OpenSubdiv's sharpness, 0 smooth … ≥ 10 infinitely sharp), and ``uvs``, the
/// texture coordinates in the form :attr:`uvs` returns (``(values, indices)``: an ``(p, 2)``
/// float array and one value index per face corner, in face order). So
/// ``Mesh(m.vertices, m.faces, tags=m.tags, uvs=m.uvs)`` is ``m`` again.
///
/// A ``Mesh`` is immutable: the array properties return new arrays.
#[pyclass(frozen, name = "Mesh", module = "subdiv")]
pub struct PyMesh {
    /// The mesh.
    pub inner: Arc<subdiv::Mesh>,
    /// The file it was read from (for the report's `input.file`).
    pub path: Option<String>,
}

impl PyMesh {
    /// A Python mesh of `mesh`.
    pub fn new(mesh: subdiv::Mesh) -> Self {
        Self { inner: Arc::new(mesh), path: None }
    }
}

/// Points as `[[f64; 3]]` (vertices, query points): borrowed from a C-contiguous
/// float64 `(n, 3)` array, else copied.
pub(crate) fn with_positions<R>(
    vertices: &Bound<'_, PyAny>,
    f: impl FnOnce(&[[f64; 3]]) -> Result<R, Error>,
) -> PyResult<R> {
    let py = vertices.py();
    let array: PyArrayLike2<'_, f64, AllowTypeChange> = vertices.extract().map_err(|_| {
        input(format!("vertices must be an (n, 3) array of numbers, got {}", type_name(vertices))).into_pyerr(py)
    })?;
    let shape = array.shape();
    if shape[1] != 3 {
        return Err(
            input(format!("vertices must be an (n, 3) array, got shape ({}, {})", shape[0], shape[1])).into_pyerr(py)
        );
    }
    // `as_slice` also accepts a Fortran-ordered array, whose memory holds the columns: only a
    // C-contiguous one is the rows' `[x, y, z]` in order.
    let flat = if array.is_c_contiguous() { array.as_slice().ok() } else { None };
    let result = match flat {
        Some(flat) => {
            let points: &[[f64; 3]] = bytemuck::try_cast_slice(flat).map_err(|e| input(format!("{e}"))).raise(py)?;
            f(points)
        }
        None => {
            let view = array.as_array();
            let points: Vec<[f64; 3]> = view.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect();
            f(&points)
        }
    };
    result.raise(py)
}

/// `type(x).__name__`, for messages.
fn type_name(x: &Bound<'_, PyAny>) -> String {
    x.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into())
}

/// A vertex index as `usize`, refusing negative ones.
fn index(value: i64, face: usize) -> Result<usize, Error> {
    usize::try_from(value).map_err(|_| input(format!("face {face}: vertex index {value} is negative")))
}

/// Faces from Python: an `(m, k)` integer array, or a sequence of sequences.
enum Faces {
    Uniform { size: usize, indices: Vec<usize> },
    Nested(Vec<Vec<usize>>),
}

impl Faces {
    fn extract(faces: &Bound<'_, PyAny>) -> Result<Faces, Error> {
        if let Ok(array) = faces.cast::<PyUntypedArray>() {
            let kind = array.dtype().kind();
            if array.ndim() == 2 {
                if !matches!(kind, b'i' | b'u') {
                    return Err(input(format!(
                        "faces must be integer vertex indices, got an array of dtype {}",
                        array.dtype()
                    )));
                }
                let ints: PyArrayLike2<'_, i64, AllowTypeChange> =
                    faces.extract().map_err(|e| input(format!("faces: {e}")))?;
                let size = ints.shape()[1];
                let view = ints.as_array();
                let indices = match view.as_slice() {
                    // C-contiguous: one vectorisable pass for the sign, one for the copy.
                    Some(flat) => match flat.iter().position(|&v| usize::try_from(v).is_err()) {
                        Some(at) => return Err(index(flat[at], at / size.max(1)).unwrap_err()),
                        None => flat.iter().map(|&v| v as usize).collect(),
                    },
                    None => {
                        let mut indices = Vec::with_capacity(view.len());
                        for (f, row) in view.rows().into_iter().enumerate() {
                            for &v in row {
                                indices.push(index(v, f)?);
                            }
                        }
                        indices
                    }
                };
                return Ok(Faces::Uniform { size, indices });
            }
            if array.ndim() != 1 {
                return Err(input(format!(
                    "faces must be an (m, k) integer array or a list of sequences, got a {}-dimensional array",
                    array.ndim()
                )));
            }
        }
        let seq: Vec<Bound<'_, PyAny>> = faces.extract().map_err(|_| {
            input(format!("faces must be an (m, k) integer array or a list of sequences, got {}", type_name(faces)))
        })?;
        let mut nested = Vec::with_capacity(seq.len());
        for (f, face) in seq.iter().enumerate() {
            let values: Vec<i64> = face.extract().map_err(|_| {
                input(format!("face {f}: expected a sequence of integer vertex indices, got {}", type_name(face)))
            })?;
            nested.push(values.into_iter().map(|v| index(v, f)).collect::<Result<_, _>>()?);
        }
        Ok(Faces::Nested(nested))
    }

    fn arrays(&self) -> FaceArrays<'_> {
        match self {
            Faces::Uniform { size, indices } => FaceArrays::uniform(*size, indices),
            Faces::Nested(faces) => faces.into(),
        }
    }
}

/// An index (vertex or texture value) of a tag or channel as `u32`, refusing negative or huge ones.
fn index_u32(value: i64, what: &dyn Fn() -> String) -> Result<u32, Error> {
    u32::try_from(value).map_err(|_| input(format!("{}: index {value} is out of range", what())))
}

/// The `tags` keyword (the form of [`PyMesh::tags`]) as the file readers' [`TagList`]; the
/// edges, vertices and sharpness values are checked with the mesh (`Mesh::from_soup`).
fn tag_list(tags: &Bound<'_, PyAny>) -> Result<TagList, Error> {
    let dict = tags.cast::<PyDict>().map_err(|_| {
        input(format!(
            "tags must be a dict {{\"creases\": [(v0, v1, s)], \"corners\": [(v, s)]}}, got {}",
            type_name(tags)
        ))
    })?;
    let mut list = TagList::default();
    for (key, value) in dict.iter() {
        let key = key.str().map(|k| k.to_string()).unwrap_or_default();
        match key.as_str() {
            "creases" => {
                let creases: Vec<(i64, i64, f64)> = value
                    .extract()
                    .map_err(|_| input("tags[\"creases\"] must be a sequence of (v0, v1, sharpness)"))?;
                for (k, (a, b, s)) in creases.into_iter().enumerate() {
                    let what = || format!("tags[\"creases\"][{k}]");
                    list.creases.push(EdgeTag {
                        a: index_u32(a, &what)?,
                        b: index_u32(b, &what)?,
                        sharpness: s as f32,
                    });
                }
            }
            "corners" => {
                let corners: Vec<(i64, f64)> = value
                    .extract()
                    .map_err(|_| input("tags[\"corners\"] must be a sequence of (vertex, sharpness)"))?;
                for (k, (v, s)) in corners.into_iter().enumerate() {
                    let what = || format!("tags[\"corners\"][{k}]");
                    list.corners.push(VertexTag { vertex: index_u32(v, &what)?, sharpness: s as f32 });
                }
            }
            _ => return Err(input(format!("tags: unknown key {key:?} (expected \"creases\", \"corners\")"))),
        }
    }
    Ok(list)
}

/// The `uvs` keyword (the form of [`PyMesh::uvs`]) as a face-varying channel; its size and
/// indices are checked with the mesh (`Mesh::from_soup`).
fn face_varying(uvs: &Bound<'_, PyAny>) -> Result<FaceVarying, Error> {
    let expected = || input(format!("uvs must be a pair (values (p, 2) floats, indices), got {}", type_name(uvs)));
    let (values, indices): (Bound<'_, PyAny>, Bound<'_, PyAny>) = uvs.extract().map_err(|_| expected())?;
    let values: PyArrayLike2<'_, f64, AllowTypeChange> = values.extract().map_err(|_| expected())?;
    if values.shape()[1] != 2 {
        return Err(input(format!("uvs: values must be a (p, 2) array, got shape {:?}", values.shape())));
    }
    let values: Vec<DVec2> = values.as_array().rows().into_iter().map(|r| DVec2::new(r[0], r[1])).collect();
    let indices: PyArrayLike1<'_, i64, AllowTypeChange> =
        indices.extract().map_err(|_| input("uvs: indices must be a 1-D integer array, one per face corner"))?;
    let indices = indices
        .as_array()
        .iter()
        .enumerate()
        .map(|(corner, &i)| index_u32(i, &|| format!("uvs: corner {corner}")))
        .collect::<Result<_, _>>()?;
    Ok(FaceVarying { values, indices })
}

/// Adds the `tags` and `uvs` keywords to `soup`.
fn with_extras(
    mut soup: PolygonSoup,
    tags: Option<&Bound<'_, PyAny>>,
    uvs: Option<&Bound<'_, PyAny>>,
) -> Result<PolygonSoup, Error> {
    if let Some(tags) = tags.filter(|t| !t.is_none()) {
        soup.tags = tag_list(tags)?;
    }
    if let Some(uvs) = uvs.filter(|u| !u.is_none()) {
        soup.uvs = Some(face_varying(uvs)?);
    }
    Ok(soup)
}

/// Validates `soup` without the GIL; its warnings become Python `UserWarning`s.
pub fn validate(py: Python<'_>, soup: PolygonSoup) -> PyResult<PyMesh> {
    let (mesh, warnings) = detached(py, move || Ok(subdiv::Mesh::from_soup(soup)?))?;
    for w in warnings {
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        PyErr::warn(py, &category, &std::ffi::CString::new(w.to_string()).unwrap_or_default(), 1)?;
    }
    Ok(PyMesh::new(mesh))
}

/// A NumPy `(rows, cols)` array owning `values` (no copy).
pub fn array2<'py, T: numpy::Element>(
    py: Python<'py>,
    values: Vec<T>,
    rows: usize,
    cols: usize,
) -> Bound<'py, PyArray2<T>> {
    Array2::from_shape_vec((rows, cols), values).expect("rows × cols values").into_pyarray(py)
}

#[pymethods]
impl PyMesh {
    #[new]
    #[pyo3(signature = (vertices, faces, *, tags = None, uvs = None))]
    fn py_new(
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        tags: Option<&Bound<'_, PyAny>>,
        uvs: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let faces = Faces::extract(faces).raise(py)?;
        let soup = with_positions(vertices, |points| Ok(PolygonSoup::from_arrays(points, faces.arrays())?))?;
        validate(py, with_extras(soup, tags, uvs).raise(py)?)
    }

    /// A mesh from CSR faces: face ``f`` is ``indices[offsets[f]:offsets[f + 1]]``
    /// (what :attr:`face_offsets` and :attr:`face_indices` give back); ``tags`` and ``uvs`` as
    /// for the constructor.
    #[staticmethod]
    #[pyo3(signature = (vertices, offsets, indices, *, tags = None, uvs = None))]
    fn from_csr(
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        offsets: &Bound<'_, PyAny>,
        indices: &Bound<'_, PyAny>,
        tags: Option<&Bound<'_, PyAny>>,
        uvs: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let ints = |x: &Bound<'_, PyAny>, what: &str| -> PyResult<Vec<usize>> {
            let values: Vec<i64> = x.extract().map_err(|_| {
                input(format!("{what} must be a 1-D integer array, got {}", type_name(x))).into_pyerr(py)
            })?;
            values
                .into_iter()
                .map(|v| usize::try_from(v).map_err(|_| input(format!("{what}: {v} is negative"))))
                .collect::<Result<_, _>>()
                .raise(py)
        };
        let (offsets, indices) = (ints(offsets, "offsets")?, ints(indices, "indices")?);
        let soup = with_positions(vertices, |points| {
            Ok(PolygonSoup::from_arrays(points, FaceArrays::csr(&offsets, &indices))?)
        })?;
        validate(py, with_extras(soup, tags, uvs).raise(py)?)
    }

    /// The vertex positions, an ``(n, 3)`` float64 array (a new array at every access).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        // A non-manifold mesh read from a file is its manifold cover: its own vertices, welded.
        let (positions, _, _) = self.inner.welded();
        let flat: Vec<f64> = positions.iter().flat_map(|p| p.to_array()).collect();
        array2(py, flat, positions.len(), 3)
    }

    /// The faces: an ``(m, k)`` int64 array when every face has ``k`` corners, else a list of
    /// 1-D int64 arrays, one per face.
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let (_, faces, _) = self.inner.welded();
        let (offsets, indices) = (faces.offsets(), faces.indices());
        let sizes = offsets.windows(2).map(|w| w[1] - w[0]);
        let first = sizes.clone().next().unwrap_or(0);
        let wide: Vec<i64> = indices.iter().map(|&v| i64::from(v)).collect();
        if sizes.clone().all(|s| s == first) {
            return Ok(array2(py, wide, offsets.len() - 1, first as usize).into_any());
        }
        let faces = offsets.windows(2).map(|w| PyArray1::from_slice(py, &wide[w[0] as usize..w[1] as usize]));
        Ok(PyList::new(py, faces)?.into_any())
    }

    /// CSR offsets of the faces, ``(m + 1,)`` int64: face ``f`` is
    /// ``face_indices[face_offsets[f]:face_offsets[f + 1]]``.
    #[getter]
    fn face_offsets<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        let offsets: Vec<i64> = self.inner.welded().1.offsets().iter().map(|&v| i64::from(v)).collect();
        PyArray1::from_vec(py, offsets)
    }

    /// CSR vertex indices of the faces, one per face corner, int64.
    #[getter]
    fn face_indices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        let indices: Vec<i64> = self.inner.welded().1.indices().iter().map(|&v| i64::from(v)).collect();
        PyArray1::from_vec(py, indices)
    }

    /// Number of vertices.
    #[getter]
    fn n_vertices(&self) -> usize {
        self.inner.welds().map_or(self.inner.topology().vertex_count(), |welds| welds.vertex_count())
    }

    /// Number of faces.
    #[getter]
    fn n_faces(&self) -> usize {
        self.inner.topology().face_count()
    }

    /// The texture coordinates, or ``None``: ``(values, indices)``, ``values`` a ``(p, 2)``
    /// float64 array of (u, v), ``indices`` an int64 array with one value index per face
    /// corner, parallel to :attr:`face_indices`.
    #[getter]
    fn uvs<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyTuple>>> {
        let Some(uvs) = self.inner.uvs() else { return Ok(None) };
        let values: Vec<f64> = uvs.values.iter().flat_map(|p| p.to_array()).collect();
        let values = array2(py, values, uvs.values.len(), 2);
        let indices = PyArray1::from_vec(py, uvs.indices.iter().map(|&i| i64::from(i)).collect());
        Ok(Some(PyTuple::new(py, [values.into_any(), indices.into_any()])?))
    }

    /// The crease and corner tags (OpenSubdiv's), or ``None`` when there are none:
    /// ``{"creases": [(v0, v1, sharpness), ...], "corners": [(v, sharpness), ...]}``,
    /// sharpness 0 smooth … ≥ 10 infinitely sharp.
    #[getter]
    fn tags<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        if self.inner.tags().is_empty() {
            return Ok(None);
        }
        let (_, _, list) = self.inner.welded();
        let creases: Vec<(u32, u32, f32)> = list.creases.iter().map(|t| (t.a, t.b, t.sharpness)).collect();
        let corners: Vec<(u32, f32)> = list.corners.iter().map(|t| (t.vertex, t.sharpness)).collect();
        let dict = pyo3::types::PyDict::new(py);
        dict.set_item("creases", creases)?;
        dict.set_item("corners", corners)?;
        Ok(Some(dict.into_any()))
    }

    /// The file the mesh was read from (:func:`subdiv.read`), else ``None``.
    #[getter]
    fn path(&self) -> Option<String> {
        self.path.clone()
    }

    /// The mesh of a ``trimesh.Trimesh`` (its ``vertices`` and ``faces``).
    #[staticmethod]
    fn from_trimesh(py: Python<'_>, tm: &Bound<'_, PyAny>) -> PyResult<Self> {
        import_trimesh(py)?;
        PyMesh::py_new(py, &tm.getattr("vertices")?, &tm.getattr("faces")?, None, None)
    }

    /// A ``trimesh.Trimesh`` of the mesh (``process=False``: vertices kept as they are, in
    /// order). trimesh holds triangles: other faces are split over their own corners
    /// (quads along the shorter valid diagonal, keeping the mesh manifold), as
    /// ``subdivide(..., scheme="loop", triangulate=True)`` does.
    fn to_trimesh<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let trimesh = import_trimesh(py)?;
        let mesh = Arc::clone(&self.inner);
        let triangles = detached(py, move || Ok(subdiv::mesh::triangulate(&mesh)?.mesh))?;
        let triangles = PyMesh::new(triangles);
        let kwargs = pyo3::types::PyDict::new(py);
        kwargs.set_item("vertices", triangles.vertices(py))?;
        kwargs.set_item("faces", triangles.faces(py)?)?;
        kwargs.set_item("process", false)?;
        trimesh.getattr("Trimesh")?.call((), Some(&kwargs))
    }

    fn __repr__(&self) -> String {
        let t = self.inner.topology();
        let mut extras = String::new();
        if !self.inner.tags().is_empty() {
            extras += &format!(
                ", {} creases, {} corners",
                self.inner.tags().crease_count(),
                self.inner.tags().corner_count()
            );
        }
        if self.inner.uvs().is_some() {
            extras += ", uvs";
        }
        format!("Mesh({} vertices, {} faces{extras})", t.vertex_count(), t.face_count())
    }
}

/// `import trimesh`, or an `ImportError` saying how to get it.
fn import_trimesh(py: Python<'_>) -> PyResult<Bound<'_, PyModule>> {
    py.import("trimesh").map_err(|e| {
        pyo3::exceptions::PyImportError::new_err(format!(
            "subdiv's trimesh conversion needs the trimesh package: pip install trimesh ({e})"
        ))
    })
}
