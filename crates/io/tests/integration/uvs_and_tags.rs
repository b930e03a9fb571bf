//! Texture coordinates and sharpness tags in every format: what each reader
//! takes from a file, what each writer puts in one, the round trips, and
//! the errors and warnings of inputs that are broken or only half there.

use crate::common;

use crate::common::{assert_round_trip, corner_uvs, fixture, within};
use subdiv_io::{
    read_mesh, read_mesh_from_bytes, read_mesh_from_bytes_with_warnings, read_mesh_with_warnings, write_mesh_to_vec,
    EdgeTag, FaceVarying, Format, IoError, MeshView, ReadWarning, TagList, VertexTag,
};
use subdiv_mesh::{DVec2, DVec3, FaceList, Mesh, MeshError, PolygonSoup};

fn obj(src: &str) -> PolygonSoup {
    read_mesh_from_bytes(src.as_bytes(), Format::Obj, "t.obj").unwrap_or_else(|e| panic!("{e}"))
}

fn obj_warnings(src: &str) -> (PolygonSoup, Vec<ReadWarning>) {
    read_mesh_from_bytes_with_warnings(src.as_bytes(), Format::Obj, "t.obj").unwrap_or_else(|e| panic!("{e}"))
}

fn obj_error(src: &str) -> IoError {
    read_mesh_from_bytes(src.as_bytes(), Format::Obj, "t.obj").expect_err(src)
}

const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

fn uv(u: f64, v: f64) -> DVec2 {
    DVec2::new(u, v)
}

/// A square of two triangles with a seam at vertex 0 (its corners use
/// values 0 and 3) and tags on every kind of element.
fn seamed_square() -> PolygonSoup {
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
    let faces = FaceList::from_faces([[0u32, 1, 2], [0, 2, 3]]);
    let uvs = FaceVarying {
        values: vec![uv(0.0, 0.0), uv(1.0, 0.0), uv(0.1, 1.0 / 3.0), uv(-0.0, 1e300), uv(0.25, 0.75)],
        indices: vec![0, 1, 2, 3, 2, 4],
    };
    let tags = TagList {
        creases: vec![
            EdgeTag { a: 0, b: 1, sharpness: 2.5 },
            EdgeTag { a: 2, b: 0, sharpness: 0.1 },
            EdgeTag { a: 3, b: 0, sharpness: f32::MAX },
        ],
        corners: vec![VertexTag { vertex: 1, sharpness: 10.0 }, VertexTag { vertex: 3, sharpness: 1e-7 }],
        ..Default::default()
    };
    PolygonSoup { uvs: Some(uvs), tags, ..PolygonSoup::new(positions, faces) }
}

// ---- OBJ: texture coordinates ----------------------------------------------

#[test]
fn obj_vt_lines_and_every_corner_form_give_one_value_index_per_corner() {
    let soup = obj(&format!(
        "{SQUARE}vt 0 0\nvt 1 0 0.5\nvt 1 1\nvt 0.5\nvn 0 0 1\n\
         f 1/1 2/2 3/3\nf 1/1/1 3/3/1 4/4/1\nf -4/-4 -2/-2 -1/-1\n"
    ));
    let uvs = soup.uvs.expect("every face has texture coordinates");
    // `w` is ignored; a missing `v` is 0, as the OBJ spec says.
    assert_eq!(uvs.values, vec![uv(0.0, 0.0), uv(1.0, 0.0), uv(1.0, 1.0), uv(0.5, 0.0)]);
    assert_eq!(uvs.indices, vec![0, 1, 2, 0, 2, 3, 0, 2, 3]);
    assert_eq!(soup.faces.face(2), &[0, 2, 3]);
}

#[test]
fn obj_texture_indices_that_cannot_be_stored_name_the_line() {
    let base = format!("{SQUARE}vt 0 0\nvt 1 0\nvt 1 1\n");
    for (face, message) in [
        ("f 1/1 2/0 3/3", "texture index 0 is invalid"),
        ("f 1/-4 2/2 3/3", "relative texture index -4 points before the first texture coordinate (3"),
        ("f 1/x 2/2 3/3", "texture index 'x' is not an integer"),
        ("f 1/1 2/99999999999999999999 3/3", "texture index 99999999999999999999 out of range"),
        ("f 1/1 2/4294967297 3/3", "texture index 4294967297 out of range"),
    ] {
        let e = obj_error(&format!("{base}{face}\n"));
        assert!(matches!(e, IoError::Parse { line: Some(8), .. }), "{face}: {e}");
        assert!(e.to_string().contains(message), "{face}: {e}");
    }
    // A positive index past the pool is kept for the validator, like a vertex index.
    let soup = obj(&format!("{base}f 1/1 2/2 3/9\n"));
    assert_eq!(soup.uvs.as_ref().unwrap().indices, vec![0, 1, 8]);
    let e = Mesh::from_soup(soup).unwrap_err();
    assert!(matches!(e, MeshError::FaceVaryingIndexOutOfRange { index: 8, .. }), "{e}");
}

#[test]
fn obj_face_with_texture_coordinates_on_some_corners_is_an_error() {
    let e = obj_error(&format!("{SQUARE}vt 0 0\nf 1 2 3\nf 1/1 3 4/1\n"));
    assert!(matches!(e, IoError::Parse { line: Some(7), .. }), "{e}");
    assert!(e.to_string().ends_with("t.obj:7: face 1 gives texture coordinates for 2 of its 3 corners"), "{e}");
}

