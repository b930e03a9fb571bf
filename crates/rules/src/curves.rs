//! Curve subdivision on open and closed polylines: Chaikin, cubic B-spline,
//! the 4-point scheme (uniform and variable tension) and the Deng-Ma
//! derivation of the 4-point scheme from Chaikin's points.
//!
//! Source: Deng & Ma 2011 as reproduced in Mahalingam & Koneru's report (DM11 in [references]) §3.1 (Eq. 1,
//! the averaging steps 2-4) and §3.1.1, with the sign of Q_{2i+1} corrected
//! ([correction D1]). These curve rules are the 1-D pictures of the surface schemes:
//! Chaikin ↔ Doo-Sabin, cubic B-spline ↔ Catmull-Clark, 4-point ↔ Deng-Ma
//! (surface tension ω_P = 16ω, [correction D4]).
//!
//! Every function refines once: a closed polygon of n points becomes 2n
//! points, an open polyline of n ≥ 2 points becomes 2n − 1 (Chaikin: 2n − 2,
//! see below). [`CurveScheme`] bundles the uniform schemes with
//! [`CurveScheme::refine_levels`].
//!
//! # Ordering of the output
//! - Chaikin, closed: for each edge PᵢPᵢ₊₁ the two points ¾Pᵢ + ¼Pᵢ₊₁,
//!   ¼Pᵢ + ¾Pᵢ₊₁.
//! - Cubic B-spline and 4-point: vertex point of P₀, edge point of P₀P₁,
//!   vertex point of P₁, …
//!
//! # End rules for open polylines
//! - **Chaikin**: the clamped (open-uniform) quadratic B-spline, knots
//!   0,0,0,1,…,L,L,L. Inserting every midpoint knot (Boehm's knot insertion)
//!   gives P₀, ½(P₀+P₁), then Chaikin's pair on every interior edge
//!   P₁P₂ … P_{n−3}P_{n−2}, then ½(P_{n−2}+P_{n−1}), P_{n−1}: the rule is
//!   stationary, keeps both endpoints and the curve is tangent to the end legs.
//!   n points become 2n − 2 (n ≥ 3; two points become the segment with its
//!   midpoint).
//! - **Cubic B-spline**: endpoints stay, edge points are midpoints, interior
//!   vertices get (1, 6, 1)/8: OpenSubdiv's crease-with-corner rule. It equals
//!   the uniform cubic B-spline of the polygon extended by the phantom points
//!   P₋₁ = 2P₀ − P₁ and Pₙ = 2P_{n−1} − P_{n−2} ((P₋₁ + 6P₀ + P₁)/8 = P₀), so the
//!   limit interpolates the endpoints with zero curvature there.
//! - **4-point** (and its variants): the same linear extrapolation
//!   P₋₁ = 2P₀ − P₁, Pₙ = 2P_{n−1} − P_{n−2}. Linear data is reproduced up to
//!   the ends; cubic reproduction holds only three coarse intervals away from
//!   them.
//!
//! [correction D1]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d1
//! [correction D4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d4
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md

use crate::constants::DEFAULT_FOUR_POINT_TENSION;
use crate::vec3::{add, lin2, scale, sub, Point3};

/// A uniform curve scheme with its parameter.
///
/// `#[non_exhaustive]`: more curve schemes may come, so a `match` outside
/// this crate needs a `_` arm:
///
/// ```compile_fail,E0004
/// use subdiv_rules::CurveScheme;
/// fn name(s: CurveScheme) -> &'static str {
///     match s {
///         CurveScheme::Chaikin => "chaikin",
///         CurveScheme::CubicBSpline => "cubic-b-spline",
///         CurveScheme::FourPoint { .. } => "four-point",
///     }
/// }
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum CurveScheme {
    /// Chaikin's corner cutting (quadratic B-spline), [`chaikin`].
    Chaikin,
    /// Cubic B-spline refinement, [`cubic_bspline`].
    CubicBSpline,
    /// The 4-point interpolatory scheme, [`four_point`], with tension ω.
    FourPoint {
        /// Tension ω, (0, 1/8) for a C¹ limit; 1/16 reproduces cubics.
        tension: f64,
    },
}

impl Default for CurveScheme {
    /// The classical 4-point scheme, ω = 1/16.
    fn default() -> Self {
        Self::FourPoint { tension: DEFAULT_FOUR_POINT_TENSION }
    }
}

impl CurveScheme {
    /// One level of refinement.
    pub fn refine(&self, points: &[Point3], closed: bool) -> Vec<Point3> {
        match *self {
            Self::Chaikin => chaikin(points, closed),
            Self::CubicBSpline => cubic_bspline(points, closed),
            Self::FourPoint { tension } => four_point(points, closed, tension),
        }
    }

    /// `levels` levels of refinement (0 returns a copy).
    ///
    /// ```
    /// use subdiv_rules::CurveScheme;
    /// let square = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    /// let fine = CurveScheme::default().refine_levels(&square, true, 3);
    /// assert_eq!(fine.len(), 4 * 8);
    /// assert_eq!(fine[8], square[1]); // interpolatory: old points are kept exactly
    /// ```
    pub fn refine_levels(&self, points: &[Point3], closed: bool, levels: usize) -> Vec<Point3> {
        let mut current = points.to_vec();
        for _ in 0..levels {
            current = self.refine(&current, closed);
        }
        current
    }
}

