//! The hand-made bad inputs of `fixtures/bad/`: errors where the file cannot
//! be read, soups that keep the defect where it can (the validator in
//! subdiv-mesh reports those).

use crate::common;

use crate::common::{fixture, scratch_dir};
use std::time::{Duration, Instant};
use subdiv_io::{read_mesh, read_mesh_from_bytes, write_mesh_view, Format, IoError, MeshView};
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
    let e = write_mesh_view(&target, MeshView::new(&positions, &bad)).unwrap_err();
    assert!(matches!(e, IoError::InvalidMesh { .. }) && e.to_string().contains("keep.obj"), "{e}");
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "old contents");

    // The target is a directory: refused before a temporary file is made (the one destination
    // check of staging).
    let target = dir.join("a_directory.ply");
    std::fs::create_dir(&target).unwrap();
    let e = write_mesh_view(&target, MeshView::new(&positions, &good)).unwrap_err();
    assert!(matches!(e, IoError::NotAFile { kind: "a directory", .. }), "{e}");

    // A missing directory: nothing is created.
    let e = write_mesh_view(&dir.join("missing/out.stl"), MeshView::new(&positions, &good)).unwrap_err();
    assert!(matches!(e, IoError::Io { .. }), "{e}");

    let mut left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    left.sort();
    assert_eq!(left, ["a_directory.ply", "keep.obj"]);

    // A successful write replaces the old file whole.
    write_mesh_view(&dir.join("keep.obj"), MeshView::new(&positions, &good)).unwrap();
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

/// Bytes from a fixed xorshift sequence: "random" data without a dependency.
fn random_bytes(n: usize, mut seed: u64) -> Vec<u8> {
    (0..n)
        .map(|_| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 32) as u8
        })
        .collect()
}

/// A triangle written in every format that has a text form (and binary PLY,
/// whose header is text).
fn triangle_files() -> Vec<(Format, Vec<u8>)> {
    let positions = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let faces = FaceList::from_faces([[0u32, 1, 2]]);
    [Format::Obj, Format::Off, Format::PlyAscii, Format::PlyBinary, Format::StlAscii, Format::Gltf]
        .into_iter()
        .map(|f| (f, subdiv_io::write_mesh_to_vec(MeshView::new(&positions, &faces), f).unwrap()))
        .collect()
}

#[test]
fn utf8_bom_is_skipped_in_every_text_format() {
    // Regression: "\u{feff}v" was an unknown statement, so the first vertex was lost.
    let src = "\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let soup = read_mesh_from_bytes(src.as_bytes(), Format::Obj, "bom.obj").unwrap();
    assert_eq!(soup.positions, [DVec3::ZERO, DVec3::X, DVec3::Y]);
    assert_eq!(soup.faces.face(0), &[0, 1, 2]);
    for (format, bytes) in triangle_files() {
        let plain = read_mesh_from_bytes(&bytes, format, "plain").unwrap();
        let with_bom = [&b"\xEF\xBB\xBF"[..], &bytes].concat();
        let soup = read_mesh_from_bytes(&with_bom, format, "bom").unwrap_or_else(|e| panic!("{format}: {e}"));
        assert_eq!(soup, plain, "{format}");
    }
}

#[test]
fn utf16_text_is_reported_as_utf16_in_every_text_format() {
    for (format, bytes) in triangle_files() {
        if format == Format::PlyBinary {
            continue;
        }
        let little: Vec<u8> = bytes.iter().flat_map(|&b| [b, 0]).collect();
        let big: Vec<u8> = bytes.iter().flat_map(|&b| [0, b]).collect();
        for (what, data) in [
            ("LE with BOM", [&b"\xFF\xFE"[..], &little].concat()),
            ("BE with BOM", [&b"\xFE\xFF"[..], &big].concat()),
            ("LE without BOM", little.clone()),
            ("BE without BOM", big.clone()),
        ] {
            let e = read_mesh_from_bytes(&data, format, "wide.txt").unwrap_err();
            assert!(matches!(e, IoError::Utf16 { .. }), "{format} {what}: {e}");
            assert_eq!(e.to_string(), "wide.txt: UTF-16 text is not supported; save the file as UTF-8");
        }
    }
}

