//! Doo-Sabin operators: the refinement stencil R of the standard step and of
//! the first-step variants, and the limit stencil.
//!
//! Corner rule: Zheng-Cai Eq. 1 (standard), Eq. 4 (V' = (V + A)/2) or the
//! two-phase Eq. 1 of Fan-Cheng-Lai (V' = λ_f V + (1 − λ_f)A, one λ per face),
//! all from `subdiv_rules`. Boundary: every boundary edge a→b gets the two
//! Chaikin points ¾a + ¼b and ¼a + ¾b, and the faces of
//! [`subdiv_mesh::refine::dual_split`] close them, so the boundary converges to
//! the quadratic B-spline of the boundary polygon (rule and its justification:
//! `subdiv_rules::doo_sabin`, "Boundary rule").
//!
//! Row order of R is [`dual_split`]'s numbering: one row per old corner
//! (= old half-edge id), then two per boundary half-edge.

use crate::apply::fill_in_chunks;
use crate::{RowBuilder, SparseMatrix, StencilError, Summation};
use glam::DVec3;
use subdiv_mesh::refine::{dual_split, DualProvenance};
use subdiv_mesh::{FaceId, HalfEdgeId, Topology, VertexId};
use subdiv_rules::doo_sabin::{BOUNDARY_CURVE_POINT, BOUNDARY_EDGE_POINT, VALENCE_TWO_LIMIT};
use subdiv_rules::{doo_sabin_weights, two_phase_weights};

/// Which corner rule the step uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CornerRule<'a> {
    /// Standard Doo-Sabin weights (Zheng-Cai Eq. 1).
    Standard,
    /// V' = λV + (1 − λ)A with one λ ∈ (0, 1) for every face (λ = ½ is
    /// Zheng-Cai Eq. 4).
    Uniform(f64),
    /// V' = λ_f V + (1 − λ_f)A with λ_f per face (Fan-Cheng-Lai Eq. 1).
    PerFace(&'a [f64]),
}

impl CornerRule<'_> {
    /// Fills `out` with the row of a face of size `out.len()`.
    pub(crate) fn weights(&self, face: usize, out: &mut [f64]) {
        let m = out.len();
        match *self {
            CornerRule::Standard => doo_sabin_weights(m, out), // Zheng-Cai Eq. (1)
            CornerRule::Uniform(lambda) => two_phase_weights(m, lambda, out), // Eq. (4) / Fan Eq. (1)
            CornerRule::PerFace(lambdas) => two_phase_weights(m, lambdas[face], out), // Fan Eq. (1)
        }
    }

    /// Checks the parameters against the mesh: λ ∈ (0, 1), one per face.
    pub fn validate(&self, t: &Topology) -> Result<(), StencilError> {
        let check = |face: Option<usize>, l: f64| {
            if l > 0.0 && l < 1.0 {
                Ok(())
            } else {
                let at = face.map(|f| format!(" of face {f}")).unwrap_or_default();
                Err(StencilError::InvalidParameter(format!("λ{at} = {l} is outside (0, 1)")))
            }
        };
        match *self {
            CornerRule::Standard => Ok(()),
            CornerRule::Uniform(l) => check(None, l),
            CornerRule::PerFace(ls) if ls.len() != t.face_count() => {
                Err(StencilError::InvalidParameter(format!("{} λ values for {} faces", ls.len(), t.face_count())))
            }
            CornerRule::PerFace(ls) => ls.iter().enumerate().try_for_each(|(f, &l)| check(Some(f), l)),
        }
    }
}

