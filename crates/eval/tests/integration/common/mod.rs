//! Shared helpers of the evaluation tests: the parameter of every vertex of
//! a refined mesh, worked out from the refinement's face numbering alone
//! (the mesh crate's documented quad and triangle splits), independently of
//! the evaluator's own child maps.
#![allow(dead_code)]

use glam::DVec3;
use subdiv_eval::{LimitSurface, SurfaceParam};
use subdiv_mesh::{FaceId, Mesh, Topology};
use subdiv_stencil::{Options, Scheme};

/// A point of a domain: (face, corner, u, v).
pub type At = (u32, u32, f64, f64);

/// A refined quad's domain (face, corner) and its corners' parameters.
pub type QuadParams = (u32, u32, [(f64, f64); 4]);

/// For every face of `levels` quad splits of `t` (Catmull-Clark), the
/// domain and the parameters of its four corners.
pub fn quad_corner_params(t: &Topology, levels: usize) -> Vec<QuadParams> {
    // Level 1: quad split face h = corner h of old face f: (v_k, e(k,k+1), f, e(k-1,k)).
    let mut current: Vec<QuadParams> = Vec::new();
    let mut topo = t.clone();
    for f in t.face_ids() {
        let n = t.face_size(f);
        for k in 0..n {
            let c = if n == 4 {
                let corner = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
                let mid = |a: (f64, f64), b: (f64, f64)| ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
                let (p, q, r) = (corner[k], corner[(k + 1) % 4], corner[(k + 3) % 4]);
                (0u32, [p, mid(p, q), (0.5, 0.5), mid(r, p)])
            } else {
                (k as u32, [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)])
            };
            current.push((f.0, c.0, c.1));
        }
    }
    for _ in 1..levels {
        topo = subdiv_mesh::refine::quad_split(&topo);
        let mut next = Vec::with_capacity(current.len() * 4);
        for (face, corner, c) in &current {
            // Bilinear map of the parent quad.
            let at = |u: f64, v: f64| {
                let x =
                    (1.0 - u) * (1.0 - v) * c[0].0 + u * (1.0 - v) * c[1].0 + u * v * c[2].0 + (1.0 - u) * v * c[3].0;
                let y =
                    (1.0 - u) * (1.0 - v) * c[0].1 + u * (1.0 - v) * c[1].1 + u * v * c[2].1 + (1.0 - u) * v * c[3].1;
                (x, y)
            };
            let corner_uv = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
            for k in 0..4 {
                let (p, q, r) = (corner_uv[k], corner_uv[(k + 1) % 4], corner_uv[(k + 3) % 4]);
                let mid = |a: (f64, f64), b: (f64, f64)| ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
                let child = [p, mid(p, q), (0.5, 0.5), mid(r, p)].map(|(u, v)| at(u, v));
                next.push((*face, *corner, child));
            }
        }
        current = next;
    }
    let _ = topo;
    current
}

/// For every face of `levels` triangle splits (Loop), the domain face and
/// the barycentric parameters of its three corners.
pub fn triangle_corner_params(t: &Topology, levels: usize) -> Vec<(u32, [(f64, f64); 3])> {
    let corner_uv = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)];
    let mid = |a: (f64, f64), b: (f64, f64)| ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
    let mut current: Vec<(u32, [(f64, f64); 3])> = t.face_ids().map(|f| (f.0, corner_uv)).collect();
    for _ in 0..levels {
        let mut next = Vec::with_capacity(current.len() * 4);
        for (face, c) in &current {
            let at = |(u, v): (f64, f64)| {
                (
                    c[0].0 + u * (c[1].0 - c[0].0) + v * (c[2].0 - c[0].0),
                    c[0].1 + u * (c[1].1 - c[0].1) + v * (c[2].1 - c[0].1),
                )
            };
            // Corner triangles 4f+k = (v_k, e(k,k+1), e(k-1,k)), centre (e01, e12, e20).
            for k in 0..3 {
                let (p, q, r) = (corner_uv[k], corner_uv[(k + 1) % 3], corner_uv[(k + 2) % 3]);
                next.push((*face, [p, mid(p, q), mid(r, p)].map(at)));
            }
            next.push((
                *face,
                [mid(corner_uv[0], corner_uv[1]), mid(corner_uv[1], corner_uv[2]), mid(corner_uv[2], corner_uv[0])]
                    .map(at),
            ));
        }
        current = next;
    }
    current
}

