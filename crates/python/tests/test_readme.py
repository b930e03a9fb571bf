"""The README's Python quickstart runs as written (from the repository root)."""

import os
import re

import pytest

from conftest import REPO


def test_readme_quickstart(tmp_path, monkeypatch):
    readme = REPO / "README.md"
    if not readme.exists():
        pytest.skip("no README (not a checkout)")
    text = readme.read_text()
    section = text.split("\n## Python\n", 1)
    assert len(section) == 2, "the README has a '## Python' section"
    blocks = re.findall(r"```python\n(.*?)```", section[1].split("\n## ", 1)[0], re.S)
    assert blocks, "the Python section has a python code block"
    monkeypatch.chdir(REPO)
    code = blocks[0].replace('"spot-surface.ply"', repr(str(tmp_path / "spot-surface.ply")))
    scope = {}
    exec(compile(code, "README.md", "exec"), scope)
    assert (tmp_path / "spot-surface.ply").exists()
    # The limit-surface block goes on from the quickstart's `mesh`.
    surface = [b for b in blocks if "subdiv.fit(" in b]
    assert surface, "the Python section shows evaluate/sample/project/fit"
    exec(compile(surface[0], "README.md", "exec"), scope)
    assert scope["at"]["position"].shape == (2, 3)
    assert (scope["near"]["distance"] > 0).all()
    # The fit it shows last (the partial scan) reaches the bar from the designer's mesh
    # (RMS ≤ 1e-3·d, d the scan's bounding-box diagonal).
    vertices = scope["scan"]
    d = float(((vertices.max(0) - vertices.min(0)) ** 2).sum() ** 0.5)
    assert abs(scope["last"]["scale"] - d) <= 1e-12 * d
    assert scope["last"]["rms_target_to_surface"] <= 1e-3 * d


def test_readme_collections(tmp_path, monkeypatch):
    """The README's local batch example runs on the fixtures (the cluster one needs a cluster)."""
    readme = REPO / "README.md"
    if not readme.exists():
        pytest.skip("no README (not a checkout)")
    section = readme.read_text().split("\n## Python\n", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```python\n(.*?)```", section, re.S)
    local = [b for b in blocks if "subdiv.batch(" in b]
    assert local, "the Python section shows collections"
    monkeypatch.chdir(REPO)
    code = local[0].replace('"scans/*.obj"', '"fixtures/quad/*.obj"').replace('"out"', repr(str(tmp_path)))
    scope = {}
    exec(compile(code, "README.md", "exec"), scope)
    assert scope["records"] and not scope["failed"]
