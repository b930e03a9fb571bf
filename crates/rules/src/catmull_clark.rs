//! Catmull-Clark masks: face, edge and vertex points with OpenSubdiv's
//! `EDGE_AND_CORNER` boundary rules, the limit masks, and Cheng's general-mesh
//! limit stencil, and the limit mask of a dart ([`dart_limit_mask`]).
//!
//! Source: Cheng et al., *Interpolating meshes of arbitrary topology* (CFL in [references]),
//! Appendix Eq. 4 (the step) and Eq. 5 (the limit stencil), with [correction C1]
//! (the factor 4/(n(n+5)) multiplies all three groups of Eq. 5) and [correction C2] (the
//! edge point of edge VEᵢ uses faces fᵢ₋₁ and fᵢ). Limit masks: [how the error is measured].
//!
//! Neighbourhood convention (as for [`VertexMask`]): vertex V of valence n has
//! neighbours E₁…Eₙ and faces fᵢ = (V, Eᵢ, F₁ⁱ, …, F_{mᵢ−3}ⁱ, Eᵢ₊₁) of sizes
//! mᵢ; the F's are the *far corners* of face i.
//!
//! | new point | interior | boundary | corner (1 face) |
//! |---|---|---|---|
//! | face point | mean of the m corners | same | same |
//! | edge point | (V + E + f_left + f_right)/4 | midpoint | — |
//! | vertex point | (n−2)/n V + Σ Eᵢ/n² + Σ fᵢ/n² | (E₋ + 6V + E₊)/8 | V |
//! | limit, all quads | (n²V + 4ΣEᵢ + ΣFᵢ)/(n(n+5)) | (E₋ + 4V + E₊)/6 | V |
//! | limit at a dart, all quads | [`dart_limit_mask`]: the eigenvector of the dart's 1-ring | — | — |
//!
//! The interior limit mask needs all faces around V to be quads (true after
//! one step); [`limit_stencil`] is the same limit expressed on the unrefined
//! mesh (Eq. 5). The boundary limit mask holds at every level because the
//! boundary rules only involve boundary vertices: the boundary is the cubic
//! B-spline of the boundary polygon.
//!
//! [correction C1]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c1
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md
//! [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured
//! [correction C2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c2

use crate::mask::{dart_ring_shape, DartMask, EdgeMask, VertexKind, VertexMask};
use crate::TriangleRule;

/// Weight of each corner in the face point of an m-sided face: 1/m
/// (Appendix Eq. 4, third line).
///
/// # Panics
/// If `m < 3`.
#[inline]
pub fn face_point_weight(m: usize) -> f64 {
    // 1/m for the common sizes without a division in the stencil loops (the
    // same correctly rounded values: const division is IEEE division).
    const RECIPROCALS: [f64; 9] = [0.0, 0.0, 0.0, 1.0 / 3.0, 1.0 / 4.0, 1.0 / 5.0, 1.0 / 6.0, 1.0 / 7.0, 1.0 / 8.0];
    assert!(m >= 3, "a face has at least 3 corners, got {m}");
    match RECIPROCALS.get(m) {
        Some(&w) => w,
        None => 1.0 / m as f64, // Eq. (4): f_i = (V + E_i + E_{i+1} + F_1^i + … + F_{m_i−3}^i)/m_i
    }
}

/// Edge-point mask over the endpoints and the corners of the edge's faces,
/// with the face points expanded: for an interior edge between faces of sizes
/// `m_left` and `m_right`, (A + B + f_left + f_right)/4 gives each endpoint
/// ¼ + 1/(4m_left) + 1/(4m_right) and every other corner of a face 1/(4m) of
/// that face (Appendix Eq. 4 as corrected by [correction C2]). A boundary edge
/// (`m_right = None`) gets the midpoint.
///
/// ```
/// use subdiv_rules::catmull_clark::edge_point_mask;
/// let quad = edge_point_mask(4, Some(4));
/// assert_eq!((quad.end, quad.left, quad.right), (0.375, 0.0625, 0.0625));
/// assert_eq!(edge_point_mask(4, None).end, 0.5);
/// ```
///
/// # Panics
/// If a face size is below 3.
///
/// [correction C2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c2
#[inline]
pub fn edge_point_mask(m_left: usize, m_right: Option<usize>) -> EdgeMask {
    let Some(m_right) = m_right else {
        return EdgeMask::MIDPOINT;
    };
    let (fl, fr) = (face_point_weight(m_left), face_point_weight(m_right));
    // Correction C2 (docs/REFERENCES.md): e_i = (V + E_i + f_{i−1} + f_i)/4, each face point expanded over
    // its corners.
    EdgeMask { end: 0.25 * (1.0 + fl + fr), left: 0.25 * fl, right: 0.25 * fr }
}

