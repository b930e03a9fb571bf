//! Doo-Sabin operators: the refinement stencil R of a step with any corner
//! mask, and the limit stencil, with or without infinitely sharp creases and
//! corners.
//!
//! Corner mask ([`CornerMask`]): the scheme's Eq. 1 ([`StandardCorners`],
//! from `subdiv_rules::doo_sabin`), or the mask of a first step that an
//! interpolation method supplies (its rules live in `subdiv-interp`); the
//! rest of the step does not depend on it. Boundary: every boundary edge a→b gets the two
//! Chaikin points ¾a + ¼b and ¼a + ¾b, and the faces of
//! [`subdiv_mesh::refine::dual_split`] close them, so the boundary converges to
//! the quadratic B-spline of the boundary polygon (rule and its justification:
//! `subdiv_rules::doo_sabin`, "Boundary rule").
//!
//! Row order of R is [`dual_split`]'s numbering: one row per old corner
//! (= old half-edge id), then two per boundary half-edge.
//!
//! # Creases and corners
//!
//! The `_tagged` functions take the level's [`Tags`]. For Doo-Sabin an edge
//! is a **crease** iff its sharpness is ≥ 10 (`SHARPNESS_INFINITE`); with the
//! boundary edges these are the **sharp** edges. A vertex is a **corner** iff
//! its corner sharpness is ≥ 10 or it has three or more sharp edges (so a
//! crease that ends on the boundary makes a corner there), a **dart** if it
//! has exactly one, a crease vertex with two. Semi-sharp values
//! (0 < s < 10) have no Doo-Sabin rule: [`StencilError::SemiSharpDooSabin`].
//! Without tags every function is its untagged twin, bit for bit (the
//! untagged ones call the tagged ones with no tags).
//!
//! **Construction** ([`dual_split_tagged`], [`DualFeatures`]): a sharp edge is
//! treated as a boundary of the faces on *each* side. Conceptually the mesh
//! is cut along its creases and every side gets the boundary rule:
//!
//! 1. *Face corners: unchanged.* Every corner image, next to a crease or not,
//!    is the corner rule's (Eq. 1 or the first-step variant).
//! 2. *Sharp points.* A sharp edge a–b gets ¾a + ¼b near a and ¼a + ¾b near b
//!    (`BOUNDARY_EDGE_POINT`), except at corners: a corner is kept (one new
//!    vertex at its position, shared by all its sharp edges), and on an edge
//!    with a corner at b the point near a is the midpoint ½a + ½b
//!    (`CLAMPED_EDGE_POINT`); an edge between two corners gets its midpoint.
//!    These points depend only on the edge's ends, so the points the two
//!    sides of a crease would get coincide: they are one vertex of the
//!    refined mesh, which stays one manifold, glued along the crease.
//! 3. *Faces.* F-faces as always; an E-face per side of a sharp edge, through
//!    its two images and the edge's sharp points (a quad, or a pentagon with a
//!    midpoint), so the two sides' E-faces share the crease's new segments;
//!    one V-face per *sector* of a vertex (its faces between two consecutive
//!    sharp edges), closed by the sharp points near the vertex on those two
//!    edges. A dart has one sector, closed by the single Chaikin point of its
//!    crease (the cut does not separate at a dart); a corner's sectors are
//!    closed by its point, a one-face sector then needs no V-face; a corner
//!    with no sharp edge gets a fan of triangles round its point (a cone).
//!    Crease vertices get two sectors whose V-faces share the segment between
//!    the vertex's two sharp points: the next piece of the crease polygon.
//!
//! The refined tags ([`dual_split_tagged`]'s third result) mark the segments
//! of the refined sharp polygon as creases and keep tagged corners, so the
//! rules apply again at every level.
//!
//! **Claims, and why they hold** (the tests in
//! `tests/integration/doo_sabin_creases.rs` check each one, against curve evaluators and
//! 8 levels of brute-force refinement):
//!
//! - *Face centroids are limit points*, sharp faces included: a face's corner
//!   images are a circulant (or λI + (1 − λ)J/m) combination of its corners
//!   whose columns sum to 1, so its F-face has the face's centroid; nested
//!   F-faces keep it and shrink (eigenvalue ½, or λ), so they converge to it.
//!   Step 1 leaves every corner image alone, so the argument of the boundary
//!   rule carries over unchanged.
//! - *The sharp polygon refines by itself, by Chaikin's rule*: its new
//!   vertices are the sharp points of step 2, which depend on old sharp
//!   vertices only, and its new edges join them along each old sharp edge and
//!   across each crease vertex. So a closed loop without corners refines by
//!   closed Chaikin (`curves::chaikin(_, true)`), a piece from corner to
//!   corner by the clamped rule (`curves::chaikin(_, false)`: corner kept,
//!   midpoint of the end leg), and a piece ending at a dart by Chaikin's pairs
//!   with no end rule (the dart's successor is the Chaikin point next to it).
//! - *Hence the sharp curve is a quadratic B-spline of the sharp polygon*:
//!   Chaikin's pairs are knot insertion for the uniform quadratic B-spline,
//!   the clamped rule for the open-uniform one (knots 0,0,0,1,…,L,L,L): a
//!   closed crease is the closed uniform B-spline, a piece between corners
//!   interpolates them and is tangent to its end legs, a piece ending at a
//!   dart stops at the midpoint of the dart's crease edge. The sharp points are
//!   vertices of the mesh at every level and the faces shrink, so the limit
//!   surface contains that curve; from level 1 on each side of a crease is an
//!   open mesh bounded by it, so the surface is creased (G⁰) there.
//! - *Limit points* ([`limit_stencil_tagged`]): a corner is kept; a crease or
//!   boundary vertex V maps to the midpoint of its segment of the refined
//!   sharp polygon (`sharp_curve_point`: (B₋ + 6V + B₊)/8 without corner
//!   neighbours, ¼B₋ + ⅝V + ⅛B₊ next to corner B₋) — the next level splits
//!   that segment by Chaikin's two points, whose midpoint is the same, and
//!   halves it, so it converges to that point of the sharp curve; a dart
//!   maps to its V-face's centroid and a smooth vertex to its V-face's (or the
//!   valence-2 mask), face centroids of the first level, hence limit points.
//! - *Untagged meshes do not move*: without creases and corners a boundary
//!   vertex has two sharp edges and is no corner, so the rules above are the
//!   boundary rule, and the functions give the untagged results bit for bit.
//!
//! Choices, and why: the clamped end at corners (rather than Chaikin's pair
//! with the corner added) is the rule whose limit is a B-spline — the
//! open-uniform one, as OpenSubdiv's corner gives the end-interpolating cubic
//! for Catmull-Clark — and it is exactly `curves::chaikin` on the open piece.
//! A boundary vertex with one face is not a corner (two sharp edges), so
//! boundaries keep their Chaikin loops unless a crease or a corner tag meets
//! them. A dart keeps one sector because the cut along a single edge does not
//! separate its faces; the crease then fades into the smooth surface.

