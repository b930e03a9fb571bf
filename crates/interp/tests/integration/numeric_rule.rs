//! The numeric rule of issue #14, for every method and every scheme: a
//! result is returned only if every coordinate is a finite f64 and the
//! independently measured error is within the tolerance; otherwise a typed
//! error. NaN never disappears from a maximum. Regression tests for the
//! failures the torture run found, then proptests over random scales
//! (1e-300..1e300), translations (up to 1e300) and duplicated points.

use glam::DVec3;
use proptest::prelude::*;
use subdiv_interp::verify::nearest_gap;
use subdiv_interp::{
    cheng, deng_ma, deng_wang, fan_cheng_lai, nasri, zheng_cai, ChengOptions, DengMaOptions, DengWangOptions,
    FanChengLaiOptions, InterpError, Interpolant, NasriOptions, Parameter, ZhengCaiOptions, DEFAULT_TOL,
};
use subdiv_mesh::{shapes, Mesh, PowerOfTwoScale};
use subdiv_stencil::{subdivide, LoopBeta, Scheme, StencilError, Tension};

/// The six methods with their default options on `mesh`.
fn every_method(mesh: &Mesh) -> Vec<(&'static str, Result<Interpolant, InterpError>)> {
    vec![
        ("nasri", nasri::interpolate(mesh, &NasriOptions::default())),
        ("zheng-cai", zheng_cai::interpolate(mesh, &ZhengCaiOptions::default())),
        ("cheng", cheng::interpolate(mesh, &ChengOptions::default())),
        ("fan-cheng-lai", fan_cheng_lai::interpolate(mesh, &FanChengLaiOptions::default())),
        ("deng-wang", deng_wang::interpolate(mesh, &DengWangOptions::default())),
        ("deng-ma", deng_ma::interpolate(mesh, &DengMaOptions::default())),
    ]
}

/// The schemes that take `mesh` (Loop: triangles only).
fn schemes(mesh: &Mesh) -> Vec<Scheme> {
    let t = mesh.topology();
    let mut all = vec![Scheme::DooSabin, Scheme::CatmullClark, Scheme::DengMa(Tension::Global(1.0))];
    all.push(Scheme::DengMa(Tension::Variable { lambda: 0.5 }));
    if t.face_ids().all(|f| t.face_size(f) == 3) {
        all.push(Scheme::Loop(LoopBeta::Warren));
    }
    all
}

/// d without overflow or underflow: the diagonal of the data scaled by a
/// power of two, scaled back (independent of `Mesh::bbox_diagonal`).
fn diagonal(mesh: &Mesh) -> f64 {
    let scale = PowerOfTwoScale::normalizing(mesh.positions().iter().copied());
    let mut scaled = mesh.clone();
    scale.apply_points(scaled.positions_mut());
    scale.inverse().apply(scaled.bbox_diagonal())
}

fn finite(mesh: &Mesh) -> bool {
    mesh.positions().iter().all(|p| p.is_finite())
}

/// The rule for one result: finite control mesh, measured error ≤ tol over
/// the interpolated vertices, a one-line message otherwise. Returns whether
/// it succeeded.
fn check_rule(what: &str, data: &Mesh, result: &Result<Interpolant, InterpError>, tol: f64) -> bool {
    match result {
        Ok(r) => {
            assert!(finite(&r.control), "{what}: non-finite control mesh returned");
            let e = r.error(data.positions(), &r.interpolated, diagonal(data));
            assert!(e.max_rel <= tol, "{what}: measured error {:e} > {tol:e} returned as success", e.max_rel);
            assert!(e.max_abs.is_finite() && e.mean_rel <= e.max_rel * (1.0 + 1e-12), "{what}: {e:?}");
            true
        }
        Err(e) => {
            assert!(!e.to_string().contains('\n'), "{what}: message on more than one line: {e}");
            false
        }
    }
}

/// The rule for `subdivide`: finite output or a typed error.
fn check_subdivide(what: &str, mesh: &Mesh, scheme: Scheme, levels: usize) -> Option<Mesh> {
    match subdivide(mesh, scheme, levels, true) {
        Ok(refined) => {
            assert!(finite(&refined), "{what}: non-finite refined mesh returned");
            Some(refined)
        }
        Err(e @ StencilError::NotRepresentable { .. }) => {
            assert!(!e.to_string().contains('\n'), "{what}: {e}");
            None
        }
        Err(e) => panic!("{what}: unexpected {e}"),
    }
}

