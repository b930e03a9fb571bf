//! √3 masks on triangle meshes (Kobbelt 2000): the face point, the smoothing
//! of old vertices with αₙ, the ternary cubic B-spline rules of the boundary
//! and the limit masks with βₙ.
//!
//! Source: L. Kobbelt, "√3-Subdivision", SIGGRAPH 2000 (not among our seed
//! files: the rules below are recalled from the paper, checked against the
//! descriptions of CGAL's `Sqrt3_mask_3` and OpenMesh's `Sqrt3T`, and every
//! limit mask is verified as the dominant left eigenvector of its step in the
//! tests). Equation numbers are not given for that reason; the section is.
//!
//! One step inserts a point at every triangle's centroid, joins it to the
//! triangle's corners and flips every old interior edge (Kobbelt §2); two
//! steps are a 1-to-9 (tri-adic) refinement. Old vertices are smoothed
//! (Kobbelt §3, chosen so that the step is C² at regular vertices and its
//! subdominant eigenvalues at valence n are those of the regular case):
//!
//! | new point | interior (valence n) | boundary, odd step | boundary, even step | corner |
//! |---|---|---|---|---|
//! | face point | (a + b + c)/3 | (a + b + c)/3 | trisection points | — |
//! | vertex point | (1 − αₙ)p + αₙ/n Σpᵢ | p | (4p₋ + 19p + 4p₊)/27 | p |
//! | limit | (1 − βₙ)p + βₙ/n Σpᵢ | (p₋ + 4p + p₊)/6 | (p₋ + 4p + p₊)/6 | p |
//!
//! with αₙ = (4 − 2cos(2π/n))/9 and βₙ = 3αₙ/(1 + 3αₙ). On the boundary
//! (Kobbelt §4) boundary edges are never flipped; every second step (the
//! even ones, counting the first step on the input as step 1) trisects the
//! boundary polygon with the ternary cubic B-spline: on edge (pᵢ, pᵢ₊₁) the
//! points (pᵢ₋₁ + 16pᵢ + 10pᵢ₊₁)/27 and (10pᵢ + 16pᵢ₊₁ + pᵢ₊₂)/27, and
//! pᵢ ↦ (4pᵢ₋₁ + 19pᵢ + 4pᵢ₊₁)/27. The odd steps leave the boundary polygon
//! as it is, so every level's boundary polygon is a control polygon of the
//! same uniform cubic B-spline and its limit mask is the B-spline's at both
//! parities.
//!
//! **Corners** (our addition; the paper has none): a corner keeps its
//! position and the boundary curve ends there, by the B-spline's natural end
//! condition: the missing neighbour beyond a corner c, towards which a mask
//! reaches, is the phantom point 2c − p₊ (p₊ its neighbour along the edge
//! the mask is on). Then c ↦ c, the trisection point next to c is
//! (2c + p₊)/3, the limit of c is c itself, and the phantom stays the
//! reflection of the refined polygon at every level (the ternary rules
//! reproduce linear functions and are symmetric), as OpenSubdiv's corner
//! rule does for the binary B-spline.
//!
//! **Limit of βₙ** (derived here, verified in the tests): after a step an
//! interior vertex's neighbours are the centroids of its old triangles, whose
//! average is (p + 2q̄)/3 when q̄ is the average of its old neighbours. On
//! (p, q̄) the step is the 2 × 2 matrix [[1 − αₙ, αₙ], [⅓, ⅔]]; its
//! eigenvalues are 1 and λₙ = ⅔ − αₙ (|λₙ| < 1 for every n ≥ 3) and its left
//! eigenvector for 1, normalised, is (1, 3αₙ)/(1 + 3αₙ): the limit point.
//! The refined points reach it geometrically, p_k − p∞ = λₙᵏ(p₀ − p∞).

use std::f64::consts::PI;

use crate::mask::{VertexKind, VertexMask};

/// Weight of each corner of a triangle in its face point: the centroid.
pub const FACE_POINT: f64 = 1.0 / 3.0;

/// αₙ = (4 − 2cos(2π/n))/9, the smoothing weight of an interior vertex of
/// valence n (Kobbelt §3).
///
/// ```
/// use subdiv_rules::sqrt3::alpha;
/// assert!((alpha(6) - 1.0 / 3.0).abs() < 1e-15);
/// ```
///
/// # Panics
/// If `n == 0`.
pub fn alpha(n: usize) -> f64 {
    assert!(n > 0, "a vertex needs at least one neighbour");
    (4.0 - 2.0 * (2.0 * PI / n as f64).cos()) / 9.0 // Kobbelt §3: αₙ = (4 − 2cos(2π/n))/9
}

/// βₙ = 3αₙ/(1 + 3αₙ), the weight of the neighbours' average in the limit
/// point of an interior vertex of valence n (the left eigenvector of the
/// step for eigenvalue 1, module docs); ½ at n = 6.
///
/// ```
/// use subdiv_rules::sqrt3::beta;
/// assert!((beta(6) - 0.5).abs() < 1e-15);
/// ```
///
/// # Panics
/// If `n == 0`.
pub fn beta(n: usize) -> f64 {
    let a3 = 3.0 * alpha(n);
    a3 / (1.0 + a3) // left eigenvector of [[1 − α, α], [⅓, ⅔]] for eigenvalue 1
}