#[test]
fn obj_faces_with_and_without_texture_coordinates_drop_them_with_a_warning() {
    // Two exported objects, only the first with a UV map (what Blender writes).
    let src = format!("{SQUARE}vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\no a\nf 1/1/1 2/2/1 3/3/1\no b\nf 1//1 3//1 4//1\n");
    let (soup, warnings) = obj_warnings(&src);
    assert_eq!(soup.uvs, None);
    assert_eq!(soup.faces.len(), 2);
    assert_eq!(warnings.len(), 1);
    assert!(matches!(&warnings[0], ReadWarning::UvsDropped { line: Some(12), .. }), "{:?}", warnings);
    assert_eq!(
        warnings[0].to_string(),
        "t.obj:12: texture coordinates dropped: face 1 has none, but 1 faces have them (the first, face 0, on line 10)"
    );
    // The other way round, the first face with them is named.
    let src = format!("{SQUARE}vt 0 0\nf 1 2 3\nf 1 3 4\nf 1/1 3/1 4/1\n");
    let (soup, warnings) = obj_warnings(&src);
    assert_eq!(soup.uvs, None);
    assert_eq!(
        warnings[0].to_string(),
        "t.obj:8: texture coordinates dropped: face 2 has them, but 2 faces have none (the first, face 0, on line 6)"
    );
    // read_mesh gives the same soup without the warning.
    assert_eq!(obj(&src), soup);
}

#[test]
fn obj_without_faces_using_vt_has_no_channel_and_no_warning() {
    let (soup, warnings) = obj_warnings(&format!("{SQUARE}vt 0 0\nvt 1 1\nvn 0 0 1\nf 1//1 2//1 3//1\nf 1 3 4\n"));
    assert_eq!((soup.uvs, warnings.len()), (None, 0));
    // An empty face (kept for the validator) neither has nor lacks them.
    let soup = obj(&format!("{SQUARE}vt 0 0\nf 1/1 2/1 3/1\nf\n"));
    assert_eq!(soup.uvs.unwrap().indices, vec![0, 0, 0]);
}

#[test]
fn obj_texture_coordinates_agree_with_tobj_on_spot() {
    let path = fixture("quad/spot_control_mesh.obj");
    let ours = read_mesh(&path).unwrap();
    let ours_uvs = ours.uvs.as_ref().expect("spot has vt");
    let options = tobj::LoadOptions { triangulate: false, single_index: false, ..Default::default() };
    let (models, _) = tobj::load_obj(&path, &options).unwrap();
    let theirs: Vec<DVec2> = models
        .iter()
        .flat_map(|m| {
            let m = &m.mesh;
            m.texcoord_indices.iter().map(|&t| {
                let t = 2 * t as usize;
                DVec2::new(f64::from(m.texcoords[t]), f64::from(m.texcoords[t + 1]))
            })
        })
        .collect();
    let mine: Vec<DVec2> = corner_uvs(&ours.faces, ours_uvs, false).iter().map(|p| p.as_vec2().as_dvec2()).collect();
    assert_eq!(mine, theirs);
    assert_eq!(ours_uvs.values.len(), 267);
}

// ---- OBJ: tags --------------------------------------------------------------

#[test]
fn obj_crease_and_corner_tags_take_vertex_pairs_and_one_or_many_floats() {
    let soup = obj(&format!(
        "{SQUARE}f 1 2 3 4\nt crease 2/1/0 0 1 2.5\nt crease 4/1/0 1 2 2 3 0.1\nt crease 4/2/1 3 0 0 2 1 10 why\n\
         t corner 1/1/0 3 10.0\nt corner 2/1/0 0 1 0.5\nt corner 2/2/0 2 3 1 2\n"
    ));
    let e = |a, b, sharpness| EdgeTag { a, b, sharpness };
    assert_eq!(soup.tags.creases, vec![e(0, 1, 2.5), e(1, 2, 0.1), e(2, 3, 0.1), e(3, 0, 1.0), e(0, 2, 10.0)]);
    let c = |vertex, sharpness| VertexTag { vertex, sharpness };
    assert_eq!(soup.tags.corners, vec![c(3, 10.0), c(0, 0.5), c(1, 0.5), c(2, 1.0), c(3, 2.0)]);
    // Sharpness is read as f32 directly (0.1 is the f32 nearest to 0.1).
    assert_eq!(soup.tags.creases[1].sharpness.to_bits(), 0.1f32.to_bits());
}

#[test]
fn obj_tags_the_validator_refuses_are_read_as_written() {
    // Not an edge (0-2 is a diagonal of the quad), negative, NaN: the reader keeps them.
    let soup = obj(&format!("{SQUARE}f 1 2 3 4\nt crease 2/1/0 0 2 1\n"));
    assert!(matches!(Mesh::from_soup(soup).unwrap_err(), MeshError::TagNotAnEdge { a: 0, b: 2 }));
    let soup = obj(&format!("{SQUARE}f 1 2 3 4\nt corner 1/1/0 2 -1\n"));
    assert!(matches!(Mesh::from_soup(soup).unwrap_err(), MeshError::InvalidSharpness { .. }));
    let soup = obj(&format!("{SQUARE}f 1 2 3 4\nt crease 2/1/0 0 1 nan\n"));
    assert!(soup.tags.creases[0].sharpness.is_nan());
    let soup = obj(&format!("{SQUARE}f 1 2 3 4\nt corner 1/1/0 9 1\n"));
    assert!(matches!(Mesh::from_soup(soup).unwrap_err(), MeshError::TagVertexOutOfRange { vertex: 9, .. }));
}

