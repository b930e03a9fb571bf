"""Shared helpers of the pytest suite: the repository's fixtures, the `subdiv` command line
(SUBDIV_CLI, set by .ci/run), an exact OBJ reader, procedural meshes."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[3]
FIXTURES = REPO / "fixtures"


def fixture(name: str) -> Path:
    """A mesh of the repository's fixtures/ (skip when the checkout has none)."""
    path = FIXTURES / name
    if not path.exists():
        pytest.skip(f"fixture {name} not found (tests run from a checkout of the repository)")
    return path


@pytest.fixture
def cli():
    """Runs the `subdiv` binary named by SUBDIV_CLI; skips when it is not set."""
    exe = os.environ.get("SUBDIV_CLI")
    if not exe or not Path(exe).is_file():
        pytest.skip("SUBDIV_CLI is not set to the subdiv binary (.ci/run sets it: target/ci/subdiv)")

    def run(*args):
        done = subprocess.run([exe, "--quiet", *map(str, args)], capture_output=True, text=True)
        return done

    return run


def read_obj(path: Path):
    """Vertices and faces of an OBJ file, parsed independently of subdiv. Our writer prints
    shortest round-trip numbers, so float() gets every f64 back exactly."""
    vertices, faces = [], []
    for line in Path(path).read_text().splitlines():
        fields = line.split()
        if not fields:
            continue
        if fields[0] == "v":
            vertices.append([float(x) for x in fields[1:4]])
        elif fields[0] == "f":
            faces.append([int(corner.split("/")[0]) - 1 for corner in fields[1:]])
    return np.array(vertices, dtype=np.float64).reshape(-1, 3), faces


def torus(nu: int, nv: int, R: float = 3.0, r: float = 1.0):
    """A quad torus of nu × nv vertices with a wobble (not a surface of revolution), as numpy
    arrays: (nu·nv, 3) float64 vertices and (nu·nv, 4) int64 faces, outward oriented."""
    u = 2 * np.pi * np.arange(nu) / nu
    v = 2 * np.pi * np.arange(nv) / nv
    U, V = np.meshgrid(u, v, indexing="ij")
    rr = r * (1 + 0.1 * np.sin(3 * U) * np.cos(2 * V))
    ring = R + rr * np.cos(V)
    X = np.stack([ring * np.cos(U), ring * np.sin(U), rr * np.sin(V)], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    a, b = i * nv + j, ((i + 1) % nu) * nv + j
    c, d = ((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv
    F = np.stack([a, b, c, d], -1).reshape(-1, 4).astype(np.int64)
    return X, F


def blender_limit_points(vertices, faces, creases, corners, boundary_smooth="ALL", quality=6):
    """The first n vertices of Blender's Subdivision Surface modifier (OpenSubdiv inside; limit
    surface, level 1) on a control mesh: the limit points of its n vertices. Edge creases
    [(a, b, s)] and vertex creases [(v, s)] become c = √(s/10) (Blender's map to OpenSubdiv
    sharpness is 10·c²). `boundary_smooth`: Blender's 'ALL' is OpenSubdiv's edge-only,
    'PRESERVE_CORNERS' edge-and-corner. Needs `bpy`."""
    import math

    import bpy

    mesh = bpy.data.meshes.new("cage")
    mesh.from_pydata(np.asarray(vertices).tolist(), [], [list(f) for f in faces])
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
    modifier.quality = quality
    modifier.boundary_smooth = boundary_smooth
    modifier.use_creases = True
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
    points = np.array([tuple(p.co) for p in evaluated.vertices])[: len(vertices)]
    bpy.data.objects.remove(obj)
    return points
