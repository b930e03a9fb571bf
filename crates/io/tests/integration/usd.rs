//! USD: the hand-written fixtures read to the values typed into them, pxr's
//! binary, text and usdz re-saves of them (fixtures/usd/make_pxr_fixtures.py)
//! read to the same meshes, every attribute round-trips through .usda, .usdc
//! and .usdz, scenes keep their prim paths and the rest of the layer, and
//! hostile files are typed errors.

use crate::common::fixture;
use subdiv_io::usd::{self, SceneMesh, SubdivisionScheme, UsdScene};
use subdiv_io::{read_mesh, read_mesh_from_bytes, write_mesh_to_vec, Format, IoError, MeshView};
use subdiv_mesh::{DVec2, DVec3, EdgeTag, FaceList, FaceVarying, FileOptions, PolygonSoup, TagList, VertexTag};
use subdiv_rules::crease::{BoundaryInterpolation, CreaseMethod, FVarInterpolation, TriangleRule};

fn scene(relative: &str) -> UsdScene {
    usd::read_scene(&fixture(relative)).unwrap_or_else(|e| panic!("{relative}: {e}")).0
}

/// `fixtures/usd/tagged.usda` as typed into it.
fn tagged_expected() -> PolygonSoup {
    let z = |i: usize| match i {
        5 => 0.5,
        6 => 0.25,
        _ => 0.0,
    };
    let positions = (0..12).map(|i| DVec3::new((i % 4) as f64, (i / 4) as f64, z(i))).collect();
    let faces = FaceList::from_faces([
        [0u32, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [4, 5, 9, 8],
        [5, 6, 10, 9],
        [6, 7, 11, 10],
    ]);
    let mut soup = PolygonSoup::new(positions, faces);
    let edge = |a, b, sharpness| EdgeTag { a, b, sharpness };
    soup.tags = TagList {
        creases: vec![edge(4, 5, 1.5), edge(5, 6, 2.0), edge(6, 7, 10.0), edge(1, 5, 0.75)],
        corners: vec![VertexTag { vertex: 0, sharpness: 10.0 }, VertexTag { vertex: 11, sharpness: 3.5 }],
        holes: vec![5],
        options: FileOptions {
            boundary: Some(BoundaryInterpolation::EdgeOnly),
            crease_method: None,
            fvar: Some(FVarInterpolation::LinearBoundaries),
            triangle_rule: Some(TriangleRule::Smooth),
        },
    };
    // Stored as texCoord2f: 0.6 is the f32 nearest it.
    let uv = |u: f64, v: f64| DVec2::new(f64::from(u as f32), f64::from(v as f32));
    soup.uvs = Some(FaceVarying {
        values: vec![
            uv(0.0, 0.0),
            uv(0.5, 0.0),
            uv(0.5, 0.5),
            uv(0.0, 0.5),
            uv(0.6, 0.0),
            uv(1.0, 0.0),
            uv(1.0, 0.5),
            uv(0.6, 0.5),
            uv(0.5, 1.0),
            uv(0.0, 1.0),
            uv(1.0, 1.0),
            uv(0.6, 1.0),
        ],
        indices: vec![0, 1, 2, 3, 4, 5, 6, 7, 4, 5, 6, 7, 3, 2, 8, 9, 7, 6, 10, 11, 7, 6, 10, 11],
    });
    soup
}

/// The fixture's values as `f32` (every coordinate is exact in it), so the soups compare exactly.
#[test]
fn the_hand_written_tagged_mesh_reads_to_the_values_in_the_file() {
    let scene = scene("usd/tagged.usda");
    assert_eq!(scene.prim_paths(), ["/World/Grid"]);
    assert_eq!(scene.meshes[0].scheme, SubdivisionScheme::CatmullClark);
    assert_eq!(scene.meshes[0].soup, tagged_expected());
    // One mesh: `read_mesh` takes it as it takes any format.
    assert_eq!(read_mesh(&fixture("usd/tagged.usda")).unwrap(), tagged_expected());
}

#[test]
fn files_pxr_wrote_read_to_the_same_meshes_as_the_hand_written_text() {
    for (hand, pxr) in [
        ("usd/tagged.usda", "usd/tagged_pxr.usdc"),
        ("usd/tagged.usda", "usd/tagged_pxr.usda"),
        ("usd/scene.usda", "usd/scene_pxr.usdc"),
        ("usd/scene.usda", "usd/scene_pxr.usdz"),
        ("usd/left_handed.usda", "usd/left_handed_pxr.usdc"),
    ] {
        let (a, b) = (scene(hand), scene(pxr));
        assert_eq!(a.meshes, b.meshes, "{hand} vs {pxr}");
    }
}

#[test]
fn a_left_handed_mesh_is_reversed_and_per_vertex_st_becomes_face_varying() {
    let scene = scene("usd/left_handed.usda");
    let mesh = &scene.meshes[0];
    assert_eq!(mesh.path, "/Fan");
    assert_eq!(mesh.scheme, SubdivisionScheme::Bilinear);
    // [0 3 2 1] and [3 4 2] reversed after their first corner.
    assert_eq!(mesh.soup.faces, FaceList::from_faces([vec![0u32, 1, 2, 3], vec![3, 2, 4]]));
    let uvs = mesh.soup.uvs.as_ref().unwrap();
    // Per vertex: each corner's value is its vertex's.
    assert_eq!(uvs.indices, mesh.soup.faces.indices());
    assert_eq!(uvs.values[4], DVec2::new(0.5, 2.0));
    // Unauthored with st: USD's fallback, not OpenSubdiv's default.
    assert_eq!(mesh.soup.tags.options.fvar, Some(FVarInterpolation::LinearCornersPlus1));
}

#[test]
fn a_scene_lists_every_mesh_prim_and_read_mesh_refuses_to_pick_one() {
    let scene = scene("usd/scene.usda");
    assert_eq!(scene.prim_paths(), ["/World/Left/Grid", "/World/Right/Octahedron"]);
    assert_eq!(scene.meshes[1].scheme, SubdivisionScheme::Loop);
    assert_eq!(scene.meshes[0].soup.positions.len(), 16);
    assert_eq!(scene.meshes[1].soup.faces.len(), 8);
    let e = read_mesh(&fixture("usd/scene.usda")).unwrap_err();
    match &e {
        IoError::SeveralMeshes { prims, .. } => assert_eq!(prims.len(), 2),
        other => panic!("{other}"),
    }
    assert!(e.to_string().contains("/World/Right/Octahedron") && e.to_string().contains("--prim"), "{e}");
    let mut one = scene;
    assert!(one.select("/World/Nothing").is_none());
    assert_eq!(one.meshes.len(), 2);
    assert_eq!(one.select("/World/Right/Octahedron").unwrap().soup.positions.len(), 6);
    assert_eq!(one.meshes.len(), 1);
}

/// A soup with every attribute: creases, corners, holes, the four options,
/// seamed face-varying st; values exact in f32.
fn everything() -> PolygonSoup {
    let mut soup = tagged_expected();
    soup.tags.options.crease_method = Some(CreaseMethod::Chaikin);
    soup
}

#[test]
fn every_attribute_round_trips_through_usda_usdc_and_usdz() {
    let original = everything();
    for format in [Format::Usda, Format::Usdc, Format::Usdz] {
        let bytes = write_mesh_to_vec(MeshView::from(&original), format).unwrap();
        let back = read_mesh_from_bytes(&bytes, format, "everything").unwrap();
        assert_eq!(back, original, "{format}");
        // The content decides, not the name: binary read through a .usda hint and back.
        let back = read_mesh_from_bytes(&bytes, Format::Usda, "everything").unwrap();
        assert_eq!(back, original, "{format} read with the text hint");
    }
}

#[test]
fn positions_and_uvs_are_stored_as_f32() {
    let mut soup = everything();
    soup.positions[3].x = 0.1;
    soup.uvs.as_mut().unwrap().values[2].y = 1.0 / 3.0;
    let bytes = write_mesh_to_vec(MeshView::from(&soup), Format::Usdc).unwrap();
    let back = read_mesh_from_bytes(&bytes, Format::Usdc, "f32").unwrap();
    assert_eq!(back.positions[3].x, f64::from(0.1f32));
    assert_eq!(back.uvs.unwrap().values[2].y, f64::from(1.0f32 / 3.0));
}

#[test]
fn scenes_keep_prim_paths_transforms_and_other_prims() {
    let mut input = scene("usd/scene.usda");
    let grid = input.meshes[0].soup.clone();
    let octahedron = input.meshes[1].soup.clone();
    // The grid moved up (same topology), the octahedron replaced by one triangle.
    // Lifted, and exact in f32 as point3f[] stores them.
    let lifted: Vec<DVec3> = grid.positions.iter().map(|p| (*p + DVec3::Z).as_vec3().as_dvec3()).collect();
    let tri_positions = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let tri_faces = FaceList::from_faces([[0u32, 1, 2]]);
    let meshes = [
        SceneMesh {
            path: "/World/Left/Grid",
            view: MeshView::new(&lifted, &grid.faces).with_tags(&grid.tags),
            scheme: Some(SubdivisionScheme::CatmullClark),
        },
        SceneMesh {
            path: "/World/Right/Octahedron",
            view: MeshView::new(&tri_positions, &tri_faces),
            scheme: Some(SubdivisionScheme::None),
        },
        SceneMesh { path: "/Extra/Deep/Mesh", view: MeshView::from(&octahedron), scheme: None },
    ];
    for format in [Format::Usda, Format::Usdc] {
        let bytes = usd::write_scene_to_vec(Some(&input), &meshes, format).unwrap();
        let (back, _) = usd::read_scene_from_bytes(&bytes, "scene").unwrap();
        assert_eq!(back.prim_paths(), ["/Extra/Deep/Mesh", "/World/Left/Grid", "/World/Right/Octahedron"]);
        let grid_back = &back.meshes[1];
        assert_eq!(grid_back.soup.positions, lifted);
        assert_eq!(grid_back.soup.tags, grid.tags);
        assert_eq!(grid_back.scheme, SubdivisionScheme::CatmullClark);
        assert_eq!(back.meshes[2].soup.faces, tri_faces);
        assert_eq!(back.meshes[2].scheme, SubdivisionScheme::None);
        assert_eq!(back.meshes[0].soup, octahedron);
        if format == Format::Usda {
            let text = String::from_utf8(bytes).unwrap();
            // The rest of the layer: its metadata, transforms, the camera; new parents are Xforms.
            for kept in [
                "upAxis = \"Y\"",
                "metersPerUnit = 0.01",
                "xformOp:translate = (-3",
                "def Camera \"Camera\"",
                "def Xform \"Extra\"",
            ] {
                assert!(text.contains(kept), "{kept} missing from\n{text}");
            }
        }
    }
    input.select("/World/Left/Grid");
    assert_eq!(input.meshes.len(), 1);
}

#[test]
fn bad_prim_paths_and_duplicates_are_refused() {
    let soup = everything();
    for path in ["World/Relative", "/World.attr", "/", "not a path"] {
        let meshes = [SceneMesh { path, view: MeshView::from(&soup), scheme: None }];
        let e = usd::write_scene_to_vec(None, &meshes, Format::Usda).unwrap_err();
        assert!(matches!(e, IoError::InvalidMesh { .. }), "{path}: {e}");
    }
    let twice = [SceneMesh { path: "/A", view: MeshView::from(&soup), scheme: None }; 2];
    assert!(matches!(usd::write_scene_to_vec(None, &twice, Format::Usdc), Err(IoError::InvalidMesh { .. })));
    assert!(usd::write_scene_to_vec(None, &twice[..1], Format::Obj).is_err());
}

/// The text of a one-mesh layer with `body` inside the prim.
fn mesh_layer(body: &str) -> String {
    format!("#usda 1.0\ndef Mesh \"M\"\n{{\n{body}\n}}\n")
}

const QUAD: &str = "point3f[] points = [(0,0,0),(1,0,0),(1,1,0),(0,1,0)]\nint[] faceVertexCounts = [4]\n";

fn parse_error(text: &str) -> String {
    match read_mesh_from_bytes(text.as_bytes(), Format::Usda, "bad.usda") {
        Err(e @ IoError::Parse { .. }) => e.to_string(),
        other => panic!("expected a parse error for\n{text}\ngot {other:?}"),
    }
}

#[test]
fn inconsistent_counts_are_parse_errors_that_name_the_attribute() {
    let cases = [
        ("int[] faceVertexIndices = [0, 1, 2]", "faceVertexCounts"),
        ("int[] faceVertexIndices = [0, 1, 2, -3]", "faceVertexIndices"),
        ("int[] faceVertexIndices = [0,1,2,3]\nint[] creaseIndices = [0, 1]\nint[] creaseLengths = [3]\nfloat[] creaseSharpnesses = [1]", "creaseLengths"),
        ("int[] faceVertexIndices = [0,1,2,3]\nint[] creaseIndices = [0]\nint[] creaseLengths = [1]\nfloat[] creaseSharpnesses = [1]", "creaseLengths"),
        ("int[] faceVertexIndices = [0,1,2,3]\nint[] creaseIndices = [0, 1, 2]\nint[] creaseLengths = [3]\nfloat[] creaseSharpnesses = [1, 2, 3]", "creaseSharpnesses"),
        ("int[] faceVertexIndices = [0,1,2,3]\nint[] cornerIndices = [0, 1]\nfloat[] cornerSharpnesses = [1]", "cornerSharpnesses"),
        ("int[] faceVertexIndices = [0,1,2,3]\ntexCoord2f[] primvars:st = [(0,0)] (interpolation = \"faceVarying\")", "primvars:st"),
        ("int[] faceVertexIndices = [0,1,2,3]\ntexCoord2f[] primvars:st = [(0,0)] (interpolation = \"vertex\")\nint[] primvars:st:indices = [0]", "primvars:st:indices"),
        ("int[] faceVertexIndices = [0,1,2,3]\nuniform token subdivisionScheme = \"butterfly\"", "subdivisionScheme"),
        ("int[] faceVertexIndices = [0,1,2,3]\ntoken interpolateBoundary = \"sometimes\"", "interpolateBoundary"),
        ("int[] faceVertexIndices = [0,1,2,3]\nuniform token orientation = \"sideways\"", "orientation"),
        ("int[] faceVertexIndices = [0,1,2,3]\nint[] holeIndices = [-1]", "holeIndices"),
        ("int[] faceVertexIndices = [0,1,2,3]\nfloat[] creaseSharpnesses = [1]\nint[] creaseLengths = [2]\nint[] creaseIndices = [0, 1]\nstring[] cornerIndices = [\"a\"]", "cornerIndices"),
    ];
    for (body, attribute) in cases {
        let message = parse_error(&mesh_layer(&format!("{QUAD}{body}")));
        assert!(message.contains(&format!("/M.{attribute}")), "{attribute}: {message}");
    }
}

#[test]
fn out_of_range_indices_are_left_to_the_validator() {
    // As every reader: indices are read as they are, and validation names them.
    let text = mesh_layer(&format!("{QUAD}int[] faceVertexIndices = [0, 1, 2, 9]\nint[] holeIndices = [4]"));
    let soup = read_mesh_from_bytes(text.as_bytes(), Format::Usda, "range.usda").unwrap();
    assert_eq!(soup.faces.face(0), [0, 1, 2, 9]);
    assert!(subdiv_mesh::Mesh::from_soup(soup).is_err());
}

#[test]
fn a_constant_st_is_dropped_with_a_warning_and_time_samples_are_read() {
    let text = mesh_layer(
        "point3f[] points.timeSamples = { 2: [(0,0,0),(1,0,0),(1,1,0),(0,1,0)], 1: [(0,0,1),(1,0,1),(1,1,1),(0,1,1)] }\n\
         int[] faceVertexCounts = [4]\nint[] faceVertexIndices = [0,1,2,3]\n\
         texCoord2f[] primvars:st = [(0,0)] (interpolation = \"constant\")",
    );
    let (soup, warnings) =
        subdiv_io::read_mesh_from_bytes_with_warnings(text.as_bytes(), Format::Usda, "samples.usda").unwrap();
    assert!(soup.uvs.is_none());
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].to_string().contains("constant"), "{}", warnings[0]);
    // The earliest sample.
    assert_eq!(soup.positions[0], DVec3::Z);
}

