//! Doo-Sabin: the parameterisation's points against `subdivide --limit`.
//! Level 0: (0,0) of every domain is its vertex's limit point, (1,1) its
//! face's centroid. Level 1: vertex h (the image of corner h) is (½,½) of
//! domain (face(h), corner(h)). Level 2: vertex y, the image of level-1
//! corner (g, j) at level-1 vertex x = image of level-0 corner (f, k), is
//! the centre of g's quarter of domain (f, k): (¼,¼) for the V-face, (¾,¼)
//! for the E-face of edge k → k+1, (¾,¾) for the F-face, (¼,¾) for the
//! E-face of edge k−1 → k. From every face corner: also continuity.

use crate::common;

use crate::common::At;
use glam::DVec3;
use subdiv_eval::{EvalError, LimitSurface, SurfaceParam};
use subdiv_mesh::refine::{dual_split_tagged, DualFace, DualFeatures, SharpPoint};
use subdiv_mesh::{shapes, EdgeTag, FaceId, HalfEdgeId, Mesh, TagList, Tags, Topology, VertexId, VertexTag};
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
/// (the crate's Doo-Sabin parameterisation), worked out from the tagged dual
/// split's provenance: (level, vertex, (face, corner, u, v)).
fn dyadic_params(mesh: &Mesh) -> Vec<(usize, u32, At)> {
    let t = mesh.topology();
    let features = DualFeatures::new(t, mesh.tags());
    let sharp = |h: HalfEdgeId| features.is_sharp(t, t.he_edge(h));
    let mut out = Vec::new();
    // Level 0: (0,0) of every corner domain is its vertex's limit point when
    // the vertex is smooth; a sharp vertex's is on the sharp curve, at (1,0)
    // of the strip at the start of a sharp half-edge leaving it and (0,1) of
    // the strip at the end of one arriving.
    for h in (0..t.half_edge_count() as u32).map(HalfEdgeId) {
        let c = t.he_corner(h);
        let v = t.he_from(h);
        if features.sharp_edge_count(t, v) == 0 {
            out.push((0, v.0, (c.face.0, c.index, 0.0, 0.0)));
        }
        if sharp(h) {
            let (f, at_start, at_end) = strips(t, h);
            out.push((0, v.0, (f, at_start, 1.0, 0.0)));
            out.push((0, t.he_to(h).0, (f, at_end, 0.0, 1.0)));
        }
    }
    // Level 1: corner image h at (½,½) of (face(h), corner(h)); the points of
    // the refined sharp polygon on sharp half-edge g at (1,½) of its start
    // strip and (½,1) of its end strip.
    let h0 = t.half_edge_count();
    let (t1, p1, tags1) = dual_split_tagged(t, mesh.tags());
    let chaikin = |p: SharpPoint| match p {
        SharpPoint::Chaikin { half_edge, near_start, .. } => (half_edge, near_start),
        other => unreachable!("no corners here: {other:?}"),
    };
    for x in 0..t1.vertex_count() {
        let at = if x < h0 {
            let c = t.he_corner(HalfEdgeId(x as u32));
            (c.face.0, c.index, 0.5, 0.5)
        } else {
            let (g, near_start) = chaikin(p1.sharp_points[x - h0]);
            let (f, s, e) = strips(t, g);
            if near_start {
                (f, s, 1.0, 0.5)
            } else {
                (f, e, 0.5, 1.0)
            }
        };
        out.push((1, x as u32, at));
    }
    // The sides of a sharp edge: its half-edges.
    let sides = |h: HalfEdgeId| [Some(h), t.he_twin(h)].into_iter().flatten();
    let holds = |g: FaceId, v: u32| t1.face(g).contains(&v);
    // Level 2: vertex y, the image of level-1 corner (g, j) at x = from(y),
    // is the centre of g's quarter of x's cell; the points of the refined
    // sharp polygon of level 1 are on the sharp curve of the strips.
    let h1 = t1.half_edge_count();
    let (t2, p2, _) = dual_split_tagged(&t1, &tags1);
    for y in 0..t2.vertex_count() {
        let at = if y < h1 {
            let (g, x) = (t1.he_face(HalfEdgeId(y as u32)), t1.he_from(HalfEdgeId(y as u32)).index());
            if x < h0 {
                let c = t.he_corner(HalfEdgeId(x as u32));
                let (u, v) = match p1.face_origin[g.index()] {
                    DualFace::V(_) => (0.25, 0.25),
                    DualFace::F(_) => (0.75, 0.75),
                    DualFace::E(e) if e == t.he_edge(HalfEdgeId(x as u32)) => (0.75, 0.25),
                    DualFace::E(_) => (0.25, 0.75),
                };
                (c.face.0, c.index, u, v)
            } else {
                // x is on the sharp polygon: its cell on g's side is the
                // strip's quarter at x; g is the V-face (the strip's first
                // quarter) or the E-face (its last at the start, its second
                // at the end) of that side, which holds the image of the
                // side's corner at x.
                let (h, near_start) = chaikin(p1.sharp_points[x - h0]);
                let (s, at_start) = sides(h)
                    .map(|s| (s, (s == h) == near_start))
                    .find(|&(s, at_start)| holds(g, if at_start { s.0 } else { t.he_next(s).0 }))
                    .expect("a face at a sharp point is on one side");
                let (f, start, end) = strips(t, s);
                match (at_start, matches!(p1.face_origin[g.index()], DualFace::V(_))) {
                    (true, true) => (f, start, 0.25, 0.25),
                    (false, true) => (f, end, 0.25, 0.25),
                    (true, false) => (f, start, 0.25, 0.75),
                    (false, false) => (f, end, 0.75, 0.25),
                }
            }
        } else {
            let (g1, near_start) = match p2.sharp_points[y - h1] {
                SharpPoint::Chaikin { half_edge, near_start, .. } => (half_edge, near_start),
                other => unreachable!("no corners here: {other:?}"),
            };
            let g = t1.he_face(g1);
            let (a, _) = chaikin(p1.sharp_points[t1.he_from(g1).index() - h0]);
            let (b, _) = chaikin(p1.sharp_points[t1.he_to(g1).index() - h0]);
            if t.he_edge(a) == t.he_edge(b) {
                // Along the E-face of side s of a level-0 sharp edge, in s's direction.
                let s = sides(a).find(|&s| holds(g, s.0) && holds(g, t.he_next(s).0)).expect("an E-face of a side");
                let (f, start, end) = strips(t, s);
                if near_start {
                    (f, start, 1.0, 0.75)
                } else {
                    (f, end, 0.75, 1.0)
                }
            } else {
                // Along a V-face of vertex V, from the point near V on the
                // sharp half-edge arriving at V to the one on the half-edge leaving.
                let arriving = sides(a).find(|&s| holds(g, t.he_next(s).0)).expect("the arriving side");
                let leaving = sides(b).find(|&s| holds(g, s.0)).expect("the leaving side");
                if near_start {
                    let (f, _, end) = strips(t, arriving);
                    (f, end, 0.25, 1.0)
                } else {
                    let (f, start, _) = strips(t, leaving);
                    (f, start, 1.0, 0.25)
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
    // Shared edges: (a's domain, a's (u, v) at s) = (b's, b's at s), and
    // whether the normals agree too (not across a crease).
    type Edge = (u32, u32, fn(f64) -> (f64, f64), u32, u32, fn(f64) -> (f64, f64), bool);
    let features = DualFeatures::new(t, mesh.tags());
    let sharp = |h: HalfEdgeId| features.is_sharp(t, t.he_edge(h));
    let mut edges: Vec<Edge> = Vec::new();
    for h in (0..t.half_edge_count() as u32).map(HalfEdgeId) {
        let c = t.he_corner(h);
        let n = t.face_size(c.face) as u32;
        let (f, k) = (c.face.0, c.index);
        // Inside the face: u = 1 of corner k is v = 1 of corner k + 1.
        edges.push((f, k, |s| (1.0, s), f, (k + 1) % n, |s| (s, 1.0), true));
        if !sharp(h) {
            // Across the edge k → k+1: v = 0 of corner k is u = 0 of the
            // neighbour's corner at the same vertex.
            let cg = t.he_corner(t.he_next(t.he_twin(h).expect("an interior edge")));
            edges.push((f, k, |s| (s, 0.0), cg.face.0, cg.index, |s| (0.0, s), true));
            continue;
        }
        // Along a sharp edge: the strips against the corners and each other,
        // and against the strip of the next sharp edge on this side.
        let (_, start, end) = strips(t, h);
        edges.push((f, start, |s| (0.0, s), f, k, |s| (s, 0.0), true));
        edges.push((f, end, |s| (s, 0.0), f, (k + 1) % n, |s| (0.0, s), true));
        edges.push((f, start, |s| (s, 1.0), f, end, |s| (1.0, s), true));
        let mut out = t.he_next(h);
        while !sharp(out) {
            out = t.he_next(t.he_twin(out).expect("a sector ends at a sharp edge"));
        }
        let (g, next_start, _) = strips(t, out);
        edges.push((g, next_start, |s| (s, 0.0), f, end, |s| (0.0, s), true));
        // Across a crease: the two sides' strips meet on the sharp curve.
        if let Some(tw) = t.he_twin(h) {
            let (g, _, twin_end) = strips(t, tw);
            edges.push((f, start, |s| (1.0, s), g, twin_end, |s| (s, 1.0), false));
        }
    }
    for (fa, ka, pa, fb, kb, pb, smooth) in edges {
        for s in [0.2, 0.6, 0.9] {
            let ((ua, va), (ub, vb)) = (pa(s), pb(s));
            let a = surface.evaluate(x, SurfaceParam::new(fa, ka, ua, va)).unwrap();
            let b = surface.evaluate(x, SurfaceParam::new(fb, kb, ub, vb)).unwrap();
            let at = format!("{name}: {fa}.{ka} ({ua}, {va}) vs {fb}.{kb} ({ub}, {vb})");
            assert!((a.position - b.position).length() <= 1e-12 * d, "{at}: positions");
            assert!(!smooth || (a.normal - b.normal).length() <= 1e-9, "{at}: normals");
        }
    }
}

#[test]
fn derivatives_normals_and_continuity() {
    check_smooth("cube", &shapes::cube());
    check_smooth("mix", &shapes::polygon_mix(&shapes::torus(6, 5), 4, 0.2, 0.2, 0.1));
}

/// Infinitely sharp creases along `edges` (pairs of vertices).
fn creased(mesh: Mesh, edges: &[(u32, u32)]) -> Mesh {
    let creases = edges.iter().map(|&(a, b)| EdgeTag { a, b, sharpness: 10.0 }).collect();
    let tags = Tags::from_list(mesh.topology(), &TagList { creases, corners: vec![], ..Default::default() }).unwrap();
    mesh.with_tags(tags)
}

/// The cube with a crease loop round face 0 (four crease vertices, no corner).
fn creased_cube() -> Mesh {
    let cube = shapes::cube();
    let f0 = cube.topology().face(FaceId(0)).to_vec();
    creased(cube, &[(f0[0], f0[1]), (f0[1], f0[2]), (f0[2], f0[3]), (f0[3], f0[0])])
}

/// A torus with a crease loop round its tube (a ring of edges of constant angle).
fn creased_torus() -> Mesh {
    let (nu, nv) = (6u32, 5u32);
    // Vertex (i, j) is i·nv + j: the loop j = 0.
    let loop_edges: Vec<(u32, u32)> = (0..nu).map(|i| (i * nv, ((i + 1) % nu) * nv)).collect();
    creased(shapes::torus(nu as usize, nv as usize), &loop_edges)
}

#[test]
fn dyadic_points_with_creases() {
    check("creased cube", &creased_cube());
    check("creased torus", &creased_torus());
}

/// A cube with two edges split (two interior vertices of valence 2, four pentagons).
fn split_cube() -> Mesh {
    let cube = shapes::cube();
    shapes::split_edges(&cube, &[subdiv_mesh::EdgeId(0), subdiv_mesh::EdgeId(7)], 0.1)
}

#[test]
fn dyadic_points_at_valence_two() {
    check("pillow", &shapes::pillow());
    check("split cube", &split_cube());
    let grid = shapes::quad_grid(4, 3);
    let interior: Vec<_> = grid.topology().edges().filter(|&e| !grid.topology().is_boundary_edge(e)).take(2).collect();
    check("split grid", &shapes::split_edges(&grid, &interior[1..], 0.2));
}

#[test]
fn derivatives_normals_and_continuity_at_valence_two() {
    // (Not the pillow: its two faces are one quad both ways round, its
    // surface a doubly covered sheet without a normal.)
    check_smooth("split cube", &split_cube());
    let grid = bumped(shapes::quad_grid(4, 3));
    let interior: Vec<_> = grid.topology().edges().filter(|&e| !grid.topology().is_boundary_edge(e)).collect();
    check_smooth("split grid", &shapes::split_edges(&grid, &interior[1..3], 0.2));
}

/// An open polygon mix with an interior valence-2 vertex and a crease loop
/// round an interior face: boundaries, n-gons, extraordinary vertices,
/// valence 2 and creases at once.
fn everything() -> Mesh {
    let mix = bumped(shapes::polygon_mix(&shapes::quad_grid(6, 5), 5, 0.2, 0.2, 0.1));
    let t = mix.topology();
    let inside = |f: FaceId| t.face(f).iter().all(|&v| !t.is_boundary_vertex(VertexId(v)));
    let f = t.face_ids().find(|&f| inside(f) && t.face_size(f) != 4).expect("an interior n-gon");
    let ring = t.face(f).to_vec();
    let far = t
        .edges()
        .find(|&e| {
            let (a, b) = t.edge_vertices(e);
            let touches = |v: VertexId| ring.contains(&v.0) || t.is_boundary_vertex(v);
            !t.is_boundary_edge(e) && !touches(a) && !touches(b)
        })
        .expect("an interior edge away from the face");
    let split = shapes::split_edges(&mix, &[far], 0.2);
    let n = ring.len();
    creased(split, &(0..n).map(|k| (ring[k], ring[(k + 1) % n])).collect::<Vec<_>>())
}

#[test]
fn everything_at_once() {
    let mesh = everything();
    let t = mesh.topology();
    assert!(t.vertices().any(|v| !t.is_boundary_vertex(v) && t.vertex_face_count(v) == 2));
    check("everything", &mesh);
    check_smooth("everything", &mesh);
}

#[test]
fn derivatives_normals_and_continuity_with_creases() {
    check_smooth("creased cube", &creased_cube());
    check_smooth("creased torus", &creased_torus());
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
            &TagList { creases: vec![], corners: vec![VertexTag { vertex: 4, sharpness: 10.0 }], ..Default::default() },
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
            &TagList {
                creases: vec![EdgeTag { a: f0[0], b: f0[1], sharpness: 10.0 }],
                corners: vec![],
                ..Default::default()
            },
        )
        .unwrap(),
    );
    assert!(unsupported(&dart));
}