/// (H + 2B) × V refinement stencil on [`dual_split`]'s numbering (H corners,
/// B boundary half-edges).
pub fn refinement_stencil(t: &Topology, rule: CornerRule<'_>) -> Result<SparseMatrix, StencilError> {
    rule.validate(t)?;
    let nh = t.half_edge_count();
    let boundary: Vec<HalfEdgeId> = t.boundary_loops().flatten().copied().collect();
    // The scratch keeps the weights of the last face seen: its corners' rows are consecutive.
    type Scratch = (Option<FaceId>, Vec<f64>);
    // A face's corners are distinct: row h has one column per corner of its face.
    let max_len = |i: usize| if i < nh { t.face_size(t.he_face(HalfEdgeId(i as u32))) } else { 2 };
    let rows = nh + 2 * boundary.len();
    Ok(RowBuilder::build_parallel_bounded(
        rows,
        t.vertex_count(),
        Summation::InOrder,
        max_len,
        |i, rows, scratch: &mut Scratch| {
            if i < nh {
                let h = HalfEdgeId(i as u32);
                let f = t.he_face(h);
                let face = t.face(f);
                let m = face.len();
                let (last, w) = scratch;
                if *last != Some(f) {
                    w.resize(m, 0.0);
                    rule.weights(f.index(), w);
                    *last = Some(f);
                }
                // Image of corner k: Σⱼ w[j]·V_{(k+j) mod m}, i.e. face[k..], then face[..k].
                let (before, from_k) = face.split_at(t.he_corner(h).index as usize);
                for (&column, &wj) in from_k.iter().chain(before).zip(w.iter()) {
                    rows.add(column, wj);
                }
            } else {
                // Boundary Chaikin points in dual_split's order (loop by loop), near end first.
                let h = boundary[(i - nh) / 2];
                let (a, b) = (t.he_from(h).0, t.he_to(h).0);
                let (near, far) = if (i - nh) % 2 == 0 { (a, b) } else { (b, a) };
                rows.add(near, BOUNDARY_EDGE_POINT.near);
                rows.add(far, BOUNDARY_EDGE_POINT.far);
            }
        },
    ))
}

/// The points of one Doo-Sabin step on [`dual_split`]'s numbering, R·x,
/// evaluated face by face without building R: what the interpolation methods
/// need once (Zheng-Cai step 3, Fan-Cheng-Lai phase one). Equal to
/// `apply(&refinement_stencil(t, rule)?, x)` up to the order of summation.
///
/// # Errors
/// [`StencilError::InvalidParameter`] for a λ outside (0, 1) or a λ list of
/// the wrong length.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn first_step(t: &Topology, rule: CornerRule<'_>, x: &[DVec3]) -> Result<Vec<DVec3>, StencilError> {
    rule.validate(t)?;
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    let nh = t.half_edge_count();
    let boundary: Vec<HalfEdgeId> = t.boundary_loops().flatten().copied().collect();
    let mut out = vec![DVec3::ZERO; nh + 2 * boundary.len()];
    let (corners, chaikin) = out.split_at_mut(nh);
    // A face's corners are consecutive half-edges (from its offset on); a
    // chunk starts in the face of its first corner.
    let offsets = t.faces().offsets();
    fill_in_chunks(corners, |first, chunk| {
        let mut f = t.he_face(HalfEdgeId(first as u32)).index();
        let mut w = Vec::new();
        let mut h = first;
        while h < first + chunk.len() {
            let face = t.face(FaceId(f as u32));
            let m = face.len();
            let lambda = match rule {
                CornerRule::Standard => None,
                CornerRule::Uniform(l) => Some(l),
                CornerRule::PerFace(ls) => Some(ls[f]),
            };
            let mut centroid = DVec3::ZERO;
            if lambda.is_some() {
                centroid = face.iter().map(|&v| x[v as usize]).sum::<DVec3>() / m as f64;
            } else {
                w.resize(m, 0.0);
                rule.weights(f, &mut w);
            }
            let start = offsets[f] as usize;
            let end = (offsets[f + 1] as usize).min(first + chunk.len());
            for k in h - start..end - start {
                chunk[start + k - first] = match lambda {
                    // Fan-Cheng-Lai Eq. 1, Zheng-Cai Eq. 4: λV + (1 − λ)A, A the face centroid.
                    Some(l) => l * x[face[k] as usize] + (1.0 - l) * centroid,
                    // Zheng-Cai Eq. 1: Σⱼ α_j·V_{(k+j) mod m}.
                    None => w.iter().enumerate().fold(DVec3::ZERO, |acc, (j, &wj)| {
                        let at = if k + j >= m { k + j - m } else { k + j };
                        acc + wj * x[face[at] as usize]
                    }),
                };
            }
            h = end;
            f += 1;
        }
    });
    // Chaikin points of each boundary half-edge a→b, near end first.
    for (pair, &h) in chaikin.chunks_exact_mut(2).zip(&boundary) {
        let (a, b) = (x[t.he_from(h).index()], x[t.he_to(h).index()]);
        pair[0] = BOUNDARY_EDGE_POINT.near * a + BOUNDARY_EDGE_POINT.far * b;
        pair[1] = BOUNDARY_EDGE_POINT.near * b + BOUNDARY_EDGE_POINT.far * a;
    }
    Ok(out)
}