/// [`edge_point_mask`] under a [`TriangleRule`]. With
/// [`TriangleRule::Smooth`] an interior edge next to a triangle takes
/// OpenSubdiv's `TRI_SUB_SMOOTH` weights (`Sdc::Scheme<CATMARK>::
/// assignSmoothMaskForEdge`, after Hbr): each face point weighs
/// f = ½(w₀ + w₁), wᵢ = 0.470 for a triangle and ¼ otherwise, each endpoint
/// ½(1 − 2f) — expanded over the faces' corners as in [`edge_point_mask`].
/// Edges between two non-triangles and boundary edges are unchanged.
///
/// ```
/// use subdiv_rules::catmull_clark::{edge_point_mask, edge_point_mask_with};
/// use subdiv_rules::TriangleRule;
/// assert_eq!(edge_point_mask_with(3, Some(4), TriangleRule::Catmark), edge_point_mask(3, Some(4)));
/// let smooth = edge_point_mask_with(3, Some(3), TriangleRule::Smooth);
/// // f = 0.47 per face point, 0.03 per endpoint: 0.03 + 2·0.47/3 at each end.
/// assert!((smooth.end - (0.03 + 2.0 * 0.47 / 3.0)).abs() < 1e-15);
/// assert!((2.0 * smooth.end + smooth.left + smooth.right - 1.0).abs() < 1e-15);
/// ```
///
/// # Panics
/// If a face has fewer than 3 corners.
pub fn edge_point_mask_with(m_left: usize, m_right: Option<usize>, rule: TriangleRule) -> EdgeMask {
    match (rule, m_right) {
        (TriangleRule::Smooth, Some(m_right)) if m_left == 3 || m_right == 3 => {
            const SMOOTH_TRIANGLE_WEIGHT: f64 = 0.470;
            let w = |m: usize| if m == 3 { SMOOTH_TRIANGLE_WEIGHT } else { 0.25 };
            let f = 0.5 * (w(m_left) + w(m_right));
            let v = 0.5 * (1.0 - 2.0 * f);
            let (fl, fr) = (face_point_weight(m_left), face_point_weight(m_right));
            EdgeMask { end: v + f * (fl + fr), left: f * fl, right: f * fr }
        }
        _ => edge_point_mask(m_left, m_right),
    }
}

/// Vertex-point mask. Interior vertex of valence n:
/// v = (n−2)/n V + (1/n²)ΣEᵢ + (1/n²)Σfᵢ, where the face term is the new
/// **face point** fᵢ of each face (Appendix Eq. 4, first line); the caller
/// composes it with [`face_point_weight`]. Boundary vertex:
/// (E₋ + 6V + E₊)/8 over its two boundary neighbours. Corner: V.
///
/// # Panics
/// If an interior vertex has valence below 2.
pub fn vertex_point_mask(kind: VertexKind, valence: usize) -> VertexMask {
    match kind {
        VertexKind::Interior => {
            assert!(valence >= 2, "interior vertex of valence {valence}");
            let n = valence as f64;
            let w = 1.0 / (n * n);
            VertexMask {
                vertex: (n - 2.0) / n, // Eq. (4): v = (n−2)/n V + 1/n² Σ E_i + 1/n² Σ f_i
                interior_neighbor: w,
                boundary_neighbor: 0.0,
                face: w,
            }
        }
        VertexKind::Boundary => {
            VertexMask { vertex: 0.75, interior_neighbor: 0.0, boundary_neighbor: 0.125, face: 0.0 }
        }
        VertexKind::Corner => VertexMask::IDENTITY,
    }
}

