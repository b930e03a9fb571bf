//! The Deng-Ma interpolatory step (Deng & Ma 2011 §3.3-3.4, ERRATA D2, D5),
//! on closed and open meshes.
//!
//! At every old vertex P with Doo-Sabin images Qᵢ (one per face) and their
//! centroid G, the moved vertices are Q̄ᵢ = P + ω_P(Qᵢ − G); the new face point
//! of a face is the centroid of its corners' moved vertices, the new edge
//! point of an edge the centroid of the four moved vertices of its E-face, and
//! old vertices stay. Connectivity is Catmull-Clark's
//! ([`subdiv_mesh::refine::quad_split`]), so the numbering of new vertices is
//! the same as [`crate::catmull_clark`]'s.
//!
//! **Open meshes** (our construction; rules and derivation in
//! `subdiv_rules::deng_ma`, "Open meshes"). A boundary vertex in one face is a
//! corner. The new point of a boundary edge is the 4-point point of its
//! boundary piece, ½(Pᵢ + Pᵢ₊₁) + ωᵢ(Pᵢ₊₁ − Pᵢ₋₁) + ωᵢ₊₁(Pᵢ − Pᵢ₊₂) with the
//! curve tension ω_P/16 and the phantom 2P₀ − P₁ beyond a corner P₀, so it
//! reads boundary vertices only. The moved images of a boundary vertex are
//! taken about G = (P₋ + 6P + P₊)/8 (P at a corner) instead of the centroid
//! of its images; face points and interior edge points are then the report's
//! centroids.
//!
//! **The exception to "one sparse product".** With a global ω the step is
//! linear and [`stencil`] gives its matrix. The displacement-safe variable ω_P
//! of §3.4 depends on the positions (edge lengths, image spread), so
//! [`step`] evaluates it geometrically, level by level; it cannot be
//! precomputed from topology and re-applied to other data.

use crate::apply::fill_in_chunks;
use crate::doo_sabin::{first_step, refinement_stencil as doo_sabin_stencil, CornerRule};
use crate::scheme::{SchemeRules, Split};
use crate::sharpness::LevelSharpness;
use crate::{vertex_kind, RowBuilder, SparseMatrix, StencilError};
use glam::DVec3;
use subdiv_mesh::refine::quad_split;
use subdiv_mesh::{EdgeId, FaceId, HalfEdgeId, Topology, VertexId};
use subdiv_rules::deng_ma::{boundary_centre, Tension, BOUNDARY_CENTRE, CURVE_TENSION_PER_OMEGA};
use subdiv_rules::VertexKind;

pub(crate) fn check_tension(tension: Tension) -> Result<(), StencilError> {
    tension.validate().map_err(|e| StencilError::InvalidParameter(e.to_string()))
}

/// Where a vertex sits for the Deng-Ma rules.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Place {
    /// Not on the boundary (or isolated): G is the centroid of its images.
    Interior,
    /// On the boundary in one face: both boundary pieces end here; G = P.
    Corner,
    /// On the boundary in two or more faces, between `prev` and `next` along its loop.
    Boundary { prev: VertexId, next: VertexId },
}

fn place(t: &Topology, v: VertexId) -> Place {
    match vertex_kind(t, v) {
        VertexKind::Interior => Place::Interior,
        VertexKind::Corner => Place::Corner,
        VertexKind::Boundary => {
            let (prev, next) = t.boundary_neighbors(v).expect("a boundary vertex has boundary neighbours");
            Place::Boundary { prev, next }
        }
    }
}

/// The positions of a boundary vertex's neighbours along its loop, as the
/// rules of `subdiv_rules::deng_ma` take them (`None` at a corner).
fn curve_neighbours(place: Place, x: &[DVec3]) -> Option<([f64; 3], [f64; 3])> {
    match place {
        Place::Boundary { prev, next } => Some((x[prev.index()].to_array(), x[next.index()].to_array())),
        _ => None,
    }
}