/// Point i of the polyline, cyclic when closed; an open polyline is extended
/// by the linear phantoms P₋₁ = 2P₀ − P₁, Pₙ = 2P_{n−1} − P_{n−2} (and only
/// those: i ∈ −1..=n). Needs n ≥ 2 when open.
fn extended(points: &[Point3], closed: bool, i: isize) -> Point3 {
    let n = points.len() as isize;
    if closed {
        return points[i.rem_euclid(n) as usize];
    }
    match i {
        -1 => lin2(2.0, points[0], -1.0, points[1]),
        i if i == n => lin2(2.0, points[(n - 1) as usize], -1.0, points[(n - 2) as usize]),
        i => points[i as usize],
    }
}

/// Chaikin's two points on edge a→b: (¾a + ¼b, ¼a + ¾b) (Deng-Ma §3.1 Eq. 1).
fn chaikin_pair(a: Point3, b: Point3) -> (Point3, Point3) {
    (lin2(0.75, a, 0.25, b), lin2(0.25, a, 0.75, b)) // Eq. (1): P_{2i} = ¾P_i + ¼P_{i+1}, P_{2i+1} = ¼P_i + ¾P_{i+1}
}

/// One level of Chaikin's corner cutting (Deng-Ma §3.1 Eq. 1). Closed: 2n
/// points, two per edge. Open: the clamped quadratic B-spline end rule (module
/// docs), which keeps both endpoints.
pub fn chaikin(points: &[Point3], closed: bool) -> Vec<Point3> {
    let n = points.len();
    if n < 2 {
        return points.to_vec();
    }
    if closed {
        let mut out = Vec::with_capacity(2 * n);
        for i in 0..n {
            let (a, b) = chaikin_pair(points[i], points[(i + 1) % n]);
            out.extend([a, b]);
        }
        return out;
    }
    if n == 2 {
        return vec![points[0], lin2(0.5, points[0], 0.5, points[1]), points[1]];
    }
    let mut out = Vec::with_capacity(2 * n - 2);
    out.push(points[0]);
    out.push(lin2(0.5, points[0], 0.5, points[1])); // clamped end: knot 0 has multiplicity 3
    for i in 1..n - 2 {
        let (a, b) = chaikin_pair(points[i], points[i + 1]);
        out.extend([a, b]);
    }
    out.push(lin2(0.5, points[n - 2], 0.5, points[n - 1]));
    out.push(points[n - 1]);
    out
}

/// One level of cubic B-spline refinement: vertex points
/// (Pᵢ₋₁ + 6Pᵢ + Pᵢ₊₁)/8 and edge midpoints (Deng-Ma §3.1 step 2, the average
/// of adjacent Chaikin points). Open polylines keep their endpoints (module
/// docs).
pub fn cubic_bspline(points: &[Point3], closed: bool) -> Vec<Point3> {
    let n = points.len();
    if n < 2 {
        return points.to_vec();
    }
    let vertex = |i: usize| {
        if !closed && (i == 0 || i == n - 1) {
            return points[i];
        }
        let (prev, next) = (points[(i + n - 1) % n], points[(i + 1) % n]);
        add(scale(add(prev, next), 0.125), scale(points[i], 0.75)) // §3.1 step 2: P̄_{2i} = ⅛P_{i−1} + ¾P_i + ⅛P_{i+1}
    };
    let edges = if closed { n } else { n - 1 };
    let mut out = Vec::with_capacity(2 * n);
    for i in 0..edges {
        out.push(vertex(i));
        out.push(lin2(0.5, points[i], 0.5, points[(i + 1) % n])); // §3.1 step 2: P̄_{2i+1} = ½(P_i + P_{i+1})
    }
    if !closed {
        out.push(points[n - 1]);
    }
    out
}

/// One level of the 4-point scheme with tension ω (Dyn-Levin-Gregory 1987;
/// Deng-Ma §3.1 step 4): old points are kept bit for bit and each edge gets
/// (½+ω)(Pᵢ + Pᵢ₊₁) − ω(Pᵢ₋₁ + Pᵢ₊₂). ω ∈ (0, 1/8) gives a C¹ limit, ω = 1/16
/// reproduces cubics. Open polylines use linear phantom end points (module
/// docs).
pub fn four_point(points: &[Point3], closed: bool, tension: f64) -> Vec<Point3> {
    interleave(points, closed, |i| {
        let p = |k: isize| extended(points, closed, k);
        let (a, b) = (add(p(i), p(i + 1)), add(p(i - 1), p(i + 2)));
        lin2(0.5 + tension, a, -tension, b) // §3.1 step 4: Q̄_{2i+1} = (½+ω)(P_i+P_{i+1}) − ω(P_{i−1}+P_{i+2})
    })
}