#[test]
fn obj_opensubdiv_option_and_hole_tags_are_applied() {
    let src = format!(
        "{SQUARE}f 1 2 3 4\nt interpolateboundary 1/0/0 2\nt crease 2/1/0 0 1 1\nt creasemethod 0/0/1 chaikin\n\
         t hole 1/0/0 0\nt facevaryinginterpolateboundary 1/0/0 0\nt smoothtriangles 0/0/1 smooth\n"
    );
    let (soup, warnings) = obj_warnings(&src);
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(soup.tags.creases.len(), 1);
    assert_eq!(soup.tags.holes, [0]);
    let options = soup.tags.options;
    assert_eq!(options.boundary.map(|b| b.to_string()).as_deref(), Some("edge-only"));
    assert_eq!(options.crease_method.map(|m| m.to_string()).as_deref(), Some("chaikin"));
    assert_eq!(options.fvar.map(|m| m.to_string()).as_deref(), Some("linear-none"));
    assert_eq!(options.triangle_rule.map(|m| m.to_string()).as_deref(), Some("smooth"));
    // Each of far_utils.h's integer codes, in Sdc's order.
    for (k, name) in ["none", "edge-and-corner", "edge-only"].iter().enumerate() {
        let (soup, _) = obj_warnings(&format!("{SQUARE}f 1 2 3 4\nt interpolateboundary 1/0/0 {k}\n"));
        assert_eq!(soup.tags.options.boundary.unwrap().to_string(), *name);
    }
    let modes = ["linear-none", "linear-corners-only", "linear-corners-plus1", "linear-corners-plus2"];
    for (k, name) in modes.iter().chain(&["linear-boundaries", "linear-all"]).enumerate() {
        let (soup, _) = obj_warnings(&format!("{SQUARE}f 1 2 3 4\nt facevaryinginterpolateboundary 1/0/0 {k}\n"));
        assert_eq!(soup.tags.options.fvar.unwrap().to_string(), *name);
    }
    // Written back as the same lines, and read back to the same list (the mesh keeps them).
    let (mesh, _) = Mesh::from_soup(soup).unwrap();
    assert!(mesh.tags().is_hole(subdiv_mesh::FaceId(0)));
    assert_eq!(mesh.tags().options(), options);
    let dir = common::scratch_dir("option-tags");
    let path = dir.join("square.obj");
    subdiv_io::write_mesh(&path, &mesh, &subdiv_io::WriteOptions::default()).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    for line in [
        "t hole 1/0/0 0",
        "t interpolateboundary 1/0/0 2",
        "t facevaryinginterpolateboundary 1/0/0 0",
        "t creasemethod 0/0/1 chaikin",
        "t smoothtriangles 0/0/1 smooth",
    ] {
        assert!(text.lines().any(|l| l == line), "{line} not in\n{text}");
    }
    let again = subdiv_io::load_mesh(&path).unwrap();
    assert_eq!(again.tags(), mesh.tags());
}

#[test]
fn obj_hierarchical_edits_are_reported_not_applied_and_bad_option_values_refused() {
    let src = format!("{SQUARE}f 1 2 3 4\nt vertexedit 4/3/3 1 4 1 0 0 0 1 add P value\nt faceedit 2/0/1 1 0 hole\n");
    let (_, warnings) = obj_warnings(&src);
    assert_eq!(
        warnings,
        vec![ReadWarning::TagsIgnored {
            path: "t.obj".into(),
            line: 6,
            lines: 2,
            names: vec!["vertexedit".into(), "faceedit".into()],
        }]
    );
    assert!(
        warnings[0].to_string().contains("hierarchical edits and unknown tags are not supported"),
        "{}",
        warnings[0]
    );
    // At most NAMES_KEPT names, then an ellipsis.
    let many: String = (0..20).map(|i| format!("t name{i} 0/0/0\n")).collect();
    let (_, warnings) = obj_warnings(&format!("{SQUARE}f 1 2 3\n{many}"));
    let ReadWarning::TagsIgnored { lines, names, .. } = &warnings[0] else { panic!("{warnings:?}") };
    assert_eq!((*lines, names.len()), (20, ReadWarning::NAMES_KEPT));
    assert!(warnings[0].to_string().contains("name7, …)"), "{}", warnings[0]);
    for (line, message) in [
        ("t interpolateboundary 1/0/0 3", "value 3 is not one of 0..=2"),
        ("t interpolateboundary 0/0/0", "expects one integer, found 0"),
        ("t facevaryinginterpolateboundary 1/0/0 6", "value 6 is not one of 0..=5"),
        ("t creasemethod 0/0/1 sharp", "'sharp' is neither 'normal' nor 'chaikin'"),
        ("t smoothtriangles 0/0/1 loop", "'loop' is neither 'catmark' nor 'smooth'"),
        ("t hole 1/1/0 0 1.0", "hole tag needs face indices and no floats"),
        ("t facevaryingpropagatecorners 1/0/0 1", "facevaryingpropagatecorners' is not supported"),
    ] {
        let e = obj_error(&format!("{SQUARE}f 1 2 3 4\n{line}\n"));
        assert!(e.to_string().contains(message), "{line}: {e}");
        assert!(e.to_string().contains("t.obj:6"), "{line}: {e}");
    }
}

