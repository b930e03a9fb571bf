//! Properties of the evaluation at arbitrary parameters: derivatives against
//! central differences, unit normals oriented like the faces, the stencil's
//! weight sums, `evaluate` equal to the stencil applied and to the bound
//! surface, continuity across shared edges, typed errors on bad parameters,
//! a proptest over generated meshes, and the fixtures.

use crate::common;

use crate::common::params;
use proptest::prelude::*;
use subdiv_eval::{EvalError, LimitSurface, SurfaceParam};
use subdiv_mesh::{shapes, FaceId, Mesh, Tags};
use subdiv_rules::LoopBeta;
use subdiv_stencil::{Options, Scheme};

fn cc() -> Options {
    Options::new(Scheme::CatmullClark)
}

fn lp() -> Options {
    Options::new(Scheme::Loop(LoopBeta::default()))
}

fn is_loop(o: &Options) -> bool {
    matches!(o.scheme, Scheme::Loop(_))
}

/// The properties on `per_domain` parameters of every domain.
fn check_properties(name: &str, mesh: &Mesh, options: Options, per_domain: usize) {
    let surface = LimitSurface::new(mesh, &options).unwrap();
    let x = mesh.positions();
    let d = mesh.bbox_diagonal();
    let bound = surface.bind(x).unwrap();
    let triangle = is_loop(&options);
    for p in params(&surface, per_domain, triangle) {
        let s = surface.evaluate(x, p).unwrap();
        // evaluate == bound == stencil applied.
        let b = bound.evaluate(p).unwrap();
        assert!((s.position - b.position).length() <= 1e-13 * d, "{name} {p:?}");
        let st = surface.stencil(p).unwrap();
        let (pos, du, dv) = st.apply(x);
        assert!((pos - s.position).length() <= 1e-12 * d, "{name} {p:?}");
        assert!((du - s.du).length() <= 1e-11 * d.max(s.du.length()), "{name} {p:?}");
        assert!((dv - s.dv).length() <= 1e-11 * d.max(s.dv.length()), "{name} {p:?}");
        // Weight sums: 1 for the position, 0 for the derivatives.
        assert!((st.position.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{name} {p:?}");
        assert!(st.du.iter().sum::<f64>().abs() < 1e-10, "{name} {p:?}");
        assert!(st.dv.iter().sum::<f64>().abs() < 1e-10, "{name} {p:?}");
        // Unit normal.
        assert!((s.normal.length() - 1.0).abs() < 1e-12, "{name} {p:?}: {:?}", s.normal);
        // Central differences, where the step stays inside the domain.
        let h = 1e-6;
        let inside = |u: f64, v: f64| u >= 0.0 && v >= 0.0 && u <= 1.0 && v <= 1.0 && (!triangle || u + v <= 1.0);
        let at = |u, v| surface.evaluate(x, SurfaceParam { u, v, ..p }).unwrap();
        if inside(p.u - h, p.v) && inside(p.u + h, p.v) {
            let fd = (at(p.u + h, p.v).position - at(p.u - h, p.v).position) / (2.0 * h);
            assert!((fd - s.du).length() <= 1e-6 * (1.0 + s.du.length()) * d, "{name} {p:?}: {fd} vs {}", s.du);
            let j = bound.evaluate_jet(p).unwrap();
            let fdd = (at(p.u + h, p.v).du - at(p.u - h, p.v).du) / (2.0 * h);
            assert!((fdd - j.duu).length() <= 1e-5 * (1.0 + j.duu.length()) * d, "{name} {p:?} duu");
            let fdv = (at(p.u + h, p.v).dv - at(p.u - h, p.v).dv) / (2.0 * h);
            assert!((fdv - j.duv).length() <= 1e-5 * (1.0 + j.duv.length()) * d, "{name} {p:?} duv");
        }
        if inside(p.u, p.v - h) && inside(p.u, p.v + h) {
            let fd = (at(p.u, p.v + h).position - at(p.u, p.v - h).position) / (2.0 * h);
            assert!((fd - s.dv).length() <= 1e-6 * (1.0 + s.dv.length()) * d, "{name} {p:?}: {fd} vs {}", s.dv);
        }
    }
}

/// The limit normal at a face's centre agrees with the face's own normal
/// on a convex shape (orientation).
fn check_orientation(mesh: &Mesh, options: Options) {
    let surface = LimitSurface::new(mesh, &options).unwrap();
    for dom in surface.domains() {
        let (u, v) = if is_loop(&options) { (1.0 / 3.0, 1.0 / 3.0) } else { (0.5, 0.5) };
        let s = surface.evaluate(mesh.positions(), SurfaceParam::new(dom.face, dom.corner, u, v)).unwrap();
        let n = mesh.face_normal(FaceId(dom.face));
        assert!(s.normal.dot(n) > 0.5, "{dom:?}: {} vs face {}", s.normal, n);
    }
}

#[test]
fn catmull_clark_properties() {
    check_properties("cube", &shapes::cube(), cc(), 6);
    check_properties("grid", &shapes::quad_grid(3, 3), cc(), 4);
    let mix = shapes::polygon_mix(&shapes::torus(6, 5), 3, 0.2, 0.2, 0.1);
    check_properties("mix", &mix, cc(), 3);
    check_properties("pyramid", &shapes::pyramid(5), cc(), 4);
    check_orientation(&shapes::cube(), cc());
    check_orientation(&shapes::pyramid(6), cc());
    check_orientation(&shapes::prism(5), cc());
}

#[test]
fn loop_properties() {
    check_properties("icosahedron", &shapes::icosahedron(), lp(), 6);
    check_properties("tetrahedron", &shapes::tetrahedron(), lp(), 6);
    check_properties("triangle grid", &shapes::triangle_grid(3, 3), lp(), 4);
    check_orientation(&shapes::icosahedron(), lp());
    check_orientation(&shapes::octahedron(), lp());
}

#[test]
fn tagged_properties() {
    let cube = shapes::cube();
    let t = cube.topology();
    let mut e = vec![0f32; t.edge_count()];
    e[0] = 10.0;
    e[1] = 1.5;
    let tagged = cube.clone().with_tags(Tags::from_arrays(t, e, Vec::new()).unwrap());
    check_properties("tagged cube", &tagged, cc(), 5);
}

/// Near and at extraordinary vertices: derivatives stay finite, the normal
/// converges to the vertex's normal, and the normal is unit at the vertex.
#[test]
fn near_extraordinary_vertices_the_normal_converges() {
    for (mesh, options) in [(shapes::cube(), cc()), (shapes::icosahedron(), lp()), (shapes::pyramid(5), cc())] {
        let surface = LimitSurface::new(&mesh, &options).unwrap();
        let x = mesh.positions();
        let p0 = SurfaceParam::new(0, 0, 0.0, 0.0);
        let at0 = surface.evaluate(x, p0).unwrap();
        assert!((at0.normal.length() - 1.0).abs() < 1e-12);
        let mut last = f64::INFINITY;
        for k in [4, 8, 12, 16, 24] {
            let e = 0.5f64.powi(k);
            let s = surface.evaluate(x, SurfaceParam { u: e, v: e, ..p0 }).unwrap();
            let gap = (s.normal - at0.normal).length();
            assert!(gap <= last + 1e-9, "normal does not converge: {gap} after {last}");
            last = gap;
            assert!((s.position - at0.position).length() < 10.0 * e.sqrt());
        }
        assert!(last < 1e-3, "{last}");
    }
}

/// The same point from both faces of every edge (a parameter on the edge).
#[test]
fn continuity_across_shared_edges() {
    for (mesh, options) in [
        (shapes::polygon_mix(&shapes::torus(5, 4), 9, 0.25, 0.25, 0.1), cc()),
        (shapes::icosahedron(), lp()),
        (shapes::quad_grid(3, 2), cc()),
    ] {
        let surface = LimitSurface::new(&mesh, &options).unwrap();
        let (t, x, d) = (mesh.topology(), mesh.positions(), mesh.bbox_diagonal());
        // A point on half-edge h at fraction s from its start, in h's face's domain.
        let on_half_edge = |h: subdiv_mesh::HalfEdgeId, s: f64| -> SurfaceParam {
            let c = t.he_corner(h);
            let n = t.face_size(c.face);
            let k = c.index;
            if is_loop(&options) {
                let uv = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)];
                let (a, b) = (uv[k as usize], uv[(k as usize + 1) % 3]);
                SurfaceParam::new(c.face.0, 0, a.0 + s * (b.0 - a.0), a.1 + s * (b.1 - a.1))
            } else if n == 4 {
                let uv = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
                let (a, b) = (uv[k as usize], uv[(k as usize + 1) % 4]);
                SurfaceParam::new(c.face.0, 0, a.0 + s * (b.0 - a.0), a.1 + s * (b.1 - a.1))
            } else if s <= 0.5 {
                // ptex quad K: (1, 0) is the midpoint of edge K -> K+1.
                SurfaceParam::new(c.face.0, k, 2.0 * s, 0.0)
            } else {
                // ptex quad K+1: (0, 1) is the midpoint of edge K -> K+1.
                SurfaceParam::new(c.face.0, (k + 1) % n as u32, 0.0, 2.0 * (1.0 - s))
            }
        };
        for e in t.edges() {
            let h = t.edge_half_edge(e);
            let Some(g) = t.he_twin(h) else { continue };
            for s in [0.1, 0.37, 0.5, 0.8] {
                let a = surface.evaluate(x, on_half_edge(h, s)).unwrap();
                let b = surface.evaluate(x, on_half_edge(g, 1.0 - s)).unwrap();
                assert!((a.position - b.position).length() <= 1e-12 * d, "edge {e:?} at {s}");
                assert!((a.normal - b.normal).length() <= 1e-9, "edge {e:?} at {s}: normals");
            }
        }
    }
}