use crate::apply::fill_in_chunks;
use crate::scheme::{LevelSplit, SchemeRules};
use crate::sharpness::LevelSharpness;
use crate::{RowBuilder, SparseMatrix, StencilError, Summation};
use glam::DVec3;
use subdiv_mesh::refine::{
    dual_split, dual_split_tagged, DualFeatures, DualProvenance, SharpDualProvenance, SharpPoint,
};
use subdiv_mesh::{FaceId, HalfEdgeId, Tags, Topology, VertexId, SHARPNESS_INFINITE};
use subdiv_rules::doo_sabin::{
    sharp_curve_point, BoundaryEdgePoint, BOUNDARY_EDGE_POINT, CLAMPED_EDGE_POINT, VALENCE_TWO_LIMIT,
};
use subdiv_rules::doo_sabin_weights;

/// The corner mask of a Doo-Sabin step: the image of every corner of a face
/// as a combination of that face's corners, one row per face (`w[j]` the
/// weight of the corner j places after the imaged one, so the image of
/// corner k is Σⱼ w\[j\]·V_{(k+j) mod m}).
///
/// The scheme's own steps use [`StandardCorners`] (Eq. 1). A first step may
/// use another mask (the interpolation methods' first steps, whose rules
/// live in `subdiv-interp`): every function of this module that takes a
/// mask keeps the rest of the step — sharp points, faces, the later steps —
/// as the standard scheme's (module docs, "Creases and corners", step 1).
/// The limit matrices of [`crate::limit_matrix_doo_sabin_sharp`] need each
/// face's row to be symmetric (`w[j] == w[m − j]`) for S to be.
pub trait CornerMask: Sync {
    /// Checks the mask's parameters against the mesh.
    ///
    /// # Errors
    /// [`StencilError::InvalidParameter`] naming the first bad parameter.
    fn validate(&self, t: &Topology) -> Result<(), StencilError>;

