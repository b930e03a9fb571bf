//! Refinement on normalised positions (issue #14): `subdivide`, the plan's
//! `apply`, `limit_points` and `subdivide` compute on positions scaled by a
//! power of two and scale back. Checked against the raw step functions (the
//! computation before normalisation) bit for bit, for exact scaling by 2^k,
//! and for the typed refusal of a surface beyond the range of f64.

use glam::DVec3;
use subdiv_mesh::refine::{dual_split, quad_split, triangle_split};
use subdiv_mesh::{shapes, Mesh, PowerOfTwoScale, Topology};
use subdiv_stencil::doo_sabin::{self, StandardCorners};
use subdiv_stencil::{apply, catmull_clark, deng_ma, loop_subdivision, sqrt3, subdivide, LevelSharpness};
use subdiv_stencil::{LoopBeta, Scheme, StencilError, SubdivisionPlan, Tension};

fn bits(points: &[DVec3]) -> Vec<[u64; 3]> {
    points.iter().map(|p| p.to_array().map(f64::to_bits)).collect()
}

fn schemes(t: &Topology) -> Vec<Scheme> {
    let mut all = vec![
        Scheme::DooSabin,
        Scheme::CatmullClark,
        Scheme::DengMa(Tension::Global(1.0)),
        Scheme::DengMa(Tension::Variable { lambda: 0.5 }),
    ];
    if t.faces().all_of_size(3) {
        all.push(Scheme::Loop(LoopBeta::Warren));
        all.push(Scheme::Sqrt3);
    }
    all
}

/// √3's raw steps: each level's parity carried in its sharpness.
fn raw_sqrt3(mesh: &Mesh, levels: usize) -> Vec<DVec3> {
    let mut t = mesh.topology().clone();
    let mut sharp = LevelSharpness::plain();
    let mut x = mesh.positions().to_vec();
    let rules = Scheme::Sqrt3.rules();
    for _ in 0..levels {
        x = sqrt3::step_points(&t, &sharp, &x).unwrap();
        let split = rules.split(&t, &sharp).unwrap();
        (t, sharp) = (split.topology, split.sharpness);
    }
    assert_eq!(rules.levels_before_limit(&t, &sharp, levels == 0), 0, "an even number of levels");
    sqrt3::limit_points(&t, &sharp, &x, t.vertex_count()).unwrap()
}

/// `levels` steps and the limit, by the raw step functions on the raw positions.
fn raw_subdivide(mesh: &Mesh, scheme: Scheme, levels: usize) -> Vec<DVec3> {
    if scheme == Scheme::Sqrt3 {
        return raw_sqrt3(mesh, levels);
    }
    let mut t = mesh.topology().clone();
    let mut x = mesh.positions().to_vec();
    for _ in 0..levels {
        let (next_t, next_x) = match scheme {
            Scheme::DooSabin => (dual_split(&t).0, doo_sabin::first_step(&t, &StandardCorners, &x).unwrap()),
            Scheme::CatmullClark => (quad_split(&t), catmull_clark::step_points(&t, &x)),
            Scheme::Loop(beta) => (triangle_split(&t).unwrap(), loop_subdivision::step_points(&t, beta, &x).unwrap()),
            Scheme::DengMa(tension) => (quad_split(&t), deng_ma::step_positions(&t, &x, tension).unwrap()),
            Scheme::Sqrt3 => unreachable!("raw_sqrt3"),
        };
        (t, x) = (next_t, next_x);
    }
    match scheme {
        Scheme::DooSabin => doo_sabin::limit_points(&t, &x),
        Scheme::CatmullClark => catmull_clark::limit_points(&t, &x),
        Scheme::Loop(beta) => loop_subdivision::limit_points(&t, beta, &x).unwrap(),
        Scheme::DengMa(_) => x,
        Scheme::Sqrt3 => unreachable!("raw_sqrt3"),
    }
}