#[test]
fn malformed_tag_lines_are_parse_errors_naming_the_line() {
    for (line, message) in [
        ("t", "tag line needs a name and its counts"),
        ("t crease", "tag line needs a name and its counts"),
        ("t crease 2/1", "counts '2/1' are not NI/NF/NS"),
        ("t crease 2/1/0/0 0 1 1", "are not NI/NF/NS"),
        ("t crease a/1/0 0 1 1", "integer count 'a' is not an integer"),
        ("t crease -2/1/0 0 1 1", "integer count -2 is negative"),
        ("t crease 2/1/0 0 1", "declares 2/1/0 values but has 2"),
        ("t crease 2/1/0 0 1 1 1", "declares 2/1/0 values but has 4"),
        ("t crease 3/1/0 0 1 2 1", "crease tag needs vertex pairs, found 3 integers"),
        ("t crease 0/1/0 1", "crease tag needs vertex pairs, found 0 integers"),
        ("t crease 4/3/0 0 1 1 2 1 1 1", "2 vertex pairs and 3 floats"),
        ("t crease 2/1/0 0 x 1", "vertex index 'x' is not an integer"),
        ("t crease 2/1/0 0 -1 1", "vertex index -1 is negative"),
        ("t crease 2/1/0 0 4294967296 1", "vertex index 4294967296 out of range"),
        ("t crease 2/1/0 0 1 sharp", "float 'sharp' is not a number"),
        ("t corner 0/1/0 1", "corner tag names no vertex"),
        ("t corner 2/3/0 0 1 1 1 1", "2 vertices and 3 floats"),
        ("t hole 1/0/0 first", "tag 'hole': face index 'first' is not an integer"),
        ("t creasemethod 0/0/1", "declares 0/0/1 values but has 0"),
    ] {
        let e = obj_error(&format!("{SQUARE}f 1 2 3 4\n{line}\n"));
        assert!(matches!(e, IoError::Parse { line: Some(6), .. }), "{line}: {e}");
        assert!(e.to_string().contains(message), "{line}: {e}");
        assert!(e.to_string().starts_with("t.obj:6: "), "{line}: {e}");
    }
}

#[test]
fn huge_tag_counts_allocate_nothing_and_long_tag_lines_read_in_linear_time() {
    for counts in ["18446744073709551615/1/0", "18446744073709551615/18446744073709551615/2", "4000000000/1/0"] {
        let e = obj_error(&format!("{SQUARE}f 1 2 3\nt crease {counts} 0 1 1\n"));
        assert!(matches!(e, IoError::Parse { line: Some(6), .. }), "{counts}: {e}");
    }
    // 400 000 pairs on one line and 100 000 lines: seconds if anything were quadratic in them.
    let pairs = 400_000;
    let mut src = format!("{SQUARE}f 1 2 3 4\nt crease {}/1/0", 2 * pairs);
    src.extend((0..pairs).map(|_| " 0 1"));
    src.push_str(" 3\n");
    src.extend((0..100_000).map(|k| format!("t corner 1/1/0 {} 1.5\n", k % 4)));
    let soup = within(30, "long tag lines", move || obj(&src));
    assert_eq!((soup.tags.creases.len(), soup.tags.corners.len()), (pairs, 100_000));
}

// ---- OBJ: writing and round trips -----------------------------------------

#[test]
fn obj_writes_vt_corner_forms_and_tag_lines_after_the_faces() {
    let soup = seamed_square();
    let text = String::from_utf8(write_mesh_to_vec(MeshView::from(&soup), Format::Obj).unwrap()).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines.contains(&"vt 0.1 0.3333333333333333"), "{text}");
    assert!(lines.contains(&"vt -0.0 1e300"), "{text}");
    assert!(lines.contains(&"f 1/1 2/2 3/3") && lines.contains(&"f 1/4 3/3 4/5"), "{text}");
    let first_tag = lines.iter().position(|l| l.starts_with("t ")).unwrap();
    assert!(lines[first_tag..].iter().all(|l| l.starts_with("t ")), "tags after the faces: {text}");
    assert_eq!(
        lines[first_tag..],
        [
            "t crease 2/1/0 0 1 2.5",
            "t crease 2/1/0 2 0 0.1",
            "t crease 2/1/0 3 0 3.4028235e38",
            "t corner 1/1/0 1 10.0",
            "t corner 1/1/0 3 1e-7",
        ]
    );
    // With normals: v/vt/vn.
    let normals = [DVec3::Z; 4];
    let view = MeshView::from(&soup).with_normals(&normals);
    let text = String::from_utf8(write_mesh_to_vec(view, Format::Obj).unwrap()).unwrap();
    assert!(text.contains("\nf 1/1/1 2/2/2 3/3/3\n"), "{text}");
}

#[test]
fn obj_round_trip_gives_the_same_soup_bit_for_bit() {
    let soup = seamed_square();
    let bytes = write_mesh_to_vec(MeshView::from(&soup), Format::Obj).unwrap();
    let back = read_mesh_from_bytes(&bytes, Format::Obj, "back.obj").unwrap();
    assert_eq!(back, soup);
    let bits = |uvs: &FaceVarying| uvs.values.iter().map(|p| p.to_array().map(f64::to_bits)).collect::<Vec<_>>();
    assert_eq!(bits(back.uvs.as_ref().unwrap()), bits(soup.uvs.as_ref().unwrap()), "-0.0 stays -0.0");
    // Every other format keeps the texture coordinates per corner where it can.
    for format in Format::ALL {
        if format == Format::Gltf || format == Format::Glb || format.is_usd() {
            continue; // 1e300 does not fit glTF's and USD's f32: see gltf_writes_no_tags_and_refuses_texcoords_beyond_f32
        }
        let bytes = write_mesh_to_vec(MeshView::from(&soup), format).unwrap();
        let back = read_mesh_from_bytes(&bytes, format, "back").unwrap_or_else(|e| panic!("{format}: {e}"));
        assert_round_trip(&soup, &back, format, &format!("seamed square as {format}"));
        assert_eq!(back.tags.is_empty(), !format.carries_tags(), "{format}");
    }
}

