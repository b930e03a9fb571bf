//! Binary PLY of every layout reads as its ASCII twin does: the same soup,
//! bit for bit, or the same error. Binary vertex and face elements of fixed
//! layout take a fast path; ASCII always takes the record loop, so this
//! compares the two on random layouts (scalar types of x, y, z and of the
//! list count and indices, extra properties and elements, both byte orders)
//! and on damaged data (negative indices, truncation). A binary file read
//! from disk (decoded as it streams, `read_mesh`) reads as its bytes in
//! memory do, on the same layouts and on files of several read chunks.

use crate::common;
use proptest::prelude::*;
use subdiv_io::{read_mesh, read_mesh_from_bytes, Format, IoError, PolygonSoup};

/// A PLY scalar type: (name, size, integer range or None for floats).
type Scalar = (&'static str, usize, Option<(i64, i64)>);

const TYPES: [Scalar; 8] = [
    ("char", 1, Some((-128, 127))),
    ("uchar", 1, Some((0, 255))),
    ("short", 2, Some((-32768, 32767))),
    ("ushort", 2, Some((0, 65535))),
    ("int", 4, Some((-(1 << 31), (1 << 31) - 1))),
    ("uint", 4, Some((0, (1 << 32) - 1))),
    ("float", 4, None),
    ("double", 8, None),
];

/// One value of type `ty`, as binary (little or big endian) and as ASCII text.
fn encode(ty: usize, x: f64, big_endian: bool, bin: &mut Vec<u8>, text: &mut String) {
    let mut put = |bytes: &[u8]| {
        if big_endian {
            bin.extend(bytes.iter().rev());
        } else {
            bin.extend_from_slice(bytes);
        }
    };
    match ty {
        0 => put(&(x as i8).to_le_bytes()),
        1 => put(&(x as u8).to_le_bytes()),
        2 => put(&(x as i16).to_le_bytes()),
        3 => put(&(x as u16).to_le_bytes()),
        4 => put(&(x as i32).to_le_bytes()),
        5 => put(&(x as u32).to_le_bytes()),
        6 => put(&(x as f32).to_le_bytes()),
        _ => put(&x.to_le_bytes()),
    }
    match ty {
        6 => text.push_str(&format!(" {:?}", f64::from(x as f32))),
        7 => text.push_str(&format!(" {x:?}")),
        _ => text.push_str(&format!(" {}", x as i64)),
    }
}

/// A value of type `ty` drawn from `seed` (within the type's range).
fn value(ty: usize, seed: u64) -> f64 {
    match TYPES[ty].2 {
        Some((lo, hi)) => (lo + (seed % (hi - lo + 1) as u64) as i64) as f64,
        None => (seed as f64 / u64::MAX as f64 - 0.5) * 1e3,
    }
}

#[derive(Debug, Clone)]
struct Layout {
    xyz: [usize; 3],
    extra: Vec<usize>,
    count_ty: usize,
    index_ty: usize,
    face_extra: bool,
    big_endian: bool,
    vertices: usize,
    faces: Vec<Vec<i64>>,
    truncate: usize,
    seed: u64,
}

fn layout() -> impl Strategy<Value = Layout> {
    let ty = 0usize..8;
    let int_ty = 0usize..6;
    (
        [ty.clone(), ty.clone(), ty.clone()],
        prop::collection::vec(ty, 0..3),
        int_ty.clone(),
        int_ty,
        any::<bool>(),
        any::<bool>(),
        3usize..30,
        prop::collection::vec(prop::collection::vec(-2i64..40, 3..7), 1..20),
        prop_oneof![4 => Just(0usize), 1 => 1usize..40],
        any::<u64>(),
    )
        .prop_map(|(xyz, extra, count_ty, index_ty, face_extra, big_endian, vertices, faces, truncate, seed)| {
            Layout { xyz, extra, count_ty, index_ty, face_extra, big_endian, vertices, faces, truncate, seed }
        })
}

/// The binary file and its ASCII twin.
fn files(l: &Layout) -> (Vec<u8>, Vec<u8>) {
    let order = if l.big_endian { "binary_big_endian" } else { "binary_little_endian" };
    let mut header = format!("element vertex {}\n", l.vertices);
    let names = ["x", "y", "z"];
    for (k, &ty) in l.xyz.iter().enumerate() {
        header.push_str(&format!("property {} {}\n", TYPES[ty].0, names[k]));
        if let Some(&e) = l.extra.get(k) {
            header.push_str(&format!("property {} extra{k}\n", TYPES[e].0));
        }
    }
    header.push_str(&format!(
        "element face {}\nproperty list {} {} vertex_indices\n",
        l.faces.len(),
        TYPES[l.count_ty].0,
        TYPES[l.index_ty].0
    ));
    if l.face_extra {
        header.push_str("property uchar flags\n");
    }
    header.push_str("element edge 1\nproperty int a\nproperty int b\nend_header\n");
    let (mut bin, mut text) = (Vec::new(), String::new());
    let mut seed = l.seed;
    for _ in 0..l.vertices {
        for (k, &ty) in l.xyz.iter().enumerate() {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            encode(ty, value(ty, seed >> 1), l.big_endian, &mut bin, &mut text);
            if let Some(&e) = l.extra.get(k) {
                encode(e, value(e, seed >> 3), l.big_endian, &mut bin, &mut text);
            }
        }
        text.push('\n');
    }
    let (lo, hi) = TYPES[l.index_ty].2.expect("integer index type");
    for face in &l.faces {
        encode(l.count_ty, face.len() as f64, l.big_endian, &mut bin, &mut text);
        for &v in face {
            // Negative indices only where the type has them (and some stay, to be refused).
            encode(l.index_ty, v.clamp(lo, hi) as f64, l.big_endian, &mut bin, &mut text);
        }
        if l.face_extra {
            encode(1, 7.0, l.big_endian, &mut bin, &mut text);
        }
        text.push('\n');
    }
    encode(4, 1.0, l.big_endian, &mut bin, &mut text);
    encode(4, 2.0, l.big_endian, &mut bin, &mut text);
    text.push('\n');
    bin.truncate(bin.len().saturating_sub(l.truncate));
    let text = if l.truncate > 0 {
        // Cut the ASCII twin at the same value: drop as many trailing values as
        // the binary cut reaches into (at least one), roughly.
        let mut values: Vec<&str> = text.split_whitespace().collect();
        values.truncate(values.len().saturating_sub(1 + l.truncate / 8));
        values.join(" ") + "\n"
    } else {
        text
    };
    let binary = format!("ply\nformat {order} 1.0\n{header}").into_bytes().into_iter().chain(bin).collect();
    let ascii = format!("ply\nformat ascii 1.0\n{header}{text}").into_bytes();
    (binary, ascii)
}

/// The message without the file name and line.
fn message(e: &IoError) -> String {
    let text = e.to_string();
    let rest = text.strip_prefix("t.ply:").unwrap_or(&text);
    let rest = rest.trim_start_matches(|c: char| c.is_ascii_digit()).trim_start_matches(':');
    rest.trim().to_owned()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn binary_layouts_read_as_their_ascii_twins(l in layout()) {
        let (binary, ascii) = files(&l);
        let from_binary = read_mesh_from_bytes(&binary, Format::PlyBinary, "t.ply");
        let from_ascii = read_mesh_from_bytes(&ascii, Format::PlyAscii, "t.ply");
        same_from_disk(&binary, &from_binary);
        match (&from_binary, &from_ascii) {
            (Ok(b), Ok(a)) => {
                prop_assert_eq!(&b.faces, &a.faces);
                let bits = |p: &[subdiv_mesh::DVec3]| p.iter().map(|v| v.to_array().map(f64::to_bits)).collect::<Vec<_>>();
                prop_assert_eq!(bits(&b.positions), bits(&a.positions));
            }
            (Err(b), Err(a)) if l.truncate == 0 => prop_assert_eq!(message(b), message(a)),
            // Cut at different places: both refuse the file.
            (Err(_), Err(_)) => {}
            _ if l.truncate > 0 => {
                // The cut may fall in the trailing edge element for one twin only.
                prop_assert!(from_binary.is_err() || from_ascii.is_err());
            }
            (b, a) => prop_assert!(false, "binary {:?} vs ascii {:?}", b.as_ref().map(|_| ()), a.as_ref().map(|_| ())),
        }
    }
}

/// `bytes` written to a file and read back by path gives `expected` (the
/// in-memory read): the same soup bit for bit, or the same error.
fn same_from_disk(bytes: &[u8], expected: &Result<PolygonSoup, IoError>) {
    // A directory of its own (removed on drop), so that the file keeps the in-memory read's name.
    let dir = common::scratch_dir("ply-stream");
    let path = dir.join("t.ply");
    std::fs::write(&path, bytes).unwrap();
    let from_disk = read_mesh(&path);
    match (&from_disk, expected) {
        (Ok(d), Ok(m)) => {
            assert_eq!(d.faces, m.faces);
            assert_eq!(d.uvs, m.uvs);
            let bits = |p: &[subdiv_mesh::DVec3]| p.iter().map(|v| v.to_array().map(f64::to_bits)).collect::<Vec<_>>();
            assert_eq!(bits(&d.positions), bits(&m.positions));
        }
        (Err(d), Err(m)) => assert_eq!(d.to_string().replace(&path.display().to_string(), "t.ply"), m.to_string()),
        (d, m) => panic!("from disk {:?} vs in memory {:?}", d.as_ref().map(|_| ()), m.as_ref().map(|_| ())),
    }
}

/// A binary PLY of `faces` (corner counts from `sizes`, cycled) over `n`
/// vertices, `uchar`/`uint` counts and `int` indices, with per-vertex `u v`.
fn big_file(n: usize, faces: usize, sizes: &[usize], uint_counts: bool) -> Vec<u8> {
    let count = if uint_counts { "uint" } else { "uchar" };
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {n}\nproperty float x\nproperty double y\nproperty double z\n\
         property float u\nproperty float v\nelement face {faces}\nproperty list {count} int vertex_indices\nend_header\n"
    )
    .into_bytes();
    for i in 0..n {
        let t = i as f64;
        out.extend((t.sin() as f32).to_le_bytes());
        out.extend((t * 0.5).to_le_bytes());
        out.extend((t.cos() * 1e-3).to_le_bytes());
        out.extend(((t * 0.25) as f32).to_le_bytes());
        out.extend((-(t as f32)).to_le_bytes());
    }
    for f in 0..faces {
        let k = sizes[f % sizes.len()];
        if uint_counts {
            out.extend((k as u32).to_le_bytes());
        } else {
            out.push(k as u8);
        }
        for j in 0..k {
            out.extend((((f * 7 + j * 13) % n) as i32).to_le_bytes());
        }
    }
    out
}

