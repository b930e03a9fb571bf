"""subdiv.read / subdiv.write: round trips, errors as OSError / ValueError."""

import numpy as np
import pytest

import subdiv
from conftest import fixture, read_obj, torus


@pytest.mark.parametrize("ext", ["obj", "off", "ply"])
def test_write_read_round_trip(tmp_path, ext):
    X, F = torus(10, 6)
    mesh = subdiv.Mesh(X, F)
    path = tmp_path / f"torus.{ext}"
    subdiv.write(mesh, path)
    back = subdiv.read(path)
    assert back.path == str(path)
    assert np.array_equal(back.faces, F)
    assert np.array_equal(back.vertices, X)  # these formats keep every f64


def test_read_matches_an_independent_parser():
    path = fixture("quad/spot_control_mesh.obj")
    mesh = subdiv.read(path)
    v, f = read_obj(path)
    assert np.array_equal(mesh.vertices, v)
    faces = mesh.faces
    assert [list(x) for x in faces] == f


def test_write_normals(tmp_path):
    X, F = torus(8, 6)
    path = tmp_path / "n.obj"
    subdiv.write(subdiv.Mesh(X, F), path, normals=True)
    assert sum(line.startswith("vn ") for line in path.read_text().splitlines()) == len(X)


def test_errors(tmp_path):
    with pytest.raises(FileNotFoundError, match="missing.obj"):
        subdiv.read(tmp_path / "missing.obj")
    with pytest.raises(ValueError, match="unknown mesh format"):
        subdiv.read(tmp_path / "mesh.xyz")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n")
    with pytest.raises(ValueError, match="bad.obj:4"):
        subdiv.read(bad)
    with pytest.raises(OSError):
        subdiv.write(subdiv.Mesh(*torus(6, 4)), tmp_path / "no-such-dir" / "x.obj")
    directory = tmp_path / "dir.obj"
    directory.mkdir()
    with pytest.raises(IsADirectoryError, match="not a regular file"):
        subdiv.read(directory)
