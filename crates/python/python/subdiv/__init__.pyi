"""Type stubs of :mod:`subdiv` (the compiled core ``subdiv._subdiv`` and its wrappers)."""

import os
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]
PathLike = Union[str, "os.PathLike[str]"]

class SubdivError(Exception):
    """Base class of every error subdiv raises itself (file system errors are OSError)."""

class InputError(SubdivError, ValueError):
    """Bad input: a malformed mesh or file, a bad option, a mesh the method cannot take."""

class NotConvergedError(SubdivError, RuntimeError):
    """The solver stopped before the tolerance, or the measured error exceeds it."""

    iterations: Optional[int]
    """Iterations the solver performed (None when no iterative solver ran)."""
    residual: Optional[float]
    """The residual or measured error reached, relative to the bounding-box diagonal d."""
    def __init__(self, message: str, iterations: Optional[int] = ..., residual: Optional[float] = ...) -> None: ...

class Mesh:
    """A validated polygon mesh: vertices (n, 3) float64, faces of any size, with the tags and
    texture coordinates of the file it was read from. Immutable."""

    def __init__(
        self,
        vertices: npt.ArrayLike,
        faces: Union[npt.ArrayLike, Sequence[Sequence[int]]],
        *,
        tags: Optional[Mapping[str, Sequence[Sequence[float]]]] = None,
        uvs: Optional[Tuple[npt.ArrayLike, npt.ArrayLike]] = None,
    ) -> None:
        """``vertices`` an (n, 3) float array; ``faces`` an (m, k) integer array or a list of
        sequences of 0-based vertex indices; ``tags`` as :attr:`tags` returns them
        (``{"creases": [(v0, v1, s)], "corners": [(v, s)]}``), ``uvs`` as :attr:`uvs`
        (``(values (p, 2), one index per face corner)``). Raises InputError for bad input."""
    @staticmethod
    def from_csr(
        vertices: npt.ArrayLike,
        offsets: npt.ArrayLike,
        indices: npt.ArrayLike,
        *,
        tags: Optional[Mapping[str, Sequence[Sequence[float]]]] = None,
        uvs: Optional[Tuple[npt.ArrayLike, npt.ArrayLike]] = None,
    ) -> "Mesh":
        """A mesh from CSR faces: face f is ``indices[offsets[f]:offsets[f + 1]]``; ``tags`` and
        ``uvs`` as for the constructor."""
    @staticmethod
    def from_trimesh(tm: Any) -> "Mesh":
        """The mesh of a ``trimesh.Trimesh`` (ImportError without trimesh)."""
    def to_trimesh(self) -> Any:
        """A ``trimesh.Trimesh`` (process=False; non-triangles split over their corners)."""
    @property
    def vertices(self) -> FloatArray:
        """(n, 3) float64 vertex positions (a new array at every access)."""
    @property
    def faces(self) -> Union[IntArray, List[IntArray]]:
        """(m, k) int64 when every face has k corners, else a list of 1-D int64 arrays."""
    @property
    def face_offsets(self) -> IntArray:
        """CSR offsets, (m + 1,) int64."""
    @property
    def face_indices(self) -> IntArray:
        """CSR vertex indices, one per face corner, int64."""
    @property
    def n_vertices(self) -> int:
        """Number of vertices."""
    @property
    def n_faces(self) -> int:
        """Number of faces."""
    @property
    def uvs(self) -> Optional[Tuple[FloatArray, IntArray]]:
        """(values (p, 2) float64, one value index per face corner), or None."""
    @property
    def tags(self) -> Optional[Dict[str, List[Tuple[Any, ...]]]]:
        """{"creases": [(v0, v1, s)], "corners": [(v, s)]}, or None without tags."""
    @property
    def path(self) -> Optional[str]:
        """The file the mesh was read from, else None."""

class Interpolation:
    """The result of :func:`interpolate`."""

    @property
    def control(self) -> Mesh:
        """The control mesh (deng-ma: the input, its scheme interpolates)."""
    @property
    def report(self) -> Dict[str, Any]:
        """The command line's --report JSON, as a dict."""
    @property
    def error(self) -> Dict[str, float]:
        """The measured error: max_rel, mean_rel, max_abs, mean_abs, vertices."""
    @property
    def method(self) -> str:
        """The method's name."""
    def surface(self, levels: int = 3) -> Mesh:
        """The control mesh refined ``levels`` times at limit positions (the CLI's --surface)."""

