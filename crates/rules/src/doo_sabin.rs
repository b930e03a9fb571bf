//! Doo-Sabin masks: the face-corner rule and the boundary rule.
//!
//! # Face-corner rule
//!
//! In a face V₀…V_{m−1} the new vertex of corner i is V'ᵢ = Σⱼ αᵢⱼVⱼ with
//! αᵢᵢ = (m+5)/(4m) and αᵢⱼ = (3 + 2cos(2π(i−j)/m))/(4m)
//! (Zheng & Cai 2005 §2, Eq. 1, ZC05 in [references]; the same
//! weights are Fan-Cheng-Lai §2 and Deng-Ma §3.2 step 1, [correction D3]). The
//! weights depend only on the offset k = (j − i) mod m, so one row
//! `w[k]` describes the whole face: the image of corner i is
//! `Σₖ w[k]·V_{(i+k) mod m}` ([`doo_sabin_weights`]). The face matrix is the
//! circulant `Circ(w)`; its eigenvalues are 1, ½ (the first harmonic pair) and
//! ¼ (all others), [correction Z8] ([`doo_sabin_eigenvalue`]).
//!
//! # First-step variants
//!
//! The interpolation methods' first steps (Zheng-Cai Eq. 4, Fan-Cheng-Lai
//! Eq. 1: V'ᵢ = λVᵢ + (1−λ)A) are method rules, in `subdiv-interp`; their
//! face rows are circulant too ([`circulant_eigenvalue`] applies).
//!
//! # Boundary rule
//!
//! Open meshes need a rule under which the boundary converges to the quadratic
//! B-spline (Chaikin curve) of each boundary loop (our requirement: the papers treat closed
//! meshes). We use:
//!
//! 1. **Face corners: unchanged.** Every corner of every face, boundary faces
//!    included, gets the face-corner rule above (Eq. 1).
//! 2. **Boundary points: two new vertices per boundary edge.** For a boundary
//!    edge A→B, `a = ¾A + ¼B` (near A) and `b = ¼A + ¾B` (near B)
//!    ([`BOUNDARY_EDGE_POINT`]).
//! 3. **Faces.** F-faces as usual; an E-face for every edge — on a boundary
//!    edge it is the quad (A_f, B_f, b, a) of the face's two images and the two
//!    boundary points; a V-face for every vertex — at a boundary vertex V with
//!    faces f₁…f_k (fan order) it is (a₋, V_{f₁}, …, V_{f_k}, a₊), the k images
//!    closed by the boundary points near V on its two boundary edges, so it has
//!    k + 2 corners (a triangle at a corner vertex, k = 1).
//!
//! Consequences, all tested below:
//! - The new boundary loop is a₀b₀a₁b₁… over the old loop's edges: exactly the
//!   closed Chaikin refinement of the old loop (`curves::chaikin`). Hence the
//!   boundary of the limit surface is the uniform quadratic B-spline of each
//!   boundary loop, and the point of that curve at boundary vertex V is
//!   (B₋ + 6V + B₊)/8 ([`BOUNDARY_CURVE_POINT`]).
//! - No face-corner image is modified, so every face, boundary faces included,
//!   keeps its centroid: face centroids are limit points at every level, on
//!   open meshes too ([how the error is measured]).
//! - On a regular quad mesh the rule is the tensor-product biquadratic
//!   B-spline with the boundary row of control points repeated: attaching the
//!   degenerate quad (A, B, B, A) to each boundary edge, Eq. 1 with m = 4 gives
//!   for corner A (9A + 3B + 3A + B)/16 = ¾A + ¼B = a.
//! - After one step every vertex has valence 4 except the boundary points,
//!   which have valence 3 and lie in two faces.
//!
//! # Interior vertices of valence 2
//!
//! An interior vertex V of valence 2 lies in two faces f₀ = (V, A, …, B) and
//! f₁ = (V, B, …, A) that share its two edges VA and VB. After one step its
//! images v₀ (in f₀) and v₁ (in f₁) would bound a digon V-face; the
//! refinement leaves it out (a face needs three corners), so v₀v₁ is an
//! ordinary edge between the E-faces of VA, (v₀, a₀, a₁, v₁), and of VB,
//! (v₁, b₁, b₀, v₀) — aᵢ, bᵢ the images of A and B in fᵢ. Nothing keeps the
//! midpoint of v₀v₁ (the digon's "centroid"): the surface does not pass
//! through it. What the surface does keep is the centroid of every face at
//! every level, and at the next level the edge v₀v₁ becomes an E-face whose
//! four corners are the images of v₀ and v₁ in the two quads above. With the
//! quad weights (9, 3, 1, 3)/16 of Eq. 1 its centroid is
//!
//! L_V = ⅜(v₀ + v₁) + 1/16·(a₀ + a₁ + b₀ + b₁)   ([`VALENCE_TWO_LIMIT`]),
//!
//! a limit point, symmetric in the two faces, and the point of the surface
//! that V's region shrinks to: the limit point associated with V. In the first
//! refined mesh a₀ and b₀ are v₀'s neighbours along f₀ (the images of the
//! corners after and before V's), a₁, b₁ v₁'s along f₁, so L_V is one mask on
//! the first step's images whatever the first-step rule (standard, Eq. 4,
//! two-phase); the limit matrices use it as the row of V. The row is not of
//! the symmetric Circ form (it weighs A's and B's images, not only V's), so
//! with such vertices the limit matrices are no longer D·S with S symmetric.
//!
//! **Source.** The requirement — boundary curve = quadratic B-spline of the
//! boundary polygon — is the property Nasri established for his Doo-Sabin
//! boundary rules (A. H. Nasri, *Polyhedral subdivision methods for free-form
//! surfaces*, ACM TOG 6(1):29–73, 1987, reference \[8\] of Zheng & Cai 2005).
//! Nasri's text was not available to us, so we do
//! not claim these are his exact masks; the rule above is the classical
//! repeated-boundary-row end condition of tensor-product B-splines carried to
//! arbitrary topology through the degenerate quad, and its Chaikin property is
//! proved by the tests of this module rather than by citation.
//!
//! [correction D3]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d3
//! [correction Z8]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#z8
//! [correction F6]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#f6
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md
//! [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured

