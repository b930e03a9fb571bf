//! √3 operators (Kobbelt 2000): the refinement stencil R of a plain or a
//! boundary-trisecting step, and the limit stencil.
//!
//! Rules: `subdiv_rules::sqrt3` (face points, αₙ, the ternary cubic
//! B-spline boundary, βₙ). Connectivity and numbering:
//! [`subdiv_mesh::refine::sqrt3_split`] — old vertices, one point per old
//! triangle, then (trisecting) the second trisection point of every boundary
//! edge; row i of R is new vertex i.
//!
//! # Which step trisects
//!
//! Counting the first step on the input as step 1, the odd steps are plain:
//! every triangle gets its centroid, boundary edges are kept (not flipped)
//! and boundary vertices do not move. The even steps trisect the boundary
//! (Kobbelt §4): the triangle of each boundary edge a─b (after an odd step
//! there is exactly one boundary edge per such triangle, opposite its
//! centroid x of the odd step) gets the two trisection points p, q instead of
//! a centroid and is split into (a, p, x), (p, q, x), (q, b, x); then every
//! old interior edge is flipped, x─a and x─b included, so a─p and q─b end in
//! triangles with the neighbouring faces' points:
//!
//! ```text
//!   level 0 (odd step next)    level 1 (even step next)     level 2
//!          c                          c                          c
//!        ╱   ╲                      ╱ │ ╲                    ╱ ╱ │ ╲ ╲
//!      ╱       ╲                  ╱   x   ╲                ·  ╱  x  ╲  ·
//!    ╱           ╲              ╱  ╱     ╲  ╲             ╱ ╱ ╱   ╲ ╲ ╲
//!   a ─────────── b            a ─────────── b           a ─ p ───── q ─ b
//! ```
//!
//! A level records whether its next step trisects
//! (`LevelSharpness::trisects_next`): every plan, `subdivide` call and limit
//! starts from an odd step, so subdividing a √3 mesh of one level again by
//! one level is not the same as two levels at once (on open meshes).
//!
//! # Limit points
//!
//! - Boundary vertices: (p₋ + 4p + p₊)/6 at both parities: an odd step
//!   leaves the boundary polygon as it is, an even step refines it with the
//!   ternary cubic B-spline, so every level's boundary polygon is a control
//!   polygon of one uniform cubic B-spline.
//! - Interior vertices: (1 − βₙ)p + βₙ/n Σpᵢ, exact when the vertex's
//!   neighbours after the next step are the points of its triangles (then
//!   the step acts on (p, q̄) by a fixed 2 × 2 matrix, `subdiv_rules::sqrt3`):
//!   before an odd step always, before an even step unless one of its
//!   triangles has a boundary edge (the x above, which gains p and q and
//!   loses a and b). So on an open mesh before an even step the limit is
//!   taken after one more step ([`SchemeRules::levels_before_limit`] is 1),
//!   which keeps the old vertices' indices.
//!
//! # Corners and tags
//!
//! √3 has no crease rules in the paper. Sharpness tags are refused
//! ([`StencilError::TagsNotSupported`]), except a vertex tag ≥ 10 on a
//! boundary vertex: a corner. Under `edge-and-corner` a boundary vertex in
//! one face is a corner too. A corner stays, and the boundary curve ends
//! there (the phantom-point rule of `subdiv_rules::sqrt3`); as a step gives a
//! corner a second triangle, the refined level carries it as a vertex tag of
//! 10 (which a written mesh keeps). Interior vertices of valence < 3 are
//! refused (the flips would double an edge).

use crate::scheme::{LevelSplit, SchemeRules};
use crate::sharpness::LevelSharpness;
use crate::{RowBuilder, SparseMatrix, StencilError, Summation};
use glam::DVec3;
use subdiv_mesh::refine::{sqrt3_split, Sqrt3Provenance, Sqrt3Vertex};
use subdiv_mesh::{EdgeId, MeshError, Topology, VertexId};
use subdiv_rules::crease::SHARPNESS_INFINITE;
use subdiv_rules::sqrt3::{limit_mask, trisection_mask, vertex_point_mask, FACE_POINT};
use subdiv_rules::{VertexKind, VertexMask};

