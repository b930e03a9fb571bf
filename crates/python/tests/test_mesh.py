"""subdiv.Mesh: NumPy in and out, uniform and mixed faces, CSR, validation messages."""

import numpy as np
import pytest

import subdiv
from conftest import fixture, torus

TETRA_V = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
TETRA_F = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
# A square pyramid: four triangles and the quad base (mixed faces).
PYRAMID_V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 1.0]])
PYRAMID_F = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4], [0, 3, 2, 1]]


def test_uniform_round_trip():
    X, F = torus(12, 8)
    mesh = subdiv.Mesh(X, F)
    assert (mesh.n_vertices, mesh.n_faces) == (96, 96)
    v = mesh.vertices
    assert v.dtype == np.float64 and v.shape == (96, 3)
    assert np.array_equal(v, X)
    assert mesh.faces.dtype == np.int64
    assert np.array_equal(mesh.faces, F)
    assert repr(mesh) == "Mesh(96 vertices, 96 faces)"


def test_mixed_faces_and_csr():
    mesh = subdiv.Mesh(PYRAMID_V, PYRAMID_F)
    faces = mesh.faces
    assert isinstance(faces, list) and [f.tolist() for f in faces] == PYRAMID_F
    offsets, indices = mesh.face_offsets, mesh.face_indices
    assert offsets.tolist() == [0, 3, 6, 9, 12, 16]
    assert indices.tolist() == sum(PYRAMID_F, [])
    again = subdiv.Mesh.from_csr(mesh.vertices, offsets, indices)
    assert np.array_equal(again.vertices, PYRAMID_V.astype(np.float64))
    assert [f.tolist() for f in again.faces] == PYRAMID_F


def test_input_layouts():
    # int32 faces, float32 and Fortran-ordered vertices, plain lists: all the same mesh.
    reference = subdiv.Mesh(TETRA_V, TETRA_F)
    for v, f in [
        (TETRA_V.astype(np.float32), TETRA_F.astype(np.int32)),
        (np.asfortranarray(TETRA_V), TETRA_F.astype(np.uint64)),
        (TETRA_V.tolist(), TETRA_F.tolist()),
        (np.hstack([TETRA_V, 0 * TETRA_V])[:, :3], TETRA_F),  # a strided view
    ]:
        mesh = subdiv.Mesh(v, f)
        assert np.array_equal(mesh.vertices, reference.vertices)
        assert np.array_equal(mesh.faces, reference.faces)


def test_vertices_are_a_copy():
    X, F = torus(6, 4)
    mesh = subdiv.Mesh(X, F)
    X[0] = 99.0
    assert not np.array_equal(mesh.vertices, X)
    out = mesh.vertices
    out[0] = 42.0
    assert mesh.vertices[0, 0] != 42.0


@pytest.mark.parametrize(
    "faces, message",
    [
        ([[0, 1, 7]], "face 0 refers to vertex 7, but there are only 4 vertices"),
        ([[0, 1, -1]], "face 0: vertex index -1 is negative"),
        (np.array([[0, 1, 2], [0, 1, -5]]), "face 1: vertex index -5 is negative"),  # contiguous
        (np.array([[2, 1, 0], [-3, 1, 0]])[:, ::-1], "face 1: vertex index -3 is negative"),  # strided
        (np.array([[0.0, 1.0, 2.0]]), "faces must be integer vertex indices"),
        ([[0, 1]], "face 0"),
        ("abc", r"faces must be an \(m, k\) integer array or a list of sequences, got str"),
    ],
)
def test_bad_faces(faces, message):
    with pytest.raises(ValueError, match=message) as raised:
        subdiv.Mesh(TETRA_V, faces)
    assert isinstance(raised.value, subdiv.InputError)
    assert isinstance(raised.value, subdiv.SubdivError)


def test_bad_vertices():
    with pytest.raises(ValueError, match=r"vertices must be an \(n, 3\) array, got shape \(4, 2\)"):
        subdiv.Mesh(TETRA_V[:, :2], TETRA_F)
    bad = TETRA_V.copy()
    bad[2, 1] = np.nan
    with pytest.raises(ValueError, match="vertex 2"):
        subdiv.Mesh(bad, TETRA_F)


def test_nonmanifold_message_is_the_library_one():
    # Three triangles on the edge (0, 1).
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0, -1, 0]], dtype=float)
    with pytest.raises(ValueError, match=r"edge \(0, 1\) is shared by 3 faces"):
        subdiv.Mesh(v, [[0, 1, 2], [1, 0, 3], [0, 1, 4]])


