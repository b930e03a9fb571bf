"""Issue #43 from Python: the cases a hostile user found in the newer calls raise, or give the
correct, finite result (as the command line exits 2/3 or 0)."""

import os
import stat

import numpy as np
import pytest

import subdiv
from conftest import fixture


def cube(scale):
    mesh = subdiv.read(fixture("canonical/cube_quad.obj"))
    return subdiv.Mesh(mesh.vertices * scale, mesh.faces)


@pytest.mark.parametrize("kwargs", [{"count": 10**12}, {"count": 2**32}, {"per_face": 65536},
                                    {"count": 2**64 - 1}, {"per_face": 2**64 - 1}])
def test_sample_counts_beyond_the_memory_budget_raise(kwargs):
    # Before: count=10**12 killed the interpreter (a 24 TB allocation).
    with pytest.raises(subdiv.InputError, match="samples need about"):
        subdiv.sample(cube(1.0), **kwargs)


@pytest.mark.parametrize("scale", [1e-300, 1e-200, 1e-150, 1e150, 1e200, 1e300])
def test_evaluate_sample_and_project_at_extreme_scales_match_scale_one(scale):
    unit, far = cube(1.0), cube(scale)
    params = np.array([[0, 0.5, 0.5], [2, 0.1, 0.9], [4, 0.0, 0.0]])
    a, b = subdiv.evaluate(unit, params), subdiv.evaluate(far, params)
    assert np.allclose(a["normal"], b["normal"], rtol=0, atol=1e-12)
    assert np.allclose(np.linalg.norm(b["normal"], axis=1), 1.0)
    assert np.allclose(a["position"] * scale, b["position"], rtol=1e-12, atol=0)
    s, t = subdiv.sample(unit, count=40, seed=1), subdiv.sample(far, count=40, seed=1)
    assert np.allclose(s["normal"], t["normal"], rtol=0, atol=1e-12)
    assert np.allclose(s["position"] * scale, t["position"], rtol=1e-12, atol=0)
    queries = np.array([[0.3, 0.4, 1.7], [-0.5, 0.5, 0.5], [0.9, 2.0, 0.1]])
    p, q = subdiv.project(unit, queries), subdiv.project(far, queries * scale)
    assert np.array_equal(p["face"], q["face"])
    assert np.allclose(p["distance"] * scale, q["distance"], rtol=1e-9, atol=0)
    assert (q["distance"] > 0).all()


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs")
def test_write_refuses_a_fifo_as_the_command_line_does(tmp_path):
    fifo = tmp_path / "out.obj"
    os.mkfifo(fifo)
    with pytest.raises(OSError, match="not a regular file"):
        subdiv.write(cube(1.0), str(fifo))
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