    /// Fills `out` with the row of face `face`, of size `out.len()` (≥ 3).
    fn weights(&self, face: FaceId, out: &mut [f64]);

    /// Writes to `out` the images of corners `ks` of face `face`, whose
    /// vertices are `corners`, of the points `x` (one image per k, in order):
    /// by default Σⱼ w\[j\]·x\[corners\[(k+j) mod m\]\] with the face's
    /// [`Self::weights`] (`scratch` holds them). A mask with a closed form may
    /// evaluate that instead (equal up to round-off).
    fn images(
        &self,
        face: FaceId,
        corners: &[u32],
        x: &[DVec3],
        ks: std::ops::Range<usize>,
        out: &mut [DVec3],
        scratch: &mut Vec<f64>,
    ) {
        let m = corners.len();
        scratch.resize(m, 0.0);
        self.weights(face, scratch);
        for (k, image) in ks.zip(out) {
            // Σⱼ w_j·V_{(k+j) mod m}.
            *image = scratch.iter().enumerate().fold(DVec3::ZERO, |acc, (j, &wj)| {
                let at = if k + j >= m { k + j - m } else { k + j };
                acc + wj * x[corners[at] as usize]
            });
        }
    }
}

/// Doo-Sabin's own corner mask, Eq. 1 (Zheng & Cai 2005 §2; module
/// `subdiv_rules::doo_sabin`, "Face-corner rule"): the mask of every step of
/// the scheme.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StandardCorners;

impl CornerMask for StandardCorners {
    /// No parameters: always `Ok`.
    fn validate(&self, _: &Topology) -> Result<(), StencilError> {
        Ok(())
    }

    fn weights(&self, _: FaceId, out: &mut [f64]) {
        doo_sabin_weights(out.len(), out); // Eq. (1)
    }
}

/// Checks that `tags` have a Doo-Sabin meaning: every edge and vertex
/// sharpness is 0 or infinitely sharp (≥ 10).
///
/// # Errors
/// [`StencilError::SemiSharpDooSabin`] naming the first semi-sharp element.
pub fn check_tags(t: &Topology, tags: &Tags) -> Result<(), StencilError> {
    let semi = |s: f32| s > 0.0 && s < SHARPNESS_INFINITE;
    if let Some((e, &sharpness)) = tags.edge_values().iter().enumerate().find(|&(_, &s)| semi(s)) {
        let (a, b) = t.edge_vertices(subdiv_mesh::EdgeId(e as u32));
        return Err(StencilError::SemiSharpDooSabin { what: format!("edge {e} (vertices {a}-{b})"), sharpness });
    }
    if let Some((v, &sharpness)) = tags.vertex_values().iter().enumerate().find(|&(_, &s)| semi(s)) {
        return Err(StencilError::SemiSharpDooSabin { what: format!("vertex {v}"), sharpness });
    }
    Ok(())
}

/// The sharp points of a tagged level ([`DualFeatures::sharp_points`]), after
/// checking the tags.
fn sharp_points(t: &Topology, tags: &Tags) -> Result<Vec<SharpPoint>, StencilError> {
    check_tags(t, tags)?;
    Ok(DualFeatures::new(t, tags).sharp_points(t))
}