fn bits(points: &[DVec3]) -> Vec<[u64; 3]> {
    points.iter().map(|p| p.to_array().map(f64::to_bits)).collect()
}

/// `actual` is `unscaled`·`scale` bit for bit, except for coordinates whose
/// scaled value is subnormal (scaling them rounds).
fn assert_scaled_bits(what: &str, actual: &[DVec3], unscaled: &[DVec3], scale: PowerOfTwoScale) {
    assert_eq!(actual.len(), unscaled.len(), "{what}");
    for (i, (a, u)) in actual.iter().zip(unscaled).enumerate() {
        let expected = scale.apply_point(*u);
        for (x, y) in a.to_array().into_iter().zip(expected.to_array()) {
            if y == 0.0 || y.abs() >= f64::MIN_POSITIVE {
                assert_eq!(x.to_bits(), y.to_bits(), "{what}: vertex {i}: {a} is not {u}·2^{}", scale.exponent);
            }
        }
    }
}

fn scaled(mesh: &Mesh, scale: PowerOfTwoScale) -> Mesh {
    let mut out = mesh.clone();
    scale.apply_points(out.positions_mut());
    out
}

fn tetrahedron_with(coordinate: f64) -> Mesh {
    let t = shapes::tetrahedron();
    let mut p = t.positions().to_vec();
    p[0].x = coordinate;
    t.with_positions(p)
}

// ---- class 1: exit 0 with non-finite output ----

/// `Ok` for the methods in `fits`; for the others the control mesh itself
/// does not fit in f64 (it overshoots the data): `NotRepresentable`.
fn expect_fits(mesh: &Mesh, fits: &[&str], borderline: &[&str]) {
    for (name, result) in every_method(mesh) {
        if fits.contains(&name) || (borderline.contains(&name) && result.is_ok()) {
            assert!(check_rule(name, mesh, &result, DEFAULT_TOL), "{name}: {:?}", result.err());
            check_surface(name, &result.unwrap());
        } else {
            let err = result.expect_err(name);
            assert!(matches!(err, InterpError::NotRepresentable { .. }), "{name}: {err}");
            let text = err.to_string();
            assert!(text.starts_with(&format!("{name}: the control mesh leaves the range of f64: vertex ")), "{text}");
            assert!(text.contains("e308, beyond the largest f64 (1.7977e308)"), "{text}");
        }
    }
}

/// The surface of a result at two levels is finite or refused as not representable.
fn check_surface(name: &str, result: &Interpolant) {
    match result.surface(2) {
        Ok(surface) => assert!(finite(&surface), "{name}: non-finite surface"),
        Err(e) => assert!(matches!(e, InterpError::NotRepresentable { .. }), "{name}: {e}"),
    }
}

#[test]
fn issue_14_tetrahedron_with_one_coordinate_of_1e308_is_interpolated_finitely() {
    let mesh = tetrahedron_with(1e308);
    // Cheng's control point lies at 3.6e308: Catmull-Clark limit masks shrink, so M̂ overshoots P.
    // Deng-Wang's lies within 1% of f64::MAX (≈ 1.79e308–1.8e308): whether it is representable
    // depends on the last bits of the other, subnormal, coordinates after normalisation; either
    // outcome keeps the rule (Ok and finite within tol, or NotRepresentable).
    expect_fits(&mesh, &["nasri", "zheng-cai", "fan-cheng-lai", "deng-ma"], &["deng-wang"]);
    for scheme in schemes(&mesh) {
        check_subdivide(&format!("{scheme:?}"), &mesh, scheme, 3).expect("the surface of 1e308 data fits");
    }
}

#[test]
fn issue_14_tetrahedron_with_one_coordinate_of_1_7e308_is_finite_or_refused() {
    let mesh = tetrahedron_with(1.7e308);
    expect_fits(&mesh, &["zheng-cai", "fan-cheng-lai", "deng-ma"], &[]);
    // `subdivide --scheme deng-ma` wrote NaN here: every scheme's surface fits.
    for scheme in schemes(&mesh) {
        check_subdivide(&format!("{scheme:?}"), &mesh, scheme, 3).expect("the surface of 1.7e308 data fits");
    }
}

