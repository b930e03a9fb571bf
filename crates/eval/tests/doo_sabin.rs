//! Doo-Sabin: the parameterisation's points against `subdivide --limit`.
//! Level 0: (0,0) of every domain is its vertex's limit point, (1,1) its
//! face's centroid. Level 1: vertex h (the image of corner h) is (½,½) of
//! domain (face(h), corner(h)). Level 2: vertex y, the image of level-1
//! corner (g, j) at level-1 vertex x = image of level-0 corner (f, k), is
//! the centre of g's quarter of domain (f, k): (¼,¼) for the V-face, (¾,¼)
//! for the E-face of edge k → k+1, (¾,¾) for the F-face, (¼,¾) for the
//! E-face of edge k−1 → k. From every face corner: also continuity.

mod common;

use subdiv_eval::{EvalError, LimitSurface, SurfaceParam};
use subdiv_mesh::refine::{dual_split, DualFace};
use subdiv_mesh::{shapes, HalfEdgeId, Mesh};
use subdiv_stencil::{Options, Scheme};

fn ds() -> Options {
    Options::new(Scheme::DooSabin)
}

fn check(name: &str, mesh: &Mesh) {
    let surface = LimitSurface::new(mesh, &ds()).unwrap();
    let (t, x, d) = (mesh.topology(), mesh.positions(), mesh.bbox_diagonal());
    let eval = |f: u32, k: u32, u: f64, v: f64| surface.evaluate(x, SurfaceParam::new(f, k, u, v)).unwrap().position;
    let tol = 1e-12 * d;
    // Level 0.
    let limit0 = subdiv_stencil::subdivide(mesh, ds(), 0, true).unwrap();
    for h in 0..t.half_edge_count() as u32 {
        let c = t.he_corner(HalfEdgeId(h));
        let v = t.he_from(HalfEdgeId(h));
        let p = eval(c.face.0, c.index, 0.0, 0.0);
        assert!((p - limit0.positions()[v.index()]).length() <= tol, "{name}: vertex {v:?} from corner {h}");
        let centroid = mesh.face_centroid(c.face);
        assert!((eval(c.face.0, c.index, 1.0, 1.0) - centroid).length() <= tol, "{name}: centre of {:?}", c.face);
    }
    // Level 1.
    let limit1 = subdiv_stencil::subdivide(mesh, ds(), 1, true).unwrap();
    for h in 0..t.half_edge_count() as u32 {
        let c = t.he_corner(HalfEdgeId(h));
        let p = eval(c.face.0, c.index, 0.5, 0.5);
        assert!((p - limit1.positions()[h as usize]).length() <= tol, "{name}: level-1 vertex {h}");
    }
    // Level 2.
    let limit2 = subdiv_stencil::subdivide(mesh, ds(), 2, true).unwrap();
    let (t1, provenance) = dual_split(t);
    for y in 0..t1.half_edge_count() as u32 {
        let c1 = t1.he_corner(HalfEdgeId(y));
        let xv = t1.he_from(HalfEdgeId(y)).0; // a level-1 vertex = level-0 corner
        let c0 = t.he_corner(HalfEdgeId(xv));
        let (u, v) = match provenance.face_origin[c1.face.index()] {
            DualFace::V(_) => (0.25, 0.25),
            DualFace::F(_) => (0.75, 0.75),
            DualFace::E(e) if e == t.he_edge(HalfEdgeId(xv)) => (0.75, 0.25),
            DualFace::E(_) => (0.25, 0.75),
        };
        let p = eval(c0.face.0, c0.index, u, v);
        let e = (p - limit2.positions()[y as usize]).length();
        assert!(e <= tol, "{name}: level-2 vertex {y}: {e:e}");
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
fn derivatives_normals_and_continuity() {
    for mesh in [shapes::cube(), shapes::polygon_mix(&shapes::torus(6, 5), 4, 0.2, 0.2, 0.1)] {
        let surface = LimitSurface::new(&mesh, &ds()).unwrap();
        let (x, d) = (mesh.positions(), mesh.bbox_diagonal());
        let bound = surface.bind(x).unwrap();
        for p in common::params(&surface, 4, false) {
            let s = surface.evaluate(x, p).unwrap();
            assert!((s.normal.length() - 1.0).abs() < 1e-12);
            assert!((bound.evaluate(p).unwrap().position - s.position).length() < 1e-13 * d);
            let st = surface.stencil(p).unwrap();
            assert!((st.apply(x).0 - s.position).length() < 1e-12 * d);
            assert!((st.position.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            let h = 1e-6;
            if p.u > h && p.u < 1.0 - h {
                let a = surface.evaluate(x, SurfaceParam { u: p.u + h, ..p }).unwrap().position;
                let b = surface.evaluate(x, SurfaceParam { u: p.u - h, ..p }).unwrap().position;
                assert!(((a - b) / (2.0 * h) - s.du).length() <= 1e-6 * (1.0 + s.du.length()) * d, "{p:?}");
            }
        }
        // Continuity: the edge u = 1 of (f, k) (toward the edge midpoint) is
        // the edge v = 1 of (f, k+1); v = 0 of (f, k) is u = 0 of the
        // neighbour's corner across edge k → k+1... checked on the face's own
        // quarters here.
        let t = mesh.topology();
        for f in t.face_ids() {
            let n = t.face_size(f) as u32;
            for k in 0..n {
                for s in [0.2, 0.6, 0.9] {
                    let a = surface.evaluate(x, SurfaceParam::new(f.0, k, 1.0, s)).unwrap();
                    let b = surface.evaluate(x, SurfaceParam::new(f.0, (k + 1) % n, s, 1.0)).unwrap();
                    assert!((a.position - b.position).length() <= 1e-12 * d, "{f:?} {k} {s}");
                    assert!((a.normal - b.normal).length() <= 1e-9, "{f:?} {k} {s}: normals");
                }
            }
        }
    }
}

#[test]
fn unsupported_cases_are_typed() {
    let grid = shapes::quad_grid(2, 2);
    assert!(matches!(LimitSurface::new(&grid, &ds()), Err(EvalError::Unsupported { .. })));
}