/// The old vertices and weights of a sharp point: (near, far) with the
/// Chaikin or clamped weights, the midpoint, or the kept corner.
#[inline]
fn sharp_point_weights(t: &Topology, point: SharpPoint) -> [(u32, f64); 2] {
    match point {
        SharpPoint::Chaikin { half_edge, near_start, far_is_corner } => {
            let (a, b) = (t.he_from(half_edge).0, t.he_to(half_edge).0);
            let (near, far) = if near_start { (a, b) } else { (b, a) };
            let BoundaryEdgePoint { near: wn, far: wf } =
                if far_is_corner { CLAMPED_EDGE_POINT } else { BOUNDARY_EDGE_POINT };
            [(near, wn), (far, wf)]
        }
        SharpPoint::Midpoint { half_edge } => {
            let BoundaryEdgePoint { near, far } = CLAMPED_EDGE_POINT;
            [(t.he_from(half_edge).0, near), (t.he_to(half_edge).0, far)]
        }
        SharpPoint::Corner { vertex } => [(vertex.0, 1.0), (vertex.0, 0.0)],
    }
}

/// (H + 2B) × V refinement stencil on [`dual_split`]'s numbering (H corners,
/// B boundary half-edges): [`refinement_stencil_tagged`] without tags.
pub fn refinement_stencil(t: &Topology, rule: &impl CornerMask) -> Result<SparseMatrix, StencilError> {
    refinement_stencil_tagged(t, &Tags::none(), rule)
}

/// (H + S) × V refinement stencil on [`dual_split_tagged`]'s numbering: H
/// corner images (the corner rule, creases or not), then the S points of the
/// refined sharp polygon (module docs, "Creases and corners").
///
/// # Errors
/// [`StencilError::InvalidParameter`] for a bad λ,
/// [`StencilError::SemiSharpDooSabin`] for a semi-sharp tag.
pub fn refinement_stencil_tagged(
    t: &Topology,
    tags: &Tags,
    rule: &impl CornerMask,
) -> Result<SparseMatrix, StencilError> {
    rule.validate(t)?;
    let sharp = sharp_points(t, tags)?;
    let nh = t.half_edge_count();
    // The scratch keeps the weights of the last face seen: its corners' rows are consecutive.
    type Scratch = (Option<FaceId>, Vec<f64>);
    // A face's corners are distinct: row h has one column per corner of its face.
    let max_len = |i: usize| if i < nh { t.face_size(t.he_face(HalfEdgeId(i as u32))) } else { 2 };
    Ok(RowBuilder::build_parallel_bounded(
        nh + sharp.len(),
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
                    rule.weights(f, w);
                    *last = Some(f);
                }
                // Image of corner k: Σⱼ w[j]·V_{(k+j) mod m}, i.e. face[k..], then face[..k].
                let (before, from_k) = face.split_at(t.he_corner(h).index as usize);
                for (&column, &wj) in from_k.iter().chain(before).zip(w.iter()) {
                    rows.add(column, wj);
                }
            } else {
                let point = sharp[i - nh];
                let [(near, wn), (far, wf)] = sharp_point_weights(t, point);
                rows.add(near, wn);
                if !matches!(point, SharpPoint::Corner { .. }) {
                    rows.add(far, wf);
                }
            }
        },
    ))
}

/// The points of one Doo-Sabin step on [`dual_split`]'s numbering:
/// [`first_step_tagged`] without tags.
///
/// # Errors
/// [`StencilError::InvalidParameter`] for a λ outside (0, 1) or a λ list of
/// the wrong length.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn first_step(t: &Topology, rule: &impl CornerMask, x: &[DVec3]) -> Result<Vec<DVec3>, StencilError> {
    first_step_tagged(t, &Tags::none(), rule, x)
}

