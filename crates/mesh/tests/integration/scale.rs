//! Geometry without overflow or underflow (issue #14, class 1): the bounding
//! box diagonal, face normals and areas, vertex normals, centroids, corner
//! angles, the zero-area check and triangulation give finite, scale-free
//! answers for finite coordinates anywhere in the `f64` range (±1.7e308,
//! 1e-300, subnormals), and ordinary meshes the naive formulas' results bit
//! for bit.

use proptest::prelude::*;
use subdiv_mesh::shapes::{self, polygon_mix, SplitMix64};
use subdiv_mesh::{
    centroid, corner_angle, diagnose, newell_normal, triangulate, unit_newell_normal, unit_vector, Aabb, DVec3,
    FaceList, Mesh, MeshError, PolygonSoup, PowerOfTwoScale, Warning,
};

fn scaled(mesh: &Mesh, s: PowerOfTwoScale) -> PolygonSoup {
    let mut soup = mesh.clone().into_soup();
    s.apply_points(&mut soup.positions);
    soup
}

fn box_of(min: f64, max: f64) -> Aabb {
    Aabb { min: DVec3::splat(min), max: DVec3::splat(max) }
}

#[test]
fn bbox_diagonal_neither_overflows_nor_underflows() {
    let sqrt3 = 3f64.sqrt();
    // The naive ‖max − min‖ squares 1e154 into 1e308 and sums three: ∞.
    assert_eq!(box_of(0.0, 1e154).diagonal(), 1e154 * sqrt3);
    assert!(((box_of(-1e154, 1e154).diagonal() / (2e154 * sqrt3)) - 1.0).abs() < 1e-15);
    // max − min itself overflows at ±1.7e308 on one axis; the diagonal 3.4e308 does too (documented ∞) …
    let wide = Aabb { min: DVec3::new(-1.7e308, 0.0, 0.0), max: DVec3::new(1.7e308, 0.0, 0.0) };
    assert_eq!(wide.diagonal(), f64::INFINITY);
    // … but ±0.85e308 spans 1.7e308, representable: finite and exact.
    let half = Aabb { min: DVec3::new(-0.85e308, 0.0, 0.0), max: DVec3::new(0.85e308, 0.0, 0.0) };
    assert_eq!(half.diagonal(), 1.7e308);
    let corner = Aabb { min: DVec3::splat(-0.5e308), max: DVec3::splat(0.5e308) };
    assert!(((corner.diagonal() / (1e308 * sqrt3)) - 1.0).abs() < 1e-15);
    assert_eq!(box_of(-f64::MAX, f64::MAX).diagonal(), f64::INFINITY);
    // The naive squares of 1e-300 underflow to 0.
    assert!(((box_of(0.0, 1e-300).diagonal() / (1e-300 * sqrt3)) - 1.0).abs() < 1e-15);
    assert_eq!(box_of(1.0, 1.0 + f64::EPSILON).diagonal(), f64::EPSILON * sqrt3);
    // Subnormal extents: the smallest positive number on every axis.
    let tiny = box_of(0.0, f64::from_bits(1)).diagonal();
    assert!(tiny > 0.0 && tiny <= 2.0 * f64::from_bits(1), "{tiny:e}");
    assert_eq!(box_of(3.0, 3.0).diagonal(), 0.0);
}

#[test]
fn bbox_diagonal_is_the_naive_one_bit_for_bit_in_range() {
    let mut rng = SplitMix64(7);
    for _ in 0..10_000 {
        let mut p = || DVec3::new(rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5);
        let (a, b) = (p() * 1e3, p());
        let aabb = Aabb::of([a, b]).unwrap();
        assert_eq!(aabb.diagonal(), (aabb.max - aabb.min).length(), "{aabb:?}");
    }
}

#[test]
fn geometry_is_the_naive_one_bit_for_bit_on_ordinary_meshes() {
    let mesh = polygon_mix(&shapes::torus(7, 5), 3, 0.3, 0.2, 0.2);
    let (t, p) = (mesh.topology(), mesh.positions());
    for f in t.face_ids() {
        let corners = t.face(f).iter().map(|&v| p[v as usize]);
        let first = p[t.face(f)[0] as usize];
        let next = corners.clone().skip(1).chain(std::iter::once(first));
        let naive = corners.clone().zip(next).fold(DVec3::ZERO, |acc, (a, b)| acc + (a - first).cross(b - first));
        assert_eq!(newell_normal(corners.clone()), naive);
        assert_eq!(mesh.face_normal(f), naive.normalize_or_zero());
        assert_eq!(mesh.face_area(f), 0.5 * naive.length());
        assert_eq!(mesh.face_centroid(f), corners.clone().sum::<DVec3>() / t.face_size(f) as f64);
    }
    let (a, b, c) = (p[0], p[1], p[2]);
    let (u, v) = (a - b, c - b);
    assert_eq!(corner_angle(a, b, c), u.cross(v).length().atan2(u.dot(v)));
}