use std::f64::consts::PI;
use std::sync::OnceLock;

/// Faces up to this size take their Doo-Sabin row from a table computed
/// once (by [`doo_sabin_weight`], so bit for bit the same values): limit
/// matrices and stencils ask for the row of every corner of every face, and
/// the cosines were a fifth of Nasri's setup time.
const TABLED_FACE_SIZE: usize = 16;

/// `table[m][k]` = [`doo_sabin_weight`]`(m, k)` for 3 ≤ m ≤ [`TABLED_FACE_SIZE`].
fn weight_table() -> &'static [[f64; TABLED_FACE_SIZE]; TABLED_FACE_SIZE + 1] {
    static TABLE: OnceLock<[[f64; TABLED_FACE_SIZE]; TABLED_FACE_SIZE + 1]> = OnceLock::new();
    TABLE.get_or_init(|| {
        let mut table = [[0.0; TABLED_FACE_SIZE]; TABLED_FACE_SIZE + 1];
        for (m, row) in table.iter_mut().enumerate().skip(3) {
            doo_sabin_weights_computed(m, &mut row[..m]);
        }
        table
    })
}

/// Weight of corner (i + k) mod m in the Doo-Sabin image of corner i of an
/// m-sided face (Zheng-Cai Eq. 1).
///
/// # Panics
/// If `m < 3` or `k >= m`.
pub fn doo_sabin_weight(m: usize, k: usize) -> f64 {
    assert!(m >= 3, "a face has at least 3 corners, got {m}");
    assert!(k < m, "offset {k} out of range for a face of {m} corners");
    let mf = m as f64;
    // cos(2πk/m) = cos(2π(m−k)/m): evaluate at the smaller offset so that
    // rows are exactly symmetric (the face matrices stay exactly symmetric).
    let k = k.min(m - k);
    if k == 0 {
        (mf + 5.0) / (4.0 * mf) // Eq. (1): α_ii = (m+5)/(4m)
    } else {
        (3.0 + 2.0 * (2.0 * PI * k as f64 / mf).cos()) / (4.0 * mf) // Eq. (1): α_ij = (3 + 2cos(2π(i−j)/m))/(4m)
    }
}

