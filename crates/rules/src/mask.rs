//! Mask types shared by the primal schemes (Catmull-Clark, Loop).
//!
//! A mask is a set of weights over a *named* neighbourhood, never over mesh
//! indices: the caller (the stencil builder) knows which mesh vertex plays
//! which role and multiplies. Every mask of this crate is uniform over the
//! members of a role (all interior edge neighbours get the same weight, …), so
//! a mask is a handful of numbers.
//!
//! The neighbourhood convention is in the docs of [`VertexMask`].

/// Where a vertex sits, which decides the rule applied to it.
///
/// This is OpenSubdiv's `EDGE_AND_CORNER` boundary interpolation: boundary
/// edges are B-spline creases and a vertex in a single face is a corner that
/// stays put.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VertexKind {
    /// All edges at the vertex have two faces (a closed fan).
    Interior,
    /// On the boundary, in two or more faces.
    Boundary,
    /// On the boundary, in exactly one face.
    Corner,
}

impl VertexKind {
    /// Classifies a vertex from whether it lies on the boundary and how many
    /// faces contain it.
    ///
    /// ```
    /// use subdiv_rules::VertexKind;
    /// assert_eq!(VertexKind::classify(false, 5), VertexKind::Interior);
    /// assert_eq!(VertexKind::classify(true, 2), VertexKind::Boundary);
    /// assert_eq!(VertexKind::classify(true, 1), VertexKind::Corner);
    /// ```
    pub fn classify(on_boundary: bool, face_count: usize) -> Self {
        match (on_boundary, face_count) {
            (false, _) => Self::Interior,
            (true, 0 | 1) => Self::Corner,
            (true, _) => Self::Boundary,
        }
    }
}

/// Weights of a vertex-centred rule (a vertex point or a limit point).
///
/// The new point is
///
/// ```text
/// vertex·V + interior_neighbor·Σ(interior-edge neighbours)
///          + boundary_neighbor·Σ(boundary-edge neighbours) + face·Σ(face terms)
/// ```
///
/// where the "face term" of each face is named by the function that returns
/// the mask (a Catmull-Clark face point, or the far corner of a quad).
///
/// Neighbourhood convention (the same as `subdiv-mesh`'s vertex fan): a vertex
/// V has neighbours E₁…Eₙ and faces f₁…f_k with fᵢ = (V, Eᵢ, …, Eᵢ₊₁), so the
/// edge VEᵢ lies in faces fᵢ₋₁ and fᵢ. On the boundary the fan is open: E₁ and
/// Eₙ are the two *boundary neighbours* (joined to V by boundary edges) and
/// k = n − 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexMask {
    /// Weight of the vertex V itself.
    pub vertex: f64,
    /// Weight of each neighbour joined to V by an interior edge.
    pub interior_neighbor: f64,
    /// Weight of each of the (two) neighbours joined to V by a boundary edge.
    pub boundary_neighbor: f64,
    /// Weight of each face term (see the function returning the mask).
    pub face: f64,
}

impl VertexMask {
    /// The identity mask: the point stays where it is (corners).
    pub const IDENTITY: Self = Self { vertex: 1.0, interior_neighbor: 0.0, boundary_neighbor: 0.0, face: 0.0 };

    /// Sum of all weights for a vertex with the given numbers of interior-edge
    /// neighbours, boundary-edge neighbours and face terms (1 for an affine
    /// mask).
    pub fn total(&self, interior_neighbors: usize, boundary_neighbors: usize, faces: usize) -> f64 {
        self.vertex
            + self.interior_neighbor * interior_neighbors as f64
            + self.boundary_neighbor * boundary_neighbors as f64
            + self.face * faces as f64
    }
}

/// Weights of an edge point, over the edge's two endpoints and the other
/// corners of its (up to two) faces.
///
/// The new point is
///
/// ```text
/// end·(A + B) + left·Σ(other corners of the left face) + right·Σ(other corners of the right face)
/// ```
///
/// where "other" means every corner of that face except A and B. On a boundary edge there is no right face and
/// `right` is 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeMask {
    /// Weight of each endpoint.
    pub end: f64,
    /// Weight of each corner of the first face other than the endpoints.
    pub left: f64,
    /// Weight of each corner of the second face other than the endpoints.
    pub right: f64,
}