const NAME: &str = "sqrt3";

/// Whether boundary vertex `v` is a corner: a vertex tag ≥ 10, or one face
/// under `edge-and-corner` ([`LevelSharpness::vertex`]).
fn is_corner(t: &Topology, sharp: &LevelSharpness, v: VertexId) -> bool {
    t.is_boundary_vertex(v) && sharp.vertex(t, v) >= SHARPNESS_INFINITE
}

/// The rule class of `v` at this level: interior, boundary, or corner.
fn kind(t: &Topology, sharp: &LevelSharpness, v: VertexId) -> VertexKind {
    if !t.is_boundary_vertex(v) {
        VertexKind::Interior
    } else if is_corner(t, sharp, v) {
        VertexKind::Corner
    } else {
        VertexKind::Boundary
    }
}

/// Refuses what √3 cannot take: other polygons, edge tags, semi-sharp or
/// interior vertex tags, interior vertices of valence < 3.
///
/// # Errors
/// [`StencilError::NotTriangles`], [`StencilError::TagsNotSupported`],
/// [`StencilError::MeshNotSupported`].
pub fn check(t: &Topology, sharp: &LevelSharpness) -> Result<(), StencilError> {
    crate::loop_subdivision::require_triangles(t)?;
    if !sharp.is_untagged() {
        let tags = sharp.tags(t);
        let edge =
            tags.edge_values().iter().enumerate().find(|&(e, &s)| s > 0.0 && !t.is_boundary_edge(EdgeId(e as u32)));
        if let Some((e, &s)) = edge {
            let (a, b) = t.edge_vertices(EdgeId(e as u32));
            let reason = format!("edge {e} (vertices {a}-{b}) has sharpness {s}, but √3 has no crease rules");
            return Err(StencilError::TagsNotSupported { scheme: NAME, reason });
        }
        for (v, &s) in tags.vertex_values().iter().enumerate() {
            let boundary = t.is_boundary_vertex(VertexId(v as u32));
            if s > 0.0 && (!boundary || s < SHARPNESS_INFINITE) {
                let reason = format!(
                    "vertex {v} has sharpness {s}; √3 takes corners only (sharpness ≥ 10 on a boundary vertex)"
                );
                return Err(StencilError::TagsNotSupported { scheme: NAME, reason });
            }
        }
    }
    if let Some(v) = t.vertices().find(|&v| !t.is_boundary_vertex(v) && !t.is_isolated(v) && t.valence(v) < 3) {
        let reason = format!("interior vertex {v} has valence {}; the √3 flips need valence ≥ 3", t.valence(v));
        return Err(StencilError::MeshNotSupported { scheme: NAME, reason });
    }
    Ok(())
}

/// The numbering of the next step on `t`.
fn provenance(t: &Topology, sharp: &LevelSharpness) -> Result<Sqrt3Provenance, StencilError> {
    Sqrt3Provenance::new(t, sharp.trisects_next()).map_err(mesh_error)
}

fn mesh_error(e: MeshError) -> StencilError {
    match e {
        MeshError::NotTriangles { face, size } => StencilError::NotTriangles { face, size },
        other => StencilError::MeshNotSupported { scheme: NAME, reason: other.to_string() },
    }
}

