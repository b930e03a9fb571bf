//! The hand-made bad inputs of `fixtures/bad/`: errors where the file cannot
//! be read, soups that keep the defect where it can (the validator in
//! subdiv-mesh reports those).

mod common;

use common::{fixture, scratch_dir};
use std::time::{Duration, Instant};
use subdiv_io::{read_mesh, read_mesh_from_bytes, write_mesh, Format, IoError, MeshView};
use subdiv_mesh::{DVec3, FaceList};

fn error(name: &str) -> IoError {
    let e = read_mesh(&fixture(name)).expect_err(name);
    let shown = e.to_string();
    let file = name.rsplit('/').next().unwrap();
    assert!(shown.contains(file), "{shown} does not name {file}");
    if let Some(line) = e.line() {
        assert!(shown.contains(&format!("{file}:{line}: ")), "{shown} does not name line {line}");
    }
    e
}

#[test]
fn empty_files() {
    assert!(matches!(error("bad/empty.obj"), IoError::Empty { .. }));
    assert!(matches!(error("bad/empty.off"), IoError::Empty { .. }));
    for format in Format::ALL {
        let e = read_mesh_from_bytes(b"", format, "e").unwrap_err();
        assert!(matches!(e, IoError::Empty { .. }), "{format}: {e}");
    }
    let e = read_mesh_from_bytes(b"# only a comment\n\n", Format::Obj, "c.obj").unwrap_err();
    assert!(matches!(e, IoError::Empty { .. }), "{e}");
}

#[test]
fn truncated_files_name_the_line_where_they_end() {
    let e = error("bad/truncated.obj");
    assert!(matches!(e, IoError::Truncated { line: Some(6), .. }), "{e}");
    assert!(e.to_string().contains("vertex has 2 coordinates"), "{e}");
    let e = error("bad/truncated.off");
    assert!(matches!(e, IoError::Truncated { line: Some(14), .. }), "{e}");
    assert!(e.to_string().contains("expected 6 faces"), "{e}");
}

#[test]
fn unmappable_obj_indices_name_the_line() {
    let e = error("bad/non_numeric_index.obj");
    assert!(matches!(e, IoError::Parse { line: Some(7), .. }), "{e}");
    assert!(e.to_string().ends_with("non_numeric_index.obj:7: face index 'x' is not an integer"), "{e}");
    let e = error("bad/zero_index.obj");
    assert!(matches!(e, IoError::Parse { line: Some(6), .. }), "{e}");
    assert!(e.to_string().contains("index 0"), "{e}");
}

#[test]
fn unknown_extension_and_missing_file() {
    let dir = scratch_dir("bad_paths");
    assert!(matches!(read_mesh(&dir.join("mesh.xyz")), Err(IoError::UnknownFormat { .. })));
    let e = read_mesh(&dir.join("missing.obj")).unwrap_err();
    assert!(matches!(e, IoError::Io { .. }) && e.to_string().contains("missing.obj"), "{e}");
}

#[test]
fn parseable_defects_are_kept_for_the_validator() {
    let soup = read_mesh(&fixture("bad/out_of_range_index.obj")).unwrap();
    assert_eq!(soup.faces.face(2), &[0, 3, 6]);
    let soup = read_mesh(&fixture("bad/out_of_range_index.off")).unwrap();
    assert_eq!(soup.faces.face(2), &[0, 3, 4]);
    let soup = read_mesh(&fixture("bad/nan_coordinate.obj")).unwrap();
    assert!(soup.positions[3].z.is_nan());
    let soup = read_mesh(&fixture("bad/inf_coordinate.off")).unwrap();
    assert_eq!(soup.positions[1].x, f64::INFINITY);
    let soup = read_mesh(&fixture("bad/face_with_two_vertices.obj")).unwrap();
    assert_eq!(soup.faces.face(4), &[0, 1]);
    let soup = read_mesh(&fixture("bad/degenerate_repeated_index.obj")).unwrap();
    assert_eq!(soup.faces.face(5), &[1, 2, 6, 6]);
    let soup = read_mesh(&fixture("bad/isolated_vertices.obj")).unwrap();
    assert_eq!((soup.positions.len(), soup.faces.len()), (6, 4));
    let soup = read_mesh(&fixture("bad/no_faces.obj")).unwrap();
    assert_eq!((soup.positions.len(), soup.faces.len()), (4, 0));
    let soup = read_mesh(&fixture("bad/duplicate_face.obj")).unwrap();
    assert_eq!(soup.faces.face(3), soup.faces.face(4));
    for (name, faces) in [
        ("degenerate_zero_area.obj", 6),
        ("inconsistent_winding.obj", 6),
        ("nonmanifold_edge_3faces.obj", 3),
        ("nonmanifold_vertex_bowtie.obj", 2),
        ("nonmanifold_vertex_two_tets.obj", 8),
    ] {
        assert_eq!(read_mesh(&fixture(&format!("bad/{name}"))).unwrap().faces.len(), faces, "{name}");
    }
}

