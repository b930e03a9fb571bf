//! The one-call entry points for a validated `Mesh`: `write_mesh` (with
//! `WriteOptions`) → `load_mesh` round trips through every format, the
//! options, and the errors and warnings of `load_mesh`.

use crate::common::{assert_round_trip, fixture, scratch_dir};
use std::path::Path;
use subdiv_io::{
    load_mesh, load_mesh_with_warnings, read_mesh, write_mesh, Format, IoError, MeshView, ReadWarning, WriteOptions,
};
use subdiv_mesh::{shapes, DVec2, EdgeId, EdgeTag, FaceVarying, Mesh, MeshError, TagList, Tags, VertexTag, Warning};

/// A cube with a semi-sharp crease, an infinitely sharp corner and texture
/// coordinates without seams (one value per vertex: its x and y).
fn tagged_cube() -> Mesh {
    let cube = shapes::cube();
    let t = cube.topology();
    let (a, b) = t.edge_vertices(EdgeId(0));
    let list = TagList {
        creases: vec![EdgeTag { a: a.0, b: b.0, sharpness: 2.5 }],
        corners: vec![VertexTag { vertex: 6, sharpness: 10.0 }],
        ..Default::default()
    };
    let tags = Tags::from_list(t, &list).unwrap();
    let values = cube.positions().iter().map(|p| DVec2::new(p.x, p.y)).collect();
    let uvs = FaceVarying { values, indices: t.faces().indices().to_vec() };
    cube.with_tags(tags).with_uvs(Some(uvs)).unwrap()
}

fn tag_list(mesh: &Mesh) -> TagList {
    mesh.tags().to_list(mesh.topology())
}

/// Every format, from each of the meshes: polygons as written (or their
/// fan triangles), positions bit-exact (or `f32`-rounded), texture
/// coordinates where the format has them, tags in OBJ only. glTF splits
/// spot's vertices at its texture seams, and where two UV islands meet at a
/// vertex only, the split is no manifold: such a file is refused, and is
/// written without texture coordinates instead.
#[test]
fn write_mesh_then_load_mesh_round_trips_through_every_format() {
    let dir = scratch_dir("mesh_files_round_trip");
    let spot = load_mesh(fixture("quad/spot_control_mesh.obj")).unwrap();
    let mixed = load_mesh(fixture("canonical/pyramid_mixed.obj")).unwrap();
    let mut files = 0;
    for (name, original) in [("cube", tagged_cube()), ("spot", spot), ("pyramid", mixed)] {
        for format in Format::ALL {
            let path = dir.join(format!("{name}_{format:?}.{}", format.extension()));
            let options = WriteOptions::default().with_format(format);
            write_mesh(&path, &original, &options).unwrap();
            files += 1;
            let what = format!("{name} as {format}");
            let (original, back) = match load_mesh(&path) {
                Ok(back) if back.welds().is_none() => (original.clone(), back),
                // Split UV seams leave vertices joining separate fans: a non-manifold mesh.
                Ok(_) if name == "spot" && format.splits_uv_seams() => {
                    let path = dir.join(format!("{name}_{format:?}_no_uvs.{}", format.extension()));
                    write_mesh(&path, &original, &options.with_uvs(false)).unwrap();
                    files += 1;
                    (original.clone().with_uvs(None).unwrap(), load_mesh(&path).unwrap())
                }
                Ok(_) => panic!("{what}: non-manifold after the round trip"),
                Err(e) => panic!("{what}: {e}"),
            };
            if format.carries_tags() {
                let expected = crate::common::stored_tags(&tag_list(&original), original.uvs().is_some(), format);
                assert_eq!(tag_list(&back), expected, "{what}: tags");
            } else {
                assert!(back.tags().is_empty(), "{what}: tags appeared");
            }
            assert_round_trip(&original.into_soup(), &back.into_soup(), format, &what);
        }
    }
    // Nothing but the outputs is left in the directory: no temporary files.
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), files);
}

