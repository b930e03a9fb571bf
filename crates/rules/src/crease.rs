//! Sharp features: the options and rules of OpenSubdiv's `Sdc::Crease`
//! and `Sdc::Options`, on sharpness values alone (no mesh).
//!
//! Sharpness is an `f32` as in OpenSubdiv: 0 smooth, ≥ 10 infinitely sharp
//! (never decays), in between semi-sharp. Per level:
//!
//! - **decay** ([`CreaseMethod::subdivide_edge_sharpness`]): uniform
//!   s → s − 1 (0 once s ≤ 1); Chaikin: each half of an edge at vertex v gets
//!   ¾s + ¼·(mean of the *other* semi-sharp edges at v) − 1, clamped at 0.
//!   Vertex (corner) sharpness decays uniformly under both methods.
//! - **rule** of a vertex ([`vertex_rule`]): sharp vertex or ≥ 3 sharp edges
//!   → [`Rule::Corner`], 2 → [`Rule::Crease`], 1 → [`Rule::Dart`],
//!   0 → [`Rule::Smooth`]. Boundary edges count as infinitely sharp.
//! - **transition** ([`fractional_weight`]): where the rule before a step
//!   (parent) differs from the rule after it (child), the new vertex point is
//!   w·(parent mask) + (1 − w)·(child mask), w the mean of the sharpness
//!   values that decay to 0 in this step, clamped to 1.
//!
//! The arithmetic is done in `f32` in OpenSubdiv's order, so the values (and
//! the weights taken from them) are the same bits as OpenSubdiv's.

use std::fmt;
use std::str::FromStr;

/// Sharpness of a smooth edge or vertex.
pub const SHARPNESS_SMOOTH: f32 = 0.0;
/// Sharpness from which an edge or vertex is infinitely sharp.
pub const SHARPNESS_INFINITE: f32 = 10.0;

/// Whether `s` is smooth (≤ 0).
#[inline]
pub fn is_smooth(s: f32) -> bool {
    s <= SHARPNESS_SMOOTH
}
/// Whether `s` is sharp at all (> 0).
#[inline]
pub fn is_sharp(s: f32) -> bool {
    s > SHARPNESS_SMOOTH
}
/// Whether `s` is infinitely sharp (≥ 10).
#[inline]
pub fn is_infinite(s: f32) -> bool {
    s >= SHARPNESS_INFINITE
}
/// Whether `s` is semi-sharp (in (0, 10)).
#[inline]
pub fn is_semi_sharp(s: f32) -> bool {
    SHARPNESS_SMOOTH < s && s < SHARPNESS_INFINITE
}

/// One level's uniform decay: s − 1 while s > 1, then 0; infinite stays.
#[inline]
pub fn decrement(s: f32) -> f32 {
    if is_smooth(s) {
        SHARPNESS_SMOOTH
    } else if is_infinite(s) {
        SHARPNESS_INFINITE
    } else if s > 1.0 {
        s - 1.0
    } else {
        SHARPNESS_SMOOTH
    }
}

/// The rule that makes a vertex's new point (OpenSubdiv `Sdc::Crease::Rule`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Rule {
    /// No sharp edge: the scheme's smooth mask.
    Smooth,
    /// One sharp edge: the smooth mask (the crease fades out here); its
    /// limit point: [`DartLimit`].
    Dart,
    /// Two sharp edges: the crease (curve) mask along them.
    Crease,
    /// A sharp vertex or three or more sharp edges: the point stays.
    Corner,
}

impl Rule {
    /// Whether the vertex gets the smooth mask (smooth or dart).
    #[inline]
    pub fn is_smooth_mask(self) -> bool {
        matches!(self, Rule::Smooth | Rule::Dart)
    }
}

