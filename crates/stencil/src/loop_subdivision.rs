//! Loop operators: the refinement stencil R and the limit stencil.
//!
//! Rules: `subdiv_rules::loop_scheme` (Deng-Wang Eq. 1-2 and 5-6 with
//! [corrections W1-W4]), Warren's β by default, Loop's original β as an option; boundaries
//! as Catmull-Clark (creases, corners stay).
//!
//! Row order of R is the [`subdiv_mesh::refine::triangle_split`] numbering:
//! old vertices, then edge points.
//!
//! [corrections W1-W4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w1

use crate::scheme::{LevelSplit, SchemeRules};
use crate::sharpness::{EdgeStep, LevelSharpness};
use crate::{RowBuilder, SparseMatrix, StencilError, Summation};
use glam::DVec3;
use subdiv_mesh::refine::triangle_split;
use subdiv_mesh::{EdgeId, MeshError, Topology, VertexId};
use subdiv_rules::loop_scheme::{dart_limit_mask, edge_point_mask, limit_mask, vertex_point_mask};
use subdiv_rules::{LoopBeta, Rule, VertexKind, VertexMask};

pub(crate) fn require_triangles(t: &Topology) -> Result<(), StencilError> {
    match t.face_ids().find(|&f| t.face_size(f) != 3) {
        Some(f) => Err(StencilError::NotTriangles { face: f.0, size: t.face_size(f) }),
        None => Ok(()),
    }
}

/// Adds a vertex-centred Loop mask of `rule` (vertex point or limit point),
/// times `scale`: smooth masks over the neighbours, crease masks along the
/// two sharp edges (`ends`), corners the point itself.
fn add_vertex_mask(
    rows: &mut RowBuilder,
    t: &Topology,
    v: VertexId,
    (rule, ends): (Rule, Option<(VertexId, VertexId)>),
    mask: impl Fn(VertexKind) -> VertexMask,
    scale: f64,
) {
    match (rule, ends) {
        (Rule::Smooth | Rule::Dart, _) => {
            let mask = mask(VertexKind::Interior);
            rows.add(v.0, scale * mask.vertex);
            for e in t.vertex_neighbors(v) {
                rows.add(e.0, scale * mask.interior_neighbor);
            }
        }
        (Rule::Crease, Some((a, b))) => {
            let mask = mask(VertexKind::Boundary);
            rows.add(v.0, scale * mask.vertex);
            rows.add(b.0, scale * mask.boundary_neighbor);
            rows.add(a.0, scale * mask.boundary_neighbor);
        }
        (Rule::Corner, _) | (Rule::Crease, None) => rows.add(v.0, scale),
    }
}

/// (V + E) × V refinement stencil: P₁ = R·P₀ on [`triangle_split`]'s numbering.
pub fn refinement_stencil(t: &Topology, beta: LoopBeta) -> Result<SparseMatrix, StencilError> {
    refinement_stencil_sharp(t, &LevelSharpness::plain(), beta)
}

/// [`refinement_stencil`] with the creases, corners and boundary option of `sharp`.
pub fn refinement_stencil_sharp(
    t: &Topology,
    sharp: &LevelSharpness,
    beta: LoopBeta,
) -> Result<SparseMatrix, StencilError> {
    require_triangles(t)?;
    let (nv, ne) = (t.vertex_count(), t.edge_count());
    Ok(RowBuilder::build_parallel(nv + ne, nv, Summation::InOrder, |i, rows| refinement_row(t, sharp, beta, i, rows)))
}

/// The points of one Loop step, `apply(&refinement_stencil(t, beta)?, x)` up
/// to round-off, evaluated row by row without building the stencil.
///
/// # Errors
/// [`StencilError::NotTriangles`] on a mesh with a non-triangle.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn step_points(t: &Topology, beta: LoopBeta, x: &[DVec3]) -> Result<Vec<DVec3>, StencilError> {
    step_points_sharp(t, &LevelSharpness::plain(), beta, x)
}

/// [`step_points`] with the creases, corners and boundary option of `sharp`.
///
/// # Errors
/// [`StencilError::NotTriangles`] on a mesh with a non-triangle.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn step_points_sharp(
    t: &Topology,
    sharp: &LevelSharpness,
    beta: LoopBeta,
    x: &[DVec3],
) -> Result<Vec<DVec3>, StencilError> {
    require_triangles(t)?;
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    let rows = t.vertex_count() + t.edge_count();
    Ok(RowBuilder::evaluate_parallel_with_scratch(rows, x, |i, rows, _: &mut ()| {
        refinement_row(t, sharp, beta, i, rows)
    }))
}

