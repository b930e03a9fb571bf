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
        pytest.skip("SUBDIV_CLI is not set to the subdiv binary (.ci/run sets it: target/release/subdiv)")

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
