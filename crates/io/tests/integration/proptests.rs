//! Property tests: random soups round-trip bit-exactly through the `f64`
//! formats; random and mutated bytes never make a reader panic.

use crate::common::assert_round_trip;
use proptest::prelude::*;
use subdiv_io::{read_mesh_from_bytes, write_mesh_to_vec, EdgeTag, Format, MeshView, VertexTag};
use subdiv_mesh::{DVec2, DVec3, FaceList, FaceVarying, PolygonSoup};

/// Any `f64` but NaN (text formats keep NaN, not its payload bits).
fn coordinate() -> impl Strategy<Value = f64> + Clone {
    use proptest::num::f64::{INFINITE, NEGATIVE, NORMAL, POSITIVE, SUBNORMAL, ZERO};
    POSITIVE | NEGATIVE | NORMAL | SUBNORMAL | ZERO | INFINITE
}

/// Positions, and faces of 3 to 8 corners with indices in range.
fn soup(coordinate: impl Strategy<Value = f64> + Clone) -> impl Strategy<Value = PolygonSoup> {
    prop::collection::vec((coordinate.clone(), coordinate.clone(), coordinate), 1..40).prop_flat_map(|points| {
        let n = points.len() as u32;
        let face = prop::collection::vec(0..n, 3..=8);
        prop::collection::vec(face, 0..30).prop_map(move |faces| {
            let positions = points.iter().map(|&(x, y, z)| DVec3::new(x, y, z)).collect();
            PolygonSoup::new(positions, FaceList::from_faces(faces))
        })
    })
}