fn ordinary_meshes() -> Vec<Mesh> {
    vec![
        shapes::torus(8, 5),
        shapes::polygon_mix(&shapes::torus(8, 6), 2, 0.2, 0.2, 0.1),
        shapes::plate_with_holes(4, 3, &[(1, 1)], false),
        shapes::triangle_grid(3, 2),
    ]
}

#[test]
fn normalising_changes_no_bit_on_ordinary_meshes() {
    for mesh in ordinary_meshes() {
        assert!(!PowerOfTwoScale::normalizing(mesh.positions().iter().copied()).is_identity());
        for scheme in schemes(mesh.topology()) {
            let raw = raw_subdivide(&mesh, scheme, 2);
            let ruled = subdivide(&mesh, scheme, 2, true).unwrap();
            assert!(bits(ruled.positions()) == bits(&raw), "{scheme:?}");
            // The plan: apply and limit_points against the raw stencil products.
            let plan = SubdivisionPlan::new(mesh.topology(), scheme, 2).unwrap();
            let mut x = mesh.positions().to_vec();
            let mut coarse = plan.base();
            for level in plan.levels() {
                x = match (&level.stencil, scheme) {
                    (Some(r), _) => apply(r, &x),
                    (None, Scheme::DengMa(tension)) => deng_ma::step_positions(coarse, &x, tension).unwrap(),
                    (None, s) => panic!("{s:?} without a stencil"),
                };
                coarse = &level.topology;
            }
            assert!(bits(&plan.apply(mesh.positions())) == bits(&x), "{scheme:?} apply");
            if let (Some(limits), Some(Ok(r))) = (plan.limit_points(&x), plan.limit_stencil()) {
                let raw_limits = match scheme {
                    Scheme::DooSabin => doo_sabin::limit_points(plan.topology(), &x),
                    Scheme::CatmullClark => catmull_clark::limit_points(plan.topology(), &x),
                    Scheme::Loop(beta) => loop_subdivision::limit_points(plan.topology(), beta, &x).unwrap(),
                    Scheme::DengMa(_) => unreachable!(),
                    Scheme::Sqrt3 => sqrt3::limit_points(plan.topology(), plan.sharpness(), &x, x.len()).unwrap(),
                };
                assert!(bits(&limits) == bits(&raw_limits), "{scheme:?} limit_points");
                assert!(limits.iter().zip(apply(&r, &x)).all(|(a, b)| a.distance(b) < 1e-12));
            }
            // The plan's subdivide: the raw stencil products and limit (the
            // single-use `subdivide` evaluates directly: equal up to round-off).
            let raw_planned = plan.limit_points(&x).unwrap_or(x);
            let planned = plan.subdivide(&mesh, true).unwrap();
            assert!(bits(planned.positions()) == bits(&raw_planned), "{scheme:?} plan");
        }
    }
}

