//! Loop operators: the refinement stencil R and the limit stencil.
//!
//! Rules: `subdiv_rules::loop_scheme` (Deng-Wang Eq. 1-2 and 5-6 with ERRATA
//! W1-W4), Warren's β by default, Loop's original β as an option; boundaries
//! as Catmull-Clark (creases, corners stay).
//!
//! Row order of R is the [`subdiv_mesh::refine::triangle_split`] numbering:
//! old vertices, then edge points.

use crate::catmull_clark::add_boundary_neighbors;
use crate::{vertex_kind, RowBuilder, SparseMatrix, StencilError, Summation};
use glam::DVec3;
use subdiv_mesh::refine::triangle_split;
use subdiv_mesh::{EdgeId, MeshError, Topology, VertexId};
use subdiv_rules::loop_scheme::{edge_point_mask, limit_mask, vertex_point_mask};
use subdiv_rules::{LoopBeta, VertexKind};

pub(crate) fn require_triangles(t: &Topology) -> Result<(), StencilError> {
    match t.face_ids().find(|&f| t.face_size(f) != 3) {
        Some(f) => Err(StencilError::NotTriangles { face: f.0, size: t.face_size(f) }),
        None => Ok(()),
    }
}

/// Adds a vertex-centred Loop mask (vertex point or limit point).
fn add_vertex_mask(rows: &mut RowBuilder, t: &Topology, v: subdiv_mesh::VertexId, mask: subdiv_rules::VertexMask) {
    rows.add(v.0, mask.vertex);
    if vertex_kind(t, v) == VertexKind::Interior {
        for e in t.vertex_neighbors(v) {
            rows.add(e.0, mask.interior_neighbor);
        }
    } else {
        add_boundary_neighbors(rows, t, v, mask.boundary_neighbor);
    }
}

/// (V + E) × V refinement stencil: P₁ = R·P₀ on [`triangle_split`]'s numbering.
pub fn refinement_stencil(t: &Topology, beta: LoopBeta) -> Result<SparseMatrix, StencilError> {
    require_triangles(t)?;
    let (nv, ne) = (t.vertex_count(), t.edge_count());
    Ok(RowBuilder::build_parallel(nv + ne, nv, Summation::InOrder, |i, rows| refinement_row(t, beta, i, rows)))
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
    require_triangles(t)?;
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    let rows = t.vertex_count() + t.edge_count();
    Ok(RowBuilder::evaluate_parallel_with_scratch(rows, x, |i, rows, _: &mut ()| refinement_row(t, beta, i, rows)))
}

/// Row `i` of the refinement stencil: vertex points, then edge points.
fn refinement_row(t: &Topology, beta: LoopBeta, i: usize, rows: &mut RowBuilder) {
    let nv = t.vertex_count();
    if i < nv {
        let v = VertexId(i as u32);
        if t.is_isolated(v) {
            rows.add(v.0, 1.0);
        } else {
            // Eq. (1): p' = (1 − kβ)p + βΣpⱼ; boundary (1, 6, 1)/8; corner p.
            add_vertex_mask(rows, t, v, vertex_point_mask(vertex_kind(t, v), t.valence(v), beta));
        }
        return;
    }
    let h = t.edge_half_edge(EdgeId((i - nv) as u32));
    let twin = t.he_twin(h);
    let mask = edge_point_mask(twin.is_none());
    rows.add(t.he_from(h).0, mask.end);
    rows.add(t.he_to(h).0, mask.end);
    // The opposite corner of a triangle is the start of the half-edge before h.
    rows.add(t.he_from(t.he_prev(h)).0, mask.left);
    if let Some(g) = twin {
        rows.add(t.he_from(t.he_prev(g)).0, mask.right);
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

/// Row v of the limit stencil: interior (1 − kγ)p + γΣpⱼ with
/// γ = 1/(k + 3/(8β)) (Deng-Wang Eq. 5-6, ERRATA W4); boundary
/// (p₋ + 4p + p₊)/6; corner p.
fn limit_row(t: &Topology, v: VertexId, beta: LoopBeta, rows: &mut RowBuilder) {
    if t.is_isolated(v) {
        rows.add(v.0, 1.0);
    } else {
        add_vertex_mask(rows, t, v, limit_mask(vertex_kind(t, v), t.valence(v), beta));
    }
}

/// V × V limit stencil ([`limit_row`]).
///
/// # Errors
/// [`StencilError::NotTriangles`] on a mesh with a non-triangle.
pub fn limit_stencil(t: &Topology, beta: LoopBeta) -> Result<SparseMatrix, StencilError> {
    require_triangles(t)?;
    let nv = t.vertex_count();
    Ok(RowBuilder::build_parallel(nv, nv, Summation::InOrder, |i, rows| limit_row(t, VertexId(i as u32), beta, rows)))
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
    require_triangles(t)?;
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    Ok(RowBuilder::evaluate_parallel_with_scratch(t.vertex_count(), x, |i, rows, _: &mut ()| {
        limit_row(t, VertexId(i as u32), beta, rows)
    }))
}
