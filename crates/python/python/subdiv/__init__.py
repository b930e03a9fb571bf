"""subdiv: smooth subdivision surfaces (Doo-Sabin, Catmull-Clark, Loop) that pass through a
polygon mesh's vertices, by the six interpolation methods of the literature; plus plain
subdivision and limit evaluation (OpenSubdiv's options), and mesh files (OBJ, OFF, PLY, STL,
glTF/GLB).

NumPy in and out (float64 vertices, int64 faces); the computation runs without the GIL, so
threads interpolate in parallel::

    import numpy as np, subdiv
    mesh = subdiv.read("fixtures/quad/spot_control_mesh.obj")
    result = subdiv.interpolate(mesh, method="cheng", tol=1e-9)
    print(result.error["max_rel"])            # measured by the limit rules, relative to d
    control = result.control.vertices          # (n, 3) float64
    subdiv.write(result.surface(3), "spot-surface.ply", normals=True)

Errors: :class:`InputError` (a ``ValueError``) for bad input, :class:`NotConvergedError` (a
``RuntimeError``, with ``iterations`` and ``residual``), both :class:`SubdivError`;
``OSError`` (``FileNotFoundError``, …) for files. The Rust library and the ``subdiv`` command
line compute the same numbers bit for bit.
"""

import json
import os
from typing import Any, Callable, Iterable, List, Optional, Union

from ._errors import InputError, NotConvergedError, SubdivError
from . import _subdiv
from ._subdiv import Interpolation, Mesh, __version__, read, write

__all__ = [
    "Mesh",
    "Interpolation",
    "read",
    "write",
    "subdivide",
    "interpolate",
    "methods",
    "info",
    "batch",
    "schemes",
    "evaluate",
    "sample",
    "project",
    "fit",
    "SubdivError",
    "InputError",
    "NotConvergedError",
    "__version__",
]


def info(mesh: Mesh) -> "dict[str, Any]":
    """The command line's ``subdiv info --json`` object of ``mesh``: counts, face sizes,
    valences, boundary, genus, tags, texture coordinates, warnings, and per interpolation
    method whether it takes the mesh and why not."""
    return json.loads(_subdiv.info(mesh))


def batch(
    paths: "Union[str, os.PathLike[str], Iterable[Union[str, os.PathLike[str]]]]",
    out_dir: "Union[str, os.PathLike[str]]",
    command: str,
    *,
    jobs: int = 0,
    resume: bool = True,
    **options: Any,
) -> "List[dict[str, Any]]":
    """Run ``command`` (``"info"``, ``"interpolate"``, ``"subdivide"``) over many meshes, in
    parallel across meshes (the command line's ``subdiv batch``).

    Args:
        paths: files, directories (the mesh files in them, sorted; not in their subdirectories)
            and glob patterns (``*``, ``?``, ``**`` across subdirectories), or one of them.
        out_dir: where ``NAME.control.EXT``/``NAME.surface.EXT`` (interpolate),
            ``NAME.subdivided.EXT`` (subdivide) and ``NAME.record.json`` go; NAME is the
            input's stem (plus a stable hash when two inputs share one).
        command: the command.
        jobs: meshes at once (0: one per core).
        resume: skip inputs whose stored record says they are done (same file, same command,
            outputs present).
        **options: the single command's options by their keyword names: interpolate
            ``method`` (required), ``tol``, ``max_iter``, ``solver``, ``levels`` (surface levels,
            0: none; default 3), ``format``, ``boundary``, ``crease_method``, ``fvar`` and the
            method's own (``shape``, ``omega``, ``mu``, …); subdivide ``scheme``, ``levels``,
            ``limit``, ``normals``, ``format``, …; info ``strict``. A misspelled option raises
            ``ValueError`` naming it.

    Returns:
        One record per input, in input order: ``input``, ``outputs``, ``report`` (the
        interpolation's ``--report`` JSON, the ``info`` object, or the subdivision's counts),
        ``error`` (``message``, ``kind``, ``exit_code``) or ``None``, ``skipped``, ``seconds``,
        ``index``, ``name``, ``warnings``. A failing mesh never stops the others.
    """
    given = [paths] if isinstance(paths, (str, os.PathLike)) else list(paths)
    records = _subdiv.batch([os.fspath(p) for p in given], os.fspath(out_dir), command, json.dumps(options), jobs, resume)
    return [json.loads(r) for r in records]


