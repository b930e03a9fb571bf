//! The Deng-Ma interpolatory step (report §3.3-3.4, ERRATA D2, D5).
//!
//! At every old vertex P with Doo-Sabin images Qᵢ (one per face) and their
//! centroid G, the moved vertices are Q̄ᵢ = P + ω_P(Qᵢ − G); the new face point
//! of a face is the centroid of its corners' moved vertices, the new edge
//! point of an edge the centroid of the four moved vertices of its E-face, and
//! old vertices stay. Connectivity is Catmull-Clark's
//! ([`subdiv_mesh::refine::quad_split`]), so the numbering of new vertices is
//! the same as [`crate::catmull_clark`]'s.
//!
//! **The exception to "one sparse product".** With a global ω the step is
//! linear and [`stencil`] gives its matrix. The displacement-safe variable ω_P
//! of §3.4 depends on the positions (edge lengths, image spread), so
//! [`step`] evaluates it geometrically, level by level; it cannot be
//! precomputed from topology and re-applied to other data.

use crate::doo_sabin::{refinement_stencil as doo_sabin_stencil, CornerRule};
use crate::{apply, RowBuilder, SparseMatrix, StencilError};
use glam::DVec3;
use subdiv_mesh::refine::quad_split;
use subdiv_mesh::{HalfEdgeId, Topology};
use subdiv_rules::deng_ma::Tension;

pub(crate) fn require_closed(t: &Topology) -> Result<(), StencilError> {
    if t.is_closed() {
        Ok(())
    } else {
        Err(StencilError::NotClosed { scheme: "the Deng-Ma scheme", loops: t.boundary_loop_count() })
    }
}

pub(crate) fn check_tension(tension: Tension) -> Result<(), StencilError> {
    let (name, value) = match tension {
        Tension::Global(w) => ("ω", w),
        Tension::Variable { lambda } => ("λ", lambda),
    };
    if value > 0.0 && value <= 1.0 {
        Ok(())
    } else {
        Err(StencilError::InvalidParameter(format!("Deng-Ma {name} = {value} is outside (0, 1]")))
    }
}

/// The four corners (old half-edge ids) of the E-face of the edge of half-edge `h`.
fn e_face_corners(t: &Topology, h: HalfEdgeId, g: HalfEdgeId) -> [HalfEdgeId; 4] {
    [t.he_next(h), h, t.he_next(g), g]
}

/// One Deng-Ma step on a closed mesh: refined topology and positions.
pub fn step(t: &Topology, positions: &[DVec3], tension: Tension) -> Result<(Topology, Vec<DVec3>), StencilError> {
    let refined = step_positions(t, positions, tension)?;
    Ok((quad_split(t), refined))
}

/// The positions of one Deng-Ma step, numbered as [`quad_split`] numbers the
/// refined vertices (old vertices, face points, edge points).
pub fn step_positions(t: &Topology, positions: &[DVec3], tension: Tension) -> Result<Vec<DVec3>, StencilError> {
    require_closed(t)?;
    check_tension(tension)?;
    // §3.3 step 1: the Doo-Sabin images Q of every corner.
    let images = apply(&doo_sabin_stencil(t, CornerRule::Standard)?, positions);
    // §3.3 step 2: moved images Q̄ = P + ω_P (Q − G) per corner.
    let mut moved = vec![DVec3::ZERO; images.len()];
    let (mut ring, mut qs) = (Vec::new(), Vec::new());
    for v in t.vertices() {
        let fan = t.vertex_fan(v);
        if fan.is_empty() {
            continue;
        }
        let p = positions[v.index()];
        qs.clear();
        qs.extend(fan.iter().map(|h| images[h.index()].to_array()));
        let g = fan.iter().map(|h| images[h.index()]).sum::<DVec3>() / fan.len() as f64;
        let omega = match tension {
            Tension::Global(w) => w,
            Tension::Variable { .. } => {
                ring.clear();
                ring.extend(t.vertex_neighbors(v).map(|e| positions[e.index()].to_array()));
                tension.omega(p.to_array(), &ring, &qs)
            }
        };
        for h in fan {
            moved[h.index()] = p + omega * (images[h.index()] - g); // §3.3 (ERRATA D2): Q̄ = P + ω(Q − G)
        }
    }
    // §3.3 step 3: old vertices, face points, edge points (Catmull-Clark numbering).
    let mut out = Vec::with_capacity(t.vertex_count() + t.face_count() + t.edge_count());
    out.extend_from_slice(positions);
    for f in t.face_ids() {
        out.push(t.face_half_edges(f).map(|h| moved[h.index()]).sum::<DVec3>() / t.face_size(f) as f64);
    }
    for e in t.edges() {
        let h = t.edge_half_edge(e);
        let g = t.he_twin(h).expect("closed mesh");
        out.push(e_face_corners(t, h, g).iter().map(|c| moved[c.index()]).sum::<DVec3>() / 4.0);
    }
    Ok(out)
}

/// The (V + F + E) × V matrix of one step with a global ω (linear case).
pub fn stencil(t: &Topology, omega: f64) -> Result<SparseMatrix, StencilError> {
    require_closed(t)?;
    check_tension(Tension::Global(omega))?;
    let ds = doo_sabin_stencil(t, CornerRule::Standard)?;
    // Row of Q̄_h = P_v + ω(Q_h − G_v), G_v = mean of Q over v's corners.
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
        for &c in fan {
            add_q(rows, c, -scale * omega / fan.len() as f64);
        }
    };
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
        let g = t.he_twin(h).expect("closed mesh");
        for c in e_face_corners(t, h, g) {
            moved_row(c, &mut rows, 0.25);
        }
        rows.finish_row();
    }
    Ok(rows.build(t.vertex_count()))
}
