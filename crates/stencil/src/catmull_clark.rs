//! Catmull-Clark operators: the refinement stencil R and the limit stencil.
//!
//! Rules: `subdiv_rules::catmull_clark` (Cheng et al., Appendix Eq. 4 as
//! corrected by ERRATA C2; limit Eq. 5 with ERRATA C1). Boundaries follow
//! OpenSubdiv's `EDGE_AND_CORNER`: boundary edges are cubic B-spline creases,
//! vertices in a single face are corners and stay.
//!
//! Row order of R is the [`subdiv_mesh::refine::quad_split`] numbering: old
//! vertices, then face points, then edge points.

use crate::{vertex_kind, RowBuilder, SparseMatrix};
use subdiv_mesh::refine::quad_split;
use subdiv_mesh::{Topology, VertexId};
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
pub fn refinement_stencil(t: &Topology) -> SparseMatrix {
    let (nv, nf, ne) = (t.vertex_count(), t.face_count(), t.edge_count());
    let mut rows = RowBuilder::with_capacity(nv + nf + ne, 10 * nv + t.half_edge_count() * 3);
    for v in t.vertices() {
        let kind = vertex_kind(t, v);
        if t.is_isolated(v) {
            rows.add(v.0, 1.0);
        } else if kind == VertexKind::Interior {
            // Eq. (4): v = (n−2)/n V + 1/n² Σ Eᵢ + 1/n² Σ fᵢ, fᵢ expanded over its corners.
            let n = t.valence(v);
            let mask = vertex_point_mask(kind, n);
            rows.add(v.0, mask.vertex);
            for e in t.vertex_neighbors(v) {
                rows.add(e.0, mask.interior_neighbor);
            }
            for c in t.vertex_corners(v) {
                let face = t.face(c.face);
                rows.add_all(face, mask.face * face_point_weight(face.len()));
            }
        } else {
            let mask = vertex_point_mask(kind, t.valence(v));
            rows.add(v.0, mask.vertex);
            add_boundary_neighbors(&mut rows, t, v, mask.boundary_neighbor);
        }
        rows.finish_row();
    }
    for f in t.face_ids() {
        let face = t.face(f);
        rows.add_all(face, face_point_weight(face.len())); // Eq. (4): f = (Σ corners)/m
        rows.finish_row();
    }
    for e in t.edges() {
        let h = t.edge_half_edge(e);
        let (a, b) = (t.he_from(h), t.he_to(h));
        let left = t.he_face(h);
        let right = t.he_twin(h).map(|g| t.he_face(g));
        let mask = edge_point_mask(t.face_size(left), right.map(|r| t.face_size(r)));
        // ERRATA C2: e = (V + Eᵢ + f_{i−1} + fᵢ)/4, the face points expanded; or the midpoint.
        for (face, w) in [(Some(left), mask.left), (right, mask.right)] {
            if let Some(face) = face.filter(|_| w != 0.0) {
                rows.add_all(t.face(face), w);
                rows.add(a.0, -w);
                rows.add(b.0, -w);
            }
        }
        rows.add(a.0, mask.end);
        rows.add(b.0, mask.end);
        rows.finish_row();
    }
    rows.build(nv)
}

/// One Catmull-Clark step: the refined topology and its stencil.
pub fn refine(t: &Topology) -> (Topology, SparseMatrix) {
    (quad_split(t), refinement_stencil(t))
}

/// V × V limit stencil: row v gives the limit point of vertex v on any polygon
/// mesh. Interior: Cheng's Eq. 5 (one step composed with the quad limit mask,
/// ERRATA C1/C2); boundary: (E₋ + 4V + E₊)/6; corner: V.
pub fn limit_stencil(t: &Topology) -> SparseMatrix {
    let nv = t.vertex_count();
    let mut rows = RowBuilder::with_capacity(nv, 16 * nv);
    let (mut sizes, mut edge_w, mut far_w) = (Vec::new(), Vec::new(), Vec::new());
    for v in t.vertices() {
        let kind = vertex_kind(t, v);
        match kind {
            _ if t.is_isolated(v) => rows.add(v.0, 1.0),
            VertexKind::Interior => {
                let fan = t.vertex_fan(v);
                sizes.clear();
                sizes.extend(fan.iter().map(|&h| t.face_size(t.he_face(h))));
                edge_w.resize(fan.len(), 0.0);
                far_w.resize(fan.len(), 0.0);
                let wv = cheng_limit(&sizes, &mut edge_w, &mut far_w); // Eq. (5)
                rows.add(v.0, wv);
                for (i, &h) in fan.iter().enumerate() {
                    rows.add(t.he_to(h).0, edge_w[i]);
                    // Far corners of face i = (V, Eᵢ, F₁ⁱ…F_{m−3}ⁱ, Eᵢ₊₁).
                    let mut g = t.he_next(t.he_next(h));
                    while t.he_to(g) != v {
                        rows.add(t.he_from(g).0, far_w[i]);
                        g = t.he_next(g);
                    }
                }
            }
            VertexKind::Boundary => {
                rows.add(v.0, 4.0 / 6.0);
                add_boundary_neighbors(&mut rows, t, v, 1.0 / 6.0);
            }
            VertexKind::Corner => rows.add(v.0, 1.0),
        }
        rows.finish_row();
    }
    rows.build(nv)
}
