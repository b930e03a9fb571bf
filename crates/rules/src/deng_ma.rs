//! Deng-Ma's interpolatory scheme derived from Doo-Sabin: the moved vertices
//! and the tension ω_P (global or displacement-safe variable).
//!
//! Source: `seeds/deng-ma-interpolatory-doo-sabin-report.txt` §3.3 (moved
//! vertices) and §3.4 (variable tension), with ERRATA D2 (Q̄ᵢ = **P** + …) and
//! D5 (the missing constant C and the cyclic index).
//!
//! # The rule at one old vertex P (§3.3)
//! 1. Qᵢ, i = 1…m: the Doo-Sabin images of P in its m faces, in fan order
//!    ([`crate::doo_sabin_weights`]); G = (Q₁ + … + Q_m)/m.
//! 2. Moved vertices Q̄ᵢ = P + ω_P(Qᵢ − G) ([`moved_images`]). Their centroid
//!    is P itself, which is why the scheme keeps every old vertex.
//! 3. The refined mesh connects like Catmull-Clark: the new face point of a
//!    face is the centroid of the moved vertices of its corners; the new edge
//!    point of an edge is the centroid of the four moved vertices of its
//!    E-face (the images of both endpoints in both faces); old vertices stay
//!    ([`crate::centroid`]).
//!
//! ω_P = 1 is the surface analogue of the 4-point curve scheme with ω = 1/16
//! (ERRATA D4: in the curve picture Q − G = (P_{2i} − P_{2i−1})/2, so
//! ω_P = 16ω); the test `regular_grid_reproduces_four_point` checks it.
//!
//! # Variable tension (§3.4)
//! Number P's neighbours P₁…P_m so that face i contains the edges PPᵢ and
//! PPᵢ₊₁ (the report does not define Pᵢ; this is the reading under which its
//! formula bounds the moved vertices by the face's own edges). Then, with
//! indices mod m (ERRATA D5: the printed `(i+1)%4` / `%m` with 1-based
//! indices means the cyclic successor) and the inner minimum over i = 1…m,
//!
//! ω_P = min{ 1, λ/max(m, 4) · minᵢ [ min(‖Pᵢ − P‖, ‖Pᵢ₊₁ − P‖) / ‖Qᵢ − G‖ ] },  0 < λ ≤ 1
//!
//! ([`variable_omega`]). Consequently every moved vertex satisfies
//! ω_P‖Qᵢ − G‖ ≤ λ/4 · min(‖Pᵢ − P‖, ‖Pᵢ₊₁ − P‖).
//!
//! # Displacement safety
//! The report calls the scheme displacement-safe if, for a constant
//! 0 < C < 1, every new edge point E and face point F satisfy
//! d_E = ‖E − (P₁+P₂)/2‖ ≤ C‖P₁ − P₂‖ and d_F = ‖F − centroid‖ ≤ C·min (edge
//! lengths of the face). The printed face condition lacks C (ERRATA D5); here
//! C is explicit ([`DisplacementBound`]). From the bound above, the variable
//! ω_P gives d_E ≤ (λ/4)‖P₁ − P₂‖, so the edge condition holds with C = λ/4;
//! for faces it gives d_F ≤ (λ/4)·(longest edge of the face), which implies
//! the face condition only when the face's edges are comparable in length —
//! the report's face condition is not guaranteed by its own ω_P.

use crate::constants::DEFAULT_DENG_MA_OMEGA;
use crate::vec3::{add, centroid, dist, scale, sub, Point3};

/// The tension of the Deng-Ma scheme.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tension {
    /// One ω for every vertex, 0 < ω ≤ 1 (§3.3). ω = 1 is the default.
    Global(f64),
    /// The displacement-safe ω_P of §3.4 with shape parameter λ ∈ (0, 1].
    Variable {
        /// λ of §3.4: smaller values pull the surface towards the mesh.
        lambda: f64,
    },
}

impl Default for Tension {
    fn default() -> Self {
        Self::Global(DEFAULT_DENG_MA_OMEGA)
    }
}

impl Tension {
    /// ω_P at vertex P with neighbours `ring` and Doo-Sabin images `images`
    /// (see [`variable_omega`] for the layout).
    pub fn omega(&self, p: Point3, ring: &[Point3], images: &[Point3]) -> f64 {
        match *self {
            Self::Global(omega) => omega,
            Self::Variable { lambda } => variable_omega(p, ring, images, lambda),
        }
    }
}