#[test]
fn normals_areas_and_angles_survive_every_power_of_two() {
    let tet = shapes::tetrahedron(); // coordinates ±1: exact at every scale, subnormal ones included
    let normals = tet.face_normals();
    let vertex_normals = tet.vertex_normals();
    let area = tet.face_area(subdiv_mesh::FaceId(0));
    let angle = corner_angle(tet.positions()[0], tet.positions()[1], tet.positions()[2]);
    for k in [-1073, -1050, -1000, -900, -600, -500, -1, 1, 500, 600, 900, 1000, 1023] {
        let s = PowerOfTwoScale { exponent: k };
        let mesh = tet.with_positions(scaled(&tet, s).positions);
        assert_eq!(mesh.face_normals(), normals, "2^{k}");
        assert_eq!(mesh.vertex_normals(), vertex_normals, "2^{k}");
        let p = mesh.positions();
        assert_eq!(corner_angle(p[0], p[1], p[2]), angle, "2^{k}");
        assert_eq!(unit_newell_normal(p[..3].iter().copied()), normals[0], "2^{k}");
        // The area is 2^2k times larger: exact where representable, ∞ beyond f64::MAX.
        let expected = PowerOfTwoScale { exponent: 2 * k }.apply(area);
        assert_eq!(mesh.face_area(subdiv_mesh::FaceId(0)), expected, "2^{k}");
        if expected.is_normal() {
            let newell = newell_normal(tet.positions()[..3].iter().copied());
            assert_eq!(newell_normal(p[..3].iter().copied()), s.apply_point(s.apply_point(newell)), "2^{k}");
        }
    }
}

