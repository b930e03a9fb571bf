//! The checks every triangulation must pass, from the input and the output
//! alone (nothing here knows how the diagonals were chosen). Shared by
//! `crates/mesh/tests/integration/triangulate.rs` and, through `#[path]`, by the
//! fixture test `crates/io/tests/integration/triangulate_fixtures.rs`, which can read
//! files (the mesh crate cannot depend on `subdiv-io`).
#![allow(dead_code)] // each including test uses part of it

use std::collections::HashSet;
use subdiv_mesh::{newell_normal, DVec3, FaceId, Mesh, Triangulation};

/// What the geometric checks covered.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Checked {
    /// Input faces with more than three corners.
    pub split: usize,
    /// Of those, faces with a triangulation into triangles of the face's
    /// orientation — projected on the plane ⟂ the face's Newell vector,
    /// every triangle has positive area — whose diagonals are neither edges
    /// of the input nor diagonals of the triangles made of earlier faces
    /// (found by exhausting all triangulations). The triangles made of each
    /// such face were checked to be of that kind. For a simple projection
    /// they tile the face without overlap (its winding number, 1 inside and 0
    /// outside, is the sum of theirs).
    pub valid: usize,
    /// Of those, faces with no such triangulation (self-intersecting
    /// projections, or every oriented split blocked by existing edges or
    /// earlier diagonals): only the topology was checked.
    pub impossible: usize,
    /// Planar faces among `valid`: the triangles' 3D areas were checked to
    /// sum to the face's area.
    pub planar: usize,
}

/// Whether the polygon `q` has a triangulation into positively oriented
/// triangles whose diagonals are not `forbidden`, by exhausting every
/// triangulation: the sub-polygon of corners i..=j (closed by side or chord
/// ij) has one when some apex k between them makes a positive triangle ikj
/// with allowed chords and both smaller sub-polygons have one (memoised).
fn oriented_triangulation_exists(q: &[[f64; 2]], forbidden: &dyn Fn(usize, usize) -> bool) -> bool {
    let m = q.len();
    let mut exists = vec![false; m * m];
    for span in 1..m {
        for i in 0..m - span {
            let j = i + span;
            exists[i * m + j] = span == 1
                || (i + 1..j).any(|k| {
                    orient(q[i], q[k], q[j]) > 0.0
                        && (k == i + 1 || !forbidden(i, k))
                        && (k + 1 == j || !forbidden(k, j))
                        && exists[i * m + k]
                        && exists[k * m + j]
                });
        }
    }
    exists[m - 1]
}

/// Doubled signed area of the 2D triangle (a, b, c).
fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The corners projected on the plane ⟂ their Newell vector, relative to
/// the first, with (u, w, n̂) right-handed; `None` for a zero-area polygon.
pub fn project(p: &[DVec3]) -> Option<Vec<[f64; 2]>> {
    let n = newell_normal(p.iter().copied());
    let longest = (0..p.len()).map(|k| p[k].distance(p[(k + 1) % p.len()])).fold(0.0, f64::max);
    if n.length() <= 1e-10 * longest * longest {
        return None;
    }
    let nh = n.normalize();
    let u = nh.any_orthonormal_vector();
    let w = nh.cross(u);
    Some(p.iter().map(|&x| [(x - p[0]).dot(u), (x - p[0]).dot(w)]).collect())
}

/// True when corner `i` of the simple 2D polygon `q` is an ear: convex, and
/// its triangle contains no other corner (not even on its sides).
pub fn is_ear(q: &[[f64; 2]], i: usize) -> bool {
    let m = q.len();
    let (a, b, c) = (q[(i + m - 1) % m], q[i], q[(i + 1) % m]);
    if orient(a, b, c) <= 0.0 {
        return false;
    }
    let inside = |x: [f64; 2]| orient(a, b, x) >= 0.0 && orient(b, c, x) >= 0.0 && orient(c, a, x) >= 0.0;
    (0..m).filter(|&k| k != i && k != (i + 1) % m && k != (i + m - 1) % m).all(|k| !inside(q[k]))
}

/// Position of `v` in `face`.
fn corner_of(face: &[u32], v: u32) -> Option<usize> {
    face.iter().position(|&x| x == v)
}

