//! The limit surface at a vertex of a (refined) level: where no regular
//! patch reaches — an extraordinary vertex, a dart, an irregular crease or
//! corner — the parameter is a corner of ever smaller irregular patches, and
//! the surface there is evaluated at the vertex itself.
//!
//! * Position: the dominant left eigenvector of the local subdivision
//!   matrix S, which is the scheme's limit mask (`SchemeRules::limit_stencil`,
//!   the masks `subdivide --limit` uses; at a dart the exact dart mask,
//!   `DartLimit::Exact`), exact once no semi-sharp value is left near the
//!   vertex and the level is not a tagged base level. Under
//!   `DartLimit::SmoothMask` the limit stencils take OpenSubdiv's smooth
//!   mask at darts; the evaluator still returns the limit itself.
//! * Derivatives: the parametric derivatives degenerate at an extraordinary
//!   vertex (they scale like (2λ)ᵏ, λ the subdominant eigenvalue of the local
//!   subdivision matrix S). We return the *tangent masks*: with Π the spectral
//!   projector of S onto its dominant invariant subspace below eigenvalue 1
//!   (dimension 2: the tangent plane), the derivative along a face edge
//!   c → e of the level is (ΠP)\[e\] − (ΠP)\[c\] per unit of that level's
//!   parameter, P the star's points. At a regular vertex this is exactly
//!   the B-spline derivative (the subdominant eigenvectors are the linear
//!   functions on the lattice, every other component has zero slope at the
//!   vertex); at an extraordinary vertex it is the same construction, finite
//!   and nonzero, spanning the tangent plane, ordered like the face (so the
//!   normal du × dv is oriented like the faces). Π does not depend on the
//!   basis chosen for the subspace. Π is computed by subspace iteration on S
//!   and Sᵀ with the eigenvalue 1 deflated (S's rows are those of the
//!   workspace's refinement stencil on the vertex's star, a small matrix).

use crate::local::{star_faces, Local};
use crate::surface::EvalError;
use subdiv_mesh::{FaceId, FaceList, HalfEdgeId, Tags, Topology, VertexId};
use subdiv_stencil::{LevelSharpness, Options, Split, SubdivisionPlan};

/// Iterations of the subspace iteration: the error decays like
/// (λ₃/λ₂)ⁱᵗ, at most ~0.65 per step for the valences and tags we meet.
const ITERATIONS: usize = 400;

/// Whether the limit masks of the level are exact at the corners of `face`:
/// no semi-sharp value left in the local submesh, not a tagged base level,
/// and (Catmull-Clark) only quads around `v` (the star then maps onto itself
/// under refinement).
pub(crate) fn ready(local: &Local, options: &Options, v: VertexId) -> bool {
    if local.is_base && !local.sharp.is_plain() {
        return false;
    }
    if local.sharp.largest_semi_sharp(&local.t).is_some() {
        return false;
    }
    let size = options.scheme.traits().regular_face_size;
    star_faces(&local.t, v).iter().all(|&f| local.t.face_size(f) == size)
}