/// The variable tension ω_P of §3.4 (formula in the module docs, indices as
/// corrected by ERRATA D5).
///
/// `images[i]` is Qᵢ, the Doo-Sabin image of P in face i, and face i contains
/// the edges P–`ring[i]` and P–`ring[i+1]`. For an interior vertex
/// `ring.len() == images.len()` and the index wraps; for a boundary vertex
/// (open fan) `ring.len() == images.len() + 1` and it does not. m in
/// max(m, 4) is the number of faces. Faces whose image coincides with G
/// (Qᵢ = G) do not constrain ω_P.
///
/// # Panics
/// If `images` is empty or `ring` has neither length.
pub fn variable_omega(p: Point3, ring: &[Point3], images: &[Point3], lambda: f64) -> f64 {
    let m = images.len();
    assert!(m > 0, "a vertex with no faces");
    assert!(ring.len() == m || ring.len() == m + 1, "{} neighbours do not fit {m} faces", ring.len());
    let g = centroid(images);
    let mut ratio = f64::INFINITY;
    for (i, &q) in images.iter().enumerate() {
        let spread = dist(q, g);
        if spread == 0.0 {
            continue;
        }
        let next = ring[(i + 1) % ring.len()]; // D5: P_{(i mod m)+1}, cyclic
        let reach = dist(ring[i], p).min(dist(next, p)); // §3.4: min{‖P_i − P‖, ‖P_{i+1} − P‖}
        ratio = ratio.min(reach / spread); // §3.4: min over i = 1..m of the quotients
    }
    let m_eff = m.max(4) as f64;
    (lambda / m_eff * ratio).min(1.0) // §3.4: ω_P = min{1, λ/max(m,4) · min{…}}
}

/// Writes the moved vertices Q̄ᵢ = P + ω(Qᵢ − G), G the centroid of `images`
/// (§3.3 with ERRATA D2: the printed "Pᵢ +" is P).
///
/// ```
/// use subdiv_rules::deng_ma::moved_images;
/// let p = [0.0, 0.0, 1.0];
/// let q = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]];
/// let mut moved = [[0.0; 3]; 4];
/// moved_images(p, &q, 0.5, &mut moved);
/// assert_eq!(moved[0], [0.5, 0.0, 1.0]);
/// assert_eq!(subdiv_rules::centroid(&moved), p);
/// ```
///
/// # Panics
/// If `images` is empty or `out.len() != images.len()`.
pub fn moved_images(p: Point3, images: &[Point3], omega: f64, out: &mut [Point3]) {
    assert_eq!(out.len(), images.len(), "one moved vertex per image");
    let g = centroid(images); // §3.3: G = (Q_1 + … + Q_m)/m
    for (o, &q) in out.iter_mut().zip(images) {
        *o = add(p, scale(sub(q, g), omega)); // §3.3 (D2): Q̄_i = P + ω_P(Q_i − G)
    }
}

/// d_E / ‖P₁ − P₂‖: how far a new edge point strays from the edge midpoint,
/// relative to the edge length (§3.4).
pub fn edge_displacement_ratio(edge_point: Point3, p1: Point3, p2: Point3) -> f64 {
    let mid = scale(add(p1, p2), 0.5);
    dist(edge_point, mid) / dist(p1, p2) // §3.4: d_E = ‖E^{k+1} − (P_1 + P_2)/2‖
}

/// d_F / (shortest edge): how far a new face point strays from the centroid
/// of the face's corners, relative to the face's shortest edge (§3.4, for a
/// face of any size).
///
/// # Panics
/// If `corners` has fewer than 3 points.
pub fn face_displacement_ratio(face_point: Point3, corners: &[Point3]) -> f64 {
    let m = corners.len();
    assert!(m >= 3, "a face has at least 3 corners, got {m}");
    let shortest = (0..m).map(|i| dist(corners[i], corners[(i + 1) % m])).fold(f64::INFINITY, f64::min); // D5: min over cyclic edges P_i P_{(i mod m)+1}
    dist(face_point, centroid(corners)) / shortest // §3.4: d_F = ‖F^{k+1} − centroid‖
}

/// The displacement-safety conditions of §3.4 with the constant C made
/// explicit (ERRATA D5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DisplacementBound {
    /// The constant C, 0 < C < 1.
    pub c: f64,
}

impl DisplacementBound {
    /// d_E ≤ C‖P₁ − P₂‖.
    pub fn edge_ok(&self, edge_point: Point3, p1: Point3, p2: Point3) -> bool {
        edge_displacement_ratio(edge_point, p1, p2) <= self.c
    }

    /// d_F ≤ C·(shortest edge of the face).
    pub fn face_ok(&self, face_point: Point3, corners: &[Point3]) -> bool {
        face_displacement_ratio(face_point, corners) <= self.c
    }
}

#[cfg(test)]
#[path = "deng_ma_tests.rs"]
mod tests;