def methods() -> "dict[str, str]":
    """The interpolation methods: ``{name: one-line summary}``, in the papers' order."""
    return dict(_subdiv.methods())


def schemes() -> "dict[str, str]":
    """The subdivision schemes (the scheme table): ``{name: one-line summary}``; the names
    :func:`subdivide`'s ``scheme`` takes."""
    return dict(_subdiv.schemes())


def subdivide(mesh: Mesh, scheme: str = "catmull-clark", levels: int = 1, limit: bool = False, **options: Any) -> Mesh:
    """Subdivide ``mesh`` ``levels`` times by a plain scheme (the command line's ``subdivide``).

    Args:
        mesh: the mesh, with its crease/corner tags and texture coordinates.
        scheme: a name of :func:`schemes`: ``"doo-sabin"``, ``"catmull-clark"``, ``"loop"``
            (triangles), ``"deng-ma"`` (interpolatory) or ``"sqrt3"`` (√3, triangles).
        levels: subdivision steps (0 with ``limit=True``: the input's limit positions).
        limit: move the final vertices to their limit positions (not for ``deng-ma``).
        **options: ``boundary`` (``"edge-and-corner"`` default, ``"edge-only"``, ``"none"``),
            ``crease_method`` (``"uniform"``, ``"chaikin"``), ``fvar`` (face-varying mode of the
            texture coordinates: ``"linear-all"`` default, ``"linear-boundaries"``,
            ``"linear-corners-plus2"``, ``"linear-corners-plus1"``, ``"linear-corners-only"``,
            ``"linear-none"``), ``triangle_rule`` (catmull-clark: ``"catmark"`` default,
            ``"smooth"``: OpenSubdiv's smooth triangles), ``dart_limit`` (``"exact"`` default:
            the limit of refinement at darts; ``"smooth-mask"``: OpenSubdiv's limit stencils); loop: ``beta`` (``"loop"`` default, as OpenSubdiv; ``"warren"``),
            ``triangulate`` (split non-triangles first); deng-ma: ``omega`` (global tension in
            (0, 1], default 1) or ``variable_tension`` (λ in (0, 1]).

    Returns:
        The refined :class:`Mesh` (with the final level's tags and texture coordinates).

    Raises:
        InputError: an unknown scheme or option value, a mesh the scheme cannot take.
    """
    return _subdiv.subdivide(mesh, scheme, levels, limit, **options)


_SURFACE_OPTIONS = """scheme: ``"catmull-clark"`` (default), ``"loop"`` (triangles) or ``"doo-sabin"``.
        **options: the surface options of :func:`subdivide` (``boundary``, ``crease_method``,
            ``fvar``; loop: ``beta``); the mesh's crease/corner tags are honoured."""


def evaluate(mesh: Mesh, params: Any, scheme: str = "catmull-clark", **options: Any) -> "dict[str, Any]":
    """The exact limit surface of ``mesh`` (as a control mesh) at given parameters.

    The command line's ``evaluate``. Parameters are per domain: a Catmull-Clark quad face is one
    domain, (u, v) in [0, 1]² with corner 0 at (0, 0), corner 1 at (1, 0), corner 3 at (0, 1);
    an n-gon (n ≠ 4) has n sub-quad domains (OpenSubdiv's ptex faces), ``corner`` K with (0, 0)
    at corner K; a Loop triangle is one domain, barycentric (u, v) with corner 1 at (1, 0) and
    corner 2 at (0, 1). Doo-Sabin: see the crate documentation of ``subdiv-eval``.

    Args:
        mesh: the control mesh.
        params: an ``(n, 3)`` array of rows ``[face, u, v]`` or ``(n, 4)`` of
            ``[face, corner, u, v]``.
        {surface}

    Returns:
        ``{{"position", "normal", "du", "dv"}}``: ``(n, 3)`` float64 arrays (unit normals oriented
        like the faces; derivatives with respect to the domain's u and v).

    Raises:
        InputError: a bad parameter (no such face or corner, outside the domain, not finite), a
            mesh the scheme cannot take, a bad option.
    """
    return _subdiv.evaluate(mesh, params, scheme, **options)