/// Row `i` of the refinement stencil: vertex points, then edge points.
fn refinement_row(t: &Topology, sharp: &LevelSharpness, beta: LoopBeta, i: usize, rows: &mut RowBuilder) {
    let nv = t.vertex_count();
    if i < nv {
        let v = VertexId(i as u32);
        if t.is_isolated(v) {
            rows.add(v.0, 1.0);
            return;
        }
        // Eq. (1): p' = (1 − kβ)p + βΣpⱼ; crease (1, 6, 1)/8; corner p;
        // w·parent + (1 − w)·child where the rule changes (semi-sharp).
        let mask = |kind| vertex_point_mask(kind, t.valence(v), beta);
        for (rule, ends, w) in sharp.vertex_step(t, v).masks() {
            add_vertex_mask(rows, t, v, (rule, ends), mask, w);
        }
        return;
    }
    let e = EdgeId((i - nv) as u32);
    let (a, b) = t.edge_vertices(e);
    let smooth = |rows: &mut RowBuilder, scale: f64| {
        let h = t.edge_half_edge(e);
        let twin = t.he_twin(h);
        let mask = edge_point_mask(twin.is_none());
        rows.add(a.0, scale * mask.end);
        rows.add(b.0, scale * mask.end);
        // The opposite corner of a triangle is the start of the half-edge before h.
        rows.add(t.he_from(t.he_prev(h)).0, scale * mask.left);
        if let Some(g) = twin {
            rows.add(t.he_from(t.he_prev(g)).0, scale * mask.right);
        }
    };
    let midpoint = |rows: &mut RowBuilder, scale: f64| {
        rows.add(a.0, scale * 0.5);
        rows.add(b.0, scale * 0.5);
    };
    match sharp.edge_step(t, e) {
        EdgeStep::Smooth => smooth(rows, 1.0),
        EdgeStep::Midpoint if t.is_boundary_edge(e) => smooth(rows, 1.0), // the boundary mask is the midpoint
        EdgeStep::Midpoint => midpoint(rows, 1.0),
        EdgeStep::Blend(s) => {
            midpoint(rows, s);
            smooth(rows, 1.0 - s);
        }
    }
}

/// One Loop step: the refined topology and its stencil.
pub fn refine(t: &Topology, beta: LoopBeta) -> Result<(Topology, SparseMatrix), StencilError> {
    let stencil = refinement_stencil(t, beta)?;
    let topology = triangle_split(t).map_err(|e| match e {
        MeshError::NotTriangles { face, size } => StencilError::NotTriangles { face, size },
        _ => unreachable!("triangle_split only rejects non-triangles"),
    })?;
    Ok((topology, stencil))
}

/// Row v of the limit stencil by the vertex's rule at this level: smooth
/// (1 − kγ)p + γΣpⱼ with γ = 1/(k + 3/(8β)) (Deng-Wang Eq. 5-6,
/// [correction W4]); a dart whose edge is infinitely sharp, under
/// [`DartLimit::Exact`] ([`LevelSharpness::exact_dart_edge`]): its exact
/// limit, [`dart_limit_mask`] (the dominant left eigenvector of its 1-ring's
/// subdivision matrix, E₀ the crease's far end); other darts (a semi-sharp
/// edge, or [`DartLimit::SmoothMask`], OpenSubdiv's `Limit`): the smooth
/// mask; crease (p₋ + 4p + p₊)/6 along its sharp edges; corner p. Exact
/// where no semi-sharp value is left around v.
///
/// [correction W4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w4
/// [`DartLimit::Exact`]: subdiv_rules::DartLimit::Exact
/// [`DartLimit::SmoothMask`]: subdiv_rules::DartLimit::SmoothMask
fn limit_row(t: &Topology, sharp: &LevelSharpness, v: VertexId, beta: LoopBeta, rows: &mut RowBuilder) {
    if t.is_isolated(v) {
        rows.add(v.0, 1.0);
        return;
    }
    let rule = sharp.limit_rule(t, v);
    if rule.0 == Rule::Dart {
        if let Some(crease) = sharp.exact_dart_edge(t, v) {
            let fan = t.vertex_fan(v);
            let mask = dart_limit_mask(fan.len(), beta);
            rows.add(v.0, mask.vertex);
            for (i, &w) in mask.edge.iter().enumerate() {
                rows.add(t.he_to(fan[(crease + i) % fan.len()]).0, w); // Eᵢ, E₀ at the crease
            }
            return;
        }
    }
    add_vertex_mask(rows, t, v, rule, |kind| limit_mask(kind, t.valence(v), beta), 1.0);
}

