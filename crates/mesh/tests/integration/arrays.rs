//! Plain-data entry points: every face layout of `FaceArrays` gives the same
//! mesh, `Mesh` → arrays → `Mesh` is the identity, and malformed arrays are
//! typed errors (property tests on generated meshes, and on arbitrary arrays
//! that must never panic).

use proptest::prelude::*;
use subdiv_mesh::shapes::{self, polygon_mix};
use subdiv_mesh::{FaceArrays, FaceList, Mesh, MeshError, PolygonSoup, Warning};

/// Triangle meshes, quad meshes and polygon mixes, open and closed, with
/// jittered positions.
fn generated_mesh() -> impl Strategy<Value = Mesh> {
    let triangles = (2usize..7, 2usize..7, any::<u64>())
        .prop_map(|(nx, ny, seed)| polygon_mix(&shapes::triangle_grid(nx, ny), seed, 0.0, 0.0, 0.2));
    let quads = (3usize..9, 3usize..7, any::<u64>())
        .prop_map(|(nu, nv, seed)| polygon_mix(&shapes::torus(nu, nv), seed, 0.0, 0.0, 0.2));
    let mixed = (3usize..9, 3usize..9, any::<bool>(), any::<u64>(), 0.0f64..0.5, 0.0f64..0.5).prop_map(
        |(nx, ny, closed, seed, merge, split)| {
            polygon_mix(&shapes::plate_with_holes(nx + 2, ny, &[(1, 1)], closed), seed, merge, split, 0.1)
        },
    );
    prop_oneof![triangles, quads, mixed, Just(shapes::icosahedron()), Just(shapes::pyramid(5))]
}

/// Positions equal bit for bit, faces equal corner for corner.
fn assert_same(a: &Mesh, b: &Mesh, what: &str) {
    let bits = |m: &Mesh| m.positions_to_arrays().into_iter().map(|p| p.map(f64::to_bits)).collect::<Vec<_>>();
    assert_eq!(bits(a), bits(b), "{what}: positions");
    assert_eq!(a.topology().faces(), b.topology().faces(), "{what}: faces");
}

/// Fixed-size faces as arrays, when every face has `N` corners.
fn fixed<const N: usize, T: TryFrom<u32>>(mesh: &Mesh) -> Option<Vec<[T; N]>> {
    let faces = mesh.topology().faces();
    faces
        .all_of_size(N)
        .then(|| faces.iter().map(|f| std::array::from_fn(|k| T::try_from(f[k]).ok().expect("u32 fits"))).collect())
}

fn usize_vec(values: &[u32]) -> Vec<usize> {
    values.iter().map(|&v| v as usize).collect()
}