#[test]
fn hostile_usd_files_are_typed_errors() {
    let good = write_mesh_to_vec(MeshView::from(&everything()), Format::Usdc).unwrap();
    // Every truncation of a binary file.
    for end in 0..good.len() {
        let e = read_mesh_from_bytes(&good[..end], Format::Usdc, "cut.usdc");
        assert!(e.is_err(), "{end} bytes read as a mesh");
    }
    // Garbage after the magic, garbage text, a zip that is not one.
    let mut garbage = b"PXR-USDC".to_vec();
    garbage.extend((0..4096u32).map(|i| (i.wrapping_mul(2654435761) >> 13) as u8));
    for (bytes, format) in [
        (garbage, Format::Usdc),
        (b"#usda 1.0\ndef Mesh \"M\" {\n point3f[] points = [(0,0,".to_vec(), Format::Usda),
        (b"#usda 1.0\n(((((".to_vec(), Format::Usda),
        (b"not usd at all\n".to_vec(), Format::Usda),
        (b"PK\x03\x04garbage".to_vec(), Format::Usdz),
    ] {
        match read_mesh_from_bytes(&bytes, format, "hostile") {
            Err(IoError::Parse { .. } | IoError::Truncated { .. } | IoError::BinaryData { .. }) => {}
            other => panic!("{format}: {other:?}"),
        }
    }
    // Huge counts in the binary file: every 8-byte word set to a large count in turn.
    // At every byte (counts, jumps and value representations are not all
    // 8-byte aligned), also a jump back onto itself and a self-nesting value.
    for at in 8..good.len().saturating_sub(8) {
        for huge in [u64::MAX, 1 << 40, 1 << 31, (at as u64).wrapping_neg(), 0, 31 << 48 | at as u64] {
            let mut bytes = good.clone();
            bytes[at..at + 8].copy_from_slice(&huge.to_le_bytes());
            if let Ok(soup) = read_mesh_from_bytes(&bytes, Format::Usdc, "huge.usdc") {
                assert!(soup.positions.len() <= bytes.len() && soup.faces.corner_count() <= bytes.len() * 8);
            }
        }
    }
    // A text file that declares more faces than it has indices.
    let message = parse_error(&mesh_layer(
        "point3f[] points = [(0,0,0)]\nint[] faceVertexCounts = [2000000000, 4]\nint[] faceVertexIndices = [0,0,0,0]",
    ));
    assert!(message.contains("faceVertexCounts"), "{message}");
}