/// Checks `tri` against `input`: same vertices bit for bit, m − 2 triangles
/// per face over the face's own corners in its cyclic order (orientation
/// kept), triangles untouched, the input's edges kept plus one new edge per
/// diagonal, the same Euler characteristic, boundary loops, components and
/// genus, groups following their faces; and for every face that has a
/// triangulation into triangles of positive projected area (see
/// [`Checked::valid`]), such triangles, with, as a cross-check, areas
/// summing to the face's.
pub fn check(input: &Mesh, tri: &Triangulation) -> Result<Checked, String> {
    let (t, r) = (input.topology(), tri.mesh.topology());
    if tri.mesh.positions().len() != input.positions().len()
        || tri
            .mesh
            .positions()
            .iter()
            .zip(input.positions())
            .any(|(a, b)| a.to_array().map(f64::to_bits) != b.to_array().map(f64::to_bits))
    {
        return Err("vertices differ".into());
    }
    if !r.faces().all_of_size(3) {
        return Err("not all triangles".into());
    }
    let expected: usize = t.face_ids().map(|f| t.face_size(f) - 2).sum();
    if r.face_count() != expected || tri.source_face.len() != expected {
        return Err(format!(
            "{} triangles and {} sources for {expected} expected",
            r.face_count(),
            tri.source_face.len()
        ));
    }
    if tri.source_face.windows(2).any(|w| w[1] < w[0]) {
        return Err("source faces are not in input order".into());
    }
    let split = t.face_ids().filter(|&f| t.face_size(f) > 3).count();
    if tri.split_faces != split {
        return Err(format!("split_faces {} != {split}", tri.split_faces));
    }
    // Topological invariants (a diagonal adds one edge and one face).
    let inv = |t: &subdiv_mesh::Topology| {
        (t.euler_characteristic(), t.boundary_loop_count(), t.component_count(), t.genus(), t.vertex_count())
    };
    if inv(t) != inv(r) {
        return Err(format!("invariants changed: {:?} → {:?}", inv(t), inv(r)));
    }
    let diagonals: usize = t.face_ids().map(|f| t.face_size(f) - 3).sum();
    if r.edge_count() != t.edge_count() + diagonals {
        return Err(format!("{} edges, expected {} + {diagonals}", r.edge_count(), t.edge_count()));
    }
    let has_edge = |a: u32, b: u32| r.vertex_neighbors(subdiv_mesh::VertexId(a)).any(|w| w.0 == b);
    if let Some(e) = t.edges().find(|&e| {
        let (a, b) = t.edge_vertices(e);
        !has_edge(a.0, b.0)
    }) {
        return Err(format!("input edge {:?} lost", t.edge_vertices(e)));
    }
    // Each face's triangles: its corners, in its cyclic order.
    let mut start = 0;
    let mut earlier_diagonals: HashSet<(u32, u32)> = HashSet::new();
    let pair = |a: u32, b: u32| (a.min(b), a.max(b));
    let mut checked = Checked { split, ..Checked::default() };
    let mut pending = Vec::new();
    for f in t.face_ids() {
        earlier_diagonals.extend(pending.drain(..));
        let face = t.face(f);
        let count = face.len() - 2;
        let tris: Vec<&[u32]> = (start..start + count).map(|k| r.face(FaceId(k as u32))).collect();
        if tri.source_face[start..start + count].iter().any(|&s| s != f) {
            return Err(format!("face {f}: wrong source faces"));
        }
        start += count;
        if face.len() == 3 {
            if tris[0] != face {
                return Err(format!("triangle {f} changed: {:?} → {:?}", face, tris[0]));
            }
            continue;
        }
        for c in &tris {
            let k: Option<Vec<usize>> = c.iter().map(|&v| corner_of(face, v)).collect();
            let Some(k) = k else { return Err(format!("face {f}: triangle {c:?} uses a foreign vertex")) };
            // Cyclically increasing: exactly one of the three steps wraps around.
            let wraps = (0..3).filter(|&i| k[(i + 1) % 3] < k[i]).count();
            if wraps != 1 {
                return Err(format!("face {f} {face:?}: triangle {c:?} reverses the face's orientation"));
            }
        }
        // This face's diagonals count for the faces after it.
        for c in &tris {
            for i in 0..3 {
                let (a, b) = (c[i], c[(i + 1) % 3]);
                let (ka, kb) = (corner_of(face, a).unwrap(), corner_of(face, b).unwrap());
                if (ka + 1) % face.len() != kb && (kb + 1) % face.len() != ka {
                    pending.push(pair(a, b));
                }
            }
        }
        // Geometry in the plane ⟂ the Newell vector.
        let p: Vec<DVec3> = face.iter().map(|&v| input.positions()[v as usize]).collect();
        let Some(q) = project(&p) else { continue };
        let taken = |a: usize, b: usize| {
            t.vertex_neighbors(subdiv_mesh::VertexId(face[a])).any(|w| w.0 == face[b])
                || earlier_diagonals.contains(&pair(face[a], face[b]))
        };
        if !oriented_triangulation_exists(&q, &taken) {
            checked.impossible += 1;
            continue;
        }
        checked.valid += 1;
        let n = newell_normal(p.iter().copied());
        let nh = n.normalize();
        let longest = (0..p.len()).map(|k| p[k].distance(p[(k + 1) % p.len()])).fold(0.0, f64::max);
        let at = |v: u32| input.positions()[v as usize];
        let mut projected = 0.0;
        let mut area = 0.0;
        for c in &tris {
            let cross = (at(c[1]) - at(c[0])).cross(at(c[2]) - at(c[0]));
            let s = cross.dot(nh);
            if s <= 0.0 {
                return Err(format!(
                    "face {f}: triangle {c:?} is flipped or degenerate (projected doubled area {s:e})"
                ));
            }
            projected += s;
            area += cross.length();
        }
        if (projected - n.length()).abs() > 1e-9 * n.length() {
            return Err(format!("face {f}: triangles cover {projected} of {} (doubled, projected)", n.length()));
        }
        let off_plane = p.iter().map(|&x| (x - p[0]).dot(nh).abs()).fold(0.0, f64::max);
        if off_plane <= 1e-9 * longest {
            checked.planar += 1;
            if (area - n.length()).abs() > 1e-9 * n.length() {
                return Err(format!("planar face {f}: triangle areas {area} ≠ face area {} (doubled)", n.length()));
            }
        }
    }
    let groups = input.groups();
    if groups.face_group.len() == t.face_count() {
        let out = tri.mesh.groups();
        if out.names != groups.names
            || out.face_group.len() != r.face_count()
            || tri.source_face.iter().zip(&out.face_group).any(|(s, &g)| groups.face_group[s.index()] != g)
        {
            return Err("groups do not follow their faces".into());
        }
    }
    Ok(checked)
}
