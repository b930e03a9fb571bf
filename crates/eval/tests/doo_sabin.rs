//! Doo-Sabin: the parameterisation's points against `subdivide --limit`.
//! Level 0: (0,0) of every domain is its vertex's limit point, (1,1) its
//! face's centroid. Level 1: vertex h (the image of corner h) is (½,½) of
//! domain (face(h), corner(h)). Level 2: vertex y, the image of level-1
//! corner (g, j) at level-1 vertex x = image of level-0 corner (f, k), is
//! the centre of g's quarter of domain (f, k): (¼,¼) for the V-face, (¾,¼)
//! for the E-face of edge k → k+1, (¾,¾) for the F-face, (¼,¾) for the
//! E-face of edge k−1 → k. From every face corner: also continuity.

mod common;

use common::At;
use glam::DVec3;
use subdiv_eval::{EvalError, LimitSurface, SurfaceParam};
use subdiv_mesh::refine::{dual_split, DualFace, DualVertex};
use subdiv_mesh::{shapes, EdgeTag, FaceId, HalfEdgeId, Mesh, TagList, Tags, Topology, VertexTag};
use subdiv_stencil::{Options, Scheme};

fn ds() -> Options {
    Options::new(Scheme::DooSabin)
}

/// The strip (phantom) domains of a sharp half-edge `h` (corner K of its
/// face f, n corners): (f, n + 2K) at its start, (f, n + 2K + 1) at its end.
fn strips(t: &Topology, h: HalfEdgeId) -> (u32, u32, u32) {
    let c = t.he_corner(h);
    let n = t.face_size(c.face) as u32;
    (c.face.0, n + 2 * c.index, n + 2 * c.index + 1)
}

/// Every vertex of levels 0, 1 and 2 with the documented parameters of it
/// (module docs of the crate's Doo-Sabin parameterisation), worked out from
/// the dual split's provenance: (level, vertex, face, corner, u, v).
fn dyadic_params(mesh: &Mesh) -> Vec<(usize, u32, At)> {
    let t = mesh.topology();
    let mut out = Vec::new();
    // Level 0: (0,0) of every corner domain is its vertex's limit point when
    // the vertex is smooth; a boundary vertex's is on the boundary curve, at
    // (1,0) of the strip at the start of its outgoing boundary half-edge and
    // (0,1) of the strip at the end of its incoming one.
    for h in 0..t.half_edge_count() as u32 {
        let h = HalfEdgeId(h);
        let c = t.he_corner(h);
        let v = t.he_from(h);
        if !t.is_boundary_vertex(v) {
            out.push((0, v.0, (c.face.0, c.index, 0.0, 0.0)));
        }
        if t.he_twin(h).is_none() {
            let (f, at_start, at_end) = strips(t, h);
            out.push((0, v.0, (f, at_start, 1.0, 0.0)));
            out.push((0, t.he_to(h).0, (f, at_end, 0.0, 1.0)));
        }
    }
    // Level 1: corner image h at (½,½) of (face(h), corner(h)); the Chaikin
    // points of boundary half-edge g at (1,½) of its start strip and (½,1)
    // of its end strip.
    let (t1, p1) = dual_split(t);
    for (x, origin) in p1.vertex_origin.iter().enumerate() {
        let at = match *origin {
            DualVertex::Corner { face, corner, .. } => (face.0, corner, 0.5, 0.5),
            DualVertex::Boundary { half_edge, near_start } => {
                let (f, s, e) = strips(t, half_edge);
                if near_start {
                    (f, s, 1.0, 0.5)
                } else {
                    (f, e, 0.5, 1.0)
                }
            }
        };
        out.push((1, x as u32, at));
    }
    // Level 2: vertex y, the image of level-1 corner (g, j) at x = from(y),
    // is the centre of g's quarter of x's cell; the Chaikin points of a
    // level-1 boundary half-edge are on the boundary curve of the strips.
    let (_, p2) = dual_split(&t1);
    for (y, origin) in p2.vertex_origin.iter().enumerate() {
        let at = match *origin {
            DualVertex::Corner { face: g, vertex: x, .. } => match p1.vertex_origin[x.index()] {
                DualVertex::Corner { face, corner, .. } => {
                    let xh = t.faces().offsets()[face.index()] + corner;
                    let (u, v) = match p1.face_origin[g.index()] {
                        DualFace::V(_) => (0.25, 0.25),
                        DualFace::F(_) => (0.75, 0.75),
                        DualFace::E(e) if e == t.he_edge(HalfEdgeId(xh)) => (0.75, 0.25),
                        DualFace::E(_) => (0.25, 0.75),
                    };
                    (face.0, corner, u, v)
                }
                // x is a Chaikin point: its cell is the strip's quarter at x;
                // its two faces are the V-face (the strip's first quarter) and
                // the E-face (the last at the start, the second at the end).
                DualVertex::Boundary { half_edge, near_start } => {
                    let (f, s, e) = strips(t, half_edge);
                    let v_face = matches!(p1.face_origin[g.index()], DualFace::V(_));
                    match (near_start, v_face) {
                        (_, true) => (f, if near_start { s } else { e }, 0.25, 0.25),
                        (true, false) => (f, s, 0.25, 0.75),
                        (false, false) => (f, e, 0.75, 0.25),
                    }
                }
            },
            DualVertex::Boundary { half_edge: g1, near_start } => {
                let start = |x: u32| match p1.vertex_origin[x as usize] {
                    DualVertex::Boundary { half_edge, near_start } => (half_edge, near_start),
                    DualVertex::Corner { .. } => unreachable!("a level-1 boundary vertex is a Chaikin point"),
                };
                let (a, a_near_start) = start(t1.he_from(g1).0);
                let (b, _) = start(t1.he_to(g1).0);
                if a == b {
                    // Along the E-face of level-0 half-edge a: from its point near the start.
                    assert!(a_near_start);
                    let (f, s, e) = strips(t, a);
                    if near_start {
                        (f, s, 1.0, 0.75)
                    } else {
                        (f, e, 0.75, 1.0)
                    }
                } else if near_start {
                    // Along a V-face: from the end of a (incoming) to the start of b.
                    let (f, _, e) = strips(t, a);
                    (f, e, 0.25, 1.0)
                } else {
                    let (f, s, _) = strips(t, b);
                    (f, s, 1.0, 0.25)
                }
            }
        };
        out.push((2, y as u32, at));
    }
    out
}