def read(path: PathLike) -> Mesh:
    """A mesh file (.obj, .off, .ply, .stl, .gltf, .glb), validated."""

def write(mesh: Mesh, path: PathLike, normals: bool = False) -> None:
    """Writes a mesh file atomically (format from the extension), with vertex normals on request."""

def methods() -> Dict[str, str]:
    """The interpolation methods: {name: one-line summary}."""

def schemes() -> Dict[str, str]:
    """The subdivision schemes: {name: one-line summary}."""

def evaluate(mesh: Mesh, params: Any, scheme: str = ..., **options: Any) -> Dict[str, Any]: ...
def sample(
    mesh: Mesh,
    scheme: str = ...,
    per_face: Optional[int] = ...,
    count: Optional[int] = ...,
    seed: int = ...,
    **options: Any,
) -> Dict[str, Any]: ...
def project(mesh: Mesh, points: Any, scheme: str = ..., **options: Any) -> Dict[str, Any]: ...
def fit(
    target: Any,
    control: Mesh,
    scheme: str = ...,
    iterations: int = ...,
    smoothness: float = ...,
    **options: Any,
) -> Tuple[Mesh, List[Dict[str, float]]]: ...
def subdivide(
    mesh: Mesh,
    scheme: str = "catmull-clark",
    levels: int = 1,
    limit: bool = False,
    *,
    boundary: str = ...,
    crease_method: str = ...,
    fvar: str = ...,
    triangle_rule: str = ...,
    dart_limit: str = ...,
    beta: str = ...,
    triangulate: bool = ...,
    omega: float = ...,
    variable_tension: float = ...,
) -> Mesh:
    """Subdivides by a plain scheme: doo-sabin, catmull-clark, loop, deng-ma."""

def interpolate(
    mesh: Mesh,
    method: str = "cheng",
    tol: float = 1e-6,
    solver: str = "auto",
    max_iter: Optional[int] = None,
    *,
    progress: Optional[Callable[[int, float], Any]] = None,
    subset: Sequence[int] = ...,
    boundary: str = ...,
    crease_method: str = ...,
    fvar: str = ...,
    triangle_rule: str = ...,
    dart_limit: str = ...,
    shape: Union[float, Sequence[float]] = ...,
    normals: Union[Mapping[int, Sequence[float]], npt.ArrayLike] = ...,
    handles: Union[Mapping[int, float], npt.ArrayLike] = ...,
    ite_max: int = ...,
    eps: float = ...,
    mu: float = ...,
    beta: str = ...,
    omega: float = ...,
    variable_tension: float = ...,
    refine: int = ...,
    fairness_weight: float = ...,
    scheme: str = ...,
) -> Interpolation:
    """Finds the control mesh whose limit surface passes through the mesh's vertices.

    Methods:
        nasri: Nasri 1987: Doo-Sabin, the global system C·M⁰ = P
        zheng-cai: Zheng & Cai 2005: Doo-Sabin, a few Gauss-Seidel sweeps + exact perturbation of M¹
        cheng: Cheng et al.: Catmull-Clark (or Loop, √3), A·M̂ = P
        fan-cheng-lai: Fan, Cheng & Lai: two-phase Doo-Sabin with per-face shape λ
        deng-wang: Deng & Wang 2010: Loop, explicit modified first step
        deng-ma: Deng & Ma 2011: interpolatory scheme derived from Doo-Sabin (no control mesh)
        fair: Halstead, Kass & DeRose 1993: Catmull-Clark (or Loop, Doo-Sabin), the fairest control mesh of the input refined K times
    """

def info(mesh: Mesh) -> Dict[str, Any]:
    """The command line's ``subdiv info --json`` object of the mesh."""

def batch(
    paths: Union[PathLike, Sequence[PathLike]],
    out_dir: PathLike,
    command: str,
    *,
    jobs: int = 0,
    resume: bool = True,
    **options: Any,
) -> List[Dict[str, Any]]:
    """Runs ``command`` (info, interpolate, subdivide) over many meshes; one record per input."""
