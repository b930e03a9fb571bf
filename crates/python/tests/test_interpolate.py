"""subdiv.interpolate: results checked independently, options, exceptions, docs."""

import inspect
import re
import sys
from pathlib import Path

import numpy as np
import pytest

import subdiv
from conftest import torus


def test_interpolates_the_data():
    X, F = torus(16, 10)
    mesh = subdiv.Mesh(X, F)
    result = subdiv.interpolate(mesh, method="cheng", tol=1e-10)
    # Independent check: the limit positions of the control mesh (plain Catmull-Clark,
    # levels=0, limit=True) are the data.
    limit = subdiv.subdivide(result.control, "catmull-clark", levels=0, limit=True).vertices
    d = np.linalg.norm(X.max(0) - X.min(0))
    assert np.abs(limit - X).max() / d <= 1e-10
    assert result.error["max_rel"] <= 1e-10
    assert result.report["input"]["vertices"] == len(X)
    assert result.method == "cheng"


@pytest.mark.filterwarnings("ignore:the mesh has 96 non-triangular faces")  # deng-wang triangulates
@pytest.mark.parametrize("method", list(subdiv.methods()))
def test_every_method_runs(method):
    X, F = torus(12, 8)
    result = subdiv.interpolate(subdiv.Mesh(X, F), method=method)
    assert result.report["method"] == method
    assert result.error["max_rel"] <= 1e-6


def test_method_options():
    X, F = torus(12, 8)
    mesh = subdiv.Mesh(X, F)
    shapes = np.full(mesh.n_faces, 0.4)
    per_face = subdiv.interpolate(mesh, method="fan-cheng-lai", shape=shapes)
    uniform = subdiv.interpolate(mesh, method="fan-cheng-lai", shape=0.4)
    assert np.array_equal(per_face.control.vertices, uniform.control.vertices)
    subset = subdiv.interpolate(mesh, method="cheng", subset=np.arange(0, 96, 2))
    assert subset.error["vertices"] == 48
    normals = {5: [0.0, 0.0, 1.0]}
    as_array = np.full((len(X), 3), np.nan)
    as_array[5] = [0.0, 0.0, 2.0]
    a = subdiv.interpolate(mesh, method="zheng-cai", normals=normals, handles={3: 0.5})
    b = subdiv.interpolate(mesh, method="zheng-cai", normals=as_array, handles={3: 0.5})
    assert np.array_equal(a.control.vertices, b.control.vertices)
    assert a.report["parameters"]["normals"] == 1


def test_not_converged():
    X, F = torus(20, 12)
    with pytest.raises(subdiv.NotConvergedError) as raised:
        subdiv.interpolate(subdiv.Mesh(X, F), method="nasri", solver="jacobi", tol=1e-14, max_iter=1)
    e = raised.value
    assert isinstance(e, RuntimeError) and isinstance(e, subdiv.SubdivError)
    assert e.iterations == 1
    assert e.residual > 1e-14
    assert "did not converge" in str(e)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"method": "nope"}, "unknown method 'nope' \\(expected one of: nasri, zheng-cai, cheng"),
        ({"method": "cheng", "shape": 0.5}, "--shape applies to --method fan-cheng-lai only"),
        ({"method": "fan-cheng-lai", "shape": 1.5}, "shape: λ = 1.5 is outside \\(0, 1\\)"),
        ({"method": "cheng", "normals": {0: [0, 0, 1]}}, "--normals applies to --method zheng-cai or deng-wang only"),
        ({"method": "zheng-cai", "normals": {0: [0, 0, 0]}}, "vertex 0: the normal is zero"),
        ({"method": "cheng", "tol": -1.0}, "tol must be positive, got -1"),
        ({"method": "cheng", "solver": "magic"}, "solver: unknown solver 'magic'"),
        ({"method": "cheng", "boundary": "sharp"}, "unknown boundary interpolation `sharp`"),
        ({"method": "cheng", "subset": [1000]}, "--subset: vertex 1000 is out of range"),
        ({"method": "deng-ma", "subset": [0]}, "deng-ma passes through every vertex"),
    ],
)
def test_bad_options(kwargs, message):
    X, F = torus(8, 6)
    mesh = subdiv.Mesh(X, F)
    with pytest.raises(ValueError, match=message):
        subdiv.interpolate(mesh, **kwargs)


