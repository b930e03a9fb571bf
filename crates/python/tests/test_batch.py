"""subdiv.batch, subdiv.info and subdiv.dask.map_files against the command line and each other."""

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

import subdiv
import subdiv.dask

from conftest import FIXTURES


def cli_binary():
    exe = os.environ.get("SUBDIV_CLI")
    return exe if exe and Path(exe).is_file() else None

GOOD = sorted((FIXTURES / "quad").glob("*.obj")) + sorted((FIXTURES / "tri").glob("*.obj"))
BAD = [FIXTURES / "bad" / "nan_coordinate.obj", FIXTURES / "bad" / "face_with_two_vertices.obj"]


def without_timings(record):
    """A record without what differs between two runs of the same job: times, the output
    directory, and whether it was resumed."""
    r = json.loads(json.dumps(record))
    r.pop("seconds", None)
    r.pop("skipped", None)
    r["outputs"] = [os.path.basename(p) for p in r["outputs"]]
    if isinstance(r.get("report"), dict):
        r["report"].pop("timing_ms", None)
    return r


def test_info_is_the_cli_json(tmp_path):
    mesh = subdiv.read(FIXTURES / "quad" / "spot_control_mesh.obj")
    summary = subdiv.info(mesh)
    assert summary["vertices"] == mesh.n_vertices and summary["faces"] == mesh.n_faces
    cli = cli_binary()
    if cli is None:
        pytest.skip("SUBDIV_CLI is not set")
    out = subprocess.run([cli, "info", "--json", str(FIXTURES / "quad" / "spot_control_mesh.obj")],
                         check=True, capture_output=True, text=True).stdout
    assert summary == json.loads(out)


def test_batch_isolates_failures_and_resumes(tmp_path):
    inputs = [str(p) for p in GOOD[:4] + BAD]
    out = tmp_path / "out"
    records = subdiv.batch(inputs, out, "interpolate", method="cheng", levels=1)
    assert [r["input"] for r in records] == inputs
    assert [r["index"] for r in records] == list(range(len(inputs)))
    for r in records[:4]:
        assert r["error"] is None and len(r["outputs"]) == 2, r
        assert all(os.path.exists(p) for p in r["outputs"])
        assert r["report"]["error"]["max_rel"] <= 1e-6
    for r in records[4:]:
        assert r["error"]["exit_code"] == 2 and r["error"]["message"], r
    stamps = {p: os.stat(p).st_mtime_ns for r in records for p in r["outputs"]}
    again = subdiv.batch(inputs, out, "interpolate", method="cheng", levels=1)
    assert all(r["skipped"] for r in again)
    assert [without_timings(r) for r in again] == [without_timings(r) for r in records]
    assert {p: os.stat(p).st_mtime_ns for p in stamps} == stamps


def test_batch_equals_the_cli_batch(tmp_path):
    cli = cli_binary()
    if cli is None:
        pytest.skip("SUBDIV_CLI is not set")
    inputs = [str(p) for p in GOOD[:3] + BAD[:1]]
    ours = subdiv.batch(inputs, tmp_path / "py", "subdivide", scheme="catmull-clark", levels=2)
    run = subprocess.run([cli, "batch", "subdivide", *inputs, "--out-dir", str(tmp_path / "cli"),
                          "--scheme", "catmull-clark", "--levels", "2"], capture_output=True, text=True)
    assert run.returncode == 5, run.stderr  # one input failed
    theirs = [json.loads(line) for line in run.stdout.splitlines()]
    assert [without_timings(r) for r in ours] == [without_timings(r) for r in theirs]
    for r in ours:
        for p in r["outputs"]:
            assert Path(p).read_bytes() == (tmp_path / "cli" / os.path.basename(p)).read_bytes()


def test_batch_rejects_a_misspelled_option(tmp_path):
    with pytest.raises(ValueError, match="levles"):
        subdiv.batch([str(GOOD[0])], tmp_path, "interpolate", method="cheng", levles=2)
    with pytest.raises(ValueError, match="unknown command"):
        subdiv.batch([str(GOOD[0])], tmp_path, "interpolat")


def test_dask_local_cluster_equals_serial(tmp_path):
    distributed = pytest.importorskip("distributed")
    meshes = tmp_path / "meshes"
    meshes.mkdir()
    # At least 20 meshes: the fixtures, plus copies under other names.
    sources = GOOD + BAD
    for i in range(max(22, len(sources))):
        src = sources[i % len(sources)]
        shutil.copy(src, meshes / f"{i:02d}-{src.name}")
    pattern = str(meshes / "*.obj")
    serial = subdiv.batch(pattern, tmp_path / "serial", "interpolate", method="cheng", levels=1)
    assert len(serial) >= 20
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        records = subdiv.dask.map_files(pattern, tmp_path / "dask", "interpolate", client=client,
                                        method="cheng", levels=1)
        again = subdiv.dask.map_files(pattern, tmp_path / "dask", "interpolate", client=client,
                                      method="cheng", levels=1)
    assert [without_timings(r) for r in records] == [without_timings(r) for r in serial]
    assert all(r["skipped"] for r in again)
    assert any(r["error"] for r in records) and any(not r["error"] for r in records)