// ---- PLY ----------------------------------------------------------------------

fn ply(src: &str) -> PolygonSoup {
    read_mesh_from_bytes(src.as_bytes(), Format::PlyAscii, "t.ply").unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn ply_reads_per_vertex_texture_coordinates_under_every_name_and_type() {
    for [u, v] in [["u", "v"], ["s", "t"], ["texture_u", "texture_v"], ["texture_s", "texture_t"]] {
        for ty in ["float", "double", "uchar", "int16"] {
            let src = format!(
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty {ty} {v}\nproperty float y\n\
                 property float z\nproperty {ty} {u}\nelement face 1\nproperty list uchar int vertex_indices\n\
                 end_header\n0 7 0 0 1\n1 8 0 0 2\n0 9 1 0 3\n3 2 0 1\n"
            );
            let soup = ply(&src);
            let uvs = soup.uvs.unwrap_or_else(|| panic!("{u} {v} {ty}"));
            assert_eq!(uvs.values, vec![uv(1.0, 7.0), uv(2.0, 8.0), uv(3.0, 9.0)], "{u} {v} {ty}");
            assert_eq!(uvs.indices, vec![2, 0, 1], "{u} {v} {ty}");
        }
    }
    // Half a pair is not a texture coordinate.
    let src = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
        property float u\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
        0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2\n";
    assert_eq!(ply(src).uvs, None);
}

/// Two triangles of a square, as MeshLab writes wedge texture coordinates;
/// vertex 0 is on a seam (0 0 in the first face, 0.5 0.5 in the second).
const MESHLAB: &str = "ply\nformat ascii 1.0\ncomment TextureFile tex.png\nelement vertex 4\nproperty float x\n\
    property float y\nproperty float z\nproperty float u\nproperty float v\nelement face 2\n\
    property list uchar int vertex_indices\nproperty list uchar float texcoord\nend_header\n\
    0 0 0 9 9\n1 0 0 9 9\n1 1 0 9 9\n0 1 0 9 9\n3 0 1 2 6 0 0 1 0 1 1\n3 0 2 3 6 0.5 0.5 1 1 0 1\n";

#[test]
fn ply_texcoord_lists_win_over_vertex_uvs_and_are_welded_per_vertex() {
    let uvs = ply(MESHLAB).uvs.unwrap();
    assert_eq!(uvs.values, vec![uv(0.0, 0.0), uv(1.0, 0.0), uv(1.0, 1.0), uv(0.5, 0.5), uv(0.0, 1.0)]);
    // Vertex 2's two corners share a value; vertex 0's do not (the seam).
    assert_eq!(uvs.indices, vec![0, 1, 2, 3, 2, 4]);
}

#[test]
fn ply_texcoord_list_of_the_wrong_length_names_the_face_and_line() {
    let src = MESHLAB.replace("3 0 2 3 6 0.5 0.5 1 1 0 1", "3 0 2 3 4 0.5 0.5 1 1");
    let e = read_mesh_from_bytes(src.as_bytes(), Format::PlyAscii, "t.ply").unwrap_err();
    assert!(matches!(e, IoError::Parse { line: Some(19), .. }), "{e}");
    assert!(e.to_string().contains("face 1: texcoord has 4 values for 3 corners"), "{e}");
}

#[test]
fn ply_writes_vertex_uvs_without_seams_and_texcoord_lists_with_them() {
    let grid = read_mesh(&fixture("peer/creases/uv_grid/uv_grid.obj")).unwrap();
    let spot = read_mesh(&fixture("peer/creases/spot_uv/spot_uv.obj")).unwrap();
    for format in [Format::PlyAscii, Format::PlyBinary] {
        let bytes = write_mesh_to_vec(MeshView::from(&grid), format).unwrap();
        let header = String::from_utf8_lossy(&bytes[..400]).into_owned();
        assert!(header.contains("property double u\nproperty double v\nelement face"), "{header}");
        assert!(!header.contains("texcoord"), "{header}");
        let back = read_mesh_from_bytes(&bytes, format, "grid.ply").unwrap();
        assert_round_trip(&grid, &back, format, &format!("uv_grid as {format}"));
        assert_eq!(back.uvs, grid.uvs, "{format}: vt k belongs to vertex k, so the channel is the same");

        let bytes = write_mesh_to_vec(MeshView::from(&spot), format).unwrap();
        let header = String::from_utf8_lossy(&bytes[..400]).into_owned();
        assert!(header.contains("property list uchar double texcoord\nend_header"), "{header}");
        let back = read_mesh_from_bytes(&bytes, format, "spot.ply").unwrap();
        assert_round_trip(&spot, &back, format, &format!("spot_uv as {format}"));
    }
}

#[test]
fn ply_texcoord_lists_of_faces_over_127_corners_use_uint_counts() {
    let n = 200u32;
    let positions: Vec<DVec3> = (0..n).map(|i| DVec3::new(f64::from(i).cos(), f64::from(i).sin(), 0.0)).collect();
    let faces = FaceList::from_faces([(0..n).collect::<Vec<_>>(), (0..n).rev().collect()]);
    // Every corner its own value: seams everywhere.
    let uvs = FaceVarying {
        values: (0..2 * n).map(|i| uv(f64::from(i) / 7.0, 1.0 - f64::from(i) / 3.0)).collect(),
        indices: (0..2 * n).collect(),
    };
    let soup = PolygonSoup { uvs: Some(uvs), ..PolygonSoup::new(positions, faces) };
    for format in [Format::PlyAscii, Format::PlyBinary] {
        let bytes = write_mesh_to_vec(MeshView::from(&soup), format).unwrap();
        assert!(String::from_utf8_lossy(&bytes).contains("property list uint double texcoord"));
        let back = read_mesh_from_bytes(&bytes, format, "disc.ply").unwrap();
        assert_round_trip(&soup, &back, format, &format!("200-gon as {format}"));
    }
}

// ---- glTF ---------------------------------------------------------------------

/// `%XX` for every byte: a `data:` URI without base64.
fn data_uri(bytes: &[u8]) -> String {
    let mut uri = "data:application/octet-stream,".to_owned();
    uri.extend(bytes.iter().map(|b| format!("%{b:02X}")));
    uri
}

/// A glTF triangle (non-indexed) whose `TEXCOORD_0` accessor has the given
/// component type, normalized flag, count and bytes.
fn gltf_triangle(component_type: u32, normalized: bool, count: usize, texcoords: &[u8]) -> Vec<u8> {
    let mut buffer: Vec<u8> =
        [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]].iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
    buffer.extend_from_slice(texcoords);
    buffer.resize(buffer.len().next_multiple_of(4), 0);
    let json = serde_json::json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": buffer.len(), "uri": data_uri(&buffer)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": texcoords.len()}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": component_type, "normalized": normalized, "count": count, "type": "VEC2"}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}}]}]
    });
    serde_json::to_vec(&json).unwrap()
}