/// The rule of a vertex from its own sharpness and its number of sharp
/// incident edges (boundary edges included).
///
/// ```
/// use subdiv_rules::crease::{vertex_rule, Rule};
/// assert_eq!(vertex_rule(0.0, 0), Rule::Smooth);
/// assert_eq!(vertex_rule(0.0, 1), Rule::Dart);
/// assert_eq!(vertex_rule(0.0, 2), Rule::Crease);
/// assert_eq!(vertex_rule(0.0, 3), Rule::Corner);
/// assert_eq!(vertex_rule(0.5, 0), Rule::Corner);
/// ```
#[inline]
pub fn vertex_rule(vertex_sharpness: f32, sharp_edges: usize) -> Rule {
    if is_sharp(vertex_sharpness) {
        return Rule::Corner;
    }
    match sharp_edges {
        0 => Rule::Smooth,
        1 => Rule::Dart,
        2 => Rule::Crease,
        _ => Rule::Corner,
    }
}

/// How semi-sharp edges decay from level to level (`Sdc::Options::CreasingMethod`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CreaseMethod {
    /// Every sharpness decays by 1 per level.
    #[default]
    Uniform,
    /// Chaikin's averaging: an edge half takes ¼ of the mean of the other
    /// semi-sharp edges at its vertex.
    Chaikin,
}

impl CreaseMethod {
    /// Sharpness of the half at vertex v of an edge of sharpness `s`, where
    /// `incident` lists the sharpness of every edge at v (this one included).
    ///
    /// ```
    /// use subdiv_rules::crease::CreaseMethod;
    /// assert_eq!(CreaseMethod::Uniform.subdivide_edge_sharpness(2.5, &[2.5, 0.75]), 1.5);
    /// // ¾·2.5 + ¼·0.75 − 1 = 1.0625
    /// assert_eq!(CreaseMethod::Chaikin.subdivide_edge_sharpness(2.5, &[2.5, 0.75, 0.0]), 1.0625);
    /// // A lone semi-sharp edge decays uniformly; infinite edges are not averaged.
    /// assert_eq!(CreaseMethod::Chaikin.subdivide_edge_sharpness(2.5, &[2.5, 10.0]), 1.5);
    /// ```
    pub fn subdivide_edge_sharpness(self, s: f32, incident: &[f32]) -> f32 {
        if self == CreaseMethod::Uniform || incident.len() < 2 {
            return decrement(s);
        }
        if is_smooth(s) {
            return SHARPNESS_SMOOTH;
        }
        if is_infinite(s) {
            return SHARPNESS_INFINITE;
        }
        let (mut sum, mut count) = (0.0f32, 0u32);
        for &t in incident.iter().filter(|&&t| is_semi_sharp(t)) {
            sum += t;
            count += 1;
        }
        let mut s = s;
        if count > 1 {
            // ¾ of its own sharpness + ¼ of the mean of the others.
            let others = (sum - s) / (count - 1) as f32;
            s = 0.75 * s + 0.25 * others;
        }
        s -= 1.0;
        if is_sharp(s) {
            s
        } else {
            SHARPNESS_SMOOTH
        }
    }
}

/// The weight w of the parent mask where a vertex's rule changes in a step
/// (`Sdc::Crease::ComputeFractionalWeightAtVertex`): the mean of the
/// sharpness values that decay to 0 in this step — the vertex's own, and each
/// incident edge's (uniform: edges with 0 < s ≤ 1; Chaikin: edges whose half
/// at this vertex becomes 0, `child_edges`) — clamped to ≤ 1; 0 if none.
pub fn fractional_weight(
    method: CreaseMethod,
    parent_vertex: f32,
    child_vertex: f32,
    parent_edges: &[f32],
    child_edges: &[f32],
) -> f32 {
    let (mut sum, mut count) = (0.0f32, 0u32);
    if is_sharp(parent_vertex) && is_smooth(child_vertex) {
        sum = parent_vertex;
        count = 1;
    }
    for (i, &p) in parent_edges.iter().enumerate() {
        let decays = match method {
            CreaseMethod::Uniform => is_sharp(p) && p <= 1.0,
            CreaseMethod::Chaikin => is_sharp(p) && is_smooth(child_edges[i]),
        };
        if decays {
            sum += p;
            count += 1;
        }
    }
    if count == 0 {
        return 0.0;
    }
    let w = sum / count as f32;
    if w > 1.0 {
        1.0
    } else {
        w
    }
}