impl EdgeMask {
    /// The boundary (crease) edge rule of every primal scheme: the midpoint.
    pub const MIDPOINT: Self = Self { end: 0.5, left: 0.0, right: 0.0 };

    /// Sum of all weights when the left face has `m_left` corners and the
    /// right face `m_right` (`None` on the boundary).
    pub fn total(&self, m_left: usize, m_right: Option<usize>) -> f64 {
        2.0 * self.end + self.left * (m_left - 2) as f64 + m_right.map_or(0.0, |m| self.right * (m - 2) as f64)
    }
}

/// Weights of a vertex-centred mask that is not uniform around its vertex:
/// the limit point of a **dart** ([`crate::catmull_clark::dart_limit_mask`],
/// [`crate::loop_scheme::dart_limit_mask`]).
///
/// The fan of the dart V (valence n) is numbered from its sharp edge: E₀ is
/// the far end of the infinitely sharp edge VE₀, E₁…Eₙ₋₁ follow in fan order
/// and face i lies between Eᵢ and Eᵢ₊₁ (indices mod n). The new point is
///
/// ```text
/// vertex·V + Σᵢ edge[i]·Eᵢ + Σᵢ far_corner[i]·Fᵢ
/// ```
///
/// where Fᵢ is the corner of quad i = (V, Eᵢ, Fᵢ, Eᵢ₊₁) diagonal to V
/// (Catmull-Clark; `far_corner` is empty for Loop, whose triangles have no
/// far corner). The masks are symmetric about the crease
/// (`edge[i] == edge[n − i]`, `far_corner[i] == far_corner[n − 1 − i]`), so
/// either direction around the fan gives the same point.
#[derive(Clone, Debug, PartialEq)]
pub struct DartMask {
    /// Weight of the dart V.
    pub vertex: f64,
    /// `edge[i]`: weight of the edge neighbour Eᵢ, E₀ the crease's far end.
    pub edge: Vec<f64>,
    /// `far_corner[i]`: weight of the far corner Fᵢ of quad i (empty for Loop).
    pub far_corner: Vec<f64>,
}

impl DartMask {
    /// Sum of all weights (1: the masks are affine).
    pub fn total(&self) -> f64 {
        self.vertex + self.edge.iter().sum::<f64>() + self.far_corner.iter().sum::<f64>()
    }

    /// The identity over a fan of `n` edges and `far_corners` far corners: the
    /// answer for a degenerate valence (below 2), which no manifold mesh has.
    pub(crate) fn identity(n: usize, far_corners: usize) -> Self {
        Self { vertex: 1.0, edge: vec![0.0; n], far_corner: vec![0.0; far_corners] }
    }

    /// Divides every weight by their sum.
    pub(crate) fn normalized(mut self) -> Self {
        let total = self.total();
        self.vertex /= total;
        self.edge.iter_mut().for_each(|w| *w /= total);
        self.far_corner.iter_mut().for_each(|w| *w /= total);
        self
    }
}

/// The ring weights' shape at a dart: uⱼ = (ρʲ + ρⁿ⁻ʲ)/(1 + ρⁿ) for
/// j = 0..=n, the solution of uⱼ₋₁ − (ρ + 1/ρ)uⱼ + uⱼ₊₁ = 0 (0 < j < n) with
/// u₀ = uₙ = 1, for 0 < ρ < 1. Powers of ρ are built by products, so a large
/// n underflows to 0 instead of overflowing (ρⁿ ≈ 0: uⱼ = ρʲ + ρⁿ⁻ʲ).
pub(crate) fn dart_ring_shape(rho: f64, n: usize) -> Vec<f64> {
    let mut powers = Vec::with_capacity(n + 1);
    let mut p = 1.0;
    for _ in 0..=n {
        powers.push(p);
        p *= rho;
    }
    let den = 1.0 + powers[n];
    (0..=n).map(|j| (powers[j] + powers[n - j]) / den).collect()
}