def test_a_non_manifold_file_reads_as_its_own_vertices_and_faces():
    # A file is read as the command line reads it (refined as OpenSubdiv does, through the
    # manifold cover); the arrays are the file's: three triangles on the edge (0, 1).
    path = fixture("bad/nonmanifold_edge_3faces.obj")
    with pytest.warns(UserWarning, match="non-manifold"):
        mesh = subdiv.read(path)
    assert mesh.n_vertices == len(mesh.vertices) == 5
    assert [list(f) for f in mesh.faces] == [[0, 1, 2], [1, 0, 3], [0, 1, 4]]
    refined = subdiv.subdivide(mesh, "loop", 1)
    assert refined.n_vertices == 5 + 7  # a vertex per input vertex and per edge, as OpenSubdiv


def test_isolated_vertex_warns():
    v = np.vstack([TETRA_V, [[5.0, 5.0, 5.0]]])
    with pytest.warns(UserWarning, match="isolated"):
        mesh = subdiv.Mesh(v, TETRA_F)
    assert mesh.n_vertices == 5


def test_uvs_and_tags_from_a_file():
    mesh = subdiv.read(fixture("quad/spot_control_mesh.obj"))
    values, indices = mesh.uvs
    assert values.shape[1] == 2 and indices.shape == mesh.face_indices.shape
    assert indices.max() < len(values)
    assert subdiv.Mesh(TETRA_V, TETRA_F).uvs is None
    assert subdiv.Mesh(TETRA_V, TETRA_F).tags is None


def test_tags_read_from_obj(tmp_path):
    # A cube whose top ring is an infinitely sharp crease and one corner tagged, in OpenSubdiv's
    # OBJ tag lines (0-based vertices).
    v = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]
    f = [[1, 4, 3, 2], [5, 6, 7, 8], [1, 2, 6, 5], [2, 3, 7, 6], [3, 4, 8, 7], [4, 1, 5, 8]]
    lines = [f"v {x} {y} {z}" for x, y, z in v] + ["f " + " ".join(map(str, face)) for face in f]
    lines += ["t crease 2/1/0 4 5 10", "t crease 2/1/0 5 6 10", "t corner 1/1/0 0 3"]
    path = tmp_path / "cube.obj"
    path.write_text("\n".join(lines) + "\n")
    mesh = subdiv.read(path)
    tags = mesh.tags
    assert sorted((min(a, b), max(a, b), s) for a, b, s in tags["creases"]) == [(4, 5, 10.0), (5, 6, 10.0)]
    assert tags["corners"] == [(0, 3.0)]
    assert "2 creases, 1 corners" in repr(mesh)


def test_tags_and_uvs_given_in_memory_round_trip():
    """`Mesh(..., tags=, uvs=)` takes what `tags` and `uvs` return: the file's mesh again."""
    read = subdiv.read(fixture("quad/spot_control_mesh.obj"))
    corners = read.face_indices
    tags = {"creases": [(int(corners[k]), int(corners[k + 1]), 2.5) for k in (0, 4, 8)], "corners": [(7, 10.0)]}
    mesh = subdiv.Mesh(read.vertices, read.faces, tags=tags, uvs=read.uvs)
    assert mesh.tags["corners"] == [(7, 10.0)]
    assert sorted(mesh.tags["creases"]) == sorted(tags["creases"])
    again = subdiv.Mesh.from_csr(mesh.vertices, mesh.face_offsets, mesh.face_indices, tags=mesh.tags, uvs=mesh.uvs)
    for a, b in zip(again.uvs, read.uvs):
        np.testing.assert_array_equal(a, b)
    assert again.tags == mesh.tags
    # The tags change the surface as a file's would.
    plain = subdiv.subdivide(subdiv.Mesh(read.vertices, read.faces), levels=1).vertices
    assert not np.allclose(subdiv.subdivide(mesh, levels=1).vertices, plain)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"tags": {"creases": [(0, 7, 10.0)]}}, "vertex 7"),
        ({"tags": {"creases": [(0, 1, -1.0)]}}, "sharpness"),
        ({"tags": {"corners": [(-1, 1.0)]}}, "out of range"),
        ({"tags": {"holes": [0]}}, "unknown key"),
        ({"tags": [(0, 1, 1.0)]}, "must be a dict"),
        ({"uvs": (np.zeros((1, 2)), np.zeros(5, dtype=np.int64))}, "corner"),
        ({"uvs": (np.zeros((1, 2)), np.ones(12, dtype=np.int64))}, "texture coordinate 1"),
        ({"uvs": (np.zeros((1, 3)), np.zeros(12, dtype=np.int64))}, r"\(p, 2\)"),
    ],
)
def test_bad_tags_and_uvs(kwargs, message):
    with pytest.raises(subdiv.InputError, match=message):
        subdiv.Mesh(TETRA_V, TETRA_F, **kwargs)