/// The four corners (old half-edge ids) of the E-face of the edge of half-edge `h`.
fn e_face_corners(t: &Topology, h: HalfEdgeId, g: HalfEdgeId) -> [HalfEdgeId; 4] {
    [t.he_next(h), h, t.he_next(g), g]
}

/// A neighbour of a boundary edge's end on its boundary piece.
#[derive(Clone, Copy, Debug)]
enum Outer {
    /// The end's other neighbour along the loop.
    Vertex(VertexId),
    /// Beyond a corner `end`: the linear phantom 2·end − `other`.
    Phantom { end: VertexId, other: VertexId },
}

impl Outer {
    fn point(self, x: &[DVec3]) -> DVec3 {
        match self {
            Outer::Vertex(v) => x[v.index()],
            Outer::Phantom { end, other } => 2.0 * x[end.index()] - x[other.index()], // P₋₁ = 2P₀ − P₁
        }
    }

    /// Adds `weight` × this point to a row.
    fn add_to(self, rows: &mut RowBuilder, weight: f64) {
        match self {
            Outer::Vertex(v) => rows.add(v.0, weight),
            Outer::Phantom { end, other } => {
                rows.add(end.0, 2.0 * weight);
                rows.add(other.0, -weight);
            }
        }
    }
}

/// The boundary piece around boundary half-edge `h` = a→b: its ends a, b and
/// their outer neighbours a₋ (before a) and b₊ (after b). A corner ends the
/// piece, and beyond it stands the linear phantom 2a − b (or 2b − a), the open
/// end rule of `subdiv_rules::curves::four_point`.
fn curve_stencil(t: &Topology, h: HalfEdgeId) -> (VertexId, VertexId, Outer, Outer) {
    let (a, b) = (t.he_from(h), t.he_to(h));
    let outer = |end: VertexId, other: VertexId, before: bool| match place(t, end) {
        Place::Boundary { prev, next } => Outer::Vertex(if before { prev } else { next }),
        _ => Outer::Phantom { end, other },
    };
    (a, b, outer(a, b, true), outer(b, a, false))
}

/// One Deng-Ma step: refined topology and positions.
pub fn step(t: &Topology, positions: &[DVec3], tension: Tension) -> Result<(Topology, Vec<DVec3>), StencilError> {
    let refined = step_positions(t, positions, tension)?;
    Ok((quad_split(t), refined))
}

/// The positions of one Deng-Ma step, numbered as [`quad_split`] numbers the
/// refined vertices (old vertices, face points, edge points). Old vertices
/// are copied bit for bit.
///
/// # Errors
/// [`StencilError::InvalidParameter`] for ω or λ outside (0, 1].
///
/// # Panics
/// If `positions.len()` differs from the vertex count (a caller bug).
pub fn step_positions(t: &Topology, positions: &[DVec3], tension: Tension) -> Result<Vec<DVec3>, StencilError> {
    check_tension(tension)?;
    assert_eq!(positions.len(), t.vertex_count(), "one point per vertex");
    // §3.3 step 1: the Doo-Sabin images Q of every corner (the first H points
    // of a Doo-Sabin step; its boundary Chaikin points are not used).
    let images = first_step(t, CornerRule::Standard, positions)?;
    // §3.3 step 2, per vertex: the centre G, ω_P and (on the boundary) the
    // curve tension; then the moved images Q̄ = P + ω_P (Q − G) per corner.
    let mut centres = vec![Centre::default(); t.vertex_count()];
    fill_in_chunks(&mut centres, |first, chunk| {
        let mut scratch = (Vec::new(), Vec::new());
        for (k, c) in chunk.iter_mut().enumerate() {
            *c = centre(t, VertexId((first + k) as u32), positions, &images, tension, &mut scratch);
        }
    });
    let mut moved = vec![DVec3::ZERO; t.half_edge_count()];
    fill_in_chunks(&mut moved, |first, chunk| {
        for (k, m) in chunk.iter_mut().enumerate() {
            let h = first + k;
            let v = t.he_from(HalfEdgeId(h as u32)).index();
            let c = centres[v];
            *m = positions[v] + c.omega * (images[h] - c.g); // §3.3 (ERRATA D2): Q̄ = P + ω(Q − G)
        }
    });
    // §3.3 step 3: old vertices, face points, edge points (Catmull-Clark numbering).
    let (nv, nf) = (t.vertex_count(), t.face_count());
    let mut out = vec![DVec3::ZERO; nv + nf + t.edge_count()];
    let (old, new) = out.split_at_mut(nv);
    old.copy_from_slice(positions);
    let (face_points, edge_points) = new.split_at_mut(nf);
    fill_in_chunks(face_points, |first, chunk| {
        for (k, point) in chunk.iter_mut().enumerate() {
            let f = FaceId((first + k) as u32);
            *point = t.face_half_edges(f).map(|h| moved[h.index()]).sum::<DVec3>() / t.face_size(f) as f64;
        }
    });
    fill_in_chunks(edge_points, |first, chunk| {
        for (k, point) in chunk.iter_mut().enumerate() {
            let h = t.edge_half_edge(EdgeId((first + k) as u32));
            *point = match t.he_twin(h) {
                Some(g) => e_face_corners(t, h, g).iter().map(|c| moved[c.index()]).sum::<DVec3>() / 4.0,
                None => boundary_edge_point(t, h, positions, tension, &centres),
            };
        }
    });
    Ok(out)
}