/// A soup with texture coordinates: per corner an index into a pool of
/// `pool` values, so that vertices get one value or several (seams), and
/// values no corner uses; and tags on random vertex pairs and vertices.
fn textured_soup() -> impl Strategy<Value = PolygonSoup> {
    (soup(-1e3..1e3f64), 1..12usize).prop_flat_map(|(soup, pool)| {
        let corners = soup.faces.corner_count();
        let n = soup.positions.len() as u32;
        let values = prop::collection::vec((-2.0..2.0f64, -2.0..2.0f64), pool);
        let indices = prop::collection::vec(0..pool as u32, corners);
        let sharpness = prop_oneof![Just(10.0f32), Just(f32::INFINITY), 0.0..12.0f32];
        let creases = prop::collection::vec((0..n, 0..n, sharpness.clone()), 0..6);
        let corners = prop::collection::vec((0..n, sharpness), 0..4);
        (Just(soup), values, indices, creases, corners).prop_map(|(mut soup, values, indices, creases, corners)| {
            let values = values.into_iter().map(|(u, v)| DVec2::new(u, v)).collect();
            soup.uvs = Some(FaceVarying { values, indices });
            soup.tags.creases = creases.into_iter().map(|(a, b, sharpness)| EdgeTag { a, b, sharpness }).collect();
            soup.tags.corners =
                corners.into_iter().map(|(vertex, sharpness)| VertexTag { vertex, sharpness }).collect();
            soup
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn texture_coordinates_and_tags_round_trip_where_the_format_carries_them(original in textured_soup()) {
        // Without faces a channel has no corner, and a file cannot tell it from no channel.
        prop_assume!(!original.faces.is_empty());
        for format in Format::ALL {
            let bytes = write_mesh_to_vec(MeshView::from(&original), format).unwrap();
            let back = read_mesh_from_bytes(&bytes, format, "random").unwrap();
            // Per corner values and (polygon formats) seams: see `assert_same_uvs`.
            assert_round_trip(&original, &back, format, &format!("{format}"));
            if format.carries_tags() {
                let mut expected = crate::common::stored_tags(&original.tags, original.uvs.is_some(), format);
                // OBJ writes a sharpness beyond f32::MAX (+∞) as f32::MAX: as infinitely sharp.
                if format == Format::Obj {
                    for t in &mut expected.creases {
                        t.sharpness = t.sharpness.min(f32::MAX);
                    }
                    for t in &mut expected.corners {
                        t.sharpness = t.sharpness.min(f32::MAX);
                    }
                }
                prop_assert_eq!(&back.tags, &expected);
                // OBJ and USD keep the channel itself, not just what it maps each corner to (USD in f32).
                let mut channel = original.uvs.clone();
                if let Some(uvs) = channel.as_mut().filter(|_| format.is_usd()) {
                    uvs.values.iter_mut().for_each(|uv| *uv = uv.as_vec2().as_dvec2());
                }
                prop_assert_eq!(&back.uvs, &channel);
            } else {
                prop_assert!(back.tags.is_empty());
            }
        }
    }

    #[test]
    fn random_soups_round_trip_bit_exactly(original in soup(coordinate())) {
        for format in [Format::Obj, Format::Off, Format::PlyAscii, Format::PlyBinary, Format::StlAscii] {
            if format.triangulates() && original.faces.is_empty() {
                continue; // STL cannot hold vertices without faces.
            }
            let bytes = write_mesh_to_vec(MeshView::from(&original), format).unwrap();
            let back = read_mesh_from_bytes(&bytes, format, "random").unwrap();
            assert_round_trip(&original, &back, format, &format!("{format}"));
        }
    }

    #[test]
    fn random_soups_round_trip_through_f32_formats(original in soup(-1e30..1e30f64)) {
        for format in [Format::StlBinary, Format::Gltf, Format::Glb] {
            if original.faces.is_empty() {
                continue;
            }
            let bytes = write_mesh_to_vec(MeshView::from(&original), format).unwrap();
            let back = read_mesh_from_bytes(&bytes, format, "random").unwrap();
            assert_round_trip(&original, &back, format, &format!("{format}"));
        }
    }
}

/// Small valid files of every format, and the binary OFF variant.
fn seeds() -> Vec<(Format, Vec<u8>)> {
    let positions = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y, DVec3::new(0.5, 0.5, 1.0)];
    let faces = FaceList::from_faces([vec![0u32, 1, 2, 3], vec![0, 1, 4], vec![1, 2, 4], vec![2, 3, 4], vec![3, 0, 4]]);
    let normals = positions.map(|p| p.normalize_or_zero());
    let view = MeshView::new(&positions, &faces).with_normals(&normals);
    let mut seeds: Vec<_> = Format::ALL.iter().map(|&f| (f, write_mesh_to_vec(view, f).unwrap())).collect();
    let mut binary_off = b"OFF BINARY\n".to_vec();
    [5i32, 1, 0].iter().for_each(|w| binary_off.extend(w.to_le_bytes()));
    positions.iter().flat_map(|p| p.to_array()).for_each(|x| binary_off.extend((x as f32).to_le_bytes()));
    [4i32, 0, 1, 2, 3].iter().for_each(|w| binary_off.extend(w.to_le_bytes()));
    seeds.push((Format::Off, binary_off));
    let ply_ascii_groups = b"g a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no b\nf -1 -2 -3\n".to_vec();
    seeds.push((Format::Obj, ply_ascii_groups));
    // Texture coordinates with a seam at vertex 0, and tags: OBJ vt and t
    // lines, PLY texcoord lists, glTF TEXCOORD_0.
    let uvs = FaceVarying {
        values: (0..7).map(|i| DVec2::new(f64::from(i) / 8.0, 1.0 - f64::from(i) / 8.0)).collect(),
        indices: vec![0, 1, 2, 3, 4, 1, 5, 1, 2, 5, 2, 3, 5, 3, 6, 5],
    };
    let tags = subdiv_io::TagList {
        creases: vec![EdgeTag { a: 0, b: 1, sharpness: 2.5 }, EdgeTag { a: 1, b: 4, sharpness: 10.0 }],
        corners: vec![VertexTag { vertex: 4, sharpness: 0.5 }],
        ..Default::default()
    };
    let textured = MeshView::new(&positions, &faces).with_uvs(&uvs).with_tags(&tags);
    for format in [Format::Obj, Format::PlyAscii, Format::PlyBinary, Format::Gltf] {
        seeds.push((format, write_mesh_to_vec(textured, format).unwrap()));
    }
    seeds
}

#[derive(Clone, Debug)]
enum Edit {
    Set(usize, u8),
    Insert(usize, Vec<u8>),
    Remove(usize, usize),
    Truncate(usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    let interesting = prop::sample::select(vec![
        b"9999999999".to_vec(),
        b"-1".to_vec(),
        b"\xff\xff\xff\x7f".to_vec(),
        b"\0\0\0\x80".to_vec(),
        b"nan".to_vec(),
        b"\n".to_vec(),
        b"#".to_vec(),
        b"/".to_vec(),
        b" 4294967296".to_vec(),
        b"\\".to_vec(),
        b"\r".to_vec(),
        b"\xEF\xBB\xBF".to_vec(),
        b"99999999999999999999".to_vec(),
        b"\nelement e 18446744073709551615\n".to_vec(),
        b"\nt crease 18446744073709551615/1/0 0 1 1\n".to_vec(),
        b"\nt corner 1/1/0 ".to_vec(),
        b"\nvt 0.5".to_vec(),
        b"/-9".to_vec(),
        b" 255 ".to_vec(),
    ]);
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(at, b)| Edit::Set(at, b)),
        (any::<usize>(), interesting).prop_map(|(at, s)| Edit::Insert(at, s)),
        (any::<usize>(), 1..16usize).prop_map(|(at, n)| Edit::Remove(at, n)),
        any::<usize>().prop_map(Edit::Truncate),
    ]
}

fn apply(mut data: Vec<u8>, edits: &[Edit]) -> Vec<u8> {
    for e in edits {
        let len = data.len().max(1);
        match e {
            Edit::Set(at, b) => {
                if !data.is_empty() {
                    data[at % len] = *b;
                }
            }
            Edit::Insert(at, s) => {
                let at = at % (data.len() + 1);
                data.splice(at..at, s.iter().copied());
            }
            Edit::Remove(at, n) => {
                let at = at % len;
                let end = (at + n).min(data.len());
                if at < end {
                    data.drain(at..end);
                }
            }
            Edit::Truncate(at) => data.truncate(at % len),
        }
    }
    data
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..600), prefix in 0..7usize) {
        // Prefixes steer the bytes into each reader's deeper paths.
        let prefixes: [&[u8]; 7] = [b"", b"OFF\n", b"OFF BINARY\n", b"ply\nformat binary_little_endian 1.0\n", b"solid ", b"glTF\x02\0\0\0", b"\xEF\xBB\xBF"];
        let data = [prefixes[prefix], &bytes].concat();
        for format in Format::ALL {
            let _ = read_mesh_from_bytes(&data, format, "garbage");
        }
    }

    #[test]
    fn mutated_valid_files_never_panic(seed in 0..14usize, edits in prop::collection::vec(edit(), 1..6)) {
        let seeds = seeds();
        let (format, data) = &seeds[seed % seeds.len()];
        let data = apply(data.clone(), &edits);
        // Whatever comes back, it must come back.
        // Whatever is read is bounded by the bytes it came from.
        if let Ok(soup) = read_mesh_from_bytes(&data, *format, "mutated") {
            prop_assert!(soup.faces.corner_count() <= data.len().max(1) * 8);
            prop_assert!(soup.positions.len() <= data.len());
            if let Some(uvs) = &soup.uvs {
                prop_assert_eq!(uvs.indices.len(), soup.faces.corner_count());
                prop_assert!(uvs.values.len() <= data.len());
            }
            prop_assert!(soup.tags.creases.len() + soup.tags.corners.len() <= data.len());
        }
    }
}