#[test]
fn bad_parameters_are_typed_errors() {
    let cube = shapes::cube();
    let s = LimitSurface::new(&cube, &cc()).unwrap();
    let x = cube.positions();
    for (u, v) in [(f64::NAN, 0.5), (0.5, f64::INFINITY), (-0.1, 0.5), (0.5, 1.0000001)] {
        assert!(matches!(s.evaluate(x, SurfaceParam::new(0, 0, u, v)), Err(EvalError::OutOfDomain { .. })));
        assert!(matches!(s.stencil(SurfaceParam::new(0, 0, u, v)), Err(EvalError::OutOfDomain { .. })));
    }
    assert!(matches!(s.evaluate(x, SurfaceParam::new(6, 0, 0.5, 0.5)), Err(EvalError::NoSuchDomain { .. })));
    assert!(matches!(s.evaluate(x, SurfaceParam::new(0, 1, 0.5, 0.5)), Err(EvalError::NoSuchDomain { .. })));
    assert!(matches!(s.evaluate(&x[1..], SurfaceParam::new(0, 0, 0.5, 0.5)), Err(EvalError::PositionCount { .. })));
    let ico = shapes::icosahedron();
    let l = LimitSurface::new(&ico, &lp()).unwrap();
    assert!(matches!(
        l.evaluate(ico.positions(), SurfaceParam::new(0, 0, 0.6, 0.6)),
        Err(EvalError::OutOfDomain { .. })
    ));
    // u + v over 1 by rounding is accepted.
    assert!(l.evaluate(ico.positions(), SurfaceParam::new(0, 0, 0.3, 0.7000000000000001)).is_ok());
    // Loop on quads: the subdivision's own refusal.
    assert!(matches!(LimitSurface::new(&cube, &lp()), Err(EvalError::Stencil(_))));
    // An n-gon has one domain per corner.
    let pyramid = shapes::pyramid(5);
    let p = LimitSurface::new(&pyramid, &cc()).unwrap();
    let base =
        (0..pyramid.topology().face_count() as u32).find(|&f| pyramid.topology().face_size(FaceId(f)) == 5).unwrap();
    assert_eq!(p.face_domains(base).len(), 5);
    assert!(matches!(
        p.evaluate(pyramid.positions(), SurfaceParam::new(base, 5, 0.5, 0.5)),
        Err(EvalError::NoSuchDomain { .. })
    ));
    // Triangles under Catmull-Clark are 3-gons.
    let apex_face =
        (0..pyramid.topology().face_count() as u32).find(|&f| pyramid.topology().face_size(FaceId(f)) == 3).unwrap();
    assert_eq!(p.face_domains(apex_face).len(), 3);
}