/// One level of the variable-tension 4-point scheme (Deng-Ma §3.1.1, with the
/// sign of [correction D1]): tension ωᵢ is attached to point Pᵢ and the edge point is
/// ½(Pᵢ + Pᵢ₊₁) + ωᵢ(Pᵢ₊₁ − Pᵢ₋₁) + ωᵢ₊₁(Pᵢ − Pᵢ₊₂). With all ωᵢ = ω it is
/// [`four_point`]. The report does not say which tensions the new points get,
/// so there is no multi-level variant.
///
/// # Panics
/// If `tensions.len() != points.len()`.
///
/// [correction D1]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d1
pub fn four_point_variable(points: &[Point3], closed: bool, tensions: &[f64]) -> Vec<Point3> {
    assert_eq!(tensions.len(), points.len(), "one tension per point");
    interleave(points, closed, |i| {
        let p = |k: isize| extended(points, closed, k);
        let n = points.len() as isize;
        let (wi, wj) = (tensions[i as usize], tensions[((i + 1) % n) as usize]);
        let mid = lin2(0.5, p(i), 0.5, p(i + 1));
        // §3.1.1 (D1 sign): ½(Q_{2i} + Q_{2i+1}) = ½(P_i+P_{i+1}) + ω_i(P_{i+1} − P_{i−1}) + ω_{i+1}(P_i − P_{i+2})
        add(mid, lin2(wi, sub(p(i + 1), p(i - 1)), wj, sub(p(i), p(i + 2))))
    })
}

/// The report's own construction of the 4-point scheme (Deng-Ma §3.1 steps 1,
/// 3, 4 and §3.1.1), kept as an executable derivation: Chaikin points
/// P^{k+1}, the moved points
/// Q_{2i} = Pᵢ + 8ωᵢ(P^{k+1}_{2i} − P^{k+1}_{2i−1}) and
/// Q_{2i+1} = Pᵢ₊₁ **+** 8ωᵢ₊₁(P^{k+1}_{2i+1} − P^{k+1}_{2i+2}) ([correction D1]: the
/// report prints −), then the averages Q̄_{2i} = ½(Q_{2i−1} + Q_{2i}) and
/// Q̄_{2i+1} = ½(Q_{2i} + Q_{2i+1}). The result equals
/// [`four_point_variable`] (and [`four_point`] for constant tension) up to
/// rounding: the old points come back as Pᵢ only to within an ulp or so, which
/// is why the direct formulas are the ones to use.
///
/// # Panics
/// If `tensions.len() != points.len()`.
///
/// [correction D1]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d1
///
/// A test oracle (the derivation the direct formulas are checked against),
/// compiled for the crate's unit tests only.
#[cfg(test)]
pub(crate) fn four_point_via_chaikin(points: &[Point3], closed: bool, tensions: &[f64]) -> Vec<Point3> {
    assert_eq!(tensions.len(), points.len(), "one tension per point");
    let n = points.len();
    if n < 2 {
        return points.to_vec();
    }
    let p = |k: isize| extended(points, closed, k);
    let w = |k: isize| tensions[k.rem_euclid(n as isize) as usize];
    // Chaikin points of edge k (Eq. 1): (P_{2k}, P_{2k+1}).
    let c = |k: isize| chaikin_pair(p(k), p(k + 1));
    // Step 3, the moved point near P_k on edge k: Q_{2k} = P_k + 8ω_k(P_{2k} − P_{2k−1}).
    let q_even = |k: isize| add(p(k), scale(sub(c(k).0, c(k - 1).1), 8.0 * w(k)));
    // Step 3 (D1 sign), near P_{k+1} on edge k: Q_{2k+1} = P_{k+1} + 8ω_{k+1}(P_{2k+1} − P_{2k+2}).
    let q_odd = |k: isize| add(p(k + 1), scale(sub(c(k).1, c(k + 1).0), 8.0 * w(k + 1)));
    let old = |i: isize| lin2(0.5, q_odd(i - 1), 0.5, q_even(i)); // step 4: Q̄_{2i} = ½(Q_{2i−1} + Q_{2i}) = P_i
    let edges = if closed { n } else { n - 1 };
    let mut out = Vec::with_capacity(2 * n);
    for i in 0..edges as isize {
        out.push(old(i));
        out.push(lin2(0.5, q_even(i), 0.5, q_odd(i))); // step 4: Q̄_{2i+1} = ½(Q_{2i} + Q_{2i+1})
    }
    if !closed {
        out.push(old(n as isize - 1));
    }
    out
}

/// Old points copied, `edge_point(i)` inserted after point i (on every edge
/// when closed, on the n − 1 edges when open).
fn interleave(points: &[Point3], closed: bool, edge_point: impl Fn(isize) -> Point3) -> Vec<Point3> {
    let n = points.len();
    if n < 2 {
        return points.to_vec();
    }
    let edges = if closed { n } else { n - 1 };
    let mut out = Vec::with_capacity(2 * n);
    for (i, &p) in points.iter().enumerate().take(edges) {
        out.push(p);
        out.push(edge_point(i as isize));
    }
    if !closed {
        out.push(points[n - 1]);
    }
    out
}

#[cfg(test)]
#[path = "curves_tests.rs"]
mod tests;
