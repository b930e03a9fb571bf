//! Catmull-Clark operators: the refinement stencil R and the limit stencil.
//!
//! Rules: `subdiv_rules::catmull_clark` (Cheng et al., Appendix Eq. 4 as
//! corrected by ERRATA C2; limit Eq. 5 with ERRATA C1). Boundaries follow
//! OpenSubdiv's `EDGE_AND_CORNER`: boundary edges are cubic B-spline creases,
//! vertices in a single face are corners and stay.
//!
//! Row order of R is the [`subdiv_mesh::refine::quad_split`] numbering: old
//! vertices, then face points, then edge points.

use crate::{face_ring_size, vertex_kind, RowBuilder, SparseMatrix, Summation};
use glam::DVec3;
use subdiv_mesh::refine::quad_split;
use subdiv_mesh::{EdgeId, FaceId, HalfEdgeId, Topology, VertexId};
use subdiv_rules::catmull_clark::{
    edge_point_mask, face_point_weight, limit_stencil as cheng_limit, vertex_point_mask,
};
use subdiv_rules::VertexKind;

/// Adds the boundary part of a vertex mask (the two boundary neighbours).
pub(crate) fn add_boundary_neighbors(rows: &mut RowBuilder, t: &Topology, v: VertexId, weight: f64) {
    if let Some((prev, next)) = t.boundary_neighbors(v) {
        rows.add(prev.0, weight);
        rows.add(next.0, weight);
    }
}

/// (V + F + E) × V refinement stencil: P₁ = R·P₀ on [`quad_split`]'s numbering.
///
/// Each row is written with its weights already merged per neighbour (an
/// edge neighbour collects its edge term and the two face points it lies in),
/// so a row holds its distinct columns once unless the mesh makes two of them
/// coincide, which [`RowBuilder`] still sums. Rows are built in parallel.
pub fn refinement_stencil(t: &Topology) -> SparseMatrix {
    let (nv, nf, ne) = (t.vertex_count(), t.face_count(), t.edge_count());
    let size = |h: HalfEdgeId| t.face_size(t.he_face(h));
    // Columns of each row when its neighbours are distinct (the usual case).
    let max_len = |i: usize| {
        if i < nv {
            let v = VertexId(i as u32);
            match vertex_kind(t, v) {
                VertexKind::Interior => face_ring_size(t, v), // 1 for an isolated vertex
                VertexKind::Boundary => 3,
                _ => 1,
            }
        } else if i < nv + nf {
            t.face_size(FaceId((i - nv) as u32))
        } else {
            let h = t.edge_half_edge(EdgeId((i - nv - nf) as u32));
            t.he_twin(h).map_or(2, |g| size(h) + size(g) - 2)
        }
    };
    RowBuilder::build_parallel_bounded(nv + nf + ne, nv, Summation::InOrder, max_len, |i, rows, _: &mut ()| {
        refinement_row(t, i, rows)
    })
}

/// The points of one Catmull-Clark step, `apply(&refinement_stencil(t), x)`
/// up to round-off, evaluated row by row without building the stencil.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn step_points(t: &Topology, x: &[DVec3]) -> Vec<DVec3> {
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    let rows = t.vertex_count() + t.face_count() + t.edge_count();
    RowBuilder::evaluate_parallel_with_scratch(rows, x, |i, rows, _: &mut ()| refinement_row(t, i, rows))
}

/// Row `i` of the refinement stencil on [`quad_split`]'s numbering.
fn refinement_row(t: &Topology, i: usize, rows: &mut RowBuilder) {
    let (nv, nf) = (t.vertex_count(), t.face_count());
    if i < nv {
        vertex_point_row(t, VertexId(i as u32), rows);
    } else if i < nv + nf {
        let face = t.face(FaceId((i - nv) as u32));
        rows.add_all(face, face_point_weight(face.len())); // Eq. (4): f = (Σ corners)/m
    } else {
        edge_point_row(t, EdgeId((i - nv - nf) as u32), rows);
    }
}

/// The corners of `h`'s face rotated to start at `h`'s corner: `ring(j)` is
/// the corner `j` steps further (`j` < face size), and the face size.
#[inline]
fn face_ring(t: &Topology, h: HalfEdgeId) -> (impl Fn(usize) -> u32 + '_, usize) {
    let corner = t.he_corner(h);
    let face = t.face(corner.face);
    let k = corner.index as usize;
    let ring = move |j: usize| {
        let at = k + j; // j < m: wraps at most once
        face[if at >= face.len() { at - face.len() } else { at }]
    };
    (ring, face.len())
}

