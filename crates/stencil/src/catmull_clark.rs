//! Catmull-Clark operators: the refinement stencil R and the limit stencil.
//!
//! Rules: `subdiv_rules::catmull_clark` (Cheng et al., Appendix Eq. 4 as
//! corrected by [correction C2]; limit Eq. 5 with [correction C1]). Boundaries follow
//! OpenSubdiv's `EDGE_AND_CORNER`: boundary edges are cubic B-spline creases,
//! vertices in a single face are corners and stay.
//!
//! Row order of R is the [`subdiv_mesh::refine::quad_split`] numbering: old
//! vertices, then face points, then edge points.
//!
//! [correction C2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c2
//! [correction C1]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c1

use crate::scheme::{LevelSplit, SchemeRules};
use crate::sharpness::{EdgeStep, LevelSharpness};
use crate::StencilError;
use crate::{face_ring_size, vertex_kind, RowBuilder, SparseMatrix, Summation};
use glam::DVec3;
use subdiv_mesh::refine::quad_split;
use subdiv_mesh::{EdgeId, FaceId, HalfEdgeId, Topology, VertexId};
use subdiv_rules::catmull_clark::{
    dart_limit_mask, edge_point_mask_with, face_point_weight, limit_mask, vertex_point_mask,
};
use subdiv_rules::{Rule, TriangleRule, VertexKind};

/// (V + F + E) × V refinement stencil: P₁ = R·P₀ on [`quad_split`]'s numbering.
///
/// Each row is written with its weights already merged per neighbour (an
/// edge neighbour collects its edge term and the two face points it lies in),
/// so a row holds its distinct columns once unless the mesh makes two of them
/// coincide, which the row builder still sums. Rows are built in parallel.
pub fn refinement_stencil(t: &Topology) -> SparseMatrix {
    refinement_stencil_sharp(t, &LevelSharpness::plain())
}

/// [`refinement_stencil`] with creases, corners and the boundary option of
/// `sharp` (OpenSubdiv's rules, [`LevelSharpness`]).
pub fn refinement_stencil_sharp(t: &Topology, sharp: &LevelSharpness) -> SparseMatrix {
    let (nv, nf, ne) = (t.vertex_count(), t.face_count(), t.edge_count());
    let size = |h: HalfEdgeId| t.face_size(t.he_face(h));
    // Columns of each row when its neighbours are distinct (the usual case).
    let max_len = |i: usize| {
        if i < nv {
            let v = VertexId(i as u32);
            match vertex_kind(t, v) {
                VertexKind::Interior => face_ring_size(t, v), // 1 for an isolated vertex
                // A boundary crease (or, under edge-only, a one-face vertex on it).
                _ => 3,
            }
        } else if i < nv + nf {
            t.face_size(FaceId((i - nv) as u32))
        } else {
            let h = t.edge_half_edge(EdgeId((i - nv - nf) as u32));
            t.he_twin(h).map_or(2, |g| size(h) + size(g) - 2)
        }
    };
    RowBuilder::build_parallel_bounded(nv + nf + ne, nv, Summation::InOrder, max_len, |i, rows, _: &mut ()| {
        refinement_row(t, sharp, i, rows)
    })
}

/// The points of one Catmull-Clark step, `apply(&refinement_stencil(t), x)`
/// up to round-off, evaluated row by row without building the stencil.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn step_points(t: &Topology, x: &[DVec3]) -> Vec<DVec3> {
    step_points_sharp(t, &LevelSharpness::plain(), x)
}

/// [`step_points`] with the creases, corners and boundary option of `sharp`.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn step_points_sharp(t: &Topology, sharp: &LevelSharpness, x: &[DVec3]) -> Vec<DVec3> {
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    let rows = t.vertex_count() + t.face_count() + t.edge_count();
    RowBuilder::evaluate_parallel_with_scratch(rows, x, |i, rows, _: &mut ()| refinement_row(t, sharp, i, rows))
}

/// Row `i` of the refinement stencil on [`quad_split`]'s numbering.
fn refinement_row(t: &Topology, sharp: &LevelSharpness, i: usize, rows: &mut RowBuilder) {
    let (nv, nf) = (t.vertex_count(), t.face_count());
    if i < nv {
        vertex_point_row(t, sharp, VertexId(i as u32), rows);
    } else if i < nv + nf {
        let face = t.face(FaceId((i - nv) as u32));
        rows.add_all(face, face_point_weight(face.len())); // Eq. (4): f = (Σ corners)/m
    } else {
        let e = EdgeId((i - nv - nf) as u32);
        match sharp.edge_step(t, e) {
            EdgeStep::Smooth => edge_point_row(t, e, sharp.triangle_rule(), 1.0, rows),
            EdgeStep::Midpoint => midpoint_row(t, e, 1.0, rows),
            EdgeStep::Blend(s) => {
                // OpenSubdiv's semi-sharp edge: s·midpoint + (1 − s)·smooth.
                midpoint_row(t, e, s, rows);
                edge_point_row(t, e, sharp.triangle_rule(), 1.0 - s, rows);
            }
        }
    }
}