def test_unknown_keyword_is_a_type_error():
    X, F = torus(8, 6)
    with pytest.raises(TypeError, match="unexpected keyword argument 'colour'"):
        subdiv.interpolate(subdiv.Mesh(X, F), colour="red")


def test_help_lists_the_methods():
    doc = subdiv.interpolate.__doc__
    for name, summary in subdiv.methods().items():
        assert f"{name}: {summary}" in doc
    # The stub's docstring carries the same list.
    stub = (Path(subdiv.__file__).parent / "__init__.pyi").read_text()
    for name, summary in subdiv.methods().items():
        assert f"{name}: {summary}" in stub
    assert inspect.signature(subdiv.interpolate).parameters["method"].default == "cheng"


def test_everything_public_is_documented():
    for name in subdiv.__all__:
        obj = getattr(subdiv, name)
        if name != "__version__":
            assert obj.__doc__, name
    for cls in (subdiv.Mesh, subdiv.Interpolation):
        for attr, member in vars(cls).items():
            if not attr.startswith("_"):
                assert member.__doc__, f"{cls.__name__}.{attr}"


def test_refinements_too_large_are_refused_not_aborted():
    X, F = torus(8, 6)
    mesh = subdiv.Mesh(X, F)
    with pytest.raises(ValueError, match="32-bit ids"):
        subdiv.subdivide(mesh, "catmull-clark", levels=30)
    with pytest.raises(ValueError, match="memory budget|32-bit ids"):
        subdiv.interpolate(mesh).surface(14)


def test_fair_interpolates_and_takes_its_options():
    X, F = torus(12, 8)
    mesh = subdiv.Mesh(X, F)
    result = subdiv.interpolate(mesh, method="fair", refine=1)
    # Independent check: the Catmull-Clark limit points of the control mesh's first
    # vertices (the input vertices' images) are the data.
    limit = subdiv.subdivide(result.control, "catmull-clark", levels=0, limit=True).vertices
    d = np.linalg.norm(X.max(0) - X.min(0))
    assert np.abs(limit[: len(X)] - X).max() / d <= 1e-9
    assert result.control.n_vertices == 96 + 192 + 96  # V + E + F of the torus
    assert result.report["parameters"]["refine"] == 1
    # refine 0 is the exact method.
    exact = subdiv.interpolate(mesh, method="fair", refine=0)
    cheng = subdiv.interpolate(mesh, method="cheng")
    assert np.array_equal(exact.control.vertices, cheng.control.vertices)
    ds = subdiv.interpolate(mesh, method="fair", scheme="doo-sabin")
    assert ds.error["max_rel"] <= 1e-9
    weighted = subdiv.interpolate(mesh, method="fair", fairness_weight=0.1)
    assert weighted.error["max_rel"] > 1e-6  # a penalty approximates
    with pytest.raises(ValueError, match="--refine applies to --method fair only"):
        subdiv.interpolate(mesh, method="cheng", refine=2)
    with pytest.raises(ValueError, match="Loop scheme needs triangles"):
        subdiv.interpolate(mesh, method="fair", scheme="loop")


def test_progress_is_told_the_solver_iterations(monkeypatch):
    v, f = torus(12, 8)
    mesh = subdiv.Mesh(v, f)
    calls = []
    result = subdiv.interpolate(mesh, tol=1e-10, progress=lambda i, r: calls.append((i, r)))
    assert calls and all(isinstance(i, int) and r >= 0 for i, r in calls)
    assert calls[-1][1] <= 1e-10 < calls[0][1]
    # Same numbers with and without the callback; an exception in it does not stop the solve.
    np.testing.assert_array_equal(result.control.vertices, subdiv.interpolate(mesh, tol=1e-10).control.vertices)

    def broken(i, r):
        raise ValueError("from the callback")

    unraisable = []
    monkeypatch.setattr(sys, "unraisablehook", unraisable.append)
    assert subdiv.interpolate(mesh, tol=1e-10, progress=broken).error["max_rel"] <= 1e-10
    assert unraisable and isinstance(unraisable[0].exc_value, ValueError)
    with pytest.raises(TypeError, match="progress must be callable"):
        subdiv.interpolate(mesh, progress=3)