/// Checks every vertex of the level-`levels` limit mesh against the
/// evaluation at its parameter (from every face it is a corner of):
/// returns the largest error relative to the bounding-box diagonal.
pub fn dyadic_error(mesh: &Mesh, options: Options, levels: usize) -> f64 {
    let surface = LimitSurface::new(mesh, &options).expect("surface");
    let refined = subdiv_stencil::subdivide(mesh, options, levels, true).expect("subdivide --limit");
    let d = mesh.bbox_diagonal();
    let rt = refined.topology();
    // A dart's `--limit` point is its exact limit where its edge is
    // infinitely sharp (`DartLimit::Exact`), else OpenSubdiv's smooth-mask
    // approximation, which changes with the level (tests/integration/dart.rs checks
    // those against the levels' convergence instead).
    // The masks are applied where no semi-sharp value is left: a vertex is
    // judged by its rule at that level (old vertices keep their numbers).
    let at_level = subdiv_stencil::LevelSharpness::from_options(refined.tags(), &options);
    let extra = at_level.largest_semi_sharp(rt).map_or(0, |s| s.ceil() as usize);
    let masked = subdiv_stencil::subdivide(mesh, options, levels + extra, false).expect("subdivide");
    let sharp = subdiv_stencil::LevelSharpness::from_options(masked.tags(), &options);
    let mt = masked.topology();
    let mut worst: f64 = 0.0;
    let mut check = |param: SurfaceParam, vertex: u32| {
        let v = subdiv_mesh::VertexId(vertex);
        if sharp.limit_rule(mt, v).0 == subdiv_rules::Rule::Dart && sharp.exact_dart_edge(mt, v).is_none() {
            return;
        }
        // Holes (boundary `none` makes the boundary faces holes) have no surface.
        if surface.face_domains(param.face).is_empty() {
            return;
        }
        let s = surface.evaluate(mesh.positions(), param).unwrap_or_else(|e| panic!("{param:?}: {e}"));
        let e = (s.position - refined.positions()[vertex as usize]).length() / d;
        assert!(e.is_finite(), "{param:?}");
        worst = worst.max(e);
    };
    match options.scheme {
        Scheme::Loop(_) => {
            for (i, (face, c)) in triangle_corner_params(mesh.topology(), levels).into_iter().enumerate() {
                for (j, &(u, v)) in c.iter().enumerate() {
                    check(SurfaceParam::new(face, 0, u, v), rt.face(FaceId(i as u32))[j]);
                }
            }
        }
        _ => {
            for (i, (face, corner, c)) in quad_corner_params(mesh.topology(), levels).into_iter().enumerate() {
                for (j, &(u, v)) in c.iter().enumerate() {
                    check(SurfaceParam::new(face, corner, u, v), rt.face(FaceId(i as u32))[j]);
                }
            }
        }
    }
    worst
}

/// Deterministic pseudo-random parameters in a domain.
pub fn params(surface: &LimitSurface, per_domain: usize, triangle: bool) -> Vec<SurfaceParam> {
    let mut rng = subdiv_mesh::shapes::SplitMix64(7);
    let mut out = Vec::new();
    for d in surface.domains() {
        for _ in 0..per_domain {
            let (mut u, mut v) = (rng.next_f64(), rng.next_f64());
            if triangle && u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            out.push(SurfaceParam::new(d.face, d.corner, u, v));
        }
    }
    out
}

/// `a` close to `b` relative to `scale`.
pub fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).length() <= tol
}
