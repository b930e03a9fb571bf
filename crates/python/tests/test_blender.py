"""Blender's own Subdivision Surface modifier (the `bpy` module from PyPI, Blender 5.0) on control
meshes written by `subdiv interpolate`: with the limit surface on, level 1, the first n evaluated
vertices are the limit points of the n control vertices, so they must land on the data.

Darts (issue #40 item 4): fandisk with its ≥ 30° features tagged has 4 dart vertices (a crease
ending inside the surface). Blender evaluates patches, which reach the true limit there; our
default dart limit (`--dart-limit exact`) is that limit, so Blender passes ≤ 2e-6·d (float32)
everywhere; OpenSubdiv's limit-stencil shortcut (`--dart-limit smooth-mask`) misses by ~3e-4·d at
the darts, which shows the check can fail.

Skipped where `bpy` is not installed (it is large; `pip install bpy` on CPython 3.11)."""

import math

import numpy as np
import pytest

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


def blender_limit_points(control):
    """The first n vertices of Blender's modifier (limit surface, level 1) on the control mesh,
    with edge and vertex creases c = √(s/10) (Blender's map to OpenSubdiv sharpness is 10·c²)."""
    vertices, faces = read_obj(control)
    creases, corners = read_tags(control)
    mesh = bpy.data.meshes.new("cage")
    mesh.from_pydata(vertices.tolist(), [], faces)
    mesh.update()
    edge = {tuple(sorted(e.vertices)): e.index for e in mesh.edges}
    crease = np.zeros(len(mesh.edges))
    for a, b, s in creases:
        crease[edge[tuple(sorted((a, b)))]] = math.sqrt(min(s, 10.0) / 10.0)
    mesh.attributes.new("crease_edge", "FLOAT", "EDGE").data.foreach_set("value", crease)
    corner = np.zeros(len(vertices))
    for v, s in corners:
        corner[v] = math.sqrt(min(s, 10.0) / 10.0)
    mesh.attributes.new("crease_vert", "FLOAT", "POINT").data.foreach_set("value", corner)
    obj = bpy.data.objects.new("cage", mesh)
    bpy.context.scene.collection.objects.link(obj)
    modifier = obj.modifiers.new("subsurf", "SUBSURF")
    modifier.levels = modifier.render_levels = 1
    modifier.use_limit_surface = True
    modifier.quality = 6
    # 'ALL' is OpenSubdiv's edge-only (Blender's BKE_subdiv_vtx_boundary_interpolation_from_subsurf),
    # 'PRESERVE_CORNERS' edge-and-corner; fandisk is closed, so either shows the same surface.
    modifier.boundary_smooth = "ALL"
    modifier.use_creases = True
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
    points = np.array([tuple(p.co) for p in evaluated.vertices])[: len(vertices)]
    bpy.data.objects.remove(obj)
    return points


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
    error = np.linalg.norm(blender_limit_points(control) - target, axis=1) / d
    if bound is not None:
        assert error.max() <= bound, f"max {error.max():.3e}·d at vertex {error.argmax()}"
    else:
        # OpenSubdiv's shortcut at the 4 darts: off by far more than float32 rounding there.
        assert np.sort(error)[-4] > 1e-4, np.sort(error)[-6:]