/// Row `i` of the refinement stencil (numbering of `p`).
fn refinement_row(t: &Topology, sharp: &LevelSharpness, p: &Sqrt3Provenance, i: usize, rows: &mut RowBuilder) {
    match p.origin(VertexId(i as u32)) {
        Sqrt3Vertex::Old(v) => {
            if t.is_isolated(v) {
                rows.add(v.0, 1.0);
                return;
            }
            let kind = kind(t, sharp, v);
            // Kobbelt §3: (1 − αₙ)p + αₙ/n Σpᵢ; §4: boundary (4p₋ + 19p + 4p₊)/27 in an even step, else p.
            add_vertex_mask(t, v, kind, &vertex_point_mask(kind, t.valence(v), p.trisects), rows);
        }
        Sqrt3Vertex::Centroid(f) => {
            for &c in t.face(f) {
                rows.add(c, FACE_POINT); // Kobbelt §2: the face point (a + b + c)/3
            }
        }
        Sqrt3Vertex::Trisection { half_edge, near_start } => {
            let (a, b) = (t.he_from(half_edge), t.he_to(half_edge));
            let (near, far) = if near_start { (a, b) } else { (b, a) };
            let (prev, next) = t.boundary_neighbors(near).expect("a boundary vertex");
            let outer = if near_start { prev } else { next };
            // Kobbelt §4: (p₋ + 16·near + 10·far)/27; a corner's phantom gives (2·near + far)/3.
            let mask = trisection_mask(is_corner(t, sharp, near));
            rows.add(near.0, mask.near);
            rows.add(far.0, mask.far);
            if mask.outer != 0.0 {
                rows.add(outer.0, mask.outer);
            }
        }
    }
}

/// Row `v` of the limit stencil (module docs; exact as they say).
fn limit_row(t: &Topology, sharp: &LevelSharpness, v: VertexId, rows: &mut RowBuilder) {
    if t.is_isolated(v) {
        rows.add(v.0, 1.0);
        return;
    }
    let kind = kind(t, sharp, v);
    // p∞ = (1 − βₙ)p + βₙ/n Σpᵢ; boundary (p₋ + 4p + p₊)/6; corner p
    add_vertex_mask(t, v, kind, &limit_mask(kind, t.valence(v)), rows);
}

/// `mask` at vertex `v` of kind `kind`: its own weight, then the interior neighbours' (all of
/// them) or the boundary neighbours' (the two along the boundary); a corner has its own only.
fn add_vertex_mask(t: &Topology, v: VertexId, kind: VertexKind, mask: &VertexMask, rows: &mut RowBuilder) {
    rows.add(v.0, mask.vertex);
    match kind {
        VertexKind::Interior => t.vertex_neighbors(v).for_each(|n| rows.add(n.0, mask.interior_neighbor)),
        VertexKind::Boundary => {
            let (prev, next) = t.boundary_neighbors(v).expect("a boundary vertex");
            rows.add(prev.0, mask.boundary_neighbor);
            rows.add(next.0, mask.boundary_neighbor);
        }
        VertexKind::Corner => {}
    }
}

/// New × old refinement stencil of the next step of level `t` (plain or
/// trisecting as `sharp` says), on [`sqrt3_split`]'s numbering.
///
/// # Errors
/// As [`check`].
pub fn refinement_stencil(t: &Topology, sharp: &LevelSharpness) -> Result<SparseMatrix, StencilError> {
    check(t, sharp)?;
    let p = provenance(t, sharp)?;
    Ok(RowBuilder::build_parallel(p.vertex_count(), t.vertex_count(), Summation::InOrder, |i, rows| {
        refinement_row(t, sharp, &p, i, rows)
    }))
}

/// The points of the next step, `apply(&refinement_stencil(t, sharp)?, x)`
/// up to round-off, without building the stencil.
///
/// # Errors
/// As [`check`].
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn step_points(t: &Topology, sharp: &LevelSharpness, x: &[DVec3]) -> Result<Vec<DVec3>, StencilError> {
    check(t, sharp)?;
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    let p = provenance(t, sharp)?;
    Ok(RowBuilder::evaluate_parallel_with_scratch(p.vertex_count(), x, |i, rows, _: &mut ()| {
        refinement_row(t, sharp, &p, i, rows)
    }))
}