/// Row of the new vertex point of `v` (Eq. 4, first line; boundary (E₋ + 6V + E₊)/8; corner V).
fn vertex_point_row(t: &Topology, v: VertexId, rows: &mut RowBuilder) {
    let kind = vertex_kind(t, v);
    if t.is_isolated(v) {
        rows.add(v.0, 1.0);
    } else if kind == VertexKind::Interior {
        // Eq. (4): v = (n−2)/n V + 1/n² Σ Eᵢ + 1/n² Σ fᵢ, fᵢ expanded over its
        // corners: V, Eᵢ and Eᵢ₊₁ (each shared with a neighbouring face) and
        // the far corners F₁ⁱ…F_{mᵢ−3}ⁱ.
        let fan = t.vertex_fan(v);
        let mask = vertex_point_mask(kind, fan.len());
        let face_weight = |m: usize| mask.face * face_point_weight(m);
        let mut previous = face_weight(t.face_size(t.he_face(fan[fan.len() - 1]))); // E₀ is in the last face too
        let mut centre = mask.vertex;
        for &h in fan {
            let (ring, m) = face_ring(t, h);
            let w = face_weight(m);
            centre += w;
            rows.add(ring(1), mask.interior_neighbor + previous + w); // Eᵢ ∈ fᵢ₋₁, fᵢ
            for j in 2..m - 1 {
                rows.add(ring(j), w); // far corners of fᵢ
            }
            previous = w;
        }
        rows.add(v.0, centre);
    } else {
        let mask = vertex_point_mask(kind, t.valence(v));
        rows.add(v.0, mask.vertex);
        if kind == VertexKind::Boundary {
            add_boundary_neighbors(rows, t, v, mask.boundary_neighbor); // a corner stays: no zero entries
        }
    }
}

/// Row of the new edge point of `e`: ERRATA C2, e = (V + Eᵢ + fᵢ₋₁ + fᵢ)/4 with
/// the face points expanded (the corners of each face other than the ends);
/// the midpoint on the boundary.
fn edge_point_row(t: &Topology, e: EdgeId, rows: &mut RowBuilder) {
    let h = t.edge_half_edge(e);
    let twin = t.he_twin(h);
    let mask = edge_point_mask(t.face_size(t.he_face(h)), twin.map(|g| t.face_size(t.he_face(g))));
    rows.add(t.he_from(h).0, mask.end);
    rows.add(t.he_to(h).0, mask.end);
    for (side, w) in [(Some(h), mask.left), (twin, mask.right)] {
        if let Some(side) = side.filter(|_| w != 0.0) {
            let (ring, m) = face_ring(t, side);
            for j in 2..m {
                rows.add(ring(j), w);
            }
        }
    }
}

/// One Catmull-Clark step: the refined topology and its stencil.
pub fn refine(t: &Topology) -> (Topology, SparseMatrix) {
    (quad_split(t), refinement_stencil(t))
}

/// Working memory of a limit row: the fan's face sizes, edge and far-corner weights.
type LimitScratch = (Vec<usize>, Vec<f64>, Vec<f64>);

/// Row v of the limit stencil on any polygon mesh. Interior: Cheng's Eq. 5
/// (one step composed with the quad limit mask, ERRATA C1/C2); boundary:
/// (E₋ + 4V + E₊)/6; corner: V.
fn limit_row(t: &Topology, v: VertexId, rows: &mut RowBuilder, scratch: &mut LimitScratch) {
    match vertex_kind(t, v) {
        _ if t.is_isolated(v) => rows.add(v.0, 1.0),
        VertexKind::Interior => {
            let fan = t.vertex_fan(v);
            let (sizes, edge_w, far_w) = scratch;
            sizes.clear();
            sizes.extend(fan.iter().map(|&h| t.face_size(t.he_face(h))));
            edge_w.resize(fan.len(), 0.0);
            far_w.resize(fan.len(), 0.0);
            let wv = cheng_limit(sizes, edge_w, far_w); // Eq. (5)
            rows.add(v.0, wv);
            for (i, &h) in fan.iter().enumerate() {
                let (ring, m) = face_ring(t, h);
                rows.add(ring(1), edge_w[i]);
                // Far corners of face i = (V, Eᵢ, F₁ⁱ…F_{m−3}ⁱ, Eᵢ₊₁).
                for j in 2..m - 1 {
                    rows.add(ring(j), far_w[i]);
                }
            }
        }
        VertexKind::Boundary => {
            rows.add(v.0, 4.0 / 6.0);
            add_boundary_neighbors(rows, t, v, 1.0 / 6.0);
        }
        VertexKind::Corner => rows.add(v.0, 1.0),
    }
}

/// V × V limit stencil: row v gives the limit point of vertex v ([`limit_row`]).
pub fn limit_stencil(t: &Topology) -> SparseMatrix {
    let nv = t.vertex_count();
    RowBuilder::build_parallel_with_scratch(nv, nv, Summation::InOrder, |i, rows, scratch: &mut LimitScratch| {
        limit_row(t, VertexId(i as u32), rows, scratch)
    })
}

/// The limit point of every vertex, `apply(&limit_stencil(t), x)` up to
/// round-off, evaluated row by row without building the stencil.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn limit_points(t: &Topology, x: &[DVec3]) -> Vec<DVec3> {
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    RowBuilder::evaluate_parallel_with_scratch(t.vertex_count(), x, |i, rows, scratch: &mut LimitScratch| {
        limit_row(t, VertexId(i as u32), rows, scratch)
    })
}