def sample(
    mesh: Mesh,
    scheme: str = "catmull-clark",
    per_face: Optional[int] = None,
    count: Optional[int] = None,
    seed: int = 0,
    **options: Any,
) -> "dict[str, Any]":
    """Points with normals on the limit surface of ``mesh`` (the command line's ``sample``).

    Args:
        mesh: the control mesh.
        per_face: an N×N grid of cell centres per domain; or
        count: about ``count`` points spread by area (deterministic for a ``seed``).
        {surface}

    Returns:
        ``{{"face", "corner", "u", "v"}}`` (1-D arrays: where each point is) and
        ``{{"position", "normal"}}`` (``(n, 3)`` arrays).
    """
    return _subdiv.sample(mesh, scheme, per_face, count, seed, **options)


def project(mesh: Mesh, points: Any, scheme: str = "catmull-clark", **options: Any) -> "dict[str, Any]":
    """The closest point of the limit surface of ``mesh`` to each query point (``project``).

    Args:
        mesh: the control mesh.
        points: an ``(n, 3)`` array of query points.
        {surface}

    Returns:
        ``{{"face", "corner", "u", "v", "distance"}}`` (1-D arrays) and ``{{"position",
        "normal"}}`` (``(n, 3)`` arrays), one row per query, in order.
    """
    return _subdiv.project(mesh, points, scheme, **options)


def fit(
    target: Any,
    control: Mesh,
    scheme: str = "catmull-clark",
    iterations: int = 30,
    smoothness: float = 0.0,
    tolerance: float = 0.0,
    method: str = "gauss-newton",
    loss: str = "l2",
    min_improvement: float = 1e-3,
    max_time: "float | None" = None,
    lambda_: float = 0.05,
    **options: Any,
) -> "tuple[Mesh, list[dict[str, Any]]]":
    """Move the control points of ``control`` so that its limit surface fits ``target``.

    The command line's ``fit``: foot points re-projected every round and a point-to-plane
    Gauss-Newton step with Levenberg-Marquardt damping; control points with little or no target
    support (a partial scan) are regularised; ``control``'s topology and tags are kept.

    Args:
        target: a :class:`Mesh` (distances to its triangles) or an ``(n, 3)`` point cloud; it may
            cover only part of the surface.
        control: the starting control mesh.
        iterations: kept rounds at most.
        smoothness: weight of an umbrella-Laplacian term on the control points (0: none).
        tolerance: stop when the RMS target→surface distance is at most this times d.
        method: ``"gauss-newton"`` (default), ``"lspia"`` (point-to-point, linear convergence) or
            ``"tangent"`` (tangent distance with λ = ``lambda_`` shrinking per round).
        loss: ``"l2"``, ``"huber"`` or ``"cauchy"`` (robust: outliers weigh less).
        min_improvement: stop when a kept round lowers the objective by less than this fraction.
        max_time: stop after this many seconds (checked after every round).
        {surface}

    Returns:
        ``(fitted_mesh, history)``: ``history`` has one dict per kept round with the RMS and
        maximum distances target→surface and surface→target (``rms_target_to_surface``, …), the
        target's bounding-box diagonal ``scale``, ``damping``, ``retries``, ``regularised``,
        ``seconds`` and ``solver``; the last dict also has ``method``, ``loss``, ``stop`` (the rule
        that stopped the fit) and ``regularised_vertices``.

    Raises:
        InputError: a bad option (``tolerance=nan``, an unknown ``method``), an empty or
            non-finite target, coordinates that cannot be represented.
    """
    return _subdiv.fit(
        target,
        control,
        scheme,
        iterations,
        smoothness,
        tolerance,
        method,
        loss,
        min_improvement,
        max_time,
        lambda_,
        **options,
    )