/// The face of corner `k` (its position in the CSR indices).
fn face_of(mesh: &Mesh, k: usize) -> u32 {
    let offsets = mesh.faces_as_csr().0;
    (offsets.partition_point(|&o| o as usize <= k) - 1) as u32
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn every_layout_round_trips(mesh in generated_mesh()) {
        let positions = mesh.positions_to_arrays();
        let (offsets, indices) = mesh.faces_as_csr();
        let vecs = mesh.faces_to_vecs();
        let usize_vecs: Vec<Vec<usize>> = vecs.iter().map(|f| usize_vec(f)).collect();
        let (offsets_usize, indices_usize) = (usize_vec(offsets), usize_vec(indices));
        let mut layouts: Vec<(&str, FaceArrays<'_>)> = vec![
            ("Vec<u32> per face", (&vecs).into()),
            ("Vec<usize> per face", (&usize_vecs).into()),
            ("CSR u32", FaceArrays::csr(offsets, indices)),
            ("CSR usize", FaceArrays::csr(&offsets_usize, &indices_usize)),
            ("CSR usize offsets, u32 indices", FaceArrays::csr(&offsets_usize, indices)),
            ("FaceList", mesh.topology().faces().into()),
        ];
        let (tri_u32, tri_usize) = (fixed::<3, u32>(&mesh), fixed::<3, usize>(&mesh));
        let (quad_u32, quad_usize) = (fixed::<4, u32>(&mesh), fixed::<4, usize>(&mesh));
        if let (Some(a), Some(b)) = (&tri_u32, &tri_usize) {
            layouts.extend([("[u32; 3]", a.into()), ("[usize; 3]", b.into()), ("flat triangles", FaceArrays::uniform(3, indices))]);
        }
        if let (Some(a), Some(b)) = (&quad_u32, &quad_usize) {
            layouts.extend([("[u32; 4]", a.into()), ("[usize; 4]", b.into()), ("flat quads", FaceArrays::uniform(4, &indices_usize))]);
        }
        for (what, faces) in layouts {
            let back = Mesh::from_arrays(&positions, faces).unwrap_or_else(|e| panic!("{what}: {e}"));
            assert_same(&mesh, &back, what);
            prop_assert_eq!(back.topology().edge_count(), mesh.topology().edge_count());
            prop_assert_eq!(back.topology().genus(), mesh.topology().genus());
        }
    }

    #[test]
    fn malformed_faces_are_typed_errors(mesh in generated_mesh(), pick in any::<prop::sample::Index>(), extra in 0u32..1000) {
        let positions = mesh.positions_to_arrays();
        let n = positions.len();
        let (offsets, indices) = mesh.faces_as_csr();
        let m = offsets.len() - 1;
        let k = pick.index(indices.len());
        let face = face_of(&mesh, k);

        // An index past the vertices, in u32 and (beyond u32) in usize.
        let mut bad = indices.to_vec();
        bad[k] = n as u32 + extra;
        let e = Mesh::from_arrays(&positions, FaceArrays::csr(offsets, &bad)).unwrap_err();
        prop_assert_eq!(e, MeshError::IndexOutOfRange { face, vertex: n as u32 + extra, vertex_count: n });
        let mut wide = usize_vec(indices);
        wide[k] = (1usize << 32) + extra as usize;
        let e = Mesh::from_arrays(&positions, FaceArrays::csr(offsets, &wide)).unwrap_err();
        prop_assert_eq!(e, MeshError::IndexTooLarge { face, index: (1 << 32) + extra as usize });
        let mut vecs: Vec<Vec<usize>> = mesh.faces_to_vecs().iter().map(|f| usize_vec(f)).collect();
        vecs[face as usize][0] = usize::MAX;
        let e = Mesh::from_arrays(&positions, &vecs).unwrap_err();
        prop_assert_eq!(e, MeshError::IndexTooLarge { face, index: usize::MAX });

        // A face cut to two corners.
        let mut vecs = mesh.faces_to_vecs();
        vecs[face as usize].truncate(2);
        let e = Mesh::from_arrays(&positions, &vecs).unwrap_err();
        prop_assert_eq!(e, MeshError::FaceTooSmall { face, size: 2 });

        // CSR offsets: not starting at 0, decreasing, not ending at the index count, empty.
        let mut o = usize_vec(offsets);
        o[0] = 1 + extra as usize;
        let e = Mesh::from_arrays(&positions, FaceArrays::csr(&o, indices)).unwrap_err();
        prop_assert_eq!(e, MeshError::OffsetsStart { first: 1 + extra as usize });
        if m >= 2 {
            let f = 1 + pick.index(m - 1);
            let mut o = usize_vec(offsets);
            o[f] = o[f + 1] + 1;
            let e = Mesh::from_arrays(&positions, FaceArrays::csr(&o, indices)).unwrap_err();
            prop_assert_eq!(e, MeshError::OffsetsDecrease { face: f, start: o[f], end: o[f + 1] });
        }
        let e = Mesh::from_arrays(&positions, FaceArrays::csr(offsets, &indices[..k])).unwrap_err();
        prop_assert_eq!(e, MeshError::OffsetsEnd { last: indices.len(), indices: k });
        let e = Mesh::from_arrays(&positions, FaceArrays::csr(&[] as &[usize], indices)).unwrap_err();
        prop_assert_eq!(e, MeshError::OffsetsEmpty);
        let e = Mesh::from_arrays(&positions, FaceArrays::csr(&[0usize], &[] as &[u32])).unwrap_err();
        prop_assert_eq!(e, MeshError::NoFaces);

        // A flat index buffer that is not a whole number of faces.
        let e = Mesh::from_arrays(&positions, FaceArrays::uniform(3, &indices[..3 * (k / 3) + 1])).unwrap_err();
        prop_assert_eq!(e, MeshError::UniformIndexCount { size: 3, indices: 3 * (k / 3) + 1 });
        let e = Mesh::from_arrays(&positions, FaceArrays::uniform(0, indices)).unwrap_err();
        prop_assert_eq!(e, MeshError::UniformIndexCount { size: 0, indices: indices.len() });

        // A coordinate that is not finite.
        let v = pick.index(n);
        let mut p = positions.clone();
        p[v][k % 3] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY][extra as usize % 3];
        let e = Mesh::from_arrays(&p, FaceArrays::csr(offsets, indices)).unwrap_err();
        prop_assert!(matches!(e, MeshError::NonFiniteCoordinate { vertex, .. } if vertex as usize == v), "{e:?}");
    }

    /// Arbitrary arrays: an error or a mesh, never a panic; a mesh reads back
    /// as the arrays it came from.
    #[test]
    fn arbitrary_arrays_never_panic(
        positions in prop::collection::vec(prop::array::uniform3(prop_oneof![-2.0f64..2.0, Just(f64::NAN)]), 0..10),
        offsets in prop::collection::vec(0usize..24, 0..8),
        indices in prop::collection::vec(prop_oneof![0usize..12, Just(1 << 32), Just(usize::MAX)], 0..24),
        size in 0usize..6,
    ) {
        let nested: Vec<Vec<usize>> = offsets.iter().map(|&o| indices.iter().copied().take(o % 7).collect()).collect();
        for faces in [FaceArrays::csr(&offsets, &indices), FaceArrays::uniform(size, &indices), (&nested).into()] {
            if let Ok(mesh) = Mesh::from_arrays(&positions, faces) {
                prop_assert_eq!(mesh.topology().faces(), &faces.to_face_list().unwrap());
                let same_bits = mesh.positions_to_arrays().iter().zip(&positions).all(|(a, b)| a.map(f64::to_bits) == b.map(f64::to_bits));
                prop_assert!(same_bits);
            }
        }
    }
}