/// Limit-point mask. Interior vertex of valence n **whose faces are all
/// quads** (any mesh after one step): (n²V + 4ΣEᵢ + ΣFᵢ)/(n(n+5)), the face
/// term being the corner of each quad diagonal to V. Boundary vertex:
/// (E₋ + 4V + E₊)/6. Corner: V. ([how the error is measured]; Cheng Appendix, the line before
/// Eq. 5.)
///
/// # Panics
/// If an interior vertex has valence below 2.
///
/// [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured
pub fn limit_mask(kind: VertexKind, valence: usize) -> VertexMask {
    match kind {
        VertexKind::Interior => {
            assert!(valence >= 2, "interior vertex of valence {valence}");
            let n = valence as f64;
            let d = 1.0 / (n * (n + 5.0));
            VertexMask {
                vertex: n * n * d, // v∞ = n²/(n(n+5)) v + 4/(n(n+5)) Σ e_i + 1/(n(n+5)) Σ f_i
                interior_neighbor: 4.0 * d,
                boundary_neighbor: 0.0,
                face: d,
            }
        }
        VertexKind::Boundary => {
            VertexMask { vertex: 4.0 / 6.0, interior_neighbor: 0.0, boundary_neighbor: 1.0 / 6.0, face: 0.0 }
        }
        VertexKind::Corner => VertexMask::IDENTITY,
    }
}

/// Limit-point mask of an interior **dart** of valence n on an all-quad fan:
/// a vertex V with vertex sharpness 0 and exactly one incident edge, VE₀,
/// infinitely sharp (weights and fan numbering: [`DartMask`]).
///
/// Refinement keeps the smooth vertex rule at V but gives VE₀ the crease
/// rule, its midpoint, at every level, so the closed 1-ring subdivision
/// matrix S on the 2n + 1 points (V, E₀…Eₙ₋₁, F₀…Fₙ₋₁) is not the smooth
/// one: V' = (n−2)/n V + 1/n² ΣEᵢ + 1/n² Σfᵢ, E₀' = (V + E₀)/2, the other
/// Eᵢ' = (V + Eᵢ + fᵢ₋₁ + fᵢ)/4, Fᵢ' = fᵢ = (V + Eᵢ + Fᵢ + Eᵢ₊₁)/4. The
/// limit is the dominant left eigenvector of the local subdivision matrix
/// (e.g. Halstead, Kass & DeRose 1993; Biermann, Levin & Zorin 2000, HKD93
/// and BLZ00 in [references]): lᵀS = lᵀ with Σl = 1, which here differs from
/// the smooth mask [`limit_mask`] (what OpenSubdiv's limit stencils and
/// `Far::PrimvarRefiner::Limit` use at a dart).
///
/// Closed form, from lᵀS = lᵀ column by column with weight 1 on V and êⱼ the
/// weight of Eⱼ for 0 < j < n, ê₀ = êₙ = 0 (E₀' is a midpoint: no face
/// term, no neighbour term):
///
/// ```text
/// column Fⱼ:          fⱼ = 1/(3n²) + (êⱼ + êⱼ₊₁)/12
/// column Eⱼ, 0<j<n:  7eⱼ = 20/n² + êⱼ₋₁ + êⱼ₊₁
///   ⇒ eⱼ = (4/n²)(1 − (ρʲ + ρⁿ⁻ʲ)/(1 + ρⁿ)),  ρ = (7 − 3√5)/2 = φ⁻⁴ (ρ² − 7ρ + 1 = 0)
/// column E₀:          e₀ = 10/(3n²) + (e₁ + eₙ₋₁)/6
/// ```
///
/// then every weight divided by 1 + Σe + Σf. The smooth mask's 4/n² and
/// 1/n² are the constant solution of the same equations (no crease); the
/// quotient (ρʲ + ρⁿ⁻ʲ)/(1 + ρⁿ) is L₂|ₙ₋₂ⱼ| / L₂ₙ (Lucas numbers), so the
/// weights are rational: at n = 3,
/// (162V + 80E₀ + 60(E₁ + E₂) + 11(F₀ + F₂) + 16F₁)/400 where the smooth
/// mask is (9V + 4ΣEᵢ + ΣFᵢ)/24. The powers of ρ are taken as products, so
/// any valence works (ρⁿ underflows to 0).
///
/// ```
/// use subdiv_rules::catmull_clark::dart_limit_mask;
/// let m = dart_limit_mask(3);
/// assert!((m.vertex - 0.405).abs() < 1e-15 && (m.edge[0] - 0.2).abs() < 1e-15);
/// assert!((m.edge[1] - 0.15).abs() < 1e-15 && (m.far_corner[1] - 0.04).abs() < 1e-15);
/// assert!((m.total() - 1.0).abs() < 1e-15);
/// ```
///
/// A valence below 2 (no manifold mesh has one) gets the identity.
///
/// [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md
pub fn dart_limit_mask(valence: usize) -> DartMask {
    let n = valence;
    if n < 2 {
        return DartMask::identity(n, n);
    }
    let nf = n as f64;
    let rho = 2.0 / (7.0 + 3.0 * 5f64.sqrt()); // ρ = (7 − 3√5)/2, without the cancellation
    let u = dart_ring_shape(rho, n);
    // ê_j: the ring weights, 0 at j = 0 and j = n (the crease).
    let ring = |j: usize| if j % n == 0 { 0.0 } else { 4.0 / (nf * nf) * (1.0 - u[j]) }; // e_j = (4/n²)(1 − u_j)
    let far_corner = (0..n).map(|j| 1.0 / (3.0 * nf * nf) + (ring(j) + ring(j + 1)) / 12.0).collect(); // f_j
    let mut edge: Vec<f64> = (0..n).map(ring).collect();
    edge[0] = 10.0 / (3.0 * nf * nf) + (edge[1] + edge[n - 1]) / 6.0; // e₀ = 10/(3n²) + (e₁ + eₙ₋₁)/6
    DartMask { vertex: 1.0, edge, far_corner }.normalized()
}

