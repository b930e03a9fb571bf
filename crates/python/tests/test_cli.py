"""The bindings compute what the command line computes, bit for bit: control meshes, surfaces,
subdivision and the report's keys (the CLI's files parsed back independently)."""

import json

import numpy as np
import pytest

import subdiv
from conftest import fixture, read_obj

CASES = [
    # (fixture, method, Python options, the same as CLI flags)
    ("quad/spot_control_mesh.obj", "cheng", {"tol": 1e-9}, ["--tol", "1e-9"]),
    ("tri/torus.obj", "deng-wang", {}, []),
    ("canonical/pyramid_mixed.obj", "nasri", {"solver": "gmres"}, ["--solver", "gmres"]),
    ("canonical/torus_quad_16x8.obj", "fan-cheng-lai", {"shape": 0.3}, ["--shape", "0.3"]),
    ("canonical/icosphere_2.obj", "zheng-cai", {"ite_max": 3}, ["--ite-max", "3"]),
    ("open/hemisphere.off", "cheng", {"boundary": "edge-only"}, ["--boundary", "edge-only"]),
]


def keys(tree):
    """The nested key structure of a JSON value."""
    if isinstance(tree, dict):
        return {k: keys(v) for k, v in tree.items()}
    return type(tree).__name__ if tree is not None else None


@pytest.mark.parametrize("name, method, options, flags", CASES, ids=[f"{c[1]}-{c[0]}" for c in CASES])
def test_interpolate_equals_cli(tmp_path, cli, name, method, options, flags):
    path = fixture(name)
    control, surface, report = tmp_path / "control.obj", tmp_path / "surface.obj", tmp_path / "report.json"
    done = cli("interpolate", path, "--method", method, *flags, "-o", control, "--surface", surface,
               "--levels", 2, "--report", report)
    assert done.returncode == 0, done.stderr

    result = subdiv.interpolate(subdiv.read(path), method=method, **options)
    cli_control, cli_faces = read_obj(control)
    assert np.array_equal(result.control.vertices, cli_control)  # bit for bit
    assert [list(f) for f in result.control.faces] == cli_faces
    cli_surface, _ = read_obj(surface)
    assert np.array_equal(result.surface(2).vertices, cli_surface)

    expected = json.loads(report.read_text())
    got = result.report
    assert keys(got) == keys(expected)
    for part in ["method", "control_scheme", "input", "control", "surface_options", "error", "parameters",
                 "warnings"]:
        assert got[part] == expected[part], part
    for key in ["name", "iterations", "converged", "matvecs", "residual", "residual_history"]:
        assert got["solver"][key] == expected["solver"][key], key
    assert result.error == expected["error"]


def test_deng_ma_surface_equals_cli(tmp_path, cli):
    path = fixture("canonical/icosahedron.obj")
    out = tmp_path / "dm.obj"
    done = cli("interpolate", path, "--method", "deng-ma", "--omega", "0.8", "-o", out, "--levels", 2)
    assert done.returncode == 0, done.stderr
    result = subdiv.interpolate(subdiv.read(path), method="deng-ma", omega=0.8)
    assert np.array_equal(result.surface(2).vertices, read_obj(out)[0])


@pytest.mark.parametrize(
    "scheme, kwargs, flags",
    [
        ("catmull-clark", {"limit": True}, ["--limit"]),
        ("doo-sabin", {}, []),
        ("loop", {"beta": "loop", "triangulate": True}, ["--beta", "loop", "--triangulate"]),
        ("deng-ma", {"variable_tension": 0.5}, ["--variable-tension", "0.5"]),
    ],
)
def test_subdivide_equals_cli(tmp_path, cli, scheme, kwargs, flags):
    path = fixture("canonical/pyramid_mixed.obj")
    out = tmp_path / "out.obj"
    done = cli("subdivide", path, "--scheme", scheme, "--levels", 2, *flags, "-o", out)
    assert done.returncode == 0, done.stderr
    mesh = subdiv.subdivide(subdiv.read(path), scheme=scheme, levels=2, **kwargs)
    v, f = read_obj(out)
    assert np.array_equal(mesh.vertices, v)
    assert [list(x) for x in mesh.faces] == f


def test_the_same_error_messages(cli, tmp_path):
    path = fixture("canonical/cube_quad.obj")
    done = cli("interpolate", path, "--method", "cheng", "--shape", "0.3")
    assert done.returncode == 2
    with pytest.raises(ValueError) as raised:
        subdiv.interpolate(subdiv.read(path), method="cheng", shape=0.3)
    # One parser for both (subdiv-job): the same sentence, naming the option as a flag.
    assert done.stderr.strip() == f"subdiv: error: {raised.value}"

    for bad in ["bad/face_with_two_vertices.obj", "bad/out_of_range_index.obj", "bad/utf16.obj"]:
        path = fixture(bad)
        done = cli("interpolate", path, "--method", "cheng")
        assert done.returncode == 2
        with pytest.raises(ValueError) as raised:
            subdiv.read(path)
        assert done.stderr.strip() == f"subdiv: error: {raised.value}"