/// λₙ = ⅔ − αₙ, the factor by which an interior vertex approaches its limit
/// point in one step (the subdominant eigenvalue of the 2 × 2 step on the
/// vertex and its neighbours' average, module docs).
///
/// # Panics
/// If `n == 0`.
pub fn convergence_factor(n: usize) -> f64 {
    2.0 / 3.0 - alpha(n)
}

/// Vertex-point mask. Interior vertex of valence n: (1 − αₙ)p + αₙ/n Σpᵢ;
/// boundary vertex: unchanged in an odd step, (4p₋ + 19p + 4p₊)/27 in an
/// even one (Kobbelt §4); corner: p. The mask has no face term.
///
/// # Panics
/// If an interior vertex has valence 0.
pub fn vertex_point_mask(kind: VertexKind, valence: usize, even_step: bool) -> VertexMask {
    match kind {
        VertexKind::Interior => {
            let a = alpha(valence);
            VertexMask {
                vertex: 1.0 - a, // Kobbelt §3: p' = (1 − αₙ)p + αₙ/n Σ pᵢ
                interior_neighbor: a / valence as f64,
                boundary_neighbor: 0.0,
                face: 0.0,
            }
        }
        VertexKind::Boundary if even_step => {
            // Kobbelt §4: the ternary cubic B-spline, p ↦ (4p₋ + 19p + 4p₊)/27.
            VertexMask { vertex: 19.0 / 27.0, interior_neighbor: 0.0, boundary_neighbor: 4.0 / 27.0, face: 0.0 }
        }
        VertexKind::Boundary | VertexKind::Corner => VertexMask::IDENTITY,
    }
}

/// Limit-point mask. Interior vertex of valence n: (1 − βₙ)p + βₙ/n Σpᵢ with
/// [`beta`]; boundary: (p₋ + 4p + p₊)/6 (the cubic B-spline's, at both
/// parities); corner: p.
///
/// The interior mask is exact where the vertex's neighbours after the next
/// step are the centroids of its triangles: always before an odd step, and
/// before an even step unless one of its triangles has a boundary edge
/// (module docs of `subdiv-stencil`'s `sqrt3`).
///
/// # Panics
/// If an interior vertex has valence 0.
pub fn limit_mask(kind: VertexKind, valence: usize) -> VertexMask {
    match kind {
        VertexKind::Interior => {
            let b = beta(valence);
            VertexMask {
                vertex: 1.0 - b, // p∞ = (1 − βₙ)p + βₙ/n Σ pᵢ
                interior_neighbor: b / valence as f64,
                boundary_neighbor: 0.0,
                face: 0.0,
            }
        }
        VertexKind::Boundary => {
            VertexMask { vertex: 4.0 / 6.0, interior_neighbor: 0.0, boundary_neighbor: 1.0 / 6.0, face: 0.0 }
        }
        VertexKind::Corner => VertexMask::IDENTITY,
    }
}

/// Weights of a trisection point of boundary edge (near, far), the point at
/// a third of the way from `near`: over the two ends and `outer`, near's
/// other boundary neighbour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrisectionMask {
    /// Weight of the nearer end.
    pub near: f64,
    /// Weight of the farther end.
    pub far: f64,
    /// Weight of the nearer end's other boundary neighbour.
    pub outer: f64,
}

impl TrisectionMask {
    /// Sum of the weights (1 for an affine mask).
    pub fn total(&self) -> f64 {
        self.near + self.far + self.outer
    }
}

/// The trisection point next to `near` on a boundary edge (Kobbelt §4,
/// the ternary cubic B-spline): (p₋ + 16·near + 10·far)/27, or, when `near`
/// is a corner, the same with the phantom p₋ = 2·near − far, which is
/// (2·near + far)/3 (module docs).
///
/// ```
/// use subdiv_rules::sqrt3::trisection_mask;
/// let m = trisection_mask(false);
/// assert_eq!((m.near * 27.0, m.far * 27.0, m.outer * 27.0), (16.0, 10.0, 1.0));
/// let c = trisection_mask(true);
/// assert!((c.near - 2.0 / 3.0).abs() < 1e-15 && c.outer == 0.0);
/// ```
pub fn trisection_mask(near_is_corner: bool) -> TrisectionMask {
    if near_is_corner {
        // Phantom 2·near − far: (2near − far + 16near + 10far)/27 = (2near + far)/3.
        TrisectionMask { near: 2.0 / 3.0, far: 1.0 / 3.0, outer: 0.0 }
    } else {
        TrisectionMask { near: 16.0 / 27.0, far: 10.0 / 27.0, outer: 1.0 / 27.0 }
        // Kobbelt §4: [1, 16, 10]/27
    }
}

#[cfg(test)]
#[path = "sqrt3_tests.rs"]
mod tests;