/// What the moved images of a vertex need: the centre G, ω_P, and on the
/// boundary the vertex's 4-point tension on its boundary curve (0 inside).
#[derive(Clone, Copy, Debug, Default)]
struct Centre {
    g: DVec3,
    omega: f64,
    curve_tension: f64,
}

/// The [`Centre`] of vertex `v`; `scratch` holds its neighbours and images
/// for the variable tension.
fn centre(
    t: &Topology,
    v: VertexId,
    positions: &[DVec3],
    images: &[DVec3],
    tension: Tension,
    (ring, qs): &mut (Vec<[f64; 3]>, Vec<[f64; 3]>),
) -> Centre {
    let fan = t.vertex_fan(v);
    if fan.is_empty() {
        return Centre::default(); // isolated: no corners, nothing moves
    }
    let p = positions[v.index()];
    let mut gather = || {
        ring.clear();
        ring.extend(t.vertex_neighbors(v).map(|e| positions[e.index()].to_array()));
        qs.clear();
        qs.extend(fan.iter().map(|h| images[h.index()].to_array()));
    };
    let at = place(t, v);
    if at == Place::Interior {
        let g = fan.iter().map(|h| images[h.index()]).sum::<DVec3>() / fan.len() as f64; // §3.3: G = ΣQᵢ/m
        let omega = match tension {
            Tension::Global(w) => w,
            Tension::Variable { .. } => {
                gather();
                tension.omega(p.to_array(), ring, qs)
            }
        };
        return Centre { g, omega, curve_tension: 0.0 };
    }
    let neighbours = curve_neighbours(at, positions);
    let g = boundary_centre(p.to_array(), neighbours); // open meshes: G = (P₋ + 6P + P₊)/8, P at a corner
    let omega = match tension {
        Tension::Global(w) => w,
        Tension::Variable { .. } => {
            gather();
            tension.boundary_omega(p.to_array(), neighbours, ring, qs, g)
        }
    };
    Centre { g: DVec3::from_array(g), omega, curve_tension: tension.curve_tension(p.to_array(), neighbours) }
}

