"""The three front-ends are thin maps onto one pipeline (subdiv-job): the command line
(`subdiv interpolate`), the batch (`subdiv.batch`, the same as `subdiv batch`) and the Python
call (`subdiv.interpolate`) give, for the same options, the same outcome (success, bad input,
no convergence), the same error text and the same control mesh, byte for byte."""

import os
from pathlib import Path

import pytest

import subdiv
from conftest import fixture

QUAD = "quad/spot_control_mesh.obj"
TRI = "canonical/icosphere_2.obj"

# (mesh, method, options by keyword name); every method, valid and invalid options.
CASES = [
    (QUAD, "cheng", {}),
    (QUAD, "cheng", {"tol": 1e-9}),
    (QUAD, "cheng", {"solver": "minres"}),
    (QUAD, "cheng", {"solver": "cg", "max_iter": 500}),
    (QUAD, "cheng", {"boundary": "edge-only", "crease_method": "chaikin"}),
    (QUAD, "nasri", {}),
    (QUAD, "nasri", {"solver": "gmres"}),
    (QUAD, "zheng-cai", {}),
    (QUAD, "zheng-cai", {"ite_max": 3, "eps": 0.01}),
    (QUAD, "fan-cheng-lai", {}),
    (QUAD, "fan-cheng-lai", {"shape": 0.3}),
    (QUAD, "deng-ma", {}),
    (QUAD, "deng-ma", {"omega": 0.8}),
    (QUAD, "deng-ma", {"variable_tension": 0.5}),
    (QUAD, "fair", {}),
    (QUAD, "fair", {"refine": 0}),
    (QUAD, "fair", {"fairness_weight": 0.1}),
    (TRI, "deng-wang", {}),
    (TRI, "deng-wang", {"mu": 0.3, "beta": "loop"}),
    (TRI, "fair", {"scheme": "loop"}),
    (TRI, "fair", {"scheme": "loop", "beta": "loop"}),
    (TRI, "cheng", {"fvar": "linear-none"}),
    (QUAD, "cheng", {"dart_limit": "smooth-mask"}),
    # Refused: options of another method, values out of range, unknown names, meshes a
    # method cannot take, and a solve that cannot reach its tolerance.
    (QUAD, "cheng", {"mu": 0.3}),
    (QUAD, "cheng", {"ite_max": 9}),
    (QUAD, "cheng", {"omega": 0.5}),
    (QUAD, "cheng", {"fairness_weight": 1.0}),
    (QUAD, "nasri", {"shape": 0.5}),
    (QUAD, "zheng-cai", {"beta": "loop"}),
    (QUAD, "fan-cheng-lai", {"shape": 1.5}),
    (QUAD, "cheng", {"tol": -1.0}),
    (QUAD, "cheng", {"solver": "nope"}),
    (QUAD, "cheng", {"boundary": "edge"}),
    (QUAD, "fair", {"dart_limit": "sharp"}),
    (QUAD, "chen", {}),
    (QUAD, "deng-ma", {"omega": 2.0}),
    (QUAD, "deng-ma", {"omega": 0.5, "variable_tension": 0.5}),
    (QUAD, "fair", {"scheme": "loop"}),
    (QUAD, "fair", {"scheme": "deng-ma"}),
    (QUAD, "fair", {"beta": "loop"}),
    (QUAD, "fair", {"refine": 2, "scheme": "doo-sabin"}),
    (QUAD, "cheng", {"tol": 1e-30, "max_iter": 1, "solver": "pia"}),
]

# Python's own parameters of subdiv.interpolate (the rest are keyword options).
OWN = ("tol", "solver", "max_iter")


def flags(options):
    """The command line's flags of `options` (`--key=value`, so negative numbers pass)."""
    return [f"--{key.replace('_', '-')}={value}" for key, value in options.items()]


def code_of(exception):
    """The exit code the command line gives the failure `exception` stands for."""
    if isinstance(exception, subdiv.NotConvergedError):
        return 3
    if isinstance(exception, subdiv.InputError):
        return 2
    raise exception


@pytest.mark.parametrize("name, method, options", CASES, ids=[f"{c[1]}-{i}" for i, c in enumerate(CASES)])
def test_cli_batch_and_python_agree(tmp_path, cli, name, method, options):
    path = fixture(name)
    # Messages name the mesh as given: the same path everywhere.
    shown = os.path.relpath(path)
    deng_ma = method == "deng-ma"

    # The command line: -o is the control mesh (deng-ma: its surface one level down).
    out = tmp_path / "cli.obj"
    levels = ["--levels", "1"] if deng_ma else []
    done = cli("interpolate", shown, "--method", method, *flags(options), "-o", out, *levels)
    cli_code = done.returncode
    cli_message = done.stderr.strip().removeprefix("subdiv: error: ")

    # The batch: NAME.control.obj (deng-ma: NAME.surface.obj), no surface otherwise.
    batch_dir = tmp_path / "batch"
    try:
        records = subdiv.batch(shown, batch_dir, "interpolate", method=method, levels=1 if deng_ma else 0, **options)
        record = records[0]
        batch_code = 0 if record["error"] is None else record["error"]["exit_code"]
        batch_message = "" if record["error"] is None else record["error"]["message"]
        batch_out = batch_dir / f"{Path(shown).stem}.{'surface' if deng_ma else 'control'}.obj"
    except subdiv.SubdivError as e:  # options refused before any input runs
        batch_code, batch_message, batch_out = code_of(e), str(e), None

    # Python, on the mesh in memory.
    own = {k: options[k] for k in OWN if k in options}
    rest = {k: v for k, v in options.items() if k not in OWN}
    py_out = tmp_path / "python.obj"
    try:
        result = subdiv.interpolate(subdiv.read(shown), method, **own, **rest)
        if deng_ma:
            subdiv.write(result.surface(1), py_out, normals=True)
        else:
            subdiv.write(result.control, py_out)
        py_code, py_message = 0, ""
    except subdiv.SubdivError as e:
        py_code, py_message = code_of(e), str(e)

    assert cli_code == batch_code == py_code, (cli_message, batch_message, py_message)
    if cli_code != 0:
        assert not out.exists() and not py_out.exists()
        assert cli_message == batch_message == py_message
        return
    assert out.read_bytes() == batch_out.read_bytes() == py_out.read_bytes()


def test_the_cases_cover_every_method_and_both_outcomes():
    methods = {method for _, method, _ in CASES}
    assert set(subdiv.methods()) <= methods
    assert len(CASES) >= 30
