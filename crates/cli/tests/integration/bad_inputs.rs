//! Every file in `fixtures/bad/`: the library reports the specific defect, and
//! `subdiv info` exits 2 with a one-line message naming the file (no panic).
//! Warning-level defects (isolated vertices, zero-area faces, non-manifold
//! edges and vertices, which are refined as OpenSubdiv does) load with a
//! warning (exit 0) and fail under `--strict` (exit 2).

use crate::common::{assert_no_panic, fixtures, subdiv};
use subdiv_io::IoError;
use subdiv_mesh::{Mesh, MeshError, Warning};

/// What each bad file must produce.
enum Expect {
    Io(fn(&IoError) -> bool),
    Mesh(fn(&MeshError) -> bool),
    Warn(fn(&Warning) -> bool),
}

fn expectations() -> Vec<(&'static str, Expect)> {
    use Expect::*;
    vec![
        ("absolute_uri.gltf", Io(|e| matches!(e, IoError::RefusedUri { .. }))),
        ("all_vertices_coincide.obj", Mesh(|e| matches!(e, MeshError::AllVerticesCoincide { vertices: 4, .. }))),
        ("binary_garbage.obj", Io(|e| matches!(e, IoError::BinaryData { .. }))),
        ("degenerate_repeated_index.obj", Warn(|w| matches!(w, Warning::NonManifold(r) if r.vertices.contains(&6)))),
        ("degenerate_zero_area.obj", Warn(|w| matches!(w, Warning::ZeroAreaFaces { faces } if faces.len() == 1))),
        ("duplicate_face.obj", Warn(|w| matches!(w, Warning::NonManifold(_)))),
        ("empty.obj", Io(|e| matches!(e, IoError::Empty { .. }))),
        ("empty.off", Io(|e| matches!(e, IoError::Empty { .. }))),
        ("face_with_two_vertices.obj", Mesh(|e| matches!(e, MeshError::FaceTooSmall { face: 4, size: 2 }))),
        ("inconsistent_winding.obj", Warn(|w| matches!(w, Warning::NonManifold(_)))),
        ("index_too_large.obj", Io(|e| e.to_string().contains("99999999999999999999 out of range"))),
        (
            "inf_coordinate.off",
            Mesh(
                |e| matches!(e, MeshError::NonFiniteCoordinate { x, y, z, .. } if x.is_infinite() || y.is_infinite() || z.is_infinite()),
            ),
        ),
        ("isolated_vertices.obj", Warn(|w| matches!(w, Warning::IsolatedVertices { vertices } if vertices.len() == 2))),
        ("lines_only.gltf", Io(|e| e.to_string().contains("no triangle primitives"))),
        (
            "nan_coordinate.obj",
            Mesh(
                |e| matches!(e, MeshError::NonFiniteCoordinate { x, y, z, .. } if x.is_nan() || y.is_nan() || z.is_nan()),
            ),
        ),
        ("no_faces.obj", Mesh(|e| matches!(e, MeshError::NoFaces))),
        ("non_numeric_index.obj", Io(|e| matches!(e, IoError::Parse { line: Some(_), .. }))),
        ("nonmanifold_edge_3faces.obj", Warn(|w| matches!(w, Warning::NonManifold(r) if r.edges == [[0, 1]]))),
        (
            "nonmanifold_vertex_bowtie.obj",
            Warn(|w| matches!(w, Warning::NonManifold(r) if r.edges.is_empty() && r.vertices.len() == 1)),
        ),
        (
            "nonmanifold_vertex_two_tets.obj",
            Warn(|w| matches!(w, Warning::NonManifold(r) if r.edges.is_empty() && r.vertices.len() == 1)),
        ),
        (
            "out_of_range_index.obj",
            Mesh(|e| matches!(e, MeshError::IndexOutOfRange { vertex: 6, vertex_count: 4, .. })),
        ),
        (
            "out_of_range_index.off",
            Mesh(|e| matches!(e, MeshError::IndexOutOfRange { vertex: 4, vertex_count: 4, .. })),
        ),
        ("truncated.obj", Io(|e| matches!(e, IoError::Parse { line: Some(_), .. } | IoError::Truncated { .. }))),
        ("truncated.off", Io(|e| matches!(e, IoError::Truncated { .. }))),
        ("utf16.obj", Io(|e| matches!(e, IoError::Utf16 { .. }))),
        ("zero_index.obj", Io(|e| matches!(e, IoError::Parse { line: Some(_), .. }))),
    ]
}

#[test]
fn every_bad_fixture_is_covered() {
    let mut on_disk: Vec<String> = std::fs::read_dir(fixtures().join("bad"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    on_disk.sort();
    let expected: Vec<String> = expectations().iter().map(|(f, _)| f.to_string()).collect();
    assert_eq!(on_disk, expected, "fixtures/bad and this test must list the same files");
}

#[test]
fn library_reports_the_specific_defect() {
    for (file, expect) in expectations() {
        let path = fixtures().join("bad").join(file);
        let read = subdiv_io::read_mesh(&path);
        match expect {
            Expect::Io(ok) => {
                let e = read.expect_err(file);
                assert!(ok(&e), "{file}: unexpected read error {e:?}");
                assert!(e.to_string().contains(file), "{file}: message must name the file: {e}");
            }
            Expect::Mesh(ok) => {
                let soup = read.unwrap_or_else(|e| panic!("{file} must parse: {e}"));
                let e = Mesh::from_soup_covering(soup).expect_err(file);
                assert!(ok(&e), "{file}: unexpected validation error {e:?}");
            }
            Expect::Warn(ok) => {
                let soup = read.unwrap_or_else(|e| panic!("{file} must parse: {e}"));
                // As the tool loads a file: non-manifold soups through their manifold cover.
                let (_, warnings) = Mesh::from_soup_covering(soup).unwrap_or_else(|e| panic!("{file} must load: {e}"));
                assert!(warnings.iter().any(ok), "{file}: missing warning in {warnings:?}");
            }
        }
    }
}

#[test]
fn info_exits_2_with_a_one_line_message() {
    for (file, expect) in expectations() {
        let path = fixtures().join("bad").join(file);
        let path = path.to_str().unwrap();
        let out = subdiv(&["info", path]);
        assert_no_panic(&out);
        let stderr = String::from_utf8_lossy(&out.stderr);
        match expect {
            Expect::Warn(_) => {
                assert_eq!(out.status.code(), Some(0), "{file}: {stderr}");
                assert!(String::from_utf8_lossy(&out.stdout).contains("warning:"), "{file}");
                let strict = subdiv(&["info", "--strict", path]);
                assert_no_panic(&strict);
                assert_eq!(strict.status.code(), Some(2), "{file} --strict");
            }
            _ => {
                assert_eq!(out.status.code(), Some(2), "{file}: {stderr}");
                assert_eq!(stderr.trim_end().lines().count(), 1, "{file}: one line: {stderr}");
                assert!(stderr.contains(file), "{file}: message must name the file: {stderr}");
            }
        }
    }
}

#[test]
fn info_on_missing_file_or_unknown_format_is_bad_input() {
    let out = subdiv(&["info", "/nonexistent/mesh.obj"]);
    assert_eq!(out.status.code(), Some(2));
    assert_no_panic(&out);
    let out = subdiv(&["info", fixtures().join("README.md").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert_no_panic(&out);
    let out = subdiv(&["info"]);
    assert_eq!(out.status.code(), Some(2), "missing argument is a usage error");
}