/// How boundary vertices are treated (`Sdc::Options::VtxBoundaryInterpolation`).
/// Boundary edges are infinitely sharp in every mode.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BoundaryInterpolation {
    /// Boundary edges are creases, and the faces at boundary vertices whose
    /// boundary edges were not tagged infinitely sharp are holes: they are
    /// refined (their points support the surface) but not part of it.
    None,
    /// Boundary edges are creases (the boundary is the B-spline curve of the
    /// boundary polygon), corners are not sharpened.
    EdgeOnly,
    /// As `EdgeOnly`, and a boundary vertex in one face is a corner (stays).
    #[default]
    EdgeAndCorner,
}

/// How a face-varying channel (UVs) is interpolated
/// (`Sdc::Options::FVarLinearInterpolation`): which of its values are
/// linear (kept, with linear edges) instead of smooth.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FVarInterpolation {
    /// Smooth everywhere, boundaries and seams included (as the boundary
    /// rule of the vertices).
    LinearNone,
    /// Smooth, with the corners of the channel (values in one face) kept.
    LinearCornersOnly,
    /// As corners-only, also where three or more seams meet.
    LinearCornersPlus1,
    /// As plus1, also darts and concave corners of the channel.
    LinearCornersPlus2,
    /// Linear along every boundary and seam, smooth inside.
    LinearBoundaries,
    /// Linear (bilinear) everywhere.
    #[default]
    LinearAll,
}

/// How Catmull-Clark treats triangles (`Sdc::Options::TriangleSubdivision`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TriangleRule {
    /// Triangles are faces like any other (Catmull-Clark's rules).
    #[default]
    Catmark,
    /// OpenSubdiv's `TRI_SUB_SMOOTH` (after Hbr): the edge points of an
    /// edge between two faces weigh a triangle's face point by 0.470 instead
    /// of ¼ ([`crate::catmull_clark::edge_point_mask_with`]), which rounds the
    /// surface over triangles. Level 0 only: every later face is a quad.
    Smooth,
}

/// Which limit point a dart gets (a vertex with vertex sharpness 0 and one
/// sharp incident edge). Not an option of OpenSubdiv's `Sdc::Options`: it
/// chooses between the limit of refinement and OpenSubdiv's shortcut, which
/// give different limit *points* of the same surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DartLimit {
    /// The limit of refinement where the dart's edge is infinitely sharp:
    /// the dominant left eigenvector of the dart's local subdivision matrix
    /// ([`crate::catmull_clark::dart_limit_mask`],
    /// [`crate::loop_scheme::dart_limit_mask`]), the point patch-based
    /// evaluators show. A dart whose edge is still semi-sharp keeps the
    /// smooth mask (its rule changes on the way: refine until the value has
    /// decayed).
    #[default]
    Exact,
    /// The smooth limit mask, as OpenSubdiv's limit stencils and
    /// `Far::PrimvarRefiner::Limit`: not the limit of refinement at a dart
    /// (the crease edge's midpoints pull it away by ~10⁻³ of the model's
    /// size on coarse meshes).
    SmoothMask,
}

/// The names of an option's values, as on the command line.
macro_rules! named {
    ($ty:ty, $what:literal, $($variant:ident = $name:literal),+ $(,)?) => {
        impl $ty {
            /// Every value, in declaration order.
            pub const ALL: &'static [$ty] = &[$(<$ty>::$variant),+];
            /// The value's name, as on the command line.
            pub fn name(self) -> &'static str {
                match self { $(<$ty>::$variant => $name),+ }
            }
        }
        impl fmt::Display for $ty {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.name())
            }
        }
        impl FromStr for $ty {
            type Err = String;
            fn from_str(s: &str) -> Result<Self, String> {
                match s {
                    $($name => Ok(<$ty>::$variant),)+
                    _ => Err(format!(
                        concat!("unknown ", $what, " `{}` (expected one of: {})"),
                        s,
                        [$($name),+].join(", ")
                    )),
                }
            }
        }
    };
}

