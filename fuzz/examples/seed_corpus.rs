//! Writes the seed corpus: `cargo run --example seed_corpus` in `fuzz/`.
//!
//! For every target a handful of small valid inputs, plus the hand-made bad
//! files of `fixtures/bad/`: procedural shapes written in every format by
//! `subdiv_io`, the small fixtures, and hand-written files for the variants
//! our writers never produce (binary OFF, big-endian PLY with extra
//! properties and elements, OBJ with groups and relative indices, glTF with
//! 8/16-bit indices or none). Seeds are named `seed-*`, so rerunning this
//! after `cargo fuzz cmin` (which renames to hashes) only adds seeds back.

use std::fs;
use std::path::{Path, PathBuf};
use subdiv_io::{write_mesh_to_vec, Format, MeshView};
use subdiv_mesh::{shapes, PolygonSoup};

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let fixtures = root.join("../fixtures");
    let corpus = root.join("corpus");
    let shapes = [
        ("tetrahedron", shapes::tetrahedron()),
        ("cube", shapes::cube()),
        ("pillow", shapes::pillow()),
        ("quad_grid_2x2", shapes::quad_grid(2, 2)),
        ("triangle_grid_2x1", shapes::triangle_grid(2, 1)),
        ("torus_3x3", shapes::torus(3, 3)),
        ("pyramid_5", shapes::pyramid(5)),
        ("plate_hole_open", shapes::plate_with_holes(3, 3, &[(1, 1)], false)),
        ("polygon_mix", shapes::polygon_mix(&shapes::torus(4, 4), 7, 0.3, 0.3, 0.05)),
    ];

    // Readers: every shape in every format its reader family reads.
    let families: [(&str, &[Format]); 6] = [
        ("obj", &[Format::Obj]),
        ("off", &[Format::Off]),
        ("ply", &[Format::PlyAscii, Format::PlyBinary]),
        ("stl", &[Format::StlAscii, Format::StlBinary]),
        ("gltf", &[Format::Gltf, Format::Glb]),
        ("usd", &[Format::Usda, Format::Usdc, Format::Usdz]),
    ];
    for (target, formats) in families {
        let dir = corpus.join(target);
        fs::create_dir_all(&dir).unwrap();
        for (name, mesh) in &shapes {
            for &format in formats {
                let view = MeshView::new(mesh.positions(), mesh.topology().faces());
                let bytes = write_mesh_to_vec(view, format).expect("shapes are writable");
                let variant = format!("{format:?}").to_lowercase();
                fs::write(dir.join(format!("seed-{name}-{variant}")), bytes).unwrap();
            }
        }
        // The first shape with normals: formats that store them get the extra columns.
        let tetra = &shapes[0].1;
        let normals = tetra.vertex_normals();
        let view = MeshView::new(tetra.positions(), tetra.topology().faces()).with_normals(&normals);
        let bytes = write_mesh_to_vec(view, formats[0]).unwrap();
        fs::write(dir.join("seed-tetrahedron-normals"), bytes).unwrap();
    }

    // Fixtures: the bad ones by extension, the small good ones.
    let small = |p: &PathBuf| fs::metadata(p).map(|m| m.len() <= 4096).unwrap_or(false);
    for sub in ["bad", "canonical", "poly", "open"] {
        for entry in fs::read_dir(fixtures.join(sub)).unwrap() {
            let path = entry.unwrap().path();
            let Some(ext) = path.extension().and_then(|e| e.to_str()) else { continue };
            if (ext == "obj" || ext == "off") && small(&path) {
                let name = path.file_name().unwrap().to_string_lossy();
                fs::copy(&path, corpus.join(ext).join(format!("seed-{sub}-{name}"))).unwrap();
            }
        }
    }

    // USD written by Pixar's own library (text, crate, usdz).
    for entry in fs::read_dir(fixtures.join("usd")).unwrap() {
        let path = entry.unwrap().path();
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if ["usda", "usdc", "usdz"].contains(&ext) {
            let name = path.file_name().unwrap().to_string_lossy();
            fs::copy(&path, corpus.join("usd").join(format!("seed-{name}"))).unwrap();
        }
    }

    for (target, name, bytes) in hand_made() {
        fs::write(corpus.join(target).join(format!("seed-{name}")), bytes).unwrap();
    }

    // from_soup: the shapes and the bad OBJ fixtures in its own encoding.
    let dir = corpus.join("from_soup");
    fs::create_dir_all(&dir).unwrap();
    for (name, mesh) in &shapes {
        fs::write(dir.join(format!("seed-{name}")), encode_soup(&mesh.clone().into_soup())).unwrap();
    }
    for entry in fs::read_dir(fixtures.join("bad")).unwrap() {
        let path = entry.unwrap().path();
        if let Ok(soup) = subdiv_io::read_mesh(&path) {
            let name = path.file_stem().unwrap().to_string_lossy();
            fs::write(dir.join(format!("seed-bad-{name}")), encode_soup(&soup)).unwrap();
        }
    }
    // Issue #14's overflowing bbox diagonal: a regression input, not a seed
    // (the corpus holds inputs that pass).
    let regressions = root.join("regressions/from_soup");
    fs::create_dir_all(&regressions).unwrap();
    fs::write(regressions.join("bbox_diagonal_overflow_1e308"), encode_soup(&extreme_tetrahedron())).unwrap();

    // end_to_end: every operation on every shape kind, default options,
    // coordinates kept (a tail of zeros decodes to "keep"), plus a few scales.
    let dir = corpus.join("end_to_end");
    fs::create_dir_all(&dir).unwrap();
    for operation in 0u8..7 {
        for shape in 0u8..16 {
            let mut bytes = vec![operation, shape, 1, 2, 0, 1];
            bytes.resize(64, 0);
            fs::write(dir.join(format!("seed-op{operation}-shape{shape}")), bytes).unwrap();
        }
        // Scale 10^e (header byte 6-7 = e, little-endian; e > 308 means 308 − e).
        for (label, exponent) in [("1e150", 150u16), ("1e-150", 458), ("1e300", 300)] {
            let mut bytes = vec![operation, 0, 0, 0, 0, 1];
            bytes.extend(exponent.to_le_bytes());
            bytes.resize(64, 0);
            fs::write(dir.join(format!("seed-op{operation}-tetra-scale{label}")), bytes).unwrap();
        }
    }
}