#[test]
fn the_format_comes_from_the_extension_unless_the_options_name_one() {
    let dir = scratch_dir("mesh_files_format");
    let cube = shapes::cube();
    let path = dir.join("cube.PLY");
    write_mesh(&path, &cube, &WriteOptions::default()).unwrap();
    assert!(std::fs::read(&path).unwrap().starts_with(b"ply\nformat binary_little_endian"));
    write_mesh(&path, &cube, &WriteOptions::default().with_format(Format::PlyAscii)).unwrap();
    assert!(std::fs::read(&path).unwrap().starts_with(b"ply\nformat ascii"));

    let unknown = dir.join("cube.txt");
    let e = write_mesh(&unknown, &cube, &WriteOptions::default()).unwrap_err();
    assert!(matches!(e, IoError::UnknownFormat { .. }), "{e}");
    assert!(!unknown.exists());
    write_mesh(&unknown, &cube, &WriteOptions::default().with_format(Format::Off)).unwrap();
    assert!(std::fs::read(&unknown).unwrap().starts_with(b"OFF\n"));
    // Read back by content once the format is known (the extension says nothing).
    let bytes = std::fs::read(&unknown).unwrap();
    let soup = subdiv_io::read_mesh_from_bytes(&bytes, Format::Off, "cube.txt").unwrap();
    assert_eq!(soup.positions, cube.positions());
}

#[test]
fn normals_are_written_on_request_where_the_format_stores_them() {
    let dir = scratch_dir("mesh_files_normals");
    let cube = shapes::cube();
    let normals = cube.vertex_normals();
    for format in Format::ALL {
        let plain = dir.join(format!("plain_{format:?}.{}", format.extension()));
        let with = dir.join(format!("normals_{format:?}.{}", format.extension()));
        write_mesh(&plain, &cube, &WriteOptions::default().with_format(format)).unwrap();
        write_mesh(&with, &cube, &WriteOptions::default().with_format(format).with_normals(true)).unwrap();
        let bytes = std::fs::read(&with).unwrap();
        let contains = |needle: &[u8]| bytes.windows(needle.len()).any(|w| w == needle);
        match format {
            Format::Obj => assert!(contains(b"\nvn "), "{format}"),
            Format::Off => assert!(bytes.starts_with(b"NOFF\n"), "{format}"),
            Format::PlyAscii | Format::PlyBinary => assert!(contains(b"property double nx"), "{format}"),
            Format::Gltf | Format::Glb => assert!(contains(b"NORMAL"), "{format}"),
            Format::Usda | Format::Usdc | Format::Usdz => assert!(contains(b"normals"), "{format}"),
            // STL writes facet normals either way.
            Format::StlAscii | Format::StlBinary => assert_eq!(bytes, std::fs::read(&plain).unwrap(), "{format}"),
        }
        // Exactly what the view with `Mesh::vertex_normals` writes.
        let view = MeshView::new(cube.positions(), cube.topology().faces()).with_normals(&normals);
        assert!(bytes == subdiv_io::write_mesh_to_vec(view, format).unwrap(), "{format}");
        // Normals are not read back: the same mesh either way.
        let (a, b) = (load_mesh(&plain).unwrap(), load_mesh(&with).unwrap());
        assert_eq!((a.positions(), a.topology().faces()), (b.positions(), b.topology().faces()), "{format}");
    }
}

#[test]
fn tags_and_texture_coordinates_can_be_left_out() {
    let dir = scratch_dir("mesh_files_options");
    let cube = tagged_cube();
    let path = dir.join("cube.obj");
    write_mesh(&path, &cube, &WriteOptions::default()).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\nvt ") && text.contains("\nt crease ") && text.contains("\nt corner "), "{text}");

    write_mesh(&path, &cube, &WriteOptions::default().with_tags(false)).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\nvt ") && !text.contains("\nt "), "{text}");
    let back = load_mesh(&path).unwrap();
    assert!(back.tags().is_empty() && back.uvs() == cube.uvs());

    write_mesh(&path, &cube, &WriteOptions::default().with_uvs(false)).unwrap();
    let back = load_mesh(&path).unwrap();
    assert_eq!((back.uvs(), tag_list(&back)), (None, tag_list(&cube)));

    let defaults = WriteOptions::default();
    assert_eq!((defaults.format, defaults.normals, defaults.tags, defaults.uvs), (None, false, true, true));
}