#[test]
fn domain_support_holds_every_stencil() {
    let mesh = shapes::polygon_mix(&shapes::quad_grid(4, 4), 2, 0.2, 0.2, 0.1);
    let s = LimitSurface::new(&mesh, &cc()).unwrap();
    for p in params(&s, 3, false) {
        let support = s.domain_support(p.domain()).unwrap();
        for i in s.stencil(p).unwrap().indices {
            assert!(support.contains(&i), "{p:?}: {i} not in the support");
        }
    }
}

#[test]
fn domain_bounds_hold_the_surface() {
    for (mesh, options) in [
        (shapes::polygon_mix(&shapes::torus(6, 5), 3, 0.2, 0.2, 0.1), cc()),
        (shapes::icosahedron(), lp()),
        (shapes::quad_grid(3, 3), cc()),
    ] {
        let surface = LimitSurface::new(&mesh, &options).unwrap();
        let bound = surface.bind(mesh.positions()).unwrap();
        let eps = 1e-12 * mesh.bbox_diagonal();
        let mut params = params(&surface, 8, is_loop(&options));
        // Corners too: the extraordinary vertices themselves.
        params.extend(surface.domains().iter().map(|d| SurfaceParam::new(d.face, d.corner, 0.0, 0.0)));
        params.extend(surface.domains().iter().map(|d| SurfaceParam::new(d.face, d.corner, 1e-5, 2e-5)));
        for p in params {
            let (lo, hi) = bound.domain_bounds(p.domain()).unwrap();
            let x = bound.evaluate(p).unwrap().position;
            assert!(x.cmpge(lo - eps).all() && x.cmple(hi + eps).all(), "{p:?}: {x} outside {lo}..{hi}");
        }
    }
}