#[test]
fn a_deng_ma_surface_beyond_f64_is_refused_naming_the_vertex() {
    // Heights 0 and 1.7e308 on the cube's vertices: the interpolatory step overshoots.
    let cube = shapes::cube();
    let p =
        cube.positions().iter().enumerate().map(|(i, p)| DVec3::new(p.x, p.y, if i % 2 == 0 { 1.7e308 } else { 0.0 }));
    let mesh = cube.with_positions(p.collect());
    let result = deng_ma::interpolate(&mesh, &DengMaOptions::default()).unwrap();
    let err = result.surface(1).unwrap_err();
    assert!(matches!(err, InterpError::NotRepresentable { method: "deng-ma", .. }), "{err}");
    let text = err.to_string();
    assert!(text.starts_with("deng-ma: the refined surface leaves the range of f64: vertex 12 "), "{text}");
    assert!(text.contains("about 2.0e308, beyond the largest f64"), "{text}");
}

#[test]
fn coordinates_near_1e154_whose_diagonal_overflows_are_interpolated_exactly_scaled() {
    // 2^512 ≈ 1.3e154: |p|² overflows in the raw diagonal.
    for base in [shapes::icosahedron(), shapes::cube(), shapes::quad_grid(3, 2)] {
        check_exact_scaling(&base, PowerOfTwoScale { exponent: 512 });
        let mut translated = base.clone();
        translated.positions_mut().iter_mut().for_each(|p| *p = *p * 2f64.powi(500) + DVec3::splat(-1e154));
        for (name, result) in every_method(&translated) {
            assert!(check_rule(name, &translated, &result, DEFAULT_TOL), "{name}: {:?}", result.err());
        }
    }
}

#[test]
fn coordinates_near_1e_300_whose_diagonal_underflows_are_interpolated_exactly_scaled() {
    // 2^-1000 ≈ 9.3e-302: |p|² underflows in the raw diagonal.
    for base in [shapes::icosahedron(), shapes::cube(), shapes::triangle_grid(2, 2)] {
        check_exact_scaling(&base, PowerOfTwoScale { exponent: -1000 });
    }
}

/// Every method and scheme on `base`·2^k gives `base`'s result·2^k, bit for
/// bit, and satisfies the rule.
fn check_exact_scaling(base: &Mesh, scale: PowerOfTwoScale) {
    let mesh = scaled(base, scale);
    for ((name, plain), (_, big)) in every_method(base).into_iter().zip(every_method(&mesh)) {
        assert!(check_rule(name, &mesh, &big, DEFAULT_TOL), "{name}: {:?}", big.as_ref().err());
        let (plain, big) = (plain.unwrap(), big.unwrap());
        assert_scaled_bits(name, big.control.positions(), plain.control.positions(), scale);
        assert_eq!(plain.solve.map(|s| s.history), big.solve.map(|s| s.history), "{name}");
    }
    for scheme in schemes(base) {
        let plain = check_subdivide("plain", base, scheme, 2).unwrap();
        let big = check_subdivide("scaled", &mesh, scheme, 2).unwrap();
        assert_scaled_bits(&format!("{scheme:?}"), big.positions(), plain.positions(), scale);
    }
}

#[test]
fn coincident_vertices_are_refused_by_every_method() {
    let cube = shapes::cube();
    let mesh = cube.with_positions(vec![DVec3::new(1.0, -2.0, 3.0); 8]);
    for (name, result) in every_method(&mesh) {
        let err = result.unwrap_err();
        assert!(matches!(err, InterpError::CoincidentVertices { .. }), "{name}: {err}");
        assert!(err.to_string().starts_with(&format!("{name}: all vertices")), "{err}");
        assert!(!err.is_not_converged());
    }
    // Subdividing them is well defined: the same point everywhere (to round-off).
    let point = DVec3::new(1.0, -2.0, 3.0);
    for scheme in schemes(&mesh) {
        let refined = check_subdivide("coincident", &mesh, scheme, 2).unwrap();
        assert!(refined.positions().iter().all(|&p| p.distance(point) <= 1e-15), "{scheme:?}");
    }
}

#[test]
fn data_spanning_more_than_f64_holds_are_refused_by_every_method() {
    let cube = shapes::cube();
    let p = cube.positions().iter().map(|&p| (p - DVec3::splat(0.5)) * f64::MAX).collect();
    let mesh = cube.with_positions(p);
    assert!(mesh.positions().iter().all(|p| p.is_finite()));
    for (name, result) in every_method(&mesh) {
        let err = result.unwrap_err();
        assert!(matches!(err, InterpError::NotRepresentable { .. }), "{name}: {err}");
        assert!(err.to_string().contains("bounding-box diagonal is about 3.1e308, beyond the largest f64"), "{err}");
    }
    // Refinement is a convex combination: it fits.
    for scheme in [Scheme::DooSabin, Scheme::CatmullClark] {
        check_subdivide("±f64::MAX", &mesh, scheme, 2).unwrap();
    }
}