/// Cheng's limit stencil of an interior vertex on an arbitrary polygon mesh
/// (Appendix Eq. 5 with [corrections C1/C2]): one Catmull-Clark step followed by the
/// quad limit mask, expressed on the unrefined mesh. With D = 4/(n(n+5)):
///
/// v∞ = D [ (n(n−1)/4 + Σ1/mᵢ) V + Σ(½ + 1/mᵢ + 1/mᵢ₋₁) Eᵢ + Σᵢ (F₁ⁱ + … + F_{mᵢ−3}ⁱ)/mᵢ ]
///
/// `face_sizes[i]` = mᵢ of face i = (V, Eᵢ, …, Eᵢ₊₁) (indices mod n, so Eᵢ
/// lies in faces i−1 and i). Fills `edge_weights[i]` with the weight of Eᵢ and
/// `far_corner_weights[i]` with the weight of **each** far corner of face i,
/// D/mᵢ, and returns the weight of V. Row i of Cheng's A = D·S: the entries
/// divided by D are the symmetric S.
///
/// ```
/// // Regular vertex: the quad limit mask of a B-spline surface.
/// let (mut e, mut f) = ([0.0; 4], [0.0; 4]);
/// let v = subdiv_rules::catmull_clark::limit_stencil(&[4; 4], &mut e, &mut f);
/// assert!((v - 4.0 / 9.0).abs() < 1e-15);
/// assert!((e[0] - 1.0 / 9.0).abs() < 1e-15 && (f[0] - 1.0 / 36.0).abs() < 1e-15);
/// ```
///
/// # Panics
/// If `face_sizes` has fewer than 2 entries, a size is below 3, or a buffer
/// length differs from `face_sizes.len()`.
///
/// [corrections C1/C2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c1
pub fn limit_stencil(face_sizes: &[usize], edge_weights: &mut [f64], far_corner_weights: &mut [f64]) -> f64 {
    let n = face_sizes.len();
    assert!(n >= 2, "interior vertex of valence {n}");
    assert_eq!(edge_weights.len(), n, "one edge weight per neighbour");
    assert_eq!(far_corner_weights.len(), n, "one far-corner weight per face");
    let nf = n as f64;
    let d = 4.0 / (nf * (nf + 5.0)); // Correction C1 (docs/REFERENCES.md): D = 4/(n(n+5)) multiplies every group
    let mut inv_sum = 0.0;
    for i in 0..n {
        let inv = face_point_weight(face_sizes[i]);
        let inv_prev = face_point_weight(face_sizes[(i + n - 1) % n]);
        inv_sum += inv;
        edge_weights[i] = d * (0.5 + inv + inv_prev); // Eq. (5): Σ(½ + 1/m_i + 1/m_{i−1}) E_i
        far_corner_weights[i] = d * inv; // Eq. (5): Σ_i (F_1^i + … + F_{m_i−3}^i)/m_i
    }
    d * (nf * (nf - 1.0) / 4.0 + inv_sum) // Eq. (5): (n(n−1)/4 + Σ 1/m_i) V
}

#[cfg(test)]
#[path = "catmull_clark_tests.rs"]
mod tests;