/// The points of one Doo-Sabin step on [`dual_split_tagged`]'s numbering,
/// R·x, evaluated face by face without building R: what the interpolation
/// methods need once (Zheng-Cai step 3, Fan-Cheng-Lai phase one). Equal to
/// `apply(&refinement_stencil_tagged(t, tags, rule)?, x)` up to the order of
/// summation.
///
/// # Errors
/// [`StencilError::InvalidParameter`] for a bad λ,
/// [`StencilError::SemiSharpDooSabin`] for a semi-sharp tag.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn first_step_tagged(
    t: &Topology,
    tags: &Tags,
    rule: &impl CornerMask,
    x: &[DVec3],
) -> Result<Vec<DVec3>, StencilError> {
    rule.validate(t)?;
    let sharp = sharp_points(t, tags)?;
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    let nh = t.half_edge_count();
    let mut out = vec![DVec3::ZERO; nh + sharp.len()];
    let (corners, sharp_out) = out.split_at_mut(nh);
    // A face's corners are consecutive half-edges (from its offset on); a
    // chunk starts in the face of its first corner.
    let offsets = t.faces().offsets();
    fill_in_chunks(corners, |first, chunk| {
        let mut f = t.he_face(HalfEdgeId(first as u32)).index();
        let mut w = Vec::new();
        let mut h = first;
        while h < first + chunk.len() {
            let face = t.face(FaceId(f as u32));
            let start = offsets[f] as usize;
            let end = (offsets[f + 1] as usize).min(first + chunk.len());
            let out = &mut chunk[h - first..end - first];
            rule.images(FaceId(f as u32), face, x, h - start..end - start, out, &mut w);
            h = end;
            f += 1;
        }
    });
    // The points of the refined sharp polygon (Chaikin's near end first).
    for (out, &point) in sharp_out.iter_mut().zip(&sharp) {
        *out = match point {
            SharpPoint::Corner { vertex } => x[vertex.index()],
            _ => {
                let [(near, wn), (far, wf)] = sharp_point_weights(t, point);
                wn * x[near as usize] + wf * x[far as usize]
            }
        };
    }
    Ok(out)
}

/// One Doo-Sabin step: the refined topology with provenance and its stencil.
pub fn refine(t: &Topology, rule: &impl CornerMask) -> Result<(Topology, DualProvenance, SparseMatrix), StencilError> {
    rule.validate(t)?;
    // Both depend on the coarse topology only: build them on both cores at once.
    let ((topology, provenance), stencil) = rayon::join(|| dual_split(t), || refinement_stencil(t, rule));
    Ok((topology, provenance, stencil?))
}