#[test]
fn files_of_many_read_chunks_read_as_their_bytes_do() {
    // Quads only (the parallel run), mixed sizes (record by record, records
    // across chunk ends), and faces longer than a chunk (2²⁰ + 1 corners).
    let cases = [
        big_file(300_000, 400_000, &[4], false),
        big_file(200_000, 500_000, &[3, 3, 4, 5, 3, 9], false),
        big_file(2_000_000, 3, &[1 << 20, 1, (1 << 20) + 1], true),
    ];
    for bytes in &cases {
        let in_memory = read_mesh_from_bytes(bytes, Format::PlyBinary, "t.ply");
        assert!(in_memory.is_ok());
        same_from_disk(bytes, &in_memory);
        // Cut inside the faces and inside the vertices: the same errors.
        for cut in [bytes.len() - 3, bytes.len() / 3] {
            let cut = &bytes[..cut];
            let in_memory = read_mesh_from_bytes(cut, Format::PlyBinary, "t.ply");
            assert!(in_memory.is_err());
            same_from_disk(cut, &in_memory);
        }
    }
    // A negative index far into the file: the record loop's message.
    let mut bad = cases[0].clone();
    let at = bad.len() - 2 * 17 + 1;
    bad[at..at + 4].copy_from_slice(&(-5i32).to_le_bytes());
    let in_memory = read_mesh_from_bytes(&bad, Format::PlyBinary, "t.ply");
    assert!(message(in_memory.as_ref().unwrap_err()).contains("negative"), "{:?}", in_memory.err());
    same_from_disk(&bad, &in_memory);
}