#[test]
fn every_from_conversion_gives_the_same_faces() {
    let want = FaceList::from_faces([[0u32, 1, 2], [0, 2, 3]]);
    let (a32, ausize) = ([[0u32, 1, 2], [0, 2, 3]], [[0usize, 1, 2], [0, 2, 3]]);
    let (v32, vusize) = (a32.to_vec(), ausize.to_vec());
    let (n32, nusize) = ([vec![0u32, 1, 2], vec![0, 2, 3]], [vec![0usize, 1, 2], vec![0, 2, 3]]);
    let (nv32, nvusize) = (n32.to_vec(), nusize.to_vec());
    let (offsets, flat) = ([0u32, 3, 6], [0u32, 1, 2, 0, 2, 3]);
    let flat_usize = usize_vec(&flat);
    let all: [FaceArrays<'_>; 17] = [
        (&a32).into(),
        (&ausize).into(),
        a32.as_slice().into(),
        ausize.as_slice().into(),
        (&v32).into(),
        (&vusize).into(),
        (&n32).into(),
        (&nusize).into(),
        nv32.as_slice().into(),
        (&nvusize).into(),
        (&want).into(),
        FaceArrays::csr(&offsets, &flat),
        FaceArrays::csr(&[0usize, 3, 6], &flat),
        FaceArrays::csr(offsets.as_slice(), &flat_usize),
        FaceArrays::uniform(3, &flat),
        FaceArrays::uniform(3, &flat_usize),
        FaceArrays::uniform(3, flat.as_slice()),
    ];
    for (i, faces) in all.iter().enumerate() {
        assert_eq!(faces.to_face_list().unwrap(), want, "conversion {i}");
    }
    let square = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    let mesh = Mesh::from_arrays(&square, &a32).unwrap();
    assert_eq!(mesh.faces_to_vecs(), n32);
}

#[test]
fn empty_faces_in_csr_are_reported_as_too_small() {
    let square = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    let e = Mesh::from_arrays(&square, FaceArrays::csr(&[0usize, 4, 4], &[0u32, 1, 2, 3])).unwrap_err();
    assert_eq!(e, MeshError::FaceTooSmall { face: 1, size: 0 });
    // An index beyond u32 after an empty face is placed in the face that holds it.
    let e = Mesh::from_arrays(&square, FaceArrays::csr(&[0usize, 0, 0, 3], &[0usize, 1, 1 << 40])).unwrap_err();
    assert_eq!(e, MeshError::IndexTooLarge { face: 2, index: 1 << 40 });
    let e = Mesh::from_arrays(&square, &[[0u32; 0]; 2]).unwrap_err();
    assert_eq!(e, MeshError::FaceTooSmall { face: 0, size: 0 });
    let e = Mesh::from_arrays(&square, &[[0u32, 1]]).unwrap_err();
    assert_eq!(e, MeshError::FaceTooSmall { face: 0, size: 2 });
    let e = Mesh::from_arrays(&square, &[[0u32, 1, 1]]).unwrap_err();
    assert_eq!(e, MeshError::RepeatedIndex { face: 0, vertex: 1 });
    let e = Mesh::from_arrays(&square, &Vec::<[u32; 3]>::new()).unwrap_err();
    assert_eq!(e, MeshError::NoFaces);
}

#[test]
fn warnings_come_with_the_soup_or_the_warnings_variant() {
    let positions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [9.0, 9.0, 9.0]];
    let (mesh, warnings) = Mesh::from_arrays_with_warnings(&positions, &[[0u32, 1, 2]]).unwrap();
    assert_eq!(warnings, [Warning::IsolatedVertices { vertices: vec![3] }]);
    let soup = PolygonSoup::from_arrays(&positions, &[[0u32, 1, 2]]).unwrap();
    assert_eq!(Mesh::from_soup(soup).unwrap().1, warnings);
    assert_eq!(mesh.positions_to_arrays(), positions);
}