// ---- class 2: exit 0 although the error is above --tol ----

#[test]
fn isolated_vertices_are_left_out_by_every_method_with_a_warning() {
    for base in [shapes::cube(), shapes::icosahedron(), shapes::quad_grid(3, 3)] {
        let mut positions = base.positions().to_vec();
        positions.push(DVec3::new(5.0, 5.0, 5.0));
        positions.push(DVec3::new(-3.0, 0.0, 1.0));
        let nv = base.topology().vertex_count();
        let mesh = Mesh::new(positions, base.topology().faces().clone()).unwrap();
        for (name, result) in every_method(&mesh) {
            assert!(check_rule(name, &mesh, &result, DEFAULT_TOL), "{name}: {:?}", result.as_ref().err());
            let r = result.unwrap();
            assert!(
                r.warnings.iter().any(|w| w.starts_with("2 isolated vertices") && w.contains("not interpolated")),
                "{name}: {:?}",
                r.warnings
            );
            assert_eq!(r.interpolated.len(), nv + 2, "{name}");
            assert!(r.interpolated[..nv].iter().all(|&b| b) && !r.interpolated[nv] && !r.interpolated[nv + 1]);
            assert_eq!(r.parameters.interpolated_vertices, Some(nv), "{name}");
        }
    }
    // A subset of isolated vertices only leaves nothing to interpolate.
    let cube = shapes::cube();
    let mut positions = cube.positions().to_vec();
    positions.push(DVec3::splat(5.0));
    let mesh = Mesh::new(positions, cube.topology().faces().clone()).unwrap();
    let err = nasri::interpolate(&mesh, &NasriOptions::default().with_subset(vec![8])).unwrap_err();
    assert!(matches!(err, InterpError::InvalidParameter { parameter: Parameter::Subset, .. }), "{err}");
}

#[test]
fn the_limit_point_of_an_isolated_vertex_is_nan_and_nan_is_never_dropped_from_the_maximum() {
    let cube = shapes::cube();
    let mut positions = cube.positions().to_vec();
    positions.push(DVec3::splat(5.0));
    let mesh = Mesh::new(positions, cube.topology().faces().clone()).unwrap();
    let r = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default()).unwrap();
    // Measured over every vertex (as the CLI did): the isolated one has no limit point.
    let all = vec![true; 9];
    let e = r.error(mesh.positions(), &all, mesh.bbox_diagonal());
    assert!(e.max_rel.is_nan() && e.max_abs.is_nan() && e.mean_rel.is_nan(), "{e:?}");
    assert!(r.limit_points(9)[8].is_nan());
    // A NaN control vertex anywhere makes the maximum NaN, not the largest number.
    let mut broken = nasri::interpolate(&cube, &NasriOptions::default()).unwrap();
    broken.control.positions_mut()[3] = DVec3::new(f64::NAN, 0.0, 0.0);
    let e = broken.error(cube.positions(), &[true; 8], cube.bbox_diagonal());
    assert!(e.max_rel.is_nan(), "{e:?}");
    // The independent check too.
    let targets = [DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 0.0), DVec3::ONE];
    assert!(nearest_gap(&targets, &[DVec3::ZERO, DVec3::ONE], 1.0).is_nan());
    assert_eq!(nearest_gap(&[DVec3::ZERO, DVec3::ONE], &[DVec3::ZERO, DVec3::ONE], 1.0), 0.0);
}