#[test]
fn real_fixtures() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/");
    for (path, options) in [
        ("quad/spot_control_mesh.obj", cc()),
        ("quad/fandisk_quads.off", cc()),
        ("poly/chamfer-cube.off", cc()),
        ("poly/P.off", cc()),
        ("open/grid.off", cc()),
        ("open/halftunnel.off", cc()),
        ("tri/eight.off", lp()),
    ] {
        let file = format!("{root}{path}");
        let mesh = subdiv_io::load_mesh(std::path::Path::new(&file)).unwrap_or_else(|e| panic!("{path}: {e}"));
        let e = common::dyadic_error(&mesh, options, 1);
        assert!(e <= 1e-12, "{path}: {e:e}");
        check_properties(path, &mesh, options, 1);
    }
}

fn arbitrary_mesh() -> impl Strategy<Value = (Mesh, bool)> {
    (0u64..1000, 2usize..5, 2usize..4, any::<bool>(), any::<bool>(), 0usize..3).prop_map(
        |(seed, nx, ny, closed, tri, tags)| {
            let base = if tri {
                if closed {
                    shapes::icosahedron()
                } else {
                    shapes::triangle_grid(nx, ny)
                }
            } else if closed {
                shapes::torus(nx + 3, ny + 3)
            } else {
                shapes::quad_grid(nx, ny)
            };
            let mesh = if tri { base } else { shapes::polygon_mix(&base, seed, 0.2, 0.2, 0.1) };
            // Up to two tagged edges: semi-sharp or infinitely sharp.
            let t = mesh.topology();
            let mut rng = shapes::SplitMix64(seed);
            let mut e = vec![0f32; t.edge_count()];
            for _ in 0..tags {
                e[rng.below(t.edge_count())] = [0.5f32, 1.5, 10.0][rng.below(3)];
            }
            let tags = Tags::from_arrays(t, e, Vec::new()).unwrap();
            (mesh.clone().with_tags(tags), tri)
        },
    )
}

#[test]
fn surfaces_are_send_and_sync() {
    fn check<T: Send + Sync>() {}
    check::<LimitSurface>();
    check::<subdiv_eval::BoundSurface<'static>>();
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]
    #[test]
    fn proptest_dyadic_and_properties((mesh, tri) in arbitrary_mesh()) {
        let options = if tri { lp() } else { cc() };
        let e = common::dyadic_error(&mesh, options, 1);
        prop_assert!(e <= 1e-12, "{e:e}");
        check_properties("generated", &mesh, options, 1);
    }
}

/// At an extraordinary vertex the derivatives are one definite pair per
/// domain: the unbound, the bound and the stencil evaluation agree, and
/// they are the tangent masks of the coarsest exact level (equal to the
/// parametric derivatives at a regular vertex: checked against a regular
/// corner's central differences elsewhere).
#[test]
fn derivatives_at_an_extraordinary_vertex_are_one_definite_pair() {
    for (mesh, options) in [(shapes::cube(), cc()), (shapes::icosahedron(), lp()), (shapes::pyramid(5), cc())] {
        let surface = LimitSurface::new(&mesh, &options).unwrap();
        let x = mesh.positions();
        let bound = surface.bind(x).unwrap();
        for d in surface.domains() {
            let p = SurfaceParam::new(d.face, d.corner, 0.0, 0.0);
            let a = surface.evaluate(x, p).unwrap();
            let b = bound.evaluate(p).unwrap();
            let (pos, du, dv) = surface.stencil(p).unwrap().apply(x);
            assert_eq!(a, b);
            assert!(
                (pos - a.position).length() < 1e-12 && (du - a.du).length() < 1e-12 && (dv - a.dv).length() < 1e-12
            );
            assert!(a.du.length() > 1e-3 && a.dv.length() > 1e-3 && a.du.cross(a.dv).length() > 1e-6, "{d:?}");
        }
    }
}