#[test]
fn gltf_reads_float_and_normalized_integer_texcoords_with_v_flipped() {
    let floats: Vec<u8> = [0.0f32, 0.0, 1.0, 0.25, 0.5, 1.0].iter().flat_map(|x| x.to_le_bytes()).collect();
    let soup = read_mesh_from_bytes(&gltf_triangle(5126, false, 3, &floats), Format::Gltf, "t.gltf").unwrap();
    let uvs = soup.uvs.unwrap();
    // glTF's origin is the top left: v = 1 - v_gltf.
    assert_eq!(uvs.values, vec![uv(0.0, 1.0), uv(1.0, 0.75), uv(0.5, 0.0)]);
    assert_eq!(uvs.indices, vec![0, 1, 2]);

    let bytes = [0u8, 255, 255, 0, 51, 102];
    let soup = read_mesh_from_bytes(&gltf_triangle(5121, true, 3, &bytes), Format::Gltf, "t.gltf").unwrap();
    assert_eq!(soup.uvs.unwrap().values, vec![uv(0.0, 0.0), uv(1.0, 1.0), uv(0.2, 0.6)]);

    let shorts: Vec<u8> = [0u16, 65535, 65535, 0, 13107, 26214].iter().flat_map(|x| x.to_le_bytes()).collect();
    let soup = read_mesh_from_bytes(&gltf_triangle(5123, true, 3, &shorts), Format::Gltf, "t.gltf").unwrap();
    assert_eq!(soup.uvs.unwrap().values, vec![uv(0.0, 0.0), uv(1.0, 1.0), uv(0.2, 0.6)]);
}

#[test]
fn gltf_texcoords_the_spec_does_not_allow_are_dropped_with_a_warning() {
    let shorts: Vec<u8> = [0u16, 1, 1, 0, 3, 6].iter().flat_map(|x| x.to_le_bytes()).collect();
    let src = gltf_triangle(5123, false, 3, &shorts);
    let (soup, warnings) = read_mesh_from_bytes_with_warnings(&src, Format::Gltf, "t.gltf").unwrap();
    assert_eq!((soup.uvs, soup.faces.len()), (None, 1));
    assert_eq!(
        warnings[0].to_string(),
        "t.gltf: texture coordinates dropped: mesh 0 primitive 0: TEXCOORD_0 accessor 1 is Vec2 U16 \
         (only VEC2 FLOAT and normalized UNSIGNED_BYTE or UNSIGNED_SHORT are read)"
    );
}

#[test]
fn gltf_texcoord_count_must_match_the_positions() {
    let floats: Vec<u8> = [0.0f32; 4].iter().flat_map(|x| x.to_le_bytes()).collect();
    let e = read_mesh_from_bytes(&gltf_triangle(5126, false, 2, &floats), Format::Gltf, "t.gltf").unwrap_err();
    assert!(e.to_string().contains("mesh 0 primitive 0: TEXCOORD_0 has 2 elements, POSITION 3"), "{e}");
}

#[test]
fn gltf_primitives_with_and_without_texcoords_drop_them_with_a_warning() {
    let floats: Vec<u8> = [0.0f32, 0.0, 1.0, 0.0, 0.0, 1.0].iter().flat_map(|x| x.to_le_bytes()).collect();
    let mut json: serde_json::Value = serde_json::from_slice(&gltf_triangle(5126, false, 3, &floats)).unwrap();
    let second = serde_json::json!({"attributes": {"POSITION": 0}});
    json["meshes"][0]["primitives"].as_array_mut().unwrap().push(second);
    let src = serde_json::to_vec(&json).unwrap();
    let (soup, warnings) = read_mesh_from_bytes_with_warnings(&src, Format::Gltf, "t.gltf").unwrap();
    assert_eq!((soup.uvs, soup.faces.len(), soup.positions.len()), (None, 2, 3));
    assert_eq!(
        warnings[0].to_string(),
        "t.gltf: texture coordinates dropped: mesh 0 primitive 1 has no TEXCOORD_0, but mesh 0 primitive 0 has"
    );
}