#[test]
fn a_mesh_made_non_finite_after_validation_is_not_written() {
    let dir = scratch_dir("mesh_files_non_finite");
    let path = dir.join("cube.obj");
    std::fs::write(&path, "kept").unwrap();
    let mut cube = shapes::cube();
    cube.positions_mut()[5].y = f64::NAN;
    let e = write_mesh(&path, &cube, &WriteOptions::default()).unwrap_err();
    assert!(matches!(&e, IoError::InvalidMesh { message, .. } if message.starts_with("vertex 5 at ")), "{e}");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "kept");
    // Beyond f32 for the formats that store f32.
    let mut far = shapes::cube();
    far.positions_mut()[0].x = 1e300;
    let e = write_mesh(dir.join("far.glb"), &far, &WriteOptions::default()).unwrap_err();
    assert!(matches!(e, IoError::InvalidMesh { .. }), "{e}");
    write_mesh(dir.join("far.ply"), &far, &WriteOptions::default()).unwrap();
}

#[test]
fn load_mesh_validates_and_names_the_file() {
    // A non-manifold mesh loads (refined as OpenSubdiv does), as its manifold cover.
    let fin = load_mesh(fixture("bad/nonmanifold_edge_3faces.obj")).unwrap();
    assert_eq!(fin.non_manifold().map(|r| r.edges.clone()), Some(vec![[0, 1]]));
    let path = fixture("bad/face_with_two_vertices.obj");
    read_mesh(&path).expect("the reader accepts it");
    let e = load_mesh(&path).unwrap_err();
    let IoError::Validation { source, .. } = &e else { panic!("{e}") };
    assert!(matches!(source, MeshError::FaceTooSmall { size: 2, .. }), "{source}");
    assert_eq!(e.path(), path);
    // As the command line reports it: the file, then the mesh error.
    assert_eq!(e.to_string(), format!("{}: {source}", path.display()));
    assert!(std::error::Error::source(&e).is_some());

    for (name, expected) in [
        ("bad/out_of_range_index.obj", "IndexOutOfRange"),
        ("bad/nan_coordinate.obj", "NonFiniteCoordinate"),
        ("bad/all_vertices_coincide.obj", "AllVerticesCoincide"),
        ("bad/face_with_two_vertices.obj", "FaceTooSmall"),
    ] {
        let e = load_mesh(fixture(name)).unwrap_err();
        let IoError::Validation { source, .. } = &e else { panic!("{name}: {e}") };
        assert!(format!("{source:?}").starts_with(expected), "{name}: {source:?}");
    }
    // Reader errors pass through unchanged.
    assert!(matches!(load_mesh(fixture("bad/truncated.off")).unwrap_err(), IoError::Truncated { .. }));
    assert!(matches!(load_mesh(fixture("bad/empty.obj")).unwrap_err(), IoError::Empty { .. }));
    assert!(matches!(load_mesh(Path::new("no/such/file.obj")).unwrap_err(), IoError::Io { .. }));
}

#[test]
fn load_mesh_with_warnings_gives_the_readers_then_the_meshs() {
    let path = fixture("bad/isolated_vertices.obj");
    let (mesh, warnings) = load_mesh_with_warnings(&path).unwrap();
    assert_eq!(
        warnings,
        [ReadWarning::MeshDefect { path: path.clone(), warning: Warning::IsolatedVertices { vertices: vec![4, 5] } }]
    );
    assert_eq!(warnings[0].to_string(), format!("{}: 2 isolated vertices (no face uses them): 4, 5", path.display()));
    assert_eq!(warnings[0].path(), path);
    assert_eq!(load_mesh(&path).unwrap().positions(), mesh.positions());

    let dir = scratch_dir("mesh_files_warnings");
    let path = dir.join("both.obj");
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 7 7 7\nf 1 2 4\nf 1 4 3\nt vertexedit 0/0/0\n";
    std::fs::write(&path, obj).unwrap();
    let (_, warnings) = load_mesh_with_warnings(&path).unwrap();
    assert!(
        matches!(&warnings[..], [ReadWarning::TagsIgnored { line: 8, .. }, ReadWarning::MeshDefect { .. }]),
        "{warnings:?}"
    );
}