#[test]
fn offsets_between_opposite_extremes_do_not_overflow() {
    // 1.7e308 − (−1.7e308) overflows; the normal, angle and centroid need not.
    let m = 1.7e308;
    let corners = [DVec3::new(-m, -m, 0.0), DVec3::new(m, -m, 0.0), DVec3::new(m, m, 0.0), DVec3::new(-m, m, 0.0)];
    assert_eq!(unit_newell_normal(corners.iter().copied()), DVec3::Z);
    assert_eq!(corner_angle(corners[0], corners[1], corners[2]), std::f64::consts::FRAC_PI_2);
    assert_eq!(centroid(corners.into_iter()), DVec3::ZERO);
    assert_eq!(centroid([DVec3::splat(m), DVec3::splat(m)].into_iter()), DVec3::splat(m));
    assert!(
        (unit_vector(DVec3::new(f64::MAX, f64::MAX, 0.0)) - DVec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-16
    );
    assert_eq!(unit_vector(DVec3::new(0.0, 0.0, -f64::from_bits(1))), -DVec3::Z);
    assert_eq!(unit_vector(DVec3::ZERO), DVec3::ZERO);
}

#[test]
fn a_tiny_face_far_from_the_origin_still_has_a_normal() {
    // Size 1e-150 at distance 1 along an axis: the naive cross products (1e-300)
    // are representable but their squares are not; the normal is still exact.
    let e = 1e-150;
    let corners = [DVec3::new(1.0, 0.0, 0.0), DVec3::new(1.0, e, 0.0), DVec3::new(1.0, e, e), DVec3::new(1.0, 0.0, e)];
    assert!((unit_newell_normal(corners.iter().copied()) - DVec3::X).length() < 1e-15);
    assert_eq!(corner_angle(corners[0], corners[1], corners[2]), std::f64::consts::FRAC_PI_2);
}

#[test]
fn zero_area_verdicts_do_not_depend_on_the_scale() {
    // The pyramid of warnings_and_repair with its apex on a base edge: face 1 has zero area.
    let mut flat = shapes::pyramid(4).into_soup();
    flat.positions[4] = (flat.positions[0] + flat.positions[1]) / 2.0;
    let flat = Mesh::new(flat.positions, flat.faces).unwrap();
    let expected = vec![Warning::ZeroAreaFaces { faces: vec![1] }];
    assert_eq!(flat.warnings(), expected);
    for k in [-1000, -900, -500, 500, 900, 1000] {
        let (_, warnings) = Mesh::from_soup(scaled(&flat, PowerOfTwoScale { exponent: k })).unwrap();
        assert_eq!(warnings, expected, "2^{k}");
    }
    // And a healthy mesh at 2^±900, where d² and the areas leave the f64 range, has none.
    for k in [-1000, -900, 900, 1000] {
        let (_, warnings) = Mesh::from_soup(scaled(&shapes::icosahedron(), PowerOfTwoScale { exponent: k })).unwrap();
        assert!(warnings.is_empty(), "2^{k}: {warnings:?}");
    }
}

#[test]
fn a_mesh_whose_vertices_all_coincide_is_refused() {
    for p in [DVec3::ZERO, DVec3::splat(1e300), DVec3::new(-1e-300, 2.0, f64::MAX)] {
        let mut soup = shapes::cube().into_soup();
        soup.positions.iter_mut().for_each(|q| *q = p);
        // An isolated vertex elsewhere does not give the faces an extent.
        soup.positions.push(DVec3::ONE);
        let err = Mesh::from_soup(soup.clone()).unwrap_err();
        assert_eq!(err, MeshError::AllVerticesCoincide { vertices: 8, x: p.x, y: p.y, z: p.z });
        assert!(err.to_string().starts_with("all vertices coincide"), "{err}");
        assert_eq!(diagnose(&soup).first_error, Some(err));
    }
    // Two distinct points are an extent (the faces are all zero-area: a warning).
    let mut soup = shapes::tetrahedron().into_soup();
    soup.positions[1..].iter_mut().for_each(|q| *q = DVec3::ZERO);
    let (mesh, warnings) = Mesh::from_soup(soup).unwrap();
    assert!(mesh.bbox_diagonal() > 0.0);
    assert_eq!(warnings, vec![Warning::ZeroAreaFaces { faces: vec![0, 1, 2, 3] }]);
}

#[test]
fn triangulation_does_not_depend_on_the_scale() {
    // Non-convex and thin faces take every path of triangulate (quads, ear clipping, the search).
    let mesh = polygon_mix(&shapes::plate_with_holes(7, 6, &[(2, 2)], true), 11, 0.5, 0.0, 0.3);
    let reference = triangulate(&mesh).unwrap();
    for k in [-1000, -900, 900, 1000] {
        let s = PowerOfTwoScale { exponent: k };
        let (big, _) = Mesh::from_soup(scaled(&mesh, s)).unwrap();
        let tri = triangulate(&big).unwrap();
        assert_eq!(tri.mesh.topology().faces(), reference.mesh.topology().faces(), "2^{k}");
        assert_eq!(tri.source_face, reference.source_face);
    }
    // And near the top of the range, where squared lengths overflow.
    let m = 1.7e308;
    let dart = [DVec3::ZERO, DVec3::new(m, -m / 2.0, 0.0), DVec3::new(m / 4.0, 0.0, 0.0), DVec3::new(m, m / 2.0, 0.0)];
    let (quad, _) = Mesh::from_soup(PolygonSoup::new(dart.to_vec(), FaceList::from_faces([[0u32, 1, 2, 3]]))).unwrap();
    let tri = triangulate(&quad).unwrap();
    assert_eq!(tri.mesh.topology().faces(), &FaceList::from_faces([[0u32, 1, 2], [0, 2, 3]]));
    assert!(tri.mesh.face_normals().iter().all(|&n| n == DVec3::Z));
}

// ---- property tests -------------------------------------------------------------------------

/// Random valid meshes: polygon mixes of plates (with holes, open or
/// closed), tori and icosahedra, jittered.
fn any_mesh() -> impl Strategy<Value = Mesh> {
    let plate = (3usize..7, 3usize..7, any::<bool>(), any::<u64>()).prop_map(|(nx, ny, closed, seed)| {
        polygon_mix(&shapes::plate_with_holes(nx + 2, ny, &[(1, 1)], closed), seed, 0.3, 0.3, 0.2)
    });
    let torus = (3usize..8, 3usize..8, any::<u64>())
        .prop_map(|(nu, nv, seed)| polygon_mix(&shapes::torus(nu, nv), seed, 0.3, 0.3, 0.2));
    let ico = any::<u64>().prop_map(|seed| polygon_mix(&shapes::icosahedron(), seed, 0.0, 0.0, 0.2));
    prop_oneof![plate, torus, ico]
}

/// What validation says about a soup: the warnings, or the kind of error.
fn verdict(soup: PolygonSoup) -> Result<Vec<Warning>, String> {
    Mesh::from_soup(soup).map(|(_, w)| w).map_err(|e| format!("{:?}", std::mem::discriminant(&e)))
}

fn assert_unit_or_zero(normals: &[DVec3]) -> Result<(), TestCaseError> {
    for n in normals {
        prop_assert!(n.is_finite(), "{n}");
        prop_assert!(*n == DVec3::ZERO || (n.length() - 1.0).abs() < 1e-15, "{n}: {}", n.length());
    }
    Ok(())
}

/// Relative distance between two diagonals.
fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn scaling_by_powers_of_two_changes_no_verdict_and_scales_the_diagonal(mesh in any_mesh(), k in -1000i32..1000) {
        let s = PowerOfTwoScale { exponent: k };
        let soup = scaled(&mesh, s);
        prop_assert_eq!(verdict(soup.clone()), verdict(mesh.clone().into_soup()));
        let big = Mesh::from_soup(soup).unwrap().0;
        let d = big.bbox_diagonal();
        prop_assert!(d.is_finite() && d > 0.0);
        prop_assert!(rel(d, s.apply(mesh.bbox_diagonal())) <= 1e-15, "2^{}: {:e}", k, d);
        assert_unit_or_zero(&big.face_normals())?;
        assert_unit_or_zero(&big.vertex_normals())?;
        // The directions do not depend on the scale (subnormal coordinates may round).
        for (a, b) in big.face_normals().iter().zip(mesh.face_normals()) {
            prop_assert!((*a - b).length() < 1e-12, "{} vs {}", a, b);
        }
    }

    #[test]
    fn arbitrary_scales_and_translations_change_no_verdict(
        mesh in any_mesh(), exponent in -300.0f64..300.0, mantissa in 1.0f64..10.0,
        shift in prop::array::uniform3(-1.0f64..1.0), shift_exponent in -3.0f64..3.0,
    ) {
        let factor = mantissa * 10f64.powf(exponent);
        let d = mesh.bbox_diagonal();
        let translation = DVec3::from_array(shift) * d * 10f64.powf(shift_exponent);
        let mut soup = mesh.clone().into_soup();
        soup.positions.iter_mut().for_each(|p| *p = (*p + translation) * factor);
        prop_assert_eq!(verdict(soup.clone()), verdict(mesh.clone().into_soup()));
        let moved = Mesh::from_soup(soup).unwrap().0;
        // Translating rounds every coordinate to the ulp of the largest.
        let largest = moved.positions().iter().map(|p| p.abs().max_element()).fold(0.0, f64::max);
        let tolerance = 1e-15 + 8.0 * f64::EPSILON * largest / (d * factor);
        prop_assert!(rel(moved.bbox_diagonal(), d * factor) <= tolerance, "{:e} vs {:e}", moved.bbox_diagonal(), d * factor);
        assert_unit_or_zero(&moved.face_normals())?;
        assert_unit_or_zero(&moved.vertex_normals())?;
    }

    #[test]
    fn duplicate_points_give_unit_or_zero_normals_at_every_scale(mesh in any_mesh(), seed in any::<u64>(), k in -1000i32..1000) {
        // Move a few vertices onto others: faces may collapse to zero area (a
        // warning) but every normal stays unit or zero, and the verdict is
        // the same at every scale.
        let mut soup = mesh.clone().into_soup();
        let mut rng = SplitMix64(seed);
        let n = soup.positions.len();
        for _ in 0..1 + rng.below(4) {
            let (from, to) = (rng.below(n), rng.below(n));
            soup.positions[from] = soup.positions[to];
        }
        let s = PowerOfTwoScale { exponent: k };
        let mut big = soup.clone();
        s.apply_points(&mut big.positions);
        prop_assert_eq!(verdict(big.clone()), verdict(soup.clone()));
        if let Ok((mesh, _)) = Mesh::from_soup(big) {
            prop_assert!(mesh.bbox_diagonal().is_finite());
            assert_unit_or_zero(&mesh.face_normals())?;
            assert_unit_or_zero(&mesh.vertex_normals())?;
        }
    }
}
