//! Subdivision rules for subdiv: the weights (masks) of every scheme,
//! computed from a local neighbourhood — face sizes, valences, parameters —
//! never from a mesh.
//!
//! This is the layer OpenSubdiv calls `sdc/`: one module per scheme, each
//! returning the weights that say how a new point is made from old ones. The
//! stencil builder (`subdiv-stencil`) walks the topology, asks this crate for
//! the masks and assembles sparse matrices; nothing here knows a mesh type or
//! touches a position, with two exceptions that are geometric by nature: the
//! curve schemes ([`curves`]) and the Deng-Ma tension ([`deng_ma`]), which take
//! `[f64; 3]` points.
//!
//! | module | scheme | source ([references]) |
//! |---|---|---|
//! | [`doo_sabin`] | Doo-Sabin: the face-corner rule, the boundary rule, crease points, the valence-2 mask (the methods' first-step variants are in subdiv-interp) | Zheng-Cai Eq. 1 |
//! | [`catmull_clark`] | Catmull-Clark, limit masks (darts too), Cheng's limit stencil | Cheng Appendix Eq. 4-5 |
//! | [`loop_scheme`] | Loop, Warren's or Loop's β, limit masks (darts too) | Deng-Wang Eq. 1-2, 5-6 |
//! | [`sqrt3`] | √3 (Kobbelt 2000): face points, αₙ smoothing, the ternary boundary, limit masks with βₙ | Kobbelt 2000 §2-4 (recalled, not a seed) |
//! | [`deng_ma`] | Deng-Ma interpolatory scheme: moved vertices, ω_P | Deng-Ma §3.3-3.4 |
//! | [`curves`] | Chaikin, cubic B-spline, 4-point (variable tension) | Deng-Ma §3.1 |
//! | [`crease`] | sharpness decay, vertex rules, semi-sharp weights | OpenSubdiv `Sdc::Crease` (DeRose, Kass & Truong 1998) |
//!
//! Key types: [`VertexMask`] and [`EdgeMask`] (weights over named neighbours),
//! [`DartMask`] (a dart's limit: one weight per fan position),
//! [`VertexKind`] (interior / boundary / corner), [`Rule`] and the sharpness
//! rules of [`crease`] (OpenSubdiv's `Sdc::Crease`: decay, Chaikin, vertex
//! rules, semi-sharp transitions), the option enums [`BoundaryInterpolation`],
//! [`CreaseMethod`], [`FVarInterpolation`], [`DartLimit`], [`CurveScheme`]. Default parameters live
//! in [`constants`]. Corrections to the papers follow [the corrections to the
//! papers] and are cited by id ("correction C1", D1, W4, …) on the line that
//! applies them.
//!
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md
//! [the corrections to the papers]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#corrections-to-the-papers
//!
//! Contract violations (a face with fewer than 3 corners, a buffer of the
//! wrong length) panic; parameter ranges that come from users are checked by
//! [`deng_ma::Tension::validate`] and [`validate_four_point_tension`].
//!
//! ```
//! use subdiv_rules::{doo_sabin_weights, centroid, catmull_clark, loop_scheme, LoopBeta, VertexKind};
//!
//! // Doo-Sabin image of every corner of a pentagon: the face keeps its centroid.
//! let face = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [3.0, 1.5, 0.5], [1.0, 3.0, 0.0], [-1.0, 1.5, 0.0]];
//! let mut w = [0.0; 5];
//! doo_sabin_weights(5, &mut w);
//! let image = |i: usize| {
//!     let mut p = [0.0; 3];
//!     for (k, wk) in w.iter().enumerate() {
//!         for c in 0..3 {
//!             p[c] += wk * face[(i + k) % 5][c];
//!         }
//!     }
//!     p
//! };
//! let images: Vec<_> = (0..5).map(image).collect();
//! let (a, b) = (centroid(&face), centroid(&images));
//! assert!((0..3).all(|c| (a[c] - b[c]).abs() < 1e-15));
//!
//! // Limit masks are affine: weights sum to one.
//! let cc = catmull_clark::limit_mask(VertexKind::Interior, 5);
//! assert!((cc.total(5, 0, 5) - 1.0).abs() < 1e-15);
//! let lp = loop_scheme::limit_mask(VertexKind::Interior, 6, LoopBeta::Warren);
//! assert!((lp.vertex - 0.5).abs() < 1e-15 && (lp.interior_neighbor - 1.0 / 12.0).abs() < 1e-15);
//! ```
#![warn(missing_docs)]

pub mod catmull_clark;
pub mod constants;
pub mod crease;
pub mod curves;
pub mod deng_ma;
pub mod doo_sabin;
pub mod loop_scheme;
mod mask;
mod options;
pub mod sqrt3;
mod vec3;

#[cfg(test)]
mod test_util;

pub use crease::{BoundaryInterpolation, CreaseMethod, DartLimit, FVarInterpolation, Rule, TriangleRule};
pub use curves::CurveScheme;
pub use doo_sabin::doo_sabin_weights;
pub use loop_scheme::LoopBeta;
pub use mask::{DartMask, EdgeMask, VertexKind, VertexMask};
pub use options::{validate_four_point_tension, OptionsError};
pub use vec3::{centroid, Point3};