/// The new point of boundary half-edge `h`: the 4-point rule along its
/// boundary piece (Deng-Ma §3.1 step 4, §3.1.1 with ERRATA D1), with the
/// phantom beyond a corner.
fn boundary_edge_point(
    t: &Topology,
    h: HalfEdgeId,
    positions: &[DVec3],
    tension: Tension,
    centres: &[Centre],
) -> DVec3 {
    let (a, b, before, after) = curve_stencil(t, h);
    let (pa, pb) = (positions[a.index()], positions[b.index()]);
    let (before, after) = (before.point(positions), after.point(positions));
    let (wa, wb) = (centres[a.index()].curve_tension, centres[b.index()].curve_tension);
    match tension {
        // (½+ω)(Pᵢ + Pᵢ₊₁) − ω(Pᵢ₋₁ + Pᵢ₊₂), evaluated as `curves::four_point` does.
        Tension::Global(_) => (0.5 + wa) * (pa + pb) + (-wa) * (before + after),
        // ½(Pᵢ + Pᵢ₊₁) + ωᵢ(Pᵢ₊₁ − Pᵢ₋₁) + ωᵢ₊₁(Pᵢ − Pᵢ₊₂), as `curves::four_point_variable`.
        Tension::Variable { .. } => (0.5 * pa + 0.5 * pb) + (wa * (pb - before) + wb * (pa - after)),
    }
}

/// The (V + F + E) × V matrix of one step with a global ω (linear case), on
/// closed and open meshes: `apply(&stencil(t, ω)?, x)` equals
/// `step_positions(t, x, Tension::Global(ω))` up to round-off.
///
/// # Errors
/// [`StencilError::InvalidParameter`] for ω outside (0, 1].
pub fn stencil(t: &Topology, omega: f64) -> Result<SparseMatrix, StencilError> {
    check_tension(Tension::Global(omega))?;
    let ds = doo_sabin_stencil(t, CornerRule::Standard)?;
    // Row of Q̄_h = P_v + ω(Q_h − G_v): G_v the mean of Q over v's corners
    // inside, (P₋ + 6P + P₊)/8 on the boundary, P at a corner.
    let moved_row = |h: HalfEdgeId, rows: &mut RowBuilder, scale: f64| {
        let v = t.he_from(h);
        let fan = t.vertex_fan(v);
        rows.add(v.0, scale);
        let add_q = |rows: &mut RowBuilder, c: HalfEdgeId, w: f64| {
            let row = ds.outer_view(c.index()).expect("corner row");
            for (col, &x) in row.iter() {
                rows.add(col as u32, w * x);
            }
        };
        add_q(rows, h, scale * omega);
        match place(t, v) {
            Place::Interior => {
                for &c in fan {
                    add_q(rows, c, -scale * omega / fan.len() as f64);
                }
            }
            Place::Corner => rows.add(v.0, -scale * omega),
            Place::Boundary { prev, next } => {
                for (u, w) in [prev, v, next].into_iter().zip(BOUNDARY_CENTRE) {
                    rows.add(u.0, -scale * omega * w);
                }
            }
        }
    };
    let w = CURVE_TENSION_PER_OMEGA * omega;
    let mut rows = RowBuilder::with_capacity(t.vertex_count() + t.face_count() + t.edge_count(), 0);
    for v in t.vertices() {
        rows.add(v.0, 1.0);
        rows.finish_row();
    }
    for f in t.face_ids() {
        let m = t.face_size(f) as f64;
        for h in t.face_half_edges(f) {
            moved_row(h, &mut rows, 1.0 / m);
        }
        rows.finish_row();
    }
    for e in t.edges() {
        let h = t.edge_half_edge(e);
        match t.he_twin(h) {
            Some(g) => {
                for c in e_face_corners(t, h, g) {
                    moved_row(c, &mut rows, 0.25);
                }
            }
            None => {
                // (½+ω)(Pᵢ + Pᵢ₊₁) − ω(Pᵢ₋₁ + Pᵢ₊₂), phantoms expanded.
                let (a, b, before, after) = curve_stencil(t, h);
                rows.add(a.0, 0.5 + w);
                rows.add(b.0, 0.5 + w);
                before.add_to(&mut rows, -w);
                after.add_to(&mut rows, -w);
            }
        }
        rows.finish_row();
    }
    Ok(rows.build(t.vertex_count()))
}

/// Deng-Ma as a [`SchemeRules`]: the quad split, evaluated geometrically
/// (no stencil, no limit masks: the scheme interpolates). No tags.
pub(crate) struct DengMaRules(pub(crate) Tension);