/// Position and tangents (along the face's edge to the next corner, `a`,
/// and to the previous corner, `b`) at corner `k` of `face`, as weights on
/// the root of `local`.
pub(crate) fn vertex_limit(
    local: &Local,
    options: &Options,
    face: FaceId,
    k: usize,
) -> Result<[Vec<f64>; 3], EvalError> {
    let t = &local.t;
    let h = HalfEdgeId(t.faces().offsets()[face.index()] + k as u32);
    let c = t.he_from(h);
    let star = Unfolded::new(t, &local.sharp, c)?;
    let j = t.vertex_fan(c).iter().position(|&g| g == h).expect("the face is in its corner's fan");
    let (a, b) = (1 + j, 1 + (j + 1) % star.edges);
    let n = star.nodes.len();

    // The star's subdivision matrix S: node i ↦ its child point.
    let plan = SubdivisionPlan::with_tags(&star.t, &star.tags, *options, 1)?;
    let r = plan.levels()[0].stencil.as_ref().ok_or(EvalError::Internal("no refinement stencil".into()))?;
    let (nv, nf) = (star.t.vertex_count(), star.t.face_count());
    let mut child = vec![0u32; n];
    for i in 1..=star.edges {
        let e = star.t.find_edge(VertexId(0), VertexId(i as u32)).expect("a star edge");
        // The edge point's number in the split (`subdiv_stencil::Split`).
        child[i] = match options.scheme.traits().split {
            Split::Quad => (nv + nf + e.index()) as u32,
            Split::Triangle => (nv + e.index()) as u32,
            Split::Dual => return Err(EvalError::Internal("the dual split has no vertex stars".into())),
            Split::Sqrt3 => return Err(EvalError::Internal("the √3 split is not evaluated".into())),
        };
    }
    for (i, &f) in star.far.iter().enumerate() {
        child[1 + star.edges + i] = (nv + f as usize) as u32;
    }
    let mut s = vec![0.0; n * n];
    for i in 0..n {
        for (j, &w) in r.outer_view(child[i] as usize).expect("child row").iter() {
            s[i * n + j] += w;
        }
    }
    // The limit mask: S's left eigenvector of eigenvalue 1 (power iteration
    // on Sᵀ, converging like λ₁ⁱᵗ). The schemes' closed-form masks are the
    // same vector, darts included (their exact mask); only under
    // `DartLimit::SmoothMask` does `--limit` (as OpenSubdiv's `Limit`) use
    // the smooth mask at a dart, an approximation that changes level by
    // level, while this stays the limit.
    let mut l0 = vec![1.0 / n as f64; n];
    let mut next0 = vec![0.0; n];
    for _ in 0..ITERATIONS {
        next0.iter_mut().for_each(|x| *x = 0.0);
        for i in 0..n {
            for j in 0..n {
                next0[j] += s[i * n + j] * l0[i];
            }
        }
        let sum: f64 = next0.iter().sum();
        next0.iter_mut().for_each(|x| *x /= sum);
        let change = l0.iter().zip(&next0).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        std::mem::swap(&mut l0, &mut next0);
        if change == 0.0 {
            break; // a fixed point in floating point
        }
    }
    let cs = VertexId(0);
    let (a, b) = (VertexId(a as u32), VertexId(b as u32));

    // Subspace iteration, eigenvalue 1 deflated: right (X) and left (Y).
    let mut x: Vec<[f64; 2]> = (0..n).map(|i| [(i as f64 * 1.3 + 0.4).cos(), (i as f64 * 0.7 + 1.1).sin()]).collect();
    let mut y = x.clone();
    let mut next = vec![[0.0; 2]; n];
    let mut steady = 0;
    for _ in 0..ITERATIONS {
        let (x_old, y_old) = (x.clone(), y.clone());
        // X ← S X, minus its component along 𝟙 (l₀·X).
        for i in 0..n {
            let mut acc = [0.0; 2];
            for j in 0..n {
                let w = s[i * n + j];
                acc[0] += w * x[j][0];
                acc[1] += w * x[j][1];
            }
            next[i] = acc;
        }
        let proj = [0, 1].map(|c| (0..n).map(|j| l0[j] * next[j][c]).sum::<f64>());
        next.iter_mut().for_each(|p| *p = [p[0] - proj[0], p[1] - proj[1]]);
        orthonormalize(&mut next);
        std::mem::swap(&mut x, &mut next);
        // Y ← Sᵀ Y, minus its component along l₀ (𝟙·Y).
        for j in 0..n {
            next[j] = [0.0; 2];
        }
        for i in 0..n {
            for j in 0..n {
                let w = s[i * n + j];
                next[j][0] += w * y[i][0];
                next[j][1] += w * y[i][1];
            }
        }
        let sum = [0, 1].map(|c| next.iter().map(|p| p[c]).sum::<f64>());
        for j in 0..n {
            next[j][0] -= l0[j] * sum[0];
            next[j][1] -= l0[j] * sum[1];
        }
        orthonormalize(&mut next);
        std::mem::swap(&mut y, &mut next);
        let moved = |a: &[[f64; 2]], b: &[[f64; 2]]| {
            a.iter().zip(b).map(|(p, q)| (p[0] - q[0]).abs().max((p[1] - q[1]).abs())).fold(0.0, f64::max)
        };
        // Stop once both bases have stopped moving (to rounding) a few times running.
        steady = if moved(&x, &x_old).max(moved(&y, &y_old)) < 1e-15 { steady + 1 } else { 0 };
        if steady >= 3 {
            break;
        }
    }
    // Π = X (YᵀX)⁻¹ Yᵀ.
    let mut g = [[0.0; 2]; 2];
    for i in 0..n {
        for p in 0..2 {
            for q in 0..2 {
                g[p][q] += y[i][p] * x[i][q];
            }
        }
    }
    let det = g[0][0] * g[1][1] - g[0][1] * g[1][0];
    if det.abs() < 1e-12 {
        return Err(EvalError::Internal("the tangent subspace did not converge".into()));
    }
    let m = [[g[1][1] / det, -g[0][1] / det], [-g[1][0] / det, g[0][0] / det]];
    let tangent = |e: VertexId| -> Vec<f64> {
        let d = [x[e.index()][0] - x[cs.index()][0], x[e.index()][1] - x[cs.index()][1]];
        let dm = [d[0] * m[0][0] + d[1] * m[1][0], d[0] * m[0][1] + d[1] * m[1][1]];
        (0..n).map(|j| dm[0] * y[j][0] + dm[1] * y[j][1]).collect()
    };
    let to_root = |w: &[f64]| -> Vec<f64> {
        let mut out = vec![0.0; local.root];
        let combo: Vec<(u32, f64)> =
            w.iter().zip(&star.nodes).filter(|&(&w, _)| w != 0.0).map(|(&w, &v)| (v, w)).collect();
        local.combine(&combo, &mut out);
        out
    };
    Ok([to_root(&l0), to_root(&tangent(a)), to_root(&tangent(b))])
}