/// Fills `out` (length m) with the Doo-Sabin row of an m-sided face:
/// `out[k]` is the weight of corner (i + k) mod m in the image of corner i
/// (Zheng-Cai Eq. 1). The row is the same for every corner i.
///
/// ```
/// let mut w = [0.0; 4];
/// subdiv_rules::doo_sabin_weights(4, &mut w);
/// assert_eq!(w, [9.0 / 16.0, 3.0 / 16.0, 1.0 / 16.0, 3.0 / 16.0]);
/// ```
///
/// # Panics
/// If `m < 3` or `out.len() != m`.
#[inline]
pub fn doo_sabin_weights(m: usize, out: &mut [f64]) {
    assert_eq!(out.len(), m, "weight buffer length must equal the face size");
    if (3..=TABLED_FACE_SIZE).contains(&m) {
        out.copy_from_slice(&weight_table()[m][..m]);
    } else {
        doo_sabin_weights_computed(m, out);
    }
}

/// [`doo_sabin_weights`] evaluated from Eq. (1).
fn doo_sabin_weights_computed(m: usize, out: &mut [f64]) {
    if m == 4 {
        // Exact dyadic values (the biquadratic B-spline mask); cos(3π/2)
        // would give 3/16 − 3e-17 for the last one.
        out.copy_from_slice(&[9.0 / 16.0, 3.0 / 16.0, 1.0 / 16.0, 3.0 / 16.0]);
        return;
    }
    for (k, w) in out.iter_mut().enumerate() {
        *w = doo_sabin_weight(m, k);
    }
}

/// Eigenvalue k (k = 0…m−1) of the Doo-Sabin face circulant, in closed form:
/// 1 for k = 0, ½ for the first harmonic pair k = 1, m−1, ¼ otherwise
/// ([correction Z8]).
///
/// # Panics
/// If `m < 3` or `k >= m`.
///
/// [correction Z8]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#z8
pub fn doo_sabin_eigenvalue(m: usize, k: usize) -> f64 {
    assert!(m >= 3 && k < m, "need m >= 3 and k < m, got m = {m}, k = {k}");
    if k == 0 {
        1.0
    } else if k == 1 || k == m - 1 {
        0.5
    } else {
        0.25
    }
}

/// Eigenvalue k of the circulant matrix whose first row is `row`
/// (`row[j]` = weight of offset j), for a symmetric row (`row[j] == row[m−j]`):
/// Σⱼ `row[j]`·cos(2πjk/m). Applies to [`doo_sabin_weights`] and to any
/// symmetric circulant row.
pub fn circulant_eigenvalue(row: &[f64], k: usize) -> f64 {
    let m = row.len() as f64;
    row.iter().enumerate().map(|(j, w)| w * (2.0 * PI * (j * k) as f64 / m).cos()).sum()
}

/// Weights of a new boundary point on a boundary edge, over the edge's end
/// near the point and its far end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryEdgePoint {
    /// Weight of the nearer endpoint.
    pub near: f64,
    /// Weight of the farther endpoint.
    pub far: f64,
}