/// The midpoint of `e`, times `scale`: the rule of a sharp edge.
fn midpoint_row(t: &Topology, e: EdgeId, scale: f64, rows: &mut RowBuilder) {
    let (a, b) = t.edge_vertices(e);
    rows.add(a.0, scale * 0.5);
    rows.add(b.0, scale * 0.5);
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

/// Row of the new vertex point of `v` by the rules of its [`VertexStep`]:
/// smooth (Eq. 4, first line), crease (E₋ + 6V + E₊)/8 along its two sharp
/// edges (the boundary rule), corner V; where the rule changes in the step,
/// w·(parent mask) + (1 − w)·(child mask).
fn vertex_point_row(t: &Topology, sharp: &LevelSharpness, v: VertexId, rows: &mut RowBuilder) {
    if t.is_isolated(v) {
        rows.add(v.0, 1.0);
        return;
    }
    for (rule, ends, w) in sharp.vertex_step(t, v).masks() {
        vertex_mask_row(t, v, rule, ends, w, rows);
    }
}

/// One vertex-point mask of `rule` at `v`, times `scale`.
fn vertex_mask_row(
    t: &Topology,
    v: VertexId,
    rule: Rule,
    ends: Option<(VertexId, VertexId)>,
    scale: f64,
    rows: &mut RowBuilder,
) {
    match (rule, ends) {
        (Rule::Smooth | Rule::Dart, _) => smooth_vertex_row(t, v, scale, rows),
        (Rule::Crease, Some((a, b))) => {
            let mask = vertex_point_mask(VertexKind::Boundary, 2); // (E₋ + 6V + E₊)/8
            rows.add(v.0, scale * mask.vertex);
            rows.add(b.0, scale * mask.boundary_neighbor);
            rows.add(a.0, scale * mask.boundary_neighbor);
        }
        (Rule::Corner, _) | (Rule::Crease, None) => rows.add(v.0, scale),
    }
}

/// Eq. (4) at an interior vertex, times `scale`: v = (n−2)/n V + 1/n² Σ Eᵢ +
/// 1/n² Σ fᵢ, fᵢ expanded over its corners: V, Eᵢ and Eᵢ₊₁ (each shared with
/// a neighbouring face) and the far corners F₁ⁱ…F_{mᵢ−3}ⁱ.
fn smooth_vertex_row(t: &Topology, v: VertexId, scale: f64, rows: &mut RowBuilder) {
    let fan = t.vertex_fan(v);
    let mask = vertex_point_mask(VertexKind::Interior, fan.len());
    let face_weight = |m: usize| mask.face * face_point_weight(m);
    let mut previous = face_weight(t.face_size(t.he_face(fan[fan.len() - 1]))); // E₀ is in the last face too
    let mut centre = mask.vertex;
    for &h in fan {
        let (ring, m) = face_ring(t, h);
        let w = face_weight(m);
        centre += w;
        rows.add(ring(1), scale * (mask.interior_neighbor + previous + w)); // Eᵢ ∈ fᵢ₋₁, fᵢ
        for j in 2..m - 1 {
            rows.add(ring(j), scale * w); // far corners of fᵢ
        }
        previous = w;
    }
    rows.add(v.0, scale * centre);
}

/// Row of the new edge point of `e`: [correction C2], e = (V + Eᵢ + fᵢ₋₁ + fᵢ)/4 with
/// the face points expanded (the corners of each face other than the ends);
/// the midpoint on the boundary; OpenSubdiv's weights next to a triangle
/// under [`TriangleRule::Smooth`]; times `scale`.
///
/// [correction C2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c2
fn edge_point_row(t: &Topology, e: EdgeId, rule: TriangleRule, scale: f64, rows: &mut RowBuilder) {
    let h = t.edge_half_edge(e);
    let twin = t.he_twin(h);
    let mask = edge_point_mask_with(t.face_size(t.he_face(h)), twin.map(|g| t.face_size(t.he_face(g))), rule);
    rows.add(t.he_from(h).0, scale * mask.end);
    rows.add(t.he_to(h).0, scale * mask.end);
    for (side, w) in [(Some(h), mask.left), (twin, mask.right)] {
        if let Some(side) = side.filter(|_| w != 0.0) {
            let (ring, m) = face_ring(t, side);
            for j in 2..m {
                rows.add(ring(j), scale * w);
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

/// Row v of the limit stencil on any polygon mesh, by the vertex's rule at
/// this level ([`LevelSharpness::limit_rule`]). Smooth: Cheng's Eq. 5 (one
/// step composed with the quad limit mask, [corrections C1/C2]); dart whose
/// edge is infinitely sharp, under [`DartLimit::Exact`]
/// ([`LevelSharpness::exact_dart_edge`]): its exact limit, [`dart_limit_row`];
/// other darts (a semi-sharp edge, or [`DartLimit::SmoothMask`]): the smooth
/// quad limit mask on an all-quad fan, as OpenSubdiv's `Limit` (Eq. 5 on
/// other fans); crease: (E₋ + 4V + E₊)/6 along its sharp edges (the cubic
/// B-spline of the crease polygon); corner: V. Exact where no semi-sharp
/// value is left around v (refine until the tags have decayed first).
///
/// [corrections C1/C2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c1
/// [`DartLimit::Exact`]: subdiv_rules::DartLimit::Exact
/// [`DartLimit::SmoothMask`]: subdiv_rules::DartLimit::SmoothMask
fn limit_row(t: &Topology, sharp: &LevelSharpness, v: VertexId, rows: &mut RowBuilder, scratch: &mut LimitScratch) {
    if t.is_isolated(v) {
        rows.add(v.0, 1.0);
        return;
    }
    let rule = sharp.limit_rule(t, v);
    if rule.0 == Rule::Dart {
        if let Some(crease) = sharp.exact_dart_edge(t, v) {
            dart_limit_row(t, v, crease, sharp.triangle_rule(), rows);
            return;
        }
    }
    match rule {
        (Rule::Dart, _) if t.vertex_fan(v).iter().all(|&h| t.face_size(t.he_face(h)) == 4) => {
            let fan = t.vertex_fan(v);
            let mask = limit_mask(VertexKind::Interior, fan.len()); // (n²V + 4ΣEᵢ + ΣFᵢ)/(n(n+5))
            rows.add(v.0, mask.vertex);
            for &h in fan {
                let (ring, _) = face_ring(t, h);
                rows.add(ring(1), mask.interior_neighbor);
                rows.add(ring(2), mask.face);
            }
        }
        (Rule::Smooth | Rule::Dart, _) => smooth_limit_row(t, v, rows, scratch),
        (Rule::Crease, Some((a, b))) => {
            rows.add(v.0, 4.0 / 6.0);
            rows.add(b.0, 1.0 / 6.0);
            rows.add(a.0, 1.0 / 6.0);
        }
        (Rule::Corner, _) | (Rule::Crease, None) => rows.add(v.0, 1.0),
    }
}

/// The exact limit of the dart `v` whose fan edge `fan[crease]` is
/// infinitely sharp: the dominant left eigenvector of its 1-ring's
/// subdivision matrix ([`dart_limit_mask`], E₀ the crease's far end). On an
/// all-quad fan the mask itself; on any other fan the mask composed with one
/// step (the dart's fan is all quads after it: V' by the smooth vertex rule,
/// E₀' the crease midpoint, the other Eᵢ' smooth edge points, Fᵢ' the face
/// points), so the row is exact on a base level too.
fn dart_limit_row(t: &Topology, v: VertexId, crease: usize, rule: TriangleRule, rows: &mut RowBuilder) {
    let fan = t.vertex_fan(v);
    let n = fan.len();
    let mask = dart_limit_mask(n);
    // Fan position (crease + i) mod n is the mask's Eᵢ and face i (Eᵢ, Fᵢ, Eᵢ₊₁).
    let at = |i: usize| fan[(crease + i) % n];
    if fan.iter().all(|&h| t.face_size(t.he_face(h)) == 4) {
        rows.add(v.0, mask.vertex);
        for i in 0..n {
            let (ring, _) = face_ring(t, at(i));
            rows.add(ring(1), mask.edge[i]);
            rows.add(ring(2), mask.far_corner[i]);
        }
        return;
    }
    smooth_vertex_row(t, v, mask.vertex, rows); // V' (Eq. 4)
    for i in 0..n {
        let h = at(i);
        if i == 0 {
            midpoint_row(t, t.he_edge(h), mask.edge[0], rows); // E₀' = (V + E₀)/2
        } else {
            edge_point_row(t, t.he_edge(h), rule, mask.edge[i], rows); // Eᵢ' (correction C2)
        }
        let face = t.face(t.he_face(h));
        rows.add_all(face, mask.far_corner[i] * face_point_weight(face.len())); // Fᵢ' = fᵢ
    }
}

/// Cheng's Eq. (5) at a smooth interior vertex of any polygon mesh.
fn smooth_limit_row(t: &Topology, v: VertexId, rows: &mut RowBuilder, scratch: &mut LimitScratch) {
    let fan = t.vertex_fan(v);
    let (sizes, edge_w, far_w) = scratch;
    sizes.clear();
    sizes.extend(fan.iter().map(|&h| t.face_size(t.he_face(h))));
    edge_w.resize(fan.len(), 0.0);
    far_w.resize(fan.len(), 0.0);
    let wv = subdiv_rules::catmull_clark::limit_stencil(sizes, edge_w, far_w); // Eq. (5)
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

/// V × V limit stencil: row v gives the limit point of vertex v
/// ([`limit_stencil_sharp`] with no tags).
pub fn limit_stencil(t: &Topology) -> SparseMatrix {
    limit_stencil_sharp(t, &LevelSharpness::plain(), t.vertex_count())
}

/// The first `rows` rows of the limit stencil with the rules of `sharp`
/// (each vertex by its rule at this level, [`LevelSharpness::limit_rule`]):
/// exact where no semi-sharp value is left.
pub fn limit_stencil_sharp(t: &Topology, sharp: &LevelSharpness, rows: usize) -> SparseMatrix {
    let nv = t.vertex_count();
    RowBuilder::build_parallel_with_scratch(rows, nv, Summation::InOrder, |i, out, scratch: &mut LimitScratch| {
        limit_row(t, sharp, VertexId(i as u32), out, scratch)
    })
}

/// The limit point of every vertex, `apply(&limit_stencil(t), x)` up to
/// round-off, evaluated row by row without building the stencil.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn limit_points(t: &Topology, x: &[DVec3]) -> Vec<DVec3> {
    limit_points_sharp(t, &LevelSharpness::plain(), x, t.vertex_count())
}

/// The limit points of the first `count` vertices with the rules of `sharp`.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn limit_points_sharp(t: &Topology, sharp: &LevelSharpness, x: &[DVec3], count: usize) -> Vec<DVec3> {
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    RowBuilder::evaluate_parallel_with_scratch(count, x, |i, rows, scratch: &mut LimitScratch| {
        limit_row(t, sharp, VertexId(i as u32), rows, scratch)
    })
}

/// Catmull-Clark as a [`SchemeRules`]: the quad split, OpenSubdiv's crease
/// rules (any tags, any boundary option).
pub(crate) struct CatmullClarkRules;

impl SchemeRules for CatmullClarkRules {
    fn check(&self, _: &Topology, _: &LevelSharpness) -> Result<(), StencilError> {
        Ok(())
    }

    fn split(&self, t: &Topology, sharp: &LevelSharpness) -> Result<LevelSplit, StencilError> {
        let topology = quad_split(t);
        // The half of h's edge at from(h) is corner 0 of quad h: half-edge 4h.
        let sharpness = sharp.refine(t, &topology, |h| 4 * h);
        Ok(LevelSplit { topology, sharpness, dual: None })
    }

    fn stencil(&self, t: &Topology, sharp: &LevelSharpness) -> Result<Option<SparseMatrix>, StencilError> {
        Ok(Some(refinement_stencil_sharp(t, sharp)))
    }

    fn step_points(&self, t: &Topology, sharp: &LevelSharpness, x: &[DVec3]) -> Result<Vec<DVec3>, StencilError> {
        Ok(step_points_sharp(t, sharp, x))
    }

    fn limit_points(
        &self,
        t: &Topology,
        sharp: &LevelSharpness,
        x: &[DVec3],
        count: usize,
    ) -> Option<Result<Vec<DVec3>, StencilError>> {
        Some(Ok(limit_points_sharp(t, sharp, x, count)))
    }

    fn limit_stencil(
        &self,
        t: &Topology,
        sharp: &LevelSharpness,
        rows: usize,
    ) -> Option<Result<SparseMatrix, StencilError>> {
        Some(Ok(limit_stencil_sharp(t, sharp, rows)))
    }
}