named!(CreaseMethod, "crease method", Uniform = "uniform", Chaikin = "chaikin");
named!(
    BoundaryInterpolation,
    "boundary interpolation",
    None = "none",
    EdgeOnly = "edge-only",
    EdgeAndCorner = "edge-and-corner"
);
named!(
    FVarInterpolation,
    "face-varying interpolation",
    LinearNone = "linear-none",
    LinearCornersOnly = "linear-corners-only",
    LinearCornersPlus1 = "linear-corners-plus1",
    LinearCornersPlus2 = "linear-corners-plus2",
    LinearBoundaries = "linear-boundaries",
    LinearAll = "linear-all"
);
named!(TriangleRule, "triangle rule", Catmark = "catmark", Smooth = "smooth");
named!(DartLimit, "dart limit", Exact = "exact", SmoothMask = "smooth-mask");
// Loop's β by name (`--beta warren|loop`): the same names, parser and messages as the options above.
named!(crate::LoopBeta, "Loop β", Warren = "warren", Loop = "loop");

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decay_reaches_zero_and_infinite_stays() {
        assert_eq!(decrement(2.5), 1.5);
        assert_eq!(decrement(1.0), 0.0);
        assert_eq!(decrement(0.75), 0.0);
        assert_eq!(decrement(10.0), 10.0);
        assert_eq!(decrement(f32::INFINITY), 10.0);
        assert_eq!(decrement(-1.0), 0.0);
    }

    #[test]
    fn chaikin_of_equal_sharpness_is_uniform() {
        // A constant-sharpness crease decays exactly as uniform (README of the peer files).
        for s in [0.5f32, 1.0, 2.5, 3.0, 7.25] {
            let c = CreaseMethod::Chaikin.subdivide_edge_sharpness(s, &[s, s, 0.0, 0.0]);
            assert_eq!(c, decrement(s), "s = {s}");
        }
    }

    #[test]
    fn chaikin_halves_of_mixed_sharpness() {
        // cube_crease_top_mixed: 0.75 and 2.5 at every top vertex.
        let at = [0.75f32, 2.5, 0.0];
        assert_eq!(CreaseMethod::Chaikin.subdivide_edge_sharpness(0.75, &at), 0.1875); // ¾·0.75 + ¼·2.5 − 1
        assert_eq!(CreaseMethod::Chaikin.subdivide_edge_sharpness(2.5, &at), 1.0625);
    }

    #[test]
    fn fractional_weight_means_the_decaying_values() {
        let u = CreaseMethod::Uniform;
        assert_eq!(fractional_weight(u, 0.5, 0.0, &[0.0, 0.0, 0.0], &[0.0; 3]), 0.5);
        assert_eq!(fractional_weight(u, 0.0, 0.0, &[0.75, 0.25, 0.0], &[0.0; 3]), 0.5);
        assert_eq!(fractional_weight(u, 0.0, 0.0, &[2.5, 2.5, 0.0], &[1.5, 1.5, 0.0]), 0.0);
        assert_eq!(fractional_weight(u, 0.0, 0.0, &[1.0, 10.0, 0.0], &[0.0, 10.0, 0.0]), 1.0);
        // Chaikin: an edge of sharpness 1.75 whose half becomes 0 weighs 1.75, clamped to 1.
        let c = CreaseMethod::Chaikin;
        assert_eq!(fractional_weight(c, 0.0, 0.0, &[1.75, 0.0], &[0.0, 0.0]), 1.0);
    }

    #[test]
    fn names_round_trip() {
        for &m in FVarInterpolation::ALL {
            assert_eq!(m.name().parse::<FVarInterpolation>(), Ok(m));
        }
        for &m in BoundaryInterpolation::ALL {
            assert_eq!(m.to_string().parse::<BoundaryInterpolation>(), Ok(m));
        }
        assert!("sharp".parse::<CreaseMethod>().unwrap_err().contains("uniform, chaikin"));
        for &m in DartLimit::ALL {
            assert_eq!(m.name().parse::<DartLimit>(), Ok(m));
        }
        assert_eq!(DartLimit::SmoothMask.to_string(), "smooth-mask");
    }
}