/// The Doo-Sabin boundary rule: each boundary edge A→B gets the two new
/// vertices ¾A + ¼B and ¼A + ¾B (Chaikin's points). See the module docs for
/// the faces they close and why the boundary converges to the quadratic
/// B-spline of the boundary loop.
pub const BOUNDARY_EDGE_POINT: BoundaryEdgePoint = BoundaryEdgePoint { near: 0.75, far: 0.25 };

/// The clamped end of a sharp curve at a corner: on a sharp edge whose far
/// end is a corner, the point near the other end is the edge's midpoint,
/// ½·near + ½·far (and an edge between two corners gets its midpoint as its
/// only new point), while the corner itself is kept. This is the end rule of
/// the clamped quadratic B-spline (`curves::chaikin` on an open polyline), so
/// a sharp curve interpolates its corners (`subdiv-stencil`'s Doo-Sabin
/// module, "Creases and corners").
pub const CLAMPED_EDGE_POINT: BoundaryEdgePoint = BoundaryEdgePoint { near: 0.5, far: 0.5 };

/// Weights `[B₋, V, B₊]` of the limit point of a crease or boundary vertex V
/// (not a corner) whose two sharp neighbours are B₋ and B₊: the midpoint of
/// V's segment of the refined sharp polygon, from the point near V on edge
/// VB₋ to the one on VB₊ — each ¾V + ¼B ([`BOUNDARY_EDGE_POINT`]), or ½V + ½B
/// when that neighbour is a corner ([`CLAMPED_EDGE_POINT`]). That midpoint
/// stays the midpoint of the segment's descendants, which shrink to it, so it
/// is a point of the sharp curve. Without corner neighbours it is
/// [`BOUNDARY_CURVE_POINT`], bit for bit.
///
/// ```
/// use subdiv_rules::doo_sabin::{sharp_curve_point, BOUNDARY_CURVE_POINT};
/// assert_eq!(sharp_curve_point(false, false), BOUNDARY_CURVE_POINT);
/// assert_eq!(sharp_curve_point(true, false), [0.25, 0.625, 0.125]);
/// ```
pub fn sharp_curve_point(prev_is_corner: bool, next_is_corner: bool) -> [f64; 3] {
    let near_point = |far_is_corner: bool| if far_is_corner { CLAMPED_EDGE_POINT } else { BOUNDARY_EDGE_POINT };
    let (prev, next) = (near_point(prev_is_corner), near_point(next_is_corner));
    // Dyadic weights: every product and sum here is exact.
    [0.5 * prev.far, 0.5 * (prev.near + next.near), 0.5 * next.far]
}

/// Weights `[B₋, V, B₊]` of the point of the limit boundary curve associated
/// with boundary vertex V (B₋, B₊ its boundary neighbours): the uniform
/// quadratic B-spline of the boundary loop at the middle of V's span,
/// (B₋ + 6V + B₊)/8.
pub const BOUNDARY_CURVE_POINT: [f64; 3] = [0.125, 0.75, 0.125];

/// Weights of the limit point of an interior valence-2 vertex on the first
/// step's images (module docs, "Interior vertices of valence 2"): `own` on
/// each of its two images, `adjacent` on each of the four images next to
/// them in their faces. `2·own + 4·adjacent = 1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ValenceTwoLimit {
    /// Weight of each of the vertex's own two images, ⅜.
    pub own: f64,
    /// Weight of each adjacent image in the same face, 1/16.
    pub adjacent: f64,
}

/// The valence-2 limit mask: ⅜ per own image, 1/16 per adjacent image — the
/// centroid of the second-level E-face of the edge between the two images
/// (quad weights (9 + 3)/16 on the edge's ends, (3 + 1)/16 on the far ends,
/// averaged over four corners).
pub const VALENCE_TWO_LIMIT: ValenceTwoLimit = ValenceTwoLimit { own: 0.375, adjacent: 0.0625 };

#[cfg(test)]
#[path = "doo_sabin_tests.rs"]
mod tests;