/// The first `rows` rows of the limit stencil of level `t`: row v the limit
/// point of vertex v, exact where the module docs say (a plan takes one more
/// step first where they are not).
///
/// # Errors
/// As [`check`].
pub fn limit_stencil(t: &Topology, sharp: &LevelSharpness, rows: usize) -> Result<SparseMatrix, StencilError> {
    check(t, sharp)?;
    Ok(RowBuilder::build_parallel(rows, t.vertex_count(), Summation::InOrder, |i, out| {
        limit_row(t, sharp, VertexId(i as u32), out)
    }))
}

/// The limit points of the first `count` vertices, `apply(&limit_stencil(t,
/// sharp, count)?, x)` up to round-off.
///
/// # Errors
/// As [`check`].
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn limit_points(
    t: &Topology,
    sharp: &LevelSharpness,
    x: &[DVec3],
    count: usize,
) -> Result<Vec<DVec3>, StencilError> {
    check(t, sharp)?;
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    Ok(RowBuilder::evaluate_parallel_with_scratch(count, x, |i, rows, _: &mut ()| {
        limit_row(t, sharp, VertexId(i as u32), rows)
    }))
}

/// The sharpness of the level after the next step: the corners carried as
/// vertex tags of 10 (a step gives them a second triangle), the parity
/// flipped.
fn child_sharpness(t: &Topology, sharp: &LevelSharpness, child: &Topology) -> LevelSharpness {
    let mut vertices = Vec::new();
    for v in t.vertices().filter(|&v| is_corner(t, sharp, v)) {
        if vertices.is_empty() {
            vertices = vec![0.0f32; child.vertex_count()];
        }
        vertices[v.index()] = SHARPNESS_INFINITE;
    }
    LevelSharpness::sqrt3_level(vertices, sharp.boundary(), sharp.method(), !sharp.trisects_next())
}

/// √3 as a [`SchemeRules`]: the plain and the trisecting split in turn.
pub(crate) struct Sqrt3Rules;

impl SchemeRules for Sqrt3Rules {
    fn check(&self, t: &Topology, sharp: &LevelSharpness) -> Result<(), StencilError> {
        check(t, sharp)
    }

    fn split(&self, t: &Topology, sharp: &LevelSharpness) -> Result<LevelSplit, StencilError> {
        check(t, sharp)?;
        let (topology, _) = sqrt3_split(t, sharp.trisects_next()).map_err(mesh_error)?;
        let sharpness = child_sharpness(t, sharp, &topology);
        Ok(LevelSplit { topology, sharpness, dual: None })
    }

    fn stencil(&self, t: &Topology, sharp: &LevelSharpness) -> Result<Option<SparseMatrix>, StencilError> {
        refinement_stencil(t, sharp).map(Some)
    }

    fn step_points(&self, t: &Topology, sharp: &LevelSharpness, x: &[DVec3]) -> Result<Vec<DVec3>, StencilError> {
        step_points(t, sharp, x)
    }

    fn limit_points(
        &self,
        t: &Topology,
        sharp: &LevelSharpness,
        x: &[DVec3],
        count: usize,
    ) -> Option<Result<Vec<DVec3>, StencilError>> {
        Some(limit_points(t, sharp, x, count))
    }

    fn limit_stencil(
        &self,
        t: &Topology,
        sharp: &LevelSharpness,
        rows: usize,
    ) -> Option<Result<SparseMatrix, StencilError>> {
        Some(limit_stencil(t, sharp, rows))
    }

    /// One level before an even step on an open mesh (the apexes of the
    /// boundary triangles, module docs), else none: tags never hold
    /// semi-sharp values here.
    fn levels_before_limit(&self, t: &Topology, sharp: &LevelSharpness, _is_base: bool) -> usize {
        usize::from(sharp.trisects_next() && !t.is_closed())
    }
}