/// One tagged Doo-Sabin step: the refined topology, its provenance, the
/// refined level's tags (for the next step) and the stencil.
///
/// # Errors
/// As [`refinement_stencil_tagged`].
pub fn refine_tagged(
    t: &Topology,
    tags: &Tags,
    rule: &impl CornerMask,
) -> Result<(Topology, SharpDualProvenance, Tags, SparseMatrix), StencilError> {
    rule.validate(t)?;
    check_tags(t, tags)?;
    let ((topology, provenance, new_tags), stencil) =
        rayon::join(|| dual_split_tagged(t, tags), || refinement_stencil_tagged(t, tags, rule));
    Ok((topology, provenance, new_tags, stencil?))
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
    rule: &impl CornerMask,
    scale: f64,
    rows: &mut RowBuilder,
    w: &mut Vec<f64>,
) {
    for &(h, weight) in corners {
        let c = t.he_corner(h);
        let face = t.face(c.face);
        w.resize(face.len(), 0.0);
        rule.weights(c.face, w);
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

/// Row v of the standard scheme's limit stencil ([how the error is measured]; module docs,
/// "Limit points"): the centroid of v's V-face after one step, (1/n)Σ over
/// v's faces of that face's Eq. 1 row; for a boundary or crease vertex, the
/// point of the sharp quadratic B-spline at v (`sharp_curve_point`, without
/// corners (B₋ + 6V + B₊)/8); for a dart, the centroid of its V-face, which
/// also holds its crease's Chaikin point; for an interior vertex of valence 2
/// (no V-face), the valence-2 mask on the first step's images
/// ([`valence_two_corners`]). A corner, and an isolated vertex, map to
/// themselves.
///
/// [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured
fn limit_row(t: &Topology, features: &DualFeatures, v: VertexId, rows: &mut RowBuilder, w: &mut Vec<f64>) {
    if t.is_isolated(v) || features.is_corner(v) {
        rows.add(v.0, 1.0);
        return;
    }
    let sharp = |end: Option<VertexId>| end.map(|b| (b, features.is_corner(b)));
    // The ends of v's sharp edges (a boundary vertex has its two and no crease: it would be a corner).
    let (first, second) = if let Some((prev, next)) = t.boundary_neighbors(v) {
        (Some((prev, features.is_corner(prev))), Some((next, features.is_corner(next))))
    } else if features.sharp_edge_count(t, v) > 0 {
        let mut ends = features.sharp_neighbors(t, v);
        (sharp(ends.next()), sharp(ends.next()))
    } else {
        (None, None)
    };
    match (first, second) {
        (Some((prev, prev_corner)), Some((next, next_corner))) => {
            let [wp, wv, wn] = sharp_curve_point(prev_corner, next_corner);
            rows.add(prev.0, wp);
            rows.add(v.0, wv);
            rows.add(next.0, wn);
        }
        (Some((end, end_corner)), None) => {
            // A dart: its V-face is its images and its crease's point near it.
            let n = (t.vertex_face_count(v) + 1) as f64;
            add_face_images(t, v, n, rows, w);
            let BoundaryEdgePoint { near, far } = if end_corner { CLAMPED_EDGE_POINT } else { BOUNDARY_EDGE_POINT };
            rows.add(v.0, near / n);
            rows.add(end.0, far / n);
        }
        _ => {
            if let Some(corners) = valence_two_corners(t, v) {
                add_valence_two_row(t, &corners, &StandardCorners, 1.0, rows, w);
            } else {
                add_face_images(t, v, t.vertex_face_count(v) as f64, rows, w);
            }
        }
    }
}

/// Adds (1/n)× the Eq. 1 image of `v` in each of its faces.
fn add_face_images(t: &Topology, v: VertexId, n: f64, rows: &mut RowBuilder, w: &mut Vec<f64>) {
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

/// V × V limit stencil of the standard scheme: [`limit_stencil_tagged`]
/// without tags.
pub fn limit_stencil(t: &Topology) -> SparseMatrix {
    limit_stencil_of(t, &DualFeatures::default())
}

/// V × V limit stencil of the standard scheme with the creases and corners
/// of `tags`: row v maps control points to the limit point of vertex v —
/// itself for a corner (and an isolated vertex), the sharp quadratic
/// B-spline's point for a crease or boundary vertex (`sharp_curve_point`),
/// the centroid of its V-face after one step for a dart or a smooth vertex,
/// the valence-2 mask ([`valence_two_corners`]) for an interior vertex of
/// valence 2 (module docs, "Limit points").
///
/// # Errors
/// [`StencilError::SemiSharpDooSabin`] for a semi-sharp tag.
pub fn limit_stencil_tagged(t: &Topology, tags: &Tags) -> Result<SparseMatrix, StencilError> {
    check_tags(t, tags)?;
    Ok(limit_stencil_of(t, &DualFeatures::new(t, tags)))
}

fn limit_stencil_of(t: &Topology, features: &DualFeatures) -> SparseMatrix {
    let nv = t.vertex_count();
    RowBuilder::build_parallel_with_scratch(nv, nv, Summation::InOrder, |i, rows, w: &mut Vec<f64>| {
        limit_row(t, features, VertexId(i as u32), rows, w)
    })
}

/// The limit point of every vertex: [`limit_points_tagged`] without tags.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn limit_points(t: &Topology, x: &[DVec3]) -> Vec<DVec3> {
    limit_points_of(t, &DualFeatures::default(), x)
}

/// The limit point of every vertex with the creases and corners of `tags`,
/// `apply(&limit_stencil_tagged(t, tags)?, x)` up to round-off, evaluated row
/// by row without building the stencil.
///
/// # Errors
/// [`StencilError::SemiSharpDooSabin`] for a semi-sharp tag.
///
/// # Panics
/// If `x.len()` differs from the vertex count (a caller bug).
pub fn limit_points_tagged(t: &Topology, tags: &Tags, x: &[DVec3]) -> Result<Vec<DVec3>, StencilError> {
    check_tags(t, tags)?;
    Ok(limit_points_of(t, &DualFeatures::new(t, tags), x))
}

fn limit_points_of(t: &Topology, features: &DualFeatures, x: &[DVec3]) -> Vec<DVec3> {
    assert_eq!(x.len(), t.vertex_count(), "one point per vertex");
    RowBuilder::evaluate_parallel_with_scratch(t.vertex_count(), x, |i, rows, w: &mut Vec<f64>| {
        limit_row(t, features, VertexId(i as u32), rows, w)
    })
}

/// Doo-Sabin as a [`SchemeRules`]: the dual split with the Chaikin boundary
/// rule; infinitely sharp creases and corners as boundaries of both sides
/// (module docs). The boundary option and the crease method do not apply
/// (Doo-Sabin has its own boundary curve; its tags never decay).
pub(crate) struct DooSabinRules;

impl SchemeRules for DooSabinRules {
    fn check(&self, t: &Topology, sharp: &LevelSharpness) -> Result<(), StencilError> {
        if sharp.is_untagged() {
            return Ok(());
        }
        // The tagged split adds a point per corner and per crease end:
        // at most H + 2E + V vertices and 4H + 10E corners.
        let (v, e, h) = (t.vertex_count(), t.edge_count(), t.half_edge_count());
        if (h + 2 * e + v).max(4 * h + 10 * e) > u32::MAX as usize - 1 {
            return Err(StencilError::TooLarge);
        }
        check_tags(t, &sharp.tags(t))
    }

    fn split(&self, t: &Topology, sharp: &LevelSharpness) -> Result<LevelSplit, StencilError> {
        if sharp.is_untagged() {
            let (topology, dual) = dual_split(t);
            return Ok(LevelSplit { topology, sharpness: sharp.clone(), dual: Some(dual) });
        }
        let tags = sharp.tags(t);
        check_tags(t, &tags)?;
        let (topology, _, child) = subdiv_mesh::refine::dual_split_tagged(t, &tags);
        let sharpness =
            LevelSharpness::new(&child, sharp.boundary(), sharp.method()).with_dart_limit(sharp.dart_limit());
        Ok(LevelSplit { topology, sharpness, dual: None })
    }

    fn stencil(&self, t: &Topology, sharp: &LevelSharpness) -> Result<Option<SparseMatrix>, StencilError> {
        refinement_stencil_tagged(t, &sharp.tags(t), &StandardCorners).map(Some)
    }

    fn step_points(&self, t: &Topology, sharp: &LevelSharpness, x: &[DVec3]) -> Result<Vec<DVec3>, StencilError> {
        first_step_tagged(t, &sharp.tags(t), &StandardCorners, x)
    }

    fn limit_points(
        &self,
        t: &Topology,
        sharp: &LevelSharpness,
        x: &[DVec3],
        count: usize,
    ) -> Option<Result<Vec<DVec3>, StencilError>> {
        Some(limit_points_tagged(t, &sharp.tags(t), x).map(|mut points| {
            points.truncate(count);
            points
        }))
    }

    fn limit_stencil(
        &self,
        t: &Topology,
        sharp: &LevelSharpness,
        rows: usize,
    ) -> Option<Result<SparseMatrix, StencilError>> {
        Some(limit_stencil_tagged(t, &sharp.tags(t)).map(|s| {
            if rows == s.rows() {
                s
            } else {
                crate::apply::first_rows(&s, rows)
            }
        }))
    }

    fn levels_before_limit(&self, _: &Topology, _: &LevelSharpness, _: bool) -> usize {
        0 // the Doo-Sabin masks are exact on any level (creases: infinitely sharp only)
    }
}