#[test]
fn huge_shape_handles_fail_the_measured_error_check() {
    let mesh = shapes::torus(8, 6);
    let n = mesh.topology().vertex_count();
    for handle in [1e12, 1e15, 1e300] {
        let handles: Option<Vec<f64>> = Some((0..n).map(|v| if v % 3 == 0 { handle } else { 1.0 }).collect());
        let result = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default().with_handles(handles));
        let err = result.expect_err("round-off of S·d is far above 1e-6·d");
        match &err {
            InterpError::ToleranceNotMet { max_rel, tol, .. } => {
                assert!((max_rel.is_nan() || *max_rel > *tol) && *tol == DEFAULT_TOL, "{err}");
                assert!(err.to_string().contains("exceeds the tolerance") || max_rel.is_nan(), "{err}");
                assert!(err.is_not_converged(), "exit 3");
            }
            InterpError::NotRepresentable { .. } => assert!(handle >= 1e300, "{handle}: {err}"),
            other => panic!("{handle}: {other}"),
        }
    }
    // Moderate handles still interpolate.
    let handles: Option<Vec<f64>> = Some((0..n).map(|v| if v % 3 == 0 { 4.0 } else { 1.0 }).collect());
    let result = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default().with_handles(handles));
    assert!(check_rule("S = 4", &mesh, &result, DEFAULT_TOL));
}

#[test]
fn huge_mu_fails_the_measured_error_check() {
    let mesh = shapes::icosahedron();
    for mu in [1e17, 1e300, -1e300] {
        let err = deng_wang::interpolate(&mesh, &DengWangOptions::default().with_mu(mu)).unwrap_err();
        assert!(
            matches!(err, InterpError::ToleranceNotMet { .. } | InterpError::NotRepresentable { .. }),
            "μ = {mu}: {err}"
        );
    }
    let result = deng_wang::interpolate(&mesh, &DengWangOptions::default().with_mu(3.0));
    assert!(check_rule("μ = 3", &mesh, &result, DEFAULT_TOL));
}

#[test]
fn a_tighter_tolerance_than_round_off_is_reported_not_met() {
    // Exact-by-construction methods measure too: 1e-300·d is below their round-off.
    let mesh = shapes::polygon_mix(&shapes::torus(8, 6), 3, 0.2, 0.2, 0.1);
    let err = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default().with_tol(1e-300)).unwrap_err();
    assert!(matches!(err, InterpError::ToleranceNotMet { tol, .. } if tol == 1e-300), "{err}");
    assert!(err.is_not_converged());
}

// ---- parameters ----

#[test]
fn invalid_parameters_name_the_parameter_on_one_line() {
    let mesh = shapes::icosahedron();
    let mut normals = vec![None; 12];
    normals[3] = Some(DVec3::ZERO);
    let err = deng_wang::interpolate(&mesh, &DengWangOptions::default().with_normals(normals.clone())).unwrap_err();
    assert!(matches!(err, InterpError::InvalidParameter { parameter: Parameter::Normals, .. }), "{err}");
    assert!(err.to_string().starts_with("invalid normals: the normal of vertex 3"), "{err}");
    let err = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default().with_normals(normals)).unwrap_err();
    assert!(matches!(err, InterpError::InvalidParameter { parameter: Parameter::Normals, .. }), "{err}");
    for tol in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let err = cheng::interpolate(&mesh, &ChengOptions::default().with_tol(tol)).unwrap_err();
        assert!(matches!(err, InterpError::InvalidParameter { parameter: Parameter::Tol, .. }), "{tol}: {err}");
    }
    let err = fan_cheng_lai::interpolate(&mesh, &FanChengLaiOptions::default().with_subset(Vec::new())).unwrap_err();
    assert!(matches!(err, InterpError::InvalidParameter { parameter: Parameter::Subset, .. }), "{err}");
    assert_eq!(err.to_string(), "invalid subset: the subset is empty: there is nothing to interpolate");
    let shape = subdiv_interp::Shape::Uniform(1.5);
    let err = fan_cheng_lai::interpolate(&mesh, &FanChengLaiOptions::default().with_shape(shape)).unwrap_err();
    assert!(matches!(err, InterpError::InvalidParameter { parameter: Parameter::Shape, .. }), "{err}");
    let err = deng_ma::interpolate(&mesh, &DengMaOptions::default().with_tension(Tension::Global(2.0))).unwrap_err();
    assert!(matches!(err, InterpError::InvalidParameter { parameter: Parameter::Tension, .. }), "{err}");
    let err = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default().with_eps(f64::NAN)).unwrap_err();
    assert!(matches!(err, InterpError::InvalidParameter { parameter: Parameter::Eps, .. }), "{err}");
    let handles = Some(vec![0.0; 12]);
    let err = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default().with_handles(handles)).unwrap_err();
    assert!(matches!(err, InterpError::InvalidParameter { parameter: Parameter::Handles, .. }), "{err}");
}