/// One Doo-Sabin step: the refined topology with provenance and its stencil.
pub fn refine(t: &Topology, rule: CornerRule<'_>) -> Result<(Topology, DualProvenance, SparseMatrix), StencilError> {
    rule.validate(t)?;
    // Both depend on the coarse topology only: build them on both cores at once.
    let ((topology, provenance), stencil) = rayon::join(|| dual_split(t), || refinement_stencil(t, rule));
    Ok((topology, provenance, stencil?))
}

/// The corners of the first step whose images make the limit point of an
/// interior vertex of valence 2, with their weights (`None` for every other
/// vertex): its two corners h₀, h₁ (⅜ each) and the corners next to them in
/// their faces, next(h₀), prev(h₀), next(h₁), prev(h₁) (1/16 each) — the
/// centroid of the second-level E-face of the edge between v's two images
/// (`subdiv_rules::doo_sabin`, "Interior vertices of valence 2"). Corner h is
/// vertex h of the first refined mesh ([`dual_split`]'s numbering).
pub fn valence_two_corners(t: &Topology, v: VertexId) -> Option<[(HalfEdgeId, f64); 6]> {
    match *t.vertex_fan(v) {
        [h0, h1] if !t.is_boundary_vertex(v) => {
            let (own, adjacent) = (VALENCE_TWO_LIMIT.own, VALENCE_TWO_LIMIT.adjacent);
            Some([
                (h0, own),
                (h1, own),
                (t.he_next(h0), adjacent),
                (t.he_prev(h0), adjacent),
                (t.he_next(h1), adjacent),
                (t.he_prev(h1), adjacent),
            ])
        }
        _ => None,
    }
}

/// Adds `scale` × the valence-2 limit row of `corners`
/// ([`valence_two_corners`]) to `rows`: each corner's image under `rule`
/// (its face's row from that corner on).
pub(crate) fn add_valence_two_row(
    t: &Topology,
    corners: &[(HalfEdgeId, f64); 6],
    rule: CornerRule<'_>,
    scale: f64,
    rows: &mut RowBuilder,
    w: &mut Vec<f64>,
) {
    for &(h, weight) in corners {
        let c = t.he_corner(h);
        let face = t.face(c.face);
        w.resize(face.len(), 0.0);
        rule.weights(c.face.index(), w);
        let (before, from_corner) = face.split_at(c.index as usize);
        for (&column, &wj) in from_corner.iter().chain(before).zip(w.iter()) {
            rows.add(column, scale * weight * wj);
        }
    }
}