#[test]
fn power_of_two_scales_give_exactly_scaled_surfaces() {
    for mesh in ordinary_meshes() {
        for exponent in [-1000, -300, 7, 512, 1000] {
            let scale = PowerOfTwoScale { exponent };
            let mut big = mesh.clone();
            scale.apply_points(big.positions_mut());
            for scheme in schemes(mesh.topology()) {
                let plain = subdivide(&mesh, scheme, 2, true).unwrap();
                let scaled = subdivide(&big, scheme, 2, true).unwrap();
                for (a, p) in scaled.positions().iter().zip(plain.positions()) {
                    for (x, y) in a.to_array().into_iter().zip(scale.apply_point(*p).to_array()) {
                        // Exact unless the scaled value is subnormal.
                        if y == 0.0 || y.abs() >= f64::MIN_POSITIVE {
                            assert_eq!(x.to_bits(), y.to_bits(), "{scheme:?} 2^{exponent}");
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn issue_14_deng_ma_on_a_tetrahedron_with_a_coordinate_of_1_7e308_is_finite() {
    for coordinate in [1e308, 1.7e308, f64::MAX, -f64::MAX] {
        let tet = shapes::tetrahedron();
        let mut p = tet.positions().to_vec();
        p[0].x = coordinate;
        let mesh = tet.with_positions(p);
        for scheme in schemes(mesh.topology()) {
            for limit in [false, true] {
                let refined = subdivide(&mesh, scheme, 3, limit).unwrap();
                assert!(refined.positions().iter().all(|p| p.is_finite()), "{coordinate:e} {scheme:?}");
                let planned = SubdivisionPlan::new(mesh.topology(), scheme, 3).unwrap().subdivide(&mesh, limit);
                assert!(planned.unwrap().positions().iter().all(|p| p.is_finite()), "{coordinate:e} {scheme:?}");
            }
        }
    }
}

/// Heights 0 and 1.7e308 on the cube: Deng-Ma's interpolatory step overshoots beyond f64.
fn overshooting_cube() -> Mesh {
    let cube = shapes::cube();
    let p =
        cube.positions().iter().enumerate().map(|(i, p)| DVec3::new(p.x, p.y, if i % 2 == 0 { 1.7e308 } else { 0.0 }));
    cube.with_positions(p.collect())
}

#[test]
fn a_surface_beyond_f64_is_refused_naming_the_vertex_and_its_magnitude() {
    let mesh = overshooting_cube();
    let scheme = Scheme::DengMa(Tension::Global(1.0));
    let err = subdivide(&mesh, scheme, 1, false).unwrap_err();
    let expected = "deng-ma: the refined surface leaves the range of f64: vertex 12 would have a coordinate of \
                    about 2.0e308, beyond the largest f64 (1.7977e308)";
    assert_eq!(err.to_string(), expected);
    assert!(matches!(err, StencilError::NotRepresentable { scheme: "deng-ma", .. }));
    let plan = SubdivisionPlan::new(mesh.topology(), scheme, 1).unwrap();
    assert_eq!(plan.subdivide(&mesh, false).unwrap_err(), err);
    // `apply` is the unchecked path: the coordinate comes back as inf.
    assert_eq!(plan.apply(mesh.positions())[12].z, f64::INFINITY);
    // Approximating schemes form convex combinations: they fit.
    for scheme in [Scheme::DooSabin, Scheme::CatmullClark] {
        assert!(subdivide(&mesh, scheme, 3, true).unwrap().positions().iter().all(|p| p.is_finite()));
    }
}

#[test]
fn a_non_finite_input_coordinate_is_named() {
    let cube = shapes::cube();
    let mut p = cube.positions().to_vec();
    p[2].y = f64::NAN;
    let mesh = cube.with_positions(p);
    for scheme in [Scheme::DooSabin, Scheme::CatmullClark, Scheme::DengMa(Tension::Global(1.0))] {
        for levels in [0, 1] {
            let err = subdivide(&mesh, scheme, levels, false).unwrap_err();
            assert!(err.to_string().contains("input vertex 2 has a non-finite coordinate"), "{scheme:?}: {err}");
        }
    }
}

#[test]
fn input_vertices_that_stay_are_copied_bit_for_bit_even_when_their_scaled_copy_is_subnormal() {
    // 1e-310 beside 1e3: scaled by 2^-10 it is subnormal and would round.
    let cube = shapes::cube();
    let mut p: Vec<DVec3> = cube.positions().iter().map(|&p| p * 1e3).collect();
    p[1] = DVec3::new(1e-310, 3e-320, 1e3);
    let mesh = cube.with_positions(p.clone());
    let unchanged = subdivide(&mesh, Scheme::CatmullClark, 0, false).unwrap();
    assert_eq!(bits(unchanged.positions()), bits(&p));
    for tension in [Tension::Global(1.0), Tension::Variable { lambda: 1.0 }] {
        let refined = subdivide(&mesh, Scheme::DengMa(tension), 2, true).unwrap();
        assert_eq!(bits(&refined.positions()[..8]), bits(&p), "{tension:?}");
    }
}