#[test]
fn binary_data_in_a_text_format_is_reported_as_binary_not_empty() {
    let noise = random_bytes(4096, 0x5eed);
    for (format, name) in [
        (Format::Obj, "an OBJ file"),
        (Format::Off, "an OFF file"),
        (Format::PlyAscii, "a PLY file"),
        (Format::PlyBinary, "a PLY file"),
        (Format::Gltf, "a glTF file"),
        (Format::Glb, "a glTF file"),
    ] {
        for data in [&noise[..], &noise[..100], b"\0\0\0\0", b"v 0 0 0\n\0\nv 1 0 0\n"] {
            let e = read_mesh_from_bytes(data, format, "noise").unwrap_err();
            assert!(matches!(e, IoError::BinaryData { line: None, .. }), "{format}: {e}");
            assert_eq!(e.to_string(), format!("noise: binary data, not {name}"));
        }
    }
    // Binary data past the part looked at first (a zero-filled tail): named with its line.
    let mut obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".repeat(200);
    obj.extend([0u8; 4096]);
    let e = read_mesh_from_bytes(&obj, Format::Obj, "tail.obj").unwrap_err();
    assert!(matches!(e, IoError::BinaryData { line: Some(801), .. }), "{e}");
    assert_eq!(e.to_string(), "tail.obj:801: binary data, not an OBJ file");
    // An ASCII PLY header over a binary body (the wrong format line).
    let header =
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    let e = read_mesh_from_bytes(&[&header[..], &noise[..64]].concat(), Format::PlyAscii, "b.ply").unwrap_err();
    assert!(matches!(e, IoError::Parse { line: Some(8), .. }), "{e}");
    assert!(e.to_string().contains("says 'format ascii', but the data after end_header is binary"), "{e}");
    // STL is binary by design: noise, with or without "solid" in front, is a (broken) binary STL.
    for data in [noise.clone(), [&b"solid x\n"[..], &noise].concat()] {
        let e = read_mesh_from_bytes(&data, Format::StlAscii, "n.stl").unwrap_err();
        assert!(matches!(e, IoError::Truncated { .. }), "{e}");
    }
}

#[test]
fn files_with_only_blanks_comments_or_a_bom_are_empty() {
    for format in Format::ALL {
        for data in [&b" \n\t\r\n  "[..], b"\xEF\xBB\xBF", b"\xEF\xBB\xBF\n \n"] {
            let e = read_mesh_from_bytes(data, format, "blank").unwrap_err();
            assert!(matches!(e, IoError::Empty { .. }), "{format}: {e}");
        }
    }
    for (data, format) in [(&b"# a\n\n# b\n"[..], Format::Off), (b"\xEF\xBB\xBF# only a comment\r\n", Format::Obj)] {
        let e = read_mesh_from_bytes(data, format, "c").unwrap_err();
        assert!(matches!(e, IoError::Empty { .. }), "{format}: {e}");
    }
}

#[test]
fn gltf_without_triangle_primitives_names_what_it_found() {
    let buffer = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAA"; // base64 of (0,0,0), (1,0,0) as f32
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "buffers": [{{"byteLength": 24, "uri": "data:;base64,{buffer}"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 24}}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 2, "type": "VEC3", "min": [0, 0, 0], "max": [1, 0, 0]}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "mode": 1}}, {{"attributes": {{"POSITION": 0}}, "mode": 0}},
                                    {{"attributes": {{"POSITION": 0}}, "mode": 3}}, {{"attributes": {{"POSITION": 0}}, "mode": 1}}]}}]}}"#
    );
    let e = read_mesh_from_bytes(json.as_bytes(), Format::Gltf, "lines.gltf").unwrap_err();
    assert!(matches!(e, IoError::Unsupported { .. }), "{e}");
    assert_eq!(e.to_string(), "lines.gltf: unsupported: no triangle primitives (found: lines, points, line strips)");
    // Our own writer stores a mesh without faces as points.
    let points = [DVec3::ZERO, DVec3::X];
    let glb = subdiv_io::write_mesh_to_vec(MeshView::new(&points, &FaceList::new()), Format::Glb).unwrap();
    let e = read_mesh_from_bytes(&glb, Format::Glb, "points.glb").unwrap_err();
    assert_eq!(e.to_string(), "points.glb: unsupported: no triangle primitives (found: points)");
    // A document without meshes holds nothing: that is empty.
    let e = read_mesh_from_bytes(br#"{"asset": {"version": "2.0"}}"#, Format::Gltf, "none.gltf").unwrap_err();
    assert!(matches!(e, IoError::Empty { .. }), "{e}");
}

