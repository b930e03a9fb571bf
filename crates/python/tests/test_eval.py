"""The limit surface between the data points from Python: evaluate, sample, project, fit."""

import numpy as np
import pytest

import subdiv
from conftest import fixture


def test_evaluate_at_face_corners_is_the_limit_position_of_the_corner_vertex():
    # Independent of the evaluator: subdivide's limit rules (levels 0, limit=True).
    mesh = subdiv.read(fixture("canonical/cube_quad.obj"))
    limit = subdiv.subdivide(mesh, "catmull-clark", levels=0, limit=True).vertices
    faces = mesh.faces
    corners = [(0.0, 0.0, 0), (1.0, 0.0, 1), (1.0, 1.0, 2), (0.0, 1.0, 3)]
    params = np.array([[f, u, v] for f in range(len(faces)) for (u, v, _) in corners])
    out = subdiv.evaluate(mesh, params)
    expected = np.array([limit[faces[f][k]] for f in range(len(faces)) for (_, _, k) in corners])
    d = np.linalg.norm(mesh.vertices.max(0) - mesh.vertices.min(0))
    assert np.abs(out["position"] - expected).max() <= 1e-12 * d
    assert np.allclose(np.linalg.norm(out["normal"], axis=1), 1.0)
    # Outward normals on the cube (centred at its centroid).
    centre = mesh.vertices.mean(0)
    assert (np.einsum("ij,ij->i", out["normal"], out["position"] - centre) > 0).all()


def test_derivatives_match_central_differences():
    mesh = subdiv.read(fixture("canonical/cube_quad.obj"))
    h = 1e-6
    at = lambda u, v: subdiv.evaluate(mesh, np.array([[2, u, v]]))
    centre = at(0.3, 0.6)
    du = (at(0.3 + h, 0.6)["position"] - at(0.3 - h, 0.6)["position"]) / (2 * h)
    dv = (at(0.3, 0.6 + h)["position"] - at(0.3, 0.6 - h)["position"]) / (2 * h)
    assert np.allclose(centre["du"], du, atol=1e-6)
    assert np.allclose(centre["dv"], dv, atol=1e-6)


def test_samples_project_back_onto_themselves():
    mesh = subdiv.read(fixture("canonical/torus_quad_16x8.obj"))
    samples = subdiv.sample(mesh, per_face=2)
    assert samples["position"].shape == (4 * 16 * 8, 3)
    found = subdiv.project(mesh, samples["position"])
    d = np.linalg.norm(mesh.vertices.max(0) - mesh.vertices.min(0))
    assert found["distance"].max() <= 1e-9 * d
    assert np.abs(found["position"] - samples["position"]).max() <= 1e-9 * d
    by_area = subdiv.sample(mesh, count=300, seed=3)
    again = subdiv.sample(mesh, count=300, seed=3)
    assert np.array_equal(by_area["position"], again["position"])


def test_fit_recovers_a_perturbed_control_mesh():
    control = subdiv.read(fixture("canonical/cube_quad.obj"))
    target = subdiv.subdivide(control, "catmull-clark", levels=3, limit=True).vertices
    rng = np.random.default_rng(5)
    d = np.linalg.norm(control.vertices.max(0) - control.vertices.min(0))
    start = subdiv.Mesh(control.vertices + 0.02 * d * rng.standard_normal(control.vertices.shape), control.faces)
    fitted, history = subdiv.fit(target, start, iterations=60)
    assert history[0]["rms_target_to_surface"] > history[-1]["rms_target_to_surface"]
    assert history[-1]["max_target_to_surface"] <= 1e-6 * d
    # Measured without the fit's own distances: the same refinement of the fitted mesh lands on
    # the target. (Not the control points themselves: on the cube, alternating ±c at the
    # vertices changes no limit point — the valence-3 vertex rule gives the vertex weight 0.)
    again = subdiv.subdivide(fitted, "catmull-clark", levels=3, limit=True).vertices
    assert np.abs(again - target).max() <= 1e-6 * d


def test_bad_parameters_are_input_errors():
    mesh = subdiv.read(fixture("canonical/cube_quad.obj"))
    with pytest.raises(subdiv.InputError):
        subdiv.evaluate(mesh, np.array([[99, 0.5, 0.5]]))
    with pytest.raises(subdiv.InputError):
        subdiv.evaluate(mesh, np.array([[0, 1.5, 0.5]]))
    with pytest.raises(subdiv.InputError):
        subdiv.evaluate(mesh, np.array([[0, 0.5]]))
    with pytest.raises(subdiv.InputError):
        subdiv.sample(mesh)
    with pytest.raises(subdiv.InputError):
        subdiv.evaluate(mesh, np.array([[0, 0.5, 0.5]]), scheme="bogus")