/// A tetrahedron with one coordinate 1e308 (issue #14's example).
fn extreme_tetrahedron() -> PolygonSoup {
    let mut soup = shapes::tetrahedron().into_soup();
    soup.positions[0].x = 1e308;
    soup
}

/// `soup` in the byte layout of `subdiv_fuzz::from_soup` (at most 64 vertices).
fn encode_soup(soup: &PolygonSoup) -> Vec<u8> {
    let n = soup.positions.len().min(64);
    let mut out = vec![n as u8];
    for p in &soup.positions[..n] {
        for x in p.to_array() {
            let grid = x * 4.0 + 120.0;
            if grid.fract() == 0.0 && (0.0..240.0).contains(&grid) {
                out.push(grid as u8);
            } else {
                out.push(240);
                out.extend(x.to_bits().to_le_bytes());
            }
        }
    }
    for face in soup.faces.iter() {
        if face.len() < 16 {
            out.push(face.len() as u8);
        } else {
            out.push(255);
            out.extend((face.len() as u16).to_le_bytes());
        }
        for &v in face {
            if v < 255 {
                out.push(v as u8);
            } else {
                out.push(255);
                out.extend(v.to_le_bytes());
            }
        }
    }
    out
}

/// Variants our writers never produce.
fn hand_made() -> Vec<(&'static str, &'static str, Vec<u8>)> {
    let mut seeds: Vec<(&str, &str, Vec<u8>)> = vec![
        (
            "obj",
            "groups-relative-slashes",
            b"# groups\r\nv 0 0 0\r\nv 1 0 0\r\nv 0 1 0\nv 0 0 1\nvt 0 0\nvn 0 0 1\ng one\nf 1/1/1 2/1/1 3/1/1\no two\nf -4//1 -1//1 -3//1\ns off\nusemtl x\nf 1 4 2\nf 2 4 3\n"
                .to_vec(),
        ),
        ("obj", "bom", b"\xef\xbb\xbfv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".to_vec()),
        ("obj", "line-continuation", b"v 0 0 \\\n 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nl 1 2\np 1\n".to_vec()),
        ("off", "counts-first-comments", b"4 4 6 # counts first\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2 255 0 0\n".to_vec()),
        ("off", "coff-noff", b"CNOFF\n3 1 0\n0 0 0 0 0 1 1 0 0 1\n1 0 0 0 0 1 0 1 0 1\n0 1 0 0 0 1 0 0 1 1\n3 0 1 2\n".to_vec()),
        ("off", "4off-unsupported", b"4OFF\n1 0 0\n0 0 0 0\n".to_vec()),
        (
            "ply",
            "edge-element-colours",
            b"ply\nformat ascii 1.0\ncomment x\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nelement face 1\nproperty list uchar uint vertex_index\nelement edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n0 0 0 255\n1 0 0 0\n0 1 0 9\n3 0 1 2\n0 1\n"
                .to_vec(),
        ),
        ("stl", "solid-binary-header", {
            let mut b = b"solid but binary".to_vec();
            b.resize(80, b' ');
            b.extend(1u32.to_le_bytes());
            for x in [0f32, 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 0.] {
                b.extend(x.to_le_bytes());
            }
            b.extend([0, 0]);
            b
        }),
        (
            "gltf",
            "external-uri-unsupported",
            br#"{"asset":{"version":"2.0"},"buffers":[{"uri":"mesh.bin","byteLength":36}],"bufferViews":[{"buffer":0,"byteLength":36}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]}"#
                .to_vec(),
        ),
    ];
    // Binary OFF, both byte orders (big-endian with the spec's colour count).
    let triangle = [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]];
    for big in [false, true] {
        let int = |x: i32| if big { x.to_be_bytes() } else { x.to_le_bytes() };
        let float = |x: f32| if big { x.to_be_bytes() } else { x.to_le_bytes() };
        let mut b = b"OFF BINARY\n".to_vec();
        [3, 1, 0].into_iter().for_each(|c| b.extend(int(c)));
        triangle.iter().flatten().for_each(|&x| b.extend(float(x)));
        [3, 0, 1, 2].into_iter().for_each(|c| b.extend(int(c)));
        if big {
            b.extend(int(0));
        }
        seeds.push(("off", if big { "binary-be" } else { "binary-le" }, b));
    }
    // Big-endian PLY with float positions, an extra property and uchar counts.
    let mut b = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty short extra\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
    for p in triangle {
        p.iter().for_each(|x| b.extend(x.to_be_bytes()));
        b.extend(7i16.to_be_bytes());
    }
    b.push(3);
    [0i32, 1, 2].iter().for_each(|i| b.extend(i.to_be_bytes()));
    seeds.push(("ply", "binary-be-float", b));
    // glTF with 8-bit, 16-bit and no indices, and a line primitive.
    let positions: Vec<u8> = triangle.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
    for (label, component, index_bytes) in
        [("u8", 5121, vec![0u8, 1, 2]), ("u16", 5123, vec![0, 0, 1, 0, 2, 0]), ("none", 0, vec![])]
    {
        let mut buffer = positions.clone();
        buffer.extend(&index_bytes);
        let data = base64(&buffer);
        let indices = if component == 0 {
            String::new()
        } else {
            format!(r#",{{"bufferView":1,"componentType":{component},"count":3,"type":"SCALAR"}}"#)
        };
        let views = if component == 0 {
            String::new()
        } else {
            format!(r#",{{"buffer":0,"byteOffset":36,"byteLength":{}}}"#, index_bytes.len())
        };
        let primitive = if component == 0 {
            r#"{"attributes":{"POSITION":0}},{"attributes":{"POSITION":0},"mode":1}"#.to_string()
        } else {
            r#"{"attributes":{"POSITION":0},"indices":1}"#.to_string()
        };
        let json = format!(
            r#"{{"asset":{{"version":"2.0"}},"buffers":[{{"uri":"data:application/octet-stream;base64,{data}","byteLength":{}}}],"bufferViews":[{{"buffer":0,"byteLength":36}}{views}],"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}{indices}],"meshes":[{{"primitives":[{primitive}]}}]}}"#,
            buffer.len()
        );
        seeds.push(("gltf", leak(format!("indices-{label}")), json.into_bytes()));
    }
    seeds
}

fn leak(s: String) -> &'static str {
    Box::leak(s.into_boxed_str())
}

/// Standard base64 with padding (for `data:` URIs).
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk.iter().enumerate().fold(0u32, |acc, (i, &b)| acc | u32::from(b) << (16 - 8 * i));
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * i)) as usize & 63] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}