/// The message of reading `src`, which must be a parse error on `line`.
fn parse_message(src: &[u8], format: Format, line: usize) -> String {
    let e = read_mesh_from_bytes(src, format, "big").unwrap_err();
    assert!(matches!(e, IoError::Parse { .. }), "{format}: {e}");
    assert_eq!(e.line(), Some(line), "{e}");
    e.to_string()
}

#[test]
fn integers_too_large_are_out_of_range_not_non_integers() {
    const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let obj = |face: &str| format!("{TRIANGLE}f {face}\n").into_bytes();
    let big = "99999999999999999999";
    let huge = "9".repeat(60);
    assert_eq!(
        parse_message(&obj(&format!("1 2 {big}")), Format::Obj, 4),
        format!("big:4: face index {big} out of range (the largest is 4294967296)")
    );
    assert_eq!(
        parse_message(&obj(&format!("1 2 {big}/1/1")), Format::Obj, 4),
        format!("big:4: face index {big} out of range (the largest is 4294967296)")
    );
    assert!(parse_message(&obj(&format!("1 2 {huge}")), Format::Obj, 4).ends_with("… out of range"));
    assert_eq!(
        parse_message(&obj("1 2 4294967297"), Format::Obj, 4),
        "big:4: face index 4294967297 out of range (the largest is 4294967296)"
    );
    assert!(parse_message(&obj(&format!("1 2 -{big}")), Format::Obj, 4).contains("points before the first vertex"));
    assert!(parse_message(&obj("1 2 3x"), Format::Obj, 4).ends_with("face index '3x' is not an integer"));
    // The largest index that fits is passed through for the validator.
    assert_eq!(read_mesh_from_bytes(&obj("1 2 4294967296"), Format::Obj, "ok").unwrap().faces.face(0)[2], u32::MAX);

    let off = |counts: &str, face: &str| format!("OFF\n{counts}\n0 0 0\n1 0 0\n0 1 0\n{face}\n").into_bytes();
    assert_eq!(
        parse_message(&off("3 1 0", &format!("3 0 1 {big}")), Format::Off, 6),
        format!("big:6: face index {big} out of range")
    );
    assert_eq!(
        parse_message(&off("3 1 0", "3 0 1 4294967296"), Format::Off, 6),
        "big:6: face index 4294967296 out of range"
    );
    assert_eq!(parse_message(&off("3 1 0", "3 0 1 -2"), Format::Off, 6), "big:6: face index -2 is negative");
    assert_eq!(
        parse_message(&off(&format!("{big} 1 0"), ""), Format::Off, 2),
        format!("big:2: vertex count {big} out of range")
    );
    assert_eq!(
        parse_message(&off(&format!("3 {big} 0"), ""), Format::Off, 2),
        format!("big:2: face count {big} out of range")
    );
    assert_eq!(parse_message(&off("3 x 0", ""), Format::Off, 2), "big:2: face count 'x' is not an integer");
    assert_eq!(
        parse_message(&off("3 1 0", &format!("{big} 0 1 2")), Format::Off, 6),
        format!("big:6: face corner count {big} out of range")
    );
    // A headerless OFF whose first count is too large is still read as counts.
    assert_eq!(
        parse_message(format!("{big} 1 0\n").as_bytes(), Format::Off, 1),
        format!("big:1: vertex count {big} out of range")
    );

    let ply = |element: &str, face: &str| {
        format!(
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
             element face {element}\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n{face}\n"
        )
        .into_bytes()
    };
    assert_eq!(
        parse_message(&ply("1", &format!("3 0 1 {big}")), Format::PlyAscii, 13),
        format!("big:13: face 0: vertex index {big} out of range")
    );
    assert_eq!(
        parse_message(&ply("1", "3 0 1 -1"), Format::PlyAscii, 13),
        "big:13: face 0: vertex index -1 is negative"
    );
    assert_eq!(
        parse_message(&ply("1", "3 0 1 1.5"), Format::PlyAscii, 13),
        "big:13: face 0: vertex index '1.5' is not an integer"
    );
    assert_eq!(
        parse_message(&ply("1", &format!("{big} 0 1 2")), Format::PlyAscii, 13),
        format!("big:13: face 0: list 'vertex_indices' length {big} out of range")
    );
    assert_eq!(parse_message(&ply(big, ""), Format::PlyAscii, 7), format!("big:7: element count {big} out of range"));
    // "2.0" is an integer written as a float; some writers do that.
    assert_eq!(read_mesh_from_bytes(&ply("1", "3 0 1 2.0"), Format::PlyAscii, "ok").unwrap().faces.face(0), &[0, 1, 2]);

    // Binary PLY: the value, not a token, is quoted.
    let header =
        "ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n";
    for (value, message) in
        [(1e20f32, "out of range"), (-1.0, "is negative"), (1.5, "is not an integer"), (f32::NAN, "is not an integer")]
    {
        let mut data = header.as_bytes().to_vec();
        data.push(1);
        data.extend(value.to_le_bytes());
        let e = read_mesh_from_bytes(&data, Format::PlyBinary, "b.ply").unwrap_err();
        assert!(matches!(e, IoError::Parse { .. }) && e.to_string().ends_with(message), "{value}: {e}");
    }
}