fn check(name: &str, mesh: &Mesh) {
    let surface = LimitSurface::new(mesh, &ds()).unwrap();
    let (x, d) = (mesh.positions(), mesh.bbox_diagonal());
    let tol = 1e-12 * d;
    let limits: Vec<_> = (0..=2).map(|l| subdiv_stencil::subdivide(mesh, ds(), l, true).unwrap()).collect();
    let mut covered = vec![std::collections::HashSet::new(); 3];
    for (level, vertex, (f, k, u, v)) in dyadic_params(mesh) {
        let p = surface.evaluate(x, SurfaceParam::new(f, k, u, v)).unwrap_or_else(|e| panic!("{name}: {e}"));
        let e = (p.position - limits[level].positions()[vertex as usize]).length();
        assert!(e <= tol, "{name}: level-{level} vertex {vertex} at {f}.{k} ({u}, {v}): {:e}·d", e / d);
        covered[level].insert(vertex);
    }
    for (level, c) in covered.iter().enumerate() {
        let nv = limits[level].positions().len();
        assert_eq!(c.len(), nv, "{name}: every level-{level} vertex checked");
    }
    // Face centroids: (1,1) of every corner domain.
    let t = mesh.topology();
    for f in t.face_ids() {
        for k in 0..t.face_size(f) as u32 {
            let p = surface.evaluate(x, SurfaceParam::new(f.0, k, 1.0, 1.0)).unwrap().position;
            assert!((p - mesh.face_centroid(f)).length() <= tol, "{name}: centre of {f:?}");
        }
    }
}

#[test]
fn dyadic_points_match_subdivide_limit() {
    check("cube", &shapes::cube());
    check("octahedron", &shapes::octahedron());
    check("torus", &shapes::torus(5, 4));
    check("prism", &shapes::prism(5));
    check("mix", &shapes::polygon_mix(&shapes::torus(6, 5), 4, 0.2, 0.2, 0.1));
}

#[test]
fn dyadic_points_on_open_meshes() {
    check("grid 1x1", &shapes::quad_grid(1, 1));
    check("grid", &shapes::quad_grid(4, 3));
    check("open mix", &shapes::polygon_mix(&shapes::quad_grid(5, 4), 5, 0.2, 0.2, 0.1));
}