/// The limit point of the edge of half-edge `h` under the standard scheme:
/// the centroid of the edge's E-face after one step, ¼ of the images of its
/// two ends in its two faces (in one face and its two Chaikin points on a
/// boundary edge). A face centroid of the next level, so a limit point; on a
/// first refined mesh it is the limit point of the valence-2 vertex whose two
/// images the edge joins.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn edge_limit_point(t: &Topology, h: HalfEdgeId, x: &[DVec3]) -> DVec3 {
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    let image = |g: HalfEdgeId| {
        let c = t.he_corner(g);
        let face = t.face(c.face);
        let mut w = [0.0; 16];
        let mut big = Vec::new();
        let w: &mut [f64] = if face.len() <= 16 {
            &mut w[..face.len()]
        } else {
            big.resize(face.len(), 0.0);
            &mut big
        };
        doo_sabin_weights(face.len(), w);
        let (before, from_corner) = face.split_at(c.index as usize);
        from_corner.iter().chain(before).zip(w.iter()).map(|(&v, &wj)| wj * x[v as usize]).sum::<DVec3>()
    };
    // The images of h's two ends in h's face: corners h (from) and next(h) (to).
    let one_side = image(h) + image(t.he_next(h));
    let other_side = match t.he_twin(h) {
        Some(g) => image(g) + image(t.he_next(g)),
        None => {
            let (a, b) = (x[t.he_from(h).index()], x[t.he_to(h).index()]);
            // The two Chaikin points ¾a + ¼b and ¼a + ¾b sum to a + b.
            a + b
        }
    };
    (one_side + other_side) / 4.0
}

/// Row v of the standard scheme's limit stencil (SPEC §1): the centroid of
/// v's V-face after one step, (1/n)Σ over v's faces of that face's Eq. 1 row;
/// for a boundary vertex, the point of the boundary quadratic B-spline at v,
/// (B₋ + 6V + B₊)/8 (`BOUNDARY_CURVE_POINT`); for an interior vertex of
/// valence 2 (no V-face), the valence-2 mask on the first step's images
/// ([`valence_two_corners`]). An isolated vertex maps to itself.
fn limit_row(t: &Topology, v: VertexId, rows: &mut RowBuilder, w: &mut Vec<f64>) {
    if t.is_isolated(v) {
        rows.add(v.0, 1.0);
    } else if let Some((prev, next)) = t.boundary_neighbors(v) {
        let [wp, wv, wn] = BOUNDARY_CURVE_POINT;
        rows.add(prev.0, wp);
        rows.add(v.0, wv);
        rows.add(next.0, wn);
    } else if let Some(corners) = valence_two_corners(t, v) {
        add_valence_two_row(t, &corners, CornerRule::Standard, 1.0, rows, w);
    } else {
        let n = t.vertex_face_count(v) as f64;
        for c in t.vertex_corners(v) {
            let face = t.face(c.face);
            w.resize(face.len(), 0.0);
            doo_sabin_weights(face.len(), w);
            // Weight w[j] goes to the corner j places after v's: face[k..], then face[..k].
            let (before, from_v) = face.split_at(c.index as usize);
            for (&column, &wj) in from_v.iter().chain(before).zip(w.iter()) {
                rows.add(column, wj / n);
            }
        }
    }
}

/// V × V limit stencil of the standard scheme: row v maps control points to
/// the limit point of vertex v ([`limit_row`]).
pub fn limit_stencil(t: &Topology) -> SparseMatrix {
    let nv = t.vertex_count();
    RowBuilder::build_parallel_with_scratch(nv, nv, Summation::InOrder, |i, rows, w: &mut Vec<f64>| {
        limit_row(t, VertexId(i as u32), rows, w)
    })
}

/// The limit point of every vertex, `apply(&limit_stencil(t), x)` up to
/// round-off, evaluated row by row without building the stencil.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn limit_points(t: &Topology, x: &[DVec3]) -> Vec<DVec3> {
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    RowBuilder::evaluate_parallel_with_scratch(t.vertex_count(), x, |i, rows, w: &mut Vec<f64>| {
        limit_row(t, VertexId(i as u32), rows, w)
    })
}