#[test]
fn ply_elements_without_properties_are_skipped_whatever_their_count() {
    // Regression: each of the 2⁶⁴−1 records took no bytes, and the loop over them ran forever.
    let header = |format: &str| {
        format!(
            "ply\nformat {format} 1.0\nelement nothing 18446744073709551615\nelement vertex 3\nproperty float x\n\
             property float y\nproperty float z\nelement empty 99999\nelement face 1\n\
             property list uchar int vertex_indices\nelement trailer 18446744073709551615\nend_header\n"
        )
    };
    let ascii = format!("{}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", header("ascii")).into_bytes();
    let mut binary = header("binary_little_endian").into_bytes();
    [0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0].iter().for_each(|x| binary.extend(x.to_le_bytes()));
    binary.push(3);
    [0i32, 1, 2].iter().for_each(|i| binary.extend(i.to_le_bytes()));
    for (format, data) in [(Format::PlyAscii, ascii), (Format::PlyBinary, binary)] {
        let soup = common::within(10, "zero-size PLY records", move || read_mesh_from_bytes(&data, format, "z.ply"))
            .unwrap_or_else(|e| panic!("{format}: {e}"));
        assert_eq!(soup.positions, [DVec3::ZERO, DVec3::X, DVec3::Y], "{format}");
        assert_eq!(soup.faces.face(0), &[0, 1, 2], "{format}");
    }
    // A vertex or face element without properties lacks what it needs.
    let e = read_mesh_from_bytes(
        b"ply\nformat ascii 1.0\nelement vertex 18446744073709551615\nend_header\n",
        Format::PlyAscii,
        "v.ply",
    )
    .unwrap_err();
    assert!(e.to_string().contains("vertex element has no 'x' property"), "{e}");
}

#[test]
fn ply_with_two_face_elements_keeps_both() {
    let src = b"ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
        element face 1\nproperty list uchar int vertex_indices\nelement face 1\nproperty list uchar int vertex_indices\n\
        end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
    let soup = read_mesh_from_bytes(src, Format::PlyAscii, "two.ply").unwrap();
    assert_eq!(soup.faces, FaceList::from_faces([[0u32, 1, 2], [0, 2, 3]]));
}

#[test]
fn text_with_classic_mac_line_ends_reads_every_line() {
    // Before: one line, so "v 0 0 0 v 1 0 0 …" gave one vertex and no face, silently.
    let soup = read_mesh_from_bytes(b"v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r", Format::Obj, "mac.obj").unwrap();
    assert_eq!((soup.positions.len(), soup.faces.len()), (3, 1));
    let e = read_mesh_from_bytes(b"v 0 0 0\rv 1 q 0\r", Format::Obj, "mac.obj").unwrap_err();
    assert_eq!(e.line(), Some(2), "{e}");
}