for _f in (evaluate, sample, project, fit):
    _f.__doc__ = (_f.__doc__ or "").format(surface=_SURFACE_OPTIONS)


def interpolate(
    mesh: Mesh,
    method: str = "cheng",
    tol: float = 1e-6,
    solver: str = "auto",
    max_iter: Optional[int] = None,
    *,
    progress: Optional[Callable[[int, float], Any]] = None,
    **method_options: Any,
) -> Interpolation:
    return _subdiv.interpolate(mesh, method, tol, solver, max_iter, progress=progress, **method_options)


_INTERPOLATE_DOC = """Find the control mesh whose limit surface passes through ``mesh``'s vertices.

The command line's ``interpolate``: the same options, checks, messages and numbers (bit for
bit).

Methods (``method=``):
{methods}

Args:
    mesh: the data: its vertices are interpolated (with its crease/corner tags).
    method: one of the names above.
    tol: bound on the measured error, max over vertices of |P - limit| / d (d the
        bounding-box diagonal); also the solver's tolerance.
    solver: ``"auto"`` (CG on positive definite systems, MINRES on possibly indefinite ones,
        GMRES on nonsymmetric ones) or one of pia, weighted-pia, jacobi, gauss-seidel,
        gauss-seidel-symmetric, gauss-seidel-multicolor, chebyshev, cg, cg-jacobi, minres,
        gmres, ldl, dense.
    max_iter: iteration cap of the iterative solvers (default 10000).
    progress: ``None``, or a callable told ``progress(iteration, relative_residual)`` after
        every iteration of the solver (each stage of a staged solve counts from 1 again; the
        residual falls towards ``tol``). It is called from the thread that runs the solve,
        with the GIL held for the call; keep it short (record the numbers, update a bar). An
        exception it raises does not stop the solve: it goes to ``sys.unraisablehook``.
    **method_options: ``subset`` (vertex indices to interpolate; default all), ``boundary``,
        ``crease_method``, ``fvar`` (as :func:`subdivide`);
        fan-cheng-lai: ``shape`` (λ in (0, 1), one float or one per face; default 0.5);
        zheng-cai: ``normals`` and ``handles`` (per vertex: a dict ``{{vertex: value}}`` or one
        entry per vertex, NaN for none; a normal is 3 numbers, a handle S > 0), ``ite_max``
        (default 5), ``eps`` (default 0.003); deng-wang: ``normals``, ``mu`` (default 3/8),
        ``beta`` (``"warren"``, ``"loop"``); deng-ma: ``omega`` or ``variable_tension``;
        fair: ``refine`` (K, the control mesh is the input refined K times; default 1),
        ``fairness_weight`` (w > 0: minimise misfit² + w·energy, the result approximates;
        default: exact interpolation), ``scheme`` (``"catmull-clark"``, ``"loop"`` with
        ``beta``, ``"doo-sabin"``); cheng: ``scheme`` (``"catmull-clark"`` default, ``"loop"``
        with ``beta``, ``"sqrt3"``: the control mesh of that scheme's limit surface).

Returns:
    An :class:`Interpolation`: ``.control`` (:class:`Mesh`), ``.report`` (the command line's
    ``--report`` JSON as a dict), ``.error`` (the measured error), ``.surface(levels)``.

Raises:
    InputError: bad options, a mesh the method cannot take (the message names the methods
        that take it).
    NotConvergedError: the tolerance was not reached (``iterations``, ``residual``).
"""


def _method_lines() -> str:
    return "\n".join(f"    {name}: {summary}" for name, summary in _subdiv.methods())


interpolate.__doc__ = _INTERPOLATE_DOC.format(methods=_method_lines())