/// Derivatives against central differences, unit normals oriented like the
/// faces, stencils and bound evaluation against evaluation, and continuity
/// (positions and normals) across every shared edge of two domains.
fn check_smooth(name: &str, mesh: &Mesh) {
    let surface = LimitSurface::new(mesh, &ds()).unwrap();
    let (x, d) = (mesh.positions(), mesh.bbox_diagonal());
    let t = mesh.topology();
    let bound = surface.bind(x).unwrap();
    for p in common::params(&surface, 4, false) {
        let s = surface.evaluate(x, p).unwrap();
        assert!((s.normal.length() - 1.0).abs() < 1e-12, "{name}: {p:?}");
        assert!((bound.evaluate(p).unwrap().position - s.position).length() < 1e-13 * d);
        let st = surface.stencil(p).unwrap();
        let (sp, su, sv) = st.apply(x);
        assert!((sp - s.position).length() < 1e-12 * d);
        assert!((su - s.du).length() < 1e-10 * d && (sv - s.dv).length() < 1e-10 * d);
        assert!((st.position.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        let h = 1e-6;
        let at = |u: f64, v: f64| surface.evaluate(x, SurfaceParam { u, v, ..p }).unwrap().position;
        let tol = |g: DVec3| 1e-6 * (1.0 + g.length()) * d;
        if p.u > h && p.u < 1.0 - h {
            let c = (at(p.u + h, p.v) - at(p.u - h, p.v)) / (2.0 * h);
            assert!((c - s.du).length() <= tol(s.du), "{name}: du at {p:?}: {c} vs {}", s.du);
        }
        if p.v > h && p.v < 1.0 - h {
            let c = (at(p.u, p.v + h) - at(p.u, p.v - h)) / (2.0 * h);
            assert!((c - s.dv).length() <= tol(s.dv), "{name}: dv at {p:?}: {c} vs {}", s.dv);
        }
    }
    // Oriented like the faces: at the centre of every domain (normals are
    // continuous, checked below, so this holds throughout).
    for dm in surface.domains() {
        let s = surface.evaluate(x, SurfaceParam::new(dm.face, dm.corner, 0.5, 0.5)).unwrap();
        let facing = s.normal.dot(quarter_normal(mesh, dm.face, dm.corner));
        assert!(facing > 0.0, "{name}: {dm:?} oriented like its face: {facing}");
    }
    // Shared edges: (a's domain, a's (u, v) at s) = (b's, b's at s).
    type Edge = (u32, u32, fn(f64) -> (f64, f64), u32, u32, fn(f64) -> (f64, f64));
    let mut edges: Vec<Edge> = Vec::new();
    for h in (0..t.half_edge_count() as u32).map(HalfEdgeId) {
        let c = t.he_corner(h);
        let n = t.face_size(c.face) as u32;
        let (f, k) = (c.face.0, c.index);
        // Inside the face: u = 1 of corner k is v = 1 of corner k + 1.
        edges.push((f, k, |s| (1.0, s), f, (k + 1) % n, |s| (s, 1.0)));
        match t.he_twin(h) {
            // Across the edge k → k+1: v = 0 of corner k is u = 0 of the
            // neighbour's corner at the same vertex.
            Some(g) => {
                let cg = t.he_corner(t.he_next(g));
                edges.push((f, k, |s| (s, 0.0), cg.face.0, cg.index, |s| (0.0, s)));
            }
            // Along a boundary edge: the strips against the corners and each
            // other, and against the strips of the next boundary edge.
            None => {
                let (_, start, end) = strips(t, h);
                edges.push((f, start, |s| (0.0, s), f, k, |s| (s, 0.0)));
                edges.push((f, end, |s| (s, 0.0), f, (k + 1) % n, |s| (0.0, s)));
                edges.push((f, start, |s| (s, 1.0), f, end, |s| (1.0, s)));
                let out = t.vertex_fan(t.he_to(h))[0]; // the boundary half-edge leaving B
                let (g, next_start, _) = strips(t, out);
                edges.push((g, next_start, |s| (s, 0.0), f, end, |s| (0.0, s)));
            }
        }
    }
    for (fa, ka, pa, fb, kb, pb) in edges {
        for s in [0.2, 0.6, 0.9] {
            let ((ua, va), (ub, vb)) = (pa(s), pb(s));
            let a = surface.evaluate(x, SurfaceParam::new(fa, ka, ua, va)).unwrap();
            let b = surface.evaluate(x, SurfaceParam::new(fb, kb, ub, vb)).unwrap();
            let at = format!("{name}: {fa}.{ka} ({ua}, {va}) vs {fb}.{kb} ({ub}, {vb})");
            assert!((a.position - b.position).length() <= 1e-12 * d, "{at}: positions");
            assert!((a.normal - b.normal).length() <= 1e-9, "{at}: normals");
        }
    }
}

#[test]
fn derivatives_normals_and_continuity() {
    check_smooth("cube", &shapes::cube());
    check_smooth("mix", &shapes::polygon_mix(&shapes::torus(6, 5), 4, 0.2, 0.2, 0.1));
}

#[test]
fn derivatives_normals_and_continuity_on_open_meshes() {
    check_smooth("grid", &bumped(shapes::quad_grid(4, 3)));
    check_smooth("open mix", &bumped(shapes::polygon_mix(&shapes::quad_grid(5, 4), 5, 0.2, 0.2, 0.1)));
}

/// The normal at the boundary curve (where the derivative across it
/// vanishes) is the limit of the normals inside.
#[test]
fn normals_on_the_boundary_curve() {
    let mesh = bumped(shapes::quad_grid(3, 3));
    let surface = LimitSurface::new(&mesh, &ds()).unwrap();
    let x = mesh.positions();
    for dom in surface.domains().iter().filter(|dm| dm.corner >= 4) {
        let at_end = (dom.corner - 4) % 2 == 1;
        for s in [0.1, 0.5, 0.8] {
            let (on, near) = if at_end { ((s, 1.0), (s, 1.0 - 1e-7)) } else { ((1.0, s), (1.0 - 1e-7, s)) };
            let a = surface.evaluate(x, SurfaceParam::new(dom.face, dom.corner, on.0, on.1)).unwrap();
            let b = surface.evaluate(x, SurfaceParam::new(dom.face, dom.corner, near.0, near.1)).unwrap();
            assert!((a.normal.length() - 1.0).abs() < 1e-12, "{dom:?} {s}");
            assert!((a.normal - b.normal).length() < 1e-5, "{dom:?} {s}: {} vs {}", a.normal, b.normal);
        }
    }
}

/// The area normal of the quarter of a face at corner K (its vertex, the
/// midpoint of edge K → K+1, the centroid, the midpoint of edge K−1 → K),
/// the control polygon of domain (f, K); for a strip, its face's.
fn quarter_normal(mesh: &Mesh, f: u32, k: u32) -> DVec3 {
    let (t, x) = (mesh.topology(), mesh.positions());
    let ring = t.face(FaceId(f));
    let n = ring.len();
    let k = k as usize;
    if k >= n {
        return mesh.face_normal(FaceId(f));
    }
    let p = |i: usize| x[ring[i % n] as usize];
    let c = mesh.face_centroid(FaceId(f));
    let quad = [p(k), 0.5 * (p(k) + p(k + 1)), c, 0.5 * (p(k) + p(k + n - 1))];
    (0..4).map(|i| quad[i].cross(quad[(i + 1) % 4])).sum::<DVec3>()
}

/// A grid lifted out of its plane (smoothly, so that every face stays
/// oriented like its neighbours).
fn bumped(mesh: Mesh) -> Mesh {
    let p = mesh.positions().iter().map(|p| *p + DVec3::Z * (0.3 * p.x).sin() * (0.4 * p.y + 0.2).cos()).collect();
    mesh.with_positions(p)
}

#[test]
fn unsupported_cases_are_typed() {
    // A corner tag, a dart and an interior vertex of valence 2.
    let grid = shapes::quad_grid(2, 2);
    let corner = grid.clone().with_tags(
        Tags::from_list(
            grid.topology(),
            &TagList { creases: vec![], corners: vec![VertexTag { vertex: 4, sharpness: 10.0 }] },
        )
        .unwrap(),
    );
    let unsupported = |m: &Mesh| matches!(LimitSurface::new(m, &ds()), Err(EvalError::Unsupported { .. }));
    assert!(unsupported(&corner));
    let cube = shapes::cube();
    let f0 = cube.topology().face(FaceId(0)).to_vec();
    let dart = cube.clone().with_tags(
        Tags::from_list(
            cube.topology(),
            &TagList { creases: vec![EdgeTag { a: f0[0], b: f0[1], sharpness: 10.0 }], corners: vec![] },
        )
        .unwrap(),
    );
    assert!(unsupported(&dart));
}