/// A glTF document over a `data:` buffer of `vertices` points (all zero),
/// with `accessors` POSITION accessors aliasing that one buffer view and
/// `primitives` non-indexed triangle primitives using them in turn.
fn reuse_bomb(vertices: usize, accessor_count: usize, primitives: usize) -> Vec<u8> {
    let bytes = 12 * vertices;
    let payload = "A".repeat(bytes.div_ceil(3) * 4);
    let accessor = format!(
        r#"{{"bufferView": 0, "componentType": 5126, "count": {vertices}, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0]}}"#
    );
    let accessors = vec![accessor; accessor_count].join(",");
    let primitives: Vec<String> =
        (0..primitives).map(|p| format!(r#"{{"attributes": {{"POSITION": {}}}}}"#, p % accessor_count)).collect();
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "buffers": [{{"byteLength": {bytes}, "uri": "data:;base64,{payload}"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": {bytes}}}], "accessors": [{accessors}],
        "meshes": [{{"primitives": [{}]}}]}}"#,
        primitives.join(",")
    )
    .into_bytes()
}

#[test]
fn gltf_accessor_reuse_cannot_multiply_the_work() {
    // 3000 vertices (36 KB); 2000 primitives repeating one accessor would be
    // 2 million triangles from a 100 KB file, 2000 aliasing accessors 6 million vertices.
    for (accessors, what) in [(1, "one accessor"), (2000, "aliasing accessors")] {
        let data = reuse_bomb(3000, accessors, 2000);
        let e = common::within(10, what, move || read_mesh_from_bytes(&data, Format::Gltf, "bomb.gltf")).unwrap_err();
        assert!(matches!(e, IoError::Unsupported { .. }), "{what}: {e}");
        assert!(e.to_string().contains("reuse accessors"), "{what}: {e}");
    }
    // Sharing one accessor among a few primitives is ordinary and reads, vertices once.
    let soup = read_mesh_from_bytes(&reuse_bomb(3000, 1, 3), Format::Gltf, "shared.gltf").unwrap();
    assert_eq!((soup.positions.len(), soup.faces.len()), (3000, 3000));
}

#[test]
fn hardening_fixtures_give_the_real_problem_in_one_line() {
    type IsKind = fn(&IoError) -> bool;
    let cases: [(&str, IsKind, &str); 5] = [
        (
            "bad/utf16.obj",
            |e| matches!(e, IoError::Utf16 { .. }),
            "UTF-16 text is not supported; save the file as UTF-8",
        ),
        ("bad/binary_garbage.obj", |e| matches!(e, IoError::BinaryData { .. }), "binary data, not an OBJ file"),
        (
            "bad/index_too_large.obj",
            |e| matches!(e, IoError::Parse { line: Some(9), .. }),
            "face index 99999999999999999999 out of range",
        ),
        (
            "bad/lines_only.gltf",
            |e| matches!(e, IoError::Unsupported { .. }),
            "no triangle primitives (found: line loops, points)",
        ),
        (
            "bad/absolute_uri.gltf",
            |e| matches!(e, IoError::RefusedUri { .. }),
            "buffer uri '/etc/hostname' refused: it is an absolute path",
        ),
    ];
    for (name, kind, message) in cases {
        let e = error(name);
        let shown = e.to_string();
        assert!(kind(&e), "{name}: {e:?}");
        assert!(shown.contains(message) && !shown.contains('\n'), "{name}: {shown}");
    }
}

#[test]
fn gltf_messages_stay_on_one_line_and_short() {
    // 200 primitives with dangling index accessors: the gltf crate reports each one.
    let primitives = vec![r#"{"attributes": {}, "indices": 7}"#; 200].join(",");
    let json = format!(r#"{{"asset": {{"version": "2.0"}}, "meshes": [{{"primitives": [{primitives}]}}]}}"#);
    let e = read_mesh_from_bytes(json.as_bytes(), Format::Gltf, "many.gltf").unwrap_err();
    let shown = e.to_string();
    assert!(shown.starts_with("many.gltf: invalid glTF: meshes[0].primitives[0]"), "{shown}");
    assert!(!shown.contains("invalid glTF: invalid glTF"), "{shown}");
    assert!(shown.ends_with(" more)") && shown.len() < 400, "{shown}");
    // A URI and a JSON string holding a newline and an escape sequence.
    let json = r#"{"asset": {"version": "2.0"}, "buffers": [{"byteLength": 4, "uri": "/etc/\n\u001b[2Jx"}]}"#;
    let e = read_mesh_from_bytes(json.as_bytes(), Format::Gltf, "nl.gltf").unwrap_err();
    assert!(matches!(e, IoError::RefusedUri { .. }), "{e}");
    assert!(!e.to_string().contains(['\n', '\u{1b}']), "{e}");
    let json = r#"{"asset": {"version": "2.0"}, "meshes": "a\nb"}"#;
    let e = read_mesh_from_bytes(json.as_bytes(), Format::Gltf, "t.gltf").unwrap_err();
    assert!(!e.to_string().contains('\n'), "{e}");
}