#[test]
fn syntax_errors_in_each_text_format_name_file_and_line() {
    let cases: [(&[u8], Format, usize); 7] = [
        (b"v 0 0 0\nv 1 q 0\n", Format::Obj, 2),
        (b"v 0 0 0\nf -2 1 1\n", Format::Obj, 2),
        (b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -2\n", Format::Off, 6),
        (b"OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", Format::Off, 4),
        (b"OFF\n3 x 0\n", Format::Off, 2),
        (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 q\n", Format::PlyAscii, 8),
        (b"solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 x\n", Format::StlAscii, 4),
    ];
    for (src, format, line) in cases {
        let e = read_mesh_from_bytes(src, format, "in.txt").unwrap_err();
        assert_eq!(e.line(), Some(line), "{format}: {e}");
        assert!(e.to_string().starts_with(&format!("in.txt:{line}: ")), "{e}");
    }
}

#[test]
fn huge_header_counts_fail_fast_without_huge_allocations() {
    let mut glb = b"glTF".to_vec();
    glb.extend(2u32.to_le_bytes());
    glb.extend(u32::MAX.to_le_bytes());
    let mut stl = vec![0u8; 80];
    stl.extend(u32::MAX.to_le_bytes());
    let mut binary_off = b"OFF BINARY\n".to_vec();
    [i32::MAX, i32::MAX, 0].iter().for_each(|w| binary_off.extend(w.to_le_bytes()));
    let cases: [(&[u8], Format); 6] = [
        (b"OFF\n999999999999 999999999999 0\n0 0 0\n", Format::Off),
        (b"ply\nformat binary_little_endian 1.0\nelement vertex 18446744073709551615\nproperty double x\nproperty double y\nproperty double z\nelement face 99999999999\nproperty list uint uint vertex_indices\nend_header\n\0\0\0\0\0\0\0\0", Format::PlyBinary),
        (b"ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty double x\nproperty double y\nproperty double z\nelement face 1\nproperty list uint uint vertex_indices\nend_header\n\xff\xff\xff\xff", Format::PlyBinary),
        (&glb, Format::Glb),
        (&stl, Format::StlBinary),
        (&binary_off, Format::Off),
    ];
    for (src, format) in cases {
        let start = Instant::now();
        let result = read_mesh_from_bytes(src, format, "huge");
        assert!(result.is_err(), "{format}");
        assert!(start.elapsed() < Duration::from_secs(1), "{format} took {:?}", start.elapsed());
    }
}

#[test]
fn failed_writes_leave_no_file_behind() {
    let dir = scratch_dir("failed_writes");
    let positions = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let good = FaceList::from_faces([[0u32, 1, 2]]);
    let bad = FaceList::from_faces([[0u32, 1, 5]]);

    // An invalid mesh never touches an existing output.
    let target = dir.join("keep.obj");
    std::fs::write(&target, "old contents").unwrap();
    let e = write_mesh(&target, MeshView::new(&positions, &bad)).unwrap_err();
    assert!(matches!(e, IoError::InvalidMesh { .. }) && e.to_string().contains("keep.obj"), "{e}");
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "old contents");

    // The target is a directory: the rename fails and the temporary file goes.
    let target = dir.join("a_directory.ply");
    std::fs::create_dir(&target).unwrap();
    assert!(matches!(write_mesh(&target, MeshView::new(&positions, &good)), Err(IoError::Io { .. })));

    // A missing directory: nothing is created.
    let e = write_mesh(&dir.join("missing/out.stl"), MeshView::new(&positions, &good)).unwrap_err();
    assert!(matches!(e, IoError::Io { .. }), "{e}");

    let mut left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    left.sort();
    assert_eq!(left, ["a_directory.ply", "keep.obj"]);

    // A successful write replaces the old file whole.
    write_mesh(&dir.join("keep.obj"), MeshView::new(&positions, &good)).unwrap();
    assert_eq!(read_mesh(&dir.join("keep.obj")).unwrap().faces, good);
}

#[test]
fn the_validator_sees_what_the_reader_kept() {
    use subdiv_mesh::{Mesh, MeshError};
    let error = |name: &str| Mesh::from_soup(read_mesh(&fixture(name)).unwrap()).map(|_| ()).unwrap_err();
    assert!(matches!(error("bad/out_of_range_index.obj"), MeshError::IndexOutOfRange { vertex: 6, .. }));
    assert!(matches!(error("bad/out_of_range_index.off"), MeshError::IndexOutOfRange { vertex: 4, .. }));
    assert!(matches!(error("bad/nan_coordinate.obj"), MeshError::NonFiniteCoordinate { vertex: 3, .. }));
    assert!(matches!(error("bad/inf_coordinate.off"), MeshError::NonFiniteCoordinate { vertex: 1, .. }));
    assert!(matches!(error("bad/face_with_two_vertices.obj"), MeshError::FaceTooSmall { face: 4, size: 2 }));
    assert!(matches!(error("bad/degenerate_repeated_index.obj"), MeshError::RepeatedIndex { face: 5, vertex: 6 }));
    assert!(matches!(error("bad/no_faces.obj"), MeshError::NoFaces));
    // And the good fixtures pass it.
    for name in ["canonical/torus_quad_16x8.obj", "poly/mpi.off", "open/fairing-cross.off"] {
        assert!(Mesh::from_soup(read_mesh(&fixture(name)).unwrap()).is_ok(), "{name}");
    }
}
