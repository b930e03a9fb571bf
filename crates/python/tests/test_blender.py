"""Blender's own Subdivision Surface modifier (the `bpy` module from PyPI, Blender 5.0) on control
meshes written by `subdiv interpolate`: with the limit surface on, level 1, the first n evaluated
vertices are the limit points of the n control vertices, so they must land on the data.

Darts (issue #40 item 4): fandisk with its ≥ 30° features tagged has 4 dart vertices (a crease
ending inside the surface). Blender evaluates patches, which reach the true limit there; our
default dart limit (`--dart-limit exact`) is that limit, so Blender passes ≤ 2e-6·d (float32)
everywhere; OpenSubdiv's limit-stencil shortcut (`--dart-limit smooth-mask`) misses by ~3e-4·d at
the darts, which shows the check can fail.

Skipped where `bpy` is not installed (it is large; `pip install bpy` on CPython 3.11)."""


import numpy as np
import pytest

from conftest import blender_limit_points
from conftest import fixture, read_obj

bpy = pytest.importorskip("bpy")


def read_tags(path):
    """The `t crease` and `t corner` lines of an OBJ file: [(a, b, s)], [(v, s)]."""
    creases, corners = [], []
    for line in open(path):
        f = line.split()
        if f[:2] == ["t", "crease"]:
            creases.append((int(f[3]), int(f[4]), float(f[5])))
        elif f[:2] == ["t", "corner"]:
            corners.append((int(f[3]), float(f[4])))
    return creases, corners


def limit_points_of_obj(control):
    """Blender's limit points of the control mesh an OBJ file holds, with its tags; 'ALL' (edge-only):
    fandisk is closed, so either boundary rule shows the same surface."""
    vertices, faces = read_obj(control)
    creases, corners = read_tags(control)
    return blender_limit_points(vertices, faces, creases, corners, boundary_smooth="ALL", quality=6)


def read_off(path):
    words = [w for line in open(path) if not line.startswith("#") for w in line.split()]
    n = int(words[1])
    return np.array([float(x) for x in words[4 : 4 + 3 * n]]).reshape(n, 3)


@pytest.mark.parametrize("dart_limit, bound", [("exact", 2e-6), ("smooth-mask", None)])
def test_blender_passes_through_the_data_at_darts(cli, tmp_path, dart_limit, bound):
    data = fixture("quad/fandisk_quads.off")
    control = tmp_path / "control.obj"
    done = cli("interpolate", data, "--method", "cheng", "--feature-angle", "30", "--dart-limit", dart_limit,
               "-o", control)
    assert done.returncode == 0, done.stderr
    target = read_off(data)
    d = np.linalg.norm(target.max(0) - target.min(0))
    error = np.linalg.norm(limit_points_of_obj(control) - target, axis=1) / d
    if bound is not None:
        assert error.max() <= bound, f"max {error.max():.3e}·d at vertex {error.argmax()}"
    else:
        # OpenSubdiv's shortcut at the 4 darts: off by far more than float32 rounding there.
        assert np.sort(error)[-4] > 1e-4, np.sort(error)[-6:]