#[test]
fn gltf_splits_vertices_at_seams_and_keeps_the_others_in_order() {
    let spot = read_mesh(&fixture("peer/creases/spot_uv/spot_uv.obj")).unwrap();
    let uvs = spot.uvs.as_ref().unwrap();
    // A vertex gets one glTF vertex per distinct value index its corners use.
    let mut pairs: Vec<(u32, u32)> = spot.faces.indices().iter().copied().zip(uvs.indices.iter().copied()).collect();
    pairs.sort_unstable();
    pairs.dedup();
    for format in [Format::Gltf, Format::Glb] {
        let bytes = write_mesh_to_vec(MeshView::from(&spot), format).unwrap();
        assert!(String::from_utf8_lossy(&bytes).contains("\"TEXCOORD_0\""));
        let back = read_mesh_from_bytes(&bytes, format, "spot").unwrap();
        assert_eq!(back.positions.len(), pairs.len(), "{format}");
        assert!(back.positions.len() > spot.positions.len(), "spot has seams");
        assert_round_trip(&spot, &back, format, &format!("spot_uv as {format}"));
    }
    // No seams: no vertex is split, and the channel is per vertex as written.
    let grid = read_mesh(&fixture("peer/creases/uv_grid/uv_grid.obj")).unwrap();
    let back = read_mesh_from_bytes(&write_mesh_to_vec(MeshView::from(&grid), Format::Glb).unwrap(), Format::Glb, "g")
        .unwrap();
    assert_eq!(back.positions.len(), grid.positions.len());
    assert_round_trip(&grid, &back, Format::Glb, "uv_grid as GLB");
}

#[test]
fn gltf_writes_no_tags_and_refuses_texcoords_beyond_f32() {
    let mut soup = seamed_square();
    let e = write_mesh_to_vec(MeshView::from(&soup), Format::Glb).unwrap_err();
    assert!(matches!(e, IoError::InvalidMesh { .. }), "{e}");
    assert!(e.to_string().ends_with("texture coordinate 3 (-0.0, 1e300) does not fit the 32-bit floats of GLB"), "{e}");
    soup.uvs.as_mut().unwrap().values[3].y = 0.5;
    let bytes = write_mesh_to_vec(MeshView::from(&soup), Format::Glb).unwrap();
    let back = read_mesh_from_bytes(&bytes, Format::Glb, "square.glb").unwrap();
    assert!(back.tags.is_empty());
    assert_round_trip(&soup, &back, Format::Glb, "seamed square as GLB");
}

// ---- OFF, STL and what each format carries ----------------------------------

#[test]
fn off_reads_st_texture_coordinates_after_normals_and_colours() {
    let read = |src: &[u8]| read_mesh_from_bytes(src, Format::Off, "t.off").unwrap();
    let expected = vec![uv(0.5, 0.25), uv(1.0, 0.0), uv(0.0, 1.0)];
    for src in [
        "STOFF\n3 1 0\n0 0 0 0.5 0.25\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n",
        "STNOFF\n3 1 0\n0 0 0 0 0 1 0.5 0.25\n1 0 0 0 0 1 1 0\n0 1 0 0 0 1 0 1\n3 0 1 2\n",
        // Colours of one, three and four values: the texture coordinates are the last two.
        "STCOFF\n3 1 0\n0 0 0 7 0.5 0.25\n1 0 0 1 1 1 1 0\n0 1 0 1 1 1 1 0 1\n3 0 1 2\n",
    ] {
        let soup = read(src.as_bytes());
        let uvs = soup.uvs.unwrap_or_else(|| panic!("{src}"));
        assert_eq!((uvs.values, uvs.indices), (expected.clone(), vec![0, 1, 2]), "{src}");
    }
    let e = read_mesh_from_bytes(b"STOFF\n3 1 0\n0 0 0 0.5\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n", Format::Off, "t.off")
        .unwrap_err();
    assert!(matches!(e, IoError::Parse { line: Some(3), .. }) && e.to_string().contains("'s t'"), "{e}");

    let mut binary = b"STNOFF BINARY\n".to_vec();
    [3i32, 1, 0].iter().for_each(|w| binary.extend(w.to_be_bytes()));
    for (p, t) in [([0.0f32, 0.0, 0.0], [0.5f32, 0.25]), ([1.0, 0.0, 0.0], [1.0, 0.0]), ([0.0, 1.0, 0.0], [0.0, 1.0])] {
        p.iter().chain(&[0.0, 0.0, 1.0]).chain(&t).for_each(|x| binary.extend(x.to_be_bytes()));
    }
    [3i32, 0, 1, 2, 0].iter().for_each(|w| binary.extend(w.to_be_bytes()));
    assert_eq!(read(&binary).uvs.unwrap().values, expected);
}