/// The star of a vertex with every far corner and edge end its own node
/// (so refinement maps it onto itself even where the mesh identifies them,
/// as at a valence-2 vertex): node 0 the vertex, nodes 1..=edges the edge
/// ends in fan order, then the far corners face by face.
struct Unfolded {
    t: Topology,
    tags: Tags,
    /// Local vertex of every node.
    nodes: Vec<u32>,
    /// Number of edges at the vertex.
    edges: usize,
    /// Face of every far-corner node (in star face order).
    far: Vec<u32>,
}

impl Unfolded {
    fn new(t: &Topology, sharp: &LevelSharpness, c: VertexId) -> Result<Self, EvalError> {
        let fan = t.vertex_fan(c);
        let boundary = t.is_boundary_vertex(c);
        let edges = fan.len() + usize::from(boundary);
        let mut nodes = vec![c.0];
        let mut edge_sharpness = Vec::with_capacity(edges);
        for &h in fan {
            nodes.push(t.he_to(h).0);
            edge_sharpness.push(sharp.edge(t, t.he_edge(h)));
        }
        if boundary {
            let incoming = t.he_prev(fan[fan.len() - 1]);
            nodes.push(t.he_from(incoming).0);
            edge_sharpness.push(sharp.edge(t, t.he_edge(incoming)));
        }
        let mut faces = FaceList::new();
        let mut far = Vec::new();
        let mut buf = Vec::new();
        for (i, &h) in fan.iter().enumerate() {
            let g = t.he_face(h);
            let ring = t.face(g);
            let m = ring.len();
            let k = t.he_corner(h).index as usize;
            buf.clear();
            buf.push(0u32);
            buf.push(1 + i as u32);
            for j in 2..m - 1 {
                far.push(i as u32);
                buf.push(nodes.len() as u32);
                nodes.push(ring[(k + j) % m]);
            }
            buf.push(1 + ((i + 1) % edges) as u32);
            faces.push(&buf);
        }
        let topo = Topology::new(faces, nodes.len()).map_err(|e| EvalError::Internal(format!("vertex star: {e}")))?;
        let mut e_values = vec![0f32; topo.edge_count()];
        for (i, &s) in edge_sharpness.iter().enumerate() {
            let e = topo.find_edge(VertexId(0), VertexId(1 + i as u32)).expect("a star edge");
            // Boundary edges are sharp by topology; keep the tag of the others.
            e_values[e.index()] = if topo.is_boundary_edge(e) { 0.0 } else { s };
        }
        let mut v_values = vec![0f32; nodes.len()];
        v_values[0] = sharp.tags(t).vertex_sharpness(c);
        let tags =
            Tags::from_arrays(&topo, e_values, v_values).map_err(|e| EvalError::Internal(format!("star tags: {e}")))?;
        Ok(Self { t: topo, tags, nodes, edges, far })
    }
}

/// Gram-Schmidt on two columns.
fn orthonormalize(x: &mut [[f64; 2]]) {
    let norm0 = x.iter().map(|p| p[0] * p[0]).sum::<f64>().sqrt();
    if norm0 > 0.0 {
        x.iter_mut().for_each(|p| p[0] /= norm0);
    }
    let d = x.iter().map(|p| p[0] * p[1]).sum::<f64>();
    x.iter_mut().for_each(|p| p[1] -= d * p[0]);
    let norm1 = x.iter().map(|p| p[1] * p[1]).sum::<f64>().sqrt();
    if norm1 > 0.0 {
        x.iter_mut().for_each(|p| p[1] /= norm1);
    }
}
