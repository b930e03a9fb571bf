"""``subdiv.fit`` (issue #42): Gauss-Newton recovery, partial targets, noise, the options
refused as on the command line, the report fields."""

import math

import numpy as np
import pytest

import subdiv
from conftest import fixture


def _start(control, fraction=0.02, seed=5):
    rng = np.random.default_rng(seed)
    d = np.linalg.norm(control.vertices.max(0) - control.vertices.min(0))
    dirs = rng.standard_normal(control.vertices.shape)
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    return subdiv.Mesh(control.vertices + fraction * d * dirs, control.faces), d


def test_fit_recovers_in_few_rounds_and_reports_the_stop():
    control = subdiv.read(fixture("canonical/cube_quad.obj"))
    target = subdiv.subdivide(control, "catmull-clark", levels=4, limit=True)
    start, d = _start(control)
    fitted, history = subdiv.fit(target, start)
    assert history[-1]["max_target_to_surface"] <= 1e-6 * d
    assert history[-1]["iteration"] <= 30
    assert history[-1]["method"] == "gauss-newton"
    assert history[-1]["stop"] in ("exact", "tolerance", "relative-improvement", "max-rounds")
    assert history[-1]["regularised_vertices"] == []
    # Independent of the fit's distances: the fitted surface's limit points are the target's.
    again = subdiv.subdivide(fitted, "catmull-clark", levels=4, limit=True).vertices
    assert np.abs(again - target.vertices).max() <= 1e-6 * d


def test_lspia_stays_as_an_option_and_is_slower():
    control = subdiv.read(fixture("canonical/cube_quad.obj"))
    target = subdiv.subdivide(control, "catmull-clark", levels=3, limit=True).vertices
    start, _ = _start(control)
    _, gn = subdiv.fit(target, start)
    _, lspia = subdiv.fit(target, start, method="lspia")
    assert lspia[-1]["method"] == "lspia"
    assert gn[-1]["rms_target_to_surface"] <= lspia[-1]["rms_target_to_surface"]


def test_a_partial_cloud_regularises_the_unsupported_vertices():
    control = subdiv.read(fixture("canonical/torus_quad_16x8.obj"))
    target = subdiv.subdivide(control, "catmull-clark", levels=3, limit=True).vertices
    part = target[target[:, 0] > 0.2 * target[:, 0].max()]
    start, _ = _start(control, 0.005)
    fitted, history = subdiv.fit(part, start, loss="huber")
    assert history[-1]["loss"] == "huber"
    assert len(history[-1]["regularised_vertices"]) > 0
    assert np.isfinite(fitted.vertices).all()


@pytest.mark.parametrize(
    "kwargs",
    [
        {"tolerance": math.nan},
        {"tolerance": -1.0},
        {"smoothness": math.nan},
        {"smoothness": -1.0},
        {"min_improvement": math.nan},
        {"max_time": 0.0},
        {"method": "newton"},
        {"loss": "tukey"},
        {"method": "tangent", "lambda_": math.nan},
    ],
)
def test_bad_options_are_input_errors(kwargs):
    control = subdiv.read(fixture("canonical/cube_quad.obj"))
    target = subdiv.subdivide(control, "catmull-clark", levels=2, limit=True).vertices
    with pytest.raises(subdiv.InputError):
        subdiv.fit(target, control, **kwargs)


def test_extreme_scales_are_finite_and_correct():
    control = subdiv.read(fixture("canonical/cube_quad.obj"))
    target = subdiv.subdivide(control, "catmull-clark", levels=3, limit=True).vertices
    start, _ = _start(control)
    for s in (1e150, 1e-200):
        scaled = subdiv.Mesh(start.vertices * s, start.faces)
        fitted, history = subdiv.fit(target * s, scaled)
        assert np.isfinite(fitted.vertices).all()
        assert history[-1]["iteration"] >= 1
        assert history[-1]["max_target_to_surface"] <= 1e-6 * history[-1]["scale"]