#[test]
fn formats_without_uvs_or_tags_write_the_mesh_without_them() {
    let soup = seamed_square();
    for format in Format::ALL {
        let carries = (format.carries_uvs(), format.carries_tags());
        let expected = match format {
            Format::Obj | Format::Usda | Format::Usdc | Format::Usdz => (true, true),
            Format::PlyAscii | Format::PlyBinary | Format::Gltf | Format::Glb => (true, false),
            Format::Off | Format::StlAscii | Format::StlBinary => (false, false),
        };
        assert_eq!(carries, expected, "{format}");
        assert_eq!(format.splits_uv_seams(), matches!(format, Format::Gltf | Format::Glb), "{format}");
        if format.carries_uvs() {
            continue;
        }
        let bytes = write_mesh_to_vec(MeshView::from(&soup), format).unwrap();
        let plain = write_mesh_to_vec(MeshView::new(&soup.positions, &soup.faces), format).unwrap();
        assert_eq!(bytes, plain, "{format}: texture coordinates and tags are left out, nothing else changes");
        let back = read_mesh_from_bytes(&bytes, format, "back").unwrap();
        assert!(back.uvs.is_none() && back.tags.is_empty(), "{format}");
    }
}

#[test]
fn writers_refuse_texture_coordinates_and_tags_that_do_not_fit_the_mesh() {
    let soup = seamed_square();
    let short = FaceVarying { indices: vec![0, 1, 2], ..soup.uvs.clone().unwrap() };
    let beyond = FaceVarying { indices: vec![0, 1, 2, 0, 1, 5], ..soup.uvs.clone().unwrap() };
    let bad_tags =
        TagList { creases: vec![EdgeTag { a: 0, b: 4, sharpness: 1.0 }], corners: Vec::new(), ..Default::default() };
    let bad_corner =
        TagList { creases: Vec::new(), corners: vec![VertexTag { vertex: 7, sharpness: 1.0 }], ..Default::default() };
    let view = MeshView::new(&soup.positions, &soup.faces);
    for format in Format::ALL {
        for (uvs, message) in [(&short, "3 texture coordinate indices for 6 face corners"), (&beyond, "corner 5")] {
            let result = write_mesh_to_vec(view.with_uvs(uvs), format);
            if format.carries_uvs() {
                let e = result.unwrap_err();
                assert!(matches!(e, IoError::InvalidMesh { .. }) && e.to_string().contains(message), "{format}: {e}");
            } else {
                assert!(result.is_ok(), "{format}: what is not written is not checked");
            }
        }
        for (tags, message) in [(&bad_tags, "crease tag 0-4"), (&bad_corner, "corner tag 7")] {
            let result = write_mesh_to_vec(view.with_tags(tags), format);
            assert_eq!(result.is_err(), format.carries_tags(), "{format}");
            if let Err(e) = result {
                assert!(e.to_string().contains(message), "{format}: {e}");
            }
        }
    }
}

#[test]
fn read_mesh_with_warnings_reads_files_and_reports_their_warnings() {
    let dir = common::scratch_dir("warnings");
    let path = dir.join("two_objects.obj");
    std::fs::write(&path, format!("{SQUARE}vt 0 0\nf 1/1 2/1 3/1\nf 1 3 4\nt faceedit 0/0/0\n")).unwrap();
    let mut calls = 0;
    let (soup, warnings) = read_mesh_with_warnings(&path, &mut |_, _| calls += 1).unwrap();
    assert!(calls >= 2);
    assert_eq!(soup, read_mesh(&path).unwrap());
    assert_eq!(warnings.len(), 2);
    assert!(warnings.iter().all(|w| w.path() == path && w.to_string().starts_with(&path.display().to_string())));
}

/// 3000 zero vertices read once, and `primitives` one-triangle primitives
/// over them, each with its own `TEXCOORD_0` accessor aliasing the same bytes.
fn texcoord_reuse_bomb(primitives: usize) -> Vec<u8> {
    let (vertices, bytes) = (3000, 36_000);
    let payload = "A".repeat(bytes / 3 * 4);
    let position = format!(
        r#"{{"bufferView": 0, "componentType": 5126, "count": {vertices}, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0]}}"#
    );
    let index = r#"{"bufferView": 0, "componentType": 5121, "count": 3, "type": "SCALAR"}"#;
    let texcoord = format!(r#"{{"bufferView": 0, "componentType": 5126, "count": {vertices}, "type": "VEC2"}}"#);
    let accessors: Vec<String> =
        [position, index.to_owned()].into_iter().chain(std::iter::repeat_n(texcoord, primitives)).collect();
    let primitives: Vec<String> = (0..primitives)
        .map(|p| format!(r#"{{"attributes": {{"POSITION": 0, "TEXCOORD_0": {}}}, "indices": 1}}"#, p + 2))
        .collect();
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "buffers": [{{"byteLength": {bytes}, "uri": "data:;base64,{payload}"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": {bytes}}}], "accessors": [{}],
        "meshes": [{{"primitives": [{}]}}]}}"#,
        accessors.join(","),
        primitives.join(",")
    )
    .into_bytes()
}

#[test]
fn gltf_texcoord_accessor_reuse_cannot_multiply_the_work() {
    // 2000 accessors of 3000 texture coordinates each would be 6 million
    // values from a 200 KB file, for 2000 triangles.
    let data = texcoord_reuse_bomb(2000);
    let e = within(10, "texcoord bomb", move || read_mesh_from_bytes(&data, Format::Gltf, "bomb.gltf")).unwrap_err();
    assert!(matches!(e, IoError::Unsupported { .. }) && e.to_string().contains("reuse accessors"), "{e}");
    // A few such primitives are an ordinary (if odd) file, and read.
    let soup = read_mesh_from_bytes(&texcoord_reuse_bomb(3), Format::Gltf, "few.gltf").unwrap();
    assert_eq!((soup.positions.len(), soup.faces.len(), soup.uvs.unwrap().values.len()), (3000, 3, 9000));
}