impl SchemeRules for DengMaRules {
    fn check(&self, _: &Topology, sharp: &LevelSharpness) -> Result<(), StencilError> {
        check_tension(self.0)?;
        if sharp.is_untagged() {
            Ok(())
        } else {
            Err(StencilError::TagsNotSupported {
                scheme: "deng-ma",
                reason: "the interpolatory scheme has no crease rules".into(),
            })
        }
    }

    fn split(&self, t: &Topology, sharp: &LevelSharpness) -> Result<Split, StencilError> {
        self.check(t, sharp)?;
        Ok(Split { topology: quad_split(t), sharpness: sharp.clone(), dual: None })
    }

    fn stencil(&self, t: &Topology, sharp: &LevelSharpness) -> Result<Option<SparseMatrix>, StencilError> {
        // Evaluated geometrically even for a global ω: its matrix
        // (`stencil`) is dense-ish (every moved vertex expands over all
        // corners around its vertex) and measured 3-4× slower to build and
        // apply than the direct step.
        self.check(t, sharp).map(|()| None)
    }

    fn step_points(&self, t: &Topology, sharp: &LevelSharpness, x: &[DVec3]) -> Result<Vec<DVec3>, StencilError> {
        self.check(t, sharp)?;
        step_positions(t, x, self.0)
    }

    fn limit_points(
        &self,
        _: &Topology,
        _: &LevelSharpness,
        _: &[DVec3],
        _: usize,
    ) -> Option<Result<Vec<DVec3>, StencilError>> {
        None
    }

    fn limit_stencil(&self, _: &Topology, _: &LevelSharpness, _: usize) -> Option<Result<SparseMatrix, StencilError>> {
        None
    }

    fn levels_before_limit(&self, _: &Topology, _: &LevelSharpness, _: bool) -> usize {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::apply;
    use subdiv_mesh::shapes;

    fn open_meshes() -> Vec<(&'static str, subdiv_mesh::Mesh)> {
        let plate = shapes::plate_with_holes(6, 5, &[(2, 2)], false);
        vec![
            ("quad grid 4×3", shapes::quad_grid(4, 3)),
            ("triangle grid 3×3", shapes::triangle_grid(3, 3)),
            ("plate with a hole", plate.clone()),
            ("plate mix", shapes::polygon_mix(&plate, 7, 0.3, 0.3, 0.2)),
            ("one quad", shapes::quad_grid(1, 1)),
        ]
    }

    #[test]
    fn stencil_equals_the_step_on_open_meshes() {
        for (name, mesh) in open_meshes() {
            let t = mesh.topology();
            // Heights make the data non-planar.
            let x: Vec<DVec3> =
                mesh.positions().iter().map(|p| *p + DVec3::Z * (p.x * 1.3 - p.y * p.y * 0.2).sin()).collect();
            for omega in [1.0, 0.5, 0.125] {
                let r = stencil(t, omega).unwrap();
                let linear = apply(&r, &x);
                let geometric = step_positions(t, &x, Tension::Global(omega)).unwrap();
                let worst = linear.iter().zip(&geometric).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
                assert!(worst <= 1e-14, "{name} ω = {omega}: stencil and step differ by {worst:e}");
                // Affine: every row sums to one.
                assert!(crate::row_sums(&r).iter().all(|s| (s - 1.0).abs() < 1e-14), "{name}");
            }
        }
    }

    #[test]
    fn boundary_edge_points_read_boundary_vertices_only() {
        for (name, mesh) in open_meshes() {
            let t = mesh.topology();
            let r = stencil(t, 1.0).unwrap();
            let base = t.vertex_count() + t.face_count();
            for e in t.edges().filter(|&e| t.is_boundary_edge(e)) {
                let row = r.outer_view(base + e.index()).unwrap();
                for (col, _) in row.iter() {
                    assert!(t.is_boundary_vertex(VertexId(col as u32)), "{name}: edge {e:?} reads vertex {col}");
                }
            }
        }
    }
}