#[test]
fn normals_given_with_tiny_or_huge_components_keep_their_direction() {
    let mesh = shapes::torus(8, 6);
    let n = mesh.topology().vertex_count();
    let with = |length: f64| {
        let normals: Vec<Option<DVec3>> =
            (0..n).map(|v| (v % 4 == 1).then(|| DVec3::new(0.3, 0.9, 0.1) * length)).collect();
        let zc = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default().with_normals(normals));
        let normals: Vec<Option<DVec3>> =
            (0..n).map(|v| (v % 4 == 1).then(|| DVec3::new(0.3, 0.9, 0.1) * length)).collect();
        let dw = deng_wang::interpolate(&mesh, &DengWangOptions::default().with_normals(normals));
        (bits(zc.unwrap().control.positions()), bits(dw.unwrap().control.positions()))
    };
    let unit = with(1.0);
    // Powers of two: the same direction bit for bit.
    assert_eq!(with(2f64.powi(-700)), unit);
    assert_eq!(with(2f64.powi(900)), unit);
}

// ---- random scales, translations, duplicated points ----

fn base_shape() -> impl Strategy<Value = Mesh> {
    prop_oneof![
        Just(shapes::tetrahedron()),
        Just(shapes::cube()),
        Just(shapes::octahedron()),
        Just(shapes::icosahedron()),
        Just(shapes::pyramid(5)),
        Just(shapes::prism(4)),
        Just(shapes::torus(4, 3)),
        Just(shapes::quad_grid(3, 2)),
        Just(shapes::triangle_grid(2, 2)),
        Just(shapes::pillow()),
    ]
}

/// A log-uniform magnitude in [1e-300, 1e300] with a sign.
fn magnitude() -> impl Strategy<Value = f64> {
    (-300.0..300.0f64, any::<bool>()).prop_map(|(e, negative)| if negative { -(10f64.powf(e)) } else { 10f64.powf(e) })
}

/// A translation: zero, or up to 1e300 per axis.
fn translation() -> impl Strategy<Value = DVec3> {
    prop_oneof![Just(DVec3::ZERO), (magnitude(), magnitude(), magnitude()).prop_map(|(x, y, z)| DVec3::new(x, y, z))]
}

/// A shape scaled, translated, with up to two vertices moved onto others.
fn extreme_mesh() -> impl Strategy<Value = Mesh> {
    (base_shape(), magnitude(), translation(), proptest::collection::vec((any::<u16>(), any::<u16>()), 0..3)).prop_map(
        |(base, scale, shift, duplicates)| {
            let mut p: Vec<DVec3> = base.positions().iter().map(|&p| p * scale + shift).collect();
            let n = p.len();
            for (i, j) in duplicates {
                p[i as usize % n] = p[j as usize % n];
            }
            base.with_positions(p)
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn every_method_and_scheme_returns_finite_results_within_tolerance_or_a_typed_error(mesh in extreme_mesh()) {
        prop_assume!(finite(&mesh));
        for (name, result) in every_method(&mesh) {
            check_rule(name, &mesh, &result, DEFAULT_TOL);
            if let Ok(r) = result {
                if let Ok(surface) = r.surface(1) {
                    prop_assert!(finite(&surface), "{}: non-finite surface", name);
                }
            }
        }
        for scheme in schemes(&mesh) {
            check_subdivide(&format!("{scheme:?}"), &mesh, scheme, 2);
        }
    }

    #[test]
    fn power_of_two_scales_give_exactly_scaled_results(base in base_shape(), exponent in -1000i32..1000) {
        let scale = PowerOfTwoScale { exponent };
        let mesh = scaled(&base, scale);
        // The claim is about exactly scaled data: a coordinate that scaling
        // pushes onto the subnormal grid is rounded already in the input (a
        // prism's 6e-17 by 2^-970), and then the methods see other data.
        let exact = mesh.positions().iter().zip(base.positions()).all(|(s, b)| scale.inverse().apply_point(*s) == *b);
        prop_assume!(exact);
        for ((name, plain), (_, big)) in every_method(&base).into_iter().zip(every_method(&mesh)) {
            match (plain, big) {
                (Ok(plain), Ok(big)) => {
                    assert_scaled_bits(name, big.control.positions(), plain.control.positions(), scale);
                }
                (Err(a), Err(b)) => prop_assert_eq!(std::mem::discriminant(&a), std::mem::discriminant(&b), "{}", name),
                (a, b) => prop_assert!(false, "{}: {:?} unscaled, {:?} scaled", name, a.err(), b.err()),
            }
        }
    }
}
