"""Mesh.from_trimesh / Mesh.to_trimesh (skipped without trimesh)."""

import numpy as np
import pytest

import subdiv
from conftest import fixture, torus

trimesh = pytest.importorskip("trimesh")


def test_round_trip_triangles():
    tm = trimesh.creation.icosphere(subdivisions=2)
    mesh = subdiv.Mesh.from_trimesh(tm)
    assert np.array_equal(mesh.vertices, np.asarray(tm.vertices))
    assert np.array_equal(mesh.faces, np.asarray(tm.faces))
    back = mesh.to_trimesh()
    assert np.array_equal(np.asarray(back.vertices), np.asarray(tm.vertices))
    assert np.array_equal(np.asarray(back.faces), np.asarray(tm.faces))
    assert back.is_watertight


def test_quads_are_split_and_volume_agrees():
    X, F = torus(24, 12)
    tm = subdiv.Mesh(X, F).to_trimesh()
    assert len(tm.faces) == 2 * len(F) and np.array_equal(np.asarray(tm.vertices), X)
    assert tm.is_watertight and tm.is_winding_consistent and tm.volume > 0  # outward


def test_interpolate_a_trimesh():
    tm = trimesh.load(fixture("tri/torus.obj"), process=False)
    result = subdiv.interpolate(subdiv.Mesh.from_trimesh(tm), method="deng-wang")
    surface = result.surface(2).to_trimesh()
    assert surface.is_watertight