/// V × V limit stencil: row v gives the limit point of vertex v
/// ([`limit_stencil_sharp`] with no tags).
///
/// # Errors
/// [`StencilError::NotTriangles`] on a mesh with a non-triangle.
pub fn limit_stencil(t: &Topology, beta: LoopBeta) -> Result<SparseMatrix, StencilError> {
    limit_stencil_sharp(t, &LevelSharpness::plain(), beta, t.vertex_count())
}

/// The first `rows` rows of the limit stencil with the rules of `sharp`.
///
/// # Errors
/// [`StencilError::NotTriangles`] on a mesh with a non-triangle.
pub fn limit_stencil_sharp(
    t: &Topology,
    sharp: &LevelSharpness,
    beta: LoopBeta,
    rows: usize,
) -> Result<SparseMatrix, StencilError> {
    require_triangles(t)?;
    let nv = t.vertex_count();
    Ok(RowBuilder::build_parallel(rows, nv, Summation::InOrder, |i, out| {
        limit_row(t, sharp, VertexId(i as u32), beta, out)
    }))
}

/// The limit point of every vertex, `apply(&limit_stencil(t, beta)?, x)` up
/// to round-off, evaluated row by row without building the stencil.
///
/// # Errors
/// [`StencilError::NotTriangles`] on a mesh with a non-triangle.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn limit_points(t: &Topology, beta: LoopBeta, x: &[DVec3]) -> Result<Vec<DVec3>, StencilError> {
    limit_points_sharp(t, &LevelSharpness::plain(), beta, x, t.vertex_count())
}

/// The limit points of the first `count` vertices with the rules of `sharp`.
///
/// # Errors
/// [`StencilError::NotTriangles`] on a mesh with a non-triangle.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn limit_points_sharp(
    t: &Topology,
    sharp: &LevelSharpness,
    beta: LoopBeta,
    x: &[DVec3],
    count: usize,
) -> Result<Vec<DVec3>, StencilError> {
    require_triangles(t)?;
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    Ok(RowBuilder::evaluate_parallel_with_scratch(count, x, |i, rows, _: &mut ()| {
        limit_row(t, sharp, VertexId(i as u32), beta, rows)
    }))
}

/// Loop as a [`SchemeRules`]: the triangle split, OpenSubdiv's crease rules
/// (any tags, any boundary option), Warren's or Loop's β.
pub(crate) struct LoopRules(pub(crate) LoopBeta);

impl SchemeRules for LoopRules {
    fn check(&self, t: &Topology, _: &LevelSharpness) -> Result<(), StencilError> {
        require_triangles(t)
    }

    fn split(&self, t: &Topology, sharp: &LevelSharpness) -> Result<LevelSplit, StencilError> {
        let topology = triangle_split(t).map_err(|e| match e {
            MeshError::NotTriangles { face, size } => StencilError::NotTriangles { face, size },
            _ => unreachable!("triangle_split only rejects non-triangles"),
        })?;
        // The half of h = 3f + k's edge at from(h) is corner 0 of child triangle 4f + k.
        let sharpness = sharp.refine(t, &topology, |h| 3 * (4 * (h / 3) + h % 3));
        Ok(LevelSplit { topology, sharpness, dual: None })
    }

    fn stencil(&self, t: &Topology, sharp: &LevelSharpness) -> Result<Option<SparseMatrix>, StencilError> {
        refinement_stencil_sharp(t, sharp, self.0).map(Some)
    }

    fn step_points(&self, t: &Topology, sharp: &LevelSharpness, x: &[DVec3]) -> Result<Vec<DVec3>, StencilError> {
        step_points_sharp(t, sharp, self.0, x)
    }

    fn limit_points(
        &self,
        t: &Topology,
        sharp: &LevelSharpness,
        x: &[DVec3],
        count: usize,
    ) -> Option<Result<Vec<DVec3>, StencilError>> {
        Some(limit_points_sharp(t, sharp, self.0, x, count))
    }

    fn limit_stencil(
        &self,
        t: &Topology,
        sharp: &LevelSharpness,
        rows: usize,
    ) -> Option<Result<SparseMatrix, StencilError>> {
        Some(limit_stencil_sharp(t, sharp, self.0, rows))
    }
}
